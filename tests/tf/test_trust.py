"""Regression tests of issue 11, item 1: terms that collapse onto one monomial.

Every expected value is derived by hand in the docstring of its test.
"""

import sympy as sp

import bondgraph as bg
from bondgraph.tf import transfer_function


def _rc_ladder():
    g = bg.BondGraph("ladder")
    V = bg.Se("V")
    g.add(V, bg.One("j1"), bg.Zero("n1"), bg.One("j2"), bg.Zero("n2"),
          bg.R("R1"), bg.R("R2"), bg.C("C1"), bg.C("C2"))
    for t, h in [(V, "j1"), ("j1", "R1"), ("j1", "n1"), ("n1", "C1"), ("n1", "j2"),
                 ("j2", "R2"), ("j2", "n2"), ("n2", "C2")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"v2": bg.effort("C2")})


def test_two_section_rc_ladder():
    """Nodal analysis, v1 and v2 the capacitor voltages:

    C1 v1' = (V - v1)/R1 - (v1 - v2)/R2,   C2 v2' = (v1 - v2)/R2
    => v2/V = 1/(R1 R2 C1 C2 s^2 + (R1 C1 + R1 C2 + R2 C2) s + 1).
    """
    R1, R2, C1, C2, s = sp.symbols("R1 R2 C1 C2 s", positive=True)
    G = _rc_ladder().transfer_function("V", "v2")
    expected = 1 / (R1 * R2 * C1 * C2 * s**2 + (R1 * C1 + R1 * C2 + R2 * C2) * s + 1)
    assert sp.simplify(G.expr.subs(G.s, s) - expected) == 0


def test_feedthrough_meets_reciprocal():
    """x' = -x + u/a, y = a x + u: G = a (1/a)/(s + 1) + 1 = (s + 2)/(s + 1)."""
    a = sp.Symbol("a", positive=True)
    G = transfer_function(A=[[-1]], B=[[1 / a]], C=[[a]], D=[[1]])
    assert sp.simplify(G.expr - (G.s + 2) / (G.s + 1)) == 0


def test_driving_point_admittance_rs_parallel_r_c():
    """Se V on a 0-junction with Rs and a 1-junction holding R and C (Rs || (R + C)).

    Current drawn from the source: i = V/Rs + V C s/(R C s + 1); at DC, V/Rs.
    The source's flow (power out of it positive) is that current.
    """
    g = bg.BondGraph("y")
    V = bg.Se("V")
    g.add(V, bg.Zero("n"), bg.R("Rs"), bg.One("b"), bg.R("R"), bg.C("C"))
    for t, h in [(V, "n"), ("n", "Rs"), ("n", "b"), ("b", "R"), ("b", "C")]:
        g.connect(t, h)
    m = bg.derive(g, outputs={"i": bg.flow(1)})
    G = m.transfer_function("V", "i")
    Rs, R, C, s = sp.symbols("Rs R C s", positive=True)
    expected = 1 / Rs + C * s / (R * C * s + 1)
    assert sp.simplify(G.expr.subs(G.s, s) - expected) == 0
