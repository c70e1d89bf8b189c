"""Operating points and the numeric plant there (issue 14), against hand derivations.

Pendulum ``J theta'' = T - b theta' - m g l sin(theta)``: equilibria at
``theta = 0`` and ``pi`` for ``T = 0``, ``asin(T/(m g l))`` otherwise; the
Jacobian at ``theta0`` is ``[[-b/J, -m g l cos(theta0)], [1/J, 0]]`` in the
states ``(p_J, q_grav)``.  Hanging mass on a spring of compliance ``c``:
``q = m g c``.  DC motor at constant voltage: ``omega = K V/(K^2 + Ra b)``,
``i = (V - K omega)/Ra``.
"""

import math

import control
import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.linear.operating import Equilibrium, EquilibriumError

M, G, L = sympy.symbols("m g l", positive=True)
PEND = {"m": 1.0, "g": 9.81, "l": 0.5, "J": 0.25, "b": 0.1}


def pendulum():
    g = bg.BondGraph("pendulum")
    w = bg.One("w")
    g.add(bg.Se("T"), w, bg.I("J"), bg.R("b"), bg.C("grav", law=M * G * L * sympy.sin(bg.q)))
    for t, h in [("T", w), (w, "J"), (w, "b"), (w, "grav")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"theta": bg.displacement("grav")})


def dc_motor():
    g = bg.BondGraph("dc")
    i, w = bg.One("i"), bg.One("w")
    g.add(bg.Se("V"), i, bg.R("Ra"), bg.I("La"), bg.GY("K"), w, bg.I("J"), bg.R("b"))
    for t, h in [("V", i), (i, "Ra"), (i, "La"), (i, "K"), ("K", w), (w, "J"), (w, "b")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"omega": bg.flow("J")})


@pytest.mark.parametrize("guess, theta0", [(0.3, 0.0), (2.8, math.pi), (-3.5, -math.pi)])
def test_pendulum_equilibria(guess, theta0):
    eq = pendulum().equilibrium(PEND, {"T": 0.0}, guess={"q_grav": guess})
    assert eq.states["q_grav"] == pytest.approx(theta0, abs=1e-12)
    assert eq.states["p_J"] == pytest.approx(0.0, abs=1e-12)
    assert eq.residual <= 1e-10


def test_pendulum_under_torque_numeric_and_exact_agree():
    T = 1.0
    want = math.asin(T / (1.0 * 9.81 * 0.5))
    exact = pendulum().equilibrium(PEND, {"T": T}, guess={"q_grav": 0.1})
    numeric = pendulum().equilibrium(PEND, {"T": T}, guess={"q_grav": 0.1}, exact=False)
    assert numeric.method == "numeric"
    assert exact.states["q_grav"] == pytest.approx(want, rel=1e-12)
    assert numeric.states["q_grav"] == pytest.approx(want, rel=1e-10)


@pytest.mark.parametrize("theta0", [0.0, math.pi])
def test_pendulum_plant_at_the_equilibrium(theta0):
    model = pendulum()
    eq = model.equilibrium(PEND, {"T": 0.0}, guess={"q_grav": theta0 + 0.2})
    P = model.linearize(eq)
    assert isinstance(P, bg.NumericStateSpace)
    assert P.state_names == ("p_J", "q_grav") and P.input_names == ("T",)
    J, b, mgl = PEND["J"], PEND["b"], PEND["m"] * PEND["g"] * PEND["l"]
    A = np.array([[-b / J, -mgl * math.cos(theta0)], [1 / J, 0.0]])
    np.testing.assert_allclose(P.A, A, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(P.B, [[1.0], [0.0]])
    np.testing.assert_allclose(P.C, [[0.0, 1.0]])
    sys_ = P.to_control()
    assert isinstance(sys_, control.StateSpace)
    assert list(sys_.output_labels) == ["theta"]
    # upright: one unstable pole; hanging: both stable
    unstable = np.sum(np.linalg.eigvals(P.A).real > 0)
    assert unstable == (1 if theta0 else 0)


def test_linearize_with_values_and_an_explicit_point():
    model = pendulum()
    P = model.linearize({"p_J": 0.0, "q_grav": math.pi}, {"T": 0.0}, values=PEND)
    assert P.A[0, 1] == pytest.approx(9.81 * 0.5)            # -m g l cos(pi)
    with pytest.raises(EquilibriumError, match=r"not an equilibrium at these values: dp_J/dt"):
        model.linearize({"p_J": 0.0, "q_grav": 1.0}, {"T": 0.0}, values=PEND)


def test_hanging_mass_spring():
    m, g_ = sympy.symbols("m g", positive=True)
    gr = bg.BondGraph("hang")
    v = bg.One("v")
    gr.add(bg.Se("W", value=m * g_), v, bg.I("m", m), bg.C("c"), bg.R("b"))
    for t, h in [("W", v), (v, "m"), (v, "c"), (v, "b")]:
        gr.connect(t, h)
    vals = {"m": 2.0, "g": 9.81, "c": 0.01, "b": 1.0}
    eq = bg.derive(gr).equilibrium(vals)
    assert eq.method == "exact"
    assert eq.states["q_c"] == pytest.approx(2.0 * 9.81 * 0.01, rel=1e-14)


def test_dc_motor_at_constant_voltage():
    vals = {"Ra": 2.0, "La": 1e-3, "K": 0.1, "J": 0.01, "b": 1e-3}
    V = 12.0
    eq = dc_motor().equilibrium(vals, {"V": V})
    omega = vals["K"] * V / (vals["K"] ** 2 + vals["Ra"] * vals["b"])
    current = (V - vals["K"] * omega) / vals["Ra"]
    assert eq.states["p_J"] == pytest.approx(vals["J"] * omega, rel=1e-12)
    assert eq.states["p_La"] == pytest.approx(vals["La"] * current, rel=1e-12)
    P = dc_motor().linearize(eq)
    dc = (P.D - P.C @ np.linalg.solve(P.A, P.B))[0, 0]
    assert dc == pytest.approx(vals["K"] / (vals["K"] ** 2 + vals["Ra"] * vals["b"]), rel=1e-12)


def test_state_no_equation_determines_must_be_fixed():
    # a damped mass with its position as an output: x' = p/m, no equation pins x
    g = bg.BondGraph("slide")
    v = bg.One("v")
    g.add(bg.Se("F"), v, bg.I("m"), bg.R("b"))
    for t, h in [("F", v), (v, "m"), (v, "b")]:
        g.connect(t, h)
    model = bg.derive(g, outputs={"x": bg.displacement("m")})
    assert model.state_names == ("p_m", "x")     # the integrator takes the output's name
    with pytest.raises(EquilibriumError, match=r"not isolated.*so x are not determined to first order.*fixed="):
        model.equilibrium({"m": 1.0, "b": 0.5}, {"F": 0.0}, exact=False)
    with pytest.raises(EquilibriumError, match=r"not isolated"):
        model.equilibrium({"m": 1.0, "b": 0.5}, {"F": 0.0})
    eq = model.equilibrium({"m": 1.0, "b": 0.5}, {"F": 0.0}, fixed={"x": 0.3})
    assert eq.states == {"p_m": 0.0, "x": 0.3}


def test_no_equilibrium_is_reported():
    # a constant force on a free mass: p' = F never vanishes
    g = bg.BondGraph("push")
    g.add(bg.Se("F"), bg.I("m"))
    g.connect("F", "m")
    with pytest.raises(EquilibriumError, match=r"no equilibrium found.*residual"):
        bg.derive(g).equilibrium({"m": 1.0}, {"F": 1.0})


def test_bad_arguments_name_the_culprit():
    model = pendulum()
    with pytest.raises(EquilibriumError, match=r"input 'TT' is not one of T"):
        model.equilibrium(PEND, {"TT": 0.0})
    with pytest.raises(EquilibriumError, match=r"guess state 'theta' is not one of p_J, q_grav"):
        model.equilibrium(PEND, guess={"theta": 0.0})
    with pytest.raises(bg.ParameterValueError, match=r"unknown parameter 'gg'"):
        model.equilibrium({**PEND, "gg": 1.0})
    with pytest.raises(bg.MissingValueError, match=r"missing l"):
        model.equilibrium({k: v for k, v in PEND.items() if k != "l"})


def test_equilibrium_is_immutable_and_picklable():
    import pickle

    eq = pendulum().equilibrium(PEND, {"T": 0.0})
    with pytest.raises(TypeError):
        eq.states["q_grav"] = 1.0
    back = pickle.loads(pickle.dumps(eq))
    assert isinstance(back, Equilibrium) and dict(back.states) == dict(eq.states)
