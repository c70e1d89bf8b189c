"""Export to .mat / .npz / JSON: read back with scipy.io.loadmat, numpy.load and json,
and atomic writes (no partial or temporary file after a failure)."""

import json
import os
import re

import numpy as np
import pytest
import scipy.io

import bondgraph.export as ex
from bondgraph.export import ExportError, export, export_json, export_mat, export_npz, load_json
from bondgraph.numeric import NumericStateSpace

MATLAB_IDENT = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,62}$")

# the DC motor of test_numeric with Ra=2, La=0.5, K=0.1, J=0.02, b=0.2 (hand-derived numbers)
A = [[-4.0, -5.0], [0.2, -10.0]]
B = [[1.0], [0.0]]
C = [[0.0, 50.0], [2.0, 0.0]]
D = [[0.0], [0.0]]
PARAMS = {"J": 0.02, "K": 0.1, "La": 0.5, "Ra": 2.0, "b": 0.2}


@pytest.fixture
def plant():
    return NumericStateSpace(A, B, C, D, ("p_La", "p_J"), ("V",), ("omega", "i"), PARAMS, "dc_motor")


@pytest.fixture
def servo():
    return NumericStateSpace([[-1.0]], [[1.0]], [[2.0]], [[0.0]], ("p_motor.La",), ("motor.V",),
                             ("omega",), {"motor.Ra": 1.5}, "servo")


def cell(arr):
    return [str(np.asarray(c).ravel()[0]) if np.asarray(c).size else "" for c in np.asarray(arr).ravel()]


def listing(path):
    return sorted(os.listdir(path))


def test_mat_loads_back(tmp_path, plant):
    path = tmp_path / "motor.mat"
    export_mat(plant, path)
    m = scipy.io.loadmat(path)
    for name, value in (("A", A), ("B", B), ("C", C), ("D", D)):
        np.testing.assert_array_equal(m[name], value)
    assert cell(m["state_names"]) == ["p_La", "p_J"]
    assert cell(m["input_names"]) == ["V"] and cell(m["output_names"]) == ["omega", "i"]
    assert cell(m["parameter_names"]) == list(PARAMS)
    np.testing.assert_array_equal(m["parameter_values"], [list(PARAMS.values())])
    assert str(m["model_name"][0]) == "dc_motor"
    assert all(MATLAB_IDENT.match(k) for k in m if not k.startswith("__"))
    assert listing(tmp_path) == ["motor.mat"]


def test_mat_keeps_hierarchical_names_as_strings(tmp_path, servo):
    export_mat(servo, tmp_path / "servo.mat")
    m = scipy.io.loadmat(tmp_path / "servo.mat")
    assert cell(m["parameter_names"]) == ["motor.Ra"] and cell(m["state_names"]) == ["p_motor.La"]


def test_mat_without_inputs(tmp_path):
    osc = NumericStateSpace([[0.0, 1.0], [-1.0, 0.0]], np.zeros((2, 0)), [[1.0, 0.0]], np.zeros((1, 0)),
                            ("q", "p"), (), ("x",), {}, "osc")
    export_mat(osc, tmp_path / "osc.mat")
    m = scipy.io.loadmat(tmp_path / "osc.mat")
    assert m["A"].shape == (2, 2) and m["B"].size == 0 and m["input_names"].size == 0


def test_npz_loads_back_without_pickle(tmp_path, plant):
    path = tmp_path / "motor.npz"
    export_npz(plant, path)
    with np.load(path, allow_pickle=False) as z:
        np.testing.assert_array_equal(z["A"], A)
        np.testing.assert_array_equal(z["C"], C)
        assert z["state_names"].tolist() == ["p_La", "p_J"]
        assert z["parameter_names"].tolist() == list(PARAMS)
        np.testing.assert_array_equal(z["parameter_values"], list(PARAMS.values()))
        assert str(z["model_name"]) == "dc_motor" and str(z["format"]) == "bondgraph-statespace"
    assert listing(tmp_path) == ["motor.npz"]


def test_json_schema_and_round_trip(tmp_path, plant):
    path = tmp_path / "motor.json"
    export_json(plant, path)
    doc = json.loads(path.read_text())
    assert doc == {"format": "bondgraph-statespace", "version": 1, "model": "dc_motor",
                   "states": ["p_La", "p_J"], "inputs": ["V"], "outputs": ["omega", "i"],
                   "A": A, "B": B, "C": C, "D": D, "parameters": PARAMS}
    for key in doc:                       # the schema is documented in the module docstring
        assert f'"{key}"' in ex.__doc__
    back = load_json(path)
    np.testing.assert_array_equal(back.A, A)
    assert back.state_names == ("p_La", "p_J") and dict(back.parameters) == PARAMS


def test_load_json_rejects_other_documents(tmp_path):
    path = tmp_path / "x.json"
    path.write_text('{"format": "something-else"}')
    with pytest.raises(ExportError, match="not a bondgraph-statespace document"):
        load_json(path)
    path.write_text("{nope")
    with pytest.raises(ExportError, match="not valid JSON"):
        load_json(path)


def test_export_dispatches_on_suffix(tmp_path, plant):
    for name in ("a.mat", "a.npz", "a.json"):
        export(plant, tmp_path / name)
    assert listing(tmp_path) == ["a.json", "a.mat", "a.npz"]
    export(plant, tmp_path / "plain.dat", format="json")
    assert json.loads((tmp_path / "plain.dat").read_text())["version"] == 1
    with pytest.raises(ExportError, match="cannot tell the format"):
        export(plant, tmp_path / "a.txt")
    with pytest.raises(ExportError, match="unknown export format 'xml'"):
        export(plant, tmp_path / "a.xml", format="xml")


# ----------------------------------------------------------------------------- atomicity
@pytest.mark.parametrize("writer", [export_mat, export_npz, export_json], ids=["mat", "npz", "json"])
def test_missing_directory(tmp_path, plant, writer):
    target = tmp_path / "nodir" / "out.bin"
    with pytest.raises(ExportError) as info:
        writer(plant, target)
    assert str(target) in str(info.value) and isinstance(info.value, OSError)
    assert info.value.filename == str(target)
    assert listing(tmp_path) == []


def test_parent_is_a_file_and_target_is_a_directory(tmp_path, plant):
    (tmp_path / "file").write_text("x")
    with pytest.raises(ExportError, match="is not a directory"):
        export_json(plant, tmp_path / "file" / "out.json")
    (tmp_path / "dir").mkdir()
    with pytest.raises(ExportError, match="it is a directory"):
        export_json(plant, tmp_path / "dir")
    assert listing(tmp_path) == ["dir", "file"] and listing(tmp_path / "dir") == []


def test_serialization_error_leaves_old_file_and_no_temp(tmp_path):
    bad = NumericStateSpace([[np.nan]], [[1.0]], [[1.0]], [[0.0]], ("x",), ("u",), ("y",))
    target = tmp_path / "plant.json"
    target.write_text("old")
    with pytest.raises(ExportError, match="plant.json.*NaN"):
        export_json(bad, target)
    assert target.read_text() == "old" and listing(tmp_path) == ["plant.json"]


def test_writer_failure_midway_removes_temp(tmp_path, plant, monkeypatch):
    def half_then_fail(fh, *args, **kwargs):
        fh.write(b"MATLAB 5.0 partial")
        raise RuntimeError("disk on fire")

    monkeypatch.setattr(scipy.io, "savemat", half_then_fail)
    target = tmp_path / "motor.mat"
    with pytest.raises(ExportError, match="motor.mat.*disk on fire"):
        export_mat(plant, target)
    assert listing(tmp_path) == []


def test_overwrite_is_whole(tmp_path, plant):
    target = tmp_path / "p.json"
    target.write_text("x" * 100000)
    export_json(plant, target)
    assert json.loads(target.read_text())["model"] == "dc_motor" and listing(tmp_path) == ["p.json"]


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0,
                    reason="directory permissions do not stop root (or non-POSIX systems)")
def test_unwritable_directory(tmp_path, plant):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        with pytest.raises(ExportError, match="locked"):
            export_json(plant, locked / "p.json")
        assert listing(locked) == []
    finally:
        locked.chmod(0o700)


def test_not_a_plant(tmp_path):
    with pytest.raises(ExportError, match="expected a NumericStateSpace"):
        export_json({"A": 1}, tmp_path / "x.json")
