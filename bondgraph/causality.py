"""Causality by the Sequential Causality Assignment Procedure (SCAP).

The rules are the elements' own (the element protocol,
:mod:`bondgraph.elements.protocol`); this module only searches.  Forced decisions first
(sources), then the elements' choice points by priority (storage elements one
at a time with integral causality preferred, then R elements where a choice
remains), then any junction bond still open; after each decision the elements
at both ends of the bond apply their propagation rule (junctions, TF, GY) from
a worklist.  The rules see counters of decided ports, so without conflicts
each bond is handled a bounded number of times and the procedure is linear in
the number of bonds.

The choices are made in an order that depends only on the graph, never on
the order of ``add``/``connect``: by priority, then nearest a source (fewest
bonds away from an element with forced decisions), ties broken by name.  A
conflict is not final: the decisions since the latest choice that has an
alternative are undone (a journal) and the alternative is tried, so a valid
assignment is found whenever one exists, and a storage element ends in
derivative causality only when no valid assignment keeps it integral together
with those before it.

The causal stroke of a bond sits at the end of the element that *receives
effort* (and so sends flow back).

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("rl")
>>> V, j = bg.Se("V"), bg.One("j")
>>> g.add(V, j, bg.R("R"), bg.I("L"))
>>> for t, h in [(V, j), (j, "R"), (j, "L")]: _ = g.connect(t, h)
>>> aug = bg.assign_causality(g)
>>> aug.integral, aug.derivative
(('L',), ())
>>> aug.bond(1).stroke     # Se imposes effort on the junction
'j'
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
from typing import Union

import networkx as nx

from ._support.gcpause import with_paused_gc
from .errors import CausalityConflictError, CausalityError
from .flatten import FlatGraph, flatten
from .graph import Bond, BondGraph
from .elements.protocol import ARBITRARY, DERIVATIVE, INTEGRAL, CausalPorts, Element

__all__ = ["AugmentedBondGraph", "CausalBond", "assign_causality", "dependencies"]


@dataclass(frozen=True)
class CausalBond:
    """A bond with its causal stroke: ``stroke`` names the element at the stroke end.

    Returned by :meth:`AugmentedBondGraph.bond` and :attr:`AugmentedBondGraph.bonds`.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> _ = g.connect("F", "m")
    >>> b = bg.assign_causality(g).bond(1)
    >>> b, str(b)
    (CausalBond(number=1, tail='F', head='m', stroke='m'), '1: F -> m|')
    """

    number: int
    tail: str
    head: str
    stroke: str

    def __str__(self) -> str:
        mark_t = "|" if self.stroke == self.tail else ""
        mark_h = "|" if self.stroke == self.head else ""
        return f"{self.number}: {mark_t}{self.tail} -> {self.head}{mark_h}"


@dataclass(frozen=True)
class AugmentedBondGraph:
    """A flattened bond graph with causality assigned (immutable).

    Attributes
    ----------
    flat : FlatGraph
    stroke_at_head : tuple of bool
        Per bond (index = number - 1): the stroke is at the head end.
    integral, derivative : tuple of str
        Storage elements in integral and in derivative causality.
    arbitrary : tuple of str
        R elements whose causality was chosen arbitrarily (algebraic loops).
    arbitrary_bonds : tuple of int
        Bonds of a junction-structure loop whose causality was chosen.
    loops : tuple of tuple of int
        Bond numbers of each algebraic loop (zero-order causal cycle).

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> _ = g.connect("F", "m")
    >>> aug = bg.assign_causality(g)
    >>> print(aug)
    augmented bond graph 'mass'
      1: F -> m|
      integral causality: m
      derivative causality: -
    >>> aug.effort_into("m", 1)
    True
    """

    flat: FlatGraph
    stroke_at_head: tuple[bool, ...]
    integral: tuple[str, ...]
    derivative: tuple[str, ...]
    arbitrary: tuple[str, ...]
    arbitrary_bonds: tuple[int, ...]
    loops: tuple[tuple[int, ...], ...] = field(default=())

    @property
    def name(self) -> str:
        return self.flat.name

    @property
    def bonds(self) -> tuple[CausalBond, ...]:
        """All bonds with their strokes."""
        return tuple(self.bond(k + 1) for k in range(len(self.flat.bonds)))

    def bond(self, number: int) -> CausalBond:
        """Bond ``number`` with its causal stroke."""
        b = self.flat.bond(number)
        return CausalBond(b.number, b.tail, b.head,
                          b.head if self.stroke_at_head[number - 1] else b.tail)

    def effort_into(self, element: str, number: int) -> bool:
        """Whether ``element`` receives the effort of bond ``number``."""
        b = self.flat.bond(number)
        return (b.head == element) == self.stroke_at_head[number - 1]

    def __str__(self) -> str:
        lines = [f"augmented bond graph {self.name!r}"]
        lines += [f"  {b}" for b in self.bonds]
        lines.append(f"  integral causality: {', '.join(self.integral) or '-'}")
        lines.append(f"  derivative causality: {', '.join(self.derivative) or '-'}")
        if self.arbitrary or self.loops:
            lines.append(f"  arbitrary R: {', '.join(self.arbitrary) or '-'}")
            lines.append("  algebraic loops (bonds): "
                         + "; ".join(" ".join(map(str, lp)) for lp in self.loops))
        return "\n".join(lines)


@with_paused_gc
def assign_causality(graph: Union[BondGraph, FlatGraph], *,
                     prefer_derivative: frozenset = frozenset()) -> AugmentedBondGraph:
    """Assign causality to every bond by SCAP.

    Parameters
    ----------
    graph : BondGraph or FlatGraph
    prefer_derivative : set of str, optional
        Storage elements to try in derivative causality first (used by
        :func:`bondgraph.derive` when an integral choice leaves a singular
        algebraic loop: a storage element whose effort or flow the junction
        structure fixes algebraically).

    Returns
    -------
    AugmentedBondGraph

    Raises
    ------
    CausalityConflictError
        When two requirements contradict (two Sf on a 1-junction, two Se on a
        0-junction, a source forced into the wrong causality); the message
        names the bonds and elements involved.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("rc")
    >>> g.add(bg.Sf("i"), bg.Zero("v"), bg.R("R"), bg.C("C"))
    >>> for tail, head in [("i", "v"), ("v", "R"), ("v", "C")]: _ = g.connect(tail, head)
    >>> aug = bg.assign_causality(g)
    >>> aug.integral, [str(b) for b in aug.bonds]
    (('C',), ['1: |i -> v', '2: v -> R|', '3: |v -> C'])
    """
    flat = graph if isinstance(graph, FlatGraph) else flatten(graph)
    return _Scap(flat, frozenset(prefer_derivative)).run()


class _Ports(CausalPorts):
    """One element's ports as SCAP sees them: port p is bond ``inc[p]``; counters kept
    up to date by :meth:`_Scap._set` and :meth:`_Scap._undo`."""

    __slots__ = ("scap", "name", "inc", "count", "undecided", "efforts_in")

    def __init__(self, scap: "_Scap", name: str, inc: tuple[int, ...]) -> None:
        self.scap = scap
        self.name = name
        self.inc = inc
        self.count = len(inc)
        self.undecided = len(inc)
        self.efforts_in = 0      # decided bonds with effort into the element

    def effort_in(self, port: int):
        k = self.inc[port]
        v = self.scap.head_gets_effort[k]
        if v is None:
            return None
        return v if self.scap.bonds[k].head == self.name else not v

    def open(self) -> list[int]:
        hge = self.scap.head_gets_effort
        return [p for p, k in enumerate(self.inc) if hge[k] is None]

    def reason(self, port: int) -> str:
        return self.scap.why[self.inc[port]]

    def number(self, port: int) -> int:
        return self.scap.bonds[self.inc[port]].number

    def into(self, port: int) -> bool:
        return self.scap.bonds[self.inc[port]].head == self.name


class _Scap:
    """SCAP as a depth-first search over its choices, with a journal to undo them.

    Choice points, in an order that depends on names only (never on the order
    of ``add``/``connect``): storage elements (integral causality first),
    R elements, then junction-structure bonds still undecided.  After each
    choice the consequences are propagated; a conflict undoes everything
    decided since the most recent choice that still has an alternative and
    tries that alternative (chronological backtracking).  The first complete
    assignment found is the one SCAP's preference order gives: a storage
    element is in derivative causality only when no valid assignment keeps it
    (together with the storage elements before it) integral.
    """

    def __init__(self, flat: FlatGraph, prefer_derivative: frozenset = frozenset()) -> None:
        self.flat = flat
        self.prefer_derivative = prefer_derivative
        self.bonds: tuple[Bond, ...] = flat.bonds
        nb = len(self.bonds)
        self.head_gets_effort: list = [None] * nb
        self.why: list = [None] * nb
        self.element: dict[str, Element] = {el.name: el for el in flat.elements}
        self.ports = {n: _Ports(self, n, flat.incidence[n]) for n in flat.index}
        self.origins: list[str] = []   # elements that force decisions (sources)
        self.element_bonds: set[int] = set()   # bonds with a choice point of their element
        self.queue: deque = deque()
        self.trail: list[int] = []  # every decided bond, in order (the journal)
        self.budget = 200 * (nb + 10) + 100_000  # propagation steps before giving up

    # effort into element `name` on bond k?
    def _ein(self, name: str, k: int):
        v = self.head_gets_effort[k]
        if v is None:
            return None
        return v if self.bonds[k].head == name else not v

    def _set(self, k: int, name: str, effort_in: bool, reason: str) -> None:
        """Decide bond k so that `name` receives effort iff effort_in."""
        b = self.bonds[k]
        want = effort_in if b.head == name else not effort_in
        have = self.head_gets_effort[k]
        if have is not None:
            if have != want:
                raise CausalityConflictError(self._conflict(k, name, effort_in, reason))
            return
        self.head_gets_effort[k] = want
        self.why[k] = reason
        self.trail.append(k)
        for end in (b.tail, b.head):
            ports = self.ports[end]
            ports.undecided -= 1
            if self._ein(end, k):
                ports.efforts_in += 1
            self.queue.append(end)

    def _conflict(self, k: int, name: str, effort_in: bool, reason: str) -> str:
        b = self.bonds[k]
        el = self.flat.element(name)
        need = "to receive effort" if effort_in else "to impose effort"
        hint = self.element[b.tail].conflict_hint or self.element[b.head].conflict_hint
        return (f"causality conflict on bond {b.number} ({b.tail} -> {b.head}): "
                f"{el.label()} needs it {need} ({reason}), but it was already decided by "
                f"{self.why[k]}.{hint}")

    def _undo(self, mark: int) -> None:
        """Undo every decision taken after the journal had ``mark`` entries."""
        while len(self.trail) > mark:
            k = self.trail.pop()
            b = self.bonds[k]
            for end in (b.tail, b.head):
                ports = self.ports[end]
                ports.undecided += 1
                if self._ein(end, k):
                    ports.efforts_in -= 1
            self.head_gets_effort[k] = None
            self.why[k] = None
        self.queue.clear()

    def _propagate(self) -> None:
        flat = self.flat
        while self.queue:
            self.budget -= 1
            if self.budget < 0:
                raise CausalityError(
                    f"model {flat.name!r}: causality search gave up after exploring too many "
                    "alternatives; the junction structure has many interlocking loops. "
                    "Assign causality by hand-simplifying the junction structure."
                )
            name = self.queue.popleft()
            ports = self.ports[name]
            for port, effort_in, reason in self.element[name].propagate(ports):
                self._set(ports.inc[port], name, effort_in, reason)

    def _distance_from_sources(self) -> dict[str, int]:
        """Number of bonds from each element to the nearest origin (breadth first)."""
        flat = self.flat
        dist = {name: 0 for name in self.origins}
        frontier = deque(sorted(dist))
        while frontier:
            name = frontier.popleft()
            for k in flat.incidence[name]:
                b = self.bonds[k]
                other = b.head if b.tail == name else b.tail
                if other not in dist:
                    dist[other] = dist[name] + 1
                    frontier.append(other)
        return dist

    def _choices(self) -> list[tuple[int, str, bool, str]]:
        """(bond, element, preferred effort_in, reason) per choice point: the elements'
        choices by priority, then the bonds still open, in name order."""
        flat = self.flat
        # storage nearest the sources first (the motor's inertia before the load's),
        # ties by name: nothing here depends on the order of add/connect
        dist = self._distance_from_sources()
        by_name = sorted(flat.elements, key=lambda el: (dist.get(el.name, len(dist) + 1), el.name))
        groups: dict[int, list[tuple[int, str, bool, str]]] = {}
        for el in by_name:
            inc = flat.incidence[el.name]
            for c in el.causal_choices(el.name in self.prefer_derivative):
                groups.setdefault(c.priority, []).append(
                    (inc[c.port], el.name, c.effort_in, c.reason))
        out = [choice for priority in sorted(groups) for choice in groups[priority]]
        self.element_bonds = {choice[0] for choice in out}
        seen: dict[tuple[str, str], int] = {}
        keyed = []
        for k, b in enumerate(self.bonds):
            nth = seen.get((b.tail, b.head), 0)
            seen[(b.tail, b.head)] = nth + 1
            keyed.append(((b.tail, b.head, nth), k))
        for _, k in sorted(keyed):
            out.append((k, self.bonds[k].head, False, f"arbitrary choice for bond {k + 1}"))
        return out

    def _search(self) -> set[int]:
        """Decide every bond; return the choice points that were free when reached."""
        choices = self._choices()
        stack: list[tuple[int, int, bool]] = []   # (choice index, journal mark, alternative left)
        free: set[int] = set()
        first_error: CausalityConflictError | None = None
        i = 0
        while i < len(choices):
            k, name, pref, reason = choices[i]
            if self.head_gets_effort[k] is not None:
                i += 1
                continue
            mark = len(self.trail)
            values = [pref, not pref]
            j = 0
            while True:
                if j < 2:
                    try:
                        self._set(k, name, values[j], reason)
                        self._propagate()
                        stack.append((i, mark, j == 0))
                        free.add(i)
                        i += 1
                        break
                    except CausalityConflictError as err:
                        first_error = first_error or err
                        self._undo(mark)
                        j += 1
                        continue
                # both values failed here: go back to the latest choice with an alternative
                while stack and not stack[-1][2]:
                    free.discard(stack.pop()[0])
                if not stack:
                    assert first_error is not None
                    raise CausalityConflictError(
                        f"{first_error} (no causal assignment exists: every alternative of the "
                        "storage, R and junction choices leads to a conflict; the junction "
                        "structure may be redundant, e.g. a circuit drawn with a 0-junction for "
                        "every node including ground: remove the ground node's junction)"
                    ) from first_error
                i, mark, _ = stack.pop()
                free.discard(i)
                self._undo(mark)
                k, name, pref, reason = choices[i]
                values = [pref, not pref]
                j = 1
        return {choices[i][0] for i in free}

    def run(self) -> AugmentedBondGraph:
        flat = self.flat
        els = flat.elements
        for el in sorted(els, key=lambda el: el.name):
            ports = self.ports[el.name]
            forced = el.forced_causality(ports)
            if forced:
                self.origins.append(el.name)
                for port, effort_in, reason in forced:
                    self._set(ports.inc[port], el.name, effort_in, reason)
                self._propagate()
        chosen = self._search()
        found: dict[str, list[str]] = {INTEGRAL: [], DERIVATIVE: [], ARBITRARY: []}
        hge, bonds = self.head_gets_effort, self.bonds
        for el in els:
            name = el.name
            inc = flat.incidence[name]
            cls = el.causal_class([hge[k] if bonds[k].head == name else not hge[k] for k in inc],
                                  [k in chosen for k in inc])
            if cls is not None:
                found[cls].append(el.name)
        arbitrary_bonds = sorted(k + 1 for k in chosen if k not in self.element_bonds)
        aug = AugmentedBondGraph(
            flat=flat,
            stroke_at_head=tuple(self.head_gets_effort),
            integral=tuple(found[INTEGRAL]),
            derivative=tuple(found[DERIVATIVE]),
            arbitrary=tuple(found[ARBITRARY]),
            arbitrary_bonds=tuple(arbitrary_bonds),
        )
        return _with_loops(aug)


def dependencies(aug: AugmentedBondGraph) -> tuple[list[int], list[tuple[int, ...]]]:
    """Which element computes each bond variable, and from which variables.

    Variables are numbered ``2*k`` (effort of bond index k) and ``2*k + 1``
    (flow).  Storage elements in integral causality and sources need no
    input; a storage element in derivative causality depends on its input
    variable (it is differentiated).

    Parameters
    ----------
    aug : AugmentedBondGraph
        A graph with causality assigned.

    Returns
    -------
    producer : list of int
        Index (into ``aug.flat.elements``) of the element computing each variable.
    inputs : list of tuple of int
        The variables that element reads to compute it.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.causality import dependencies
    >>> g = bg.BondGraph("rl")
    >>> g.add(bg.Se("V"), bg.One("j"), bg.R("R"), bg.I("L"))
    >>> for tail, head in [("V", "j"), ("j", "R"), ("j", "L")]: _ = g.connect(tail, head)
    >>> dependencies(bg.assign_causality(g))   # elements: V, j, R, L
    ([0, 1, 2, 1, 1, 3], [(), (5,), (3,), (5,), (0, 2), ()])
    """
    flat = aug.flat
    bonds = flat.bonds
    hge = aug.stroke_at_head
    nvar = 2 * len(bonds)
    producer = [0] * nvar
    inputs: list[tuple[int, ...]] = [()] * nvar

    causality = {n: INTEGRAL for n in aug.integral}
    causality.update((n, DERIVATIVE) for n in aug.derivative)
    causality.update((n, ARBITRARY) for n in aug.arbitrary)
    for idx, el in enumerate(flat.elements):
        name = el.name
        inc = flat.incidence[name]
        ein = [hge[k] if bonds[k].head == name else not hge[k] for k in inc]
        reads = el.output_dependencies(ein, causality.get(name))
        for p, k in enumerate(inc):
            v = 2 * k + 1 if ein[p] else 2 * k        # the element's output on port p
            producer[v] = idx
            ports = reads[p]
            if ports:                                  # the input variables it reads
                inputs[v] = tuple([2 * inc[q] if ein[q] else 2 * inc[q] + 1 for q in ports])
    return producer, inputs


def _with_loops(aug: AugmentedBondGraph) -> AugmentedBondGraph:
    """Find the zero-order causal cycles (algebraic loops) and record their bonds."""
    if not aug.arbitrary and not aug.arbitrary_bonds:
        return aug
    producer, inputs = dependencies(aug)
    dg = nx.DiGraph()
    deriv = {aug.flat.index[n] for n in aug.derivative}
    for v, ins in enumerate(inputs):
        if producer[v] in deriv:
            continue
        for u in ins:
            dg.add_edge(u, v)
    loops = []
    for comp in nx.strongly_connected_components(dg):
        if len(comp) > 1:
            loops.append(tuple(sorted({v // 2 + 1 for v in comp})))
    loops.sort()
    return AugmentedBondGraph(
        flat=aug.flat, stroke_at_head=aug.stroke_at_head, integral=aug.integral,
        derivative=aug.derivative, arbitrary=aug.arbitrary,
        arbitrary_bonds=aug.arbitrary_bonds, loops=tuple(loops),
    )
