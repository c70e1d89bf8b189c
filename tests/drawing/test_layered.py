"""The layered (Sugiyama-style) layout: its pieces against hand counts, its drawings by geometry.

References: crossings between two layers counted by hand (every pair of
links whose ends are in opposite orders); the least-squares non-decreasing
fit of a short sequence solved by hand (pooling violators to their mean);
a tree has a layered drawing without crossings (children kept next to their
parent), checked on the scene's coordinates with segment intersection.
"""

import random

import networkx as nx
import pytest

import bondgraph as bg
from bondgraph.drawing.geometry import bond_crossings, bonds_through_labels, printed_size
from bondgraph.drawing.layered import _isotonic, layer_crossings, layered_layout, layered_roots
from bondgraph.drawing.scene import _build_scene, build_scene
from bondgraph.drawing.source import diagram


def test_layer_crossings_hand_counts():
    # a-z, b-y, c-x: every one of the 3 pairs is inverted
    assert layer_crossings([0, 1, 2], [0, 1, 2], [(0, 2), (1, 1), (2, 0)]) == 3
    # a-x, a-y, b-x: a-y and b-x cross (a < b, y > x); a-x shares ends with both
    assert layer_crossings([0, 1], [0, 1], [(0, 0), (0, 1), (1, 0)]) == 1
    # K(2,2) drawn in two layers: exactly one crossing (C(2,2) * C(2,2))
    assert layer_crossings([0, 1], [0, 1], [(0, 0), (0, 1), (1, 0), (1, 1)]) == 1
    # K(3,3): C(3,2) * C(3,2) = 9 in any order
    links = [(i, j) for i in range(3) for j in range(3)]
    assert layer_crossings([0, 1, 2], [2, 0, 1], links) == 9


def test_isotonic_fit_hand_solutions():
    assert _isotonic([1.0, 2.0, 3.0]) == [1.0, 2.0, 3.0]
    assert _isotonic([3.0, 1.0, 2.0]) == pytest.approx([2.0, 2.0, 2.0])
    assert _isotonic([1.0, 3.0, 2.0, 4.0]) == pytest.approx([1.0, 2.5, 2.5, 4.0])
    assert _isotonic([4.0, 3.0, 2.0, 1.0]) == pytest.approx([2.5] * 4)


def _tree_graph(seed: int, n: int) -> bg.BondGraph:
    """A random tree of junctions (alternating 0/1 by depth) with a one-port on every leaf."""
    rng = random.Random(seed)
    tree = nx.random_labeled_tree(n, seed=seed)
    depth = nx.single_source_shortest_path_length(tree, 0)
    g = bg.BondGraph(f"tree{seed}")
    g.add(*[(bg.Zero if depth[v] % 2 else bg.One)(f"j{v}") for v in tree])
    for u, v in nx.bfs_edges(tree, 0):
        g.connect(f"j{u}", f"j{v}")
    g.add(bg.Se("E"))
    g.connect("E", "j0")
    for v in tree:
        if tree.degree(v) == 1 and v != 0:
            el = rng.choice([bg.I, bg.C, bg.R])(f"e{v}")
            g.add(el)
            g.connect(f"j{v}", el)
    return g


def test_trees_are_drawn_without_crossings():
    # layers as rows, from every candidate root; layers as columns only need distinct cells:
    # there a steep bond next to a wide label may bend round it and cross a short bond, and
    # build_scene then prefers another candidate (checked last)
    for seed in range(4):
        d = diagram(_tree_graph(seed, 13), causality=False)
        names = [n.name for n in d.nodes]
        kinds = {n.name: n.role for n in d.nodes}
        edges = [(e.tail, e.head) for e in d.edges]
        for root in layered_roots(names, kinds, edges):
            for transpose in (False, True):
                cells = layered_layout(names, kinds, edges, root=root, transpose=transpose)
                assert len(set(cells.values())) == len(names)          # one node per cell
                sc = _build_scene(d, cells, True, True, False)
                assert sc.overlaps() == []
                if not transpose:
                    assert bond_crossings(sc) == [], (seed, root)
                    assert bonds_through_labels(sc) == [], (seed, root)
        sc = build_scene(d, max_width=17.0)
        assert bond_crossings(sc) == [] and bonds_through_labels(sc) == []
        assert printed_size(sc)[0] <= 17.0


def test_leaves_beside_their_junction_and_layers_adjacent():
    # a ring of four junctions, each with an inertia and a resistor, and a source on one
    g = bg.BondGraph("ring")
    g.add(bg.Se("E"), *[(bg.One if k % 2 else bg.Zero)(f"j{k}") for k in range(4)])
    for k in range(4):
        g.add(bg.I(f"m{k}"), bg.R(f"b{k}"))
        g.connect(f"j{k}", f"m{k}")
        g.connect(f"j{k}", f"b{k}")
        g.connect(f"j{k}", f"j{(k + 1) % 4}")
    g.connect("E", "j0")
    d = diagram(g, causality=False)
    names = [n.name for n in d.nodes]
    kinds = {n.name: n.role for n in d.nodes}
    edges = [(e.tail, e.head) for e in d.edges]
    cells = layered_layout(names, kinds, edges, root="j0")
    for k in range(4):
        (c, r) = cells[f"j{k}"]
        assert cells[f"m{k}"] == (c + 1, r) and cells[f"b{k}"] == (c - 1, r)
    # j0 on top, j1 and j3 one layer down, j2 (the far side of the ring) below them
    rows = {k: cells[f"j{k}"][1] for k in range(4)}
    assert rows[0] == 0 and rows[1] == rows[3] == 1 and rows[2] == 2
    assert cells["E"][1] == 1
    sc = _build_scene(d, cells, True, True, False)
    assert bond_crossings(sc) == [] and bonds_through_labels(sc) == [] and sc.overlaps() == []


def test_unknown_root_is_refused():
    with pytest.raises(ValueError, match="root 'x'"):
        layered_layout(["a", "b"], {"a": "1", "b": "0"}, [("a", "b")], root="x")


def test_a_long_chain_snakes_within_the_width():
    # 30 mass-damper cells joined by springs: 59 junctions.  Drawn as the comb's snake, rows of
    # junctions that all stay in the first row's columns (no drift sideways: it fits 17 cm),
    # each row holding several junctions (not one tall column)
    g = bg.BondGraph("chain")
    g.add(bg.Se("F"))
    prev = None
    for i in range(30):
        g.add(bg.One(f"v{i}"), bg.I(f"m{i}"), bg.R(f"b{i}"))
        g.connect(f"v{i}", f"m{i}")
        g.connect(f"v{i}", f"b{i}")
        if prev is None:
            g.connect("F", "v0")
        else:
            g.add(bg.Zero(f"s{i}"), bg.C(f"k{i}"))
            g.connect(prev, f"s{i}")
            g.connect(f"s{i}", f"v{i}")
            g.connect(f"s{i}", f"k{i}")
        prev = f"v{i}"
    sc = build_scene(diagram(g), max_width=17.0)
    assert printed_size(sc)[0] <= 17.0
    assert bond_crossings(sc) == [] and bonds_through_labels(sc) == [] and sc.overlaps() == []
    rows: dict = {}
    for lb in sc.labels:
        if lb.role == "junction":
            rows.setdefault(round(lb.y), []).append(lb.x)
    counts = [len(rows[y]) for y in sorted(rows)]
    assert len(counts) >= 3 and all(c >= 4 for c in counts[:-1]), counts     # the last: what is left
