"""Storage rigidly constrained through a nonlinear relation (issue 29): index reduction.

Every expected value is derived here by hand and solved with scipy, without
the code under test:

* a crank: inertia ``J1`` (angle ``theta``) drives ``J2`` through an MTF of
  ratio ``r cos(theta)``, with friction ``b`` and a torque ``T``.  Lagrange:
  ``L = (J1 + J2 r^2 cos^2 theta) w^2 / 2``, so ``J_eff(theta) w' =
  T - b w + J2 r^2 sin(theta) cos(theta) w^2``;
* two nonlinear springs on one node, ``e = 2 q1 + q1^3`` and ``e = q2 +
  tanh(q2)`` (no closed-form inverse: ``q2`` is an algebraic unknown), a
  damper ``b`` and a flow source ``F``: ``F = q1' + q2' + e/b`` with ``q2' =
  e'(q1) q1' / (1 + sech^2 q2)``; ``q2`` by :func:`scipy.optimize.brentq`;
  equilibrium ``e = b F`` and the hand linearization ``A = -(e'/b) / (1 +
  e'/(1 + sech^2 q2))``, ``B = 1 / (1 + e'/(1 + sech^2 q2))``;
* a compliance ``c`` fed through an MTF whose ratio ``N = 2 + cos(q_c)``
  follows its own displacement, from a node held by the compliance ``k``
  and fed by a flow source ``J``: ``q_c N(q_c) = (c/k) q_k`` (brentq), and
  ``q_k' = J - q_c'/N``, ``(N^2 - (c/k) q_k sin q_c) q_c' = (c/k) N q_k'``
  (the constraint differentiated by hand), a 2 x 2 linear solve;
* an inertia ``J2`` behind an MTF whose ratio ``1 + tanh(i)/2`` follows the
  current ``i`` of a nonlinear loop (a capacitor discharging through a
  resistor in series with ``e = a f + beta tanh(f)``): ``i`` by brentq, its
  rate by differentiating the loop equation by hand, and ``(J1 + J2 n^2)
  w1' = T - b w1 - J2 n n' w1``;
* a storage element whose stored quantity depends on the *rate* of another
  in derivative causality stays refused, naming both.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import bondgraph as bg


# ----------------------------------------------------------------------------- crank
CRANK = {"J1": 0.5, "J2": 2.0, "r": 0.3, "b": 0.1}


def crank() -> bg.Model:
    r = sympy.Symbol("r", positive=True)
    g = bg.BondGraph("crank")
    g.add(bg.Se("T"), bg.One("w1"), bg.I("J1"), bg.R("b"),
          bg.MTF("M", r * sympy.cos(bg.displacement("J1"))), bg.One("w2"), bg.I("J2"))
    for t, h in [("T", "w1"), ("w1", "J1"), ("w1", "b"), ("w1", "M"), ("M", "w2"), ("w2", "J2")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"w2": bg.flow("J2")})


def test_crank_against_lagrange():
    model = crank()
    assert set(model.state_names) == {"p_J1", "x_J1"} and not model.algebraic
    J1, J2, r, b = (CRANK[k] for k in ("J1", "J2", "r", "b"))

    def torque(t):
        return 0.4 + 0.3 * math.sin(2 * t)

    def hand(t, y):
        th, w = y
        Jeff = J1 + J2 * r**2 * math.cos(th)**2
        return [w, (torque(t) - b * w + J2 * r**2 * math.sin(th) * math.cos(th) * w**2) / Jeff]
    t_eval = np.linspace(0.0, 4.0, 21)
    ref = solve_ivp(hand, (0.0, 4.0), [0.3, 1.5], t_eval=t_eval, rtol=1e-11, atol=1e-13)
    res = bg.simulate(model, CRANK, (0.0, 4.0), {"x_J1": 0.3, "p_J1": J1 * 1.5},
                      u=lambda t: [torque(t)], t_eval=t_eval, rtol=1e-11, atol=1e-13)
    assert np.allclose(res["x_J1"], ref.y[0], rtol=1e-7, atol=1e-9)
    assert np.allclose(res["p_J1"] / J1, ref.y[1], rtol=1e-7, atol=1e-9)
    assert np.allclose(res["w2"], r * np.cos(ref.y[0]) * ref.y[1], rtol=1e-7, atol=1e-9)


# ----------------------------------------------------------------------------- springs
SPRINGS = {"b": 0.8}


def springs() -> bg.Model:
    g = bg.BondGraph("springs")
    g.add(bg.Sf("F"), bg.Zero("n"), bg.C("k1", law=2 * bg.q + bg.q**3),
          bg.C("k2", law=bg.q + sympy.tanh(bg.q)), bg.R("b"))
    for t, h in [("F", "n"), ("n", "k1"), ("n", "k2"), ("n", "b")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"f2": bg.flow("k2"), "e": bg.effort("n")})


def q2_of(e: float) -> float:
    return brentq(lambda q: q + math.tanh(q) - e, -abs(e) - 1, abs(e) + 1, xtol=1e-15)


def springs_hand(q1: float, F: float, b: float) -> tuple[float, float]:
    """(q1', q2') by hand."""
    e, de = 2 * q1 + q1**3, 2 + 3 * q1**2
    sech2 = 1 - math.tanh(q2_of(e))**2
    q1dot = (F - e / b) / (1 + de / (1 + sech2))
    return q1dot, de * q1dot / (1 + sech2)


def test_springs_kept_implicit_and_named():
    model = springs()
    assert model.state_names == ("q_k1",) and model.algebraic_names == ("q_k2",)
    assert "C:k2" in model.algebraic_origin[0] and "derivative causality" in \
        model.algebraic_origin[0]


def test_springs_simulation_against_hand_ode():
    model = springs()
    b = SPRINGS["b"]

    def force(t):
        return 1.0 + 0.5 * math.sin(3 * t)
    t_eval = np.linspace(0.0, 3.0, 16)
    ref = solve_ivp(lambda t, y: [springs_hand(y[0], force(t), b)[0]], (0.0, 3.0), [-0.4],
                    t_eval=t_eval, rtol=1e-11, atol=1e-13)
    res = bg.simulate(model, SPRINGS, (0.0, 3.0), {"q_k1": -0.4}, u=lambda t: [force(t)],
                      t_eval=t_eval, rtol=1e-11, atol=1e-13)
    assert np.allclose(res["q_k1"], ref.y[0], rtol=1e-7, atol=1e-9)
    hand = [springs_hand(q, force(t), b) for q, t in zip(ref.y[0], t_eval)]
    assert np.allclose(res["f2"], [h[1] for h in hand], rtol=1e-6, atol=1e-8)
    assert np.allclose(res["e"], 2 * ref.y[0] + ref.y[0]**3, rtol=1e-7, atol=1e-9)


def test_springs_equilibrium_and_linearization_by_hand():
    model = springs()
    b, F = SPRINGS["b"], 1.5
    eq = model.equilibrium(SPRINGS, {"F": F}, tol=1e-12)
    # 2 q1 + q1^3 = b F: the real root of the cubic
    q1 = float(next(v.real for v in np.roots([1, 0, 2, -b * F]) if abs(v.imag) < 1e-12))
    assert eq.states["q_k1"] == pytest.approx(q1, rel=1e-10)
    assert eq.algebraic["q_k2"] == pytest.approx(q2_of(b * F), rel=1e-10)
    de, sech2 = 2 + 3 * q1**2, 1 - math.tanh(q2_of(b * F))**2
    plant = model.linearize(eq)
    assert plant.A[0, 0] == pytest.approx(-(de / b) / (1 + de / (1 + sech2)), rel=1e-8)
    assert plant.B[0, 0] == pytest.approx(1 / (1 + de / (1 + sech2)), rel=1e-8)
    assert eq.stability == "stable"


def test_springs_python_code_and_fmu_agree_with_simulate(tmp_path):
    from bondgraph.codegen import generate_python

    model = springs()
    ns: dict = {}
    exec(generate_python(model), ns)
    p = [SPRINGS["b"]]
    for q1, F in [(-0.4, 1.0), (0.7, -0.3), (1.2, 2.0)]:
        q1dot, q2dot = springs_hand(q1, F, SPRINGS["b"])
        assert ns["derivatives"](0.0, [q1], [F], p)[0] == pytest.approx(q1dot, rel=1e-10)
        assert ns["outputs"](0.0, [q1], [F], p)[0] == pytest.approx(q2dot, rel=1e-10)
    fmpy = pytest.importorskip("fmpy")
    import shutil

    if (shutil.which("cc") or shutil.which("gcc")) is None:
        pytest.skip("no C compiler")
    from bondgraph.fmu import export_fmu

    path = export_fmu(model, tmp_path / "springs.fmu", fmi=2, values=SPRINGS)
    out = fmpy.simulate_fmu(str(path), fmi_type="ModelExchange", stop_time=1.0,
                            output_interval=0.1, start_values={"F": 1.0, "q_k1": -0.4},
                            relative_tolerance=1e-10)
    ref = solve_ivp(lambda t, y: [springs_hand(y[0], 1.0, SPRINGS["b"])[0]], (0.0, 1.0),
                    [-0.4], t_eval=out["time"], rtol=1e-11, atol=1e-13)
    assert np.allclose(out["e"], 2 * ref.y[0] + ref.y[0]**3, rtol=1e-6, atol=1e-8)
    f2 = [springs_hand(q, 1.0, SPRINGS["b"])[1] for q in ref.y[0]]
    assert np.allclose(out["f2"], f2, rtol=1e-6, atol=1e-8)


# ----------------------------------------------------------------------------- self-modulated
SELF = {"c": 0.7, "k": 0.4}


def selfmod() -> bg.Model:
    g = bg.BondGraph("selfmod")
    g.add(bg.Sf("J"), bg.Zero("m"), bg.C("k"), bg.Zero("n"), bg.C("c"),
          bg.MTF("M", 2 + sympy.cos(bg.displacement("c"))))
    for t, h in [("J", "m"), ("m", "k"), ("m", "M"), ("M", "n"), ("n", "c")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"qc": bg.displacement("c"), "fc": bg.flow("c")})


def selfmod_hand(qk: float, J: float) -> tuple[float, float, float]:
    """(q_k', q_c, q_c') by hand."""
    a = SELF["c"] / SELF["k"]
    qc = brentq(lambda q: q * (2 + math.cos(q)) - a * qk, -abs(a * qk) - 1, abs(a * qk) + 1,
                xtol=1e-15)
    N = 2 + math.cos(qc)
    # unknowns (q_k', q_c'): q_k' + q_c'/N = J;  -(c/k) N q_k' + (N^2 - a q_k sin q_c) q_c' = 0
    M = np.array([[1.0, 1.0 / N], [-a * N, N**2 - a * qk * math.sin(qc)]])
    qkdot, qcdot = np.linalg.solve(M, [J, 0.0])
    return qkdot, qc, qcdot


def test_self_modulated_compliance_against_hand_ode():
    model = selfmod()
    assert model.state_names == ("q_k",) and model.algebraic_names == ("q_c",)
    t_eval = np.linspace(0.0, 2.0, 11)

    def source(t):
        return 0.8 * math.cos(2 * t)
    ref = solve_ivp(lambda t, y: [selfmod_hand(y[0], source(t))[0]], (0.0, 2.0), [0.5],
                    t_eval=t_eval, rtol=1e-11, atol=1e-13)
    res = bg.simulate(model, SELF, (0.0, 2.0), {"q_k": 0.5}, u=lambda t: [source(t)],
                      t_eval=t_eval, rtol=1e-11, atol=1e-13)
    assert np.allclose(res["q_k"], ref.y[0], rtol=1e-7, atol=1e-9)
    hand = [selfmod_hand(q, source(t)) for q, t in zip(ref.y[0], t_eval)]
    assert np.allclose(res["qc"], [h[1] for h in hand], rtol=1e-7, atol=1e-9)
    assert np.allclose(res["fc"], [h[2] for h in hand], rtol=1e-6, atol=1e-8)


# ----------------------------------------------------------------------------- loop
LOOP = {"Cc": 0.5, "R1": 1.0, "a": 0.3, "beta": 0.8, "J1": 1.0, "b": 0.2, "J2": 2.0}


def loop_gear() -> bg.Model:
    """A capacitor discharging through ``R1`` in series with ``e = a f + beta tanh(f)`` (a
    nonlinear loop: the current ``i`` is an algebraic unknown) sets the ratio ``n = 1 +
    tanh(i)/2`` of an MTF between the driven inertia ``J1`` and ``J2``."""
    a, beta = sympy.symbols("a beta", positive=True)
    g = bg.BondGraph("loop_gear")
    g.add(bg.C("Cc"), bg.Zero("n"), bg.One("s"), bg.R("R1"),
          bg.R("D", law=a * bg.f + beta * sympy.tanh(bg.f)), bg.Se("T"), bg.One("w1"),
          bg.I("J1"), bg.R("b"), bg.MTF("M", 1 + sympy.tanh(bg.flow("D")) / 2), bg.One("w2"),
          bg.I("J2"))
    for t, h in [("n", "Cc"), ("n", "s"), ("s", "R1"), ("s", "D"), ("T", "w1"), ("w1", "J1"),
                 ("w1", "b"), ("w1", "M"), ("M", "w2"), ("w2", "J2")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"w2": bg.flow("J2")})


def test_inertia_through_a_nonlinear_loop_against_hand_ode():
    """By hand: ``q/Cc = (R1 + a) i + beta tanh(i)`` (brentq), ``q' = -i``, so ``i' = -i /
    (Cc (R1 + a + beta sech^2 i))``; ``p2 = J2 n w1`` and ``J1 w1' = T - b w1 - n p2'`` give
    ``(J1 + J2 n^2) w1' = T - b w1 - J2 n n' w1`` with ``n' = sech^2(i) i' / 2``."""
    model = loop_gear()
    assert model.state_names == ("q_Cc", "p_J1") and model.algebraic_names == ("f_D",)
    v = LOOP

    def current(q):
        return brentq(lambda i: (v["R1"] + v["a"]) * i + v["beta"] * math.tanh(i) - q / v["Cc"],
                      -50.0, 50.0, xtol=1e-15)

    def hand(t, y):
        q, w = y
        i = current(q)
        sech2 = 1 - math.tanh(i)**2
        di = -i / (v["Cc"] * (v["R1"] + v["a"] + v["beta"] * sech2))
        n, dn = 1 + math.tanh(i) / 2, sech2 * di / 2
        return [-i, (1.0 - v["b"] * w - v["J2"] * n * dn * w) / (v["J1"] + v["J2"] * n**2)]
    t_eval = np.linspace(0.0, 3.0, 13)
    ref = solve_ivp(hand, (0.0, 3.0), [1.0, 0.5], t_eval=t_eval, rtol=1e-11, atol=1e-13)
    res = bg.simulate(model, LOOP, (0.0, 3.0), {"q_Cc": 1.0, "p_J1": 0.5 * v["J1"]},
                      u=lambda t: [1.0], t_eval=t_eval, rtol=1e-11, atol=1e-13)
    assert np.allclose(res["q_Cc"], ref.y[0], rtol=1e-8, atol=1e-10)
    assert np.allclose(res["p_J1"] / v["J1"], ref.y[1], rtol=1e-8, atol=1e-10)
    n = [1 + math.tanh(current(q)) / 2 for q in ref.y[0]]
    assert np.allclose(res["w2"], np.array(n) * ref.y[1], rtol=1e-8, atol=1e-10)


# ----------------------------------------------------------------------------- refused
def test_stored_quantity_depending_on_another_rate_is_refused_naming_both():
    """A source across the compliance ``a`` that follows the effort of the inertia ``m``
    (itself in derivative causality under a flow source): ``q_a = C k e_m = C k m F'``
    would need a second derivative."""
    k = sympy.Symbol("kk")
    g = bg.BondGraph("chain")
    g.add(bg.Sf("F"), bg.One("s"), bg.I("m"), bg.R("r"),
          bg.Se("M", value=k * bg.effort("m")), bg.Zero("n"), bg.C("a"), bg.R("r2"))
    for t, h in [("F", "s"), ("s", "m"), ("s", "r"), ("M", "n"), ("n", "a"), ("n", "r2")]:
        g.connect(t, h)
    with pytest.raises(bg.AlgebraicLoopError, match=r"C:a .*rate of the storage element\(s\) m,"):
        bg.derive(g)
