"""Infinite zeros of a multi-input multi-output model: their orders from causal paths.

For a ``p x m`` transfer matrix ``G(s)`` the orders ``n_1 <= n_2 <= ...`` of
the infinite zeros (the Smith-McMillan form at infinity; for one input and one
output, the relative degree) are read two ways:

* *from the bond graph* (Bertrand, Sueur and Dauphin-Tanguy; van der Woude for
  structured systems): ``n_1 + ... + n_k`` is the smallest total number of
  integrations of ``k`` input-output causal paths that share no input, state
  or output, so ``n_k = L_k - L_{k-1}``; the largest such ``k`` is the
  structural rank of ``G``.  The families are found as minimum-cost flows
  (:func:`networkx.min_cost_flow`) in the signal digraph with every node split
  into an entry and an exit of capacity one;
* *generically*, from the Markov parameters ``M_j`` (``G = sum_j M_j s^-j``)
  at random rational parameter points: the rank increments of the block
  Toeplitz matrices ``T_j = [[M_1], [M_2, M_1], ..., [M_j, ..., M_1]]`` count
  the infinite zeros of order at most ``j`` (a model with direct feedthrough or
  derivative inputs is shifted by ``s^-(K+1)`` first).

The two agree unless causal-path gains cancel; the result reports both.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.structure import infinite_zeros
>>> g = bg.BondGraph("two_masses")
>>> v1, v2, s = bg.One("v1"), bg.One("v2"), bg.Zero("s")
>>> g.add(bg.Se("F1"), bg.Se("F2"), v1, v2, s, bg.I("m1"), bg.I("m2"), bg.C("k"))
>>> for t, h in [("F1", v1), ("F2", v2), (v1, "m1"), (v1, s), (s, "k"), (s, v2), (v2, "m2")]:
...     _ = g.connect(t, h)
>>> iz = infinite_zeros(bg.derive(g, outputs={"x1": bg.displacement("m1"),
...                                           "x2": bg.displacement("m2")}))
>>> iz.orders, iz.structural_orders, iz.rank
((2, 2), (2, 2), 2)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import networkx as nx
import sympy

from ..model import Model
from ._generic import LinearForm, StructureError, at_point, exact_rank, linear_form, random_points
from ._paths import path_names, signal_digraph

__all__ = ["InfiniteZeros", "infinite_zeros"]


@dataclass(frozen=True)
class InfiniteZeros:
    """Orders of the infinite zeros of a MIMO input-output selection (immutable).

    Attributes
    ----------
    model : str
    inputs, outputs : tuple of str
    orders : tuple of int
        Generic orders ``n_1 <= n_2 <= ...`` (one per unit of normal rank).
    structural_orders : tuple of int
        Orders from the shortest families of disjoint causal paths.
    paths : tuple of tuple of str
        A family of ``structural rank`` disjoint causal paths of least total
        length (inputs, states, outputs by name).
    lengths : tuple of int
        ``L_k``: the least total number of integrations of ``k`` disjoint paths.
    """

    model: str
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    orders: tuple[int, ...]
    structural_orders: tuple[int, ...]
    paths: tuple[tuple[str, ...], ...]
    lengths: tuple[int, ...]

    @property
    def rank(self) -> int:
        """The normal rank of ``G`` for almost all parameter values."""
        return len(self.orders)

    @property
    def structural_rank(self) -> int:
        """The largest number of disjoint input-output causal paths."""
        return len(self.structural_orders)

    def __str__(self) -> str:
        lines = [f"infinite zeros of {', '.join(self.outputs)} / {', '.join(self.inputs)} in "
                 f"{self.model!r}",
                 f"  normal rank {self.rank}; orders {list(self.orders)}"]
        lines.append(f"  from disjoint causal paths: orders {list(self.structural_orders)} "
                     f"(least total lengths {list(self.lengths)})")
        for p in self.paths:
            lines.append("    " + " -> ".join(p))
        if self.orders != self.structural_orders:
            lines.append("  (causal-path gains cancel: the generic orders differ)")
        return "\n".join(lines)


def _pick(names: Sequence[str], wanted, what: str, model: str) -> tuple[int, ...]:
    if wanted is None:
        return tuple(range(len(names)))
    out = []
    for w in ((wanted,) if isinstance(wanted, str) else wanted):
        if w not in names:
            raise StructureError(f"model {model!r} has no {what} {w!r}; {what}s: "
                                 f"{', '.join(names) or 'none'}")
        out.append(names.index(w))
    return tuple(out)


def _families(G: nx.DiGraph, us: Sequence, ys: Sequence) -> tuple[list[int], list]:
    """Least total weight ``L_k`` of ``k`` vertex-disjoint u -> y paths, k = 1, 2, ...; and
    the paths of the largest family."""
    lengths: list[int] = []
    best: list = []
    for k in range(1, min(len(us), len(ys)) + 1):
        H = nx.DiGraph()
        for node in G.nodes:
            H.add_edge(("in", node), ("out", node), capacity=1, weight=0)
        for a, b, w in G.edges(data="weight"):
            H.add_edge(("out", a), ("in", b), capacity=1, weight=int(w))
        for u in us:
            H.add_edge("source", ("in", u), capacity=1, weight=0)
        for y in ys:
            H.add_edge(("out", y), "sink", capacity=1, weight=0)
        H.nodes["source"]["demand"] = -k
        H.nodes["sink"]["demand"] = k
        try:
            flow = nx.min_cost_flow(H)
        except nx.NetworkXUnfeasible:
            break
        lengths.append(int(nx.cost_of_flow(H, flow)))
        best = _paths(flow, us)
    return lengths, best


def _paths(flow: dict, us: Sequence) -> list:
    out = []
    for u in us:
        if not flow["source"].get(("in", u)):
            continue
        path, node = [u], u
        while True:
            nxt = [b for b, f in flow[("out", node)].items() if f]
            if not nxt or nxt[0] == "sink":
                break
            node = nxt[0][1]
            path.append(node)
        out.append(path_names(path))
    return out


def _markov(lf: LinearForm, rows, cols, pt, count: int, shift: int) -> list:
    """``M_j`` for j = 1..count of ``s^-shift G(s)`` at the point."""
    A = at_point(lf.A, pt)
    C = at_point(lf.C, pt)[list(rows), :]
    Bs = [at_point(B, pt)[:, list(cols)] for B in lf.Bs]
    Ds = [at_point(D, pt)[list(rows), list(cols)] for D in lf.Ds]
    n = A.rows
    powers = [C]
    top = count + len(Bs)
    for _ in range(top):
        powers.append(powers[-1] * A)
    out = []
    for j in range(1, count + 1):
        jj = j - shift                           # coefficient of s^-jj in G
        M = sympy.zeros(len(rows), len(cols))
        for k, B in enumerate(Bs):
            e = jj + k - 1
            if e >= 0 and n:
                M += powers[e] * B
        if 0 <= -jj < len(Ds):
            M += Ds[-jj]
        out.append(M)
    return out


def _generic_orders(lf: LinearForm, rows, cols, points) -> tuple[int, ...]:
    shift = max(len(lf.Bs), len(lf.Ds))      # s^-shift G is strictly proper
    n = lf.A.rows
    count = n + 2 * shift + 1
    best: tuple[int, ...] = ()
    for pt in points:
        Ms = _markov(lf, rows, cols, pt, count, shift)
        orders: list[int] = []
        prev_rank = prev_count = 0
        for j in range(1, count + 1):
            T = sympy.Matrix(sympy.BlockMatrix(
                [[Ms[i - c] if i >= c else sympy.zeros(len(rows), len(cols))
                  for c in range(j)] for i in range(j)])) if rows and cols else sympy.zeros(0, 0)
            r = exact_rank(T) if T.rows else 0
            # rank T_j - rank T_{j-1}: the number of infinite zeros of order <= j
            c = r - prev_rank
            orders += [j - shift] * (c - prev_count)
            prev_rank, prev_count = r, c
        if len(orders) > len(best):
            best = tuple(orders)
    return best


def infinite_zeros(model: Model, inputs: Sequence[str] | str | None = None,
                   outputs: Sequence[str] | str | None = None, *,
                   seed: int = 0) -> InfiniteZeros:
    """Orders of the infinite zeros of ``G`` from ``inputs`` to ``outputs`` (MIMO).

    Parameters
    ----------
    model : Model
        A linear model.
    inputs, outputs : str or sequence of str, optional
        The channels (default all).
    seed : int
        Seed of the random rational points of the generic orders.

    Returns
    -------
    InfiniteZeros

    Raises
    ------
    StructureError
        A nonlinear model or an unknown channel name.
    """
    lf = linear_form(model)
    cols = _pick(lf.inputs, inputs, "input", model.name)
    rows = _pick(lf.outputs, outputs, "output", model.name)
    G = signal_digraph(lf)
    us = [("u", lf.inputs[j]) for j in cols]
    ys = [("y", lf.outputs[i]) for i in rows]
    lengths, fam = _families(G, us, ys)
    structural = tuple(b - a for a, b in zip([0] + lengths, lengths))
    generic = _generic_orders(lf, rows, cols, random_points(lf.parameters, 2, seed=seed))
    return InfiniteZeros(model=model.name, inputs=tuple(lf.inputs[j] for j in cols),
                         outputs=tuple(lf.outputs[i] for i in rows), orders=generic,
                         structural_orders=structural, paths=tuple(fam),
                         lengths=tuple(lengths))
