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

from typing import Mapping, Optional, Union

from ..flatten import FlatGraph
from ..graph import BondGraph
from ..model import Model
from .averaging import ModeLike, average
from .errors import ModeError
from .events import SwitchedResult, simulate
from .modes import ModeSet

__all__ = ["SwitchedModel", "derive_switched"]


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

    def simulate(self, t_span, x0=None, *, values=None, inputs=None, **options) -> SwitchedResult:
        """Simulate with events; see :func:`bondgraph.hybrid.simulate`."""
        return simulate(self, t_span, x0, values=values, inputs=inputs, **options)

    def simulate_with_events(self, values, t_span, x0=None, *, u=None, t_eval=None,
                             method: str = "RK45", rtol: float = 1e-9, atol=1e-12,
                             max_step=None) -> SwitchedResult:
        """What ``bondgraph.simulate(switched_model, values, t_span, x0, u=...)`` calls.

        ``u``: None or a mapping of input name to a number or a function of time.
        """
        if u is not None and not isinstance(u, Mapping):
            raise ModeError(f"model {self.name!r} is switched: give its inputs as u={{name: "
                            f"number or function of t}}; got {type(u).__name__}")
        return simulate(self, t_span, x0, values=values, inputs=u, t_eval=t_eval, method=method,
                        rtol=rtol, atol=atol, max_step=max_step)

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
