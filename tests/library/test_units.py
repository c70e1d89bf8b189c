"""Units: bond domains, unit-carrying values, the dimensional check.

Expected units are written out by hand (N/m for a stiffness on a
translational bond, ...); the FLEXCAM check compares the plant built from
values given in engineering units with the plant built from the SI numbers
of ``models/flexcam.py``.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy.physics.units as u

import bondgraph as bg
from bondgraph.library import electrical as el, mechanical as me
from bondgraph.library.chemical import GAS_CONSTANT, ReactionNetwork
from bondgraph.library.units import UnitError, bond_domains, check_units, si_values

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "models"))
import flexcam  # noqa: E402
import srv02  # noqa: E402


def _msd():
    g = bg.BondGraph("msd")
    g.add(me.ForceSource("F"), me.Mass("m", mass="m"), me.Spring("k", stiffness="k", grounded=True),
          me.Damper("b", damping="b", grounded=True), bg.One("v"))
    for t, h in [("F.p", "v"), ("v", "m.p"), ("v", "k.a"), ("v", "b.a")]:
        g.connect(t, h)
    return g


GOOD = {"m": 2 * u.kilogram, "k": 3 * u.newton / u.millimeter,
        "b": 40 * u.newton * u.second / u.meter}


def test_domains_come_from_the_components_ports():
    doms = bond_domains(_msd())
    assert set(doms.values()) == {"translation"} and len(doms) == len(bg.flatten(_msd()).bonds)


def test_a_consistent_model_passes_and_carries_state_and_input_units():
    rep = check_units(_msd(), GOOD)
    assert not rep.unchecked and rep.checked > 0
    assert rep.units["p_m.I"] == "kilogram*meter/second"      # momentum: N s
    assert rep.units["q_k.C"] == "meter"                       # spring deflection
    assert rep.units["F.F"] == "newton"


def test_a_wrong_parameter_unit_is_refused_naming_element_parameter_and_both_units():
    bad = dict(GOOD, k=3 * u.newton * u.second / u.meter)     # a damping given as a stiffness
    with pytest.raises(UnitError) as err:
        check_units(_msd(), bad)
    msg = str(err.value)
    assert "C:k.C" in msg and "parameter k:" in msg
    assert "newton*second/meter" in msg and "needs newton/meter" in msg
    assert isinstance(err.value, bg.BondGraphError) and isinstance(err.value, ValueError)


def test_values_in_other_units_give_the_si_numbers():
    model = bg.derive(_msd(), outputs={"x": bg.displacement("k.C")})
    plain = bg.numeric_plant(model, {"m": 2.0, "k": 3000.0, "b": 40.0})
    united = bg.numeric_plant(model, si_values({"m": 2000 * u.gram, "k": 3 * u.newton / u.mm,
                                                "b": 0.04 * u.newton * u.second / u.mm}))
    np.testing.assert_allclose(united.A, plain.A, rtol=1e-14)


def test_models_without_units_are_not_refused_and_their_laws_are_listed_unchecked():
    rep = check_units(_msd(), {"m": 2.0, "k": 3.0, "b": 4.0})
    assert sorted(rep.unchecked) == ["C:k.C, effort on bond 3: k has no unit",
                                     "I:m.I, flow on bond 2: m has no unit",
                                     "R:b.R, effort on bond 4: b has no unit"]


def test_conflicting_domains_are_refused_naming_both():
    g = bg.BondGraph("mixed")
    g.add(me.Mass("m"), el.Resistor("R"), bg.One("v"), me.ForceSource("F"))
    for t, h in [("F.p", "v"), ("v", "m.p"), ("v", "R.p")]:
        g.connect(t, h)
    g.add(el.Ground("gnd"))
    g.connect("R.n", "gnd.p")
    with pytest.raises(UnitError, match="electrical .* and translation|translation .* and electrical"):
        bond_domains(g)


def test_chemical_units_and_a_wrong_thermodynamic_constant():
    net = ReactionNetwork("abc")
    A, B, C = (net.species(n) for n in "ABC")
    net.reaction("r", A + B, C)
    per_mol = {f"K_{n}": 1 / u.mole for n in "ABC"}
    per_mol.update(T=310 * u.kelvin, R_gas=GAS_CONSTANT * u.joule / (u.mole * u.kelvin))
    # the rate constant of the Marcelin-de Donder law is a molar flow
    rep = check_units(net.graph(), dict(per_mol, r_r=2 * u.mole / u.second))
    assert rep.unchecked == ()
    assert rep.units["q_A"] == "mole"
    with pytest.raises(UnitError, match=r"Ce:A: .*log of mole\*\*2.*K_A in mole"):
        check_units(net.graph(), dict(per_mol, K_A=1 * u.mole, r_r=2 * u.mole / u.second))


def test_flexcam_with_units_gives_the_same_numbers():
    g, outs, params = flexcam.build(2, formulation="system")
    # the SRV-02 data as the data sheet gives it, in its own units
    sheet = {
        "Rm": 2.6 * u.ohm, "Lm": 0.18 * u.milli * u.henry,
        "kt": 7.67 * u.newton * u.meter / (1000 * u.ampere),
        "km": 7.67e-3 * u.volt * u.second / u.radian,
        "eta_m": 0.69, "eta_g": 0.90, "Kg": 14.0,
        "Jm": 3.87 * u.gram * u.centimeter**2,
        "Beq": 1.5e-4 * u.newton * u.meter * u.second / u.radian,
        "k_pot": 0.0284 * u.volt / u.degree,
        "k_tach": 1.5e-3 * u.volt / (2 * math.pi * u.radian / u.minute),     # 1.5 mV/RPM
        "k_cam": 0.39 * u.volt / u.centimeter,
    }
    united = dict(params, **sheet)
    model = bg.derive(g, outs)
    P_si = bg.numeric_plant(model, {k: v for k, v in params.items() if k in
                                    {p.name for p in model.parameters}})
    P_u = bg.numeric_plant(model, {k: v for k, v in si_values(united).items() if k in
                                   {p.name for p in model.parameters}})
    for M in ("A", "B", "C", "D"):
        np.testing.assert_allclose(getattr(P_u, M), getattr(P_si, M), rtol=1e-12, atol=1e-300)
    rep = check_units(g, united, domains={"hub.e_in": "electrical", "hub.w_m": "rotation",
                                          "hub.w_l": "rotation"})
    assert rep.checked >= 8          # the hub's relations, with its declared units


def test_srv02_tachometer_conversion_matches_the_model_constant():
    si = si_values({"k_tach": 1.5e-3 * u.volt / (2 * math.pi * u.radian / u.minute)})
    # 1.5 mV per RPM; models/srv02.py: 1.5e-3 * 60 / (2 pi) V/(rad/s)
    assert si["k_tach"] == pytest.approx(srv02.PARAMETERS["k_tach"], rel=1e-12)


@pytest.mark.parametrize("fmi", [2, 3])
def test_fmu_carries_the_units_fmpy_reads_them(tmp_path, fmi):
    fmpy = pytest.importorskip("fmpy")
    from bondgraph.library.units import export_fmu_with_units

    g = _msd()
    model = bg.derive(g, outputs={"x": bg.displacement("k.C"), "v": bg.flow("v")})
    path = export_fmu_with_units(model, tmp_path / "msd.fmu", graph=g, values=GOOD, fmi=fmi,
                                 binary=False)
    md = fmpy.read_model_description(str(path), validate=True)
    unit = {v.name: (v.unit if v.unit is None or isinstance(v.unit, str) else v.unit.name)
            for v in md.modelVariables}
    # by hand: momentum N s, deflection m, force N, velocity m/s; parameters in SI
    assert unit["p_m.I"] == "kilogram*meter/second"
    assert unit["der(p_m.I)"] == "newton"
    assert unit["F.F"] == "newton"
    assert unit["x"] == "meter" and unit["v"] == "meter/second"
    assert unit["k"] == "newton/meter" and unit["m"] == "kilogram"
    bases = {u_.name: u_.baseUnit for u_ in md.unitDefinitions}
    assert (bases["newton"].kg, bases["newton"].m, bases["newton"].s) == (1, 1, -2)
    starts = {v.name: v.start for v in md.modelVariables}
    assert float(starts["k"]) == 3000.0           # 3 N/mm in SI


def test_mat_and_json_carry_the_units(tmp_path):
    import json

    import scipy.io

    from bondgraph.export import load_json
    from bondgraph.library.units import export_json_with_units, export_mat_with_units, model_units

    g = _msd()
    model = bg.derive(g, outputs={"x": bg.displacement("k.C"), "v": bg.flow("v")})
    plant = bg.numeric_plant(model, si_values(GOOD))
    dims = model_units(model, g, GOOD)
    export_mat_with_units(plant, tmp_path / "msd.mat", dims)
    m = scipy.io.loadmat(tmp_path / "msd.mat")
    units = {str(m["state_names"][0, i][0]): str(m["state_units"][0, i][0]) for i in range(2)}
    assert units == {"p_m.I": "kilogram*meter/second", "q_k.C": "meter"}
    assert [str(c[0]) for c in m["output_units"][0]] == ["meter", "meter/second"]
    assert str(m["input_units"][0, 0][0]) == "newton"
    export_json_with_units(plant, tmp_path / "msd.json", dims)
    doc = json.loads((tmp_path / "msd.json").read_text())
    assert doc["units"]["F.F"] == "newton" and doc["units"]["v"] == "meter/second"
    back = load_json(tmp_path / "msd.json")          # the reader accepts the key
    np.testing.assert_allclose(back.A, plant.A)


def test_rs_joins_an_electrical_and_a_thermal_domain_with_units():
    from bondgraph.library.thermal import RS, EntropyStore

    g = bg.BondGraph("heater")
    g.add(el.VoltageSource("V"), bg.Zero("n"), bg.One("i"), RS("Rh", "Rh"), bg.Zero("T"),
          EntropyStore("body", heat_capacity="c", reference_temperature="T0"))
    for t, h in [("V.p", "n"), ("n", "i"), ("i", "Rh"), ("Rh", "T"), ("T", "body.p")]:
        g.connect(t, h)
    values = {"Rh": 4 * u.ohm, "c": 200 * u.joule / u.kelvin, "T0": 300 * u.kelvin}
    rep = check_units(g, values)
    assert rep.unchecked == () and rep.units["q_body.S"] == "joule/kelvin"    # entropy
    assert set(rep.domains.values()) == {"electrical", "thermal (entropy)"}
    with pytest.raises(UnitError, match=r"RS:Rh, parameter Rh: .*henry.* needs ohm"):
        check_units(g, dict(values, Rh=4 * u.henry))


def test_a_zero_source_has_every_unit():
    g = bg.BondGraph("wall")
    g.add(me.ForceSource("F"), bg.One("v"), me.Spring("k", stiffness="k"), me.Fixed("wall"))
    for t, h in [("F.p", "v"), ("v", "k.a"), ("k.b", "wall.p")]:
        g.connect(t, h)
    assert check_units(g, {"k": 1 * u.newton / u.meter}).unchecked == ()
