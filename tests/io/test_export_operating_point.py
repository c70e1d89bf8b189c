"""Exported linear plants store the operating point they were taken about (x0, u0, y0).

The values are written by hand here: a first-order lag ``x' = -x + u``,
``y = 2 x`` about ``x0 = 3``, ``u0 = 3``, ``y0 = 6`` (an equilibrium:
``-3 + 3 = 0``).
"""

from __future__ import annotations

import json
import zipfile

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp
import sympy

from bondgraph.export import ExportError, export_json, export_mat, export_npz, load_json, load_npz
from bondgraph.linear import OperatingPoint
from bondgraph.numeric import NumericStateSpace

POINT = OperatingPoint({"x": 3.0}, {"u": 3.0}, {"y": 6.0}, {"x": "meter"}, how="by hand")


def lag(point=POINT, sparse=False):
    A = sp.csr_array([[-1.0]]) if sparse else [[-1.0]]
    return NumericStateSpace(A, [[1.0]], [[2.0]], [[0.0]], ("x",), ("u",), ("y",), {}, "lag",
                             operating_point=point)


def test_every_format_round_trips_the_point(tmp_path):
    export_mat(lag(), tmp_path / "l.mat")
    m = scipy.io.loadmat(tmp_path / "l.mat")
    assert m["x0"].tolist() == [[3.0]] and m["u0"].tolist() == [[3.0]] and m["y0"].tolist() == [[6.0]]
    assert "x = 3 meter" in str(m["operating_point"][0])
    for sparse in (False, True):
        export_npz(lag(sparse=sparse), tmp_path / "l.npz")
        back = load_npz(tmp_path / "l.npz").operating_point
        assert (dict(back.states), dict(back.inputs), dict(back.outputs)) == (
            {"x": 3.0}, {"u": 3.0}, {"y": 6.0})
        assert back.how == POINT.note
    export_json(lag(), tmp_path / "l.json")
    back = load_json(tmp_path / "l.json").operating_point
    assert dict(back.outputs) == {"y": 6.0} and back.how == "by hand"


def test_a_plant_without_a_point_writes_none(tmp_path):
    export_mat(lag(None), tmp_path / "l.mat")
    assert "x0" not in scipy.io.loadmat(tmp_path / "l.mat")
    export_json(lag(None), tmp_path / "l.json")
    assert "operating_point" not in json.loads((tmp_path / "l.json").read_text())
    assert load_json(tmp_path / "l.json").operating_point is None


def test_a_symbolic_point_is_not_written(tmp_path):
    symbolic = OperatingPoint({"x": sympy.Symbol("a")}, {"u": 1.0}, {"y": 2.0})
    for writer, name in ((export_mat, "l.mat"), (export_npz, "l.npz"), (export_json, "l.json")):
        with pytest.raises(ExportError, match="x = a is symbolic"):
            writer(lag(symbolic), tmp_path / name)
        assert not (tmp_path / name).exists()


def test_an_archive_with_part_of_a_point_is_refused(tmp_path):
    export_npz(lag(), tmp_path / "l.npz")
    with zipfile.ZipFile(tmp_path / "l.npz") as z:
        kept = {n: z.read(n) for n in z.namelist() if n != "y0.npy"}
    with zipfile.ZipFile(tmp_path / "cut.npz", "w") as z:
        for n, data in kept.items():
            z.writestr(n, data)
    with pytest.raises(ExportError, match="operating point needs x0, u0, y0"):
        load_npz(tmp_path / "cut.npz")
    np.testing.assert_array_equal(load_npz(tmp_path / "l.npz").A, [[-1.0]])
