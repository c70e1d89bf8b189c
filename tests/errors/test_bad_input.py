"""The bad-input catalogue: each error is raised at the call that is wrong,
from the package base class, with a message naming the culprit."""

import pytest
import sympy

import bondgraph as bg


def small():
    g = bg.BondGraph("g")
    V, j = bg.Se("V"), bg.One("j")
    g.add(V, j, bg.R("R"), bg.I("L"))
    g.connect(V, j)
    g.connect(j, "R")
    g.connect(j, "L")
    return g


def test_dangling_port():
    sub = bg.BondGraph("motor")
    sub.add(bg.Se("V"), bg.One("i"), bg.R("Ra"), bg.Port("shaft"))
    for t, h in [("V", "i"), ("i", "Ra"), ("i", "shaft")]:
        sub.connect(t, h)
    top = bg.BondGraph("top")
    top.add(sub)
    with pytest.raises(bg.PortError, match=r"port 'motor.shaft'.*dangling"):
        bg.derive(top)
    with pytest.raises(bg.BondGraphError):
        bg.derive(sub)


def test_inertia_with_two_bonds():
    g = small()
    g.add(bg.One("k"))
    with pytest.raises(bg.ModelStructureError, match=r"I:L takes 1 bond and already has bond 3"):
        g.connect("L", "k")


def test_transformer_with_three_bonds():
    g = bg.BondGraph("g")
    g.add(bg.One("a"), bg.One("b"), bg.One("c"), bg.TF("n"))
    g.connect("a", "n")
    g.connect("n", "b")
    with pytest.raises(bg.ModelStructureError, match=r"TF:n takes 2 bonds"):
        g.connect("n", "c")


def test_transformer_two_bonds_same_direction():
    g = bg.BondGraph("g")
    g.add(bg.One("a"), bg.One("b"), bg.TF("n"))
    g.connect("a", "n")
    with pytest.raises(bg.ModelStructureError, match=r"TF:n already has bond 1 pointing into it"):
        g.connect("b", "n")


def test_element_with_too_few_bonds_at_derive():
    g = small()
    g.add(bg.C("C"))
    with pytest.raises(bg.ModelStructureError, match=r"element C:C has 0 bonds; expected 1"):
        bg.derive(g)


def test_name_used_twice():
    g = small()
    with pytest.raises(bg.DuplicateNameError, match=r"'R' is already used by element R:R"):
        g.add(bg.C("R"))


def test_connect_element_not_in_graph():
    g = small()
    with pytest.raises(bg.UnknownElementError, match=r"element C:C2 is not in this graph"):
        g.connect("j", bg.C("C2"))
    with pytest.raises(bg.UnknownElementError, match=r"has no element 'nothing'"):
        g.connect("j", "nothing")


def test_bond_to_itself():
    g = small()
    with pytest.raises(bg.ModelStructureError, match=r"bond from 'j' to itself"):
        g.connect("j", "j")


def test_two_flow_sources_on_one_junction():
    g = bg.BondGraph("g")
    g.add(bg.Sf("F1"), bg.Sf("F2"), bg.One("j"), bg.R("R"))
    for t, h in [("F1", "j"), ("F2", "j"), ("j", "R")]:
        g.connect(t, h)
    with pytest.raises(bg.CausalityConflictError, match=r"bond 2 \(F2 -> j\).*Sf:F2.*1:j"):
        bg.assign_causality(g)


def test_two_effort_sources_on_zero_junction():
    g = bg.BondGraph("g")
    g.add(bg.Se("E1"), bg.Se("E2"), bg.Zero("n"), bg.C("C"))
    for t, h in [("E1", "n"), ("E2", "n"), ("n", "C")]:
        g.connect(t, h)
    with pytest.raises(bg.CausalityConflictError, match=r"Se:E2"):
        bg.derive(g)


def test_nonlinear_law_not_in_own_variable():
    with pytest.raises(bg.LawError, match=r"C:spring.*uses p.*own variable q"):
        bg.C("spring", law=3 * bg.p)
    with pytest.raises(bg.LawError, match=r"R:d.*not a function of the element's own variable f"):
        bg.R("d", law=sympy.Symbol("c") * 2)


def test_output_names_nothing():
    with pytest.raises(bg.OutputError, match=r"no element 'Jx'"):
        bg.derive(small(), outputs={"w": bg.flow("Jx")})
    with pytest.raises(bg.OutputError, match=r"bonds 1..3; got bond 9"):
        bg.derive(small(), outputs={"w": bg.flow(9)})
    with pytest.raises(bg.OutputError, match=r"must be a signal expression"):
        bg.derive(small(), outputs={"w": "flow(L)"})
    with pytest.raises(bg.OutputError, match=r"effort of 1:j is not a single variable"):
        bg.derive(small(), outputs={"w": bg.effort("j")})


def test_parameter_unparsable_string():
    with pytest.raises(bg.ParameterError, match=r"R:R1.*'2\*x \+' is not a parameter name"):
        bg.R("R1", "2*x +")
    with pytest.raises(bg.ParameterError, match=r"I:m.*must be finite"):
        bg.I("m", float("nan"))
    assert isinstance(bg.ParameterError("x"), TypeError)


def test_identifier_parameter_string_is_a_symbol_not_parsed():
    r = bg.R("R1", "Rm")
    assert r.parameter == sympy.Symbol("Rm", positive=True)
    with pytest.raises(bg.ParameterError):
        bg.R("R2", "__import__('os')")


def test_bad_names():
    with pytest.raises(bg.ModelStructureError, match=r"name 'a.b' is not valid"):
        bg.R("a.b")
    with pytest.raises(bg.ModelStructureError, match=r"name 'lambda' is not valid"):
        bg.BondGraph("lambda")


def test_modulus_with_signal_needs_mtf():
    with pytest.raises(bg.ParameterError, match=r"use MTF"):
        bg.TF("n", modulus=bg.displacement("J"))


def test_subgraph_port_errors():
    sub = bg.BondGraph("motor")
    sub.add(bg.Se("V"), bg.One("i"), bg.R("Ra"), bg.Port("shaft"))
    for t, h in [("V", "i"), ("i", "Ra"), ("i", "shaft")]:
        sub.connect(t, h)
    top = bg.BondGraph("top")
    top.add(sub, bg.R("load"), bg.R("load2"))
    with pytest.raises(bg.PortError, match=r"'motor.Ra' is not a port of sub-model 'motor'; its ports are: shaft"):
        top.connect("motor.Ra", "load")
    top.connect("motor.shaft", "load")
    with pytest.raises(bg.PortError, match=r"already has bond 1"):
        top.connect("motor.shaft", "load2")


def test_errors_are_value_or_type_errors():
    for cls in (bg.ModelStructureError, bg.CausalityConflictError, bg.OutputError, bg.LawError):
        assert issubclass(cls, ValueError) and issubclass(cls, bg.BondGraphError)


# ---------------------------------------------------------------- degenerate values
@pytest.mark.parametrize("make, culprit", [
    (lambda: bg.I("m", 0), "I:m: parameter is 0"),
    (lambda: bg.C("k", stiffness=0), "C:k: stiffness is 0"),
    (lambda: bg.TF("n", 0), "TF:n: modulus is 0"),
    (lambda: bg.GY("r", 0.0), "GY:r: modulus is 0"),
    (lambda: bg.TF("n", 2, efficiency=0), "TF:n: efficiency is 0"),
    (lambda: bg.R("b", sympy.oo), "R:b: parameter oo is not a finite real"),
    (lambda: bg.R("b", sympy.nan), "R:b: parameter nan is not a finite real"),
    (lambda: bg.R("b", sympy.zoo), "R:b: parameter zoo is not a finite real"),
    (lambda: bg.R("b", 1 + sympy.I), "R:b: parameter 1 \\+ I is not a finite real"),
    (lambda: bg.R("b", sympy.Float("1e400")), "R:b: parameter 1.000e\\+400 is not a finite real"),
    (lambda: bg.R("b", "Rm\n"), "R:b: parameter 'Rm\\\\n' is not a parameter name"),
    (lambda: bg.I("m\n"), "I name 'm\\\\n' is not valid"),
])
def test_degenerate_values_refused_at_construction(make, culprit):
    with pytest.raises(bg.BondGraphError, match=culprit):
        make()


def test_negative_values_allowed_for_active_elements():
    assert bg.R("b", -2, active=True).parameter == -2
    with pytest.raises(bg.ParameterError, match="R:b: its resistance -2 must not be negative"):
        bg.R("b", -2)


def test_every_package_error_is_a_bondgraph_error():
    """Errors raised on purpose by the transfer-function and identification layers
    derive from BondGraphError too (they escaped the hierarchy before)."""
    from bondgraph.identification import IdentificationError
    from bondgraph.tf import transfer_function
    from bondgraph.tf.errors import TransferFunctionError, UnknownSignalError

    for cls in (TransferFunctionError, UnknownSignalError, IdentificationError):
        assert issubclass(cls, bg.BondGraphError) and issubclass(cls, ValueError)
    with pytest.raises(bg.BondGraphError, match="nope"):
        transfer_function(A=[[-1]], B=[[1]], C=[[1]], D=[[0]], input="nope")
