"""Regression tests of issue 11: names, law variables, position outputs, warnings.

Expected values are derived by hand in each test.
"""

import warnings

import pytest
import sympy as sp

import bondgraph as bg
from helpers import assert_same_tf, connect_all, s, tf_of

P = lambda names: sp.symbols(names, positive=True)  # noqa: E731


def test_input_named_like_a_state_is_refused():
    g = bg.BondGraph("clash")
    g.add(bg.Se("p_m"), bg.One("v"), bg.I("m"), bg.R("b"))
    connect_all(g, [("p_m", "v"), ("v", "m"), ("v", "b")])
    with pytest.raises(bg.NameClashError, match="'p_m'.*state of I:m.*input of Se:p_m"):
        bg.derive(g)


def test_input_named_like_a_loop_unknown():
    """Sf 'f_2' on 0:A, R on 1:B, two parallel bonds A -> B (a loop torn at a bond
    flow, which the engine once called f_2 too).  By hand: e_A = R f_2 / 4."""
    g = bg.BondGraph("loop")
    g.add(bg.Sf("f_2"), bg.Zero("A"), bg.One("B"), bg.R("R"))
    connect_all(g, [("f_2", "A"), ("A", "B"), ("A", "B"), ("B", "R")])
    m = bg.derive(g, outputs={"eA": bg.effort("A")})
    u, R = sp.Symbol("f_2", real=True), sp.Symbol("R", positive=True)
    assert sp.simplify(m.output_exprs[0] - R * u / 4) == 0


def test_input_named_like_an_integrator_output():
    """Se 'x_m' pushes a free mass m; output 'x_m' its displacement: 1/(m s^2)."""
    g = bg.BondGraph("free")
    g.add(bg.Se("x_m"), bg.One("v"), bg.I("m"))
    connect_all(g, [("x_m", "v"), ("v", "m")])
    m = bg.derive(g, outputs={"x_m": bg.displacement("m")})
    assert m.input_names == ("x_m",)
    assert len(set(m.state_names) | set(m.input_names)) == 3
    mass = sp.Symbol("m", positive=True)
    assert_same_tf(tf_of(m, "x_m", "x_m"), 1 / (mass * s**2))
    assert m.integrators == ((m.state_names[1], "displacement[m]"),)


@pytest.mark.parametrize("param", ["p_m", "t", "F"])
def test_parameter_printing_like_a_state_input_or_time_is_refused(param):
    g = bg.BondGraph("pclash")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b", param))
    connect_all(g, [("F", "v"), ("v", "m"), ("v", "b")])
    with pytest.raises(bg.NameClashError, match=repr(param)):
        bg.derive(g)


def test_law_variable_is_not_a_parameter():
    with pytest.raises(bg.ParameterError, match="R:b.*law variable"):
        bg.R("b", bg.q)
    with pytest.raises(bg.ParameterError, match="TF:n.*law variable"):
        bg.TF("n", 2 * bg.e)


def two_masses():
    g = bg.BondGraph("two")
    g.add(bg.Se("F"), bg.One("v1"), bg.One("v2"), bg.Zero("n"),
          bg.I("m1"), bg.I("m2"), bg.C("k1", stiffness="k1"), bg.C("k2", stiffness="k2"))
    connect_all(g, [("F", "v1"), ("v1", "m1"), ("v1", "k1"), ("v1", "n"), ("n", "k2"),
                    ("n", "v2"), ("v2", "m2")])
    return g


def test_position_output_reuses_states():
    """m1 on a spring k1 to ground, m2 joined to m1 by k2 (0-junction n).

    KCL at n: v1 = q_k2' + v2, and q_k1' = v1, so x2 = q_k1 - q_k2 exactly: no
    integrator.  Newton: (m1 s^2 + k1 + k2) X1 - k2 X2 = F, (m2 s^2 + k2) X2 = k2 X1
    => X2/F = k2/((m1 s^2 + k1 + k2)(m2 s^2 + k2) - k2^2).
    """
    m = bg.derive(two_masses(), outputs={"x2": bg.displacement("m2")})
    assert sorted(m.state_names) == ["p_m1", "p_m2", "q_k1", "q_k2"]
    assert m.integrators == ()
    qk1, qk2 = sp.Symbol("q_k1", real=True), sp.Symbol("q_k2", real=True)
    assert sp.simplify(m.output_exprs[0] - (qk1 - qk2)) == 0
    m1, m2, k1, k2 = P("m1 m2 k1 k2")
    assert_same_tf(tf_of(m, "F", "x2"),
                   k2 / ((m1 * s**2 + k1 + k2) * (m2 * s**2 + k2) - k2**2))
    # the numeric plant is controllable (rank 4), which an extra integrator breaks
    import numpy as np
    plant = bg.compile_plant(m).plant({"m1": 1.0, "m2": 2.0, "k1": 3.0, "k2": 5.0})
    ctrb = np.hstack([np.linalg.matrix_power(plant.A, i) @ plant.B for i in range(4)])
    assert np.linalg.matrix_rank(ctrb) == 4


def test_free_mass_position_needs_an_integrator():
    """A free mass (F on m, no spring): x = integral of p/m is no state combination."""
    g = bg.BondGraph("free")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"))
    connect_all(g, [("F", "v"), ("v", "m"), ("v", "b")])
    m = bg.derive(g, outputs={"x": bg.displacement("m")})
    assert m.state_names == ("p_m", "x")
    assert m.integrators == (("x", "displacement[m]"),)


def test_reversed_bond_warns():
    g = bg.BondGraph("rev")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"))
    connect_all(g, [("F", "v"), ("m", "v")])
    with pytest.warns(bg.BondGraphWarning, match="bond 2 points out of I:m"):
        bg.derive(g)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.simplefilter("ignore", bg.BondGraphWarning)
        bg.derive(g)
