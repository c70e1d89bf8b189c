"""The ``bondgraph`` command line, in process (``main([...])``) and once as the installed script.

Numbers are those of the DC motor in tests/data/dc_motor.py (Ra=2, La=0.5, K=0.1,
J=0.02, b=0.2): A = [[-Ra/La, -K/J], [K/La, -b/J]] = [[-4, -5], [0.2, -10]], poles
-7 +- 2 sqrt(2) = -4.172, -9.828.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.io

from bondgraph.cli import load_params, main
from bondgraph.modelfile import ModelDefinition, ModelFileError, load_model

DATA = Path(__file__).resolve().parents[1] / "data"
MOTOR = str(DATA / "dc_motor.py")
SERVO = str(DATA / "servo_partial.py")       # defaults lack J and b
DUFFING = str(DATA / "duffing.py")
HAND_A = [[-4.0, -5.0], [0.2, -10.0]]


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def failed(capsys, *argv):
    code, out, err = run(capsys, *argv)
    assert code == 1, (out, err)
    assert err.startswith("error: ") and "Traceback" not in err
    return err


# ----------------------------------------------------------------------------- model files
def test_load_model_protocol():
    defn = load_model(DATA / "dc_motor.py")
    assert isinstance(defn, ModelDefinition) and defn.name == "dc_motor"
    assert defn.derive().state_names == ("p_La", "p_J") and defn.derive() is defn.derive()
    assert defn.parameters["J"] == 0.02 and "DC motor" in defn.description
    with pytest.raises(TypeError):
        defn.parameters["J"] = 1.0              # read-only mapping


@pytest.mark.parametrize("path, words", [
    ("nothere.py", "does not exist"), ("no_model.py", "defines no function model()"),
    ("bad_return.py", "returned BondGraph; expected"), ("dc_motor.txt", "not a Python file")],
    ids=["missing", "no-model", "bad-return", "not-py"])
def test_load_model_errors(path, words, tmp_path):
    if path == "dc_motor.txt":
        (tmp_path / path).write_text("x")
        full = tmp_path / path
    else:
        full = DATA / path
    with pytest.raises(ModelFileError, match=words) as info:
        load_model(full)
    assert isinstance(info.value, ValueError)


def test_model_file_that_raises(tmp_path):
    (tmp_path / "boom.py").write_text("import bondgraph as bg\ndef model():\n    return bg.I('not valid')\n")
    with pytest.raises(ModelFileError, match=r"model\(\) failed.*not valid"):
        load_model(tmp_path / "boom.py")
    (tmp_path / "syntax.py").write_text("def model(:\n")
    with pytest.raises(ModelFileError, match="syntax error at line 1"):
        load_model(tmp_path / "syntax.py")


def test_definition_validates_defaults():
    defn = load_model(MOTOR)
    with pytest.raises(ModelFileError, match="parameter 'J' must be finite"):
        ModelDefinition(defn.graph, {}, {"J": float("nan")})
    with pytest.raises(ModelFileError, match="must be a bondgraph.BondGraph"):
        ModelDefinition("graph")


# ----------------------------------------------------------------------------- params files
def test_params_json_and_toml(tmp_path):
    (tmp_path / "p.json").write_text('{"J": 0.01, "motor": {"Ra": 3}}')
    (tmp_path / "p.toml").write_text('J = 0.01\n[motor]\nRa = 3\n')
    expected = {"J": 0.01, "motor.Ra": 3.0}
    assert load_params(tmp_path / "p.json") == load_params(tmp_path / "p.toml") == expected


# ----------------------------------------------------------------------------- commands
def test_equations(capsys):
    code, out, _ = run(capsys, "equations", MOTOR)
    assert code == 0
    assert "states (2): p_La, p_J" in out and "J = 0.02" in out
    assert "dp_La/dt = V - Ra*p_La/La - K*p_J/J" in out and "omega = p_J/J" in out
    code, out, _ = run(capsys, "equations", MOTOR, "--latex")
    assert code == 0 and "\\begin{aligned}" in out and "\\dot{p}_{La} &= V" in out


def test_tf_symbolic_and_numeric(capsys):
    code, out, _ = run(capsys, "tf", MOTOR, "--input", "V", "--output", "omega")
    assert code == 0 and "omega/V" in out and "Ra" in out
    code, out, _ = run(capsys, "tf", MOTOR, "-u", "V", "-y", "omega", "--numeric")
    assert code == 0
    assert "-4.172" in out and "-9.828" in out        # -7 +- 2 sqrt(2)
    code, out, _ = run(capsys, "tf", MOTOR, "-u", "V", "-y", "i", "--latex")
    assert code == 0 and "\\frac" in out


def test_export_numeric_formats(tmp_path, capsys):
    for fmt in ("mat", "npz", "json"):
        code, out, _ = run(capsys, "export", MOTOR, "--format", fmt, "-o", str(tmp_path / f"m.{fmt}"))
        assert code == 0 and f"m.{fmt}" in out
    np.testing.assert_array_equal(scipy.io.loadmat(tmp_path / "m.mat")["A"], HAND_A)
    np.testing.assert_array_equal(np.load(tmp_path / "m.npz")["A"], HAND_A)
    assert json.loads((tmp_path / "m.json").read_text())["A"] == HAND_A
    assert sorted(os.listdir(tmp_path)) == ["m.json", "m.mat", "m.npz"]


def test_export_params_override_and_nested_toml(tmp_path, capsys):
    (tmp_path / "p.json").write_text('{"Ra": 4.0}')
    code, _, _ = run(capsys, "export", MOTOR, "--params", str(tmp_path / "p.json"), "-o", str(tmp_path / "a.json"))
    assert code == 0
    assert json.loads((tmp_path / "a.json").read_text())["A"][0][0] == -8.0     # -Ra/La
    (tmp_path / "s.toml").write_text("J = 0.02\nb = 0.2\n[motor]\nRa = 2.0\n")
    code, _, _ = run(capsys, "export", SERVO, "--params", str(tmp_path / "s.toml"), "-o", str(tmp_path / "s.json"))
    assert code == 0
    doc = json.loads((tmp_path / "s.json").read_text())
    assert doc["parameters"]["motor.Ra"] == 2.0 and doc["inputs"] == ["motor.V"]
    assert sorted(np.linalg.eigvals(np.array(doc["A"])).real.round(6))[:2] == [-9.828427, -4.171573]


def test_export_code(tmp_path, capsys):
    code, out, err = run(capsys, "export", DUFFING, "-o", str(tmp_path / "duff.c"), "--name", "duff")
    assert code == 0 and "duff.h" in out
    source = (tmp_path / "duff.c").read_text()
    assert "const double duff_default_parameters[] = {0.3, 2.0, 0.5, 1.0};" in source     # b, k, k3, m
    assert run(capsys, "export", DUFFING, "-f", "m", "-o", str(tmp_path / "duff_ode.m"))[0] == 0
    assert run(capsys, "export", DUFFING, "-o", str(tmp_path / "duff_eqs.py"))[0] == 0
    assert sorted(os.listdir(tmp_path)) == ["duff.c", "duff.h", "duff_eqs.py", "duff_ode.m"]
    # code for a model with incomplete defaults is still generated, without defaults
    code, _, err = run(capsys, "export", SERVO, "-o", str(tmp_path / "servo.py"))
    assert code == 0 and "no defaults" in err


def test_draw(tmp_path, capsys):
    code, out, err = run(capsys, "draw", MOTOR, "-o", str(tmp_path / "m.svg"))
    if code == 1 and "bondgraph.drawing" in err:     # drawing package not installed
        pytest.skip(err)
    assert code == 0 and "<svg" in (tmp_path / "m.svg").read_text()


# ----------------------------------------------------------------------------- bad input
def test_missing_parameter_keeps_old_file(tmp_path, capsys):
    target = tmp_path / "s.json"
    target.write_text("old")
    err = failed(capsys, "export", SERVO, "-o", str(target))
    assert "no value for parameters J, b" in err and "--params" in err
    assert target.read_text() == "old" and os.listdir(tmp_path) == ["s.json"]
    err = failed(capsys, "tf", SERVO, "-y", "omega", "--numeric")
    assert "J, b" in err


@pytest.mark.parametrize("content, words", [
    ('{"Ra": NaN}', "parameter 'Ra' must be finite"), ('{"Ra": "2"}', "parameter 'Ra' must be a number"),
    ('{"Ra": true}', "parameter 'Ra' must be a number"), ('[1, 2]', "must hold a mapping"),
    ('{"Rb": 1.0, "Jx": 2}', "unknown parameter 'Jx' (did you mean 'J'?); unknown parameter 'Rb'"),
    ("{oops", "not valid JSON")],
    ids=["nan", "string", "bool", "list", "unknown", "syntax"])
def test_bad_params_file(tmp_path, capsys, content, words):
    (tmp_path / "p.json").write_text(content)
    err = failed(capsys, "export", MOTOR, "--params", str(tmp_path / "p.json"), "-o", str(tmp_path / "o.mat"))
    assert words in err and "p.json" in err
    assert sorted(os.listdir(tmp_path)) == ["p.json"]


def test_bad_params_file_kinds(tmp_path, capsys):
    assert "does not exist" in failed(capsys, "export", MOTOR, "--params", str(tmp_path / "none.json"),
                                      "-o", str(tmp_path / "o.mat"))
    (tmp_path / "p.yaml").write_text("Ra: 1")
    assert "must be .json or .toml" in failed(capsys, "export", MOTOR, "--params", str(tmp_path / "p.yaml"),
                                              "-o", str(tmp_path / "o.mat"))
    (tmp_path / "p.toml").write_text("Ra = inf\n")
    assert "parameter 'Ra' must be finite" in failed(capsys, "export", MOTOR, "--params",
                                                     str(tmp_path / "p.toml"), "-o", str(tmp_path / "o.mat"))


@pytest.mark.parametrize("model, words", [
    ("nothere.py", "does not exist"), (str(DATA / "no_model.py"), "defines no function model()"),
    (str(DATA / "bad_return.py"), "expected a bondgraph.modelfile.ModelDefinition")],
    ids=["missing", "no-model", "bad-return"])
@pytest.mark.parametrize("command", ["equations", "tf", "export", "draw"])
def test_bad_model_file(tmp_path, capsys, model, words, command):
    outputs = {"export": ["-o", str(tmp_path / "o.json")], "draw": ["-o", str(tmp_path / "o.svg")]}
    extra = outputs.get(command, [])
    assert words in failed(capsys, command, model, *extra)
    assert os.listdir(tmp_path) == []


def test_unknown_signal_names_list_valid_ones(capsys):
    err = failed(capsys, "tf", MOTOR, "-u", "V", "-y", "theta")
    assert "no output named 'theta'; valid outputs: omega, i" in err
    assert "no input named 'F'; valid inputs: V" in failed(capsys, "tf", MOTOR, "-u", "F", "-y", "omega")
    assert "choose one with --output: omega, i" in failed(capsys, "tf", MOTOR)


def test_nonlinear_model_has_no_tf_or_numeric_export(tmp_path, capsys):
    assert "nonlinear" in failed(capsys, "tf", DUFFING, "-y", "x")
    assert "nonlinear" in failed(capsys, "export", DUFFING, "-o", str(tmp_path / "d.json"))
    assert os.listdir(tmp_path) == []


def test_unwritable_output_paths(tmp_path, capsys):
    (tmp_path / "afile").write_text("x")
    for target in (tmp_path / "nodir" / "m.json", tmp_path / "afile" / "m.mat", tmp_path / "nodir" / "m.c",
                   tmp_path / "nodir" / "m.py"):
        err = failed(capsys, "export", MOTOR, "-o", str(target))
        assert str(target) in err
    assert os.listdir(tmp_path) == ["afile"]
    assert "cannot tell the export format" in failed(capsys, "export", MOTOR, "-o", str(tmp_path / "m.txt"))


@pytest.mark.parametrize("command", [[], ["equations"], ["tf"], ["export"], ["draw"]],
                         ids=["top", "equations", "tf", "export", "draw"])
def test_help(capsys, command):
    code, out, _ = run(capsys, *command, "--help")
    assert code == 0 and "usage: bondgraph" in out


def test_usage_errors_exit_2(capsys):
    code, _, err = run(capsys, "export", MOTOR)             # -o missing
    assert code == 2 and "required" in err
    code, _, err = run(capsys, "export", MOTOR, "-f", "xml", "-o", "x")
    assert code == 2 and "invalid choice" in err
    code, _, err = run(capsys)
    assert code == 2


def test_installed_console_script(tmp_path):
    script = Path(sys.executable).with_name("bondgraph")
    if not script.exists():
        pytest.skip("the bondgraph console script is not installed next to this Python")
    ok = subprocess.run([str(script), "export", MOTOR, "-o", str(tmp_path / "m.json")],
                        capture_output=True, text=True, timeout=60)
    assert ok.returncode == 0, ok.stderr
    assert json.loads((tmp_path / "m.json").read_text())["A"] == HAND_A
    bad = subprocess.run([str(script), "tf", MOTOR, "-u", "V", "-y", "nope"], capture_output=True, text=True,
                         timeout=60)
    assert bad.returncode == 1 and bad.stderr.startswith("error: ") and "Traceback" not in bad.stderr
