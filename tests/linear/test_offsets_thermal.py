"""A heated body losing heat to a constant ambient: linear analysis about its operating point.

Hand derivation, written here (pseudo-thermal bond graph: effort =
temperature, flow = heat flow).  A capacity ``C`` at temperature ``T =
E/C`` (state ``q_C = E``, the heat stored) is heated by the input ``Q`` and
loses ``(T - Ta)/R`` through a resistance ``R`` to the ambient ``Ta``, a
constant source.  Energy balance:

    E' = Q - (E/C - Ta)/R.

Equilibrium at ``Q = Q0``: ``T0 = Ta + Q0 R``, ``E0 = C (Ta + Q0 R)``.  In
deviations ``C dT' = dQ - dT/R``, so ``T/Q = R/(R C s + 1)`` (the ambient
drops out), ``A = -1/(R C)``, ``B = 1``, ``C_out = 1/C``.
"""

from __future__ import annotations

import json
import os

import numpy as np
import pytest
import scipy.io
import sympy

import bondgraph as bg
from bondgraph.export import export_json, export_mat, export_npz, load_json, load_npz

R, C, Ta = sympy.symbols("R C Ta", positive=True)
s = sympy.Symbol("s")
VALUES = {"R": 0.5, "C": 400.0, "Ta": 293.15}
Q0 = 40.0


def heater() -> bg.Model:
    g = bg.BondGraph("heater")
    g.add(bg.Sf("Q"), bg.Zero("T"), bg.C("C"), bg.One("loss"), bg.R("R"),
          bg.Se("ambient", value=Ta))
    for tail, head in [("Q", "T"), ("T", "C"), ("T", "loss"), ("loss", "R"),
                       ("loss", "ambient")]:
        g.connect(tail, head)
    return bg.derive(g, outputs={"T": bg.effort("C")})


def test_transfer_function_and_symbolic_equilibrium():
    model = heater()
    G = model.transfer_function("Q", "T")
    assert sympy.simplify(G.expr - R / (R * C * s + 1)) == 0
    op = G.operating_point
    q0 = op.inputs["Q"]                                  # the nominal heat input Q0
    assert sympy.simplify(op.outputs["T"] - (Ta + q0 * R)) == 0
    assert sympy.simplify(op.states["q_C"] - C * (Ta + q0 * R)) == 0
    assert sympy.simplify(model.operating_point({"Q": 0}).outputs["T"] - Ta) == 0


def test_mat_file_holds_the_operating_point(tmp_path):
    model = heater()
    plant = model.linearize(values=VALUES, u0={"Q": Q0})      # equilibrium found, then the plant
    Rv, Cv, Tav = VALUES["R"], VALUES["C"], VALUES["Ta"]
    np.testing.assert_allclose(plant.A, [[-1 / (Rv * Cv)]], rtol=1e-14)
    T0 = Tav + Q0 * Rv
    op = plant.operating_point
    assert op.states["q_C"] == pytest.approx(Cv * T0, rel=1e-12)
    assert op.outputs["T"] == pytest.approx(T0, rel=1e-12)
    plant = plant.with_units({"q_C": "joule", "Q": "watt", "T": "kelvin"})
    path = tmp_path / "heater.mat"
    export_mat(plant, path)
    mat = scipy.io.loadmat(path)
    np.testing.assert_allclose(mat["x0"], [[Cv * T0]], rtol=1e-12)
    np.testing.assert_allclose(mat["u0"], [[Q0]])
    np.testing.assert_allclose(mat["y0"], [[T0]], rtol=1e-12)
    assert str(mat["state_units"][0, 0][0]) == "joule"
    note = str(mat["operating_point"][0])
    assert "T = 313.15 kelvin" in note and "Q = 40 watt" in note


def test_npz_and_json_round_trip_the_point(tmp_path):
    plant = bg.compile_plant(heater()).plant(VALUES)        # the ambient alone: Q0 = 0
    assert plant.operating_point.outputs["T"] == pytest.approx(VALUES["Ta"], rel=1e-14)
    plant = plant.with_units({"T": "kelvin"})
    export_npz(plant, tmp_path / "h.npz")
    back = load_npz(tmp_path / "h.npz")
    assert back.operating_point.outputs["T"] == pytest.approx(VALUES["Ta"], rel=1e-14)
    export_json(plant, tmp_path / "h.json")
    doc = json.loads((tmp_path / "h.json").read_text())
    assert doc["operating_point"]["states"]["q_C"] == pytest.approx(VALUES["C"] * VALUES["Ta"])
    assert doc["operating_point"]["inputs"] == {"Q": 0.0}
    again = load_json(tmp_path / "h.json")
    assert again.operating_point.units["T"] == "kelvin"
    assert again.operating_point.outputs["T"] == pytest.approx(VALUES["Ta"], rel=1e-14)


@pytest.mark.parametrize("bad, words", [
    ({"states": {"q_C": 1.0}, "inputs": {"Q": 0.0}}, "operating_point"),
    ({"states": {"q_C": "hot"}, "inputs": {"Q": 0.0}, "outputs": {"T": 1.0}}, "q_C"),
    ({"states": {"x": 1.0}, "inputs": {"Q": 0.0}, "outputs": {"T": 1.0}}, "exactly the states"),
], ids=["no-outputs", "text", "wrong-name"])
def test_json_with_a_bad_point_is_refused(tmp_path, bad, words):
    export_json(bg.compile_plant(heater()).plant(VALUES), tmp_path / "h.json")
    doc = json.loads((tmp_path / "h.json").read_text())
    doc["operating_point"] = bad
    (tmp_path / "h.json").write_text(json.dumps(doc))
    with pytest.raises(bg.BondGraphError, match=words):
        load_json(tmp_path / "h.json")


HEATER_FILE = '''
import sympy
import bondgraph as bg
from bondgraph.modelfile import ModelDefinition

def model():
    Ta = sympy.Symbol("Ta", positive=True)
    g = bg.BondGraph("heater")
    g.add(bg.Sf("Q"), bg.Zero("T"), bg.C("C"), bg.One("loss"), bg.R("R"),
          bg.Se("ambient", value=Ta))
    for tail, head in [("Q", "T"), ("T", "C"), ("T", "loss"), ("loss", "R"),
                       ("loss", "ambient")]:
        g.connect(tail, head)
    return ModelDefinition(g, {"T": bg.effort("C")}, {"R": 0.5, "C": 400.0, "Ta": 293.15})
'''


def test_command_line_without_trim(tmp_path, capsys):
    from bondgraph.cli import main

    path = tmp_path / "heater.py"
    path.write_text(HEATER_FILE)
    assert main(["tf", str(path), "--input", "Q", "--output", "T"]) == 0
    out, err = capsys.readouterr()
    assert "T/Q = (1/C)/(s + 1/(C*R))" in out            # R/(R C s + 1), monic
    assert "operating point" in err and "Ta" in err
    mat = tmp_path / "heater.mat"
    assert main(["export", str(path), "-o", str(mat)]) == 0
    got = scipy.io.loadmat(mat)
    np.testing.assert_allclose(got["x0"], [[400.0 * 293.15]], rtol=1e-12)
    np.testing.assert_allclose(got["u0"], [[0.0]])
    assert "operating point" in capsys.readouterr().err
    assert os.path.getsize(mat) > 0
