"""When the trim accepts a point as an equilibrium (bondgraph.linear.trim.assess).

A point is accepted only when its residual is rounding noise of its terms, or
when a Newton step that really shrinks the residual is tiny: at ``x = 1e-155``
the law ``sign(x) sqrt|x|`` has a slope of about 1e77, and the Newton correction
of a residual of 0.5 is 1e-78 (the graph where this made a wrong equilibrium,
seed 321 of the nonlinear differential run, is checked there).  A Jacobian is
singular only when two unit-free scalings agree (seed 160 of an earlier run: a
rounding residue of 1e-14 made a regular point look singular).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.linear import trim

x, u = sympy.symbols("x u", real=True)


def _orifice_equations():
    """x' = u - sign(x) sqrt|x|: the equilibrium is x = u**2 (u = 0.5: x = 0.25)."""
    return trim.Equations([u - sympy.sign(x) * sympy.sqrt(sympy.Abs(x))], [x], [u], [0.5])


def test_a_huge_slope_does_not_make_a_residual_look_converged():
    eqs = _orifice_equations()
    a = trim.assess(eqs, np.array([1e-155]), [0])
    assert a.max_residual == 0.5                     # f(1e-155) = 0.5 - 1e-77.5
    assert a.scaled_residual > 1e-3


def test_the_true_root_is_accepted():
    eqs = _orifice_equations()
    a = trim.assess(eqs, np.array([0.25]), [0])
    assert a.scaled_residual <= 1e-12


def test_pendulum_upright_is_still_accepted_at_pi():
    """-m g l sin(q) at q = pi: every term is rounding noise (sin(pi) = 1.2e-16)."""
    q, p = sympy.symbols("q p", real=True)
    eqs = trim.Equations([p / 0.25, -9.81 * 0.5 * sympy.sin(q)], [p, q], [], [])
    a = trim.assess(eqs, np.array([0.0, math.pi]), [0, 1])
    assert a.scaled_residual <= 1e-10


def test_tank_with_an_orifice_drain_by_hand():
    """Flow source Q into a tank C drained by an orifice f = K sign(e) sqrt|e| given as its
    flow law: at rest K sqrt(q/C) = Q, q = C (Q/K)**2."""
    K, C, Q = 0.8, 2.0, 0.3
    g = bg.BondGraph("tank")
    z = bg.Zero("z")
    g.add(bg.Sf("Q"), z, bg.C("C"),
          bg.R("o", inverse=K * sympy.sign(bg.e) * sympy.sqrt(sympy.Abs(bg.e))))
    for t, h in [("Q", z), (z, "C"), (z, "o")]:
        g.connect(t, h)
    eq = bg.derive(g).equilibrium({"C": C}, {"Q": Q}, guess={"q_C": 1e-155})
    assert math.isclose(eq.states["q_C"], C * (Q / K) ** 2, rel_tol=1e-9)


def test_a_rounding_residue_does_not_make_a_regular_jacobian_singular():
    """The Jacobian of seed 160 (its (0, 0) entry is the rounding residue -1.19e-14 of a
    slope that is 0): det J != 0 by expansion along row 3 (only its first entry is
    nonzero), so the point is isolated."""
    J = np.array([[-1.1944e-14, -2.0225, -0.51733, 0.0, 0.0],
                  [1.8669, 0.0, 0.0, -1.0, -1.0],
                  [1.1990, 0.0, 0.0, 0.0, 0.0],
                  [0.0, -1.2990, 0.0, 1.0689, 0.0],
                  [0.0, -1.2990, 0.0, 0.0, 0.81762]])
    z = sympy.symbols("z0:5", real=True)
    f = [sum(float(J[i, j]) * z[j] for j in range(5)) for i in range(5)]
    eqs = trim.Equations(f, list(z), [], [])
    a = trim.assess(eqs, np.zeros(5), list(range(5)))
    assert abs(np.linalg.det(J)) > 0.1
    assert not a.singular


def test_linearization_at_the_kink_of_a_quadratic_damper():
    """Flow source Q into a tank C drained by a quadratic damper e = a f + b f|f|, given with
    its inverse f = sign(e) (-a + sqrt(a^2 + 4 b |e|)) / (2 b).  At Q = 0 the tank rests
    empty, where df/de = 1/a from both sides: q' = Q - f(q/C) gives A = -1/(C a), B = 1.
    The symbolic slope reads sign(0)**2 = 0 there (seed 1727 of the differential run)."""
    a, b, C = 0.7, 0.25, 2.0
    law = a * bg.f + b * bg.f * sympy.Abs(bg.f)
    inverse = sympy.sign(bg.e) * (-a + sympy.sqrt(a**2 + 4 * b * sympy.Abs(bg.e))) / (2 * b)
    g = bg.BondGraph("tank")
    z = bg.Zero("z")
    g.add(bg.Sf("Q"), z, bg.C("C"), bg.R("d", law=law, inverse=inverse))
    for t, h in [("Q", z), (z, "C"), (z, "d")]:
        g.connect(t, h)
    model = bg.derive(g)
    eq = model.equilibrium({"C": C}, {"Q": 0.0})
    assert eq.states["q_C"] == 0.0
    (lam,) = eq.eigenvalues
    assert lam.real == pytest.approx(-1.0 / (C * a), rel=1e-6)
    plant = model.linearize(eq)
    assert float(plant.A[0, 0]) == pytest.approx(-1.0 / (C * a), rel=1e-6)
    assert float(plant.B[0, 0]) == pytest.approx(1.0, rel=1e-9)
