"""The bad-input catalogue: each wrong input, the error it gets, the culprit its message names.

``tests/errors/test_catalogue.py`` runs every case (error class, message
naming the culprit, nothing written in the output directory) and checks
that ``docs/errors.md`` is this catalogue rendered.  After changing a case
or a message, regenerate the page::

    python tests/bad_inputs.py docs/errors.md
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import sympy

import bondgraph as bg
from bondgraph.beam import BeamParameterError
from bondgraph.identification import IdentificationError
from bondgraph.errors import NonlinearModelError
from bondgraph.numeric import NumericError, SimulationError
from bondgraph.tf import InvalidOptionError, ShapeError, UnknownSignalError

ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Dirs:
    """``inp``: where a case puts the files it reads; ``out``: where output is asked for."""

    inp: Path
    out: Path


@dataclass(frozen=True)
class Case:
    id: str
    area: str
    input: str
    error: type
    match: str
    call: Callable[[Dirs], object]


CASES: list[Case] = []


def _fmu_error() -> type:
    from bondgraph.fmu import FMUError
    return FMUError


FMUError = _fmu_error()


def case(area: str, input: str, error: type, match: str):
    """Register the decorated function ``f(dirs)`` as a catalogue case."""
    def register(fn):
        CASES.append(Case(fn.__name__, area, input, error, match, fn))
        return fn
    return register


class CliError(bg.BondGraphError):
    """Stands for a command-line failure in the catalogue: exit status and stderr."""


def cli(*argv: str) -> None:
    """Run the command line in-process; a failure becomes :class:`CliError` (stderr text)."""
    import contextlib
    import io

    from bondgraph.cli import main

    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            code = main(list(argv))
        except SystemExit as exc:
            code = exc.code
    text = err.getvalue()
    if "Traceback" in text:
        raise AssertionError(f"traceback from bondgraph {' '.join(argv)}:\n{text}")
    if code not in (0, None):
        raise CliError(f"exit {code}: {text.strip()}")


# ------------------------------------------------------------------ helpers
def msd(name: str = "msd") -> bg.BondGraph:
    g = bg.BondGraph(name)
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"), bg.C("c"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "c")]:
        g.connect(t, h)
    return g


def msd_model() -> bg.Model:
    return bg.derive(msd(), outputs={"x": bg.displacement("c")})


VALUES = {"m": 2.0, "b": 6.0, "c": 0.25}


def model_file(dirs: Dirs, body: str, name: str = "model.py") -> str:
    path = dirs.inp / name
    path.write_text(body, encoding="utf-8")
    return str(path)


MSD_FILE = """\
import bondgraph as bg

def model():
    g = bg.BondGraph("msd")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"), bg.C("c"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "c")]:
        g.connect(t, h)
    return bg.ModelDefinition(g, outputs={"x": bg.displacement("c")},
                              parameters={"m": 2.0, "b": 6.0, "c": 0.25})
"""


# ------------------------------------------------------------------ model building
@case("building", 'I("m\\n") (name with a trailing newline)', bg.ModelStructureError, r"'m\\n'")
def name_trailing_newline(d):
    bg.I("m\n")


@case("building", 'BondGraph("g\\n")', bg.ModelStructureError, r"'g\\n'")
def graph_name_newline(d):
    bg.BondGraph("g\n")


@case("building", 'R("lambda") (a Python keyword)', bg.ModelStructureError, r"'lambda'")
def keyword_name(d):
    bg.R("lambda")


@case("building", 'I("a.b") (dot in an element name)', bg.ModelStructureError, r"'a\.b'")
def dotted_element_name(d):
    bg.I("a.b")


@case("building", "I(42) (name not a string)", bg.ModelStructureError, r"42")
def name_not_string(d):
    bg.I(42)


@case("building", "two elements named R", bg.DuplicateNameError, r"'R' is already used by element R:R")
def duplicate_name(d):
    g = bg.BondGraph("g")
    g.add(bg.R("R"))
    g.add(bg.C("R"))


@case("building", "connect to an element not in the graph", bg.UnknownElementError, r"'nothing'")
def connect_unknown(d):
    g = bg.BondGraph("g")
    g.add(bg.One("j"))
    g.connect("j", "nothing")


@case("building", "bond from a junction to itself", bg.ModelStructureError, r"bond from 'j' to itself")
def self_bond(d):
    g = bg.BondGraph("g")
    g.add(bg.One("j"))
    g.connect("j", "j")


@case("building", "second bond on I:m", bg.ModelStructureError, r"I:m takes 1 bond")
def inertia_two_bonds(d):
    g = msd()
    g.add(bg.One("k"))
    g.connect("m", "k")


@case("building", "third bond on TF:n", bg.ModelStructureError, r"TF:n takes 2 bonds")
def transformer_three_bonds(d):
    g = bg.BondGraph("g")
    g.add(bg.One("a"), bg.One("b"), bg.One("c"), bg.TF("n", 2))
    g.connect("a", "n")
    g.connect("n", "b")
    g.connect("n", "c")


@case("building", "both bonds of TF:n pointing into it", bg.ModelStructureError,
      r"TF:n already has bond 1 pointing into it")
def transformer_same_direction(d):
    g = bg.BondGraph("g")
    g.add(bg.One("a"), bg.One("b"), bg.TF("n", 2))
    g.connect("a", "n")
    g.connect("b", "n")


@case("building", "C:C added but never connected", bg.ModelStructureError, r"C:C has 0 bonds; expected 1")
def unconnected_storage(d):
    g = msd()
    g.add(bg.C("C"))
    bg.derive(g)


@case("building", "sub-model port left dangling", bg.PortError, r"port 'motor\.shaft'.*dangling")
def dangling_port(d):
    sub = bg.BondGraph("motor")
    sub.add(bg.Se("V"), bg.One("i"), bg.R("Ra"), bg.Port("shaft"))
    for t, h in [("V", "i"), ("i", "Ra"), ("i", "shaft")]:
        sub.connect(t, h)
    top = bg.BondGraph("top")
    top.add(sub)
    bg.derive(top)


@case("building", "connect to a sub-model element that is not a port", bg.PortError,
      r"'motor\.Ra' is not a port of sub-model 'motor'")
def not_a_port(d):
    sub = bg.BondGraph("motor")
    sub.add(bg.Se("V"), bg.One("i"), bg.R("Ra"), bg.Port("shaft"))
    for t, h in [("V", "i"), ("i", "Ra"), ("i", "shaft")]:
        sub.connect(t, h)
    top = bg.BondGraph("top")
    top.add(sub, bg.I("J"))
    top.connect("motor.Ra", "J")


# ------------------------------------------------------------------ parameters of elements
@case("parameters", "I('m', 0) (zero inertance)", bg.ParameterError, r"I:m: parameter is 0")
def zero_inertance(d):
    bg.I("m", 0)


@case("parameters", "TF('n', 0) (zero modulus)", bg.ParameterError, r"TF:n: modulus is 0")
def zero_modulus(d):
    bg.TF("n", 0)


@case("parameters", "C('c', sympy.oo)", bg.ParameterError, r"C:c: parameter oo is not a finite real")
def infinite_compliance(d):
    bg.C("c", sympy.oo)


@case("parameters", "R('b', sympy.nan)", bg.ParameterError, r"R:b: parameter nan")
def nan_resistance(d):
    bg.R("b", sympy.nan)


@case("parameters", "R('b', sympy.zoo)", bg.ParameterError, r"R:b: parameter zoo")
def zoo_resistance(d):
    bg.R("b", sympy.zoo)


@case("parameters", "R('b', sympy.I) (imaginary)", bg.ParameterError, r"R:b: parameter I is not a finite real")
def imaginary_resistance(d):
    bg.R("b", sympy.I)


@case("parameters", "I('m', 1e400) (overflowing float)", bg.ParameterError, r"I:m: parameter must be finite, got inf")
def overflow_inertance(d):
    bg.I("m", 1e400)


@case("parameters", "I('m', sympy.Float('1e400'))", bg.ParameterError, r"I:m: parameter 1\.000e\+400 is not a finite real value.*beyond the float range")
def overflow_sympy_float(d):
    bg.I("m", sympy.Float("1e400"))


@case("parameters", "I('m', 1+2j) (complex)", bg.ParameterError, r"I:m: parameter must be a number.*got complex")
def complex_inertance(d):
    bg.I("m", 1 + 2j)


@case("parameters", "R('b', True)", bg.ParameterError, r"R:b: parameter .*bool")
def bool_parameter(d):
    bg.R("b", True)


@case("parameters", "R('R1', '2*x +') (text that is not a name)", bg.ParameterError,
      r"R:R1.*'2\*x \+' is not a parameter name")
def text_parameter(d):
    bg.R("R1", "2*x +")


@case("parameters", "R('b', bg.q) (law variable as a parameter)", bg.ParameterError, r"R:b: parameter q uses the law variable")
def law_variable_parameter(d):
    bg.R("b", bg.q)


@case("parameters", "C('spring', law=k*bg.p) (law in the other variable)", bg.LawError, r"C:spring.*uses p")
def law_wrong_variable(d):
    bg.C("spring", law=sympy.Symbol("k") * bg.p)


@case("parameters", "parameter named 'p_m' beside I('m')", bg.NameClashError, r"'p_m'")
def parameter_clashes_with_state(d):
    g = bg.BondGraph("g")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b", "p_m"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b")]:
        g.connect(t, h)
    bg.derive(g)


@case("parameters", "parameter named 't' (time)", bg.NameClashError, r"'t'")
def parameter_named_time(d):
    g = bg.BondGraph("g")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b", "t"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b")]:
        g.connect(t, h)
    bg.derive(g)


@case("parameters", "Se('p_m') beside I('m') (input named like a state)", bg.NameClashError, r"'p_m'")
def input_clashes_with_state(d):
    g = bg.BondGraph("g")
    g.add(bg.Se("p_m"), bg.One("v"), bg.I("m"))
    g.connect("p_m", "v")
    g.connect("v", "m")
    bg.derive(g)


# ------------------------------------------------------------------ causality and outputs
@case("causality", "two Sf on one 1-junction", bg.CausalityConflictError, r"Sf:F2.*1:j")
def two_flow_sources(d):
    g = bg.BondGraph("g")
    g.add(bg.Sf("F1"), bg.Sf("F2"), bg.One("j"), bg.R("R"))
    for t, h in [("F1", "j"), ("F2", "j"), ("j", "R")]:
        g.connect(t, h)
    bg.derive(g)


@case("causality", "two Se on one 0-junction", bg.CausalityConflictError, r"Se:E2")
def two_effort_sources(d):
    g = bg.BondGraph("g")
    g.add(bg.Se("E1"), bg.Se("E2"), bg.Zero("j"), bg.R("R"))
    for t, h in [("E1", "j"), ("E2", "j"), ("j", "R")]:
        g.connect(t, h)
    bg.derive(g)


@case("causality", "circuit drawn with a 0-junction for ground too (singular loop)",
      bg.AlgebraicLoopError, r"loop in f_4 is singular.*remove the ground node's junction.*bond 4: a -> i")
def singular_ground_loop(d):
    g = bg.BondGraph("floating")
    g.add(bg.Se("V"), bg.One("s"), bg.Zero("a"), bg.Zero("gnd"), bg.One("i"), bg.R("R"))
    for t, h in [("V", "s"), ("s", "a"), ("gnd", "s"), ("a", "i"), ("i", "gnd"), ("i", "R")]:
        g.connect(t, h)
    bg.derive(g, outputs={"e": bg.effort("a")})


@case("outputs", "output on an element that does not exist", bg.OutputError, r"no element 'Jx'")
def output_unknown_element(d):
    bg.derive(msd(), outputs={"y": bg.flow("Jx")})


@case("outputs", "output on bond 9 of a 4-bond graph", bg.OutputError, r"bonds 1\.\.4; got bond 9")
def output_unknown_bond(d):
    bg.derive(msd(), outputs={"y": bg.effort(9)})


@case("outputs", "output given as a string", bg.OutputError, r"must be a signal expression")
def output_string(d):
    bg.derive(msd(), outputs={"y": "p_m/m"})


# ------------------------------------------------------------------ multiport fields
@case("fields", "IField with a 2x3 mass matrix", bg.FieldError, r"IF:M: the mass matrix is 2x3")
def field_not_square(d):
    bg.IField("M", [[1, 0, 0], [0, 1, 0]])


@case("fields", "IField with a 3x3 mass matrix and 2 bonds", bg.ModelStructureError,
      r"IF:M has 2 bonds; expected 3")
def field_wrong_bond_count(d):
    g = bg.BondGraph("short")
    g.add(bg.Se("F"), bg.Se("G"), bg.IField("M", np.eye(3)))
    g.connect("F", "M")
    g.connect("G", "M")
    bg.derive(g)


@case("fields", "IField with a non-symmetric mass matrix", bg.FieldError,
      r"IF:M: the mass matrix is not symmetric: entry \[2,1\] is 2 but \[1,2\] is 1")
def field_not_symmetric(d):
    bg.IField("M", [[3, 1], [2, 3]])


@case("fields", "CField with a stiffness matrix that is not positive definite", bg.FieldError,
      r"CF:K: the stiffness matrix is not positive definite \(smallest eigenvalue -1\)")
def field_not_definite(d):
    bg.CField("K", stiffness=[[1, 2], [2, 1]])


@case("fields", "IField([[m, c], [c, m]]).check_values({m: 1, c: 2})", bg.FieldError,
      r"IF:M: the mass matrix is not positive definite")
def field_values_not_definite(d):
    m, c = sympy.symbols("m c", positive=True)
    bg.IField("M", [[m, c], [c, m]]).check_values({"m": 1.0, "c": 2.0})


@case("fields", "nonlinear kinetic energy to invert on a port driven by a flow source",
      bg.FieldError, r"IF:M: the causality puts port 2 in derivative causality.*solutions")
def field_law_not_invertible(d):
    p1, p2 = sympy.symbols("p1 p2")
    g = bg.BondGraph("nl")
    g.add(bg.Se("F"), bg.Sf("V"),
          bg.IField("M", energy=p1**2 / 2 + p2**4 / 4 + p1 * p2**2, variables=(p1, p2)))
    g.connect("F", "M")
    g.connect("V", "M")
    bg.derive(g)


@case("fields", "output bg.flow('M') of a two-port field (no port)", bg.OutputError,
      r"IF:M has 2 ports, so its flow is ambiguous; name one, e.g. bg.flow\('M', port=1\)")
def field_ambiguous_signal(d):
    g = bg.BondGraph("amb")
    g.add(bg.Se("F"), bg.Se("G"), bg.IField("M", np.eye(2)))
    g.connect("F", "M")
    g.connect("G", "M")
    bg.derive(g, outputs={"v": bg.flow("M")})


# ------------------------------------------------------------------ parameter values
@case("values", "plant({... 'bb': 6.0}) (misspelled name)", bg.ParameterValueError,
      r"unknown parameter 'bb' \(did you mean 'b'\?\).*Valid names: b, c, m")
def plant_misspelled(d):
    bg.compile_plant(msd_model()).plant({"m": 2.0, "bb": 6.0, "c": 0.25})


@case("values", "plant() without a value for c", bg.MissingValueError, r"missing c")
def plant_missing(d):
    bg.compile_plant(msd_model()).plant({"m": 2.0, "b": 6.0})


@case("values", "plant({'m': nan, ...})", bg.ParameterValueError, r"parameter 'm' must be a finite real number; got nan")
def plant_nan(d):
    bg.compile_plant(msd_model()).plant({**VALUES, "m": float("nan")})


@case("values", "plant({'m': '2'}) (text)", bg.ParameterValueError, r"parameter 'm'.*text is never parsed")
def plant_text(d):
    bg.compile_plant(msd_model()).plant({**VALUES, "m": "2"})


@case("values", "plant({'m': 10**400})", bg.ParameterValueError, r"parameter 'm'.*too large")
def plant_huge_int(d):
    bg.compile_plant(msd_model()).plant({**VALUES, "m": 10 ** 400})


@case("values", "plant({'m': 0.0}) (an inertia of zero)", bg.ParameterValueError, r"I:m: its mass \(inertance\) m = 0 must be positive")
def plant_zero_divisor(d):
    bg.compile_plant(msd_model()).plant({**VALUES, "m": 0.0})


@case("values", "batch({'m': [1, 2], 'b': [1, 2, 3], ...})", bg.ParameterValueError, r"same length; got b: 3, m: 2")
def batch_lengths(d):
    bg.compile_plant(msd_model()).batch({"m": [1.0, 2.0], "b": [1.0, 2.0, 3.0], "c": 0.25})


@case("values", "SymbolicTF.subs({'mm': 2, ...})", bg.ParameterValueError, r"unknown parameter 'mm' \(did you mean 'm'\?\)")
def tf_subs_misspelled(d):
    msd_model().transfer_function("F", "x").subs({"mm": 2.0, "b": 6.0, "c": 0.25})


@case("values", "SymbolicStateSpace.subs({'Rmm': 1})", bg.ParameterValueError, r"unknown parameter 'Rmm'")
def ss_subs_unknown(d):
    msd_model().state_space().subs({"Rmm": 1.0})


@case("values", "TransferMatrix.subs({'c': 1j, ...})", bg.ParameterValueError, r"parameter 'c'.*complex")
def tm_subs_complex(d):
    msd_model().transfer_matrix().subs({**VALUES, "c": 1j})


@case("values", "plant([2.0, 6.0, 0.25]) (a list, not a mapping)", bg.ParameterValueError, r"must be a mapping.*got list")
def plant_list(d):
    bg.compile_plant(msd_model()).plant([2.0, 6.0, 0.25])


@case("values", "plant({1: 2.0}) (key neither a name nor a Symbol)", bg.ParameterValueError, r"keys must be sympy Symbols.*got int 1")
def plant_int_key(d):
    bg.compile_plant(msd_model()).plant({1: 2.0})


# ------------------------------------------------------------------ physics (issues 35 and 36)
@case("values", "simulate({'m': -2.0, ...}) (a negative mass given as a value)", bg.ParameterValueError,
      r"I:m: its mass \(inertance\) m = -2 must be positive")
def simulate_negative_mass(d):
    bg.simulate(msd_model(), {**VALUES, "m": -2.0}, (0.0, 1.0))


@case("values", "plant({'F': 1.0, ...}) (an input given as a parameter)", bg.ParameterValueError,
      r"'F' is an input of the model, not a parameter")
def plant_input_as_parameter(d):
    bg.compile_plant(msd_model()).plant({**VALUES, "F": 1.0})


@case("physics", "bg.R('b', -2) (a negative resistance, not marked active)", bg.ParameterError,
      r"R:b: its resistance -2 must not be negative; pass active=True")
def negative_resistance(d):
    bg.R("b", -2)


@case("physics", "an RS heater bonded to a pseudo-thermal HeatCapacity", bg.ModelStructureError,
      r"thermal \(entropy\) \(entropy flow, from RS:Rh\)")
def rs_into_pseudo_thermal(d):
    from bondgraph.library.thermal import RS, HeatCapacity
    g = bg.BondGraph("heater")
    g.add(bg.Se("V"), bg.One("i"), RS("Rh", 10), HeatCapacity("body", capacity=2))
    for t, h in [("V", "i"), ("i", "Rh"), ("Rh", "body.p")]:
        g.connect(t, h)
    bg.derive(g)


@case("physics", "simulate of a species with K_A = -1 given as a value", bg.ParameterValueError,
      r"Ce:A: its thermodynamic constant K_A = -1 must be positive")
def species_negative_k_value(d):
    from bondgraph.library.chemical import ReactionNetwork
    net = ReactionNetwork("n")
    A, B = net.species("A"), net.species("B", K=1)
    net.reaction("r", A, B, r=1)
    bg.simulate(bg.derive(net.graph()), {"K_A": -1.0, "R_gas": 8.314, "T": 300.0}, (0, 1),
                {"q_A": 1.0, "q_B": 0.0})


@case("physics", "a species of network n1 inside a sum of a reaction of n2", bg.ModelStructureError,
      r"species A belongs to network 'n1', not 'n2'")
def species_other_network_in_sum(d):
    from bondgraph.library.chemical import ReactionNetwork
    n1, n2 = ReactionNetwork("n1"), ReactionNetwork("n2")
    A1 = n1.species("A")
    n2.species("A"); B2, P2 = n2.species("B"), n2.species("P")
    n2.reaction("r", A1 + B2, P2)


@case("physics", "a network whose species A takes part in no reaction", bg.ModelStructureError,
      r"species A takes part in no reaction")
def species_idle(d):
    from bondgraph.library.chemical import ReactionNetwork
    net = ReactionNetwork("one")
    net.species("A", K=1)
    net.graph()


@case("physics", "si_values({'m': 500*u.gram + 1*u.meter})", bg.BondGraphError,
      r"parameter 'm'.*adds 500\*gram \(mass\) and meter \(length\)")
def units_sum_of_dimensions(d):
    import sympy.physics.units as u
    from bondgraph.library.units import si_values
    si_values({"m": 500 * u.gram + 1 * u.meter})


@case("physics", "si_values({'m': a*u.kilogram}) (a symbolic coefficient)", bg.BondGraphError,
      r"parameter 'm'.*coefficient a is symbolic")
def units_symbolic_coefficient(d):
    import sympy.physics.units as u
    from bondgraph.library.units import si_values
    si_values({"m": sympy.Symbol("a") * u.kilogram})


# ------------------------------------------------------------------ structural results on bad data
@case("structure", "invert(model, Abs(t)) (a kink where x must be twice differentiable)",
      bg.BondGraphError, r"trajectory Abs\(t\) is not 2 times differentiable.*at t = 0")
def invert_kink(d):
    from bondgraph.structure import invert
    invert(msd_model(), sympy.Abs(bg.t))


@case("structure", "residuals(...) from two samples (a second derivative needs 5)", bg.BondGraphError,
      r"2 sample\(s\) are too few")
def residuals_two_samples(d):
    from bondgraph.structure import fault_signatures
    t = np.array([0.0, 1.0])
    fault_signatures(msd_model()).residuals(t, {"F": 2 * np.ones(2)}, {"x": t**2}, VALUES)


@case("structure", "residuals(...) with 40 measurements for 50 times", bg.BondGraphError,
      r"measurement 'x' has shape \(40,\), but t has 50 samples")
def residuals_mismatched(d):
    from bondgraph.structure import fault_signatures
    t = np.linspace(0, 1, 50)
    fault_signatures(msd_model()).residuals(t, {"F": np.ones(50)}, {"x": np.ones(40)}, VALUES)


@case("structure", "minimum_phase({'m2': nan, ...})", bg.ParameterValueError,
      r"parameter 'm2' must be a finite real number; got nan")
def minimum_phase_nan(d):
    from bondgraph.structure import zero_structure
    g = bg.BondGraph("two_masses")
    v1, v2, s = bg.One("v1"), bg.One("v2"), bg.Zero("s")
    g.add(bg.Se("F"), v1, v2, s, bg.I("m1"), bg.I("m2"), bg.C("k", stiffness="k"))
    for a, b in [("F", v1), (v1, "m1"), (v1, s), (s, "k"), (s, v2), (v2, "m2")]:
        g.connect(a, b)
    z = zero_structure(bg.derive(g, outputs={"x1": bg.displacement("m1")}))
    z.minimum_phase({"m1": 1.0, "m2": float("nan"), "k": 1.0})


@case("structure", "linearize where an implicit law e = f**3 + f**5 has zero slope", bg.BondGraphError,
      r"f_d")
def linearize_zero_slope_law(d):
    g = bg.BondGraph("nl")
    g.add(bg.Se("V"), bg.One("j"), bg.R("r0", 1), bg.Zero("n"), bg.C("c", 1),
          bg.R("d", law=bg.f**3 + bg.f**5))
    for a, b in [("V", "j"), ("j", "r0"), ("j", "n"), ("n", "c"), ("n", "d")]:
        g.connect(a, b)
    bg.derive(g).linearize({"q_c": 0.0}, {"V": 0.0}, values={})


@case("library", "write_catalogue('cat') where cat is a file", bg.ModelStructureError,
      r"'.*cat' is a file, not a directory")
def write_catalogue_onto_file(d):
    from bondgraph.library.catalogue import write_catalogue
    target = d.inp / "cat"
    target.write_text("x")
    write_catalogue(target)


# ------------------------------------------------------------------ symbolic forms
@case("symbolic", "state_space() of a nonlinear model", bg.NonlinearModelError, r"model 'duffing': state equation 1 .* is nonlinear in q_k")
def nonlinear_state_space(d):
    g = bg.BondGraph("duffing")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.C("k", law=bg.q ** 3))
    for t, h in [("F", "v"), ("v", "m"), ("v", "k")]:
        g.connect(t, h)
    bg.derive(g).state_space()


@case("symbolic", "port_hamiltonian() of a model with a nonlinear damper", NonlinearModelError,
      r"R:Rf: the nonlinear law f\*\*3 .*needs linear R elements")
def port_hamiltonian_nonlinear_r(d):
    damped(bg.R("Rf", law=bg.f ** 3)).port_hamiltonian()


@case("symbolic", "linearize about a point that is not an equilibrium", bg.NonlinearModelError,
      r"not an equilibrium: dp_m/dt")
def linearize_not_equilibrium(d):
    msd_model().linearize({"p_m": 0, "q_c": 1}, {"F": 0})


@case("symbolic", "linearize without a value for state q_c", bg.NonlinearModelError, r"states q_c")
def linearize_missing_state(d):
    msd_model().linearize({"p_m": 0}, {"F": 0})


@case("symbolic", "transfer_function('F', 'z') (unknown output)", UnknownSignalError, r"'z' is not an output.*'x'")
def tf_unknown_output(d):
    msd_model().transfer_function("F", "z")


@case("symbolic", "transfer_function(..., normalize='unit')", InvalidOptionError, r"normalize: expected one of")
def tf_bad_normalize(d):
    msd_model().transfer_function("F", "x", normalize="unit")


@case("symbolic", "tf.transfer_function(A, B, C, D='1')", ShapeError, r"D: .*string.*never parsed")
def tf_text_d(d):
    from bondgraph.tf import transfer_function
    transfer_function([[-1]], [[1]], [[1]], D="1")


@case("symbolic", "SymbolicTF.from_expr('1/(s+1)')", InvalidOptionError, r"expr: .*string")
def tf_from_text(d):
    from bondgraph.tf import SymbolicTF
    SymbolicTF.from_expr("1/(s+1)")


@case("symbolic", "tf.transfer_function with a 2x3 A", ShapeError, r"A: expected a square matrix")
def tf_nonsquare(d):
    from bondgraph.tf import transfer_function
    transfer_function([[1, 2, 3], [4, 5, 6]], [[1], [1]], [[1, 1]])


@case("symbolic", "beam.characteristic_expression(mass_ratio='0.1')", BeamParameterError, r"mass_ratio: .*string")
def beam_text_ratio(d):
    from bondgraph.beam import characteristic_expression
    characteristic_expression("clamped-free", mass_ratio="0.1")


@case("symbolic", "beam.characteristic_expression('free-free')", BeamParameterError, r"boundary.*'free-free'")
def beam_bad_boundary(d):
    from bondgraph.beam import characteristic_expression
    characteristic_expression("free-free")


# ------------------------------------------------------------------ simulation
def damped(law) -> bg.Model:
    g = bg.BondGraph("damped")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.C("c"), law)
    for t, h in [("F", "v"), ("v", "m"), ("v", "c"), ("v", law.name)]:
        g.connect(t, h)
    return bg.derive(g)


@case("simulation", "a damper law log(f) driven to f < 0 (NaN derivative)", SimulationError,
      r"derivative of state p_m is nan .* at t = 0")
def simulate_nan_derivative(d):
    model = damped(bg.R("Rf", law=sympy.log(bg.f)))
    bg.simulate(model, {"m": 1.0, "c": 0.25}, (0.0, 10.0), {"p_m": -1.0, "q_c": 0.0}, u=[0.0])


@case("simulation", "t_span=(0, nan)", NumericError, r"t_span must be two finite numbers.*got \(0, nan\)")
def simulate_nan_span(d):
    bg.simulate(msd_model(), VALUES, (0.0, float("nan")))


@case("simulation", "method='RK54' (misspelled)", NumericError, r"method must be one of RK45, .*got 'RK54'")
def simulate_bad_method(d):
    bg.simulate(msd_model(), VALUES, (0.0, 1.0), method="RK54")


@case("simulation", "x0={'p_mm': 1} (unknown state)", NumericError, r"p_mm.*p_m, q_c")
def simulate_unknown_state(d):
    bg.simulate(msd_model(), VALUES, (0.0, 1.0), {"p_mm": 1.0})


@case("simulation", "max_step=0", NumericError, r"max_step must be a number > 0.*got 0")
def simulate_zero_step(d):
    bg.simulate(msd_model(), VALUES, (0.0, 1.0), max_step=0.0)


@case("simulation", "t_eval outside t_span", NumericError, r"t_eval\[1\] = 2\.0 is outside")
def simulate_t_eval_outside(d):
    bg.simulate(msd_model(), VALUES, (0.0, 1.0), t_eval=[0.5, 2.0])


@case("simulation", "law=lambda f: 1 // 0 (a callable law that raises)", bg.LawError, r"R:Rf.*raised ZeroDivisionError")
def law_callable_raises(d):
    bg.R("Rf", law=lambda f: 1 // 0)


@case("simulation", "law=lambda q: None (a callable law returning nothing)", bg.LawError, r"C:k.*returned NoneType")
def law_callable_none(d):
    bg.C("k", law=lambda q: None)


# ------------------------------------------------------------------ numeric plants and files
@case("numeric", "compile_plant('msd') (not a Model)", NumericError, r"expected a bondgraph Model.*got str")
def compile_not_model(d):
    bg.compile_plant("msd")


@case("export", "export .mat to a directory that does not exist", bg.ExportError, r"cannot write '.*plant\.mat': the directory '.*missing' does not exist")
def export_missing_dir(d):
    from bondgraph.export import export_mat
    P = bg.compile_plant(msd_model()).plant(VALUES)
    export_mat(P, d.out / "missing" / "plant.mat")


@case("export", "export to an unknown format '.xlsx'", bg.ExportError, r"cannot tell the format of '.*plant\.xlsx'")
def export_unknown_format(d):
    from bondgraph.export import export
    P = bg.compile_plant(msd_model()).plant(VALUES)
    export(P, d.out / "plant.xlsx")


@case("export", "load_json of a file with 'states': null", bg.ExportError, r"plant\.json': \"states\" must be a list of names; got NoneType")
def load_json_null_states(d):
    from bondgraph.export import export_json, load_json
    P = bg.compile_plant(msd_model()).plant(VALUES)
    src = d.inp / "plant.json"
    export_json(P, src)
    doc = json.loads(src.read_text())
    doc["states"] = None
    src.write_text(json.dumps(doc))
    load_json(src)


@case("export", "load_json of a file with a duplicate key", bg.ExportError, r"plant\.json': the key 'format' appears twice")
def load_json_duplicate_key(d):
    from bondgraph.export import load_json
    src = d.inp / "plant.json"
    src.write_text('{"format": "bondgraph-plant", "format": "x"}')
    load_json(src)


@case("export", "FMU of a model whose output needs an input derivative", FMUError,
      r"model 'shaker' cannot be an FMU: its equations use time derivatives of inputs \(dv/dt\)")
def fmu_input_derivative(d):
    from bondgraph.fmu import export_fmu

    g = bg.BondGraph("shaker")
    g.add(bg.Sf("v"), bg.One("j"), bg.I("m"), bg.R("b"))
    for t, h in [("v", "j"), ("j", "m"), ("j", "b")]:
        g.connect(t, h)
    export_fmu(bg.derive(g, outputs={"F": bg.effort(1)}), d.out / "shaker.fmu",
               values={"m": 1.0, "b": 1.0})


# ------------------------------------------------------------------ identification
@case("identification", "prbs(1) (order below the minimum)", IdentificationError, r"order: expected an integer in \[2, 32\], got 1")
def prbs_low_order(d):
    from bondgraph.identification import prbs
    prbs(1)


@case("identification", "TimeData with a NaN sample", IdentificationError, r"y: expected finite values, found 1 NaN")
def timedata_nan(d):
    from bondgraph.identification import TimeData
    y = np.ones(10)
    y[3] = np.nan
    TimeData(np.ones(10), y, 0.01)


@case("identification", "greybox_fit values with a misspelled name", bg.ParameterValueError,
      r"unknown parameter 'cc' \(did you mean 'c'\?\)")
def greybox_misspelled(d):
    from bondgraph.identification import FrequencyData, greybox_fit
    w = np.linspace(0.5, 5.0, 20)
    greybox_fit(msd_model(), FrequencyData(w, 1.0 / (1j * w + 1.0)), free=["m"],
                values={"m": 2.0, "b": 6.0, "cc": 0.25})


@case("identification", "greybox_fit free=['mass']", IdentificationError, r"unknown parameter.*mass")
def greybox_unknown_free(d):
    from bondgraph.identification import FrequencyData, greybox_fit
    w = np.linspace(0.5, 5.0, 20)
    greybox_fit(msd_model(), FrequencyData(w, 1.0 / (1j * w + 1.0)), free=["mass"], values=VALUES)


# ------------------------------------------------------------------ model files
@case("model file", "load_model of a file that does not exist", bg.ModelFileError, r"nope\.py")
def load_missing_model(d):
    bg.load_model(str(d.inp / "nope.py"))


@case("model file", "load_model of a file with a syntax error", bg.ModelFileError, r"model\.py")
def load_syntax_error(d):
    bg.load_model(model_file(d, "def model(:\n"))


@case("model file", "load_model of a file that calls sys.exit(0)", bg.ModelFileError, r"model\.py.*exit")
def load_sys_exit(d):
    bg.load_model(model_file(d, "import sys\nsys.exit(0)\n"))


# ------------------------------------------------------------------ command line
def params_file(d: Dirs, text: str) -> str:
    path = d.inp / "params.json"
    path.write_text(text, encoding="utf-8")
    return str(path)


@case("command line", "params file with a 400-digit integer", CliError,
      r"exit 1: error: .*params\.json.*'m'.*too large for a float")
def cli_huge_int(d):
    cli("export", model_file(d, MSD_FILE), "--params", params_file(d, '{"m": ' + "9" * 400 + "}"),
        "-o", str(d.out / "plant.mat"))


@case("command line", "params file nested 100,000 levels deep", CliError,
      r"exit 1: error: .*params\.json.* nested too deeply")
def cli_deep_json(d):
    cli("export", model_file(d, MSD_FILE), "--params", params_file(d, "[" * 100000 + "]" * 100000),
        "-o", str(d.out / "plant.mat"))


@case("command line", "params file with the key m twice", CliError,
      r"exit 1: error: .*params\.json.*'m' appears twice")
def cli_duplicate_param(d):
    cli("export", model_file(d, MSD_FILE), "--params", params_file(d, '{"m": 1.0, "m": 2.0}'),
        "-o", str(d.out / "plant.mat"))


@case("command line", 'params file with "m": "2"', CliError, r"exit 1: error: .*params\.json.*'m'")
def cli_text_param(d):
    cli("export", model_file(d, MSD_FILE), "--params", params_file(d, '{"m": "2"}'),
        "-o", str(d.out / "plant.mat"))


@case("command line", "params file with a misspelled parameter", CliError,
      r"exit 1: error: params file '.*params\.json': unknown parameter 'mm' \(did you mean 'm'\?\)")
def cli_unknown_param(d):
    cli("export", model_file(d, MSD_FILE), "--params", params_file(d, '{"mm": 2.0}'),
        "-o", str(d.out / "plant.mat"))


@case("command line", "model file that calls sys.exit(0)", CliError,
      r"exit 1: error: model file '.*model\.py' called sys\.exit\(0\)")
def cli_sys_exit(d):
    cli("export", model_file(d, "import sys\nsys.exit(0)\n"), "-o", str(d.out / "plant.mat"))


@case("command line", "model file that does not exist", CliError, r"exit 1: error: model file '.*nope\.py' does not exist")
def cli_missing_model(d):
    cli("equations", str(d.inp / "nope.py"))


@case("command line", "export -o plant.xlsx", CliError,
      r"exit 1: error: cannot tell the export format from '.*plant\.xlsx'; give --format")
def cli_bad_suffix(d):
    cli("export", model_file(d, MSD_FILE), "-o", str(d.out / "plant.xlsx"))


@case("command line", "export --format c --name $'abc\\n'", CliError, r"exit [12]: error: .*'abc\\n'")
def cli_name_newline(d):
    cli("export", model_file(d, MSD_FILE), "--format", "c", "--name", "abc\n",
        "-o", str(d.out / "plant.c"))


@case("command line", "export into a directory that does not exist", CliError,
      r"exit 1: error: cannot write '.*missing/plant\.mat'")
def cli_missing_dir(d):
    cli("export", model_file(d, MSD_FILE), "-o", str(d.out / "missing" / "plant.mat"))


def op_file(d: Dirs, text: str) -> str:
    path = d.inp / "op.toml"
    path.write_text(text, encoding="utf-8")
    return str(path)


@case("command line", "operating-point file with a state the model does not have", CliError,
      r"exit 2: error: operating-point file '.*op\.toml': the model has no state named 'x'; "
      r"valid states: p_m, q_c")
def cli_op_unknown_state(d):
    cli("export", model_file(d, MSD_FILE), "--operating-point",
        op_file(d, "[states]\np_m = 0.0\nx = 0.0\n[inputs]\nF = 0.0\n"), "-o", str(d.out / "plant.json"))


@case("command line", "operating-point file without a value for state q_c", CliError,
      r"exit 2: error: operating-point file '.*op\.toml': no value for the state q_c")
def cli_op_missing_state(d):
    cli("export", model_file(d, MSD_FILE), "--operating-point",
        op_file(d, "[states]\np_m = 0.0\n[inputs]\nF = 0.0\n"), "-o", str(d.out / "plant.json"))


@case("command line", 'operating-point file with q_c = "0"', CliError,
      r"exit 2: error: operating-point file '.*op\.toml': state 'q_c' must be a number; got str '0'")
def cli_op_text_value(d):
    cli("export", model_file(d, MSD_FILE), "--operating-point",
        op_file(d, '[states]\np_m = 0.0\nq_c = "0"\n[inputs]\nF = 0.0\n'), "-o", str(d.out / "plant.json"))


@case("command line", "export --trim --input-value G=1 (no input G)", CliError,
      r"exit 2: error: .*--input-value G=\.\.\.: the model has no input named 'G'; valid inputs: F")
def cli_trim_unknown_input(d):
    cli("export", model_file(d, MSD_FILE), "--trim", "--input-value", "G=1", "-o", str(d.out / "plant.json"))


# ------------------------------------------------------------------ hostile files, odd paths, huge inputs (issue 23)
def _two_state_npz(d: Dirs, **changes) -> Path:
    from bondgraph.export import export_npz
    from bondgraph.numeric import NumericStateSpace
    ss = NumericStateSpace([[-1.0, 0.0], [1.0, -2.0]], [[1.0], [0.0]], [[0.0, 1.0]], [[0.0]],
                           ("x1", "x2"), ("u",), ("y",))
    sparse = changes.pop("sparse", False)
    path = d.inp / "plant.npz"
    export_npz(ss.to_sparse() if sparse else ss, path)
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    arrays.update(changes)
    np.savez(path, **arrays)
    return path


@case("hostile files and huge inputs", "load_npz with a sparse A_indices entry 10**8 (out of range)",
      bg.ExportError, r"plant\.npz': malformed sparse matrix A: A_indices must lie in \[0, 2\)")
def npz_index_out_of_range(d):
    from bondgraph.export import load_npz
    path = _two_state_npz(d, sparse=True)
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["A_indices"] = arrays["A_indices"].copy()
    arrays["A_indices"][0] = 10**8
    np.savez(path, **arrays)
    load_npz(path)


@case("hostile files and huge inputs", "load_npz with a complex A", bg.ExportError,
      r"plant\.npz': the array A has dtype complex128; expected real numbers")
def npz_complex(d):
    from bondgraph.export import load_npz
    load_npz(_two_state_npz(d, A=np.array([[1j, 0], [0, 1]])))


@case("hostile files and huge inputs", "load_npz with repeated state names", bg.ExportError,
      r"plant\.npz': state_names names 'x' more than once")
def npz_duplicate_names(d):
    from bondgraph.export import load_npz
    load_npz(_two_state_npz(d, state_names=np.array(["x", "x"])))


@case("hostile files and huge inputs", "load_npz of an empty file", bg.ExportError,
      r"plant\.npz': not a numpy \.npz archive")
def npz_empty(d):
    from bondgraph.export import load_npz
    (d.inp / "plant.npz").write_bytes(b"")
    load_npz(d.inp / "plant.npz")


@case("hostile files and huge inputs", "load_json of a FIFO (would block forever)", bg.ExportError,
      r"cannot read plant file '.*plant\.json': it is a FIFO, not a regular file")
def json_fifo(d):
    import os
    from bondgraph.export import load_json
    if not (d.inp / "plant.json").exists():
        os.mkfifo(d.inp / "plant.json")
    load_json(d.inp / "plant.json")


@case("hostile files and huge inputs", "export --params p.json, a symlink to /dev/zero", CliError,
      r"exit 1: error: cannot read params file '.*p\.json': it is a character device")
def cli_params_dev_zero(d):
    model = model_file(d, MSD_FILE)
    if not (d.inp / "p.json").is_symlink():
        (d.inp / "p.json").symlink_to("/dev/zero")
    cli("export", model, "--params", str(d.inp / "p.json"), "-o", str(d.out / "x.json"))


@case("hostile files and huge inputs", "export_json onto a Unix socket", bg.ExportError,
      r"cannot write '.*s\.json': it is a socket, not a regular file")
def export_to_socket(d):
    import socket
    from bondgraph.export import export_json
    P = bg.compile_plant(msd_model()).plant(VALUES)
    (d.inp / "s.json").unlink(missing_ok=True)
    with socket.socket(socket.AF_UNIX) as sock:
        sock.bind(str(d.inp / "s.json"))
        export_json(P, d.inp / "s.json")


@case("hostile files and huge inputs", 'R("b", Symbol("p_m", real=True)) (is the state p_m)',
      bg.NameClashError, r"R:b holds the symbol 'p_m', which prints like the state of I:m")
def parameter_is_state_symbol(d):
    g = bg.BondGraph("g")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b", sympy.Symbol("p_m", real=True)))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b")]:
        g.connect(t, h)
    bg.derive(g)


@case("hostile files and huge inputs", 'batch({"m": ["1", "2"], ...}) (text in an array)',
      bg.ParameterValueError, r"'m' must be finite real numbers \(int or float\); got <U1 values")
def batch_text(d):
    bg.compile_plant(msd_model()).batch({"m": ["1", "2"], "b": 6.0, "c": 0.25})


@case("hostile files and huge inputs", 'plant.frequency_response("10")', NumericError,
      r"omega holds text \(dtype <U2\), not numbers")
def frequency_response_text(d):
    bg.compile_plant(msd_model()).plant(VALUES).frequency_response("10")


def _field(matrix):
    g = bg.BondGraph("fld")
    g.add(bg.Se("F1"), bg.Se("F2"), bg.IField("M", matrix))
    g.connect("F1", "M")
    g.connect("F2", "M")
    return bg.derive(g, outputs={"v": bg.flow("M", port=1)})


@case("hostile files and huge inputs", "simulate with IField [[m, 2m], [2m, m]] (indefinite) at m = 1",
      bg.LawError, r"IF:M: the mass matrix is not positive definite \(smallest eigenvalue -1\)")
def simulate_indefinite_field(d):
    m = sympy.Symbol("m", positive=True)
    bg.simulate(_field([[m, 2 * m], [2 * m, m]]), {"m": 1.0}, (0, 1), u=[1.0, 0.0])


@case("hostile files and huge inputs", "IField [[m, m], [m, m]] (singular for every m)", bg.LawError,
      r"IF:M: the mass matrix is singular for every parameter value")
def singular_field(d):
    m = sympy.Symbol("m", positive=True)
    _field([[m, m], [m, m]])


@case("hostile files and huge inputs", "simulate with m = 1e-9 (pole at -1e9) and the default RK45",
      SimulationError, r"model 'msd' is stiff.*use method='Radau', 'BDF' or 'LSODA'")
def simulate_stiff(d):
    bg.simulate(msd_model(), {"m": 1e-9, "b": 1.0, "c": 1.0}, (0.0, 100.0), u=[1.0])


@case("hostile files and huge inputs", "prbs(32) (4.3e9 samples)", IdentificationError,
      r"length: the sequence would have 4,294,967,295 samples")
def prbs_too_long(d):
    from bondgraph.identification import prbs
    prbs(32)


@case("hostile files and huge inputs", "arx with a complex y", IdentificationError,
      r"y: expected an array of real numbers; it holds complex numbers")
def arx_complex(d):
    from bondgraph.identification import arx
    u = np.sin(np.arange(50.0))
    arx(u + 1j, u, na=1, nb=1)


@case("hostile files and huge inputs", "SymbolicTF.from_expr(1/(s - s)) (zoo)",
      bg.BondGraphError, r"expected a finite rational function of s; got zoo")
def tf_from_zoo(d):
    from bondgraph.tf import SymbolicTF
    s = sympy.Symbol("s")
    SymbolicTF.from_expr(1 / (s - s), s)


@case("hostile files and huge inputs", "SymbolicTF.from_expr(exp(-s)) (a delay)",
      bg.BondGraphError, r"expected a rational function of s .*Pade")
def tf_from_delay(d):
    from bondgraph.tf import SymbolicTF
    s = sympy.Symbol("s")
    SymbolicTF.from_expr(sympy.exp(-s), s)


@case("hostile files and huge inputs", "simulate with t_eval of 10**8 times", bg.BondGraphError,
      r"t_eval has 100,000,000 times.*budget")
def simulate_huge_t_eval(d):
    bg.simulate(msd_model(), VALUES, (0.0, 1.0), t_eval=range(10**8))


@case("hostile files and huge inputs", "IField of a dense symbolic 8x8 matrix", bg.FieldError,
      r"IF:M: the mass matrix: its symbolic inverse is too large.*40,320 terms")
def dense_symbolic_field(d):
    M = [[sympy.Symbol(f"m{min(i, j)}{max(i, j)}") for j in range(8)] for i in range(8)]
    g = bg.BondGraph("f")
    g.add(bg.IField("M", M))
    for i in range(8):
        g.add(bg.Se(f"F{i}"))
        g.connect(f"F{i}", "M")
    bg.derive(g)


@case("hostile files and huge inputs", "two parameter Symbols named k (positive, real)",
      bg.NameClashError, r"two different parameter Symbols print as 'k'")
def twin_parameter_symbols(d):
    g = bg.BondGraph("tk")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b", sympy.Symbol("k", positive=True)),
          bg.C("c", sympy.Symbol("k", real=True)))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "c")]:
        g.connect(t, h)
    bg.derive(g)


@case("hostile files and huge inputs", "draw of a 200-cell chain (801 elements)", bg.BondGraphError,
      r"'chain' has 801 elements to draw, more than 600")
def draw_too_large(d):
    g = bg.BondGraph("chain")
    g.add(bg.Se("F"))
    prev = "F"
    for i in range(200):
        g.add(bg.One(f"v{i}"), bg.I(f"m{i}"), bg.Zero(f"f{i}"), bg.C(f"k{i}"))
        for t, h in [(prev, f"v{i}"), (f"v{i}", f"m{i}"), (f"v{i}", f"f{i}"), (f"f{i}", f"k{i}")]:
            g.connect(t, h)
        prev = f"f{i}"
    bg.draw(g)


def render(results: list[tuple[Case, str]]) -> str:
    """The catalogue as a Markdown page (``docs/errors.md``)."""
    lines = ["# Errors: the bad-input catalogue", "",
             "Every wrong input below is refused with an error derived from",
             "`bondgraph.BondGraphError` whose message names the culprit, and no output file is",
             "written.  Generated from `tests/bad_inputs.py` (regenerate with",
             "`python tests/bad_inputs.py docs/errors.md`); `tests/errors/test_catalogue.py`",
             "runs every case and fails if this page is out of date.", "",
             f"{len(results)} cases.", ""]
    area = None
    for c, message in results:
        if c.area != area:
            area = c.area
            lines += ["", f"## {area}", "", "| input | error | message |", "|---|---|---|"]
        msg = message.replace("|", "\\|").replace("\n", " ")
        inp = c.input.replace("|", "\\|")
        lines.append(f"| {inp} | `{c.error.__name__}` | {msg} |")
    return "\n".join(lines) + "\n"


def run(c: Case, dirs: Dirs) -> str:
    """Run one case; return its normalized message (raises AssertionError if it does not fail)."""
    try:
        c.call(dirs)
    except bg.BondGraphError as exc:
        if not isinstance(exc, c.error):
            raise AssertionError(f"{c.id}: expected {c.error.__name__}, got "
                                 f"{type(exc).__name__}: {exc}") from exc
        text = str(exc)
        for path, label in ((dirs.inp, "<in>"), (dirs.out, "<out>")):
            text = text.replace(str(path), label)
        return text
    raise AssertionError(f"{c.id}: no error raised")


def generate() -> str:
    import tempfile
    import warnings

    results = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for c in CASES:
            with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
                results.append((c, run(c, Dirs(Path(a), Path(b)))))
    return render(results)


if __name__ == "__main__":
    text = generate()
    if len(sys.argv) > 1:
        Path(sys.argv[1]).write_text(text, encoding="utf-8")
    else:
        sys.stdout.write(text)
