"""The façade: :class:`SwitchedModel`, the modes of a switched graph with their verbs.

:class:`~bondgraph.hybrid.modes.ModeSet` holds the switches and derives the
modes; this class adds the simulation with events
(:func:`bondgraph.hybrid.events.simulate`, also what ``bondgraph.simulate``
calls) and the state-space average (:func:`bondgraph.hybrid.averaging.average`).

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.hybrid import Switch, SwitchedModel
>>> g = bg.BondGraph("g")
>>> g.add(bg.Se("E"), bg.One("i"), bg.R("R"), Switch("S", on=True))
>>> for a, b in [("E", "i"), ("i", "R"), ("i", "S")]: _ = g.connect(a, b)
>>> sm = SwitchedModel(g, outputs={"i": bg.flow("R")})
>>> sm.mode().output_exprs, sm.mode(off={"S"}).output_exprs
((E/R,), (0,))
"""

from __future__ import annotations

import dataclasses
import warnings
from typing import Any, Mapping, Optional, Union

import numpy as np

from ..errors import ParameterValueError
from ..flatten import FlatGraph
from ..graph import BondGraph
from ..model import Model
from .averaging import ModeLike, average
from .errors import ModeError
from .events import SwitchedResult
from .events import simulate as _events_simulate
from .modes import ModeSet

__all__ = ["SwitchedModel", "derive_switched", "simulate"]


class SwitchedModel(ModeSet):
    """A switched bond graph: its switches, its modes and their equations, simulation, averaging.

    Parameters
    ----------
    graph : BondGraph or FlatGraph
        A bond graph with switch elements (:mod:`bondgraph.hybrid.elements`);
        the state each switch is built in (``on=``) is the initial mode.
    outputs : mapping of str to signal expression, optional
        Named outputs of every mode, as for :func:`bondgraph.derive`.

    Raises
    ------
    ModeError
        The graph has no switch element.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.hybrid import Switch
    >>> g = bg.BondGraph("short")
    >>> g.add(bg.Sf("I"), bg.Zero("v"), bg.C("C"), Switch("S"))
    >>> for a, b in [("I", "v"), ("v", "C"), ("v", "S")]: _ = g.connect(a, b)
    >>> sm = SwitchedModel(g)
    >>> sm.switches, str(sm.initial)
    (('S',), 'S off')
    >>> sm.mode(on={"S"}).state_names, sm.mode(off={"S"}).rhs
    ((), (I,))
    """

    def simulate(self, *args: Any, **options: Any) -> SwitchedResult:
        """Simulate with events: ``sm.simulate(values, t_span, x0, u=...)``, as
        :func:`bondgraph.simulate` (see there for the options).

        The older form ``sm.simulate(t_span, x0, values=..., inputs=...)`` still
        works and warns (:class:`DeprecationWarning`).

        Examples
        --------
        >>> import bondgraph as bg
        >>> from bondgraph.hybrid import ControlledSwitch, SwitchedModel
        >>> g = bg.BondGraph("rl")
        >>> g.add(bg.Se("E"), bg.One("i"), bg.R("R"), bg.I("L"),
        ...       ControlledSwitch("S", gate=1 - bg.t, on=True))
        >>> for a, b in [("E", "i"), ("i", "R"), ("i", "L"), ("i", "S")]: _ = g.connect(a, b)
        >>> sm = SwitchedModel(g, outputs={"i": bg.flow("L")})
        >>> res = sm.simulate({"R": 1, "L": 1}, (0, 2), u={"E": 1.0})
        >>> [round(e.time, 9) for e in res.events], float(res["i"][-1])
        ([1.0], 0.0)
        """
        return _simulate(self, args, options)

    def simulate_with_events(self, values, t_span, x0=None, *, u=None, t_eval=None,
                             method: str = "RK45", rtol: float = 1e-9, atol=1e-12,
                             max_step=None, max_events: Optional[int] = None,
                             time_budget: Optional[float] = None,
                             chatter_count: Optional[int] = None,
                             chatter_time: Optional[float] = None,
                             guard_tol: Optional[float] = None) -> SwitchedResult:
        """What ``bondgraph.simulate(switched_model, values, t_span, x0, u=...)`` calls.

        ``u``: None or a mapping of input name to a number or a function of
        time; the result holds the inputs at its samples.  The event options
        left None take the defaults of :func:`bondgraph.hybrid.events.simulate`.
        """
        if u is not None and not isinstance(u, Mapping):
            raise ModeError(f"model {self.name!r} is switched: give its inputs as u={{name: "
                            f"number or function of t}}; got {type(u).__name__}")
        inputs = self._input_names()
        if isinstance(values, Mapping):
            for key in values:
                name = getattr(key, "name", key)
                if name in inputs:
                    raise ParameterValueError(
                        f"model {self.name!r}: {name!r} is an input of the model, not a parameter "
                        "(give it as an input: u= when simulating)", unknown=(name,))
        chosen: dict[str, Any] = {k: v for k, v in (("max_events", max_events), ("time_budget", time_budget),
                                    ("chatter_count", chatter_count), ("chatter_time", chatter_time),
                                    ("guard_tol", guard_tol)) if v is not None}
        res = _events_simulate(self, t_span, x0, values=values, inputs=u, t_eval=t_eval,
                               method=method, rtol=rtol, atol=atol, max_step=max_step, **chosen)
        return dataclasses.replace(res, inputs=self._input_histories(res.t, u))

    def _input_names(self) -> tuple[str, ...]:
        """The inputs of every consistent mode, in order of first appearance."""
        names: dict = {}
        for mode in self.modes:
            names.update(dict.fromkeys(s.name for s in self.derived(mode).full.inputs))
        return tuple(names)

    def _input_histories(self, t, u) -> dict:
        """Each input of the model at the times ``t`` (from the mapping ``u``)."""
        names = self._input_names()
        u = dict(u or {})
        out = {}
        for name in names:
            v = u.get(name, 0.0)
            if callable(v):
                column = np.array([float(v(float(tk))) for tk in t], dtype=float)
            else:
                column = np.full(len(t), float(v))
            column.flags.writeable = False
            out[name] = column
        return out

    def drawing_mode(self, mode: Optional[ModeLike] = None):
        """What :func:`bondgraph.draw` draws: the causal graph of ``mode`` and each
        switch's state in it.

        Parameters
        ----------
        mode : Mode or mapping with keys ``'on'`` and ``'off'``, optional
            Default: the initial mode (the states the switches are built in).
            Switches not named keep their built state.

        Returns
        -------
        (Mode, AugmentedBondGraph, dict of str to bool)

        Raises
        ------
        ModeError
            ``mode`` is not a consistent mode (the consistent ones listed).

        Examples
        --------
        >>> import bondgraph as bg
        >>> from bondgraph.hybrid import SwitchedModel, library
        >>> sm = SwitchedModel(library.buck())
        >>> mode, aug, states = sm.drawing_mode({"on": {"D"}, "off": {"S"}})
        >>> str(mode), states, aug.derivative
        ('D on, S off', {'S': False, 'D': True}, ())
        >>> sm.drawing_mode({"on": {"S", "D"}})
        Traceback (most recent call last):
        ...
        bondgraph.hybrid.errors.ModeError: mode (D on, S on) of model 'buck' is not consistent: ...
        """
        from .averaging import _mode

        chosen = self.initial if mode is None else _mode(self, mode)
        try:
            derived = self.derived(chosen)
        except ModeError as exc:
            raise ModeError(f"{exc}; the consistent modes are "
                            f"{'; '.join(f'({m})' for m in self.modes) or 'none'}") from None
        return chosen, derived.full.augmented, {n: chosen.is_on(n) for n in self.switches}

    def average(self, duty, active: ModeLike, passive: ModeLike, *,
                name: Optional[str] = None, inputs=()) -> Model:
        """State-space average of two modes; see :func:`bondgraph.hybrid.average`."""
        return average(self, duty, active, passive, name=name, inputs=inputs)


def derive_switched(graph: Union[BondGraph, FlatGraph], outputs: Optional[Mapping] = None) -> SwitchedModel:
    """The :class:`SwitchedModel` of a graph with switches (modes derived when asked for).

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.hybrid import Switch, derive_switched
    >>> g = bg.BondGraph("g")
    >>> g.add(bg.Se("E"), bg.One("i"), bg.R("R"), Switch("S", on=True))
    >>> for a, b in [("E", "i"), ("i", "R"), ("i", "S")]: _ = g.connect(a, b)
    >>> derive_switched(g, outputs={"i": bg.flow("R")}).mode().output_exprs
    (E/R,)
    """
    return SwitchedModel(graph, outputs)


def simulate(sm: "SwitchedModel", *args: Any, **options: Any) -> SwitchedResult:
    """Simulate a switched model with events, in the one form of :func:`bondgraph.simulate`.

    ``simulate(sm, values, t_span, x0=None, *, u=None, ...)`` is
    ``bondgraph.simulate(sm, values, t_span, x0, u=...)``: prefer that.  The
    older form ``simulate(sm, t_span, x0=None, *, values=..., inputs=..., ...)``
    still works and warns (:class:`DeprecationWarning`).

    Examples
    --------
    >>> import bondgraph as bg, warnings
    >>> from bondgraph.hybrid import ControlledSwitch, SwitchedModel, simulate
    >>> g = bg.BondGraph("rl")
    >>> g.add(bg.Se("E", value=1), bg.One("i"), bg.R("R"), bg.I("L"),
    ...       ControlledSwitch("S", gate=1 - bg.t, on=True))
    >>> for a, b in [("E", "i"), ("i", "R"), ("i", "L"), ("i", "S")]: _ = g.connect(a, b)
    >>> sm = SwitchedModel(g, outputs={"i": bg.flow("L")})
    >>> new = simulate(sm, {"R": 1, "L": 1}, (0, 2))
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     old = simulate(sm, (0, 2), values={"R": 1, "L": 1})
    >>> caught[0].category.__name__, old.events[0].time == new.events[0].time
    ('DeprecationWarning', True)
    """
    if not isinstance(sm, SwitchedModel):
        raise ModeError(f"simulate: expected a SwitchedModel; got {type(sm).__name__} (a model "
                        "without switches is simulated by bondgraph.simulate)")
    return _simulate(sm, args, options)


def _simulate(sm: "SwitchedModel", args: tuple, options: dict) -> SwitchedResult:
    """The one form, or the deprecated one with a warning pointing at the caller's line."""
    if _old_form(args, options):
        warnings.warn("simulate(sm, t_span, x0, values=..., inputs=...) is deprecated; use the one "
                      "form bondgraph.simulate(sm, values, t_span, x0, u=...)",
                      DeprecationWarning, stacklevel=3)
        if "inputs" in options:
            options["u"] = options.pop("inputs")
        values = options.pop("values", None)
        return sm.simulate_with_events(values, *args, **options)
    return sm.simulate_with_events(*args, **options)


def _old_form(args: tuple, options: dict) -> bool:
    """The deprecated order: ``t_span`` first (a pair of times), ``values=``/``inputs=`` by keyword."""
    if "inputs" in options or ("values" in options and "t_span" not in options and
                               (not args or not isinstance(args[0], Mapping))):
        return True
    return bool(args) and args[0] is not None and not isinstance(args[0], Mapping)

