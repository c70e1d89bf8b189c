"""Issue 11, item 6: the equilibrium check of ``Model.linearize`` with floats.

``Float(0.0) != 0`` in sympy, and ``sin(math.pi)`` is 1.2e-16, not 0: genuine
equilibria given as floats must be accepted (within ``tol``), non-equilibria
still refused.  Every expected Jacobian is derived by hand in the test.
"""

import math

import pytest
import sympy

import bondgraph as bg

m, g_, l, b, J, k = sympy.symbols("m g l b J k", positive=True)


def msd():
    """p' = F - b p/m - k q,  q' = p/m (states p_m, q_k)."""
    g = bg.BondGraph("msd")
    v = bg.One("v")
    g.add(bg.Se("F"), v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
    for t, h in [("F", v), (v, "m"), (v, "b"), (v, "k")]:
        g.connect(t, h)
    return bg.derive(g)


def pendulum():
    """J th'' = T - b th' - m g l sin th: states p = J th', th (gravity as a nonlinear C)."""
    g = bg.BondGraph("pendulum")
    w = bg.One("w")
    g.add(bg.Se("T"), w, bg.I("J", J), bg.R("b", b),
          bg.C("grav", law=m * g_ * l * sympy.sin(bg.q)))
    for t, h in [("T", w), (w, "J"), (w, "b"), (w, "grav")]:
        g.connect(t, h)
    return bg.derive(g)


def test_msd_at_float_zero():
    # rest at the origin: p' = 0 - 0 - 0 = 0, q' = 0; Jacobian by hand
    lin = msd().linearize({"p_m": 0.0, "q_k": 0.0}, {"F": 0.0})
    assert lin.A == sympy.Matrix([[-b / m, -k], [1 / m, 0]])
    assert lin.B == sympy.Matrix([[1], [0]])


def test_msd_float_static_deflection():
    """k = 10 (a number): F = 2.5 held by the spring at q = F/k = 0.25, p = 0.

    p' = 2.5 - b*0/m - 10*0.25 = 0.0; Jacobian [[-b/m, -10], [1/m, 0]].
    With k symbolic, q = 0.25 is no equilibrium (p' = 2.5 - 0.25 k).
    """
    gen = bg.BondGraph("msd10")
    v = bg.One("v")
    gen.add(bg.Se("F"), v, bg.I("m"), bg.R("b"), bg.C("k", stiffness=10))
    for t, h in [("F", v), (v, "m"), (v, "b"), (v, "k")]:
        gen.connect(t, h)
    lin = bg.derive(gen).linearize({"p_m": 0.0, "q_k": 0.25}, {"F": 2.5})
    assert lin.A == sympy.Matrix([[-b / m, -10], [1 / m, 0]])
    with pytest.raises(bg.NonlinearModelError, match=r"dp_m/dt = 2\.5 - 0\.25\*k"):
        msd().linearize({"p_m": 0.0, "q_k": 0.25}, {"F": 2.5})


def test_pendulum_upright_at_math_pi():
    """At th = pi, p = 0, T = 0: p' = -m g l sin(pi) = 0 (1.2e-16 in floats).

    Jacobian: d p'/d p = -b/J, d p'/d th = -m g l cos(pi) = +m g l,
    d th'/d p = 1/J, d th'/d th = 0.
    """
    lin = pendulum().linearize({"p_J": 0.0, "q_grav": math.pi}, {"T": 0.0})
    hand = sympy.Matrix([[-b / J, m * g_ * l], [1 / J, 0]])
    for i in range(2):
        for j in range(2):
            diff = sympy.expand(lin.A[i, j] - hand[i, j])
            # float coefficients (cos(math.pi) = -1.0): zero up to rounding
            for term in sympy.Add.make_args(diff):
                c, _ = term.as_coeff_Mul()
                assert abs(float(c)) < 1e-12, (i, j, diff)
    assert lin.B == sympy.Matrix([[1], [0]])


def test_pendulum_numeric_parameters_at_math_pi():
    """All numbers: J = 2, b = 0.5, m g l = 9.81 * 0.3 * 1.2; A = [[-b/J, mgl], [1/J, 0]]."""
    gen = bg.BondGraph("p")
    w = bg.One("w")
    mgl = 9.81 * 0.3 * 1.2
    gen.add(bg.Se("T"), w, bg.I("J", 2), bg.R("b", 0.5), bg.C("grav", law=mgl * sympy.sin(bg.q)))
    for t, h in [("T", w), (w, "J"), (w, "b"), (w, "grav")]:
        gen.connect(t, h)
    lin = bg.derive(gen).linearize({"p_J": 0.0, "q_grav": math.pi}, {"T": 0.0})
    assert [float(x) for x in lin.A] == pytest.approx([-0.25, mgl, 0.5, 0.0], rel=1e-12)


def test_genuine_non_equilibria_still_refused():
    model = pendulum()
    # th = pi/2 (as a float): p' = -m g l, far from zero
    with pytest.raises(bg.NonlinearModelError, match=r"not an equilibrium: dp_J/dt = -1\.0\*g\*l\*m"):
        model.linearize({"p_J": 0.0, "q_grav": math.pi / 2}, {"T": 0.0})
    # a float torque that gravity does not balance at th = pi: p' = 1e-6
    with pytest.raises(bg.NonlinearModelError, match="not an equilibrium"):
        model.linearize({"p_J": 0.0, "q_grav": math.pi}, {"T": 1e-6})
    # msd pushed by F = 1e-3 at the origin: p' = 1e-3
    with pytest.raises(bg.NonlinearModelError, match=r"dp_m/dt = 0\.001"):
        msd().linearize({"p_m": 0.0, "q_k": 0.0}, {"F": 1e-3})
    # moving mass at the origin, p = 1: p' = -b/m (exact, symbolic): refused whatever tol
    with pytest.raises(bg.NonlinearModelError, match=r"dp_m/dt = -b/m"):
        msd().linearize({"p_m": 1, "q_k": 0}, {"F": 0}, tol=1.0)


def test_tolerance_is_settable():
    model = pendulum()
    # tol=0: sin(math.pi) = 1.2e-16 is not exactly zero
    with pytest.raises(bg.NonlinearModelError, match=r"tol=0"):
        model.linearize({"p_J": 0.0, "q_grav": math.pi}, {"T": 0.0}, tol=0)
    # a loose tolerance accepts T = 1e-6 (|1e-6| <= 1e-3 * max(1, 1e-6))
    lin = model.linearize({"p_J": 0.0, "q_grav": math.pi}, {"T": 1e-6}, tol=1e-3)
    assert lin.A[1, 0] == 1 / J
    # relative above 1: F = 1000.0 against k q = 1000.0000001 (parts ~1e3)
    gen = bg.BondGraph("s")
    v = bg.One("v")
    gen.add(bg.Se("F"), v, bg.I("m"), bg.C("k", stiffness=1000))
    for t, h in [("F", v), (v, "m"), (v, "k")]:
        gen.connect(t, h)
    spring = bg.derive(gen)   # p' = F - 1000 q, q' = p/m
    spring.linearize({"p_m": 0.0, "q_k": 1.0000000001}, {"F": 1000.0})   # |r| = 1e-7 <= 1e-9*2000
    with pytest.raises(bg.NonlinearModelError, match="not an equilibrium"):
        spring.linearize({"p_m": 0.0, "q_k": 1.001}, {"F": 1000.0})
    for bad in (-1.0, "1e-9", None):
        with pytest.raises(bg.NonlinearModelError, match="tol: expected a number >= 0"):
            model.linearize({"p_J": 0.0, "q_grav": math.pi}, {"T": 0.0}, tol=bad)


def test_exact_symbolic_values_unchanged():
    # sympy.pi is exact: sin(pi) = 0 exactly, even with tol=0
    lin = pendulum().linearize({"p_J": 0, "q_grav": sympy.pi}, {"T": 0}, tol=0)
    assert lin.A == sympy.Matrix([[-b / J, m * g_ * l], [1 / J, 0]])
