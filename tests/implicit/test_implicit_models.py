"""Implicit models (issue 29): nonlinear loops and laws with no closed-form inverse.

Every expected value comes from outside the code under test: the Lambert-W
closed form of a diode in series with a resistor, the small-signal
conductance ``g_d = (I + Is)/Vt`` by hand, the orifice formula
``Q = sqrt(dp / (1/K1^2 + 1/K2^2))``, and ODE solutions written here with
their own ``fsolve`` / closed forms and ``solve_ivp``.

For the nonlinear random-graph differential check (issue 22,
``tests/verification/``): a graph that used to be refused with
``AlgebraicLoopError`` "nonlinear algebraic loop" or ``LawError`` "needs the
inverse" now derives with ``model.algebraic`` non-empty.  The harness should
count such graphs as answered, not refused, and compare
``compile_dynamics(model).derivatives(t, x, u, p)`` (which solves ``0 = g``
for ``z`` by Newton) with its all-bond-variables ``scipy.optimize.root``
reference at the same random states; a ``SimulationError`` from the Newton
solve at a state where the reference finds a solution is a failure to report.
Storage in derivative causality constrained through such unknowns is reduced
by differentiating the constraint (``tests/implicit/test_index_reduction.py``).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve
from scipy.special import lambertw

import bondgraph as bg
from bondgraph.numeric.errors import SimulationError

Is_, Vt_ = sympy.symbols("Is Vt", positive=True)
DIODE = {"R1": 500.0, "R": 500.0, "C": 1e-6, "Is": 1e-12, "Vt": 0.025}


def diode_circuit() -> bg.Model:
    """V -- R1 -- node(C) -- [R in series with the diode D] to ground."""
    g = bg.BondGraph("diode")
    g.add(bg.Se("V"), bg.One("a"), bg.R("R1"), bg.Zero("n"), bg.C("C"), bg.One("s"), bg.R("R"),
          bg.R("D", inverse=Is_ * (sympy.exp(bg.e / Vt_) - 1)))
    for t, h in [("V", "a"), ("a", "R1"), ("a", "n"), ("n", "C"), ("n", "s"), ("s", "R"),
                 ("s", "D")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"i": bg.flow("D"), "vd": bg.effort("D")})


def lambert_current(V: float, R: float, Is: float, Vt: float) -> float:
    """Series resistor R and diode across V: ``I = (Vt/R) W((R Is/Vt) exp((V + R Is)/Vt)) - Is``."""
    arg = np.log(R * Is / Vt) + (V + R * Is) / Vt        # W of exp(arg), arg large
    w = float(np.real(lambertw(np.exp(arg)))) if arg < 700 else _lambertw_exp(arg)
    return Vt / R * w - Is


def _lambertw_exp(a: float) -> float:
    """W(exp(a)) for large a: w + log(w) = a by Newton (no overflow)."""
    w = a - np.log(a)
    for _ in range(50):
        w -= (w + np.log(w) - a) / (1 + 1 / w)
    return w


def test_diode_loop_is_kept_implicit_and_printed():
    model = diode_circuit()
    assert model.algebraic_names == ("f_D",)
    assert model.is_implicit and "R:D" in model.algebraic_origin[0]
    text = str(model)
    assert "1 algebraic unknowns (f_D)" in text and "\n  0 = " in text
    assert "0 &= " in model.to_latex()
    assert {p.name for p in model.parameters} == {"R1", "R", "C", "Is", "Vt"}
    with pytest.raises(bg.NonlinearModelError, match="f_D"):
        model.state_space()
    with pytest.raises(bg.NonlinearModelError, match="implicit"):
        model.linearize({"q_C": 0.0}, {"V": 0.0})


@pytest.mark.parametrize("V", [0.3, 5.0], ids=["below-knee", "forward"])
def test_diode_operating_point_against_lambert_w(V):
    model = diode_circuit()
    eq = model.equilibrium(DIODE, {"V": V}, tol=1e-12)
    Rt = DIODE["R1"] + DIODE["R"]
    I = lambert_current(V, Rt, DIODE["Is"], DIODE["Vt"])
    assert eq.algebraic["f_D"] == pytest.approx(I, rel=1e-9)
    u = V - DIODE["R1"] * I                          # node voltage: no current into C
    assert eq.states["q_C"] == pytest.approx(DIODE["C"] * u, rel=1e-9)
    dyn = bg.numeric.compile_dynamics(model)
    p = dyn.parameter_vector(DIODE)
    i, vd = dyn.outputs(0.0, [eq.states["q_C"]], [V], p)
    assert vd == pytest.approx(V - Rt * I, rel=1e-9)
    assert i == pytest.approx(I, rel=1e-9)


def test_diode_small_signal_by_hand():
    model = diode_circuit()
    V = 5.0
    eq = model.equilibrium(DIODE, {"V": V}, tol=1e-12)
    I = lambert_current(V, DIODE["R1"] + DIODE["R"], DIODE["Is"], DIODE["Vt"])
    gd = (I + DIODE["Is"]) / DIODE["Vt"]             # d/de Is (exp(e/Vt) - 1)
    R, R1, C = DIODE["R"], DIODE["R1"], DIODE["C"]
    gs = gd / (1 + R * gd)                           # the series branch R + diode
    plant = model.linearize(eq)
    assert plant.A[0, 0] == pytest.approx(-1 / (R1 * C) - gs / C, rel=1e-8)
    assert plant.B[0, 0] == pytest.approx(1 / R1, rel=1e-12)
    # outputs i and vd against the node voltage u = q/C
    assert plant.C[0, 0] * C == pytest.approx(gs, rel=1e-8)
    assert plant.C[1, 0] * C == pytest.approx(1 / (1 + R * gd), rel=1e-8)
    assert np.allclose(plant.D, 0.0)


def orifices() -> bg.Model:
    K1, K2 = sympy.symbols("K1 K2", positive=True)
    g = bg.BondGraph("pipes")
    g.add(bg.C("A1"), bg.Zero("n1"), bg.One("s"), bg.R("o1", law=bg.f * abs(bg.f) / K1**2),
          bg.R("o2", law=bg.f * abs(bg.f) / K2**2), bg.Zero("n2"), bg.C("A2"))
    for t, h in [("n1", "A1"), ("n1", "s"), ("s", "o1"), ("s", "o2"), ("s", "n2"), ("n2", "A2")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"Q": bg.flow("o1"), "dp1": bg.effort("o1")})


PIPES = {"A1": 2.0, "A2": 0.5, "K1": 3.0, "K2": 4.0}


def q_hand(dp: float) -> float:
    return np.sign(dp) * np.sqrt(abs(dp) / (1 / PIPES["K1"]**2 + 1 / PIPES["K2"]**2))


@pytest.mark.parametrize("q", [(10.0, 1.0), (1.0, 3.0), (4.0, 0.25)], ids=["forward", "back", "zero"])
def test_orifices_flow_against_hand_formula(q):
    model = orifices()
    assert len(model.algebraic) == 1
    dyn = bg.numeric.compile_dynamics(model)
    p = dyn.parameter_vector(PIPES)
    dp = q[0] / PIPES["A1"] - q[1] / PIPES["A2"]
    Q, dp1 = dyn.outputs(0.0, list(q), [], p)
    assert Q == pytest.approx(q_hand(dp), rel=1e-10, abs=1e-12)
    assert dp1 == pytest.approx(q_hand(dp) * abs(q_hand(dp)) / PIPES["K1"]**2, rel=1e-9, abs=1e-12)
    assert dyn.derivatives(0.0, list(q), [], p) == pytest.approx([-Q, Q], rel=1e-12, abs=1e-14)


def test_orifices_simulation_against_closed_form_ode():
    """Until just before the pressures equalize (at t = 0.745 here, where Q ~ sqrt(dp) is not
    Lipschitz and any integrator crawls)."""
    model = orifices()
    t_eval = np.linspace(0.0, 0.5, 6)
    res = bg.simulate(model, PIPES, (0.0, 0.5), {"q_A1": 10.0, "q_A2": 0.0}, t_eval=t_eval,
                      rtol=1e-10, atol=1e-12)

    def rhs(t, x):
        Q = q_hand(x[0] / PIPES["A1"] - x[1] / PIPES["A2"])
        return [-Q, Q]
    ref = solve_ivp(rhs, (0.0, 0.5), [10.0, 0.0], t_eval=t_eval, rtol=1e-11, atol=1e-13)
    assert np.allclose(res.x, ref.y.T, rtol=1e-7, atol=1e-8)
    # by hand: sqrt(dp) falls linearly at (1/A1 + 1/A2) / (2 sqrt(1/K1^2 + 1/K2^2))
    rate = (1 / PIPES["A1"] + 1 / PIPES["A2"]) / (2 * np.sqrt(1 / 9 + 1 / 16))
    assert res["Q"] == pytest.approx([q_hand((np.sqrt(5.0) - rate * t)**2) for t in t_eval],
                                     rel=1e-7)


FRICTION = {"m": 2.0, "Ff": 1.5, "v0": 0.1, "b": 3.0}


def friction_mass() -> bg.Model:
    """A driven mass; tanh friction and a viscous damper in series (same force) to ground."""
    Ff, v0 = sympy.symbols("Ff v0", positive=True)
    g = bg.BondGraph("drive")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.Zero("c"),
          bg.R("fr", law=Ff * sympy.tanh(bg.f / v0)), bg.R("b"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "c"), ("c", "fr"), ("c", "b")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"force": bg.effort("b"), "v": bg.flow("m")})


def test_tanh_friction_in_series_with_damper_against_independent_solve():
    model = friction_mass()
    assert model.algebraic
    m, Ff, v0, b = (FRICTION[k] for k in ("m", "Ff", "v0", "b"))

    def force(v: float, guess: float) -> float:
        # the series pair: common force e, v = v_fr + v_b, e = Ff tanh(v_fr/v0) = b v_b
        vf = fsolve(lambda w: Ff * np.tanh(w[0] / v0) - b * (v - w[0]), [guess], xtol=1e-13)[0]
        return Ff * np.tanh(vf / v0)

    def rhs(t, x):
        return [np.sin(2 * t) * 3.0 - force(x[0] / m, 0.0)]
    t_eval = np.linspace(0.0, 4.0, 17)
    ref = solve_ivp(rhs, (0.0, 4.0), [0.5], t_eval=t_eval, rtol=1e-10, atol=1e-12)
    res = bg.simulate(model, FRICTION, (0.0, 4.0), {"p_m": 0.5}, u=lambda t: [3.0 * np.sin(2 * t)],
                      t_eval=t_eval, rtol=1e-10, atol=1e-12)
    assert np.allclose(res["p_m"], ref.y[0], rtol=1e-7, atol=1e-9)
    forces = [force(p / m, 0.0) for p in ref.y[0]]
    assert np.allclose(res["force"], forces, rtol=1e-6, atol=1e-8)


def test_law_with_no_solution_names_the_unknown_and_state():
    """``e = Ff (tanh f + tanh^3 f)`` cannot exceed 2 Ff: an effort of 3 Ff has no flow."""
    Ff = sympy.Symbol("Ff", positive=True)
    g = bg.BondGraph("sat")
    g.add(bg.Se("F"), bg.Zero("n"), bg.R("fr", law=Ff * (sympy.tanh(bg.f) + sympy.tanh(bg.f)**3)),
          bg.One("j"), bg.I("m"))
    for t, h in [("F", "n"), ("n", "fr"), ("n", "j"), ("j", "m")]:
        g.connect(t, h)
    model = bg.derive(g, outputs={"f": bg.flow("fr")})
    assert model.algebraic_names == ("f_fr",)
    dyn = bg.numeric.compile_dynamics(model)
    p = dyn.parameter_vector({"Ff": 1.0, "m": 1.0})
    # solvable below 2 Ff: tanh(f) + tanh(f)^3 = 1 at tanh f = 0.6823278 (root of s^3 + s - 1)
    s = float(np.real([r for r in np.roots([1, 0, 1, -1]) if abs(r.imag) < 1e-12][0]))
    assert dyn.outputs(0.0, [0.0], [1.0], p)[0] == pytest.approx(np.arctanh(s), rel=1e-10)
    with pytest.raises(SimulationError, match=r"f_fr.*R:fr.*p_m = 0\.25"):
        dyn.derivatives(0.0, [0.25], [3.0], p)


def test_inertia_with_only_an_inverse_law():
    """``p = m f + a f^5`` has no closed-form ``f(p)``: the flow of the I is an algebraic unknown."""
    from scipy.optimize import brentq

    m_, a_ = sympy.symbols("m a", positive=True)
    g = bg.BondGraph("stiffening")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m", inverse=m_ * bg.f + a_ * bg.f**5), bg.R("b"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b")]:
        g.connect(t, h)
    model = bg.derive(g, outputs={"v": bg.flow("m")})
    assert model.algebraic_names == ("f_m",) and "I:m" in model.algebraic_origin[0]
    dyn = bg.numeric.compile_dynamics(model)
    p = dyn.parameter_vector({"m": 2.0, "a": 0.5, "b": 3.0})
    f = brentq(lambda f: 2.0 * f + 0.5 * f**5 - 7.0, 0.0, 7.0, xtol=1e-15)
    assert dyn.outputs(0.0, [7.0], [1.0], p)[0] == pytest.approx(f, rel=1e-12)
    assert dyn.derivatives(0.0, [7.0], [1.0], p)[0] == pytest.approx(1.0 - 3.0 * f, rel=1e-12)
