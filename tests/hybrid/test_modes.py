"""Per-mode state equations of switched bond graphs against hand derivations (Kirchhoff, Newton)."""

import pytest
import sympy

import bondgraph as bg
from bondgraph.hybrid import (ControlledSwitch, Diode, Mode, ModeError, Switch, SwitchedModel,
                              library)

E, R1, R2, C1, C2 = sympy.symbols("E R1 R2 C1 C2", positive=True)
q1, q2 = sympy.symbols("q_C1 q_C2", real=True)


def two_switch():
    """E -- R1 -- node a (C1, switch S1 to ground) -- switch S2 -- node b (C2, R2 to ground)."""
    g = bg.BondGraph("two")
    g.add(bg.Se("E"), bg.One("i1"), bg.R("R1"), bg.Zero("a"), bg.C("C1"), Switch("S1"),
          bg.One("s"), Switch("S2"), bg.Zero("b"), bg.C("C2"), bg.R("R2"))
    for t, h in [("E", "i1"), ("i1", "R1"), ("i1", "a"), ("a", "C1"), ("a", "S1"), ("a", "s"),
                 ("s", "S2"), ("s", "b"), ("b", "C2"), ("b", "R2")]:
        g.connect(t, h)
    return SwitchedModel(g, outputs={"va": bg.effort("C1"), "vb": bg.effort("C2"),
                                     "i_S1": bg.flow("S1")})


def _plain(expr):
    """The expression with every symbol replaced by a plain one of the same name (inputs,
    parameters and states carry different assumptions)."""
    expr = sympy.sympify(expr)
    return expr.xreplace({s: sympy.Symbol(s.name) for s in expr.free_symbols})


def _same(a, b):
    return sympy.simplify(_plain(a) - _plain(b)) == 0


def test_two_switch_modes_both_open():
    m = two_switch().mode(off={"S1", "S2"})
    # Kirchhoff: C1 charged through R1, C2 discharging through R2, no coupling
    assert m.state_names == ("q_C1", "q_C2")
    assert _same(m.rhs[0], (E - q1 / C1) / R1)
    assert _same(m.rhs[1], -q2 / (C2 * R2))
    assert m.output_exprs[2] == 0          # an open switch carries no current


def test_two_switch_parallel_capacitors_derivative_causality():
    sm = two_switch()
    m = sm.mode(on={"S2"}, off={"S1"})
    # C1 and C2 in parallel: one of them in derivative causality.  Hand: total charge
    # Q = q1 + q2 with v = Q/(C1 + C2); Q' = (E - v)/R1 - v/R2; the state kept is C1's
    # charge q1 = C1 v, so q1' = C1/(C1 + C2) Q'.
    assert len(m.states) == 1
    dep = sm.derivative_storage(sm.mode_of(on={"S2"}, off={"S1"}))
    assert len(dep) == 1 and dep[0] in ("C1", "C2")
    x = m.states[0]
    if x == q1:
        v = q1 / C1
        expect = C1 / (C1 + C2) * ((E - v) / R1 - v / R2)
    else:
        v = q2 / C2
        expect = C2 / (C1 + C2) * ((E - v) / R1 - v / R2)
    assert _same(m.rhs[0], expect)
    assert _same(m.output_exprs[0], m.output_exprs[1])      # va = vb


def test_two_switch_shorted_node():
    sm = two_switch()
    m = sm.mode(on={"S1"}, off={"S2"})
    # node a shorted: C1 has no state (q1 = 0), the switch carries E/R1; C2 decays alone
    assert m.state_names == ("q_C2",)
    assert _same(m.rhs[0], -q2 / (C2 * R2))
    assert m.output_exprs[0] == 0
    assert _same(m.output_exprs[2], E / R1)
    both = sm.mode(on={"S1", "S2"})
    assert both.states == () and both.output_exprs[:2] == (0, 0)
    assert _same(both.output_exprs[2], E / R1)


def test_two_switch_mode_listing_and_causality_changes():
    sm = two_switch()
    assert len(sm.modes) == 4 and not sm.inconsistent_modes
    changes = sm.causality_changes
    assert set(changes) == {"C1", "C2"}
    assert "S1 on, S2 on" in changes["C1"] and "S1 off, S2 off" not in changes["C1"]


def test_cached_mode_is_the_same_object():
    sm = two_switch()
    assert sm.mode(on={"S1"}) is sm.mode(on={"S1"}, off={"S2"})


def test_clutch_locked_mode_newton():
    sm = SwitchedModel(library.clutch(), outputs={"torque": bg.effort("K"), "w2": bg.flow("J2")})
    J1, J2 = sympy.symbols("J1 J2", positive=True)
    tau, p1 = sympy.Symbol("tau"), sympy.Symbol("p_J1", real=True)
    locked = sm.mode(off={"K"})
    # Newton on the locked pair: (J1 + J2) w' = tau, w = p1/J1 -> p1' = J1 tau/(J1 + J2);
    # the clutch transmits the torque J2 w' = J2 tau/(J1 + J2)
    assert locked.state_names == ("p_J1",)
    assert _same(locked.rhs[0], J1 * tau / (J1 + J2))
    assert _same(locked.output_exprs[0], J2 * tau / (J1 + J2))
    assert _same(locked.output_exprs[1], p1 / J1)
    free = sm.mode(on={"K"})
    assert free.state_names == ("p_J1", "p_J2")
    assert _same(free.rhs[0], tau) and free.rhs[1] == 0
    assert sm.causality_changes == {"J2": ("K off",)}


def test_inconsistent_mode_names_the_switches():
    sm = SwitchedModel(library.buck())
    # switch and diode both on short the source Vin: no causal assignment
    with pytest.raises(ModeError, match=r"D on, S on.*not consistent"):
        sm.mode(on={"S", "D"})
    assert [str(m) for m in sm.inconsistent_modes] == ["D on, S on"]
    assert Mode(on={"S", "D"}) not in sm.modes


@pytest.mark.parametrize("kwargs, message", [
    (dict(on={"X"}), r"no switch 'X'.*D, S|no switch 'X'.*S, D"),
    (dict(on={"S"}, off={"S"}), r"switch S is given both on and off"),
    (dict(on=[1]), r"switch names"),
], ids=["unknown", "both", "not-a-name"])
def test_bad_mode_requests(kwargs, message):
    with pytest.raises(ModeError, match=message):
        SwitchedModel(library.buck()).mode(**kwargs)


def test_graph_without_switch_is_refused():
    g = bg.BondGraph("plain")
    g.add(bg.Se("E"), bg.R("R"))
    g.connect("E", "R")
    with pytest.raises(ModeError, match="no switch element"):
        SwitchedModel(g)


def test_switch_state_must_be_bool_and_gate_an_expression():
    with pytest.raises(bg.BondGraphError, match="on must be True or False"):
        Diode("D", on=1)
    with pytest.raises(bg.BondGraphError, match="gate must be a sympy expression"):
        ControlledSwitch("S", gate="t > 1")


def test_a_mode_is_drawn_with_its_switch_states():
    sm = SwitchedModel(library.buck())
    svg = bg.draw(sm.mode(on={"D"}, off={"S"}))
    # the diode conducts (closed), the switch blocks (open); strokes as the mode's causality
    assert "CSw:S" in svg and "D:D" in svg
    assert svg.count(">open<") == 1 and svg.count(">closed<") == 1


def test_switched_zero_junction_by_hand():
    from bondgraph.hybrid import SwitchedZero

    g = bg.BondGraph("sj")
    g.add(bg.Se("E"), bg.One("i"), bg.R("R1"), SwitchedZero("n"), bg.C("C"), bg.R("R2"))
    for t, h in [("E", "i"), ("i", "R1"), ("i", "n"), ("n", "C"), ("n", "R2")]:
        g.connect(t, h)
    sm = SwitchedModel(g, outputs={"i1": bg.flow("R1"), "i2": bg.flow("R2"), "v": bg.effort("C")})
    C_, q = sympy.Symbol("C", positive=True), sympy.Symbol("q_C", real=True)
    on = sm.mode(on={"n"})
    # on, an ordinary node: C charged through R1 and drained by R2 (Kirchhoff)
    assert _same(on.rhs[0], (E - q / C_) / R1 - q / (C_ * R2))
    off = sm.mode(off={"n"})
    # off: zero effort on every bond of the node: C has no state and no charge, R2 no current,
    # and R1 carries E/R1 into the junction
    assert off.states == ()
    assert _same(off.output_exprs[0], E / R1) and off.output_exprs[1:] == (0, 0)
    assert sm.causality_changes == {"C": ("n off",)}


def test_reachable_modes_keep_the_user_set_switches():
    sm = two_switch()                     # S1, S2: plain switches, built off
    assert [str(m) for m in sm.reachable_modes] == ["S1 off, S2 off"]
    buck = SwitchedModel(library.buck())  # S (gate) and D (diode) may both flip
    assert set(buck.reachable_modes) == set(buck.modes) and len(buck.modes) == 3
