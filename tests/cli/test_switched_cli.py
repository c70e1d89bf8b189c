"""The command line on a switched model file (models/buck.py): every command, no silent mode.

Hand references, buck converter (Vin = 10 V, L = C = 1e-4, R = 5 ohm, duty 0.5, T = 10 us):

* switch on, diode off (Kirchhoff): L diL/dt = Vin - vC, C dvC/dt = iL - vC/R, so with
  x = (p_L, q_C): x' = A x + b, A = [[0, -1/C], [1/L, -1/(R C)]], b = (Vin, 0);
* switch off, diode on (freewheeling, iL > 0): the same A with b = 0;
* state-space average with duty d: x' = A x + (d Vin, 0), so
  vo/d = Vin / (L C s^2 + (L/R) s + 1).
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg
import sympy

import bondgraph as bg
from bondgraph.cli import main
from bondgraph.cli._parser import SWEEP_DESIGNS, SWEEP_METRICS

ROOT = Path(__file__).resolve().parents[2]
BUCK = str(ROOT / "models" / "buck.py")
CLUTCH = str(ROOT / "models" / "clutch.py")
VIN, L, C, R, DUTY, T = 10.0, 1e-4, 1e-4, 5.0, 0.5, 1e-5
A = np.array([[0.0, -1 / C], [1 / L, -1 / (R * C)]])


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def affine(x0, b, t):
    """x(t) of x' = A x + b from x0 (A invertible): e^{At} x0 + A^-1 (e^{At} - I) b."""
    E = scipy.linalg.expm(A * t)
    return E @ x0 + np.linalg.solve(A, (E - np.eye(2)) @ b)


# ----------------------------------------------------------------------------- refusals
@pytest.mark.parametrize("argv", [
    ["tf", BUCK, "-y", "v"],
    ["tf", BUCK, "-y", "v", "--numeric"],
    ["export", BUCK, "-o", "{tmp}/buck.json"],
    ["export", BUCK, "-o", "{tmp}/buck.c"],
], ids=["tf", "tf-numeric", "export-json", "export-c"])
def test_command_needing_one_mode_refuses_and_lists_the_modes(argv, capsys, tmp_path):
    code, out, err = run(capsys, *[a.format(tmp=tmp_path) for a in argv])
    assert code == 1 and out == "" and "Traceback" not in err
    assert "is switched" in err and "--mode" in err and "--average" in err
    for mode in ("on=S (D off, S on)", "on=D (D on, S off)", "on= (D off, S off)"):
        assert mode in err
    assert not list(tmp_path.iterdir())             # nothing written


def test_mode_or_average_on_a_model_without_switches_is_a_usage_error(capsys):
    code, _, err = run(capsys, "tf", str(ROOT / "tests" / "data" / "dc_motor.py"), "--mode", "on=S")
    assert code == 2 and "no switch" in err


@pytest.mark.parametrize("mode, words", [
    ("on=S,D", "not consistent"), ("on=X", "no switch 'X'"), ("up=S", "expected on=NAMES"),
    ("on=S;off=S", "both on and off"), ("on=S;off=", "give every switch"),
], ids=["inconsistent", "unknown", "syntax", "both", "incomplete"])
def test_bad_modes_are_refused(mode, words, capsys):
    code, _, err = run(capsys, "equations", BUCK, "--mode", mode)
    assert code in (1, 2) and words in err


# ----------------------------------------------------------------------------- equations
def test_equations_print_every_mode(capsys):
    code, out, _ = run(capsys, "equations", BUCK)
    assert code == 0
    assert "mode on=S (D off, S on):" in out and "mode on=D (D on, S off):" in out
    assert "mode on=S,D (D on, S on): not consistent" in out
    on = out.split("mode on=S (D off, S on):")[1]
    assert "dp_L/dt = Vin - q_C/C" in on          # L diL/dt = Vin - vC
    freewheel = out.split("mode on=D (D on, S off):")[1].split("mode on=S")[0]
    assert "dp_L/dt = -q_C/C" in freewheel


def test_equations_of_one_mode_and_of_the_average(capsys):
    code, out, _ = run(capsys, "equations", BUCK, "--mode", "off=S")      # S off, D on
    assert code == 0 and "(mode off=S)" in out and "dp_L/dt = -q_C/C" in out
    code, out, _ = run(capsys, "equations", BUCK, "--average", "d", "on=S", "on=D")
    assert code == 0 and "inputs (1): d" in out and "dp_L/dt = Vin*d - q_C/C" in out


# ----------------------------------------------------------------------------- tf
def test_averaged_tf_is_the_hand_duty_to_output_function(capsys):
    code, out, err = run(capsys, "tf", BUCK, "--average", "d", "on=S", "on=D", "-u", "d", "-y", "v")
    assert code == 0, err
    lhs, rhs = out.splitlines()[0].split(" = ", 1)
    assert lhs == "v/d"
    Vin, Ls, Cs, Rs, s = sympy.symbols("Vin L C R s", positive=True)
    got = sympy.parse_expr(rhs, local_dict={"Vin": Vin, "L": Ls, "C": Cs, "R": Rs, "s": s})
    hand = Vin / (Ls * Cs * s**2 + (Ls / Rs) * s + 1)
    assert sympy.simplify(got - hand) == 0


def test_averaged_plant_export_matches_the_hand_function(tmp_path, capsys):
    out = tmp_path / "avg.json"
    code, _, err = run(capsys, "export", BUCK, "--average", "d", "on=S", "on=D", "-o", str(out))
    assert code == 0, err
    from bondgraph.export import load_json

    plant = load_json(out)
    assert plant.input_names == ("d",) and "v" in plant.output_names
    row = plant.output_names.index("v")
    for w in (0.0, 1e3, 1e4, 1e5):
        s = 1j * w
        G = (plant.C @ np.linalg.solve(s * np.eye(2) - plant.A, plant.B) + plant.D)[row, 0]
        assert G == pytest.approx(VIN / (L * C * s**2 + (L / R) * s + 1), rel=1e-12)


# ----------------------------------------------------------------------------- fmu
def test_fmu_of_the_switched_model_has_every_mode_and_event_indicators(tmp_path, capsys):
    fmpy = pytest.importorskip("fmpy")
    out = tmp_path / "buck.fmu"
    code, stdout, err = run(capsys, "export", BUCK, "-f", "fmu", "-o", str(out), "--kind", "me")
    assert code == 0, err
    assert "3 modes" in stdout
    md = fmpy.read_model_description(str(out))
    assert md.numberOfEventIndicators == 2          # the PWM gate of S and the diode's guard
    names = {v.name for v in md.modelVariables}
    assert {"p_L", "q_C", "v", "iL", "duty", "T"} <= names


# ----------------------------------------------------------------------------- draw
def test_draw_shows_the_initial_mode_or_the_chosen_one(tmp_path, capsys):
    first, second = tmp_path / "a.svg", tmp_path / "b.svg"
    assert run(capsys, "draw", BUCK, "-o", str(first))[0] == 0
    assert run(capsys, "draw", BUCK, "-o", str(second), "--mode", "on=D")[0] == 0
    a, b = first.read_text(), second.read_text()
    assert "buck (D off, S on)" in a and "buck (D on, S off)" in b
    assert ">on<" in a and ">off<" in a
    code, _, err = run(capsys, "draw", BUCK, "-o", str(tmp_path / "c.svg"), "--mode", "on=D,S")
    assert code == 1 and "not consistent" in err and "on=S (D off, S on)" in err


# ----------------------------------------------------------------------------- simulate
def _table(path: Path) -> dict[str, list]:
    rows = list(csv.reader(io.StringIO(path.read_text())))
    return {name: [r[k] for r in rows[1:]] for k, name in enumerate(rows[0])}


def test_simulate_csv_agrees_with_the_hand_solution_and_the_api(tmp_path, capsys):
    out = tmp_path / "buck.csv"
    code, stdout, err = run(capsys, "simulate", BUCK, "-o", str(out), "--t-end", "1e-4",
                            "--points", "201")
    assert code == 0, err
    table = _table(out)
    assert list(table)[:5] == ["t", "v", "iL", "p_L", "q_C"] and list(table)[-1] == "mode"
    t = np.array(table["t"], dtype=float)
    x = np.column_stack([np.array(table[k], dtype=float) for k in ("p_L", "q_C")])
    # first period by hand: on for DUTY*T from rest, then freewheeling
    t_off = DUTY * T
    x_off = affine(np.zeros(2), np.array([VIN, 0.0]), t_off)
    for k in np.flatnonzero(t < T):
        if t[k] < t_off or (t[k] == t_off and table["mode"][k] == "D off, S on"):
            hand = affine(np.zeros(2), np.array([VIN, 0.0]), t[k])
        else:
            hand = affine(x_off, np.zeros(2), t[k] - t_off)
        np.testing.assert_allclose(x[k], hand, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(np.array(table["v"], dtype=float), x[:, 1] / C, rtol=1e-12)
    # and the API gives the same numbers (the command is bondgraph.simulate)
    import sys
    sys.path.insert(0, str(ROOT / "models"))
    try:
        import buck
    finally:
        sys.path.remove(str(ROOT / "models"))
    res = bg.simulate(buck.switched(), buck.PARAMETERS, (0.0, 1e-4), t_eval=np.linspace(0, 1e-4, 201),
                      rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(t, res.t, rtol=0, atol=0)
    np.testing.assert_allclose(x[:, 0], res["p_L"], rtol=1e-13, atol=0)
    assert f"{len(res.events)} events" in stdout


def test_simulate_a_smooth_model_with_an_input_against_the_closed_form(tmp_path, capsys):
    model = tmp_path / "rc.py"
    model.write_text(
        "import bondgraph as bg\nfrom bondgraph.modelfile import ModelDefinition\n"
        "def model():\n"
        "    g = bg.BondGraph('rc'); g.add(bg.Se('V'), bg.One('i'), bg.R('R'), bg.C('C'))\n"
        "    for a, b in [('V', 'i'), ('i', 'R'), ('i', 'C')]: g.connect(a, b)\n"
        "    return ModelDefinition(g, {'vC': bg.effort('C')}, {'R': 2.0, 'C': 0.5})\n")
    out, png = tmp_path / "rc.csv", tmp_path / "rc.png"
    code, _, err = run(capsys, "simulate", str(model), "-o", str(out), "--t-end", "3",
                       "--input", "V=2", "--x0", "q_C=0.25", "--signals", "vC,V", "--plot", str(png),
                       "--rtol", "1e-10", "--atol", "1e-12")
    assert code == 0, err
    table = _table(out)
    assert list(table) == ["t", "vC", "V"]
    t = np.array(table["t"], dtype=float)
    # RC = 1 s, vC(0) = q0/C = 0.5: vC = V + (vC0 - V) e^{-t/RC}
    np.testing.assert_allclose(np.array(table["vC"], dtype=float), 2 + (0.5 - 2) * np.exp(-t),
                               rtol=1e-8)
    assert set(table["V"]) == {"2.0"}
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_simulate_parquet_and_bad_options(tmp_path, capsys):
    code, _, err = run(capsys, "simulate", BUCK, "-o", str(tmp_path / "x.txt"), "--t-end", "1e-5")
    assert code == 1 and ".csv or .parquet" in err
    code, _, err = run(capsys, "simulate", BUCK, "-o", str(tmp_path / "x.csv"), "--t-end", "1e-5",
                       "--signals", "vout")
    assert code == 2 and "vout" in err and "iL" in err
    code, _, err = run(capsys, "simulate", BUCK, "-o", str(tmp_path / "x.csv"), "--t-end", "1e-5",
                       "--input", "Vin=3")
    assert code == 2 and "no input" in err
    pa = pytest.importorskip("pyarrow.parquet")
    out = tmp_path / "avg.parquet"
    code, _, err = run(capsys, "simulate", BUCK, "-o", str(out), "--t-end", "1e-3",
                       "--average", "d", "on=S", "on=D", "--input", "d=0.5", "--points", "11")
    assert code == 0, err
    table = pa.read_table(out).to_pydict()
    assert list(table)[:2] == ["t", "v"] and table["d"] == [0.5] * 11


def test_clutch_model_equations_list_both_modes(capsys):
    code, out, _ = run(capsys, "equations", CLUTCH)
    assert code == 0 and "mode on=K (K on):" in out and "mode on= (K off):" in out


def test_sweep_names_are_the_study_packages():
    from bondgraph.study.design import DESIGNS
    from bondgraph.study.metrics import BUILTIN

    assert SWEEP_DESIGNS == tuple(DESIGNS) and SWEEP_METRICS == tuple(BUILTIN)
