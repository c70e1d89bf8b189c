"""Issue 23, item 4 (audit P13, P13c, P13d): clashes decided on printed names, whatever assumptions.

Before: ``R("b", Symbol("p_m", real=True))`` *was* the state p_m (rhs
``F - p_m**2/m``), ``Symbol("F", real=True)`` merged with the input F.
"""

import pytest
import sympy

import bondgraph as bg


def _damped_mass(b):
    g = bg.BondGraph("g")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b", b))
    for tail, head in [("F", "v"), ("v", "m"), ("v", "b")]:
        g.connect(tail, head)
    return g


@pytest.mark.parametrize("symbol,role", [
    (sympy.Symbol("p_m", real=True), "the state of I:m"),
    (sympy.Symbol("p_m"), "the state of I:m"),
    (sympy.Symbol("p_m", positive=True), "the state of I:m"),
    (sympy.Symbol("F", real=True), "the input of Se:F"),
    (sympy.Symbol("F", positive=True), "the input of Se:F"),
    (sympy.Symbol("t", positive=True), "time"),
    (2 * sympy.Symbol("p_m", real=True) + 1, "the state of I:m"),
], ids=["state-real", "state-plain", "state-positive", "input-real", "input-positive",
        "time-positive", "in-an-expression"])
def test_parameter_printing_like_a_state_input_or_time_is_refused(symbol, role):
    with pytest.raises(bg.NameClashError, match=role.replace("(", r"\(")) as info:
        bg.derive(_damped_mass(symbol))
    assert "'g'" in str(info.value)


def test_time_itself_is_time():
    """``Symbol("t", real=True)`` is ``bg.t``: a time-modulated damper, as documented."""
    assert sympy.Symbol("t", real=True) == bg.t
    model = bg.derive(_damped_mass(1 + bg.t))
    p_m, F, m = sympy.symbols("p_m", real=True), sympy.Symbol("F", real=True), sympy.Symbol("m", positive=True)
    # Newton: dp/dt = F - b(t) v, v = p/m
    assert sympy.simplify(model.rhs[0] - (F - (1 + bg.t) * p_m / m)) == 0


def test_field_entry_printing_like_an_input_is_refused():
    g = bg.BondGraph("fld")
    g.add(bg.Se("F1"), bg.Se("F2"),
          bg.IField("M", [[sympy.Symbol("F1", real=True), 0], [0, 1]]))
    g.connect("F1", "M")
    g.connect("F2", "M")
    with pytest.raises(bg.NameClashError, match="IF:M holds the symbol 'F1'.*input of Se:F1"):
        bg.derive(g)


def test_law_variables_and_signals_are_not_clashes():
    """bg.q in a law is the own variable; an input named q is still free to exist."""
    g = bg.BondGraph("g")
    g.add(bg.Se("q"), bg.One("v"), bg.I("m"), bg.C("k", law=sympy.Symbol("kk", positive=True) * bg.q ** 3))
    for tail, head in [("q", "v"), ("v", "m"), ("v", "k")]:
        g.connect(tail, head)
    model = bg.derive(g)
    assert model.state_names == ("p_m", "q_k") and model.input_names == ("q",)
