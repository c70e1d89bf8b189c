"""simulate and to_nonlinear_iosys refuse bad arguments and report failures promptly.

Issue 12: a NaN derivative (a law used outside its domain) or a NaN/inf in
``t_span`` made ``simulate`` loop forever inside scipy's step-size control,
scipy's own ``ValueError`` escaped raw, and a user's law callable that raised
was not named.  Each case here must raise a package error (``BondGraphError``
and ``ValueError``/``RuntimeError``) whose message names the culprit, within
a few seconds (:func:`deadline` turns a hang into a failure).

The models are small and solved by hand:

* mass ``m`` driven by ``F``, spring ``e = k q``, damper ``R:Rf``: states
  ``p_m``, ``q_k``; ``p_m' = F - e_Rf - k q_k``, ``q_k' = p_m / m``.
* with the damper law ``e = sqrt(f) - sqrt(|f|)`` (zero for ``f >= 0``, NaN
  in numpy for ``f < 0``) and no spring force (``k q_k`` starts at 0 and
  ``k`` is tiny), ``p_m' = F`` while ``p_m >= 0``: from ``p_m(0) = 2`` with
  ``F = -1`` the momentum is ``2 - t`` and turns negative after ``t = 2``.
* a free mass: ``p_m(t) = p0 + F t``, ``v = p_m / m``.
"""

from __future__ import annotations

import contextlib
import math
import re
import signal

import numpy as np
import pytest
import sympy
from sympy.utilities.lambdify import implemented_function

import bondgraph as bg
from bondgraph.numeric import (NumericDynamics, NumericError, ParameterValueError, SimulationError,
                               simulate, to_nonlinear_iosys)

MSD_VALUES = {"m": 1.0, "k": 4.0, "Rf": 0.5}
#: a run that takes longer than this (seconds) is a hang
LIMIT = 20


class Hang(Exception):
    pass


@contextlib.contextmanager
def deadline(seconds: float = LIMIT):
    """Fail (instead of hanging the test run) when the block takes longer than ``seconds``."""
    def alarm(signum, frame):
        raise Hang(f"no answer within {seconds} s")

    old = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def raises_promptly(exc_class, *words, call):
    """``call()`` raises ``exc_class`` within :data:`LIMIT`, its message holding every word."""
    with deadline(), pytest.raises(exc_class) as info:
        call()
    assert isinstance(info.value, bg.BondGraphError)
    for word in words:
        assert word in str(info.value), (word, str(info.value))
    return info.value


def msd_graph(damper: bg.R | None = None, outputs=None) -> bg.Model:
    g = bg.BondGraph("msd")
    F, v = bg.Se("F"), bg.One("v")
    g.add(F, v, bg.I("m"), bg.C("k", stiffness="k"), damper if damper is not None else bg.R("Rf"))
    for tail, head in [(F, v), (v, "m"), (v, "k"), (v, "Rf")]:
        g.connect(tail, head)
    return bg.derive(g, outputs=outputs or {"x": bg.displacement("k")})


@pytest.fixture(scope="module")
def msd():
    return NumericDynamics(msd_graph())


@pytest.fixture(scope="module")
def mass():
    g = bg.BondGraph("mass")
    g.add(bg.Se("F"), bg.I("m"))
    g.connect("F", "m")
    return NumericDynamics(bg.derive(g, outputs={"v": bg.flow("m")}))


def time_in(message: str) -> float:
    return float(re.search(r"at t = ([-+0-9.e]+)", message).group(1))


# ----------------------------------------------------------------------------- non-finite values
def test_nan_derivative_at_the_start_names_the_state():
    # log(f) with f = p_m/m = -1 at t = 0: dp_m/dt is NaN at once
    model = msd_graph(bg.R("Rf", law=sympy.log(bg.f)))
    err = raises_promptly(SimulationError, "p_m", "t = 0", "not finite", call=lambda: simulate(
        model, {"m": 1.0, "k": 4.0}, (0.0, 10.0), {"p_m": -1.0}, u=[0.0]))
    assert "also of" not in str(err)          # dq_k/dt = p_m/m = -1 is finite


@pytest.mark.parametrize("method", ["RK45", "LSODA", "BDF"])
def test_nan_derivative_later_names_the_state_and_time(method):
    # p_m = 2 - t (hand solution, see the module docstring): NaN only once p_m < 0, after t = 2
    model = msd_graph(bg.R("Rf", law=sympy.sqrt(bg.f) - sympy.sqrt(sympy.Abs(bg.f))))
    err = raises_promptly(SimulationError, "p_m", "not finite", call=lambda: simulate(
        model, {"m": 1.0, "k": 1e-12}, (0.0, 5.0), {"p_m": 2.0}, u=[-1.0], method=method,
        max_step=0.01))
    assert 2.0 < time_in(str(err)) <= 2.0 + 0.01 + 1e-9


def test_non_finite_output_names_the_output_and_time():
    # x = q_k = integral of p_m/m = 0.5 t for p_m = 0.5, m = 1 (no force: F = 0, k tiny);
    # log(x - 1) is NaN for t < 2 and finite after
    model = msd_graph(outputs={"x": bg.displacement("k"), "lx": sympy.log(bg.displacement("k") - 1)})
    err = raises_promptly(SimulationError, "output lx", "t = 0", call=lambda: simulate(
        model, {"m": 1.0, "k": 1e-12, "Rf": 1e-12}, (0.0, 3.0), {"p_m": 0.5}, t_eval=[0.0, 1.0, 3.0]))
    assert "first of 2" in str(err)


def test_blow_up_is_reported_with_the_state():
    # softening spring e = q - q^3 from q = 1e3: q escapes to infinity in finite time
    g = bg.BondGraph("soft")
    v = bg.One("v")
    g.add(v, bg.I("m"), bg.C("s", law=bg.q - bg.q**3))
    g.connect(v, "m")
    g.connect(v, "s")
    model = bg.derive(g)
    raises_promptly(SimulationError, "solver failed", call=lambda: simulate(
        model, {"m": 1.0}, (0.0, 100.0), [0.0, 1e3]))


def test_iosys_nan_derivative_is_reported_promptly():
    import control

    sys = to_nonlinear_iosys(msd_graph(bg.R("Rf", law=sympy.log(bg.f))), values={"m": 1.0, "k": 4.0})
    raises_promptly(SimulationError, "p_m", "t = 0", call=lambda: control.input_output_response(
        sys, [0.0, 1.0], [0.0, 0.0], [-1.0, 0.0]))


# ----------------------------------------------------------------------------- t_span
@pytest.mark.parametrize("t_span, words", [
    ((0.0, float("nan")), ("t_span", "not finite")),
    ((0.0, float("inf")), ("t_span", "not finite")),
    ((float("-inf"), 1.0), ("t_span", "not finite")),
    ((1.0, 0.0), ("t_span", "t0 < t1", "(1, 0)")),
    ((1.0, 1.0), ("t_span", "t0 < t1")),
    ((1.0,), ("t_span", "two finite numbers", "got 1 value")),
    ((0.0, 1.0, 2.0), ("t_span", "got 3 value")),
    (5.0, ("t_span", "two finite numbers")),
    (("0", "1"), ("t_span", "two finite numbers")),
    ((0.0, 1j), ("t_span", "two finite numbers")),
    (None, ("t_span",)),
], ids=["nan", "inf", "-inf", "decreasing", "empty", "one", "three", "scalar", "text", "complex", "None"])
def test_bad_t_span(msd, t_span, words):
    raises_promptly(NumericError, *words, call=lambda: simulate(msd, MSD_VALUES, t_span))


# ----------------------------------------------------------------------------- x0
@pytest.mark.parametrize("x0, words", [
    ([float("nan"), 0.0], ("x0", "state p_m is nan")),
    ([0.0, float("inf")], ("x0", "state q_k is inf")),
    ([1.0, 2.0, 3.0], ("x0", "shape (2,)", "p_m, q_k", "got shape (3,)")),
    ([1.0], ("x0", "shape (2,)")),
    ({"p_M": 1.0, "x": 0.0}, ("unknown states p_M, x", "the states are p_m, q_k")),
    ({"p_m": float("nan")}, ("x0", "p_m")),
    ({"q_k": "1"}, ("x0['q_k']", "a finite number")),
    (["a", "b"], ("x0", "2 finite number(s), one per state p_m, q_k")),
    ([1j, 0.0], ("x0",)),
], ids=["nan", "inf", "long", "short", "unknown-names", "nan-by-name", "text-by-name", "text", "complex"])
def test_bad_x0(msd, x0, words):
    raises_promptly(NumericError, *words, call=lambda: simulate(msd, MSD_VALUES, (0.0, 1.0), x0))


def test_x0_by_symbol_matches_x0_by_name(mass):
    # free mass: p_m(1) = p0 + F*1 = 1 + 3
    a = simulate(mass, {"m": 2.0}, (0.0, 1.0), {sympy.Symbol("p_m"): 1.0}, u=[3.0], t_eval=[1.0])
    assert a["p_m"][-1] == pytest.approx(4.0, rel=1e-9)


# ----------------------------------------------------------------------------- t_eval
@pytest.mark.parametrize("t_eval, words", [
    ([0.0, 0.5, 1.5], ("t_eval", "within t_span (0, 1)", "t_eval[2] = 1.5")),
    ([-0.1, 0.5], ("t_eval", "t_eval[0] = -0.1")),
    ([0.0, 0.6, 0.5], ("t_eval", "sorted", "t_eval[2] = 0.5 follows t_eval[1] = 0.6")),
    ([0.0, 0.5, 0.5], ("t_eval", "no repeats")),
    ([0.0, float("nan")], ("t_eval", "t_eval[1] is nan")),
    ([], ("t_eval", "shape (0,)")),
    ([[0.0, 1.0]], ("t_eval", "shape (1, 2)")),
    (["0.5"], ("t_eval",)),
], ids=["after", "before", "unsorted", "repeat", "nan", "empty", "2d", "text"])
def test_bad_t_eval(msd, t_eval, words):
    raises_promptly(NumericError, *words, call=lambda: simulate(msd, MSD_VALUES, (0.0, 1.0), t_eval=t_eval))


# ----------------------------------------------------------------------------- solver options
@pytest.mark.parametrize("options, words", [
    ({"method": "rk45"}, ("method", "RK45, RK23, DOP853, Radau, BDF, LSODA", "'rk45'", "did you mean 'RK45'")),
    ({"method": "Euler"}, ("method", "RK45, RK23, DOP853, Radau, BDF, LSODA", "'Euler'")),
    ({"method": 3}, ("method", "got 3")),
    ({"max_step": 0.0}, ("max_step", "> 0", "got 0")),
    ({"max_step": -1.0}, ("max_step", "got -1")),
    ({"max_step": float("nan")}, ("max_step", "got nan")),
    ({"max_step": "1"}, ("max_step",)),
    ({"rtol": 0.0}, ("rtol", "0 < rtol < 1", "got 0")),
    ({"rtol": -1e-6}, ("rtol",)),
    ({"rtol": float("nan")}, ("rtol", "got nan")),
    ({"rtol": 2.0}, ("rtol", "got 2")),
    ({"rtol": [1e-6, 1e-6]}, ("rtol", "shape (2,)")),
    ({"atol": -1e-9}, ("atol", "> 0")),
    ({"atol": 0.0}, ("atol", "> 0", "got 0")),
    ({"atol": [1e-9, 0.0]}, ("atol", "> 0")),
    ({"atol": float("inf")}, ("atol", "finite")),
    ({"atol": [1e-9, 1e-9, 1e-9]}, ("atol", "one per state", "got shape (3,)")),
], ids=["lowercase", "unknown", "number", "zero-step", "negative-step", "nan-step", "text-step",
        "zero-rtol", "negative-rtol", "nan-rtol", "big-rtol", "array-rtol", "negative-atol",
        "zero-atol", "zero-atol-entry", "inf-atol", "atol-shape"])
def test_bad_solver_options(msd, options, words):
    raises_promptly(NumericError, *words, call=lambda: simulate(msd, MSD_VALUES, (0.0, 1.0), **options))


def test_good_solver_options_are_accepted(mass):
    # free mass, p_m(2) = 0 + F*2 = 2 with F = 1, whatever the solver
    from scipy.integrate import RK23

    for options in ({"method": "Radau", "atol": [1e-10]}, {"method": RK23, "max_step": np.inf},
                    {"method": "LSODA", "rtol": 1e-8, "atol": 1e-12}):
        res = simulate(mass, {"m": 1.0}, (0.0, 2.0), u=1.0, t_eval=2.0, **options)
        assert res["p_m"][-1] == pytest.approx(2.0, rel=1e-6)


# ----------------------------------------------------------------------------- inputs
@pytest.mark.parametrize("u, error, words", [
    (lambda t: [1.0, 2.0], NumericError, ("u(t) must have shape (1,)", "inputs F", "at t = 0")),
    (lambda t: None, NumericError, ("u(t) must be", "finite number", "at t = 0")),
    (lambda t: "a", NumericError, ("u(t) must be", "at t = 0")),
    (lambda t: [float("nan")], NumericError, ("u(t) must be finite", "input F is nan", "at t = 0")),
    (lambda t: [1.0 if t < 0.5 else float("inf")], NumericError, ("u(t) must be finite", "input F is inf (at t = ")),
    (lambda t: 1 / 0, SimulationError, ("u(t) raised ZeroDivisionError", "t = 0")),
    ([float("nan")], NumericError, ("constant input u", "input F is nan")),
    ([1.0, 2.0], NumericError, ("constant input u", "shape (1,)")),
    ("F", NumericError, ("constant input u",)),
    ((np.array([0.0, 1.0]), np.array([0.0, float("nan")])), NumericError,
     ("input samples", "input F is nan at t = 1")),
    ((np.array([0.0, float("inf")]), np.array([0.0, 1.0])), NumericError, ("input sample times",)),
    ((np.array([0.0, 1.0]), np.array([[0.0, 1.0], [1.0, 2.0]])), NumericError,
     ("input samples", "shape (2, 1)")),
    ({"G": 1.0}, NumericError, ("u names unknown inputs G", "the inputs are F")),
    ({"F": "x"}, NumericError, ("u['F'] must be a finite number or a function of time",)),
    ({"F": lambda t: 1 / 0}, SimulationError, ("u['F'] raised ZeroDivisionError", "t = 0")),
    ({"F": lambda t: float("nan")}, NumericError, ("u(t) must be finite", "input F is nan")),
], ids=["shape", "None", "text", "nan", "inf-later", "raises", "nan-const", "long-const", "text-const",
        "nan-sample", "inf-sample-time", "sample-shape", "named-unknown", "named-text",
        "named-raises", "named-nan"])
def test_bad_inputs(msd, u, error, words):
    raises_promptly(error, *words, call=lambda: simulate(msd, MSD_VALUES, (0.0, 1.0), u=u, max_step=0.25))


def test_raising_input_function_is_chained(msd):
    err = raises_promptly(SimulationError, "ZeroDivisionError", call=lambda: simulate(
        msd, MSD_VALUES, (0.0, 1.0), u=lambda t: 1 / 0))
    assert isinstance(err.__cause__, ZeroDivisionError)


def test_bad_parameter_values_are_parameter_errors(msd):
    raises_promptly(ParameterValueError, "Rf", call=lambda: simulate(
        msd, {"m": 1.0, "k": 4.0, "Rf": float("nan")}, (0.0, 1.0)))
    raises_promptly(ParameterValueError, "Rf", call=lambda: simulate(msd, {"m": 1.0, "k": 4.0}, (0.0, 1.0)))


def test_inputs_by_name(mass):
    """u={"F": 3.0} and u={"F": lambda t: 3.0*t}: p(1) = 3 and p(1) = 3/2 (Newton: p' = F)."""
    res = simulate(mass, {"m": 2.0}, (0.0, 1.0), u={"F": 3.0}, t_eval=[1.0])
    assert res["p_m"][-1] == pytest.approx(3.0, rel=1e-9)
    res = simulate(mass, {"m": 2.0}, (0.0, 1.0), u={"F": lambda t: 3.0 * t}, t_eval=[1.0],
                   rtol=1e-10, atol=1e-12)
    assert res["p_m"][-1] == pytest.approx(1.5, rel=1e-8)


# ----------------------------------------------------------------------------- renamed argument
def test_parameter_values_are_passed_as_values(mass):
    # free mass: p_m(1) = 0 + 3*1, v = p_m/m = 1.5
    res = simulate(mass, values={"m": 2.0}, t_span=(0.0, 1.0), u=[3.0], t_eval=[1.0])
    assert res["v"][-1] == pytest.approx(1.5, rel=1e-9)
    sys = to_nonlinear_iosys(mass, values={"m": 2.0})
    assert sys.output(0.0, [3.0], [0.0]) == pytest.approx([1.5])
    with pytest.raises(TypeError):
        simulate(mass, params={"m": 2.0}, t_span=(0.0, 1.0))  # type: ignore[call-arg]


# ----------------------------------------------------------------------------- user law callables
@pytest.mark.parametrize("law, cause, words", [
    (lambda f: 1 // 0, ZeroDivisionError, ("raised ZeroDivisionError",)),
    (lambda f: math.log(f), TypeError, ("raised TypeError", "sympy.log, not math.log")),
], ids=["zero-division", "math-log"])
def test_raising_law_callable_names_the_element(law, cause, words):
    err = raises_promptly(bg.LawError, "R:Rf", "law callable", *words, call=lambda: bg.R("Rf", law=law))
    assert isinstance(err.__cause__, cause) and isinstance(err, ValueError)


@pytest.mark.parametrize("result, words", [
    (None, "returned NoneType"), ("abc", "returned str"), ([1.0], "returned list"),
    (np.array([1.0]), "returned ndarray"), (True, "returned bool")],
    ids=["None", "str", "list", "array", "bool"])
def test_law_callable_returning_a_non_number_names_the_element(result, words):
    raises_promptly(bg.LawError, "R:Rf", words, call=lambda: bg.R("Rf", law=lambda f: result))
    raises_promptly(bg.LawError, "C:k", words, call=lambda: bg.C("k", law=lambda q: result))


def test_law_callable_returning_an_expression_still_works():
    assert bg.R("Rf", law=lambda f: 2 * f**3).forward() == 2 * bg.f**3


def test_uninvertible_law_is_kept_implicit():
    # on a 0-junction the damper is given its effort and needs f(e): f + sin(f) = e has no
    # closed form; since issue 29 the flow stays an algebraic unknown solved numerically
    from scipy.optimize import brentq

    g = bg.BondGraph("par")
    z = bg.Zero("z")
    g.add(bg.Sf("v"), z, bg.C("k"), bg.R("Rf", law=bg.f + sympy.sin(bg.f)))
    for tail, head in [("v", z), (z, "k"), (z, "Rf")]:
        g.connect(tail, head)
    model = bg.derive(g, outputs={"f": bg.flow("Rf")})
    assert model.algebraic_names == ("f_Rf",)
    dyn = bg.numeric.compile_dynamics(model)
    y = dyn.outputs(0.0, [3.0], [0.0], dyn.parameter_vector({"k": 2.0}))[0]
    assert y == pytest.approx(brentq(lambda f: f + np.sin(f) - 1.5, 0.0, 1.5, xtol=1e-15), rel=1e-12)


def _user_law(fn, name="user"):
    return bg.R("Rf", law=lambda f: implemented_function(name, fn)(f))


def test_law_function_raising_in_simulation_names_the_element():
    # 1/f with f = p_m/m = 0 at t = 0
    model = msd_graph(_user_law(lambda v: 1 / float(v), "inv"))
    err = raises_promptly(SimulationError, "R:Rf", "inv", "ZeroDivisionError", "t = 0", call=lambda: simulate(
        model, {"m": 1.0, "k": 4.0}, (0.0, 1.0)))
    assert isinstance(err.__cause__, ZeroDivisionError)


def test_law_function_returning_a_non_number_names_the_element():
    model = msd_graph(_user_law(lambda v: "oops", "bad"))
    raises_promptly(SimulationError, "R:Rf", "bad", "returned str", call=lambda: simulate(
        model, {"m": 1.0, "k": 4.0}, (0.0, 1.0)))


def test_law_function_in_a_model_runs_like_the_expression():
    # the same damper e = 2 f written as a Python function and as a parameter give one history
    model = msd_graph(_user_law(lambda v: 2.0 * v, "twice"))
    res = simulate(model, {"m": 1.0, "k": 4.0}, (0.0, 1.0), {"q_k": 1.0}, t_eval=[1.0], rtol=1e-10, atol=1e-12)
    ref = simulate(msd_graph(), {"m": 1.0, "k": 4.0, "Rf": 2.0}, (0.0, 1.0), {"q_k": 1.0}, t_eval=[1.0],
                   rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res.x, ref.x, rtol=1e-9)
    # m x'' + 2 x' + 4 x = 0, x(0) = 1, x'(0) = 0: x = e^-t (cos(sqrt3 t) + sin(sqrt3 t)/sqrt3)
    w = math.sqrt(3.0)
    assert res["x"][-1] == pytest.approx(math.exp(-1) * (math.cos(w) + math.sin(w) / w), rel=1e-8)


def test_scalar_only_function_in_an_output_is_called_per_sample():
    # math.sqrt takes no arrays; the outputs are evaluated per sample then.  Free decay of
    # x from 1 with no damping: x = cos(2 t) for m = 1, k = 4; sqrt(x + 1) at t = 0 is sqrt(2)
    root = implemented_function("root", math.sqrt)
    model = msd_graph(outputs={"r": root(bg.displacement("k") + 1)})
    res = simulate(model, {"m": 1.0, "k": 4.0, "Rf": 1e-12}, (0.0, 1.0), {"q_k": 1.0}, t_eval=[0.0, 1.0],
                   rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res["r"], [math.sqrt(2.0), math.sqrt(math.cos(2.0) + 1)], rtol=1e-7)
