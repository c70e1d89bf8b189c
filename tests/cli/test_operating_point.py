"""Operating points on the command line (issue 14): ``--trim`` and ``--operating-point FILE``.

Hand derivations, written here:

* Pendulum ``J theta'' = T - b theta' - m g l sin(theta)``, states
  ``(p_J, q_grav)`` with ``p_J = J theta'``, ``q_grav = theta``: equilibria
  ``theta = 0`` (hanging) and ``pi`` (upright) at ``T = 0``; Jacobian
  ``A = [[-b/J, -m g l cos(theta0)], [1/J, 0]]``, so the entry ``A[0][1]``
  flips sign from ``-m g l`` to ``+m g l``, ``B = [[1], [0]]``.  The transfer
  function ``theta/T = 1/(J s^2 + b s + m g l cos(theta0))``.
* Mass ``m`` hanging on a spring of compliance ``c`` with a damper ``b``,
  loaded by its weight ``m g``: ``q_c = m g c``, ``p_m = 0``;
  ``A = [[-b/m, -1/c], [1/m, 0]]``.
* DC motor at constant voltage ``V``: ``omega = K V/(K^2 + Ra b)``,
  ``i = (V - K omega)/Ra``, ``p_J = J omega``, ``p_La = La i``;
  ``A = [[-Ra/La, -K/J], [K/La, -b/J]]``.
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from bondgraph.cli import main

PEND = {"m": 1.0, "g": 9.81, "l": 0.5, "J": 0.25, "b": 0.1}
HANG = {"m": 2.0, "g": 9.81, "c": 0.01, "b": 1.0}
MOTOR = {"Ra": 2.0, "La": 1e-3, "K": 0.1, "J": 0.01, "b": 1e-3}

PENDULUM_FILE = f'''
import sympy
import bondgraph as bg
from bondgraph.modelfile import ModelDefinition

def model():
    m, g, l = sympy.symbols("m g l", positive=True)
    gr = bg.BondGraph("pendulum")
    w = bg.One("w")
    gr.add(bg.Se("T"), w, bg.I("J"), bg.R("b"), bg.C("grav", law=m * g * l * sympy.sin(bg.q)))
    for t, h in [("T", w), (w, "J"), (w, "b"), (w, "grav")]:
        gr.connect(t, h)
    return ModelDefinition(gr, {{"theta": bg.displacement("grav")}}, {PEND!r})
'''

HANGING_FILE = f'''
import sympy
import bondgraph as bg
from bondgraph.modelfile import ModelDefinition

def model():
    m, g = sympy.symbols("m g", positive=True)
    gr = bg.BondGraph("hanging")
    v = bg.One("v")
    gr.add(bg.Se("W", value=m * g), v, bg.I("m", m), bg.C("c"), bg.R("b"))
    for t, h in [("W", v), (v, "m"), (v, "c"), (v, "b")]:
        gr.connect(t, h)
    return ModelDefinition(gr, {{"x": bg.displacement("c")}}, {HANG!r})
'''

MOTOR_FILE = f'''
import bondgraph as bg
from bondgraph.modelfile import ModelDefinition

def model():
    g = bg.BondGraph("dc")
    i, w = bg.One("i"), bg.One("w")
    g.add(bg.Se("V"), i, bg.R("Ra"), bg.I("La"), bg.GY("K"), w, bg.I("J"), bg.R("b"))
    for t, h in [("V", i), (i, "Ra"), (i, "La"), (i, "K"), ("K", w), (w, "J"), (w, "b")]:
        g.connect(t, h)
    return ModelDefinition(g, {{"omega": bg.flow("J")}}, {MOTOR!r})
'''


@pytest.fixture
def files(tmp_path):
    out = {}
    for name, text in (("pendulum", PENDULUM_FILE), ("hanging", HANGING_FILE), ("motor", MOTOR_FILE)):
        path = tmp_path / f"{name}.py"
        path.write_text(text)
        out[name] = str(path)
    (tmp_path / "out").mkdir()
    return out


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return code, out, err


def exported(capsys, tmp_path, *argv):
    target = tmp_path / "out" / "plant.json"
    code, out, err = run(capsys, "export", *argv, "-o", target)
    assert code == 0, err
    return json.loads(target.read_text()), err


def note_values(err):
    """``name = value`` pairs of the operating point noted on stderr."""
    line = next(s for s in err.splitlines() if s.startswith("note: operating point"))
    return {k: float(v) for k, v in re.findall(r"(\w+) = (-?[0-9.e+-]+)", line)}


# ----------------------------------------------------------------------------- trim
@pytest.mark.parametrize("guess, theta0", [(0.3, 0.0), (2.8, math.pi)])
def test_pendulum_trim_gives_the_hand_jacobian(capsys, tmp_path, files, guess, theta0):
    plant, err = exported(capsys, tmp_path, files["pendulum"], "--trim", "--guess",
                          f"q_grav={guess}")
    J, b, mgl = PEND["J"], PEND["b"], PEND["m"] * PEND["g"] * PEND["l"]
    hand = [[-b / J, -mgl * math.cos(theta0)], [1 / J, 0.0]]
    np.testing.assert_allclose(plant["A"], hand, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(plant["B"], [[1.0], [0.0]])
    np.testing.assert_allclose(plant["C"], [[0.0, 1.0]])
    assert plant["A"][0][1] == pytest.approx(-mgl if theta0 == 0 else mgl)   # g/l sign flip
    point = note_values(err)
    assert point["q_grav"] == pytest.approx(theta0, abs=1e-12) and point["T"] == 0


def test_pendulum_trim_under_a_torque(capsys, tmp_path, files):
    T = 1.0
    plant, err = exported(capsys, tmp_path, files["pendulum"], "--trim", "--input-value", f"T={T}")
    theta0 = math.asin(T / (PEND["m"] * PEND["g"] * PEND["l"]))
    assert note_values(err)["q_grav"] == pytest.approx(theta0, rel=1e-12)
    mgl = PEND["m"] * PEND["g"] * PEND["l"]
    assert plant["A"][0][1] == pytest.approx(-mgl * math.cos(theta0), rel=1e-12)


def test_hanging_mass_spring(capsys, tmp_path, files):
    # without an option: the plant about the equilibrium of the constant weight, stored
    m, g, c, b = HANG["m"], HANG["g"], HANG["c"], HANG["b"]
    plain, err = exported(capsys, tmp_path, files["hanging"])
    assert "deviations about the operating point" in err
    assert plain["operating_point"]["states"]["q_c"] == pytest.approx(m * g * c, rel=1e-12)
    plant, err = exported(capsys, tmp_path, files["hanging"], "--trim")
    point = note_values(err)
    assert point["q_c"] == pytest.approx(m * g * c, rel=1e-12) and point["p_m"] == 0
    np.testing.assert_allclose(plant["A"], [[-b / m, -1 / c], [1 / m, 0.0]], rtol=1e-12)


def test_dc_motor_at_constant_voltage(capsys, tmp_path, files):
    V = 12.0
    plant, err = exported(capsys, tmp_path, files["motor"], "--trim", "--input-value", f"V={V}")
    Ra, La, K, J, b = (MOTOR[k] for k in ("Ra", "La", "K", "J", "b"))
    omega = K * V / (K ** 2 + Ra * b)
    point = note_values(err)
    assert point["p_J"] == pytest.approx(J * omega, rel=1e-12)
    assert point["p_La"] == pytest.approx(La * (V - K * omega) / Ra, rel=1e-12)
    np.testing.assert_allclose(plant["A"], [[-Ra / La, -K / J], [K / La, -b / J]], rtol=1e-12)


def test_tf_at_the_upright_pendulum(capsys, files):
    code, out, err = run(capsys, "tf", files["pendulum"], "--numeric", "--trim", "--guess",
                         "q_grav=3")
    assert code == 0, err
    J, b, mgl = PEND["J"], PEND["b"], PEND["m"] * PEND["g"] * PEND["l"]
    # 1/(J s^2 + b s - m g l): poles from the quadratic formula
    disc = math.sqrt(b * b + 4 * J * mgl)
    for pole in ((-b + disc) / (2 * J), (-b - disc) / (2 * J)):
        assert f"{pole:.4g}" in out, out
    code, out, err = run(capsys, "tf", files["pendulum"], "--trim")
    assert code == 2 and "add --numeric" in err


# ----------------------------------------------------------------------------- files
def op_file(tmp_path, text, suffix=".toml"):
    path = tmp_path / f"op{suffix}"
    path.write_text(text)
    return path


def test_operating_point_file(capsys, tmp_path, files):
    upright = op_file(tmp_path, f"[states]\np_J = 0.0\nq_grav = {math.pi!r}\n[inputs]\nT = 0.0\n")
    plant, _ = exported(capsys, tmp_path, files["pendulum"], "--operating-point", upright)
    mgl = PEND["m"] * PEND["g"] * PEND["l"]
    assert plant["A"][0][1] == pytest.approx(mgl, rel=1e-12)
    # symbolic transfer function at the file's point: 1/(J s^2 + b s - g l m)
    code, out, err = run(capsys, "tf", files["pendulum"], "--operating-point", upright)
    assert code == 0, err
    assert "g*l*m" in out.replace(" ", "") and "-g*l*m" in out.replace(" ", "")
    # JSON works the same; a point that is not an equilibrium is refused (exit 1)
    tilted = op_file(tmp_path, '{"states": {"p_J": 0, "q_grav": 1.0}, "inputs": {"T": 0}}', ".json")
    code, _, err = run(capsys, "export", files["pendulum"], "--operating-point", tilted,
                       "-o", tmp_path / "out" / "p.json")
    assert code == 1 and "not an equilibrium" in err and "dp_J/dt" in err


BAD_FILES = [
    ("[states]\np_J = 0.0\ntheta = 0.0\n[inputs]\nT = 0.0\n",
     r"no state named 'theta'; valid states: p_J, q_grav"),
    ("[states]\np_J = 0.0\n[inputs]\nT = 0.0\n", r"no value for the state q_grav"),
    ("[states]\np_J = 0.0\nq_grav = 0.0\n", r"no value for the input T"),
    ('[states]\np_J = 0.0\nq_grav = "zero"\n[inputs]\nT = 0.0\n',
     r"state 'q_grav' must be a number; got str 'zero'"),
    ("[states]\np_J = 0.0\nq_grav = nan\n[inputs]\nT = 0.0\n", r"state 'q_grav' must be finite"),
    ("[inputs]\nT = 0.0\n", r"has no states table"),
    ("[states]\np_J = 0.0\nq_grav = 0.0\n[params]\nm = 1.0\n", r"unknown table 'params'"),
    ("[states\n", r"op\.toml"),
]


@pytest.mark.parametrize("text, words", BAD_FILES,
                         ids=["wrong-name", "missing-state", "missing-input", "text", "nan",
                              "no-states", "extra-table", "syntax"])
@pytest.mark.parametrize("command", ["export", "tf"])
def test_bad_operating_point_files_are_usage_errors(capsys, tmp_path, files, text, words, command):
    path = op_file(tmp_path, text)
    argv = ["--numeric"] if command == "tf" else ["-o", tmp_path / "out" / "p.json"]
    code, out, err = run(capsys, command, files["pendulum"], "--operating-point", path, *argv)
    assert code == 2, err
    assert err.startswith("error: ") and re.search(words, err), err
    assert f"'{path}'" in err                                   # names the file
    assert list((tmp_path / "out").iterdir()) == []


@pytest.mark.parametrize("argv, words", [
    (["--trim", "--input-value", "Tau=1"], r"--input-value Tau=\.\.\.: the model has no input named "
                                           r"'Tau'; valid inputs: T"),
    (["--trim", "--guess", "theta=1"], r"no state named 'theta'"),
    (["--trim", "--input-value", "T"], r"expected NAME=VALUE"),
    (["--trim", "--input-value", "T=abc"], r"must be a finite number"),
    (["--guess", "q_grav=1"], r"--guess only applies with --trim"),
    (["--trim", "--operating-point", "x.toml"], r"not both"),
    (["--trim", "-f", "c"], r"apply to the numeric plant formats"),
])
def test_bad_operating_point_options_are_usage_errors(capsys, tmp_path, files, argv, words):
    target = tmp_path / "out" / ("p.c" if "c" in argv else "p.json")
    code, _, err = run(capsys, "export", files["pendulum"], *argv, "-o", target)
    assert code == 2 and re.search(words, err), err
    assert list((tmp_path / "out").iterdir()) == []


def test_nonlinear_model_without_a_point_names_the_options(capsys, tmp_path, files):
    code, _, err = run(capsys, "tf", files["pendulum"])
    assert code == 1 and "nonlinear" in err
    assert "--operating-point FILE" in err and "--trim" in err
    code, _, err = run(capsys, "export", files["pendulum"], "-o", tmp_path / "out" / "p.npz")
    assert code == 1 and "--operating-point FILE" in err and "--trim" in err
    assert list((tmp_path / "out").iterdir()) == []


def test_point_that_holds_only_at_the_parameter_values(capsys, tmp_path, files):
    """Under a torque T the equilibrium theta0 = asin(T/(m g l)) depends on the parameters."""
    T = 1.0
    mgl, J, b = PEND["m"] * PEND["g"] * PEND["l"], PEND["J"], PEND["b"]
    theta0 = math.asin(T / mgl)
    path = op_file(tmp_path, f"[states]\np_J = 0.0\nq_grav = {theta0!r}\n[inputs]\nT = {T!r}\n")
    code, _, err = run(capsys, "tf", files["pendulum"], "--operating-point", path)
    assert code == 1 and "not an equilibrium" in err and "--numeric" in err
    code, out, err = run(capsys, "tf", files["pendulum"], "--operating-point", path, "--numeric")
    assert code == 0, err
    # 1/(J s^2 + b s + m g l cos(theta0)): complex poles -b/(2J) +- j sqrt(4 J k - b^2)/(2J)
    k = mgl * math.cos(theta0)
    wn = math.sqrt(k / J)
    assert f"{wn:.4g}" in out and f"{b / (2 * math.sqrt(k * J)):.4g}" in out, out
