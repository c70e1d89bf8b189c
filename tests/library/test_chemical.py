"""Chemical domain: Ce, Re, chemostats, the reaction builder, stoichiometry.

Every expected value is a published number (BondGraphs.jl's test suite,
``test/simulation_tests.jl``: "Simple Biochemical Simulation",
"Stoichiometry Simulation", "Reversible Michaelis-Menten") or derived by hand
in the test (mass action, detailed balance, the Nernst potential).
"""

from __future__ import annotations

import math

import pytest
import sympy

import bondgraph as bg
from bondgraph.library.chemical import (FARADAY, GAS_CONSTANT, Ce, Chemostat, ReactionNetwork, Re,
                                        conservation_laws, equilibrium_constant,
                                        stoichiometric_matrix)
from bondgraph.library.chemical import ReactionError

TIGHT = dict(rtol=1e-10, atol=1e-12)


def _final(model, values, t1, x0):
    res = bg.simulate(model, values, (0.0, t1), x0, t_eval=[t1], method="LSODA", **TIGHT)
    return {n: res[n][-1] for n in model.state_names}


def test_a_plus_b_to_c_bondgraphs_jl():
    net = ReactionNetwork("ABC")
    A, B, C = (net.species(n, K=1) for n in "ABC")
    net.reaction("r1", A + B, C, r=1)
    model = bg.derive(net.graph())
    # mass action by hand: v = qA qB - qC
    qA, qB, qC = sympy.symbols("q_A q_B q_C", real=True)
    assert [sympy.expand(x) for x in model.rhs] == [qC - qA * qB, qC - qA * qB, qA * qB - qC]
    x = _final(model, {}, 3.0, {"q_A": 1, "q_B": 2, "q_C": 3})
    assert x["q_A"] == pytest.approx(1.23606, abs=1e-5)
    assert x["q_B"] == pytest.approx(2.23606, abs=1e-5)
    assert x["q_C"] == pytest.approx(2.76393, abs=1e-5)


def test_a_to_2b_stoichiometry_bondgraphs_jl():
    net = ReactionNetwork("A2B")
    A, B = net.species("A", K=1), net.species("B", K=1)
    net.reaction("r1", A, 2 * B, r=1)
    model = bg.derive(net.graph())
    qA, qB = sympy.symbols("q_A q_B", real=True)
    assert [sympy.expand(x) for x in model.rhs] == [qB**2 - qA, 2 * qA - 2 * qB**2]
    x = _final(model, {}, 1.0, {"q_A": 1, "q_B": 0})
    assert x["q_A"] == pytest.approx(0.61969, abs=1e-5)
    assert x["q_B"] == pytest.approx(0.76062, abs=1e-5)


def test_reversible_michaelis_menten_chemostats_bondgraphs_jl():
    net = ReactionNetwork("MM")
    E, C = net.species("E", K=1), net.species("C", K=1)
    S, P = net.chemostat("S", K=1, amount=2), net.chemostat("P", K=1, amount=1)
    net.reaction("r1", E + S, C, r=1)
    net.reaction("r2", C, E + P, r=1)
    model = bg.derive(net.graph())
    assert model.state_names == ("q_E", "q_C")
    x = _final(model, {}, 3.0, {"q_E": 1, "q_C": 2})
    # steady state by hand: 2 qC = 3 qE with qE + qC = 3
    assert x["q_E"] == pytest.approx(1.2, abs=1e-5)
    assert x["q_C"] == pytest.approx(1.8, abs=1e-5)


def test_symbolic_rt_cancels_and_thermodynamic_constants_enter_as_mass_action():
    net = ReactionNetwork("n")
    A, B = net.species("A"), net.species("B")
    net.reaction("r", A, 2 * B)
    model = bg.derive(net.graph())
    r, KA, KB = (sympy.Symbol(n, positive=True) for n in ("r_r", "K_A", "K_B"))
    qA, qB = sympy.symbols("q_A q_B", real=True)
    v = r * (KA * qA - KB**2 * qB**2)          # Gawthrop & Crampin 2014, Eq. 2.9
    assert sympy.simplify(model.rhs[0] + v) == 0
    assert sympy.simplify(model.rhs[1] - 2 * v) == 0
    assert {s.name for s in model.parameters} == {"r_r", "K_A", "K_B"}    # R_gas, T cancelled


def test_detailed_balance_equilibrium_by_simulation():
    net = ReactionNetwork("eq")
    A, B = net.species("A", K=2), net.species("B", K=3)
    net.reaction("r", A, 2 * B, r=1)
    # detailed balance by hand: K_A qA = (K_B qB)^2, so qB^2/qA = K_A/K_B^2 = 2/9
    assert equilibrium_constant(net, "r") == sympy.Rational(2, 9)
    x = _final(bg.derive(net.graph()), {}, 40.0, {"q_A": 1.0, "q_B": 0.0})
    assert x["q_B"] ** 2 / x["q_A"] == pytest.approx(2 / 9, rel=1e-7)
    assert x["q_A"] + x["q_B"] / 2 == pytest.approx(1.0, rel=1e-9)     # moiety A + B/2


def test_wegscheider_cycle_product_of_equilibrium_constants_is_one():
    net = ReactionNetwork("cycle")
    A, B, C = (net.species(n) for n in "ABC")
    for name, s, p in (("r1", A, B), ("r2", B, C), ("r3", C, A)):
        net.reaction(name, s, p)
    prod = sympy.Mul(*[equilibrium_constant(net, r) for r in ("r1", "r2", "r3")])
    assert sympy.simplify(prod) == 1


def test_stoichiometric_matrix_and_moieties_by_hand():
    net = ReactionNetwork("mm_closed")
    E, S, C, P = (net.species(n) for n in ("E", "S", "C", "P"))
    net.reaction("r1", E + S, C)
    net.reaction("r2", C, E + P)
    st = stoichiometric_matrix(net.graph())
    assert st.species == ("E", "S", "C", "P") and st.reactions == ("r1", "r2")
    N = sympy.Matrix([[-1, 1], [-1, 0], [1, -1], [0, 1]])     # by hand
    assert st.matrix == N
    laws = conservation_laws(net.graph())
    hand = [{"E": 1, "C": 1}, {"S": 1, "C": 1, "P": 1}]      # free enzyme; substrate moiety
    L = sympy.Matrix([[law.get(s, 0) for s in st.species] for law in laws])
    H = sympy.Matrix([[law.get(s, 0) for s in st.species] for law in hand])
    assert L * N == sympy.zeros(2, 2)
    assert L.rank() == 2 and L.col_join(H).rank() == 2       # the same space as the hand laws
    assert laws == tuple(hand)                               # and the same basis


def test_stoichiometric_matrix_of_a_hand_built_graph_with_tf():
    # 2 A + B = 3 C drawn by hand, species junctions in a different order
    g = bg.BondGraph("hand")
    g.add(Ce("A"), Ce("B"), Ce("C"), bg.Zero("a"), bg.Zero("b"), bg.Zero("c"),
          bg.One("fwd"), bg.One("rev"), Re("r"), bg.TF("nA", sympy.Rational(1, 2)),
          bg.TF("nC", 3))
    for t, h in [("a", "A"), ("b", "B"), ("c", "C"), ("a", "nA"), ("nA", "fwd"), ("b", "fwd"),
                 ("fwd", "r"), ("r", "rev"), ("rev", "nC"), ("nC", "c")]:
        g.connect(t, h)
    st = stoichiometric_matrix(g)
    assert st.matrix == sympy.Matrix([[-2], [-1], [3]])
    laws = conservation_laws(g)
    assert len(laws) == 2
    for law in laws:       # each law l satisfies l . N = 0 with N by hand
        assert -2 * law.get("A", 0) - law.get("B", 0) + 3 * law.get("C", 0) == 0


def test_ion_pore_electrochemical_coupling_nernst_potential():
    """BondGraphs.jl's ion pore (Cudmore et al. 2021): an Re charging a membrane through TF(zF/2).

    Equilibrium by hand: mu_e - zFV/2 = mu_i + zFV/2, so V = RT/(zF) ln(c_e/c_i)
    (Nernst); the pole by hand: dV/dt = zF v / C_m with
    dv/dV = -r zF/(2RT) (c_e e^{-zFV/2RT} + c_i e^{zFV/2RT}) = -r zF sqrt(c_e c_i)/RT at V*.
    """
    for z, c_e, c_i in ((1, 0.155, 0.019), (-1, 0.112, 0.078), (1, 0.005, 0.136)):
        g = bg.BondGraph("pore")
        half = sympy.Rational(z, 2) * sympy.Symbol("F", positive=True)
        g.add(Chemostat("Ie", K=1, amount=c_e), Chemostat("Ii", K=1, amount=c_i),
              bg.One("f"), bg.One("r"), Re("pore", r=1e-7), bg.Zero("Vm"), bg.C("mem", 1e-3),
              bg.TF("zf", half), bg.TF("zr", half))
        for t, h in [("Ie", "f"), ("f", "pore"), ("pore", "r"), ("r", "Ii"), ("f", "zf"),
                     ("zf", "Vm"), ("r", "zr"), ("zr", "Vm"), ("Vm", "mem")]:
            g.connect(t, h)
        model = bg.derive(g, outputs={"V": bg.effort("mem")})
        values = {"F": FARADAY, "R_gas": GAS_CONSTANT, "T": 310.0}
        RT = GAS_CONSTANT * 310.0
        V_star = RT / (z * FARADAY) * math.log(c_e / c_i)
        subs = {p: values[p.name] for p in model.parameters}
        rhs = model.rhs[0].xreplace(subs)
        dyn = sympy.lambdify(model.states, rhs)
        q_star = 1e-3 * V_star
        assert abs(dyn(q_star)) < 1e-12 * abs(dyn(0.0))
        pole = -(z * FARADAY) ** 2 * 1e-7 * math.sqrt(c_e * c_i) / (RT * 1e-3)
        slope = float(sympy.diff(rhs, model.states[0]).subs(
            model.states[0], q_star))
        assert slope == pytest.approx(pole, rel=1e-9)
        res = bg.simulate(model, values, (0.0, 12 / abs(pole)), [0.0], t_eval=[12 / abs(pole)],
                          method="LSODA", **TIGHT)
        assert res["V"][-1] == pytest.approx(V_star, rel=1e-4)


@pytest.mark.parametrize("bad, match", [
    (lambda A, B: 2.5 * A, "positive integer, got 2.5"),
    (lambda A, B: True * A, "positive integer, got True"),
    (lambda A, B: 0 * B, "positive integer, got 0"),
    (lambda A, B: A + A, "appears twice"),
    (lambda A, B: "A", "text is never parsed"),
], ids=["float", "bool", "zero", "twice", "string"])
def test_bad_reactions_refused(bad, match):
    net = ReactionNetwork("n")
    A, B = net.species("A"), net.species("B")
    with pytest.raises(ReactionError, match=match):
        net.reaction("r", bad(A, B), B)


def test_bad_chemical_elements_refused():
    other = ReactionNetwork("other").species("X")
    net = ReactionNetwork("n")
    A = net.species("A")
    with pytest.raises(ReactionError, match="belongs to network 'other'"):
        net.reaction("r", other, A)
    with pytest.raises(bg.BondGraphError, match="Ce:A: a species' law"):
        Ce("A", 2)
    with pytest.raises(bg.ParameterError, match="Re:r: r must be positive, got -1"):
        Re("r", r=-1)
    g = bg.BondGraph("g")
    g.add(Ce("A"), Ce("B"), Re("r"))
    g.connect("A", "r")
    with pytest.raises(bg.ModelStructureError, match="its other bond must point the other way"):
        g.connect("B", "r")
    with pytest.raises(bg.BondGraphError, match="no Re reaction"):
        stoichiometric_matrix(bg.flatten(_rc()))


def _rc():
    g = bg.BondGraph("rc")
    g.add(bg.Se("V"), bg.One("i"), bg.R("R"), bg.C("C"))
    for t, h in [("V", "i"), ("i", "R"), ("i", "C")]:
        g.connect(t, h)
    return g


def test_chemical_elements_draw_with_their_labels():
    net = ReactionNetwork("MM")
    E, C = net.species("E"), net.species("C")
    S = net.chemostat("S")
    net.reaction("r1", E + S, C)
    svg = bg.draw(net.graph())
    for text in ("Ce:E", "SCe:S", "Re:r1", "chemostat"):
        assert text in svg


def _open_cycle(x_A):
    """BondGraphTools' open cycle (test/test_biochem.py, open_cycle): X + A = Y = Z = X + B."""
    net = ReactionNetwork("open_cycle", temperature=1, gas_constant=1)
    X, Y, Z = net.species("X", K=1), net.species("Y", K=2), net.species("Z", K=3)
    A, B = net.chemostat("A", K=1, amount=x_A), net.chemostat("B", K=2, amount=1)
    net.reaction("r1", X + A, Y, r=1)
    net.reaction("r2", Y, Z, r=2)
    net.reaction("r3", Z, X + B, r=3)
    return bg.derive(net.graph())


def test_open_cycle_relations_bondgraphtools():
    model = _open_cycle(1)
    x0, x1, x2 = sympy.symbols("q_X q_Y q_Z", real=True)
    # BondGraphTools test_open_cycle: dx0 + 7 x0 - 2 x1 - 9 x2, dx1 - x0 + 6 x1 - 6 x2,
    # dx2 - 6 x0 - 4 x1 + 15 x2
    assert [sympy.expand(r) for r in model.rhs] == [-7 * x0 + 2 * x1 + 9 * x2,
                                                    x0 - 6 * x1 + 6 * x2,
                                                    6 * x0 + 4 * x1 - 15 * x2]


@pytest.mark.parametrize("x_A, flux", [(0.02, -3.0906200316489003), (2.0, 0.0),
                                       (200.0, 10.860335195530652)], ids=["low", "balanced", "high"])
def test_open_cycle_steady_fluxes_bondgraphtools(x_A, flux):
    """BondGraphTools test_sims.py::test_open_cycle: the flux of r1 after 10 s from (2, 2, 2)."""
    x = _final(_open_cycle(x_A), {}, 10.0, {"q_X": 2.0, "q_Y": 2.0, "q_Z": 2.0})
    v1 = 1 * (1 * x["q_X"] * 1 * x_A - 2 * x["q_Y"])
    assert v1 == pytest.approx(flux, abs=1e-6)


def test_mass_action_form_by_hand():
    # A + B = 2C with kf = 3, kr = 0.5 and K = 1 species: v = 3 qA qB - 0.5 qC^2
    net = ReactionNetwork("ma")
    A, B, C = (net.species(n, K=1) for n in "ABC")
    net.reaction("r", A + B, 2 * C, kf=3, kr=sympy.Rational(1, 2))
    model = bg.derive(net.graph())
    qA, qB, qC = sympy.symbols("q_A q_B q_C", real=True)
    v = 3 * qA * qB - qC**2 / 2
    assert [sympy.expand(x) for x in model.rhs] == [sympy.expand(-v), sympy.expand(-v),
                                                    sympy.expand(2 * v)]
    with pytest.raises(bg.ParameterError, match="give r .* or both kf and kr"):
        Re("bad", r=1, kf=2, kr=1)
    with pytest.raises(bg.ParameterError, match="not a mix"):
        Re("bad", kf=2)
