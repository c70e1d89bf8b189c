"""Differential verification against an independent solver (issue 11).

Random linear bond graphs (``verification/generator.py``: ladders, bridges,
circuits, junction trees and chains, TF/GY drivetrains, parallel bonds,
junction cycles, rigidly joined storage, several Se/Sf, every kind of output
and linear combinations, random bond directions) are built in two insertion
orders.  For each, the symbolic ``model.transfer_matrix()`` (evaluated) and
the numeric plant ``compile_plant(model).plant(values)`` (``C (sI-A)^-1 B + D``)
must agree, at two random complex ``s``, with the exact Laplace-domain
solution of the bond graph's own equations (``verification/reference.py``,
which imports nothing from bondgraph) to 1e-8 relative; an ill-posed graph
(singular bond equations) must be refused with a ``BondGraphError``.  No
graph may be answered wrongly, refused while well-posed, crash with another
exception, or exceed the time limit.

The first tests prove the reference itself on hand-derived closed forms.

The long run (20,000 graphs) is ``python bench/verify_random.py``.
"""

from __future__ import annotations

import random
from fractions import Fraction

import numpy as np
import pytest

from verification import generator as gen
from verification.reference import Bond, Element, Graph, Output, Reference, Term, exact

# ============================================================ the reference, by hand

S_POINTS = [complex(0.37, 1.21), complex(-0.8, 0.45), complex(2.5, 0.3)]


def _graph(elements, bonds, outputs, name="hand"):
    els = tuple(Element(n, k, v) for n, k, v in elements)
    bs = tuple(Bond(i + 1, t, h) for i, (t, h) in enumerate(bonds))
    outs = tuple(Output(n, tuple(Term(c, k, tg) for c, k, tg in terms)) for n, terms in outputs)
    return Graph(name, els, bs, outs)


def _close(a, b, rtol=1e-12):
    return abs(complex(a) - complex(b)) <= rtol * max(abs(complex(b)), 1e-300)


def _exact_value(ref: Reference, s, i=0, j=0) -> complex:
    return ref.evaluate(s)[i, j]


def test_reference_rc_lowpass():
    R, C = 2.2, 0.47
    g = _graph([("V", "Se", None), ("i", "One", None), ("R", "R", R), ("C", "C", C)],
               [("V", "i"), ("i", "R"), ("i", "C")],
               [("vC", [(1, "effort", "C")]), ("q", [(1, "displacement", "C")]),
                ("iR", [(1, "flow", "R")])])
    ref = Reference(g)
    assert ref.well_posed
    for s in S_POINTS:
        G = ref.evaluate(s)
        assert _close(G[0, 0], 1 / (R * C * s + 1))
        assert _close(G[1, 0], C / (R * C * s + 1))          # q = C*vC
        assert _close(G[2, 0], C * s / (R * C * s + 1))      # i = C s vC


def _fit_poly(points, deg):
    """Exact coefficients (lowest first) of the polynomial through (x, y) Fractions."""
    n = deg + 1
    A = [[x ** k for k in range(n)] + [y] for x, y in points[:n]]
    for c in range(n):                       # Gauss-Jordan over the rationals
        p = next(r for r in range(c, n) if A[r][c] != 0)
        A[c], A[p] = A[p], A[c]
        A[c] = [v / A[c][c] for v in A[c]]
        for r in range(n):
            if r != c and A[r][c] != 0:
                A[r] = [a - A[r][c] * b for a, b in zip(A[r], A[c])]
    return [A[k][n] for k in range(n)]


def test_reference_two_section_rc_ladder_exact_denominator():
    """Se V -> 1[R1] -> 0[C1] -> 1[R2] -> 0[C2]: 1/G = R1C1R2C2 s^2 + (R1C1+R2C2+R1C2) s + 1,
    so the monic denominator's constant term is exactly 1/(C1 C2 R1 R2)."""
    R1, C1, R2, C2 = 1.5, 0.25, 3.0, 0.125
    g = _graph([("V", "Se", None), ("a", "One", None), ("R1", "R", R1), ("n1", "Zero", None),
                ("C1", "C", C1), ("b", "One", None), ("R2", "R", R2), ("n2", "Zero", None),
                ("C2", "C", C2)],
               [("V", "a"), ("a", "R1"), ("a", "n1"), ("n1", "C1"), ("n1", "b"), ("b", "R2"),
                ("b", "n2"), ("n2", "C2")],
               [("v2", [(1, "effort", "C2")])])
    ref = Reference(g)
    pts = []
    for x in (1, 2, 3, 5):
        ((re, im),), = ref.evaluate_exact(complex(x, 0))
        assert im == 0
        pts.append((Fraction(x), 1 / re))
    c0, c1, c2 = _fit_poly(pts, 2)
    R1, C1, R2, C2 = map(exact, (R1, C1, R2, C2))
    assert (c0, c1, c2) == (1, R1 * C1 + R2 * C2 + R1 * C2, R1 * C1 * R2 * C2)
    # the 4th point lies on the same quadratic
    x, y = pts[3]
    assert c0 + c1 * x + c2 * x ** 2 == y
    assert c0 / c2 == 1 / (C1 * C2 * R1 * R2)


def test_reference_mass_spring_damper():
    """x/F = 1/(m s^2 + b s + k), with the spring as a compliance 1/k."""
    m, b, k = 1.7, 0.35, 4.0
    g = _graph([("F", "Se", None), ("v", "One", None), ("m", "I", m), ("b", "R", b),
                ("c", "C", 1 / k)],
               [("F", "v"), ("v", "m"), ("v", "b"), ("v", "c")],
               [("x", [(1, "displacement", "m")]), ("xc", [(1, "displacement", "c")]),
                ("p", [(1, "momentum", "m")]), ("fk", [(1, "effort", "c")])])
    ref = Reference(g)
    for s in S_POINTS:
        G = ref.evaluate(s)
        d = m * s ** 2 + b * s + k
        assert _close(G[0, 0], 1 / d)
        assert _close(G[1, 0], 1 / d)
        assert _close(G[2, 0], m * s / d)             # p = m v = m s x
        assert _close(G[3, 0], k / d)                 # spring force k x


def test_reference_reversed_bond_flips_the_elements_own_signals():
    """connect("m", v): power is directed out of m; its own flow (power into m) is -v."""
    m = 2.0
    g = _graph([("F", "Se", None), ("v", "One", None), ("m", "I", m)],
               [("F", "v"), ("m", "v")],
               [("fm", [(1, "flow", "m")]), ("fv", [(1, "flow", "v")]), ("f2", [(1, "flow", 2)])])
    G = Reference(g).evaluate(S_POINTS[0])
    s = S_POINTS[0]
    # 1-junction: F - e2... bond 2 points into v: F + e_2 = 0, e_2 = s*m*f_in, f_in = -f_2 = -v
    assert _close(G[1, 0], 1 / (m * s))
    assert _close(G[0, 0], -1 / (m * s))
    assert _close(G[2, 0], 1 / (m * s))


def test_reference_dc_motor_gyrator():
    Ra, La, K, J, b = 1.1, 0.3, 0.7, 0.25, 0.05
    g = _graph([("V", "Se", None), ("ia", "One", None), ("Ra", "R", Ra), ("La", "I", La),
                ("K", "GY", K), ("w", "One", None), ("J", "I", J), ("b", "R", b)],
               [("V", "ia"), ("ia", "Ra"), ("ia", "La"), ("ia", "K"), ("K", "w"), ("w", "J"),
                ("w", "b")],
               [("omega", [(1, "flow", "J")]), ("i", [(1, "flow", "ia")])])
    ref = Reference(g)
    for s in S_POINTS:
        G = ref.evaluate(s)
        d = (La * s + Ra) * (J * s + b) + K ** 2
        assert _close(G[0, 0], K / d)
        assert _close(G[1, 0], (J * s + b) / d)


def test_reference_transformer_and_rigid_gear():
    """Se -> 1[J1] -> TF n -> 1[J2]: J2 is rigidly joined, effective inertia J1 + n^2 J2."""
    n, J1, J2 = 3.0, 0.5, 0.2
    g = _graph([("T", "Se", None), ("a", "One", None), ("J1", "I", J1), ("n", "TF", n),
                ("b", "One", None), ("J2", "I", J2)],
               [("T", "a"), ("a", "J1"), ("a", "n"), ("n", "b"), ("b", "J2")],
               [("w1", [(1, "flow", "J1")]), ("w2", [(1, "flow", "J2")]),
                ("p2", [(1, "momentum", "J2")]), ("tq", [(1, "effort", 4)])])
    ref = Reference(g)
    s = S_POINTS[1]
    G = ref.evaluate(s)
    w1 = 1 / (s * (J1 + n ** 2 * J2))
    assert _close(G[0, 0], w1)
    assert _close(G[1, 0], n * w1)                 # f2 = n f1
    assert _close(G[2, 0], J2 * n * w1)            # p2 = J2 f2
    assert _close(G[3, 0], J2 * s * n * w1)        # e2 on bond 4 drives J2


def test_reference_flow_source_with_reversed_bonds():
    """Sf Q with its bond pointing into it and a C whose bond points out of it:
    Q still flows into the node and into C, e = Q/(C s)."""
    Cc = 0.8
    g = _graph([("Q", "Sf", None), ("z", "Zero", None), ("C", "C", Cc)],
               [("z", "Q"), ("C", "z")],
               [("e", [(1, "effort", "C")]), ("fC", [(1, "flow", "C")]), ("fQ", [(1, "flow", "Q")])])
    s = S_POINTS[2]
    G = Reference(g).evaluate(s)
    assert _close(G[0, 0], 1 / (Cc * s))
    assert _close(G[1, 0], 1)
    assert _close(G[2, 0], -1)     # the flow *into* the source is -Q


def test_reference_parallel_bonds_loop():
    """Issue 11: Sf on a 0-junction, R on a 1-junction, two parallel bonds: e = R u / 4."""
    R = 1.3
    g = _graph([("u", "Sf", None), ("A", "Zero", None), ("B", "One", None), ("R", "R", R)],
               [("u", "A"), ("A", "B"), ("A", "B"), ("B", "R")],
               [("e", [(1, "effort", "A")]), ("eR", [(1, "effort", "R")])])
    G = Reference(g).evaluate(S_POINTS[0])
    assert _close(G[0, 0], R / 4)
    assert _close(G[1, 0], R / 2)


def test_reference_effort_source_on_capacitor_is_well_posed():
    """Derivative causality: Se straight onto a C, q = C u, f = C s u."""
    Cc = 0.6
    g = _graph([("u", "Se", None), ("C", "C", Cc)], [("u", "C")],
               [("q", [(1, "displacement", "C")]), ("f", [(2, "flow", "C")])])
    ref = Reference(g)
    assert ref.well_posed
    s = S_POINTS[0]
    G = ref.evaluate(s)
    assert _close(G[0, 0], Cc)
    assert _close(G[1, 0], 2 * Cc * s)


@pytest.mark.parametrize("case", ["two Se on a 0", "two Sf on a 1", "loop, same direction",
                                  "loop, opposite directions"])
def test_reference_detects_ill_posed_graphs(case):
    if case == "two Se on a 0":
        els = [("a", "Se", None), ("b", "Se", None), ("z", "Zero", None), ("R", "R", 1.0)]
        bonds = [("a", "z"), ("b", "z"), ("z", "R")]
    elif case == "two Sf on a 1":
        els = [("a", "Sf", None), ("b", "Sf", None), ("o", "One", None), ("C", "C", 1.0)]
        bonds = [("a", "o"), ("b", "o"), ("o", "C")]
    else:   # Se on a 0-junction with two bonds to an otherwise empty 1-junction
        els = [("u", "Se", None), ("A", "Zero", None), ("B", "One", None)]
        bonds = [("u", "A"), ("A", "B"), ("A", "B") if "same" in case else ("B", "A")]
    g = _graph(els, bonds, [("y", [(1, "effort", 2)])])
    assert not Reference(g).well_posed


def test_reference_does_not_depend_on_description_order():
    for seed in range(20):
        g = gen.generate(seed, max_elements=14)
        ref = Reference(g)
        if not ref.well_posed:
            continue
        rng = random.Random(seed)
        els, bonds = list(g.elements), list(g.bonds)
        rng.shuffle(els)
        rng.shuffle(bonds)
        h = Graph(g.name, tuple(els), tuple(bonds), g.outputs)
        s = complex(0.41, 0.93)
        ref_h = Reference(h)

        def named(r):
            rows = r.evaluate_exact(s)
            return {(o, u): rows[i][j] for i, o in enumerate(r.output_names)
                    for j, u in enumerate(r.input_names)}
        assert named(ref) == named(ref_h)


def test_compare_flags_small_disagreements():
    ref = np.array([[1.0 + 2j, 0.0]])
    ok, _, _ = gen._compare(ref, ref * (1 + 1e-10), np.zeros(ref.shape))
    assert ok
    ok, rel, worst = gen._compare(ref, ref * (1 + 1e-7), np.zeros(ref.shape))
    assert not ok and worst == (0, 0)
    ok, _, worst = gen._compare(ref, ref + np.array([[0, 1e-9]]), np.zeros(ref.shape))
    assert not ok and worst == (0, 1)          # an exact zero compared absolutely


# ============================================================ the generator covers the structures

N_GRAPHS = 320
CHUNK = 16
MAX_ELEMENTS = 20      # the bench script goes to 25; 20 keeps this file near 40 s on 2 cores
TIME_LIMIT_S = 10.0    # CPU seconds per graph (both insertion orders, both paths)


def test_generator_covers_the_structures():
    graphs = [gen.generate(seed, max_elements=MAX_ELEMENTS) for seed in range(N_GRAPHS)]
    fams = {g.family.rstrip("*") for g in graphs}
    assert fams == set(gen.FAMILIES)
    assert any(g.family.endswith("*") for g in graphs)           # dualized
    kinds = {el.kind for g in graphs for el in g.elements}
    assert kinds == {"Se", "Sf", "I", "C", "R", "TF", "GY", "Zero", "One"}
    signal_kinds = {(t.kind, type(t.target)) for g in graphs for o in g.outputs for t in o.terms}
    assert signal_kinds == {(k, tp) for k in ("effort", "flow", "displacement", "momentum")
                            for tp in (str, int)}
    assert any(len(o.terms) > 1 for g in graphs for o in g.outputs)   # linear combinations
    assert any(len(g.sources) >= 3 for g in graphs)
    assert any(len({el.kind for el in g.sources}) == 2 for g in graphs)
    assert any(g.meta.get("clash") for g in graphs)
    assert max(len(g.elements) for g in graphs) >= MAX_ELEMENTS - 2

    def count(pred):
        return sum(1 for g in graphs if pred(g))

    kind = lambda g: {el.name: el.kind for el in g.elements}  # noqa: E731
    junction = ("Zero", "One")
    # reversed bonds into storage/R and out of sources
    assert count(lambda g: any(kind(g)[b.tail] in ("I", "C", "R") for b in g.bonds)) > 30
    assert count(lambda g: any(kind(g)[b.head] in ("Se", "Sf") for b in g.bonds)) > 10
    # parallel junction-junction bonds
    assert count(lambda g: len({frozenset((b.tail, b.head)) for b in g.bonds
                                if kind(g)[b.tail] in junction and kind(g)[b.head] in junction})
                 < sum(1 for b in g.bonds if kind(g)[b.tail] in junction
                       and kind(g)[b.head] in junction)) > 5
    # two I on one 1-junction or two C on one 0-junction (rigidly joined storage)
    def twins(g):
        k = kind(g)
        for j, jk in k.items():
            if jk in junction:
                st = "I" if jk == "One" else "C"
                if sum(k[b.tail if b.head == j else b.head] == st for b in g.bonds
                       if j in (b.tail, b.head)) >= 2:
                    return True
        return False
    assert count(twins) > 20
    # ill-posed graphs exist (and must be refused)
    assert sum(not Reference(g).well_posed for g in graphs[:120]) >= 3


# ============================================================ the engine against the reference

def _report(bad) -> str:
    lines = []
    by_cls: dict = {}
    for o in bad:
        by_cls.setdefault(o.cls, []).append(o)
    for cls, os_ in by_cls.items():
        lines.append(f"{cls}: {len(os_)} graphs (seeds {', '.join(str(o.graph.seed) for o in os_)})")
    for cls, os_ in by_cls.items():
        small = min(os_, key=lambda o: o.graph.size)
        lines.append(f"\n--- smallest {cls} (seed {small.graph.seed}, {small.graph.family}) ---")
        lines.append(small.reproducer())
    return "\n".join(lines)


@pytest.mark.parametrize("chunk", range(N_GRAPHS // CHUNK))
def test_random_graphs_match_the_reference(chunk):
    outcomes = []
    for seed in range(chunk * CHUNK, (chunk + 1) * CHUNK):
        g = gen.generate(seed, max_elements=MAX_ELEMENTS)
        outcomes.append(gen.check(g, time_limit_s=TIME_LIMIT_S))
    bad = [o for o in outcomes if o.cls in gen.FAILURES]
    assert not bad, _report(bad)


# Graphs that the long run (bench/verify_random.py, up to 25 elements) once failed:
# singular loops from storage fixed by the junction structure (421, 812, 2699), nested
# loop solutions too slow to reduce (1995, 2628), outputs that cancel to 0 (1538).
REGRESSION_SEEDS = [421, 812, 1538, 1995, 2628, 2699]


@pytest.mark.parametrize("seed", REGRESSION_SEEDS)
def test_long_run_regressions(seed):
    g = gen.generate(seed)
    outcome = gen.check(g, time_limit_s=30)
    assert outcome.cls not in gen.FAILURES, _report([outcome])
