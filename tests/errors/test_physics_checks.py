"""Physics checked without units, values checked by their element, results that check their
assumptions (issue 35 item 3, issue 36 items 1-4).

Expectations are hand derivations: first-order decay ``q = q0 e^{-k t}``, the poles of
``m s^2 + b s + 1/c``, ``S = c ln(T/T0)`` for a body at the ambient temperature, the
inverse of a mass-spring-damper ``F = m x'' + b x' + x/c``.
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
import sympy
import sympy.physics.units as u

import bondgraph as bg
from bondgraph.library.chemical import ReactionNetwork
from bondgraph.library.thermal import (RS, EntropyStore, HeatCapacity, TemperatureSource,
                                       TrueConduction)
from bondgraph.library.units import check_units, si_values
from bondgraph.structure import fault_signatures, invert, zero_structure


def msd(*, active: bool = False) -> bg.Model:
    g = bg.BondGraph("msd")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b", "b", active=active), bg.C("c"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "c")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"x": bg.displacement("c")})


VALUES = {"m": 2.0, "b": 6.0, "c": 0.25}     # 2 s^2 + 6 s + 4 = 2 (s + 1)(s + 2)


# ------------------------------------------------------------------ values, by their element
@pytest.mark.parametrize("make, culprit", [
    (lambda: bg.I("m", -2), r"I:m: its mass \(inertance\) -2 must be positive"),
    (lambda: bg.C("c", -1), r"C:c: its compliance \(capacitance\) -1 must be positive"),
    (lambda: bg.C("k", stiffness=-3), r"C:k: its stiffness -3 must be positive"),
    (lambda: bg.R("b", -0.5), r"R:b: its resistance -0.5 must not be negative"),
], ids=["mass", "compliance", "stiffness", "resistance"])
def test_numbers_refused_at_construction(make, culprit):
    with pytest.raises(bg.ParameterError, match=culprit):
        make()


@pytest.mark.parametrize("call", [
    lambda m, v: bg.compile_plant(m).plant(v),
    lambda m, v: bg.compile_plant(m).batch({k: [x, x] for k, x in v.items()}),
    lambda m, v: bg.simulate(m, v, (0.0, 0.1)),
    lambda m, v: m.equilibrium(v, {"F": 0.0}),
    lambda m, v: m.transfer_function("F", "x").subs(v),
    lambda m, v: m.state_space().subs(v),
    lambda m, v: __import__("bondgraph.codegen", fromlist=["x"]).generate_python(m, defaults=v),
], ids=["plant", "batch", "simulate", "equilibrium", "tf_subs", "ss_subs", "codegen_defaults"])
@pytest.mark.parametrize("name, value, culprit", [
    ("m", -2.0, r"I:m: its mass \(inertance\) m = -2( in parameter set 0)? must be positive"),
    ("m", 0.0, r"I:m: its mass \(inertance\) m = 0( in parameter set 0)? must be positive"),
    ("b", -6.0, r"R:b: its resistance b = -6( in parameter set 0)? must not be negative"),
], ids=["negative_mass", "zero_mass", "negative_damper"])
def test_symbols_refused_at_every_evaluation(call, name, value, culprit):
    with pytest.raises(bg.ParameterValueError, match=culprit):
        call(msd(), {**VALUES, name: value})


def test_active_element_opts_out_and_gives_the_unstable_poles():
    # m s^2 - 6 s + 1/c with m = 2, c = 0.25: 2 (s - 1)(s - 2)
    plant = bg.compile_plant(msd(active=True)).plant({**VALUES, "b": -6.0})
    assert np.allclose(np.sort(np.linalg.eigvals(plant.A).real), [1.0, 2.0])
    assert bg.R("Rn", -1, active=True).parameter == -1


def test_an_input_given_as_a_parameter_says_it_is_an_input():
    with pytest.raises(bg.ParameterValueError, match="'F' is an input of the model, not a parameter"):
        bg.simulate(msd(), {**VALUES, "F": 1.0}, (0.0, 1.0))


# ------------------------------------------------------------------ chemistry
def a_to_b(**rates) -> bg.Model:
    net = ReactionNetwork("n")
    A, B = net.species("A", K=1), net.species("B", K=1)
    net.reaction("r", A, B, **rates)
    return bg.derive(net.graph())


def test_species_constant_refused_as_a_value_like_at_construction():
    net = ReactionNetwork("n")
    A, B = net.species("A"), net.species("B", K=1)
    net.reaction("r", A, B, r=1)
    with pytest.raises(bg.ParameterValueError, match=r"Ce:A: its thermodynamic constant K_A = -1"):
        bg.simulate(bg.derive(net.graph()), {"K_A": -1.0}, (0, 1), {"q_A": 1.0, "q_B": 0.0})
    with pytest.raises(bg.ParameterError, match="K must be positive"):
        ReactionNetwork("m").species("A", K=-2)


def test_absolute_temperature_refused_when_not_positive():
    model = a_to_b(r=1)
    with pytest.raises(bg.ParameterValueError, match=r"its absolute temperature T = -300 must be positive"):
        bg.simulate(model, {"T": -300.0, "R_gas": 8.314}, (0, 1), {"q_A": 1.0, "q_B": 0.0})


def test_irreversible_step_and_a_reaction_that_never_runs():
    # kf = 1, kr = 0: dq_A/dt = -q_A, so q_A(1) = e^-1 (hand)
    res = bg.simulate(a_to_b(kf=1, kr=0), {"T": 300.0, "R_gas": 8.314}, (0.0, 1.0),
                      {"q_A": 1.0, "q_B": 0.0}, rtol=1e-10, atol=1e-12)
    assert res["q_A"][-1] == pytest.approx(math.exp(-1), rel=1e-7)
    with pytest.raises(bg.ParameterError, match="kf and kr are both 0"):
        a_to_b(kf=0, kr=0)


@pytest.mark.parametrize("side", [
    lambda A1, B2: A1 + B2, lambda A1, B2: 2 * A1, lambda A1, B2: B2 + 2 * A1,
], ids=["sum", "term", "sum_with_term"])
def test_species_of_another_network_refused_in_every_form(side):
    n1, n2 = ReactionNetwork("n1"), ReactionNetwork("n2")
    A1 = n1.species("A", K=5)
    n2.species("A", K=1)
    B2, P2 = n2.species("B", K=1), n2.species("P", K=1)
    with pytest.raises(bg.ModelStructureError, match="species A belongs to network 'n1', not 'n2'"):
        n2.reaction("r", side(A1, B2), P2)


def test_a_species_in_no_reaction_is_named_not_its_junction():
    net = ReactionNetwork("one")
    net.species("A", K=1)
    with pytest.raises(bg.ModelStructureError, match="species A takes part in no reaction") as info:
        net.graph()
    assert "mu_A" not in str(info.value)


# ------------------------------------------------------------------ domains without units
def test_rs_into_a_pseudo_thermal_capacity_is_refused_naming_both():
    g = bg.BondGraph("heater")
    g.add(bg.Se("V"), bg.One("i"), RS("Rh", 10), HeatCapacity("body", capacity=2))
    for t, h in [("V", "i"), ("i", "Rh"), ("Rh", "body.p")]:
        g.connect(t, h)
    with pytest.raises(bg.ModelStructureError) as info:
        bg.derive(g)
    text = str(info.value)
    for name in ("RS:Rh", "HeatCapacity", "thermal (entropy)", "heat flow"):
        assert name in text


def test_rs_into_an_entropy_store_is_accepted():
    g = bg.BondGraph("heater")
    g.add(bg.Se("V"), bg.One("i"), RS("Rh", 10),
          EntropyStore("body", heat_capacity=2, reference_temperature=300))
    for t, h in [("V", "i"), ("i", "Rh"), ("Rh", "body.p")]:
        g.connect(t, h)
    (rate,) = bg.derive(g).rhs
    # dS/dt = P/T = V^2/(R T) with T = 300 exp(S/2)
    V, S = sympy.Symbol("V", real=True), bg.derive(g).states[0]
    assert sympy.simplify(rate - V**2 / (10 * 300 * sympy.exp(S / 2))) == 0


def test_temperature_source_in_a_true_thermal_graph_with_units():
    g = bg.BondGraph("true")
    g.add(TemperatureSource("amb", value="Ta"),
          EntropyStore("body", heat_capacity="cb", reference_temperature="T0"),
          TrueConduction("k", resistance="Rk"), bg.Zero("n"))
    for t, h in [("amb.p", "k.a"), ("k.b", "n"), ("n", "body.p")]:
        g.connect(t, h)
    report = check_units(g, {"Ta": 300 * u.kelvin, "cb": 10 * u.joule / u.kelvin,
                             "T0": 290 * u.kelvin, "Rk": 2 * u.kelvin / u.watt})
    assert set(report.domains.values()) == {"thermal (entropy)"} and report.unchecked == ()
    eq = bg.derive(g).equilibrium({"Ta": 300, "cb": 10, "T0": 290, "Rk": 2},
                                  guess={"q_body.S": 0.1})
    assert eq.states["q_body.S"] == pytest.approx(10 * math.log(300 / 290), rel=1e-9)
    with pytest.raises(bg.ParameterError, match="TemperatureSource .amb.*must not be negative"):
        TemperatureSource("amb", value=-5.0)


# ------------------------------------------------------------------ units
def test_unit_arithmetic_checked():
    assert si_values({"x": 1 * u.meter + 20 * u.centimeter})["x"] == pytest.approx(1.2)
    with pytest.raises(bg.BondGraphError, match=r"'m'.*500\*gram \(mass\) and meter \(length\)"):
        si_values({"m": 500 * u.gram + 1 * u.meter})
    with pytest.raises(bg.BondGraphError, match=r"'m'.*coefficient a is symbolic"):
        si_values({"m": sympy.Symbol("a") * u.kilogram})
    with pytest.raises(bg.BondGraphError, match=r"'m'.*1 \+ 2\*I is not a finite real number"):
        si_values({"m": (1 + 2 * sympy.I) * u.kilogram})


def test_model_definition_refuses_a_sum_of_units_and_pickles():
    from bondgraph.modelfile import ModelDefinition
    g = bg.BondGraph("m")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"))
    g.connect("F", "v")
    g.connect("v", "m")
    with pytest.raises(bg.BondGraphError, match="parameter 'm'"):
        ModelDefinition(g, {}, {"m": 500 * u.gram + 1 * u.meter}, domains={"F": "translation"})
    d = ModelDefinition(g, {"v": bg.flow("m")}, {"m": 500 * u.gram}, "a mass",
                        domains={"F": "translation"})
    back = pickle.loads(pickle.dumps(d))
    assert dict(back.parameters) == {"m": 0.5} and dict(back.units) == dict(d.units)
    assert back.plant().B[0, 0] == pytest.approx(1.0)            # dp/dt = F


def test_unit_messages_name_bond_variables_not_placeholders():
    net = ReactionNetwork("n")
    A, B = net.species("A"), net.species("B")
    net.reaction("r", A, B)
    per_mol = {"K_A": 1 / u.mole, "K_B": 1 / u.mole, "T": 300 * u.kelvin,
               "R_gas": 8.314 * u.joule / (u.mole * u.kelvin)}
    with pytest.raises(bg.BondGraphError) as info:       # a rate constant in meters
        check_units(net.graph(), {**per_mol, "r_r": 3 * u.meter})
    assert "_in" not in str(info.value) and "e_3" in str(info.value)
    with pytest.raises(bg.BondGraphError) as info:       # K in meters: log of a dimension
        check_units(net.graph(), {**per_mol, "K_A": 1 * u.meter})
    assert "_q" not in str(info.value) and "q_A" in str(info.value)


# ------------------------------------------------------------------ results that state assumptions
@pytest.mark.parametrize("trajectory, point", [
    (sympy.Abs(bg.t), "0"),
    ((bg.t - 1) * sympy.Heaviside(bg.t - 1), "1"),
    (sympy.Piecewise((0, bg.t < 1), (bg.t - 1, True)), "1"),
    (sympy.Max(0, bg.t - 2), "2"),
], ids=["abs", "heaviside_ramp", "piecewise_ramp", "max_ramp"])
def test_invert_refuses_a_trajectory_that_is_not_smooth_enough(trajectory, point):
    with pytest.raises(bg.BondGraphError, match=rf"not 2 times differentiable.*at t = {point}"):
        invert(msd(), trajectory)


def test_invert_accepts_a_kink_smooth_enough():
    # x = (t - 1)^3 H(t - 1) is twice differentiable: F = m x'' + b x' + x/c by hand
    t = bg.t
    m, b, c = sympy.symbols("m b c", positive=True)
    for traj in ((t - 1)**3 * sympy.Heaviside(t - 1),
                 sympy.Piecewise((0, t < 1), ((t - 1)**3, True))):
        inv = invert(msd(), traj)
        H = sympy.Heaviside(t - 1)
        hand = m * 6 * (t - 1) * H + b * 3 * (t - 1)**2 * H + (t - 1)**3 * H / c
        assert sympy.simplify(inv.input_expr - hand) == 0


def test_invert_refuses_nan():
    with pytest.raises(bg.BondGraphError, match="not a finite function of t"):
        invert(msd(), sympy.nan)


def test_residuals_need_enough_finite_matching_samples():
    fd = fault_signatures(msd())
    t = np.linspace(0.0, 1.0, 5)
    # exact data x = t^2 with F = m x'' + b x' + x/c = 2 m + 2 b t + t^2/c: the residual is 0
    F = 2 * VALUES["m"] + 2 * VALUES["b"] * t + t**2 / VALUES["c"]
    assert np.allclose(fd.residuals(t, {"F": F}, {"x": t**2}, VALUES), 0.0, atol=1e-9)
    with pytest.raises(bg.BondGraphError, match="too few"):
        fd.residuals(t[:2], {"F": F[:2]}, {"x": t[:2]**2}, VALUES)
    with pytest.raises(bg.BondGraphError, match=r"measurement 'x' has shape \(4,\)"):
        fd.residuals(t, {"F": F}, {"x": t[:4]}, VALUES)
    bad = t.copy()
    bad[2] = np.nan
    with pytest.raises(bg.BondGraphError, match="t must be finite; sample 2 is nan"):
        fd.residuals(bad, {"F": F}, {"x": t**2}, VALUES)
    with pytest.raises(bg.ParameterValueError, match="parameter 'm'"):
        fd.residuals(t, {"F": F}, {"x": t**2}, {**VALUES, "m": float("nan")})


def test_minimum_phase_refuses_nan():
    z = zero_structure(msd(), "F", "x")
    with pytest.raises(bg.ParameterValueError, match="parameter 'b' must be a finite real number"):
        z.minimum_phase({**VALUES, "b": float("nan")})
    with pytest.raises(bg.BondGraphError, match="tol: expected a finite number"):
        z.minimum_phase(VALUES, tol=-1)


def test_linearize_refuses_an_infinite_slope_of_an_implicit_law():
    g = bg.BondGraph("nl")
    g.add(bg.Se("V"), bg.One("j"), bg.R("r0", 1), bg.Zero("n"), bg.C("c", 1),
          bg.R("d", law=bg.f**3 + bg.f**5))
    for a, b in [("V", "j"), ("j", "r0"), ("j", "n"), ("n", "c"), ("n", "d")]:
        g.connect(a, b)
    model = bg.derive(g)
    with pytest.raises(bg.BondGraphError, match="f_d"):
        model.linearize({"q_c": 0.0}, {"V": 0.0}, values={})
    # away from the flat point the slope exists: e = f^3 + f^5 at f = 1 (e = 2, q_c = 2):
    # df/de = 1/8, so dq_c/dt = V - f_d - q_c gives A = -(1/8 + 1) (hand)
    lin = model.linearize({"q_c": 2.0}, {"V": 3.0}, values={})
    assert lin.A[0, 0] == pytest.approx(-9 / 8, rel=1e-7)


def test_write_catalogue_onto_a_file(tmp_path):
    from bondgraph.library.catalogue import write_catalogue
    target = tmp_path / "cat"
    target.write_text("x")
    with pytest.raises(bg.ModelStructureError, match="is a file, not a directory"):
        write_catalogue(target)


# ------------------------------------------------------------------ files keep and check units
def test_npz_keeps_units_and_json_refuses_control_characters(tmp_path):
    import json

    from bondgraph.export import ExportError, export_json, export_npz, load_json, load_npz
    from bondgraph.numeric import NumericStateSpace
    ss = NumericStateSpace([[-1.0]], [[1.0]], [[1.0]], [[0.0]], ("x",), ("u",), ("y",),
                           units={"x": "meter", "u": "newton"})
    export_npz(ss, tmp_path / "p.npz")
    assert dict(load_npz(tmp_path / "p.npz").units) == {"x": "meter", "u": "newton"}
    export_json(ss, tmp_path / "p.json")
    doc = json.loads((tmp_path / "p.json").read_text())
    doc["units"] = {"x": "\u001b[2Jmeter"}
    (tmp_path / "q.json").write_text(json.dumps(doc))
    with pytest.raises(ExportError, match="not a printable unit name"):
        load_json(tmp_path / "q.json")
