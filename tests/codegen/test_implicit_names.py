"""Generated code of an implicit model whose names collide with the Newton solver's own.

The diode circuit of ``test_implicit_codegen.py`` with its parameters named
after the identifiers the generated solvers use (``z``, ``g``, ``jac``,
``status``, ``i``, ``solve_algebraic``, ``_Z``, ``bg_zlast``,
``plant_solve``...) and one named by a text holding quotes, ``%s``, ``*/``,
``??/`` and a newline.  The C must compile with ``-Wall -Wextra -pedantic
-Werror``, and every target must still give the values of the independent
``brentq`` solve of the hand-written loop equation.
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
from bondgraph.codegen import generate_c, generate_python, write_matlab

CC = shutil.which("cc") or shutil.which("gcc")
OCTAVE = shutil.which("octave-cli") or shutil.which("octave")
PTR = ctypes.POINTER(ctypes.c_double)
HOSTILE = 'a*/ "b" %s ??/\n\'c\''
#: the parameters, each named like an identifier of one of the generated solvers
NAMES = {"R": "z", "C": "jac", "Is": "solve_algebraic", "Vt": "bg_zlast", "Rs": "plant_solve",
         "Rt": "status", "Rh": HOSTILE}


def model() -> bg.Model:
    S = {k: sympy.Symbol(v, positive=True) for k, v in NAMES.items()}
    g = bg.BondGraph("hostile")
    g.add(bg.Se("V"), bg.One("s"), bg.R("R", S["R"] + S["Rs"] + S["Rt"] + S["Rh"]),
          bg.R("i", inverse=S["Is"] * (sympy.exp(bg.e / S["Vt"]) - 1)), bg.C("g", S["C"]))
    for t, h in [("V", "s"), ("s", "R"), ("s", "i"), ("s", "g")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"_Z": bg.flow("i")})


def values(rng) -> dict:
    return {HOSTILE: rng.uniform(0, 100), "z": rng.uniform(100, 600), "plant_solve": rng.uniform(100, 600),
            "status": rng.uniform(0, 800),
            "jac": rng.uniform(1e-7, 1e-5), "solve_algebraic": rng.uniform(1e-13, 1e-11),
            "bg_zlast": rng.uniform(0.02, 0.03)}


def hand(q, V, v):
    R = v["z"] + v["plant_solve"] + v["status"] + v[HOSTILE]
    w = V - q / v["jac"]
    Is, Vt = v["solve_algebraic"], v["bg_zlast"]
    vd = brentq(lambda e: R * Is * math.expm1(e / Vt) + e - w, -abs(w) - 1, abs(w) + 1, xtol=1e-15)
    return Is * math.expm1(vd / Vt)


def points(count=6):
    rng = np.random.default_rng(11)
    for _ in range(count):
        v = values(rng)
        V, w = rng.uniform(-5, 5), rng.uniform(0.2, 3.0)
        yield v["jac"] * (V - w), V, v


def vector(m, v):
    return np.array([v[p.name] for p in m.parameters])


@pytest.mark.skipif(CC is None, reason="no C compiler (cc) on PATH")
def test_c_with_clashing_names(tmp_path):
    m = model()
    assert len(m.algebraic) == 1
    code = generate_c(m, name="plant")
    (tmp_path / "plant.c").write_text(code.source)
    (tmp_path / "plant.h").write_text(code.header)
    lib = tmp_path / "libplant.so"
    subprocess.run([CC, "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-shared", "-fPIC", "-o",
                    str(lib), str(tmp_path / "plant.c"), "-lm"], check=True, capture_output=True, text=True)
    c = ctypes.CDLL(str(lib))
    c.plant_status_message.restype = ctypes.c_char_p
    z = np.zeros(1)
    for q, V, v in points():
        xdot, p = np.zeros(1), vector(m, v)
        assert c.plant_derivatives(ctypes.c_double(0.0), np.array([q]).ctypes.data_as(PTR),
                                   np.array([V]).ctypes.data_as(PTR), p.ctypes.data_as(PTR),
                                   z.ctypes.data_as(PTR), xdot.ctypes.data_as(PTR)) == 0
        assert xdot[0] == pytest.approx(hand(q, V, v), rel=1e-9)
    message = c.plant_status_message(2).decode("utf-8")
    assert message.startswith("model 'hostile': ") and f"{m.algebraic_names[0]} (the flow of" in message


def test_python_with_clashing_names():
    m = model()
    ns: dict = {}
    exec(generate_python(m), ns)
    for q, V, v in points():
        assert ns["derivatives"](0.0, [q], [V], v)[0] == pytest.approx(hand(q, V, v), rel=1e-9)
        assert ns["outputs"](0.0, [q], [V], v)[0] == pytest.approx(hand(q, V, v), rel=1e-9)
    assert HOSTILE in ns["PARAMETER_NAMES"]


def test_matlab_with_clashing_names(tmp_path):
    if OCTAVE is None:      # pragma: no cover - depends on the machine
        pytest.skip("octave not installed")
    m = model()
    write_matlab(m, tmp_path / "plant.m")
    pts = list(points(4))
    script = "\n".join(f"[xd, y] = plant(0, {q!r}, {V!r}, [{'; '.join(repr(float(x)) for x in vector(m, v))}]); "
                       "printf('%.17g %.17g\\n', xd, y);" for q, V, v in pts)
    out = subprocess.run([OCTAVE, "--no-gui", "--quiet", "--norc", "--no-history", "--eval", script],
                         cwd=tmp_path, capture_output=True, text=True, timeout=120, check=True)
    for line, (q, V, v) in zip(out.stdout.splitlines(), pts):
        xd, y = (float(s) for s in line.split())
        assert xd == pytest.approx(hand(q, V, v), rel=1e-9) and y == pytest.approx(xd, rel=1e-9)
