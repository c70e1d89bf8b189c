"""Modes of a switched bond graph: one ordinary :class:`~bondgraph.Model` per switch state.

A mode is the graph with every switch in one state: each switch then is the
source ``Se:0`` (on) or ``Sf:0`` (off), and the mode is derived by the
ordinary :func:`bondgraph.derive` -- with its own causal assignment, storage
elements in derivative causality included (two inertias locked by a clutch).
Modes are derived lazily, when asked for, and cached.

Examples
--------
A series circuit: a voltage source, a diode and an RC load.

>>> import bondgraph as bg, sympy
>>> from bondgraph.hybrid import Diode, SwitchedModel
>>> g = bg.BondGraph("rect")
>>> g.add(bg.Se("V"), bg.One("i"), Diode("D"), bg.Zero("v"), bg.R("R"), bg.C("C"))
>>> for a, b in [("V", "i"), ("i", "D"), ("i", "v"), ("v", "R"), ("v", "C")]:
...     _ = g.connect(a, b)
>>> sm = SwitchedModel(g, outputs={"vC": bg.effort("C")})
>>> [str(m) for m in sm.modes]
['D off', 'D on']
>>> sm.mode(off={"D"}).rhs
(-q_C/(C*R),)
>>> sm.mode(on={"D"}).state_names, sm.mode(on={"D"}).output_exprs
((), (V,))
>>> sm.causality_changes
{'C': ('D on',)}
"""

from __future__ import annotations

import dataclasses
import itertools
import warnings
from dataclasses import dataclass
from typing import Any, Iterable, Mapping, Optional, Union, cast

import sympy

from ..model import derive
from ..errors import AlgebraicLoopError, BondGraphWarning, CausalityError, OutputError
from ..flatten import FlatGraph, flatten
from ..graph import BondGraph
from ..model import Model
from .elements import Diode, SwitchElement, gate_signals
from .errors import ModeError

__all__ = ["Mode", "ModeModel", "ModeSet"]

#: prefixes of the outputs the hybrid machinery adds to every mode
_E, _S = "hyb_E", "hyb_S"
#: most switches whose 2**n combinations ``modes`` enumerates
MAX_SWITCHES = 12


@dataclass(frozen=True)
class Mode:
    """A combination of switch states: the switches that are on and those that are off.

    Examples
    --------
    >>> m = Mode(on={"D1"}, off={"S1", "S2"})
    >>> str(m), m.is_on("S1")
    ('D1 on, S1 off, S2 off', False)
    """

    on: frozenset = frozenset()
    off: frozenset = frozenset()

    def __post_init__(self) -> None:
        object.__setattr__(self, "on", frozenset(self.on))
        object.__setattr__(self, "off", frozenset(self.off))
        object.__setattr__(self, "_hash", hash((self.on, self.off)))

    def __hash__(self) -> int:      # modes key the caches of every event: hashed once
        return self._hash           # type: ignore[attr-defined]

    def __reduce__(self):           # the hash of str differs between processes: not pickled
        return (Mode, (self.on, self.off))

    def is_on(self, name: str) -> bool:
        """Whether switch ``name`` is on in this mode."""
        return name in self.on

    def flipped(self, *names: str) -> "Mode":
        """This mode with the states of ``names`` flipped."""
        flip = set(names)
        return Mode(on=(self.on - flip) | (self.off & flip), off=(self.off - flip) | (self.on & flip))

    def __str__(self) -> str:
        names = sorted(self.on | self.off)
        return ", ".join(f"{n} {'on' if n in self.on else 'off'}" for n in names)


@dataclass(frozen=True)
class ModeModel:
    """A derived mode with what the hybrid machinery needs besides the user's model.

    Attributes
    ----------
    mode : Mode
    full : Model
        The mode derived with the user's outputs followed by the stored
        quantities of every storage element (``hyb_E*``) and the signals the
        guards read (``hyb_S*``).
    user : Model
        The same with the user's outputs only (what :meth:`SwitchedModel.mode` returns).
    """

    mode: Mode
    full: Model
    user: Model


class ModeSet:
    """A switched bond graph's switches, modes and their equations (the record under
    :class:`~bondgraph.hybrid.SwitchedModel`, which adds simulation and averaging).

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
    >>> sm = ModeSet(g)
    >>> sm.switches, str(sm.initial)
    (('S',), 'S off')
    >>> sm.mode(on={"S"}).state_names, sm.mode(off={"S"}).rhs
    ((), (I,))
    """

    def __init__(self, graph: Union[BondGraph, FlatGraph], outputs: Optional[Mapping] = None) -> None:
        flat = graph if isinstance(graph, FlatGraph) else flatten(graph)
        self.flat = flat
        self.name = flat.name
        self.switches: tuple[str, ...] = tuple(
            el.name for el in flat.elements if isinstance(el, SwitchElement))
        if not self.switches:
            raise ModeError(f"model {flat.name!r} has no switch element (Switch, Diode, "
                            "ControlledSwitch from bondgraph.hybrid); derive it with bondgraph.derive")
        _warn_reversed_diodes(flat, self.switches)
        self.user_outputs: dict = dict(outputs or {})
        for name in self.user_outputs:
            if isinstance(name, str) and name.startswith(("hyb_E", "hyb_S")):
                raise OutputError(f"output name {name!r}: names starting 'hyb_E' or 'hyb_S' are "
                                  "reserved for the switched model's internal outputs")
        self.initial = Mode(on=frozenset(n for n in self.switches if self.element(n).on),
                            off=frozenset(n for n in self.switches if not self.element(n).on))
        # storage elements and the signals of their stored quantities (p of an I, q of a C)
        self.storage: tuple[tuple[str, tuple], ...] = tuple(
            (el.name, tuple(el.energy_signals())) for el in flat.elements if el.energy_signals())
        self.energy_signals: tuple = tuple(s for _, sigs in self.storage for s in sigs)
        signals: list = []
        for name in self.switches:
            el = self.element(name)
            for on in (True, False):
                for s in sorted(gate_signals(el.guard(on)), key=str):
                    if s not in signals:
                        signals.append(s)
        for expr in self.user_outputs.values():
            if isinstance(expr, sympy.Expr):
                for s in sorted(gate_signals(expr), key=str):
                    if s not in signals:
                        signals.append(s)
        #: the signals read by the guards and the outputs, in the order of the ``hyb_S*``
        #: outputs (an integrator state of one of them carries over between modes)
        self.guard_signals: tuple = tuple(signals)
        self._cache: dict = {}

    def __getstate__(self) -> dict:
        # the compiled numbers of past simulations are functions: not pickled, rebuilt when asked
        state = dict(self.__dict__)
        state.pop("_numeric", None)
        return state

    def element(self, name: str) -> SwitchElement:
        """The element named ``name`` (a switch, or any other element of the graph)."""
        return cast(SwitchElement, self.flat.element(name))

    # ------------------------------------------------------------ modes
    def mode_of(self, on: Iterable[str] = (), off: Iterable[str] = ()) -> Mode:
        """The :class:`Mode` with ``on`` on, ``off`` off and the other switches in their
        initial state.

        Raises
        ------
        ModeError
            A name is not a switch of the graph, or is both on and off.
        """
        on, off = _names(on, "on"), _names(off, "off")
        for name in sorted(on | off):
            if name not in self.switches:
                raise ModeError(f"model {self.name!r} has no switch {name!r}; its switches are "
                                f"{', '.join(self.switches)}")
        both = on & off
        if both:
            raise ModeError(f"switch {', '.join(sorted(both))} is given both on and off")
        rest = set(self.switches) - on - off
        return Mode(on=frozenset(on | (rest & self.initial.on)),
                    off=frozenset(off | (rest & self.initial.off)))

    def mode(self, on: Iterable[str] = (), off: Iterable[str] = ()) -> Model:
        """The ordinary :class:`~bondgraph.Model` of one mode (derived once, then cached).

        Switches not named keep the state they were built in.

        Raises
        ------
        ModeError
            The combination is not a consistent mode (its causality conflicts):
            the message names the switches and the conflict.
        """
        return self.derived(self.mode_of(on, off)).user

    def derived(self, mode: Mode) -> ModeModel:
        """The derived :class:`ModeModel` of ``mode`` (cached), or :class:`ModeError`."""
        hit = self._cache.get(mode)
        if hit is None:
            hit = self._cache[mode] = self._derive(mode)
        if isinstance(hit, ModeError):
            raise hit
        return hit

    def _derive(self, mode: Mode) -> Union[ModeModel, ModeError]:
        elements = tuple(cast(SwitchElement, el).in_state(mode.is_on(el.name))
                         if el.name in self.switches else el for el in self.flat.elements)
        flat = dataclasses.replace(self.flat, elements=elements)
        outputs = dict(self.user_outputs)
        outputs.update({f"{_E}{k}": s for k, s in enumerate(self.energy_signals)})
        outputs.update({f"{_S}{k}": s for k, s in enumerate(self.guard_signals)})
        try:
            full = derive(cast(Any, flat), outputs=outputs)   # derive reads a FlatGraph too
        except (CausalityError, AlgebraicLoopError) as err:
            return ModeError(f"mode ({mode}) of model {self.name!r} is not consistent: the "
                             f"switch states contradict each other: {err}")
        n = len(self.user_outputs)
        user = dataclasses.replace(full, output_names=full.output_names[:n],
                                   output_exprs=full.output_exprs[:n])
        return ModeModel(mode, full, user)

    @property
    def all_modes(self) -> tuple[Mode, ...]:
        """Every combination of switch states (consistent or not)."""
        if len(self.switches) > MAX_SWITCHES:
            raise ModeError(f"model {self.name!r} has {len(self.switches)} switches; enumerating "
                            f"its 2**{len(self.switches)} modes is refused (at most {MAX_SWITCHES}): "
                            "ask for modes one by one with mode(on=..., off=...)")
        out = []
        for states in itertools.product((False, True), repeat=len(self.switches)):
            on = frozenset(n for n, s in zip(self.switches, states) if s)
            out.append(Mode(on=on, off=frozenset(self.switches) - on))
        return tuple(out)

    @property
    def modes(self) -> tuple[Mode, ...]:
        """The consistent modes (those with a causal assignment and equations)."""
        out = []
        for mode in self.all_modes:
            try:
                self.derived(mode)
            except ModeError:
                continue
            out.append(mode)
        return tuple(out)

    @property
    def reachable_modes(self) -> tuple[Mode, ...]:
        """The consistent modes a simulation from the built state can reach: those whose
        user-set switches (no guard: :class:`Switch`) keep their built state."""
        fixed = [n for n in self.switches if self.element(n).guard(True) is None]
        return tuple(m for m in self.modes
                     if all(m.is_on(n) == self.initial.is_on(n) for n in fixed))

    @property
    def inconsistent_modes(self) -> dict[Mode, str]:
        """The modes with no consistent causality, each with the reason."""
        out = {}
        for mode in self.all_modes:
            try:
                self.derived(mode)
            except ModeError as err:
                out[mode] = str(err)
        return out

    def derivative_storage(self, mode: Mode) -> tuple[str, ...]:
        """The storage elements in derivative causality in ``mode``."""
        return tuple(self.derived(mode).full.augmented.derivative)

    @property
    def causality_changes(self) -> dict[str, tuple[str, ...]]:
        """Storage elements whose causality changes between consistent modes, each with the
        modes in which it is in derivative causality (so its state is not a state there)."""
        modes = self.modes
        out: dict[str, list] = {}
        for mode in modes:
            for name in self.derivative_storage(mode):
                out.setdefault(name, []).append(str(mode))
        return {name: tuple(ms) for name, ms in out.items() if len(ms) < len(modes)}

    def energy(self) -> tuple[tuple[sympy.Symbol, ...], sympy.Expr]:
        """Placeholders for the stored quantities (in the order of the ``hyb_E*``
        outputs) and the total stored energy as a function of them."""
        qs = tuple(sympy.Symbol(f"{_E}{k}", real=True) for k in range(len(self.energy_signals)))
        total, k = sympy.Integer(0), 0
        for name, sigs in self.storage:
            total += self.element(name).stored_energy(qs[k:k + len(sigs)])
            k += len(sigs)
        return qs, total

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r}, switches={self.switches})"


def _warn_reversed_diodes(flat: FlatGraph, switches: Iterable[str]) -> None:
    """A :class:`~bondgraph.BondGraphWarning` for each diode bonded away from itself."""
    for name in switches:
        el = flat.element(name)
        if not isinstance(el, Diode):
            continue
        for b in flat.incidence.get(name, ()):
            bond = flat.bonds[b]
            if bond.tail == name:
                warnings.warn(
                    f"diode {name!r} is bonded away from itself ({name} -> {bond.head}): it conducts "
                    f"while the flow from {name} into {bond.head} is >= 0 and blocks while its effort "
                    f"is <= 0 on that bond, the reverse of a diode bonded {bond.head} -> {name}; "
                    f"bond it {bond.head} -> {name} for the usual direction (forward flow into the "
                    "diode)", BondGraphWarning, stacklevel=4)


def _names(names: Iterable[str], what: str) -> frozenset:
    if isinstance(names, str):
        names = (names,)
    try:
        out = frozenset(names)
    except TypeError:
        raise ModeError(f"{what} must be a set of switch names; got {names!r}") from None
    for n in out:
        if not isinstance(n, str):
            raise ModeError(f"{what} must hold switch names (str); got {n!r}")
    return out
