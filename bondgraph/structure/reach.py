"""Structural controllability and observability of a linear bond-graph model.

For each state (each storage element in integral causality, and each
integrator added for an output) the analysis asks two questions, after
Sueur and Dauphin-Tanguy (1991) and Lin (1974):

1. *Causal paths*: is there a causal path from an input to the state
   (controllability) or from the state to an output (observability)?  A state
   no path reaches is uncontrollable (unobservable) for every parameter value.
2. *Rank*: the rank of ``[A B]`` (of ``[A; C]``), three ways.  From the bond
   graph (Sueur and Dauphin-Tanguy, :mod:`bondgraph.structure.derivative`):
   ``n`` minus the storage elements that stay in integral causality when
   derivative causality is preferred and the sources (detectors) are
   dualised; each names the junction where its derivative causality
   conflicts.  From the equations: the size of a maximum matching in the
   bipartite graph of the nonzero entries
   (:func:`networkx.bipartite.hopcroft_karp_matching`).  Numerically: the
   exact rank at random rational parameter points (the generic rank, the
   cross-check).  The structural values are upper bounds of the generic one
   and differ from it only when causal-path gains cancel (junction-structure
   gains of opposite sign); the result reports all three.  The states in the
   support of the left kernel are the ones involved in a deficiency, with the
   junctions they share.

Finally the generic rank of the Kalman matrix ``[B AB ... A^(n-1)B]`` tells
whether the model is controllable for almost all parameter values; a state
outside its range for every point is named as uncontrollable with the reason
(no causal path, a rank deficiency of ``[A B]``, or a dependence between
parameters).

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.structure import controllability
>>> g = bg.BondGraph("series_c")
>>> j = bg.One("j")
>>> g.add(bg.Sf("i"), j, bg.C("C1"), bg.C("C2"), bg.R("R"))
>>> for t, h in [("i", j), (j, "C1"), (j, "C2"), (j, "R")]: _ = g.connect(t, h)
>>> res = controllability(bg.derive(g))
>>> res.generic_rank, res.controllable, res.lost
(1, False, ('q_C1', 'q_C2'))
>>> print(res.reason("q_C2"))
q_C2 (C:C2): reached by a causal path (i -> q_C2) but [A B] has rank 1 < 2: q_C1, q_C2 share the junction j; in derivative causality with the sources dualised C:C2 stays integral, its derivative causality conflicts at the junction j
>>> res.graph_rank
1
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping, Optional, Sequence

import networkx as nx
import sympy

from ..model import Model
from ._generic import (PRIMES, LinearForm, StructureError, at_point, exact_rank,
                       left_kernel_support, modular, modular_rank_and_support,
                       linear_form, random_points, term_rank)
from ._paths import bond_paths as bond_paths_to, path_names, signal_digraph, state_elements
from .derivative import DerivativeCausality, derivative_causality

__all__ = ["Reachability", "controllability", "observability"]


@dataclass(frozen=True)
class Reachability:
    """Structural controllability or observability of a model (immutable).

    Attributes
    ----------
    kind : {"controllability", "observability"}
    model : str
    states : tuple of str
    elements : tuple of (str or None)
        The storage element of each state (None: an integrator for an output).
    signals : tuple of str
        The inputs (controllability) or outputs (observability) considered.
    paths : tuple of tuple of str
        Per state, a shortest causal path in the signal digraph (input ->
        states -> state, or state -> states -> output); ``()`` when none.
    bond_paths : tuple of tuple of str
        Per state (controllability only), the elements of a shortest causal path
        in the augmented bond graph from a source to the storage element.
    structural_rank : int
        Maximum-matching rank of ``[A B]`` (``[A; C]``).
    generic_rank : int
        Exact rank of ``[A B]`` (``[A; C]``) for almost all parameter values.
    deficient : tuple of str
        States involved in a rank deficiency of ``[A B]`` (``[A; C]``).
    shared : tuple of str
        Elements adjacent to two or more of the ``deficient`` storage elements
        (the junctions where the deficiency sits).
    kalman_rank : int
        Generic rank of the controllability (observability) matrix.
    lost : tuple of str
        States on which an uncontrollable (unobservable) direction has a
        component, for almost all parameter values.
    graph : DerivativeCausality or None
        The bond graph in derivative causality with the sources (detectors)
        dualised, Sueur and Dauphin-Tanguy's structural rank and the junctions
        where it is lost (drawable: ``res.graph.draw()``).
    """

    kind: str
    model: str
    states: tuple[str, ...]
    elements: tuple[Optional[str], ...]
    signals: tuple[str, ...]
    paths: tuple[tuple[str, ...], ...]
    bond_paths: tuple[tuple[str, ...], ...]
    structural_rank: int
    generic_rank: int
    deficient: tuple[str, ...]
    shared: tuple[str, ...]
    kalman_rank: int
    lost: tuple[str, ...]
    graph: Optional[DerivativeCausality] = None

    @property
    def n(self) -> int:
        return len(self.states)

    @property
    def graph_rank(self) -> Optional[int]:
        """Structural rank from the bond graph in derivative causality (None: not applicable,
        see ``graph.why``); covers the storage states, not the output integrators."""
        return self.graph.rank if self.graph is not None else None

    def draw(self, path=None, **options) -> str:
        """Draw the bond graph in derivative causality with the dualised ports
        (:meth:`DerivativeCausality.draw`)."""
        if self.graph is None:
            raise StructureError(f"{self.kind} of {self.model!r}: no bond graph to draw")
        return self.graph.draw(path, **options)

    def _graph_text(self, state: str) -> str:
        g = self.graph
        if g is None or not g.applicable:
            return ""
        ports = "sources" if self.kind == "controllability" else "detectors"
        if state in g.integral:
            el = self.elements[self._index(state)] or state
            where = g.junctions[g.integral.index(state)]
            return (f"; in derivative causality with the {ports} dualised {el} stays integral, "
                    f"its derivative causality conflicts at the junction {where}")
        if g.integral:
            return (f"; in derivative causality with the {ports} dualised "
                    f"{', '.join(g.integral)} stay{'s' if len(g.integral) == 1 else ''} integral "
                    f"(conflicts at {', '.join(dict.fromkeys(g.junctions))})")
        return (f"; the bond graph in derivative causality gives rank {g.rank} (causal-path "
                "gains cancel)")

    @property
    def unreached(self) -> tuple[str, ...]:
        """States that no causal path connects to the signals."""
        return tuple(s for s, p in zip(self.states, self.paths) if not p)

    @property
    def structural(self) -> bool:
        """Structurally controllable (observable): every state reached, full generic rank."""
        return not self.unreached and self.generic_rank == self.n

    @property
    def controllable(self) -> bool:
        """Full generic Kalman rank (``observable`` is the same for observability)."""
        return self.kalman_rank == self.n

    observable = controllable

    def path(self, state: str) -> tuple[str, ...]:
        """The causal path of ``state`` (see :attr:`paths`)."""
        return self.paths[self._index(state)]

    def _index(self, state: str) -> int:
        if state not in self.states:
            raise StructureError(f"model {self.model!r} has no state {state!r}; "
                                 f"states: {', '.join(self.states)}")
        return self.states.index(state)

    def _label(self, state: str) -> str:
        el = self.elements[self._index(state)]
        return f"{state} ({el})" if el else f"{state} (integrator)"

    def reason(self, state: str) -> str:
        """Why ``state`` is, or is not, controllable (observable)."""
        i = self._index(state)
        word = "from the inputs" if self.kind == "controllability" else "to the outputs"
        label = self._label(state)
        mat = "[A B]" if self.kind == "controllability" else "[A; C]"
        if not self.paths[i]:
            return f"{label}: no causal path {word} ({', '.join(self.signals) or 'none'})"
        via = f"reached by a causal path ({' -> '.join(self.paths[i])})"
        if state in self.deficient:
            where = f": {', '.join(self.deficient)} share {self._shared_text()}"
            return (f"{label}: {via} but {mat} has rank {self.generic_rank} < {self.n}{where}"
                    + self._graph_text(state))
        if state in self.lost:
            word2 = "controllability" if self.kind == "controllability" else "observability"
            return (f"{label}: {via} and {mat} has full rank, but the {word2} matrix has rank "
                    f"{self.kalman_rank} < {self.n} for every parameter value (the parameters "
                    "of the elements along the paths are not independent)")
        return f"{label}: {via}"

    def _shared_text(self) -> str:
        if not self.shared:
            return "no single junction"
        return ("the junction " if len(self.shared) == 1 else "the junctions ") + \
            ", ".join(self.shared)

    def __str__(self) -> str:
        sig = "from " if self.kind == "controllability" else "to "
        lines = [f"structural {self.kind} of {self.model!r} {sig}{', '.join(self.signals)}"]
        lines += ["  " + self.reason(s) for s in self.states]
        mat = "[A B]" if self.kind == "controllability" else "[A; C]"
        g = self.graph
        by_graph = (f"{g.rank} of {len(g.states)} storage states" if g is not None and
                    g.applicable else f"not applicable: {g.why}" if g is not None else "-")
        lines.append(f"  rank {mat} = {self.generic_rank} of {self.n} (by matching: "
                     f"{self.structural_rank}; bond graph in derivative causality: {by_graph})")
        verdict = "yes" if self.controllable else "no"
        word = "controllable" if self.kind == "controllability" else "observable"
        lines.append(f"  {word} for almost all parameter values: {verdict} "
                     f"(Kalman rank {self.kalman_rank})")
        return "\n".join(lines)


def _pick(names: Sequence[str], wanted, what: str, model: str) -> tuple[int, ...]:
    if wanted is None:
        return tuple(range(len(names)))
    if isinstance(wanted, str):
        wanted = (wanted,)
    out = []
    for w in wanted:
        if w not in names:
            raise StructureError(f"model {model!r} has no {what} {w!r}; {what}s: "
                                 f"{', '.join(names) or 'none'}")
        out.append(names.index(w))
    return tuple(out)


#: above this many states a Kalman rank found deficient modulo two primes is not
#: recomputed over the rationals (dense rational elimination grows steeply)
KALMAN_EXACT_MAX = 40


def _kalman_rank_and_lost(at: list, n: int) -> tuple[int, tuple[int, ...]]:
    """Kalman rank and left-kernel support of ``[B AB ...]`` from ``[A B]`` at each point.

    The fast route: ``[B AB ... A^(n-1) B]`` modulo a 62-bit prime (python-flint
    ``nmod_mat``).  A rank modulo a prime never exceeds the rank over the
    rationals, so a full rank there is exact.  A deficient rank is confirmed
    over the rationals up to :data:`KALMAN_EXACT_MAX` states; above, by a
    second prime (a wrong deficiency needs both primes to divide every
    nonzero maximal minor at the point).
    """
    best: tuple[int, tuple[int, ...]] = (-1, ())
    for AB in at:
        Av, Bv = AB[:, :n], AB[:, n:]
        if not Bv.cols:
            return 0, tuple(range(n))
        found = None
        for prime in PRIMES:
            mod = _kalman_modular(Av, Bv, n, prime)
            if mod is None or (found is not None and mod != found):
                found = None
                break
            found = mod
            if mod[0] == n:
                break
        if found is None or (found[0] < n and n <= KALMAN_EXACT_MAX):
            found = _kalman_exact(Av, Bv, n)
        if found[0] > best[0]:
            best = found
    return best


def _kalman_modular(Av, Bv, n: int, prime: int):
    A, B = modular(Av, prime), modular(Bv, prime)
    if A is None or B is None:
        return None
    blocks, cur = [B], B
    for _ in range(max(n - 1, 0)):
        cur = A * cur
        blocks.append(cur)
    m = Bv.cols
    K = flint_hstack(blocks, n, m, prime)
    return modular_rank_and_support(K, n)


def flint_hstack(blocks: list, n: int, m: int, prime: int):
    """``[M_0 M_1 ...]`` of flint ``nmod_mat`` blocks of shape ``(n, m)``."""
    import flint

    rows: list[list] = [[] for _ in range(n)]
    for blk in blocks:
        t = blk.tolist()
        for i in range(n):
            rows[i].extend(int(v) for v in t[i])
    return flint.nmod_mat(n, m * len(blocks), [v for r in rows for v in r], prime)


def _kalman_exact(Av, Bv, n: int) -> tuple[int, tuple[int, ...]]:
    blocks, cur = [Bv], Bv
    for _ in range(max(n - 1, 0)):
        cur = Av * cur
        blocks.append(cur)
    K = sympy.Matrix.hstack(*blocks)
    r = exact_rank(K)
    return r, (left_kernel_support(K, {}) if r < n else ())


def _shared(model: Model, elements: Sequence[Optional[str]]) -> tuple[str, ...]:
    aug = model.augmented
    els = [e for e in elements if e]
    if aug is None or len(els) < 2:
        return ()
    flat = aug.flat
    count: dict[str, int] = {}
    for name in set(els):
        nb = set()
        for k in flat.incidence[name]:
            b = flat.bonds[k]
            nb.add(b.head if b.tail == name else b.tail)
        for other in nb:
            count[other] = count.get(other, 0) + 1
    return tuple(sorted(n for n, c in count.items() if c >= 2))


def _analyse(model: Model, kind: str, pick, seed: int, detectors=None) -> Reachability:
    lf: LinearForm = linear_form(model)
    n = len(lf.states)
    owners = state_elements(model)
    elements = tuple(owners[s] for s in lf.states)
    labels = {el.name: el.label() for el in model.augmented.flat.elements} \
        if model.augmented is not None else {}
    elements = tuple(labels.get(e, e) if e else None for e in elements)
    G = signal_digraph(lf)
    points = random_points(lf.parameters, 2, seed=seed)
    if kind == "controllability":
        idx = _pick(lf.inputs, pick, "input", model.name)
        signals = tuple(lf.inputs[j] for j in idx)
        B0 = lf.Bs[0][:, list(idx)] if idx else sympy.zeros(n, 0)
        Ball = sympy.Matrix.hstack(*[B[:, list(idx)] for B in lf.Bs]) if idx else B0
        M = sympy.Matrix.hstack(lf.A, B0)
        A_k, B_k = lf.A, Ball
        starts = [("u", s) for s in signals]
        H = G
    else:
        idx = _pick(lf.outputs, pick, "output", model.name)
        signals = tuple(lf.outputs[j] for j in idx)
        C = lf.C[list(idx), :] if idx else sympy.zeros(0, n)
        M = sympy.Matrix.vstack(lf.A, C).T      # rows: states
        A_k, B_k = lf.A.T, C.T
        starts = [("y", s) for s in signals]
        H = G.reverse(copy=True)
    paths: list[tuple[str, ...]] = []
    if starts:
        H = H.copy()
        H.add_edges_from(("start", s) for s in starts)
        found = nx.single_source_shortest_path(H, "start")
    else:
        found = {}
    for s in lf.states:
        p = found.get(("x", s))
        if p is None:
            paths.append(())
            continue
        names = path_names(p[1:])
        paths.append(names if kind == "controllability" else names[::-1])
    bond_paths: list[tuple[str, ...]] = [()] * n
    aug = model.augmented
    if kind == "controllability" and aug is not None:
        srcs = tuple(el.name for el in aug.flat.elements if el.input_name() in signals)
        held = [i for i, s in enumerate(lf.states) if owners[s] is not None]
        for i, bp in zip(held, bond_paths_to(aug, srcs, [str(owners[lf.states[i]]) for i in held])):
            bond_paths[i] = bp
    # each point substituted once: [A B] (observability: [A^T C^T], rows = states)
    at = [at_point(sympy.Matrix.hstack(A_k, B_k), pt) for pt in points] or \
        [sympy.Matrix.hstack(A_k, B_k)]
    ncols_b0 = M.cols - n
    ranks = [exact_rank(Mv[:, :n + ncols_b0]) for Mv in at]
    best = max(range(len(at)), key=lambda q: ranks[q])
    grank = ranks[best]
    deficient: tuple[str, ...] = ()
    if grank < n:
        deficient = tuple(lf.states[i] for i in left_kernel_support(at[best][:, :n + ncols_b0], {}))
    kal, lost_idx = _kalman_rank_and_lost(at, n)
    return Reachability(
        kind=kind, model=model.name, states=lf.states, elements=elements, signals=signals,
        paths=tuple(paths), bond_paths=tuple(bond_paths),
        structural_rank=term_rank(M), generic_rank=grank, deficient=deficient,
        shared=_shared(model, [owners[s] for s in deficient]),
        kalman_rank=kal, lost=tuple(lf.states[i] for i in lost_idx) if kal < n else (),
        graph=derivative_causality(model, kind=kind, signals=signals, detectors=detectors))


def controllability(model: Model, *, inputs: Sequence[str] | str | None = None,
                    seed: int = 0) -> Reachability:
    """Structural controllability of each state from the inputs.

    Parameters
    ----------
    model : Model
        A linear model (:func:`bondgraph.derive`).
    inputs : str or sequence of str, optional
        The inputs to use (default all).
    seed : int
        Seed of the random rational points of the generic ranks.

    Returns
    -------
    Reachability

    Raises
    ------
    StructureError
        A nonlinear model, or an unknown input name.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.structure import controllability
    >>> g = bg.BondGraph("rc_branch")       # C2 sits in a branch no source reaches
    >>> a, b = bg.Zero("a"), bg.One("b")
    >>> g.add(bg.Sf("i"), a, bg.R("R1"), bg.C("C1"), b, bg.C("C2"), bg.R("R2"))
    >>> for t, h in [("i", a), (a, "R1"), (a, "C1"), (b, "C2"), (b, "R2")]: _ = g.connect(t, h)
    >>> res = controllability(bg.derive(g))
    >>> res.structural, res.unreached, res.bond_paths[0]
    (False, ('q_C2',), ('i', 'a', 'C1'))
    >>> print(res.reason("q_C2"))
    q_C2 (C:C2): no causal path from the inputs (i)
    """
    return _analyse(model, "controllability", inputs, seed)


def observability(model: Model, *, outputs: Sequence[str] | str | None = None,
                  detectors: Optional[Mapping[str, Any]] = None,
                  seed: int = 0) -> Reachability:
    """Structural observability of each state from the outputs.

    The dual of :func:`controllability`: causal paths from each state to an
    output, the generic rank of ``[A; C]`` and of the observability matrix.
    ``detectors`` (the ``outputs`` given to :func:`bondgraph.derive`) places
    the dualised detectors of the bond-graph rank without searching for them
    (:func:`bondgraph.structure.derivative_causality`).

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.structure import observability
    >>> g = bg.BondGraph("two_rc")
    >>> a = bg.Zero("a")
    >>> g.add(bg.Sf("i"), a, bg.C("C1"), bg.R("R1"))
    >>> for t, h in [("i", a), (a, "C1"), (a, "R1")]: _ = g.connect(t, h)
    >>> res = observability(bg.derive(g, outputs={"v": bg.effort("a")}))
    >>> res.structural, res.path("q_C1")
    (True, ('q_C1', 'v'))
    """
    return _analyse(model, "observability", outputs, seed, detectors)
