"""Generated code of implicit models (issue 29): C (compiled, called with ctypes), Python and
MATLAB (run in Octave) solve ``0 = g(x, z, u)`` by Newton's method.

Every expected value is computed here without the code under test:

* a diode ``i = Is (exp(v/Vt) - 1)`` in series with a resistor, driven by a
  source and charging a capacitor: ``V - q/C = R i + v`` solved for the
  diode voltage ``v`` with :func:`scipy.optimize.brentq` on the hand-written
  residual ``R Is (exp(v/Vt) - 1) + v - (V - q/C)``; ``dq/dt = i``;
* two quadratic orifices ``dp_k = Q |Q| / K_k^2`` in series between two
  accumulators: ``Q = sign(dp) sqrt(|dp| / (1/K1^2 + 1/K2^2))`` with
  ``dp = q1/A1 - q2/A2``; ``dq1/dt = -Q``, ``dq2/dt = Q``;
* a pipe network: orifice ``o1`` in series with two orifices ``o2 || o3`` in
  parallel, two coupled algebraic unknowns (the flows of ``o2`` and
  ``o3``, a full 2 x 2 ``dg/dz``): ``Q1 = sign(dp) sqrt(|dp| / (1/K1^2 +
  1/(K2 + K3)^2))`` (parallel orifices add their ``K``), ``Q2 = Q1 K2 /
  (K2 + K3)``;
* a law ``e = Ff (tanh f + tanh^3 f)`` that saturates at ``2 Ff``: driven by
  ``F = Ff`` its flow is ``artanh(s)``, ``s`` the real root of
  ``s^3 + s - 1``; driven by ``3 Ff`` there is no solution, and every target
  reports the failure naming the unknown ``f_fr``.

They are also compared with :func:`bondgraph.numeric.compile_dynamics` at the
same points (which once failed on the network from a cold start, where
every orifice's slope is 0, and after a reverse-bias warm start of the
diode: both are solved by its last-resort starts now).  In reverse bias the derived ``dq/dt = (V - v(i) - q/C)/R`` is a
difference of nearly equal voltages (``v(i) = Vt log(1 + i/Is)`` with
``1 + i/Is`` near 0), so there the state derivative is compared with an
absolute tolerance of 1e-9 of the largest current of the sample; the outputs
``i`` and ``v`` are compared relatively everywhere.
"""

import ctypes
import math
import shutil
import subprocess

import numpy as np
import pytest
import sympy
from scipy.optimize import brentq

import bondgraph as bg
from bondgraph.codegen import generate_python, write_c, write_matlab

CC = shutil.which("cc") or shutil.which("gcc")
OCTAVE = shutil.which("octave-cli") or shutil.which("octave")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler (cc) on PATH")
CFLAGS = ["-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-O2", "-shared", "-fPIC"]
PTR = ctypes.POINTER(ctypes.c_double)


# ----------------------------------------------------------------------------- models
def diode_rc() -> bg.Model:
    Is, Vt = sympy.symbols("Is Vt", positive=True)
    g = bg.BondGraph("diode_rc")
    g.add(bg.Se("V"), bg.One("s"), bg.R("R"), bg.R("D", inverse=Is * (sympy.exp(bg.e / Vt) - 1)),
          bg.C("C"))
    for t, h in [("V", "s"), ("s", "R"), ("s", "D"), ("s", "C")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"i": bg.flow("D"), "vd": bg.effort("D")})


def diode_hand(x, u, p):
    """(xdot, [i, v]) by brentq on the series loop; p in name order C, Is, R, Vt."""
    C, Is, R, Vt = p
    w = u[0] - x[0] / C                  # the voltage across resistor and diode
    span = abs(w) + 1.0
    v = brentq(lambda v: R * Is * math.expm1(v / Vt) + v - w, -span, span, xtol=1e-15, rtol=1e-15)
    i = Is * math.expm1(v / Vt)
    return np.array([i]), np.array([i, v])


def diode_points(seed, count=12):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        p = np.array([rng.uniform(1e-7, 1e-5), rng.uniform(1e-13, 1e-11), rng.uniform(200, 2000),
                      rng.uniform(0.02, 0.03)])
        V, w = rng.uniform(-5, 5), rng.uniform(-0.3, 3.0)
        yield 0.0, np.array([p[0] * (V - w)]), np.array([V]), p


def orifices() -> bg.Model:
    K1, K2 = sympy.symbols("K1 K2", positive=True)
    g = bg.BondGraph("pipes")
    g.add(bg.C("A1"), bg.Zero("n1"), bg.One("s"), bg.R("o1", law=bg.f * abs(bg.f) / K1**2),
          bg.R("o2", law=bg.f * abs(bg.f) / K2**2), bg.Zero("n2"), bg.C("A2"))
    for t, h in [("n1", "A1"), ("n1", "s"), ("s", "o1"), ("s", "o2"), ("s", "n2"), ("n2", "A2")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"Q": bg.flow("o1")})


def orifice_hand(x, u, p):
    A1, A2, K1, K2 = p
    dp = x[0] / A1 - x[1] / A2
    Q = math.copysign(math.sqrt(abs(dp) / (1 / K1**2 + 1 / K2**2)), dp)
    return np.array([-Q, Q]), np.array([Q])


def orifice_points(seed, count=12):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        yield (0.0, rng.uniform(0.0, 10.0, 2), np.zeros(0),
               np.array([rng.uniform(0.5, 3), rng.uniform(0.5, 3), rng.uniform(1, 5), rng.uniform(1, 5)]))


def network() -> bg.Model:
    K1, K2, K3 = sympy.symbols("K1 K2 K3", positive=True)
    g = bg.BondGraph("net")
    g.add(bg.C("A1"), bg.Zero("n1"), bg.One("s"), bg.R("o1", law=bg.f * abs(bg.f) / K1**2), bg.Zero("m"),
          bg.One("b2"), bg.One("b3"), bg.R("o2", law=bg.f * abs(bg.f) / K2**2),
          bg.R("o3", law=bg.f * abs(bg.f) / K3**2), bg.Zero("n2"), bg.C("A2"))
    for t, h in [("n1", "A1"), ("n1", "s"), ("s", "o1"), ("s", "m"), ("m", "b2"), ("m", "b3"), ("b2", "o2"),
                 ("b3", "o3"), ("b2", "n2"), ("b3", "n2"), ("n2", "A2")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"Q1": bg.flow("o1"), "Q2": bg.flow("o2")})


def network_hand(x, u, p):
    A1, A2, K1, K2, K3 = p
    dp = x[0] / A1 - x[1] / A2
    Q1 = math.copysign(math.sqrt(abs(dp) / (1 / K1**2 + 1 / (K2 + K3)**2)), dp)
    return np.array([-Q1, Q1]), np.array([Q1, Q1 * K2 / (K2 + K3)])


def network_points(seed, count=12):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        yield 0.0, rng.uniform(0.0, 10.0, 2), np.zeros(0), rng.uniform([0.5, 0.5, 1, 1, 1], [3, 3, 5, 5, 5])


def saturating() -> bg.Model:
    Ff = sympy.Symbol("Ff", positive=True)
    g = bg.BondGraph("sat")
    g.add(bg.Se("F"), bg.Zero("n"), bg.R("fr", law=Ff * (sympy.tanh(bg.f) + sympy.tanh(bg.f)**3)),
          bg.One("j"), bg.I("m"))
    for t, h in [("F", "n"), ("n", "fr"), ("n", "j"), ("j", "m")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"f": bg.flow("fr")})


SAT_FLOW = float(np.arctanh([r.real for r in np.roots([1, 0, 1, -1]) if abs(r.imag) < 1e-12][0]))
CASES = {"diode_rc": (diode_rc, diode_hand, diode_points), "pipes": (orifices, orifice_hand, orifice_points),
         "net": (network, network_hand, network_points)}


def check(case, got_xdot, got_y, x, u, p, dyn, scale):
    _, hand, _ = CASES[case]
    xdot, y = hand(x, u, p)
    np.testing.assert_allclose(got_y, y, rtol=1e-9, atol=1e-18)
    np.testing.assert_allclose(got_xdot, xdot, rtol=1e-8, atol=1e-9 * scale)
    np.testing.assert_allclose(got_xdot, dyn.derivatives(0.0, x, u, p), rtol=1e-8, atol=1e-9 * scale)
    np.testing.assert_allclose(got_y, dyn.outputs(0.0, x, u, p), rtol=1e-8, atol=1e-9 * scale)


def sample_scale(case, points):
    return max(float(np.max(np.abs(CASES[case][1](x, u, p)[1]))) for _, x, u, p in points)


# ----------------------------------------------------------------------------- C
def build_c(model, tmp_path):
    src, _ = write_c(model, tmp_path / f"{model.name}.c")
    lib = tmp_path / f"lib{model.name}.so"
    subprocess.run([CC, *CFLAGS, "-o", str(lib), str(src), "-lm"], check=True, capture_output=True,
                   text=True)
    lib = ctypes.CDLL(str(lib))
    getattr(lib, f"{model.name}_status_message").restype = ctypes.c_char_p
    return lib


def c_eval(fn, t, x, u, p, z, n_out):
    out = np.zeros(n_out)
    status = fn(ctypes.c_double(t), *(np.ascontiguousarray(a, float).ctypes.data_as(PTR) for a in (x, u, p)),
                z.ctypes.data_as(PTR), out.ctypes.data_as(PTR))
    return status, out


@needs_cc
@pytest.mark.parametrize("case", list(CASES))
def test_c_solves_the_loop_at_random_states(case, tmp_path):
    build, _, points = CASES[case]
    model = build()
    lib = build_c(model, tmp_path)
    dyn = bg.numeric.compile_dynamics(model)
    pts = list(points(seed=3))
    scale = sample_scale(case, pts)
    z = np.zeros(len(model.algebraic))          # one warm start carried from point to point
    for t, x, u, p in pts:
        s1, xdot = c_eval(getattr(lib, f"{case}_derivatives"), t, x, u, p, z, len(model.states))
        s2, y = c_eval(getattr(lib, f"{case}_outputs"), t, x, u, p, z, len(model.output_names))
        assert s1 == s2 == 0
        check(case, xdot, y, x, u, p, dyn, scale)
    # the last solution is the caller's z: here the flow of the loop (output 0 of the first two)
    if case != "net":
        assert z[0] == pytest.approx(y[0], rel=1e-12)
    else:
        assert z[0] == pytest.approx(y[1], rel=1e-12) and z[0] + z[1] == pytest.approx(y[0], rel=1e-12)


@needs_cc
def test_c_failure_is_a_status_naming_the_unknown_and_nothing_is_computed(tmp_path):
    model = saturating()
    lib = build_c(model, tmp_path)
    assert [q.name for q in model.parameters] == ["Ff"]      # m is not in the equations
    p = np.array([1.0])
    z = np.zeros(1)
    status, y = c_eval(lib.sat_outputs, 0.0, [0.0], [1.0], p, z, 1)
    assert status == 0 and y[0] == pytest.approx(SAT_FLOW, rel=1e-12) and z[0] == y[0]
    status, xdot = c_eval(lib.sat_derivatives, 0.0, [0.25], [3.0], p, z, 1)
    assert status != 0 and np.isnan(xdot).all()
    assert z[0] == pytest.approx(SAT_FLOW, rel=1e-12)        # the last solution is kept
    message = lib.sat_status_message(status).decode()
    assert "f_fr" in message and "R:fr" in message and "no solution" in message
    assert lib.sat_status_message(0).decode() == "converged"
    x = np.array([0.25])
    step = lib.sat_step_rk4
    got = step(ctypes.c_double(0.0), ctypes.c_double(0.01), x.ctypes.data_as(PTR),
               np.array([3.0]).ctypes.data_as(PTR), p.ctypes.data_as(PTR), z.ctypes.data_as(PTR))
    assert got == status and x[0] == 0.25                   # x unchanged by a failed step


@needs_cc
def test_c_rk4_step_against_independent_rk4(tmp_path):
    """Two RK4 steps of the diode circuit: the generated step against RK4 on the brentq rhs."""
    model = diode_rc()
    lib = build_c(model, tmp_path)
    p = np.array([1e-6, 1e-12, 1e3, 0.025])
    u = np.array([5.0])
    x, z, h = np.array([0.0]), np.zeros(1), 2e-5
    ref = x.copy()
    for k in range(2):
        f = lambda xx: diode_hand(xx, u, p)[0]  # noqa: E731
        k1 = f(ref)
        k2 = f(ref + h / 2 * k1)
        k3 = f(ref + h / 2 * k2)
        k4 = f(ref + h * k3)
        ref = ref + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        assert lib.diode_rc_step_rk4(ctypes.c_double(k * h), ctypes.c_double(h), x.ctypes.data_as(PTR),
                                     u.ctypes.data_as(PTR), p.ctypes.data_as(PTR), z.ctypes.data_as(PTR)) == 0
    assert x[0] == pytest.approx(ref[0], rel=1e-10)


# ----------------------------------------------------------------------------- Python
@pytest.mark.parametrize("case", list(CASES))
def test_python_solves_the_loop_at_random_states(case):
    build, _, points = CASES[case]
    model = build()
    ns: dict = {}
    exec(generate_python(model), ns)
    dyn = bg.numeric.compile_dynamics(model)
    pts = list(points(seed=5))
    scale = sample_scale(case, pts)
    assert ns["ALGEBRAIC_NAMES"] == model.algebraic_names
    for t, x, u, p in pts:
        check(case, ns["derivatives"](t, x, u, p), ns["outputs"](t, x, u, p), x, u, p, dyn, scale)


def test_python_failure_raises_naming_the_unknown_and_the_state():
    ns: dict = {}
    exec(generate_python(saturating()), ns)
    assert ns["outputs"](0.0, [0.0], [1.0], [1.0])[0] == pytest.approx(SAT_FLOW, rel=1e-12)
    with pytest.raises(ns["AlgebraicSolveError"], match=r"f_fr \(the flow of R:fr.*p_m = 0\.25.*F = 3\.0"):
        ns["derivatives"](0.0, [0.25], [3.0], {"Ff": 1.0})
    with pytest.raises(ValueError, match="p has 2 values; expected 1"):
        ns["derivatives"](0.0, [0.25], [3.0], [1.0, 1.0])
    assert issubclass(ns["AlgebraicSolveError"], ArithmeticError)


# ----------------------------------------------------------------------------- MATLAB / Octave
def octave(script, cwd):
    if OCTAVE is None:      # pragma: no cover - depends on the machine
        pytest.skip("octave not installed")
    out = subprocess.run([OCTAVE, "--no-gui", "--quiet", "--norc", "--no-history", "--eval", script],
                         cwd=cwd, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout


def vec(a):
    return "[" + "; ".join(repr(float(v)) for v in np.ravel(a)) + "]"


def test_matlab_solves_the_loops_and_reports_failure_in_octave(tmp_path):
    script = []
    runs = []
    for case, (build, _, points) in CASES.items():
        model = build()
        write_matlab(model, tmp_path / f"{case}_m.m")
        pts = list(points(seed=9, count=6))
        runs.append((case, model, pts))
        for t, x, u, p in pts:
            script.append(f"[xd, y] = {case}_m({t!r}, {vec(x)}, {vec(u)}, {vec(p)}); "
                          "printf('%.17g ', [xd; y]); printf('\\n');")
    write_matlab(saturating(), tmp_path / "sat_m.m")
    script.append("try, sat_m(0, 0.25, 3, 1); printf('no error\\n'); "
                  "catch err, printf('%s|%s\\n', err.identifier, err.message); end")
    lines = octave("\n".join(script), tmp_path).splitlines()
    k = 0
    for case, model, pts in runs:
        dyn = bg.numeric.compile_dynamics(model)
        scale = sample_scale(case, pts)
        n = len(model.states)
        for t, x, u, p in pts:
            values = np.array([float(v) for v in lines[k].split()])
            check(case, values[:n], values[n:], x, u, p, dyn, scale)
            k += 1
    ident, message = lines[k].split("|", 1)
    assert ident == "bondgraph:newton"
    assert "f_fr (the flow of R:fr" in message and "p_m = 0.25" in message
