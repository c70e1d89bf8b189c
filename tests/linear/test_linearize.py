"""Linearization of a nonlinear pendulum against Jacobians derived by hand."""

import pytest
import sympy

import bondgraph as bg

m, g_, l, b, J = sympy.symbols("m g l b J", positive=True)


def pendulum():
    # J th'' = T - b th' - m g l sin(th): gravity as a nonlinear C in the angle
    g = bg.BondGraph("pendulum")
    w = bg.One("w")
    g.add(bg.Se("T"), w, bg.I("J", J), bg.R("b", b), bg.C("grav", law=m * g_ * l * sympy.sin(bg.q)))
    for t, h in [("T", w), (w, "J"), (w, "b"), (w, "grav")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"theta": bg.displacement("grav"), "omega": bg.flow("w")})


@pytest.mark.parametrize("theta0, sign", [(0, 1), (sympy.pi, -1)], ids=["bottom", "top"])
def test_pendulum_linearized(theta0, sign):
    # states (p, th): p' = T - b p/J - m g l sin th, th' = p/J
    # d/dth(-m g l sin th) = -m g l cos th0 = -sign m g l
    model = pendulum()
    lin = model.linearize({"p_J": 0, "q_grav": theta0}, {"T": 0})
    assert lin.A == sympy.Matrix([[-b / J, -sign * m * g_ * l], [1 / J, 0]])
    assert lin.B == sympy.Matrix([[1], [0]])
    assert lin.C == sympy.Matrix([[0, 1], [1 / J, 0]])
    assert lin.D == sympy.zeros(2, 1)


def test_not_an_equilibrium():
    model = pendulum()
    with pytest.raises(bg.NonlinearModelError, match=r"not an equilibrium: dp_J/dt = -g\*l\*m"):
        model.linearize({"p_J": 0, "q_grav": sympy.pi / 2}, {"T": 0})
    lin = model.linearize({"p_J": 0, "q_grav": sympy.pi / 2}, {"T": 0}, equilibrium=False)
    assert lin.A[0, 1] == 0


def test_missing_operating_point_value():
    with pytest.raises(bg.NonlinearModelError, match=r"needs a value for inputs T"):
        pendulum().linearize({"p_J": 0, "q_grav": 0})
    with pytest.raises(bg.NonlinearModelError, match=r"'p_x' is not one of"):
        pendulum().linearize({"p_x": 0}, {"T": 0})
