"""Generated code of switched models (C compiled and called with ctypes, Python executed)
against hand derivations: the rectifier's per-mode rates and guards, the clutch's
momentum-conserving lock and its energy loss, the mode selection of a diode."""

import ctypes
import math
import shutil
import subprocess

import pytest
import sympy

import bondgraph as bg
from bondgraph.codegen import (SwitchedExportError, generate_switched_c, generate_switched_matlab,
                               generate_switched_python)
from bondgraph.hybrid import ControlledSwitch, Diode, SwitchedModel, library

CC = shutil.which("cc") or shutil.which("gcc")
OCTAVE = shutil.which("octave-cli") or shutil.which("octave")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler (cc) on PATH")
STRICT = ["-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-fPIC", "-shared"]
VM, W, R, C = 10.0, 2 * math.pi * 50, 100.0, 1e-4
J1, J2, TL = 1.0, 2.0, 1.0


def rectifier():
    return SwitchedModel(library.rectifier(), outputs={"v": bg.effort("C"), "i": bg.flow("D")})


def clutch():
    return SwitchedModel(library.clutch(), outputs={"w1": bg.flow("J1"), "w2": bg.flow("J2")})


def python_module(sm):
    ns: dict = {}
    exec(compile(generate_switched_python(sm), "generated", "exec"), ns)
    return ns


@pytest.fixture(scope="module")
def c_libs(tmp_path_factory):
    if CC is None:
        pytest.skip("no C compiler")
    folder = tmp_path_factory.mktemp("switched_c")
    out = {}
    for name, sm in (("rect", rectifier()), ("clutch", clutch()),
                     ("buck", SwitchedModel(library.buck(), outputs={"v": bg.effort("C")})),
                     ("stop", SwitchedModel(library.end_stop(), outputs={"x": bg.displacement("m")}))):
        code = generate_switched_c(sm, name=name)
        (folder / f"{name}.c").write_text(code.source)
        (folder / f"{name}.h").write_text(code.header)
        subprocess.run([CC, *STRICT, "-o", str(folder / f"{name}.so"), str(folder / f"{name}.c"), "-lm"],
                       check=True, cwd=folder, capture_output=True)
        out[name] = (ctypes.CDLL(str(folder / f"{name}.so")), code)
    return out


def _arr(values):
    return (ctypes.c_double * max(1, len(values)))(*values)


def _call(lib, fn, mode, t, x, u, p, n):
    out = _arr([0.0] * n)
    getattr(lib, fn)(ctypes.c_int(mode), ctypes.c_double(t), _arr(x), _arr(u), _arr(p), out)
    return list(out)[:n]


def _select(lib, name, proposed, free, check, t, x, u, p):
    xs, loss = _arr(x), ctypes.c_double(0.0)
    f = getattr(lib, f"{name}_select")
    f.restype = ctypes.c_int
    mode = f(ctypes.c_ulong(proposed), ctypes.c_ulong(free), ctypes.c_ulong(check), ctypes.c_double(1e-9),
             ctypes.c_double(t), xs, _arr(u), _arr(p), ctypes.byref(loss))
    return mode, list(xs)[:len(x)], loss.value


# ------------------------------------------------------------------ hand results
def rectifier_hand(mode_on, t, q):
    """(q', v, i, guard) of the rectifier: diode on, v = Vm sin(w t) and q = C v so
    q' = C Vm w cos(w t), i = q' + v/R, guard i; off, q' = -q/(R C), i = 0, guard v - Vs."""
    vs = VM * math.sin(W * t)
    if mode_on:
        dq = C * VM * W * math.cos(W * t)
        return dq, vs, dq + vs / R, dq + vs / R
    return -q / (R * C), q / C, 0.0, q / C - vs


def clutch_lock_hand(w1, w2):
    """Locking: total momentum conserved, common velocity, energy lost (Newton)."""
    wc = (J1 * w1 + J2 * w2) / (J1 + J2)
    return [J1 * wc, J2 * wc], J1 * J2 * (w1 - w2) ** 2 / (2 * (J1 + J2))


# ------------------------------------------------------------------ tests
@needs_cc
def test_c_rectifier_modes_against_the_hand_rates_and_guards(c_libs):
    lib, code = c_libs["rect"]
    sp = code.prepared
    assert sp.parameter_names == ("C", "R", "Vm", "w") and sp.state_names == ("q_C",)
    p = [C, R, VM, W]
    for k, on in enumerate(sp.mode_on):
        for t, q in ((1e-3, 3e-4), (7e-3, 9e-4)):
            dq, v, i, g = rectifier_hand(on, t, q)
            assert _call(lib, "rect_derivatives", k, t, [q], [], p, 1) == pytest.approx([dq], rel=1e-12)
            assert _call(lib, "rect_outputs", k, t, [q], [], p, 2) == pytest.approx([v, i], rel=1e-12, abs=1e-15)
            assert _call(lib, "rect_guards", k, t, [q], [], p, 1) == pytest.approx([g], rel=1e-12)


@needs_cc
def test_c_clutch_lock_conserves_momentum_and_reports_the_loss(c_libs):
    lib, code = c_libs["clutch"]
    sp = code.prepared
    w1, w2 = 1.0, 3.0
    locked = sp.mode_on.index(0)                      # K off: engaged
    mode, x, loss = _select(lib, "clutch", 0, 0, 0, TL, [J1 * w1, J2 * w2], [1.0], [J1, J2, TL])
    q_new, lost = clutch_lock_hand(w1, w2)
    assert mode == locked
    assert x == pytest.approx(q_new, rel=1e-14) and loss == pytest.approx(lost, rel=1e-14)
    # engaged: (J1 + J2) w' = tau, split by the inertias; the guard t - t_lock
    assert _call(lib, "clutch_derivatives", locked, 2.0, x, [1.0], [J1, J2, TL], 2) == \
        pytest.approx([J1 / (J1 + J2), J2 / (J1 + J2)], rel=1e-14)
    assert _call(lib, "clutch_guards", locked, 2.0, x, [1.0], [J1, J2, TL], 1) == pytest.approx([2.0 - TL])


@needs_cc
def test_c_buck_and_end_stop_compile_strictly_and_name_their_modes(c_libs):
    _, code = c_libs["buck"]
    assert "#define BUCK_NMODES 3" in code.header and '"D off, S on"' in code.source
    _, code = c_libs["stop"]
    assert code.prepared.state_names == ("p_m", "q_k", "x")   # x: the integrated displacement


def test_python_rectifier_diode_turns_off_and_on_where_its_guard_says():
    ns = python_module(rectifier())
    p = [C, R, VM, W]
    on, off = ns["MODE_ON"].index(1), ns["MODE_ON"].index(0)
    for k, mask in ((on, 1), (off, 0)):
        dq, _, _, g = rectifier_hand(mask, 2e-3, 5e-4)
        assert ns["derivatives"](k, 2e-3, [5e-4], [], p) == pytest.approx([dq], rel=1e-12)
        assert ns["guards"](k, 2e-3, [5e-4], [], p) == pytest.approx([g], rel=1e-12)
    # the diode's current falls through zero at tan(w t) = -w R C: the diode turns off, and its
    # charge C Vm sin(w t) is kept (no loss)
    t_off = (math.pi - math.atan(W * R * C)) / W
    q = C * VM * math.sin(W * t_off)
    mode, x, loss = ns["select"](0, ns["SELF_SWITCHED"], ns["SELF_SWITCHED"], 1e-9, t_off + 1e-6, [q], [], p)
    assert mode == off and x == [q] and loss == 0.0
    # blocking with v = 2 V above a source at 0 V: entering "on" would need v = 0, losing C v^2/2
    # of energy; "off" is consistent (its guard v - Vs > 0), so it stays off
    mode, x, loss = ns["select"](1, ns["SELF_SWITCHED"], ns["SELF_SWITCHED"], 1e-9, 0.0, [2 * C], [], p)
    assert mode == off and loss == 0.0


def test_python_clutch_lock_matches_newton():
    ns = python_module(clutch())
    mode, x, loss = ns["select"](0, 0, 0, 1e-9, TL, [J1 * 1.0, J2 * 3.0], [1.0], [J1, J2, TL])
    q_new, lost = clutch_lock_hand(1.0, 3.0)
    assert ns["MODES"][mode] == "K off"
    assert x == pytest.approx(q_new, rel=1e-14) and loss == pytest.approx(lost, rel=1e-14)
    assert ns["outputs"](mode, 1.5, x, [1.0], [J1, J2, TL]) == pytest.approx([7 / 3, 7 / 3])


@pytest.mark.skipif(OCTAVE is None, reason="octave not installed")
def test_matlab_modes_in_octave_against_the_hand_results(tmp_path):
    (tmp_path / "clutch_sw.m").write_text(generate_switched_matlab(clutch(), name="clutch_sw"))
    (tmp_path / "rect_sw.m").write_text(generate_switched_matlab(rectifier(), name="rect_sw"))
    script = (
        "info = clutch_sw(); k = find(info.mode_on == 0);"
        "[xd, y, g, xn, H] = clutch_sw(k, 1.5, [1; 6], 1, struct('J1', 1, 'J2', 2, 't_lock', 1));"
        "printf('%.17g ', xd, y, g, xn, H); printf('\\n');"
        "info = rect_sw();"
        "for k = 1:2 [xd, y, g] = rect_sw(k, 2e-3, 5e-4, [], [1e-4; 100; 10; 100*pi]);"
        "printf('%d %.17g %.17g %.17g %.17g ', info.mode_on(k), xd, y, g); end; printf('\\n');")
    out = subprocess.run([OCTAVE, "--no-gui", "--quiet", "--norc", "--no-history", "--eval", script],
                         cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    clutch_line, rect_line = out.stdout.strip().splitlines()
    xd1, xd2, w1, w2, g, xn1, xn2, h = map(float, clutch_line.split())
    q_new, _ = clutch_lock_hand(1.0, 3.0)
    # engaged: (J1 + J2) w' = tau split by the inertias; w = p_J1/J1; guard t - t_lock; energy
    assert [xd1, xd2, w1, w2, g] == pytest.approx([1 / 3, 2 / 3, 1.0, 1.0, 0.5], rel=1e-15)
    assert [xn1, xn2] == pytest.approx(q_new, rel=1e-15)
    assert h == pytest.approx(1 / 2 + 36 / 4, rel=1e-15)
    vals = rect_line.split()
    for j in range(2):
        on, dq, v, i, g = int(vals[5 * j]), *map(float, vals[5 * j + 1:5 * j + 5])
        assert [dq, v, i, g] == pytest.approx(list(rectifier_hand(on, 2e-3, 5e-4)), rel=1e-13, abs=1e-15)


def test_linear_capacitors_joined_share_their_charge():
    k = sympy.Symbol("k", positive=True)
    g = bg.BondGraph("caps")
    g.add(bg.Zero("v1"), bg.C("C1"), bg.One("s"), bg.Zero("v2"), bg.C("C2", stiffness=k),
          ControlledSwitch("S", gate=bg.t - 1))
    for tail, head in [("v1", "C1"), ("v1", "s"), ("s", "v2"), ("v2", "C2"), ("s", "S")]:
        g.connect(tail, head)
    ns = python_module(SwitchedModel(g))
    c1, kk, q1, q2 = 2.0, 0.25, 3.0, 1.0
    mode, x, loss = ns["select"](1, 0, 0, 1e-9, 1.0, [q1, q2], [], [c1, kk])
    assert ns["MODES"][mode] == "S on"
    # equal voltages q1'/C1 = k q2' with q1' + q2' = q1 + q2 (charge conserved, Kirchhoff)
    q2n = (q1 + q2) / (1 + c1 * kk)
    assert x == pytest.approx([q1 + q2 - q2n, q2n], rel=1e-14)
    e_before = q1**2 / (2 * c1) + kk * q2**2 / 2
    e_after = x[0] ** 2 / (2 * c1) + kk * x[1] ** 2 / 2
    assert loss == pytest.approx(e_before - e_after, rel=1e-12) and loss > 0


def test_a_nonlinear_re_initialisation_is_refused_naming_the_mode():
    k, k3 = sympy.symbols("k k3", positive=True)
    g = bg.BondGraph("caps")
    g.add(bg.Zero("v1"), bg.C("C1"), bg.One("s"), bg.Zero("v2"), bg.C("C2", law=k * bg.q + k3 * bg.q**3),
          ControlledSwitch("S", gate=bg.t - 1))
    for tail, head in [("v1", "C1"), ("v1", "s"), ("s", "v2"), ("v2", "C2"), ("s", "S")]:
        g.connect(tail, head)
    with pytest.raises(SwitchedExportError, match=r"model 'caps', mode \(S on\): C2 .* not a linear map"):
        generate_switched_python(SwitchedModel(g))
    with pytest.raises(bg.BondGraphError):
        generate_switched_c(SwitchedModel(g))


def test_not_a_switched_model_is_refused():
    g = bg.BondGraph("m")
    g.add(bg.Se("F"), bg.I("m"))
    g.connect("F", "m")
    with pytest.raises(bg.BondGraphError, match="expected a switched model"):
        generate_switched_c(bg.derive(g))


def test_a_mode_needing_input_derivatives_is_refused_naming_it():
    # the source as an input: with the diode on, the capacitor follows it, i_C = C dVs/dt
    g = bg.BondGraph("rect_in")
    g.add(bg.Se("Vs"), bg.One("i"), Diode("D", on=True), bg.Zero("v"), bg.R("R"), bg.C("C"))
    for tail, head in [("Vs", "i"), ("i", "D"), ("i", "v"), ("v", "R"), ("v", "C")]:
        g.connect(tail, head)
    with pytest.raises(SwitchedExportError, match=r"mode \(D on\).*time derivatives of the inputs dVs/dt"):
        generate_switched_c(SwitchedModel(g))
