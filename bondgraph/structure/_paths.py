"""Causal paths: the signal digraph of a model and the causal graph of its bond graph.

Two graphs, both :class:`networkx.DiGraph`:

* the *signal digraph* of the linear form (Lin's structural graph): a node per
  input ``("u", name)``, state ``("x", name)`` and output ``("y", name)``, an
  edge wherever an entry of ``A``, ``B_k``, ``C`` or ``D_k`` is nonzero.  In a
  bond graph in integral causality an edge ``x_i -> x_j`` is a causal path
  from the storage element of ``x_i`` to that of ``x_j`` through the junction
  structure, R, TF and GY elements (Sueur and Dauphin-Tanguy); the weight of
  an edge is the number of integrations it adds (1 into a state, 0 into an
  output, ``-k`` for a ``k``-th input derivative);
* the *causal graph* of the augmented bond graph: a node per bond variable,
  an edge from each variable an element reads to the variable it computes
  (:func:`bondgraph.causality.dependencies`), plus the integration inside each
  storage element in integral causality.  Its paths name the elements a causal
  path crosses.
"""

from __future__ import annotations

from typing import Optional, Sequence

import networkx as nx

from ..causality import AugmentedBondGraph, dependencies
from ..model import Model
from ._generic import LinearForm

__all__ = ["signal_digraph", "state_elements", "bond_path", "bond_paths", "path_names"]


def signal_digraph(lf: LinearForm) -> nx.DiGraph:
    """The signal digraph of a linear form (see the module docstring)."""
    G = nx.DiGraph()
    G.add_nodes_from(("u", n) for n in lf.inputs)
    G.add_nodes_from(("x", n) for n in lf.states)
    G.add_nodes_from(("y", n) for n in lf.outputs)
    A, C = lf.A, lf.C
    for i in range(A.rows):
        for j in range(A.cols):
            if A[i, j] != 0:
                G.add_edge(("x", lf.states[j]), ("x", lf.states[i]), weight=1)
    for k, B in enumerate(lf.Bs):
        for i in range(B.rows):
            for j in range(B.cols):
                if B[i, j] != 0:
                    _add_min(G, ("u", lf.inputs[j]), ("x", lf.states[i]), 1 - k)
    for i in range(C.rows):
        for j in range(C.cols):
            if C[i, j] != 0:
                G.add_edge(("x", lf.states[j]), ("y", lf.outputs[i]), weight=0)
    for k, D in enumerate(lf.Ds):
        for i in range(D.rows):
            for j in range(D.cols):
                if D[i, j] != 0:
                    _add_min(G, ("u", lf.inputs[j]), ("y", lf.outputs[i]), -k)
    return G


def _add_min(G: nx.DiGraph, a, b, w: int) -> None:
    if G.has_edge(a, b):
        w = min(w, G[a][b]["weight"])
    G.add_edge(a, b, weight=w)


def state_elements(model: Model) -> dict[str, Optional[str]]:
    """The element owning each state (None for an integrator added for an output)."""
    aug = model.augmented
    out: dict[str, Optional[str]] = {n: None for n in model.state_names}
    if aug is None:
        return out
    flat = aug.flat
    for name in aug.integral:
        el = flat.element(name)
        ein = [aug.effort_into(name, flat.bonds[k].number) for k in flat.incidence[name]]
        for s in el.state_names(ein):
            if s in out:
                out[s] = name
    return out


def path_names(path) -> tuple[str, ...]:
    """A signal-digraph path as names (``('F', 'p_m1', 'q_k', 'x2')``)."""
    return tuple(node[1] for node in path)


def _causal_graph(aug: AugmentedBondGraph) -> tuple[nx.DiGraph, list[int]]:
    producer, inputs = dependencies(aug)
    G = nx.DiGraph()
    G.add_nodes_from(range(len(producer)))
    for v, ins in enumerate(inputs):
        for u in ins:
            G.add_edge(u, v)
    flat = aug.flat
    for name in aug.integral:            # the integration inside the storage element
        idx = flat.index[name]
        outs = [v for v in range(len(producer)) if producer[v] == idx]
        for k in flat.incidence[name]:
            for v in outs:
                for u in (2 * k, 2 * k + 1):
                    if producer[u] != idx:
                        G.add_edge(u, v)
    return G, producer


def bond_path(aug: AugmentedBondGraph, sources: tuple[str, ...], target: str
              ) -> tuple[str, ...]:
    """Elements along a shortest causal path from any of ``sources`` to storage ``target``.

    Empty when there is none.  Consecutive repeats are merged; the path runs
    through the bond variables of the augmented bond graph.
    """
    return bond_paths(aug, sources, (target,))[0]


def bond_paths(aug: AugmentedBondGraph, sources: tuple[str, ...], targets: Sequence[str]
               ) -> tuple[tuple[str, ...], ...]:
    """:func:`bond_path` for each of ``targets``: one causal graph, one shortest-path search."""
    flat = aug.flat
    G, producer = _causal_graph(aug)
    names = [el.name for el in flat.elements]
    starts = [v for v in range(len(producer)) if names[producer[v]] in sources]
    paths = nx.multi_source_dijkstra(G, set(starts), target=None)[1] if starts else {}
    return tuple(_path_to(flat, producer, names, paths, t) for t in targets)


def _path_to(flat, producer, names, paths, target: str) -> tuple[str, ...]:
    tidx = flat.index[target]
    goals = {u for k in flat.incidence[target] for u in (2 * k, 2 * k + 1)
             if producer[u] != tidx}
    if not paths or not goals:
        return ()
    best = min((paths[g] for g in goals if g in paths), key=len, default=None)
    if best is None:
        return ()
    out: list[str] = []
    for v in best:
        n = names[producer[v]]
        if not out or out[-1] != n:
            out.append(n)
    if out[-1] != target:
        out.append(target)
    return tuple(out)
