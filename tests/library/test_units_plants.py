"""Units carried by numeric plants, python-control systems, the console and its exports.

A model declares units through its model definition (unit-carrying parameter
values, domain seeds); every expected unit and number here is by hand:

* mass-spring-damper, m = 2 kg, k = 3 N/mm = 3000 N/m, b = 40 N s/m, driven
  by a force F: the momentum p_m is in kg m/s, the spring's displacement q_k
  in m; A = [[-b/m, -k], [1/m, 0]] = [[-20, -3000], [0.5, 0]];
  x/F = (1/m)/(s^2 + (b/m) s + k/m), so a0 = 1/m is in m/(N s^2) (= 1/kg);
* a body of heat capacity C = 450 J/K losing heat through R = 0.5 K/W to an
  ambient temperature: its state (heat) in J, dq/dt = Q - (q/C - T_amb)/R,
  A = -1/(R C) = -1/225 s^-1, B = [1, 1/R] = [1, 2].
"""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest
import scipy.io
import sympy.physics.units as u

import bondgraph as bg
from bondgraph.cli import main
from bondgraph.export import load_json
from bondgraph.library.thermal import Conduction, HeatCapacity, HeatFlowSource, TemperatureSource
from bondgraph.library.units import UnitError, plant_with_units, ratio_text, unit_dims, unit_text
from bondgraph.modelfile import ModelDefinition
from bondgraph.numeric import NumericStateSpace
from bondgraph.numeric.errors import NumericError

MSD_UNITS = {"p_m": "kilogram*meter/second", "q_k": "meter", "F": "newton", "x": "meter",
             "vel": "meter/second"}

MSD_FILE = '''
import bondgraph as bg
import sympy.physics.units as u
from bondgraph.modelfile import ModelDefinition

def model():
    g = bg.BondGraph("msd")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.C("k", stiffness="k"), bg.R("b"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "k"), ("v", "b")]:
        g.connect(t, h)
    return ModelDefinition(g, {"x": bg.displacement("m"), "vel": bg.flow("m")},
                           {"m": 2 * u.kilogram, "k": K_VALUE,
                            "b": 40 * u.newton * u.second / u.meter},
                           domains={"F": "translation"})
'''


def _msd_graph() -> bg.BondGraph:
    g = bg.BondGraph("msd")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.C("k", stiffness="k"), bg.R("b"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "k"), ("v", "b")]:
        g.connect(t, h)
    return g


def _msd(k=3 * u.newton / u.millimeter, **kw) -> ModelDefinition:
    return ModelDefinition(_msd_graph(), {"x": bg.displacement("m"), "vel": bg.flow("m")},
                           {"m": 2 * u.kilogram, "k": k, "b": 40 * u.newton * u.second / u.meter},
                           domains={"F": "translation"}, **kw)


def _file(tmp_path, k="3 * u.newton / u.millimeter") -> str:
    path = tmp_path / "msd_units.py"
    path.write_text(MSD_FILE.replace("K_VALUE", k))
    return str(path)


def _run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


# ------------------------------------------------------------------ the plant and python-control
def test_a_definition_with_units_gives_si_numbers_and_a_plant_carrying_its_units():
    d = _msd()
    assert dict(d.parameters) == {"m": 2.0, "k": 3000.0, "b": 40.0}
    plant = d.plant()
    np.testing.assert_allclose(plant.A, [[-20.0, -3000.0], [0.5, 0.0]], rtol=1e-12)
    assert dict(plant.units) == MSD_UNITS
    assert d.units["k"] == "newton/meter" and d.units["b"] == "newton*second/meter"
    sys = d.to_control()
    assert sys.units == MSD_UNITS
    # the plant keeps its units through the ways it is copied
    assert dict(pickle.loads(pickle.dumps(plant)).units) == MSD_UNITS
    assert dict(plant.to_sparse().units) == MSD_UNITS
    minimal = plant.minimal()          # its states are combinations: only inputs and outputs kept
    assert dict(minimal.units) == {"F": "newton", "x": "meter", "vel": "meter/second"}


def test_plant_with_units_from_a_graph_and_unit_carrying_values():
    g = _msd_graph()
    model = bg.derive(g, outputs={"x": bg.displacement("m"), "vel": bg.flow("m")})
    plant = plant_with_units(model, g, {"m": 2000 * u.gram, "k": 3 * u.newton / u.millimeter,
                                        "b": 0.04 * u.newton * u.second / u.millimeter},
                             domains={"F": "translation"})
    np.testing.assert_allclose(plant.A, [[-20.0, -3000.0], [0.5, 0.0]], rtol=1e-12)
    assert dict(plant.units) == MSD_UNITS


def test_hierarchical_names_and_component_domains_carry_units_to_python_control():
    g = bg.BondGraph("body")
    g.add(HeatCapacity("b1", capacity="C1"), HeatFlowSource("heater"),
          Conduction("rod", resistance="Rth"), TemperatureSource("amb"), bg.Zero("T1"))
    for t, h in [("heater.p", "T1"), ("T1", "b1.p"), ("T1", "rod.a"), ("rod.b", "amb.p")]:
        g.connect(t, h)
    d = ModelDefinition(g, {"T": bg.effort("b1.C")},
                        {"C1": 450 * u.joule / u.kelvin, "Rth": 0.5 * u.kelvin / u.watt})
    plant = d.plant()
    np.testing.assert_allclose(plant.A, [[-1 / 225]], rtol=1e-12)
    np.testing.assert_allclose(plant.B, [[1.0, 2.0]], rtol=1e-12)
    assert dict(plant.units) == {"q_b1.C": "joule", "heater.Q": "watt", "amb.T": "kelvin",
                                 "T": "kelvin"}
    assert d.to_control().units == {"q_b1_C": "joule", "heater_Q": "watt", "amb_T": "kelvin",
                                    "T": "kelvin"}


def test_models_without_units_are_unchanged():
    g = _msd_graph()
    d = ModelDefinition(g, {"x": bg.displacement("m")}, {"m": 2.0, "k": 3000.0, "b": 40.0})
    assert not d.declares_units and dict(d.units) == {}
    assert dict(d.plant().units) == {} and d.to_control().units == {}


def test_a_wrong_unit_in_a_definition_is_refused_at_once():
    with pytest.raises(UnitError, match=r"C:k, parameter k: its value has the unit newton .*"
                                        r"needs newton/meter"):
        _msd(k=3 * u.newton)


def test_plant_units_must_name_its_signals_and_be_texts():
    ss = NumericStateSpace([[-1.0]], [[1.0]], [[1.0]], [[0.0]], ("q",), ("V",), ("vC",))
    with pytest.raises(NumericError, match=r"unit given for 'w', which is no state, input or "
                                           r"output of the plant \(states q; inputs V; outputs vC\)"):
        ss.with_units({"w": "radian/second"})
    with pytest.raises(NumericError, match=r"the unit of 'q' must be a text"):
        ss.with_units({"q": u.coulomb})


def test_unit_texts_by_hand():
    assert unit_text(unit_dims(u.kilogram * u.meter / u.second**2)) == "newton"
    assert ratio_text(unit_dims(u.volt), unit_dims(u.ampere)) == "ohm"
    assert ratio_text(unit_dims(u.meter), unit_dims(u.meter)) == "1 (dimensionless)"
    assert ratio_text(unit_dims(u.meter), unit_dims(u.newton)) == "meter/newton"


# ------------------------------------------------------------------ the console
def test_equations_print_the_units_of_states_inputs_outputs_and_parameters(capsys, tmp_path):
    code, out, _ = _run(capsys, "equations", _file(tmp_path))
    assert code == 0
    assert "states (2): p_m [kilogram*meter/second], q_k [meter]" in out
    assert "inputs (1): F [newton]" in out
    assert "outputs (2): x [meter], vel [meter/second]" in out
    assert "k = 3000 [newton/meter]" in out and "m = 2 [kilogram]" in out


def test_tf_prints_the_units_of_its_input_output_gain_and_coefficients(capsys, tmp_path):
    code, out, _ = _run(capsys, "tf", _file(tmp_path), "--output", "x", "--numeric")
    assert code == 0
    assert "units: input F [newton], output x [meter], x/F [meter/newton]" in out
    a0 = next(line for line in out.splitlines() if line.startswith("a0"))
    assert a0.split()[2:] == ["0.5", "meter/(newton", "s^2)"]          # 1/m = 0.5 per kg
    b0 = next(line for line in out.splitlines() if line.startswith("b0"))
    assert b0.split()[2:] == ["1500", "1/s^2"]                        # k/m
    code, out, _ = _run(capsys, "tf", _file(tmp_path), "--output", "vel")
    assert "vel/F [(meter/second)/newton]" in out


def test_console_output_without_units_has_no_unit_brackets(capsys):
    from pathlib import Path

    motor = str(Path(__file__).resolve().parents[1] / "data" / "dc_motor.py")
    code, out, _ = _run(capsys, "equations", motor)
    assert code == 0 and "[" not in out.split("\n\n")[0]
    code, out, _ = _run(capsys, "tf", motor, "--output", "omega")
    assert code == 0 and "units:" not in out


def test_a_wrong_unit_in_a_model_file_is_a_console_error_naming_it(capsys, tmp_path):
    code, out, err = _run(capsys, "equations", _file(tmp_path, k="3 * u.newton"))
    assert code == 1 and "Traceback" not in err
    assert "msd_units.py" in err and "C:k, parameter k" in err and "newton/meter" in err


def test_console_exports_carry_the_units(capsys, tmp_path):
    model = _file(tmp_path)
    code, _, _ = _run(capsys, "export", model, "-o", str(tmp_path / "msd.json"))
    assert code == 0
    doc = json.loads((tmp_path / "msd.json").read_text())
    assert doc["units"] == MSD_UNITS
    assert dict(load_json(tmp_path / "msd.json").units) == MSD_UNITS
    code, _, _ = _run(capsys, "export", model, "-o", str(tmp_path / "msd.mat"))
    assert code == 0
    m = scipy.io.loadmat(tmp_path / "msd.mat")
    assert [str(c[0]) for c in m["state_units"][0]] == ["kilogram*meter/second", "meter"]
    assert [str(c[0]) for c in m["output_units"][0]] == ["meter", "meter/second"]


def test_console_fmu_carries_the_units_fmpy_reads_them(capsys, tmp_path):
    fmpy = pytest.importorskip("fmpy")
    code, _, err = _run(capsys, "export", _file(tmp_path), "-o", str(tmp_path / "msd.fmu"),
                        "--kind", "cs")
    if code != 0 and "compiler" in err:
        pytest.skip("no C compiler")
    assert code == 0, err
    md = fmpy.read_model_description(str(tmp_path / "msd.fmu"), validate=True)
    units = {v.name: v.unit for v in md.modelVariables}
    assert {k: units[k] for k in MSD_UNITS} == MSD_UNITS
    assert units["der(p_m)"] == "newton" and units["der(q_k)"] == "meter/second"
    assert units["k"] == "newton/meter"
    base = {d.name: d.baseUnit for d in md.unitDefinitions}
    assert (base["newton"].kg, base["newton"].m, base["newton"].s) == (1, 1, -2)
