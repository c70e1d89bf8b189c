"""Generated C (compiled, called with ctypes), Python and MATLAB code against hand-written
right-hand sides at random states, inputs and parameters."""

import ast
import ctypes
import importlib.util
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.codegen import (CodegenError, generate_c, generate_matlab, generate_python, write_c,
                               write_matlab, write_python)
from bondgraph.codegen._common import sanitize
from bondgraph.export import ExportError

CC = shutil.which("cc") or shutil.which("gcc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler (cc) on PATH")
RTOL = 1e-12


# ----------------------------------------------------------------------------- models and hand rhs
def dc_motor():
    g = bg.BondGraph("dc_motor")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
    for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
        g.connect(tail, head)
    return bg.derive(g, outputs={"omega": bg.flow("J"), "i": bg.flow("La")})


def motor_rhs(t, x, u, p):            # parameters sorted by name: J, K, La, Ra, b
    J, K, La, Ra, b = p
    A = np.array([[-Ra / La, -K / J], [K / La, -b / J]])
    return A @ x + np.array([u[0], 0.0]), np.array([x[1] / J, x[0] / La])


def duffing():
    """Nonlinear spring k q + k3 q^3 with pi in it, hierarchical names and a name clash."""
    k3 = sympy.Symbol("spring.k3", positive=True)
    k = sympy.Symbol("k", positive=True)
    g = bg.BondGraph("duffing")
    F, v = bg.Se("F"), bg.One("v")
    g.add(F, v, bg.I("m", "mass.m"), bg.R("b", "mass_m"), bg.C("s", law=k * bg.q + sympy.pi * k3 * bg.q**3))
    for tail, head in [(F, v), (v, "m"), (v, "b"), (v, "s")]:
        g.connect(tail, head)
    return bg.derive(g, outputs={"x": bg.displacement("s"), "Fs": bg.effort("s")})


def duffing_rhs(t, x, u, p):          # parameters: k, mass.m, mass_m (damper), spring.k3
    k, m, b, k3 = p
    pm, q = x
    spring = k * q + np.pi * k3 * q**3
    return np.array([u[0] - b * pm / m - spring, pm / m]), np.array([q, spring])


def lever():
    """Time-varying: a lever whose ratio is cos(t) drives a damper."""
    g = bg.BondGraph("lever")
    F, v, w = bg.Se("F"), bg.One("v"), bg.One("w")
    g.add(F, v, w, bg.I("m"), bg.MTF("lever", modulus=sympy.cos(bg.t)), bg.R("b"))
    for tail, head in [(F, v), (v, "m"), (v, "lever"), ("lever", w), (w, "b")]:
        g.connect(tail, head)
    return bg.derive(g, outputs={"v": bg.flow("m")})


def lever_rhs(t, x, u, p):            # b, m
    b, m = p
    return np.array([u[0] - b * np.cos(t) ** 2 * x[0] / m]), np.array([x[0] / m])


CASES = {"dc_motor": (dc_motor, motor_rhs), "duffing": (duffing, duffing_rhs), "lever": (lever, lever_rhs)}


def samples(model, seed, count=5):
    rng = np.random.default_rng(seed)
    n, m, k = len(model.states), len(model.inputs), len(model.parameters)
    for _ in range(count):
        yield (float(rng.uniform(-3, 3)), rng.uniform(-2, 2, n), rng.uniform(-2, 2, m),
               rng.uniform(0.3, 3.0, k))


def close(got, want):
    np.testing.assert_allclose(got, want, rtol=RTOL, atol=RTOL * max(1.0, float(np.max(np.abs(want)))))


# ----------------------------------------------------------------------------- C
def build_c(model, tmp_path, name=None, defaults=None):
    src, hdr = write_c(model, tmp_path / "model.c", name=name, defaults=defaults)
    lib = tmp_path / "libmodel.so"
    subprocess.run([CC, "-shared", "-fPIC", "-O2", "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror",
                    "-o", str(lib), str(src), "-lm"], check=True, capture_output=True, text=True)
    return ctypes.CDLL(str(lib))


def c_call(fn, *args, out_size):
    ptr = ctypes.POINTER(ctypes.c_double)
    out = np.zeros(out_size)
    conv = [ctypes.c_double(a) if np.isscalar(a) else np.ascontiguousarray(a, float).ctypes.data_as(ptr)
            for a in args]
    fn(*conv, out.ctypes.data_as(ptr))
    return out


@needs_cc
@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_c_matches_hand_rhs(case, tmp_path):
    build, rhs = CASES[case]
    model = build()
    lib = build_c(model, tmp_path)
    prefix = model.name
    deriv, outs = getattr(lib, f"{prefix}_derivatives"), getattr(lib, f"{prefix}_outputs")
    deriv.restype = outs.restype = None
    for t, x, u, p in samples(model, seed=len(case)):
        xdot, y = rhs(t, x, u, p)
        close(c_call(deriv, t, x, u, p, out_size=len(x)), xdot)
        close(c_call(outs, t, x, u, p, out_size=len(y)), y)


@needs_cc
def test_c_names_sizes_and_defaults(tmp_path):
    model = duffing()
    defaults = {"k": 2.0, "mass.m": 1.5, "mass_m": 0.1, "spring.k3": 1e-3}
    lib = build_c(model, tmp_path, name="duff", defaults=defaults)
    header = (tmp_path / "model.h").read_text()
    for macro, value in (("DUFF_NX", 2), ("DUFF_NU", 1), ("DUFF_NY", 2), ("DUFF_NP", 4)):
        assert f"#define {macro} {value}" in header
    names = [n.decode() for n in (ctypes.c_char_p * 5).in_dll(lib, "duff_parameter_names")[:4]]
    assert names == ["k", "mass.m", "mass_m", "spring.k3"]
    assert (ctypes.c_char_p * 5).in_dll(lib, "duff_parameter_names")[4] is None
    states = [n.decode() for n in (ctypes.c_char_p * 2).in_dll(lib, "duff_state_names")]
    assert states == ["p_m", "q_s"]
    assert list((ctypes.c_double * 4).in_dll(lib, "duff_default_parameters")) == [2.0, 1.5, 0.1, 1e-3]
    # the clash of mass.m and mass_m is resolved, and documented in the header
    assert "mass.m  [as mass_m_2]" in header and "spring.k3  [as spring_k3]" in header


def python_rk4(rhs, t, h, x, u, p):
    f = lambda tt, xx: rhs(tt, xx, u, p)[0]  # noqa: E731
    k1 = f(t, x)
    k2 = f(t + h / 2, x + h / 2 * k1)
    k3 = f(t + h / 2, x + h / 2 * k2)
    k4 = f(t + h, x + h * k3)
    return x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


@needs_cc
@pytest.mark.parametrize("case", ["duffing", "lever"])
def test_c_fixed_step_integrators(case, tmp_path):
    build, rhs = CASES[case]
    model = build()
    lib = build_c(model, tmp_path)
    ptr = ctypes.POINTER(ctypes.c_double)
    for t, x, u, p in samples(model, seed=7, count=3):
        h = 0.01
        euler = x + h * rhs(t, x, u, p)[0]
        for step, expected in (("rk4", python_rk4(rhs, t, h, x, u, p)), ("euler", euler)):
            fn = getattr(lib, f"{model.name}_step_{step}")
            fn.restype = None
            state = np.array(x, dtype=float)
            fn(ctypes.c_double(t), ctypes.c_double(h), state.ctypes.data_as(ptr),
               np.ascontiguousarray(u).ctypes.data_as(ptr), np.ascontiguousarray(p).ctypes.data_as(ptr))
            close(state, expected)


def test_c_refuses_functions_it_lacks_and_bad_names():
    g = bg.BondGraph("bessel")
    g.add(bg.Se("F"), bg.I("m", law=sympy.besselj(0, bg.p) + bg.p))
    g.connect("F", "m")
    model = bg.derive(g, outputs={"v": bg.flow("m")})
    with pytest.raises(CodegenError, match="C has no function.*besselj"):
        generate_c(model)
    with pytest.raises(CodegenError, match="no Python math function.*besselj"):
        generate_python(model)
    with pytest.raises(CodegenError, match="C name prefix 'my-model'"):
        generate_c(dc_motor(), name="my-model")
    with pytest.raises(CodegenError, match="C name prefix 'int'"):
        generate_c(dc_motor(), name="int")


def test_input_derivatives_cannot_be_generated():
    g = bg.BondGraph("push")
    g.add(bg.Sf("v"), bg.I("m"))
    g.connect("v", "m")
    with pytest.raises(CodegenError, match="time derivatives of inputs"):
        generate_c(bg.derive(g, outputs={"F": bg.effort("m")}))   # F = m dv/dt


def test_write_c_is_all_or_nothing(tmp_path):
    with pytest.raises(ExportError, match="does not exist"):
        write_c(dc_motor(), tmp_path / "nodir" / "m.c")
    (tmp_path / "m.h").mkdir()                  # the header cannot be written
    with pytest.raises(ExportError, match="m.h"):
        write_c(dc_motor(), tmp_path / "m.c")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.h"]


def test_sanitize_keeps_valid_names_and_resolves_clashes():
    got = sanitize(["motor.Ra", "motor_Ra", "2x", "if"], reserved={"if"})
    assert got == ("motor_Ra_2", "motor_Ra", "v_2x", "if_2")
    assert sanitize(["_a", "motor.Ra"], matlab=True) == ("v_a", "motor_Ra")


def test_sanitize_matches_whole_names():
    # a trailing newline is not an identifier ($ alone would have let "m\n" through)
    assert sanitize(["m\n", "m"]) == ("m_", "m")
    assert sanitize(["m\n"], matlab=True) == ("m_",)
    # "_", "__" and names made of underscores stay clear of C's reserved _X / __ (and terminate)
    assert sanitize(["_", "\u200f", "\u00e9", "__x", "_Ab"]) == ("_", "v_", "v__2", "v__x", "v_Ab")
    assert sanitize(["x" * 80], matlab=True) == ("x" * 58,)


def test_names_that_would_be_macros_are_renamed_in_c():
    g = bg.BondGraph("plant")
    g.add(bg.Se("F"), bg.I("m", sympy.Symbol("M_PI") + sympy.Symbol("PLANT_NX") + sympy.Symbol("FP_NAN")))
    g.connect("F", "m")
    code = generate_c(bg.derive(g, outputs={"v": bg.flow("m")}))
    # M_PI_2 is a macro too (pi/2)
    assert dict(code.identifiers) == {"p_m": "p_m", "F": "F", "FP_NAN": "FP_NAN_2", "M_PI": "M_PI_3",
                                      "PLANT_NX": "PLANT_NX_2"}


# ----------------------------------------------------------------------------- Python
def import_generated(path):
    spec = importlib.util.spec_from_file_location(f"generated_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_python_module_matches_hand_rhs(case, tmp_path):
    build, rhs = CASES[case]
    model = build()
    path = write_python(model, tmp_path / f"{case}_eqs.py")
    tree = ast.parse(path.read_text())
    imported = {a.name for node in ast.walk(tree) if isinstance(node, (ast.Import, ast.ImportFrom))
                for a in node.names}
    assert imported <= {"math"}
    mod = import_generated(path)
    assert mod.STATE_NAMES == model.state_names and mod.INPUT_NAMES == model.input_names
    assert mod.OUTPUT_NAMES == model.output_names
    assert mod.PARAMETER_NAMES == tuple(p.name for p in model.parameters)
    for t, x, u, p in samples(model, seed=11):
        xdot, y = rhs(t, x, u, p)
        close(mod.derivatives(t, list(x), list(u), list(p)), xdot)
        close(mod.outputs(t, x, u, dict(zip(mod.PARAMETER_NAMES, p))), y)


def test_python_defaults_and_suffix(tmp_path):
    values = {"J": 0.02, "K": 0.1, "La": 0.5, "Ra": 2.0, "b": 0.2}
    mod = import_generated(write_python(dc_motor(), tmp_path / "m.py", defaults=values))
    assert mod.DEFAULT_PARAMETERS == values
    # hand: x' = A x + B u with A = [[-4, -5], [0.2, -10]]
    assert mod.derivatives(0.0, [1.0, 1.0], [3.0], mod.DEFAULT_PARAMETERS) == [-6.0, -9.8]
    with pytest.raises(CodegenError, match="must end in .py"):
        write_python(dc_motor(), tmp_path / "m.txt")
    with pytest.raises(bg.BondGraphError, match="missing b"):
        generate_python(dc_motor(), defaults={k: v for k, v in values.items() if k != "b"})


# ----------------------------------------------------------------------------- MATLAB
def check_matlab_syntax(text, name):
    lines = text.splitlines()
    assert lines[0] == f"function [xdot, y] = {name}(t, x, u, p)"
    depth = 0
    for line in lines[1:]:
        code = re.sub(r"'[^']*(?:''[^']*)*'", "''", line).split("%", 1)[0].strip()  # strings, comments
        if not code:
            continue
        assert code.count("(") == code.count(")") and code.count("[") == code.count("]"), line
        assert code.count("{") == code.count("}"), line
        if re.match(r"^(if|for|while|switch)\b", code):
            depth += 1
        elif code == "end":
            depth -= 1
        else:
            assert code.endswith(";") or code in ("return;",), line
            assert "**" not in code and "math." not in code and "pow(" not in code, line
    assert depth == -1          # the function's own end closes it


@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_matlab_file_is_plausible(case, tmp_path):
    model = CASES[case][0]()
    path = write_matlab(model, tmp_path / f"{case}_ode.m")
    text = path.read_text()
    check_matlab_syntax(text, f"{case}_ode")
    # every state is read from x(k), every parameter from p(k), in order
    for k, ident in enumerate(re.findall(r"^(\w+) = x\((\d+)\);$", text, re.M)):
        assert ident[1] == str(k + 1)
    assert len(re.findall(r"^\w+ = p\(\d+\);$", text, re.M)) == len(model.parameters)
    with pytest.raises(CodegenError, match="MATLAB function name"):
        write_matlab(model, tmp_path / "bad-name.m")


def test_matlab_struct_fields_are_identifiers():
    text = generate_matlab(duffing(), name="duff")
    assert "p = [p.k; p.mass_m_2; p.mass_m; p.spring_k3];" in text
    assert "%      p(2)  mass.m  [as mass_m_2]" in text


OCTAVE = shutil.which("octave-cli") or shutil.which("octave")


@pytest.mark.skipif(OCTAVE is None, reason="GNU Octave is not installed; the .m files are checked "
                                           "for syntax by pattern only")
def test_matlab_runs_in_octave(tmp_path):   # pragma: no cover - depends on the machine
    model = duffing()
    write_matlab(model, tmp_path / "duff.m")
    t, x, u, p = next(samples(model, seed=3))
    fmt = lambda v: "[" + "; ".join(repr(float(a)) for a in v) + "]"  # noqa: E731
    script = f"[xd, y] = duff({t!r}, {fmt(x)}, {fmt(u)}, {fmt(p)}); printf('%.17g\\n', [xd; y]);"
    out = subprocess.run([OCTAVE, "--no-gui", "--quiet", "--eval", script], cwd=tmp_path, check=True,
                         capture_output=True, text=True).stdout.split()
    xdot, y = duffing_rhs(t, x, u, p)
    close(np.array(out, dtype=float), np.concatenate([xdot, y]))


def test_generators_are_deterministic():
    assert generate_c(duffing()).source == generate_c(duffing()).source
    assert generate_python(lever()) == generate_python(lever())
    assert sys.modules.get("bondgraph") is not None
