"""Grid layout of a bond graph from its structure.

The junction structure (junctions, two-ports, sub-model boxes) forms the
*backbone*; one-port elements are *leaves*.  A spanning tree of the backbone
is drawn as a comb:

* its longest path (with sources at its ends) runs left to right on one row,
  so a chain reads as a chain; a long path snakes back and forth in bands;
* each path node carries its leaves directly above and below it (inertias,
  capacitors and sources above, resistors below) and its side branches as
  blocks hanging above or below;
* a branch is a tidy tree: each branch node has up to two leaves beside it
  and its children in the row below, packed side by side.

Blocks of neighbouring nodes never share a column range on the same side, so
a tree is drawn without crossing bonds; bonds that close a cycle of the
junction structure are drawn straight.  Cells are integer ``(column, row)``
pairs, rows growing downward; the scene sizes columns and rows to their
contents, so labels cannot overlap.

Examples
--------
>>> cells = grid_layout(["V", "j", "R", "L"], {"V": "Se", "j": "1", "R": "R", "L": "I"},
...                     [("V", "j"), ("j", "R"), ("j", "L")])
>>> cells["V"], cells["j"]          # the source in line, left of its junction
((0, 1), (1, 1))
>>> cells["L"], cells["R"]          # inertia above, resistor below
((1, 0), (1, 2))
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import networkx as nx

from ..elements.protocol import drawing_role
from .source import LEAF_ROLES, SOURCE_ROLES, UP_ROLES

__all__ = ["grid_layout", "boxes_overlap", "overlapping_pairs"]

Cell = tuple[int, int]


def grid_layout(names: Sequence[str], kinds: Mapping[str, str],
                edges: Sequence[tuple[str, str]], *, wrap: int = 14) -> dict[str, Cell]:
    """Grid cells for the nodes of a bond graph.

    Parameters
    ----------
    names : sequence of str
        Node names, in the graph's order (used to break ties).
    kinds : mapping of str to str
        Node kind: an element kind (``'Se'``, ``'1'``, ``'TF'``, ...; its element
        class's :attr:`~bondgraph.elements.protocol.Element.drawing_role` is used) or a
        drawing role (``'source'``, ``'storage'``, ``'dissipative'``,
        ``'junction'``, ``'backbone'``, ``'sub'``).
    edges : sequence of (tail, head)
        The bonds.
    wrap : int
        About the most columns of one row before the main path snakes back.

    Returns
    -------
    dict
        Node name -> ``(column, row)``; every node gets its own cell and the
        smallest column and row are 0.

    Examples
    --------
    >>> cells = grid_layout(list("abc"), dict(a="1", b="0", c="1"), [("a", "b"), ("b", "c")])
    >>> [cells[n] for n in "abc"]
    [(0, 0), (1, 0), (2, 0)]
    """
    if wrap < 2:
        raise ValueError(f"wrap must be at least 2; got {wrap}")
    order = {n: i for i, n in enumerate(names)}
    roles = {n: drawing_role(k) for n, k in kinds.items()}
    graph = nx.MultiGraph()
    graph.add_nodes_from(names)
    graph.add_edges_from(edges)
    comps = sorted(nx.connected_components(graph), key=lambda c: min(order[n] for n in c))
    cells: dict[str, Cell] = {}
    top = 0
    for comp in comps:
        local = _Comb(graph.subgraph(comp), roles, order, edges, wrap).run()
        c0 = min(c for c, _ in local.values())
        r0 = min(r for _, r in local.values())
        r1 = max(r for _, r in local.values())
        for n, (c, r) in local.items():
            cells[n] = (c - c0, r - r0 + top)
        top += r1 - r0 + 2
    return cells


@dataclass
class _Block:
    """Cells of a hanging item relative to its root at (0, 0), growing downward."""

    cells: dict[str, Cell] = field(default_factory=dict)
    left: int = 0
    right: int = 0
    depth: int = 0

    @staticmethod
    def single(name: str) -> "_Block":
        return _Block({name: (0, 0)})

    def add(self, other: "_Block", dx: int, dy: int) -> None:
        for n, (c, r) in other.cells.items():
            self.cells[n] = (c + dx, r + dy)
        self.left = min(self.left, other.left + dx)
        self.right = max(self.right, other.right + dx)
        self.depth = max(self.depth, other.depth + dy)


def _arrange(items: list[_Block]) -> list[int]:
    """Column offsets packing blocks side by side: the first at 0, then right, left, ..."""
    if not items:
        return []
    offs = [0]
    rc, lc = items[0].right + 1, items[0].left - 1
    for k, b in enumerate(items[1:], start=1):
        if k % 2:
            off = rc - b.left
            rc = off + b.right + 1
        else:
            off = lc - b.right
            lc = off + b.left - 1
        offs.append(off)
    return offs


class _Comb:
    """Layout of one connected component."""

    def __init__(self, graph: nx.MultiGraph, roles: Mapping[str, str],
                 order: Mapping[str, int], edges: Sequence[tuple[str, str]], wrap: int) -> None:
        self.graph = graph
        self.roles = roles
        self.order = order
        self.directed = [(t, h) for t, h in edges if t in graph and h in graph]
        self.wrap = wrap
        self.leaf: set[str] = set()
        self.tree = nx.Graph()

    def _sorted(self, items) -> list[str]:
        return sorted(items, key=self.order.__getitem__)

    def _leaves(self, n: str, skip: set) -> list[str]:
        return self._sorted(k for k in self.graph[n] if k in self.leaf and k not in skip)

    def run(self) -> dict[str, Cell]:
        g = self.graph
        nodes = self._sorted(g)
        if len(nodes) <= 2 and all(self.roles[n] in LEAF_ROLES for n in nodes):
            return {n: (i, 0) for i, n in enumerate(self._orient(nodes))}
        self.leaf = {n for n in nodes if g.degree(n) <= 1 and self.roles[n] in LEAF_ROLES}
        backbone = [n for n in nodes if n not in self.leaf]
        simple = nx.Graph(g.subgraph(backbone))
        self.tree = nx.Graph(nx.bfs_tree(simple, backbone[0], sort_neighbors=self._sorted))
        self.tree.add_nodes_from(backbone)
        ext = self.tree.copy()
        for n in self._sorted(self.leaf):
            if self.roles[n] in SOURCE_ROLES:
                ext.add_edge(n, next(iter(g[n])))
        path = self._orient(_longest_path(ext, self._sorted))
        on_path = set(path)

        # each path node: items above and below
        sides: list[tuple[list[_Block], list[_Block]]] = []
        for i, p in enumerate(path):
            leaves = self._leaves(p, on_path)
            ups = [x for x in leaves if self.roles[x] in UP_ROLES]
            downs = [x for x in leaves if self.roles[x] not in UP_ROLES]
            above = [_Block.single(x) for x in ups[:1]]
            below = [_Block.single(x) for x in downs[:1]]
            extra = [_Block.single(x) for x in ups[1:] + downs[1:]]
            nbrs = self.tree[p] if p in self.tree else ()
            branches = [self._branch(v, p) for v in self._sorted(nbrs) if v not in on_path]
            for b in branches + extra:
                # the lighter side, counting this node's and its neighbours' items
                load_a = sum(x.right - x.left + 1 for x in above) + self._near(path, i, up=True)
                load_b = sum(x.right - x.left + 1 for x in below) + self._near(path, i, up=False)
                (above if load_a < load_b else below).append(b)
            sides.append((above, below))
        return self._place(path, sides)

    def _near(self, path: list[str], i: int, *, up: bool) -> float:
        """Half the number of leaves that the path neighbours put on one side."""
        count = 0
        for j in (i - 1, i + 1):
            if 0 <= j < len(path):
                count += sum((self.roles[x] in UP_ROLES) == up
                             for x in self._leaves(path[j], set(path)))
        return 0.5 * count

    def _branch(self, v: str, parent: str) -> _Block:
        """A side branch rooted at ``v``, growing downward (a tidy tree)."""
        block = _Block.single(v)
        leaves = self._leaves(v, set())
        ups = [x for x in leaves if self.roles[x] in UP_ROLES]
        downs = [x for x in leaves if self.roles[x] not in UP_ROLES]
        beside = (ups + downs)[:2]
        # inertias and capacitors to the right, resistors to the left; a second one opposite
        first_right = self.roles[beside[0]] in UP_ROLES if beside else True
        for x, right in zip(beside, (first_right, not first_right)):
            block.add(_Block.single(x), 1 if right else -1, 0)
        kids = [self._branch(c, v) for c in self._sorted(self.tree[v]) if c != parent]
        kids += [_Block.single(x) for x in leaves if x not in beside]
        for b, off in zip(kids, _arrange(kids)):
            block.add(b, off, 1)
        return block

    def _orient(self, path: list[str]) -> list[str]:
        """Left to right along the bonds' power direction (sources first on a tie)."""
        pos = {n: i for i, n in enumerate(path)}
        fwd = bwd = 0
        for t, h in self.directed:
            if t in pos and h in pos and abs(pos[t] - pos[h]) == 1:
                if pos[h] > pos[t]:
                    fwd += 1
                else:
                    bwd += 1
        if bwd > fwd or (bwd == fwd and self.roles[path[-1]] in SOURCE_ROLES
                         and self.roles[path[0]] not in SOURCE_ROLES):
            return path[::-1]
        return path

    def _place(self, path: list[str], sides) -> dict[str, Cell]:
        # a path that only just passes `wrap` columns stays on one row
        packed = [self._pack(a, b) for a, b in sides]
        u = self._positions(list(range(len(path))), packed, 1)
        if u[-1] + 1 <= self.wrap + self.wrap // 3:
            return self._rows(path, [list(range(len(path)))], packed)
        # bands: each as long as it stays within the first band's columns (the snake does not
        # drift sideways), at least two nodes; at a turn the vertical bond needs its column
        # free on the turning side, so the turning node's items all go to the other side
        pole = _Block({})

        def turned(i: int, first: bool, last: bool) -> tuple[_Block, _Block]:
            a, b = sides[i]
            if first:
                a, b = [pole], a + b
            if last:
                a, b = a + b, [pole]
            return self._pack(a, b)

        bands: list[list[int]] = []
        final: list[tuple[_Block, _Block]] = [packed[i] for i in range(len(path))]
        lo = hi = 0
        col_end, i = 0, 0
        while i < len(path):
            k = len(bands)
            sign = 1 if k % 2 == 0 else -1
            best = None
            for j in range(min(i + 2, len(path)), len(path) + 1):
                band = list(range(i, j))
                last_band = j == len(path)
                trial = {n: turned(n, n == i and k > 0, n == j - 1 and not last_band) for n in band}
                offs = self._positions(band, trial, sign)
                xs = [col_end + sign * o for o in offs]
                left = min(x + min(trial[n][0].left, trial[n][1].left, 0) for x, n in zip(xs, band))
                right = max(x + max(trial[n][0].right, trial[n][1].right, 0) for x, n in zip(xs, band))
                # (the turning node's own items may stand one column out)
                inside = (right - left + 1 <= self.wrap) if k == 0 else (left >= lo - 1 and right <= hi + 1
                                                                         and min(xs) >= lo and max(xs) <= hi)
                if not inside and best is not None:
                    break
                best = (j, trial, xs[-1], left, right)
            assert best is not None
            j, trial, x_last, left, right = best
            if k == 0:
                lo, hi = left, max(right, left + self.wrap - 1)
            if len(path) - j == 1:          # the last node joins this band
                j = len(path)
                band = list(range(i, j))
                trial = {n: turned(n, n == i and k > 0, False) for n in band}
                x_last = col_end + sign * self._positions(band, trial, sign)[-1]
            for n in range(i, j):
                final[n] = trial[n]
            bands.append(list(range(i, j)))
            col_end, i = x_last, j
        return self._rows(path, bands, final)

    def _rows(self, path: list[str], bands: list[list[int]], packed) -> dict[str, Cell]:
        cells: dict[str, Cell] = {}
        row = 0
        col_end = 0
        for k, band in enumerate(bands):
            sign = 1 if k % 2 == 0 else -1
            u = self._positions(band, packed, sign)
            above_depth = max((packed[i][0].depth for i in band), default=0)
            row = row + above_depth + 1 if k else above_depth
            for j, i in enumerate(band):
                x = col_end + sign * u[j]
                cells[path[i]] = (x, row)
                for s, flip in ((0, -1), (1, 1)):
                    for name, (c, r) in packed[i][s].cells.items():
                        cells[name] = (x + c, row + flip * r)
            col_end += sign * u[-1]
            row += max((packed[i][1].depth for i in band), default=0)
        return cells

    @staticmethod
    def _pack(above: list[_Block], below: list[_Block]) -> tuple[_Block, _Block]:
        """Each side's items arranged about the path node, as one block."""
        pair = []
        for items in (above, below):
            blk = _Block({})
            for b, off in zip(items, _arrange(items)):
                blk.add(b, off, 1)
            if not items:
                blk.left, blk.right = 1, -1   # empty: takes no column
            pair.append(blk)
        return pair[0], pair[1]

    @staticmethod
    def _positions(band: list[int], packed, sign: int) -> list[int]:
        """Offsets along a band keeping each side's blocks of different nodes apart."""
        u: list[int] = []
        for j, i in enumerate(band):
            pos = u[-1] + 1 if u else 0
            for jj in range(j):
                for s in (0, 1):
                    a, b = packed[band[jj]][s], packed[i][s]
                    if a.left > a.right or b.left > b.right:
                        continue
                    ar, bl = (a.right, b.left) if sign > 0 else (-a.left, -b.right)
                    pos = max(pos, u[jj] + ar - bl + 1)
            u.append(pos)
        return u


def _longest_path(tree: nx.Graph, sort) -> list[str]:
    """A longest path of a tree (double breadth-first search)."""
    nodes = sort(tree)
    if len(nodes) == 1:
        return nodes

    def farthest(src: str) -> tuple[str, dict]:
        parent: dict[str, str | None] = {src: None}
        dist = {src: 0}
        queue = deque([src])
        while queue:
            u = queue.popleft()
            for v in sort(tree[u]):
                if v not in dist:
                    dist[v] = dist[u] + 1
                    parent[v] = u
                    queue.append(v)
        far = max(sort(dist), key=lambda n: dist[n])
        return far, parent

    a, _ = farthest(nodes[0])
    b, parent = farthest(a)
    path = [b]
    while parent[path[-1]] is not None:
        path.append(parent[path[-1]])
    return path



# ---------------------------------------------------------------- overlap checks
Box = tuple[float, float, float, float]  # x, y (top-left), width, height


def boxes_overlap(a: Box, b: Box, *, margin: float = 0.0) -> bool:
    """Whether two ``(x, y, width, height)`` boxes overlap (touching is not overlap).

    Parameters
    ----------
    a, b : (float, float, float, float)
        Boxes as top-left corner, width and height.
    margin : float
        Extra clearance: boxes closer than this also count as overlapping.

    Examples
    --------
    >>> boxes_overlap((0, 0, 10, 10), (5, 5, 10, 10)), boxes_overlap((0, 0, 10, 10), (10, 0, 5, 5))
    (True, False)
    """
    ax, ay, aw, ah = a
    bx, by, bw, bh = b
    return (ax < bx + bw + margin and bx < ax + aw + margin
            and ay < by + bh + margin and by < ay + ah + margin)


def overlapping_pairs(boxes: Mapping[str, Box], *, margin: float = 0.0) -> list[tuple[str, str]]:
    """Pairs of names whose boxes overlap.

    Parameters
    ----------
    boxes : mapping of str to (float, float, float, float)
        Name -> box (top-left corner, width, height).
    margin : float
        Extra clearance, as in :func:`boxes_overlap`.

    Returns
    -------
    list of (str, str)

    Examples
    --------
    >>> overlapping_pairs({"a": (0, 0, 4, 4), "b": (3, 3, 4, 4), "c": (20, 0, 1, 1)})
    [('a', 'b')]
    """
    items = sorted(boxes.items(), key=lambda kv: kv[1][0])
    out = []
    for i, (na, a) in enumerate(items):
        for nb, b in items[i + 1:]:
            if b[0] >= a[0] + a[2] + margin:
                break
            if boxes_overlap(a, b, margin=margin):
                out.append((na, nb))
    return out
