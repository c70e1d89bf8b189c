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


# ----------------------------------------------------------------------------- load_json schema
def _doc(**changes):
    doc = {"format": "bondgraph-statespace", "version": 1, "model": "m", "states": ["x1", "x2"],
           "inputs": ["u"], "outputs": ["y"], "A": [[-1.0, 0.0], [0.0, -2.0]], "B": [[1.0], [0.0]],
           "C": [[1.0, 0.0]], "D": [[0.0]], "parameters": {"k": 2.0}}
    for key, value in changes.items():
        if value is _DROP:
            del doc[key]
        else:
            doc[key] = value
    return json.dumps(doc)


_DROP = object()
BAD_DOCUMENTS = [
    (_doc(states=None), '"states" must be a list of names; got NoneType None'),
    (_doc(inputs="u"), '"inputs" must be a list of names; got str'),
    (_doc(outputs=[1]), '"outputs"[0] must be a string; got int 1'),
    (_doc(states=["x", "x"]), '"states" names \'x\' twice'),
    (_doc(version=2), "unsupported bondgraph-statespace version 2; this bondgraph reads version 1 only"),
    (_doc(version="1"), '"version" must be an integer; got str'),
    (_doc(version=True), '"version" must be an integer; got bool'),
    (_doc(version=1.0), '"version" must be an integer; got float'),
    (_doc(version=_DROP), 'missing key "version"'),
    (_doc(A=_DROP, D=_DROP), "missing keys A, D"),
    (_doc(extra=1), "unknown keys 'extra'"),
    (_doc(model=3), '"model" must be a string; got int 3'),
    (_doc(A=[[-1.0, 0.0]]), '"A" must be 2 rows (one per name in "states") of 2 numbers'),
    (_doc(B=[[1.0, 2.0], [0.0, 0.0]]), "row 0 has 2 numbers"),
    (_doc(C=[1.0, 0.0]), '"C" must be 1 rows (one per name in "outputs") of 2 numbers'),
    (_doc(D={"0": 0}), "got dict"),
    (_doc(A=[[-1.0, "0"], [0.0, -2.0]]), "A[0][1] must be a number; got str '0'"),
    (_doc(A=[[-1.0, None], [0.0, -2.0]]), "A[0][1] must be a number; got NoneType"),
    (_doc(A=[[-1.0, False], [0.0, -2.0]]), "A[0][1] must be a number; got bool"),
    (_doc(A=[[-1.0, 0.0], [0.0, float("nan")]]), "A[1][1] must be finite; got nan"),
    (_doc(B=[[float("inf")], [0.0]]), "B[0][0] must be finite; got inf"),
    (_doc(D=[[10 ** 400]]), "D[0][0] is an integer too large for a float (401 digits)"),
    (_doc(parameters=[1]), '"parameters" must be an object of names to numbers; got list'),
    (_doc(parameters={"k": "2"}), "parameter 'k' must be a number; got str"),
    (_doc(parameters={"k": float("-inf")}), "parameter 'k' must be finite"),
    ('{"format": "bondgraph-statespace", "version": 1, "version": 1}', "the key 'version' appears twice"),
    (_doc(parameters={"k": 1})[:-2] + ', "k": 2}}', "the key 'k' appears twice"),
    ("[" * 200_000 + "]" * 200_000, "nested too deeply"),   # deeper than any recursion limit a library sets
    ("[1, 2]", "is not a bondgraph-statespace document"),
    ('"bondgraph-statespace"', "is not a bondgraph-statespace document"),
    ("", "is not valid JSON"),
    (b'{"format": "\xff"}', "is not UTF-8 text"),
]


@pytest.mark.parametrize("content, words", BAD_DOCUMENTS, ids=[w[:32] for _, w in BAD_DOCUMENTS])
def test_load_json_checks_every_field(tmp_path, content, words):
    path = tmp_path / "plant.json"
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content)
    with pytest.raises(ExportError) as info:
        load_json(path)
    assert words in str(info.value) and f"'{path}'" in str(info.value)
    assert isinstance(info.value, ex.BondGraphError) and info.value.filename == str(path)


def test_load_json_optional_fields_and_empty_matrices(tmp_path):
    path = tmp_path / "plant.json"
    path.write_text(_doc(model=_DROP, parameters=_DROP))
    back = load_json(path)
    assert back.name == "" and dict(back.parameters) == {} and back.A.shape == (2, 2)
    static = NumericStateSpace(np.zeros((0, 0)), np.zeros((0, 2)), np.zeros((1, 0)), [[1.0, 2.0]],
                               (), ("u", "v"), ("y",), {}, "gain")
    export_json(static, path)
    assert json.loads(path.read_text())["A"] == [] and json.loads(path.read_text())["C"] == [[]]
    back = load_json(path)
    assert back.A.shape == (0, 0) and back.B.shape == (0, 2) and back.C.shape == (1, 0)
    np.testing.assert_array_equal(back.D, [[1.0, 2.0]])


def test_load_json_reading_errors(tmp_path):
    with pytest.raises(ExportError, match=f"cannot read plant file '{tmp_path}': it is a directory"):
        load_json(tmp_path)
    with pytest.raises(ExportError, match="NUL character"):
        load_json("a\0.json")
