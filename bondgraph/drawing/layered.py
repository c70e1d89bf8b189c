"""Layered (Sugiyama-style) grid layout of a bond graph.

The alternative to the comb of :mod:`~bondgraph.drawing.layout` for graphs
whose junction structure branches a lot or closes cycles:

1. **Layers.**  The junction structure (every node but the one-port leaves)
   is searched breadth first from a root; each edge is oriented from the
   nearer node to the farther one (between nodes at the same distance, by
   the graph's order), and a node's layer is the longest path to it in that
   acyclic orientation, so every bond runs from one layer to a later one.
   A bond spanning several layers gets a placeholder in each layer between
   (it keeps that column range free of other nodes).
2. **Leaves beside their junction.**  A junction's first two one-port
   elements sit beside it in its own layer (storage and sources on the
   right, resistors on the left, the convention of hand-drawn bond graphs);
   further ones go to the next layer like children.
3. **Crossing reduction.**  The order within each layer is improved by the
   barycentre heuristic, sweeping down and up, keeping the order with the
   fewest crossings between adjacent layers (counted exactly, as
   inversions).
4. **Columns.**  Each layer's items get integer columns as near the mean
   column of their neighbours in the adjacent layer as their order and
   widths allow: an isotonic regression (pool adjacent violators) solves
   that least-squares problem exactly, in passes down and up.

Layers are rows (``transpose=False``) or columns (``transpose=True``: then
the leaves beside a junction sit above and below it).  Cells are
``(column, row)`` as from :func:`~bondgraph.drawing.layout.grid_layout`.

Examples
--------
>>> kinds = {"V": "Se", "j": "1", "R": "R", "L": "I", "k": "0", "C": "C", "R2": "R"}
>>> edges = [("V", "j"), ("j", "R"), ("j", "L"), ("j", "k"), ("k", "C"), ("k", "R2")]
>>> cells = layered_layout(list(kinds), kinds, edges, root="j")
>>> cells["j"], cells["L"], cells["R"]       # inertia right of its junction, resistor left
((1, 0), (2, 0), (0, 0))
>>> cells["V"][1], cells["k"], cells["R2"], cells["C"]   # the next layer
(1, (2, 1), (1, 1), (3, 1))
"""

from __future__ import annotations

from typing import Mapping, Optional, Sequence

import networkx as nx

from ..elements.protocol import drawing_role
from .source import LEAF_ROLES, SOURCE_ROLES, UP_ROLES

__all__ = ["layered_layout", "layered_roots", "layer_crossings"]

Cell = tuple[int, int]

#: which one-port elements take the places beside a junction first
_PRIORITY = {"storage": 0, "dissipative": 1, "source": 2}


def layered_roots(names: Sequence[str], kinds: Mapping[str, str],
                  edges: Sequence[tuple[str, str]]) -> list[str]:
    """Candidate roots of :func:`layered_layout`: the centres of each component's junction
    structure, then the junctions that sources are bonded to.

    Examples
    --------
    >>> layered_roots(list("Vabc"), dict(V="Se", a="1", b="0", c="1"),
    ...               [("V", "a"), ("a", "b"), ("b", "c")])
    ['b', 'a']
    """
    graph = nx.Graph()
    graph.add_nodes_from(names)
    graph.add_edges_from(edges)
    order = {n: i for i, n in enumerate(names)}
    roles = {n: drawing_role(k) for n, k in kinds.items()}
    out: list[str] = []
    for comp in sorted(nx.connected_components(graph), key=lambda c: min(order[n] for n in c)):
        core = [n for n in comp if not _is_leaf(graph, roles, n)] or sorted(comp, key=order.__getitem__)
        centre = nx.center(graph.subgraph(core))
        out.extend(sorted(centre, key=order.__getitem__))
    for n in names:
        if roles[n] in SOURCE_ROLES:
            out.extend(k for k in sorted(graph[n], key=order.__getitem__) if k not in out)
    return out


def _is_leaf(graph: nx.Graph, roles: Mapping[str, str], n: str) -> bool:
    return graph.degree(n) <= 1 and roles[n] in LEAF_ROLES


def layered_layout(names: Sequence[str], kinds: Mapping[str, str],
                   edges: Sequence[tuple[str, str]], *, root: Optional[str] = None,
                   transpose: bool = False, sweeps: int = 8) -> dict[str, Cell]:
    """Grid cells of a layered layout (see the module's description).

    Parameters
    ----------
    names : sequence of str
        Node names, in the graph's order (used to break ties).
    kinds : mapping of str to str
        Node kind (element kind or drawing role, as for
        :func:`~bondgraph.drawing.layout.grid_layout`).
    edges : sequence of (tail, head)
        The bonds.
    root : str, optional
        Where the search of the component holding it starts (other
        components start at their first centre); default: every
        component's first centre (:func:`layered_roots`).
    transpose : bool
        Layers as columns instead of rows.
    sweeps : int
        Down-and-up passes of the barycentre heuristic.

    Returns
    -------
    dict
        Node name -> ``(column, row)``; distinct cells, smallest column and row 0.

    Examples
    --------
    >>> cells = layered_layout(list("abc"), dict(a="1", b="0", c="1"), [("a", "b"), ("b", "c")])
    >>> cells["b"], cells["a"], cells["c"]       # the centre on top
    ((0, 0), (0, 1), (1, 1))
    """
    graph = nx.MultiGraph()
    graph.add_nodes_from(names)
    graph.add_edges_from(edges)
    if root is not None and root not in graph:
        raise ValueError(f"root {root!r} is not a node of the graph")
    order = {n: i for i, n in enumerate(names)}
    roles = {n: drawing_role(k) for n, k in kinds.items()}
    starts = layered_roots(names, kinds, edges)
    cells: dict[str, Cell] = {}
    top = 0
    for comp in sorted(nx.connected_components(graph), key=lambda c: min(order[n] for n in c)):
        start: str = root if root is not None and root in comp else next(s for s in starts if s in comp)
        local = _Layered(graph.subgraph(comp), roles, order, start, sweeps).run(-1 if transpose else 1)
        c0 = min(c for c, _ in local.values())
        r1 = max(r for _, r in local.values())
        for n, (c, r) in local.items():
            cells[n] = (c - c0, r + top)
        top += r1 + 2
    if transpose:
        cells = {n: (r, c) for n, (c, r) in cells.items()}
    return cells


def layer_crossings(upper: Sequence[float], lower: Sequence[float],
                    links: Sequence[tuple[int, int]]) -> int:
    """Crossings between two layers: pairs of links ``(i, j)`` (item ``i`` of the upper layer
    to item ``j`` of the lower) whose ends are in opposite orders.

    ``upper`` and ``lower`` give each item's position.

    Examples
    --------
    >>> layer_crossings([0, 1], [0, 1], [(0, 1), (1, 0)]), layer_crossings([0, 1], [0, 1], [(0, 0), (1, 1)])
    (1, 0)
    """
    ends = sorted((upper[i], lower[j]) for i, j in links)
    count = 0
    for k, (a, b) in enumerate(ends):
        for c, d in ends[k + 1:]:
            if a < c and b > d:
                count += 1
    return count


class _Layered:
    """Layout of one connected component."""

    def __init__(self, graph: nx.MultiGraph, roles: Mapping[str, str], order: Mapping[str, int],
                 root: str, sweeps: int) -> None:
        self.graph = graph
        self.roles = roles
        self.order = order
        self.root = root
        self.sweeps = sweeps

    def _sorted(self, items) -> list[str]:
        return sorted(items, key=self.order.__getitem__)

    def run(self, right: int = 1) -> dict[str, Cell]:
        """Cells, layers as rows; ``right`` is the side (+1 or -1) of storage beside a junction."""
        g = self.graph
        nodes = self._sorted(g)
        leaf = {n for n in nodes if _is_leaf(g, self.roles, n) and len(nodes) > 2}
        # leaves beside their junction: the first storage/source on the right, resistor left
        beside: dict[str, dict[int, str]] = {}
        for n in nodes:
            if n in leaf:
                continue
            # storage first, then resistors, then sources (a source may as well start a layer)
            mine = sorted((k for k in g[n] if k in leaf),
                          key=lambda k: (_PRIORITY.get(self.roles[k], 3), self.order[k]))
            side: dict[int, str] = {}
            for x in mine:
                want = 1 if self.roles[x] in UP_ROLES else -1
                for s in (want, -want):
                    if s not in side:
                        side[s] = x
                        break
            beside[n] = side
        placed_beside = {x for side in beside.values() for x in side.values()}

        # layers: breadth-first distance, then longest path in the oriented graph
        core = [n for n in nodes if n not in placed_beside]
        start = self.root if self.root in core else core[0]
        simple = nx.Graph(g.subgraph(core))
        dist = nx.single_source_shortest_path_length(simple, start)
        dag = nx.DiGraph()
        dag.add_nodes_from(core)
        for u, v in simple.edges():
            if (dist[u], self.order[u]) > (dist[v], self.order[v]):
                u, v = v, u
            dag.add_edge(u, v)
        layer: dict = {}
        for n in nx.topological_sort(dag):
            layer[n] = max((layer[p] + 1 for p in dag.predecessors(n)), default=0)
        # placeholders on long edges
        links: list[tuple] = []
        for u, v in dag.edges():
            prev = u
            for k in range(layer[u] + 1, layer[v]):
                d = ("dummy", u, v, k)
                layer[d] = k
                links.append((prev, d))
                prev = d
            links.append((prev, v))
        nlay = max(layer.values()) + 1
        layers: list[list] = [[] for _ in range(nlay)]
        # first order: breadth-first discovery
        seen = [start] + [n for _, n in nx.bfs_edges(simple, start, sort_neighbors=self._sorted)]
        rank = {n: i for i, n in enumerate(seen)}
        for n in sorted(layer, key=lambda n: (rank[n] if n in rank else rank[n[1]] + 0.5,
                                              0 if n in rank else n[3])):
            layers[layer[n]].append(n)
        up: dict = {n: [] for n in layer}
        down: dict = {n: [] for n in layer}
        for a, b in links:
            down[a].append(b)
            up[b].append(a)
        width = {n: (1 if -right in beside.get(n, {}) else 0, 1 if right in beside.get(n, {}) else 0)
                 for n in layer}

        def positions(lay: list) -> dict:
            pos, x = {}, 0.0
            for n in lay:
                lo, hi = width[n]
                x += lo
                pos[n] = x
                x += hi + 1
            return pos

        def crossings(lays: list[list]) -> int:
            total = 0
            for a, b in zip(lays, lays[1:]):
                pa, pb = positions(a), positions(b)
                ia = {n: i for i, n in enumerate(a)}
                ib = {n: i for i, n in enumerate(b)}
                total += layer_crossings([pa[n] for n in a], [pb[n] for n in b],
                                         [(ia[u], ib[v]) for u in a for v in down[u]])
            return total

        best = ([list(lay) for lay in layers], crossings(layers))
        for _ in range(self.sweeps):
            for rng, nbr in ((range(1, nlay), up), (range(nlay - 2, -1, -1), down)):
                for i in rng:
                    ref = positions(layers[i - 1] if nbr is up else layers[i + 1])
                    cur = positions(layers[i])
                    def key(n, ref=ref, cur=cur, nbr=nbr):
                        ps = [ref[m] for m in nbr[n]]
                        return sum(ps) / len(ps) if ps else cur[n]
                    layers[i].sort(key=key)
                c = crossings(layers)
                if c < best[1]:
                    best = ([list(lay) for lay in layers], c)
            if best[1] == 0:
                break
        layers = best[0]

        # columns: least squares about the neighbours' mean, order and widths kept
        x = {n: p for lay in layers for n, p in positions(lay).items()}
        for sweep in range(4):
            rng = range(1, nlay) if sweep % 2 == 0 else range(nlay - 2, -1, -1)
            nbr = up if sweep % 2 == 0 else down
            for i in rng:
                lay = layers[i]
                target = [sum(x[m] for m in nbr[n]) / len(nbr[n]) if nbr[n] else x[n] for n in lay]
                gaps = [0.0] + [width[a][1] + width[b][0] + 1 for a, b in zip(lay, lay[1:])]
                off, acc = [], 0.0
                for gap in gaps:
                    acc += gap
                    off.append(acc)
                fit = _isotonic([t - o for t, o in zip(target, off)])
                # rounding a non-decreasing sequence keeps it non-decreasing
                for n, y, o in zip(lay, fit, off):
                    x[n] = float(round(y)) + o
        cells: dict[str, Cell] = {}
        for i, lay in enumerate(layers):
            for n in lay:
                if isinstance(n, tuple):
                    continue
                cells[n] = (int(x[n]), i)
                for s, leaf_name in beside.get(n, {}).items():
                    cells[leaf_name] = (int(x[n]) + s * right, i)
        return cells


def _isotonic(values: list[float]) -> list[float]:
    """The non-decreasing sequence nearest ``values`` in least squares (pool adjacent violators)."""
    blocks: list[list[float]] = []      # [mean, count]
    for v in values:
        blocks.append([v, 1.0])
        while len(blocks) > 1 and blocks[-2][0] > blocks[-1][0]:
            m2, c2 = blocks.pop()
            m1, c1 = blocks.pop()
            blocks.append([(m1 * c1 + m2 * c2) / (c1 + c2), c1 + c2])
    out: list[float] = []
    for m, c in blocks:
        out.extend([m] * int(c))
    return out
