"""Structural rank of ``[A B]`` and ``[A; C]`` from the bond graph in derivative causality.

Sueur and Dauphin-Tanguy (1991) read the structural ranks off the bond graph
itself, without forming a matrix:

* ``rank [A B] = n - t`` where ``n`` is the number of states and ``t`` the
  number of storage elements that remain in integral causality when
  derivative causality is preferred for every storage element and the input
  sources are *dualised* (their causality left free, so a source may take the
  causality a conflict needs).  An element already in derivative causality in
  the model (no state of its own) that must turn integral here counts in
  ``t`` too: two capacitors in series across a voltage source give
  ``rank [A B] = 0``, the charge moving only with the source's derivative;
* ``rank [A; C] = n - t`` with the *detectors* dualised instead: each output
  becomes a source-sensor on the bond whose effort (flow) it measures, free to
  impose the measured variable.

A storage element that keeps integral causality there is where the rank is
lost; forcing it into derivative causality (with the others kept as found)
makes the junction structure conflict, and the conflict names the junction.

The assignment is the engine's own SCAP (:func:`bondgraph.assign_causality`,
``prefer_derivative`` for every storage element; the dualised ports are free
one-ports, :class:`SS`), followed by a pass that moves each remaining
integral element into derivative causality whenever that is still possible,
so the set found is maximal.  The value is the structural (generic) rank; the
numeric generic rank can only be lower, when causal-path gains cancel, and
:mod:`bondgraph.structure.reach` reports both.

The graph method covers the storage elements' states: integrator states (an
output that integrates a flow) lie outside the bond graph, and an output that
is not proportional to one effort or flow (or to a one-port storage
element's own displacement or momentum) has no detector; the result then
says so (``applicable`` is False).

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.structure import derivative_causality
>>> g = bg.BondGraph("series_c")
>>> j = bg.One("j")
>>> g.add(bg.Sf("i"), j, bg.C("C1"), bg.C("C2"), bg.R("R"))
>>> for t, h in [("i", j), (j, "C1"), (j, "C2"), (j, "R")]: _ = g.connect(t, h)
>>> bgd = derivative_causality(bg.derive(g))
>>> bgd.rank, bgd.integral, bgd.junctions
(1, ('q_C2',), ('j',))
"""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass
from typing import Any, ClassVar, Mapping, Optional, Sequence

import sympy

from ..causality import AugmentedBondGraph, assign_causality
from ..elements import One, Zero
from ..elements.bond import Bond
from ..elements.protocol import RESISTIVE, CausalPorts, Choice, Decision, Element, rename
from ..errors import BondGraphError, BondGraphWarning, CausalityConflictError
from ..flatten import FlatGraph
from ..model import Model, derive
from ..signals import Signal
from ._generic import StructureError
from ._paths import state_elements

__all__ = ["SS", "DerivativeCausality", "derivative_causality"]

#: without ``detectors=``, outputs are matched to bond variables only up to this many bonds
_SEARCH_BONDS = 12


@dataclass(frozen=True, eq=False)
class SS(Element):
    """A dualised source or detector: a one-port whose causality is free.

    Used only for the structural analysis; its ``note`` says what it stands
    for (``"dualised Se"``, ``"detector of effort"``).

    Examples
    --------
    >>> SS("u", note="dualised Se").drawing_label()
    ('SS:u', 'dualised Se')
    """

    note: str = ""
    kind: ClassVar[str] = "SS"
    drawing_role: ClassVar[str] = "source"

    def causal_choices(self, prefer_derivative: bool) -> Sequence[Choice]:
        return (Choice(0, False, f"free causality of {self.label()} ({self.note})", RESISTIVE),)

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        return ((),)

    def drawing_label(self) -> tuple[str, str]:
        return self.label(), self.note


@dataclass(frozen=True, eq=False)
class _Fixed(Element):
    """A storage element held in the causality found (the conflict search)."""

    effort_in: bool = False
    reason: str = ""
    kind: ClassVar[str] = "fixed"
    shown: str = ""

    def label(self) -> str:
        return self.shown or super().label()

    def forced_causality(self, ports: CausalPorts) -> Sequence[Decision]:
        return (Decision(0, self.effort_in, self.reason),)

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        return ((),)


@dataclass(frozen=True)
class DerivativeCausality:
    """The bond graph in preferred derivative causality with dualised ports (immutable).

    Attributes
    ----------
    kind : {"controllability", "observability"}
    model : str
    applicable : bool
        False when the graph method does not cover the question (see ``why``).
    why : str
        Why not applicable (empty otherwise).
    states : tuple of str
        The storage elements' states considered (integrators excluded).
    rank : int or None
        ``len(states) - len(integral)``: the structural rank of ``[A B]``
        (``[A; C]``) restricted to the storage states; None when not applicable.
    integral : tuple of str
        The state names of the storage elements that remain in integral
        causality (an element in derivative causality in the model is named
        by the state it would have).
    conflicts : tuple of str
        Per state in ``integral``, the conflict that derivative causality of
        its element meets.
    junctions : tuple of str
        Per state in ``integral``, the junction (or element) where it conflicts.
    dualised : tuple of str
        The dualised sources (controllability) or detectors (observability).
    augmented : AugmentedBondGraph or None
        The bond graph in derivative causality (``bondgraph.draw`` draws it).
    """

    kind: str
    model: str
    applicable: bool
    why: str
    states: tuple[str, ...]
    rank: Optional[int]
    integral: tuple[str, ...]
    conflicts: tuple[str, ...]
    junctions: tuple[str, ...]
    dualised: tuple[str, ...]
    augmented: Optional[AugmentedBondGraph] = None

    def draw(self, path: Any = None, **options: Any) -> str:
        """Draw the bond graph in derivative causality (:func:`bondgraph.draw`)."""
        if self.augmented is None:
            raise StructureError(f"{self.kind} of {self.model!r}: no graph to draw ({self.why})")
        from ..drawing import draw

        return draw(self.augmented, path, **options)

    def conflict(self, state: str) -> str:
        """Why ``state``'s element cannot take derivative causality (empty if it can)."""
        if state in self.integral:
            return self.conflicts[self.integral.index(state)]
        return ""

    def __str__(self) -> str:
        what = "sources" if self.kind == "controllability" else "detectors"
        mat = "[A B]" if self.kind == "controllability" else "[A; C]"
        head = f"bond graph in derivative causality of {self.model!r}, {what} dualised"
        if not self.applicable:
            return f"{head}: not applicable ({self.why})"
        lines = [head + f" ({', '.join(self.dualised) or 'none'})",
                 f"  structural rank {mat} = {len(self.states)} - {len(self.integral)} "
                 f"= {self.rank}"]
        for s, j, c in zip(self.integral, self.junctions, self.conflicts):
            lines.append(f"  {s} stays integral: rank lost at {j} ({c})")
        return "\n".join(lines)


def _not(kind: str, model: Model, why: str, states: tuple[str, ...]) -> DerivativeCausality:
    return DerivativeCausality(kind=kind, model=model.name, applicable=False, why=why,
                               states=states, rank=None, integral=(), conflicts=(),
                               junctions=(), dualised=())


def _fresh(base: str, taken: set) -> str:
    name, k = base, 1
    while name in taken:
        k += 1
        name = f"{base}{k}"
    taken.add(name)
    return name


def _flat(flat: FlatGraph, replace: dict, splits: Sequence[tuple[int, Element, Element]]
          ) -> FlatGraph:
    """``flat`` with elements replaced and bonds split by a junction carrying a one-port."""
    elements = [replace.get(el.name, el) for el in flat.elements]
    bonds = list(flat.bonds)
    incidence = {n: list(v) for n, v in flat.incidence.items()}
    for k, junction, port in splits:
        b = bonds[k]
        kb, kd = len(bonds), len(bonds) + 1
        bonds[k] = Bond(b.number, b.tail, junction.name)
        bonds.append(Bond(kb + 1, junction.name, b.head))
        bonds.append(Bond(kd + 1, junction.name, port.name))
        incidence[b.head] = [kb if i == k else i for i in incidence[b.head]]
        incidence[junction.name] = [k, kb, kd]
        incidence[port.name] = [kd]
        elements += [junction, port]
    return FlatGraph(name=flat.name, elements=tuple(elements), bonds=tuple(bonds),
                     incidence={n: tuple(v) for n, v in incidence.items()},
                     index={el.name: i for i, el in enumerate(elements)})


def _given_bonds(model: Model, chosen: Sequence[str], detectors: Mapping) -> tuple[list, str]:
    """Per chosen output, (bond index, 'effort'/'flow') from the signal it was defined by."""
    flat = model.augmented.flat
    found = []
    for name in chosen:
        if name not in detectors:
            raise StructureError(f"detectors: no signal given for output {name!r} of model "
                                 f"{model.name!r}")
        expr = detectors[name]
        sigs = [x for x in getattr(expr, "free_symbols", ()) if isinstance(x, Signal)]
        if len(sigs) != 1 or (expr / sigs[0]).free_symbols & set(sigs) or \
                sigs[0].variable not in ("effort", "flow") and _stored_bond(model, sigs[0]) is None:
            return [], (f"output {name!r} = {expr} is not proportional to one effort or flow, "
                        "nor to a storage element's own displacement or momentum (no single "
                        "detector measures it)")
        sig = sigs[0]
        stored = _stored_bond(model, sig)
        if stored is not None:
            found.append(stored)
            continue
        if isinstance(sig.target, int):
            if not 1 <= sig.target <= len(flat.bonds):
                raise StructureError(f"detectors: {sig} names no bond of model {model.name!r}")
            found.append((sig.target - 1, sig.variable))
            continue
        if sig.target not in flat.index:
            raise StructureError(f"detectors: {sig} names no element of model {model.name!r}")
        el = flat.element(sig.target)
        carried = (el.signal_port(sig.variable) if sig.port is None else
                   el.port_signal(sig.variable, sig.port))
        if carried is None:
            return [], f"{sig} is not the variable of one bond"
        found.append((flat.incidence[sig.target][carried[0]], sig.variable))
    return found, ""


def _stored_bond(model: Model, sig: Signal) -> Optional[tuple[int, str]]:
    """A one-port storage element's own energy variable (``bg.displacement`` of a C):
    in a linear model it is proportional to the element's co-energy variable, the one
    it puts out in integral causality; (bond index, 'effort'/'flow'), else None."""
    if sig.variable not in ("displacement", "momentum") or sig.port is not None or \
            not isinstance(sig.target, str):
        return None
    aug = model.augmented
    flat = aug.flat
    if sig.target not in flat.index:
        return None
    el = flat.element(sig.target)
    inc = flat.incidence[sig.target]
    if len(inc) != 1 or el.energy_variable(sig.variable) != 0:
        return None
    receives = aug.effort_into(sig.target, flat.bonds[inc[0]].number)
    integral = sig.target in aug.integral
    puts_out_effort = (not receives) if integral else receives
    return inc[0], "effort" if puts_out_effort else "flow"


def _detector_bonds(model: Model, picked: Sequence[int]) -> tuple[list, str]:
    """Per picked output, (bond index, 'effort'/'flow') of a bond variable it is proportional to."""
    from ..signals import effort, flow

    aug = model.augmented
    nb = len(aug.flat.bonds)
    outs = {}
    for k in range(nb):
        outs[f"e_bond{k + 1}"] = effort(k + 1)
        outs[f"f_bond{k + 1}"] = flow(k + 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BondGraphWarning)
        other = derive(aug, outputs=outs)
    if other.states != model.states:
        return [], "the bond variables need other states than the model"
    live = set(model.states) | set(model.inputs) | set(model.input_derivatives)
    found = []
    for i in picked:
        y = model.output_exprs[i]
        hit = None
        if y != 0:
            for name, c in zip(other.output_names, other.output_exprs):
                if c == 0:
                    continue
                ratio = sympy.cancel(y / c)
                if not (ratio.free_symbols & live):
                    hit = (int(name[len("e_bond"):]) - 1, "effort" if name[0] == "e" else "flow")
                    break
        if hit is None:
            return [], (f"output {model.output_names[i]!r} is not proportional to one effort or "
                        "flow of the bond graph (no single detector measures it)")
        found.append(hit)
    return found, ""


def _assign(flat: FlatGraph, prefer: frozenset) -> AugmentedBondGraph:
    return assign_causality(flat, prefer_derivative=prefer)


def _effort_in(aug: AugmentedBondGraph, name: str) -> list[bool]:
    flat = aug.flat
    return [aug.effort_into(name, flat.bonds[k].number) for k in flat.incidence[name]]


def _conflict_site(flat: FlatGraph, text: str) -> str:
    m = re.match(r"causality conflict on bond (\d+)", text)
    if not m:
        return "the junction structure"
    b = flat.bonds[int(m.group(1)) - 1]
    ends = [n for n in (b.tail, b.head) if flat.element(n).drawing_role == "junction"]
    return ends[0] if ends else b.tail


def derivative_causality(model: Model, *, kind: str = "controllability",
                         signals: Optional[Sequence[str]] = None,
                         detectors: Optional[Mapping[str, Any]] = None) -> DerivativeCausality:
    """Sueur and Dauphin-Tanguy's structural rank from the bond graph in derivative causality.

    Parameters
    ----------
    model : Model
        A derived model (its augmented bond graph is used).
    kind : {"controllability", "observability"}
        Dualise the sources of the inputs (rank of ``[A B]``) or put dualised
        detectors on the outputs (rank of ``[A; C]``).
    signals : sequence of str, optional
        The inputs (outputs) to use; default all.
    detectors : mapping of str to signal, optional
        Observability: the signal each output was defined by (the ``outputs``
        given to :func:`bondgraph.derive`, e.g. ``{"v": bg.effort("a")}``):
        the detector sits on that bond.  Without it every bond variable is
        derived once to find the one each output is proportional to, on graphs
        of at most 12 bonds (larger ones need ``detectors``).

    Returns
    -------
    DerivativeCausality

    Raises
    ------
    StructureError
        An unknown ``kind`` or signal name.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.structure import derivative_causality
    >>> g = bg.BondGraph("two_rc")
    >>> a = bg.Zero("a")
    >>> g.add(bg.Sf("i"), a, bg.C("C1"), bg.R("R1"))
    >>> for t, h in [("i", a), (a, "C1"), (a, "R1")]: _ = g.connect(t, h)
    >>> obs = derivative_causality(bg.derive(g, outputs={"v": bg.effort("a")}),
    ...                            kind="observability")
    >>> obs.rank, obs.dualised
    (1, ('SS:v',))
    """
    if kind not in ("controllability", "observability"):
        raise StructureError(f"kind: expected 'controllability' or 'observability', got {kind!r}")
    aug = model.augmented
    owners = state_elements(model)
    states = tuple(s for s in model.state_names if owners.get(s))
    if aug is None:
        return _not(kind, model, "the model has no bond graph", states)
    flat = aug.flat
    names = model.input_names if kind == "controllability" else model.output_names
    chosen = tuple(names) if signals is None else tuple(signals)
    for s in chosen:
        if s not in names:
            word = "input" if kind == "controllability" else "output"
            raise StructureError(f"model {model.name!r} has no {word} {s!r}; {word}s: "
                                 f"{', '.join(names) or 'none'}")
    taken = set(flat.index)
    replace: dict = {}
    splits: list = []
    dualised: list[str] = []
    if kind == "controllability":
        for el in flat.elements:
            if el.input_name() in chosen:
                if len(flat.incidence[el.name]) != 1:
                    return _not(kind, model, f"the input source {el.label()} is not a one-port",
                                states)
                ss = rename(SS("u", note=f"dualised {el.kind}"), el.name)
                replace[el.name] = ss
                dualised.append(ss.label())
    else:
        picked = [model.output_names.index(s) for s in chosen]
        if detectors is None and len(flat.bonds) > _SEARCH_BONDS:
            return _not(kind, model, f"{len(flat.bonds)} bonds: give detectors= (the outputs "
                        "given to derive) to place the detectors", states)
        try:
            bonds, why = (_detector_bonds(model, picked) if detectors is None else
                          _given_bonds(model, chosen, detectors))
        except StructureError:
            raise
        except BondGraphError as err:
            bonds, why = [], f"the bond variables cannot be derived ({err})"
        if why:
            return _not(kind, model, why, states)
        for (k, var), out in zip(bonds, chosen):
            junction = (Zero if var == "effort" else One)(_fresh(f"{var[0]}_{out}", taken))
            port = SS(_fresh(out if out not in taken else f"D{out}", taken),
                      note=f"detector of {var}")
            splits.append((k, junction, port))
            dualised.append(port.label())
    flat2 = _flat(flat, replace, splits)
    prefer = frozenset(flat2.index)       # only storage elements answer the preference
    try:
        bgd = _assign(flat2, prefer)
    except CausalityConflictError as err:       # pragma: no cover - freeing ports cannot conflict
        return _not(kind, model, f"no causal assignment ({err})", states)
    bgd, integral, conflicts, junctions = _maximal(bgd, flat2, prefer)
    return DerivativeCausality(kind=kind, model=model.name, applicable=True, why="",
                               states=states, rank=len(states) - len(integral),
                               integral=integral, conflicts=conflicts, junctions=junctions,
                               dualised=tuple(dualised), augmented=bgd)


def _restored(found: AugmentedBondGraph, flat2: FlatGraph) -> AugmentedBondGraph:
    """``found`` with the held stand-ins replaced by their elements again."""
    flat = _flat(found.flat, {el.name: el for el in flat2.elements}, ())
    classes: dict[str, list[str]] = {"integral": [], "derivative": []}
    for el in flat.elements:
        ein = _effort_in(found, el.name)
        cls = el.causal_class(ein, [False] * len(ein))
        if cls in classes:
            classes[cls].append(el.name)
    return AugmentedBondGraph(flat=flat, stroke_at_head=found.stroke_at_head,
                              integral=tuple(classes["integral"]),
                              derivative=tuple(classes["derivative"]),
                              arbitrary=found.arbitrary, arbitrary_bonds=found.arbitrary_bonds,
                              loops=found.loops)


def _storage(bgd: AugmentedBondGraph) -> tuple[list[str], list[str]]:
    """States of the elements in integral causality, and the one-ports in derivative causality."""
    integral: list[str] = []
    derivative: list[str] = []
    for el in bgd.flat.elements:
        ein = _effort_in(bgd, el.name)
        integral += el.state_names(ein)
        if el.derivative_ports(ein) and len(ein) == 1:
            derivative.append(el.name)
    return integral, derivative


def _owner(bgd: AugmentedBondGraph, state: str) -> Element:
    for el in bgd.flat.elements:
        if state in el.state_names(_effort_in(bgd, el.name)):
            return el
    raise StructureError(f"no element holds state {state!r}")  # pragma: no cover


def _maximal(bgd: AugmentedBondGraph, flat2: FlatGraph, prefer: frozenset):
    """Move integral elements into derivative causality while possible; explain the rest."""
    conflicts: dict[str, tuple[str, str]] = {}
    changed = True
    while changed:
        changed = False
        integral, derivative = _storage(bgd)
        held = {}
        for name in derivative:      # every element in derivative causality stays there
            el = flat2.element(name)
            held[name] = rename(_Fixed("x", effort_in=_effort_in(bgd, name)[0],
                                       reason=f"derivative causality of {el.label()}",
                                       shown=el.label()), name)
        for s in integral:
            el = _owner(bgd, s)
            ein = _effort_in(bgd, el.name)
            if len(ein) != 1:
                conflicts[s] = ("a multiport field", el.label())
                continue
            trial = dict(held)
            trial[el.name] = rename(_Fixed("x", effort_in=not ein[0],
                                           reason=f"derivative causality of {el.label()}",
                                           shown=el.label()),
                                    el.name)
            try:
                found = _assign(_flat(flat2, trial, ()), frozenset())
            except CausalityConflictError as err:
                text = str(err).split(" (no causal assignment exists")[0]
                conflicts[s] = (text, _conflict_site(flat2, text))
                continue
            # derivative causality was still possible: keep it and look again
            bgd = _restored(found, flat2)
            changed = True
            break
    integral, _ = _storage(bgd)
    return (bgd, tuple(integral), tuple(conflicts[s][0] for s in integral),
            tuple(conflicts[s][1] for s in integral))
