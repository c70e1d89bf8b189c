"""Numeric plants, batches and simulation against hand derivations.

DC motor (Kirchhoff and Newton): La i' = V - Ra i - K w, J w' = K i - b w, with
states p_La = La i and p_J = J w, so A = [[-Ra/La, -K/J], [K/La, -b/J]],
B = [[1], [0]], omega = p_J/J, i = p_La/La.  With Ra=2, La=0.5, K=0.1,
J=0.02, b=0.2: A = [[-4, -5], [0.2, -10]], trace -14, determinant 41, poles
-7 +- 2 sqrt(2), omega/V = K / ((La s + Ra)(J s + b) + K^2).
"""

import math

import control
import numpy as np
import pytest
import scipy.linalg
import scipy.signal
import sympy
from scipy.integrate import solve_ivp

import bondgraph as bg
from bondgraph.numeric import (BatchStateSpace, NumericDynamics, NumericError, NumericStateSpace,
                               ParameterValueError, SimulationError, compile_dynamics, compile_plant,
                               numeric_plant, simulate, to_nonlinear_iosys)

VALUES = {"Ra": 2.0, "La": 0.5, "K": 0.1, "J": 0.02, "b": 0.2}


def dc_motor_model():
    g = bg.BondGraph("dc_motor")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
    for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
        g.connect(tail, head)
    return bg.derive(g, outputs={"omega": bg.flow("J"), "i": bg.flow("La")})


def duffing_model(with_damper=True):
    k, k3 = sympy.symbols("k k3", positive=True)
    g = bg.BondGraph("duffing")
    F, v = bg.Se("F"), bg.One("v")
    g.add(F, v, bg.I("m"), bg.C("s", law=k * bg.q + k3 * bg.q**3))
    pairs = [(F, v), (v, "m"), (v, "s")]
    if with_damper:
        g.add(bg.R("b"))
        pairs.append((v, "b"))
    for tail, head in pairs:
        g.connect(tail, head)
    return bg.derive(g, outputs={"x": bg.displacement("s"), "v": bg.flow("m")})


def servo_model():
    motor = bg.BondGraph("motor")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    motor.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.Port("shaft"))
    for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "shaft")]:
        motor.connect(tail, head)
    top = bg.BondGraph("servo")
    load = bg.One("load")
    top.add(motor, load, bg.I("J"), bg.R("b"))
    for tail, head in [("motor.shaft", load), (load, "J"), (load, "b")]:
        top.connect(tail, head)
    return bg.derive(top, outputs={"omega": bg.flow("J")})


def hand_abcd(Ra, La, K, J, b):
    A = np.array([[-Ra / La, -K / J], [K / La, -b / J]])
    B = np.array([[1.0], [0.0]])
    C = np.array([[0.0, 1 / J], [1 / La, 0.0]])
    return A, B, C, np.zeros((2, 1))


def hand_tf(s, Ra, La, K, J, b):
    den = (La * s + Ra) * (J * s + b) + K**2
    return K / den, (J * s + b) / den


@pytest.fixture(scope="module")
def motor():
    return dc_motor_model()


@pytest.fixture(scope="module")
def motor_plant(motor):
    return compile_plant(motor)


# ----------------------------------------------------------------------------- one plant
def test_plant_matches_hand_derivation(motor_plant):
    ss = motor_plant.plant(VALUES)
    A, B, C, D = hand_abcd(**VALUES)
    for got, want in zip((ss.A, ss.B, ss.C, ss.D), (A, B, C, D)):
        np.testing.assert_allclose(got, want, rtol=1e-14, atol=0)
    assert ss.A.tolist() == [[-4.0, -5.0], [0.2, -10.0]]
    assert (ss.state_names, ss.input_names, ss.output_names) == (("p_La", "p_J"), ("V",), ("omega", "i"))
    assert dict(ss.parameters) == VALUES and ss.name == "dc_motor"
    with pytest.raises(ValueError):
        ss.A[0, 0] = 1.0
    with pytest.raises(AttributeError):
        ss.A = np.eye(2)


def test_keys_may_be_symbols_or_names(motor, motor_plant):
    sym = {p.name: p for p in motor.parameters}
    mixed = {sym["Ra"]: 2.0, "La": 0.5, sym["K"]: 0.1, "J": 0.02, "b": np.float64(0.2)}
    np.testing.assert_array_equal(motor_plant.plant(mixed).A, motor_plant.plant(VALUES).A)
    assert np.array_equal(numeric_plant(motor, VALUES).B, [[1.0], [0.0]])


def test_eigenvalues_closed_form(motor_plant):
    ev = motor_plant.plant(VALUES).eigenvalues()
    expected = np.array([-7 - 2 * math.sqrt(2), -7 + 2 * math.sqrt(2)])
    np.testing.assert_allclose(ev, expected, rtol=1e-13)


def test_frequency_response_closed_form(motor_plant):
    w = np.array([0.0, 0.3, 1.0, 7.0, 100.0])
    H = motor_plant.plant(VALUES).frequency_response(w)
    assert H.shape == (5, 2, 1)
    g_omega, g_i = hand_tf(1j * w, **VALUES)
    np.testing.assert_allclose(H[:, 0, 0], g_omega, rtol=1e-12)
    np.testing.assert_allclose(H[:, 1, 0], g_i, rtol=1e-12)


def test_frequency_response_at_a_pole_is_nan():
    ss = NumericStateSpace([[0.0, 1.0], [-4.0, 0.0]], [[0.0], [1.0]], [[1.0, 0.0]], [[0.0]],
                           ("x", "v"), ("F",), ("x",))
    H = ss.frequency_response([1.0, 2.0])          # poles at +-2j
    assert abs(H[0, 0, 0] - 1 / 3) < 1e-14 and np.isnan(H[1, 0, 0])


def test_to_control_keeps_names_and_matches_closed_form(motor_plant):
    sys = motor_plant.plant(VALUES).to_control()
    assert isinstance(sys, control.StateSpace)
    assert sys.state_labels == ["p_La", "p_J"] and sys.input_labels == ["V"]
    assert sys.output_labels == ["omega", "i"] and sys.name == "dc_motor"
    w = np.array([0.5, 5.0])
    g_omega, _ = hand_tf(1j * w, **VALUES)
    np.testing.assert_allclose(sys(1j * w)[0, 0], g_omega, rtol=1e-12)
    assert sys.dcgain()[0, 0] == pytest.approx(0.1 / (2.0 * 0.2 + 0.1**2), rel=1e-12)


def test_to_tf_coefficients(motor_plant):
    G = motor_plant.plant(VALUES).to_tf(input="V", output="omega")
    # K/(La J) / (s^2 + (Ra/La + b/J) s + (Ra b + K^2)/(La J)) = 10 / (s^2 + 14 s + 41)
    num = np.trim_zeros(np.asarray(G.num[0][0], float).round(10), "f")
    np.testing.assert_allclose(num, [10.0], rtol=1e-10)
    np.testing.assert_allclose(G.den[0][0], [1.0, 14.0, 41.0], rtol=1e-10)
    assert G.input_labels == ["V"] and G.output_labels == ["omega"]
    full = motor_plant.plant(VALUES).to_tf()
    assert full.output_labels == ["omega", "i"]
    with pytest.raises(NumericError, match="valid|outputs are omega, i"):
        motor_plant.plant(VALUES).to_tf(output="theta")


@pytest.mark.filterwarnings("ignore::scipy.signal.BadCoefficients")   # freqresp's own tf conversion
def test_to_scipy(motor_plant):
    sys = motor_plant.plant(VALUES).to_scipy()
    assert isinstance(sys, scipy.signal.StateSpace)
    w, H = scipy.signal.freqresp(scipy.signal.StateSpace(sys.A, sys.B, sys.C[:1], sys.D[:1]), w=[2.0])
    np.testing.assert_allclose(H, hand_tf(2j, **VALUES)[0], rtol=1e-12)


def test_hierarchical_names_get_control_labels():
    plant = compile_plant(servo_model())
    assert plant.parameter_names == ("J", "b", "motor.K", "motor.La", "motor.Ra")
    ss = plant.plant({"J": 0.02, "b": 0.2, "motor.K": 0.1, "motor.La": 0.5, "motor.Ra": 2.0})
    assert ss.input_names == ("motor.V",)
    sys = ss.to_control()
    assert sys.input_labels == ["motor_V"] and sys.state_labels == ["p_J", "p_motor_La"]
    # the same motor: same poles as the flat model
    np.testing.assert_allclose(ss.eigenvalues(), [-7 - 2 * math.sqrt(2), -7 + 2 * math.sqrt(2)], rtol=1e-13)


# ----------------------------------------------------------------------------- bad values
def test_missing_and_unknown_reported_together(motor_plant):
    with pytest.raises(ParameterValueError) as info:
        motor_plant.plant({"Ra": 2.0, "La": 0.5, "K": 0.1, "Jm": 1.0, "bb": 2.0})
    msg = str(info.value)
    assert "missing J, b" in msg and "Valid names: J, K, La, Ra, b" in msg
    assert "unknown parameter 'Jm' (did you mean 'J'?)" in msg and "unknown parameter 'bb' (did you mean 'b'?)" in msg
    assert info.value.missing == ("J", "b") and info.value.unknown == ("Jm", "bb")
    assert isinstance(info.value, ValueError) and isinstance(info.value, bg.BondGraphError)


@pytest.mark.parametrize("bad, words", [
    (float("nan"), "must be a finite real number; got nan"),
    (float("inf"), "must be a finite real number; got inf"), (1 + 2j, "complex"),
    ("0.5", "got str"), (True, "bool"), (None, "got NoneType")],
    ids=["nan", "inf", "complex", "str", "bool", "None"])
def test_bad_value_names_the_parameter(motor_plant, bad, words):
    with pytest.raises(ParameterValueError, match=f"parameter 'La'.*{words}"):
        motor_plant.plant({**VALUES, "La": bad})


def test_zero_inertance_gives_a_clear_error(motor_plant):
    with pytest.raises(ParameterValueError, match=r"I:La: its mass \(inertance\) La = 0 must be positive"):
        motor_plant.plant({**VALUES, "La": 0.0})


def test_nonlinear_model_has_no_plant():
    with pytest.raises(bg.NonlinearModelError):
        compile_plant(duffing_model())


# ----------------------------------------------------------------------------- compile once
def test_compiled_once_and_never_substituted(motor, monkeypatch):
    calls = []
    real = sympy.lambdify

    def counting(*args, **kwargs):
        calls.append(kwargs.get("cse"))
        return real(*args, **kwargs)

    monkeypatch.setattr(sympy, "lambdify", counting)
    plant = compile_plant(motor)
    assert calls in ([], [True])      # monomial entries are not lambdified at all
    before = list(calls)

    def forbidden(*args, **kwargs):
        raise AssertionError("sympy must not be used while evaluating a compiled plant")

    monkeypatch.setattr(sympy.Basic, "subs", forbidden)
    monkeypatch.setattr(sympy.Basic, "xreplace", forbidden)
    monkeypatch.setattr(sympy.Expr, "evalf", forbidden)
    plant.plant(VALUES)
    plant.batch({k: [v, 2 * v] for k, v in VALUES.items()})
    assert calls == before


# ----------------------------------------------------------------------------- batches
def random_sets(P, seed=1):
    rng = np.random.default_rng(seed)
    return {name: rng.uniform(0.5, 2.0, P) * base for name, base in VALUES.items()}


def test_batch_matrices_and_eigenvalues(motor_plant):
    sets = random_sets(200)
    batch = motor_plant.batch(sets)
    assert isinstance(batch, BatchStateSpace) and len(batch) == 200
    assert batch.A.shape == (200, 2, 2) and batch.B.shape == (200, 2, 1)
    assert batch.C.shape == (200, 2, 2) and batch.D.shape == (200, 2, 1)
    Ra, La, K, J, b = (sets[n] for n in ("Ra", "La", "K", "J", "b"))
    np.testing.assert_allclose(batch.A[:, 0, 0], -Ra / La, rtol=1e-14)
    np.testing.assert_allclose(batch.A[:, 0, 1], -K / J, rtol=1e-14)
    np.testing.assert_allclose(batch.A[:, 1, 0], K / La, rtol=1e-14)
    np.testing.assert_allclose(batch.A[:, 1, 1], -b / J, rtol=1e-14)
    np.testing.assert_array_equal(batch.B[:, :, 0], np.tile([1.0, 0.0], (200, 1)))
    # closed form: roots of s^2 - tr s + det
    tr = -Ra / La - b / J
    det = (Ra * b + K**2) / (La * J)
    disc = np.sqrt((tr**2 - 4 * det).astype(complex))
    expected = np.sort(np.stack([(tr - disc) / 2, (tr + disc) / 2], axis=1), axis=1)
    np.testing.assert_allclose(batch.eigenvalues(), expected, rtol=1e-10, atol=1e-12)
    assert not batch.A.flags.writeable and not batch.parameter_values.flags.writeable


def test_batch_frequency_response_closed_form(motor_plant):
    sets = random_sets(50, seed=2)
    w = np.logspace(-1, 2, 7)
    H = motor_plant.batch(sets).frequency_response(w)
    assert H.shape == (50, 7, 2, 1)
    args = [sets[n][:, None] for n in ("Ra", "La", "K", "J", "b")]
    g_omega, g_i = hand_tf(1j * w[None, :], *args)
    np.testing.assert_allclose(H[..., 0, 0], g_omega, rtol=1e-11)
    np.testing.assert_allclose(H[..., 1, 0], g_i, rtol=1e-11)


def test_batch_item_equals_single_plant_and_array_input(motor_plant):
    sets = random_sets(5, seed=3)
    batch = motor_plant.batch(sets)
    one = motor_plant.plant({k: v[3] for k, v in sets.items()})
    np.testing.assert_array_equal(batch[3].A, one.A)
    assert dict(batch[3].parameters) == dict(one.parameters)
    arr = np.column_stack([sets[n] for n in motor_plant.parameter_names])
    np.testing.assert_array_equal(motor_plant.batch(arr).A, batch.A)
    # scalars are shared by every set
    shared = motor_plant.batch({**VALUES, "Ra": [1.0, 2.0, 3.0]})
    np.testing.assert_allclose(shared.A[:, 0, 0], [-2.0, -4.0, -6.0])


def test_batch_errors(motor_plant):
    with pytest.raises(ParameterValueError, match="same length"):
        motor_plant.batch({**VALUES, "Ra": [1.0, 2.0], "La": [1.0, 2.0, 3.0]})
    with pytest.raises(ParameterValueError, match="parameter 'J' must be finite; set 2"):
        motor_plant.batch({**VALUES, "J": [0.1, 0.2, np.nan]})
    with pytest.raises(ParameterValueError, match="missing b"):
        motor_plant.batch({k: v for k, v in VALUES.items() if k != "b"})
    with pytest.raises(ParameterValueError, match=r"shape \(P, 5\)"):
        motor_plant.batch(np.ones((4, 3)))
    with pytest.raises(ParameterValueError, match="La = 0 in parameter set 1 must be positive"):
        motor_plant.batch({**VALUES, "La": [0.5, 0.0]})


# ----------------------------------------------------------------------------- simulation
def test_step_response_matches_matrix_exponential(motor):
    t = np.linspace(0.0, 1.0, 11)
    res = simulate(motor, VALUES, (0.0, 1.0), u=[12.0], t_eval=t, rtol=1e-10, atol=1e-12)
    A, B, C, _ = hand_abcd(**VALUES)
    # x(t) = A^-1 (e^{At} - I) B u for x(0) = 0
    x = np.array([np.linalg.solve(A, (scipy.linalg.expm(A * ti) - np.eye(2)) @ B[:, 0] * 12.0) for ti in t])
    np.testing.assert_allclose(res.x, x, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(res["omega"], x @ C[0], rtol=1e-7, atol=1e-8)
    np.testing.assert_allclose(res.u, 12.0)
    assert res.y.shape == (11, 2) and res.output_names == ("omega", "i")


def test_nonlinear_spring_conserves_energy():
    model = duffing_model(with_damper=False)
    m, k, k3 = 1.3, 2.0, 0.7
    res = simulate(model, {"m": m, "k": k, "k3": k3}, (0.0, 10.0), x0={"q_s": 1.5},
                   t_eval=np.linspace(0, 10, 50), method="DOP853", rtol=1e-11, atol=1e-12)
    p, q = res["p_m"], res["q_s"]
    energy = p**2 / (2 * m) + k * q**2 / 2 + k3 * q**4 / 4
    assert energy[0] == pytest.approx(k * 1.5**2 / 2 + k3 * 1.5**4 / 4, rel=1e-12)
    np.testing.assert_allclose(energy, energy[0], rtol=1e-8)
    assert np.ptp(q) > 2.5             # it does oscillate


def test_sampled_and_callable_inputs():
    g = bg.BondGraph("mass")
    g.add(bg.Se("F"), bg.I("m"))
    g.connect("F", "m")
    model = bg.derive(g, outputs={"v": bg.flow("m")})
    dyn = compile_dynamics(model)
    # F = t (a ramp): p(t) = t^2 / 2, v = p/m
    ramp = (np.array([0.0, 1.0, 2.0]), np.array([0.0, 1.0, 2.0]))
    a = simulate(dyn, {"m": 2.0}, (0.0, 2.0), u=ramp, t_eval=[2.0], rtol=1e-10, atol=1e-12)
    b = simulate(dyn, {"m": 2.0}, (0.0, 2.0), u=lambda t: [t], t_eval=[2.0], rtol=1e-10, atol=1e-12)
    assert a["p_m"][-1] == pytest.approx(2.0, rel=1e-9) and b["v"][-1] == pytest.approx(1.0, rel=1e-9)
    # beyond the samples the last value is held
    c = simulate(dyn, {"m": 1.0}, (0.0, 3.0), u=ramp, t_eval=[3.0], rtol=1e-10, atol=1e-12)
    assert c["p_m"][-1] == pytest.approx(2.0 + 2.0, rel=1e-8)


def test_time_varying_model_matches_hand_rhs():
    g = bg.BondGraph("lever")
    F, v, w = bg.Se("F"), bg.One("v"), bg.One("w")
    g.add(F, v, w, bg.I("m"), bg.MTF("lever", modulus=sympy.cos(bg.t)), bg.R("b"))
    for tail, head in [(F, v), (v, "m"), (v, "lever"), ("lever", w), (w, "b")]:
        g.connect(tail, head)
    model = bg.derive(g, outputs={"v": bg.flow("m")})
    m, b = 2.0, 3.0
    t_eval = np.linspace(0, 4, 9)
    res = simulate(model, {"m": m, "b": b}, (0, 4), [1.0], u=[0.5], t_eval=t_eval, rtol=1e-10, atol=1e-12)
    ref = solve_ivp(lambda t, p: [0.5 - b * np.cos(t) ** 2 * p[0] / m], (0, 4), [1.0], t_eval=t_eval,
                    rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res["p_m"], ref.y[0], rtol=1e-7)


def test_simulation_argument_errors(motor):
    with pytest.raises(NumericError, match=r"x0 must have shape \(2,\)"):
        simulate(motor, VALUES, (0, 1), [1.0, 2.0, 3.0])
    with pytest.raises(NumericError, match="unknown states nope"):
        simulate(motor, VALUES, (0, 1), {"nope": 1.0})
    with pytest.raises(NumericError, match=r"u\(t\) must have shape \(1,\)"):
        simulate(motor, VALUES, (0, 1), u=lambda t: [1.0, 2.0])
    with pytest.raises(NumericError, match="strictly increasing"):
        simulate(motor, VALUES, (0, 1), u=(np.array([0.0, 0.0]), np.array([1.0, 2.0])))
    with pytest.raises(ParameterValueError, match="missing"):
        simulate(motor, {"Ra": 1.0}, (0, 1))
    g = bg.BondGraph("push")
    g.add(bg.Sf("v"), bg.I("m"))
    g.connect("v", "m")
    with pytest.raises(NumericError, match="time derivatives of inputs"):
        NumericDynamics(bg.derive(g, outputs={"F": bg.effort("m")}))


def test_solver_failure_is_reported():
    model = duffing_model(with_damper=False)
    with pytest.raises(SimulationError, match="solver failed"):
        # negative stiffness and a huge start: the state escapes to infinity in finite time
        simulate(model, {"m": 1.0, "k": 1.0, "k3": -1.0}, (0.0, 100.0), [0.0, 1e3], method="RK45",
                 rtol=1e-6, atol=1e-9)


# ----------------------------------------------------------------------------- python-control
def test_nonlinear_iosys_linearization_matches_hand_jacobian():
    model = duffing_model()
    m, b, k, k3, q0 = 1.5, 0.3, 2.0, 0.5, 0.8
    sys = to_nonlinear_iosys(model, {"m": m, "b": b, "k": k, "k3": k3})
    assert isinstance(sys, control.NonlinearIOSystem)
    assert sys.state_labels == ["p_m", "q_s"] and sys.output_labels == ["x", "v"]
    # equilibrium p = 0, q = q0 with F = k q0 + k3 q0^3
    lin = control.linearize(sys, [0.0, q0], [k * q0 + k3 * q0**3])
    expected = np.array([[-b / m, -(k + 3 * k3 * q0**2)], [1 / m, 0.0]])
    np.testing.assert_allclose(lin.A, expected, rtol=1e-5, atol=1e-7)
    np.testing.assert_allclose(lin.C, [[0.0, 1.0], [1 / m, 0.0]], atol=1e-7)


def test_nonlinear_iosys_response_matches_hand_written_duffing():
    model = duffing_model()
    m, b, k, k3 = 1.0, 0.4, 2.0, 0.5
    values = {"m": m, "b": b, "k": k, "k3": k3}
    t = np.linspace(0, 5, 26)
    resp = control.input_output_response(to_nonlinear_iosys(model, values), t, np.ones_like(t), [0.0, 0.2],
                                         solve_ivp_kwargs={"rtol": 1e-10, "atol": 1e-12})
    # hand-written Duffing with F = 1: m x'' = F - b x' - k x - k3 x^3, state (x, x'),
    # start p_m = m x' = 0, q_s = x = 0.2
    def rhs(_t, z):
        x, xd = z
        return [xd, (1.0 - b * xd - k * x - k3 * x**3) / m]

    ref = solve_ivp(rhs, (0, 5), [0.2, 0.0], t_eval=t, method="DOP853", rtol=1e-11, atol=1e-13)
    np.testing.assert_allclose(resp.outputs[0], ref.y[0], rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(resp.outputs[1], ref.y[1], rtol=1e-6, atol=1e-8)
