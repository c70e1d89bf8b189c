"""Causality by the Sequential Causality Assignment Procedure (SCAP).

Sources first, then storage elements one at a time with integral causality
preferred, then R elements where a choice remains, then any junction bond
still open; after each choice the consequences are propagated through
junctions, TF and GY with a worklist.  Junctions keep counters, so without
conflicts each bond is handled a bounded number of times and the procedure
is linear in the number of bonds.

The choices are made in an order that depends only on the graph, never on
the order of ``add``/``connect``: storage elements nearest a source first
(fewest bonds away), ties broken by name.  A conflict is not final: the
decisions since the latest choice that has an alternative are undone
(a journal) and the alternative is tried, so a valid assignment is found
whenever one exists, and a storage element ends in derivative causality only
when no valid assignment keeps it integral together with those before it.

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

from .errors import CausalityConflictError, CausalityError
from .flatten import FlatGraph, flatten
from .graph import Bond, BondGraph

__all__ = ["AugmentedBondGraph", "CausalBond", "assign_causality", "dependencies"]

_STORAGE = ("I", "C")
_TWO_PORT = ("TF", "GY", "MTF", "MGY")


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

    def _repr_svg_(self):
        from .drawing import repr_svg
        return repr_svg(self)

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
        self.undecided = {n: len(flat.incidence[n]) for n in flat.index}
        self.efforts_in = {n: 0 for n in flat.index}  # decided bonds with effort into n
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
            self.undecided[end] -= 1
            if self._ein(end, k):
                self.efforts_in[end] += 1
            self.queue.append(end)

    def _conflict(self, k: int, name: str, effort_in: bool, reason: str) -> str:
        b = self.bonds[k]
        el = self.flat.element(name)
        need = "to receive effort" if effort_in else "to impose effort"
        hint = ""
        kinds = {self.flat.element(b.tail).kind, self.flat.element(b.head).kind}
        if "Sf" in kinds or "Se" in kinds:
            hint = (" Two sources fix the same variable (two Sf on a 1-junction or two "
                    "Se on a 0-junction), or a source drives a storage-free node the wrong "
                    "way: remove one source or put a storage or R element between them.")
        return (f"causality conflict on bond {b.number} ({b.tail} -> {b.head}): "
                f"{el.label()} needs it {need} ({reason}), but it was already decided by "
                f"{self.why[k]}.{hint}")

    def _undo(self, mark: int) -> None:
        """Undo every decision taken after the journal had ``mark`` entries."""
        while len(self.trail) > mark:
            k = self.trail.pop()
            b = self.bonds[k]
            for end in (b.tail, b.head):
                self.undecided[end] += 1
                if self._ein(end, k):
                    self.efforts_in[end] -= 1
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
            el = flat.element(name)
            kind = el.kind
            inc = flat.incidence[name]
            if kind in ("0", "1"):
                # 0: exactly one bond brings effort in; 1: exactly one takes effort out
                strong_is_in = kind == "0"
                n = len(inc)
                strong = self.efforts_in[name] if strong_is_in else \
                    (n - self.undecided[name] - self.efforts_in[name])
                if strong > 1:
                    ks = [k for k in inc if self._ein(name, k) is strong_is_in]
                    raise CausalityConflictError(
                        f"causality conflict at {el.label()}: bonds "
                        f"{', '.join(str(self.bonds[k].number) for k in ks)} all "
                        f"{'impose its effort' if strong_is_in else 'set its flow'} "
                        f"(from {', '.join(str(self.why[k]) for k in ks)}); a "
                        f"{kind}-junction takes exactly one. Remove one of the sources "
                        "or add a storage or R element between them."
                    )
                if self.undecided[name] == 0:
                    if strong == 0:
                        raise CausalityConflictError(
                            f"causality conflict at {el.label()}: no bond "
                            f"{'imposes its effort' if strong_is_in else 'sets its flow'}"
                        )
                    continue
                if strong == 1:
                    for k in inc:
                        if self.head_gets_effort[k] is None:
                            self._set(k, name, not strong_is_in, f"{el.label()}")
                elif self.undecided[name] == 1:
                    for k in inc:
                        if self.head_gets_effort[k] is None:
                            self._set(k, name, strong_is_in, f"{el.label()}")
            elif kind in _TWO_PORT:
                k1, k2 = inc
                a, b = self._ein(name, k1), self._ein(name, k2)
                # TF passes effort through (exactly one port receives it); GY
                # turns flow into effort (both ports receive effort, or neither)
                same = kind in ("GY", "MGY")
                if a is not None and b is None:
                    self._set(k2, name, a if same else not a, el.label())
                elif b is not None and a is None:
                    self._set(k1, name, b if same else not b, el.label())
                elif a is not None and b is not None and (a == b) != same:
                    raise CausalityConflictError(
                        f"causality conflict at {el.label()}: bonds {self.bonds[k1].number} and "
                        f"{self.bonds[k2].number} were decided independently "
                        f"(by {self.why[k1]} and {self.why[k2]}) and "
                        + ("both bring effort into it or both take it out; a "
                           f"{kind} passes effort from one port to the other"
                           if not same else
                           "only one of them brings effort in; a "
                           f"{kind} takes effort on both ports or on neither")
                    )

    def _distance_from_sources(self) -> dict[str, int]:
        """Number of bonds from each element to the nearest source (breadth first)."""
        flat = self.flat
        dist = {el.name: 0 for el in flat.elements if el.kind in ("Se", "Sf")}
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
        """(bond, element, preferred effort_in, reason) per choice point, in name order."""
        flat = self.flat
        # storage nearest the sources first (the motor's inertia before the load's),
        # ties by name: nothing here depends on the order of add/connect
        dist = self._distance_from_sources()
        by_name = sorted(flat.elements, key=lambda el: (dist.get(el.name, len(dist) + 1), el.name))
        out = []
        for el in by_name:
            if el.kind in _STORAGE:
                (k,) = flat.incidence[el.name]
                if el.name in self.prefer_derivative:
                    out.append((k, el.name, el.kind != "I", f"derivative causality of {el.label()}"))
                else:
                    out.append((k, el.name, el.kind == "I", f"integral causality of {el.label()}"))
        for el in by_name:
            if el.kind == "R":
                (k,) = flat.incidence[el.name]
                out.append((k, el.name, False, f"arbitrary choice for {el.label()}"))
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
            if el.kind in ("Se", "Sf"):
                (k,) = flat.incidence[el.name]
                self._set(k, el.name, el.kind == "Sf", f"source {el.label()}")
                self._propagate()
        chosen = self._search()
        integral: list[str] = []
        derivative: list[str] = []
        arbitrary: list[str] = []
        arbitrary_bonds: list[int] = []
        for el in els:
            if el.kind in _STORAGE:
                (k,) = flat.incidence[el.name]
                (integral if self._ein(el.name, k) == (el.kind == "I") else derivative).append(el.name)
            elif el.kind == "R" and flat.incidence[el.name][0] in chosen:
                arbitrary.append(el.name)
        one_ports = {flat.incidence[el.name][0] for el in els
                     if el.kind in _STORAGE or el.kind == "R"}
        arbitrary_bonds = sorted(k + 1 for k in chosen if k not in one_ports)
        aug = AugmentedBondGraph(
            flat=flat,
            stroke_at_head=tuple(self.head_gets_effort),
            integral=tuple(integral),
            derivative=tuple(derivative),
            arbitrary=tuple(arbitrary),
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

    def ein(name: str, k: int) -> bool:
        return hge[k] if bonds[k].head == name else not hge[k]

    def incoming(name: str, k: int) -> int:
        return 2 * k if ein(name, k) else 2 * k + 1

    def outgoing(name: str, k: int) -> int:
        return 2 * k + 1 if ein(name, k) else 2 * k

    for idx, el in enumerate(flat.elements):
        name, kind = el.name, el.kind
        inc = flat.incidence[name]
        if kind in ("0", "1"):
            strong_in = kind == "0"
            strong = next(k for k in inc if ein(name, k) is strong_in)
            out_strong = outgoing(name, strong)
            producer[out_strong] = idx
            inputs[out_strong] = tuple(incoming(name, k) for k in inc if k != strong)
            src = incoming(name, strong)
            for k in inc:
                if k != strong:
                    v = outgoing(name, k)
                    producer[v] = idx
                    inputs[v] = (src,)
        elif kind in _TWO_PORT:
            # TF: e1 = n e2, f2 = n f1; GY: e1 = r f2, e2 = r f1 -- either way each
            # port's output is computed from the other port's input
            k1, k2 = inc
            for a, b in ((k1, k2), (k2, k1)):
                producer[outgoing(name, a)] = idx
                inputs[outgoing(name, a)] = (incoming(name, b),)
        else:
            (k,) = inc
            v = outgoing(name, k)
            producer[v] = idx
            if kind == "R" or name in aug.derivative:
                inputs[v] = (incoming(name, k),)
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
