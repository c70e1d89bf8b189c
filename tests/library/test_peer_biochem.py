"""BondGraphTools' biochemical examples not covered by test_chemical.py, built natively.

* The SERCA pump (Tran et al., *Biophys. J.* 96, 2009; as a bond graph Pan et
  al., *J. Theor. Biol.* 481, 2019), the model of BondGraphTools' biochemical
  tutorial "4 - Generating a model of SERCA" (github.com/mic-pan/
  BGT_BiochemicalNetworkTutorials): nine reactions among the pump states
  P1 ... P10 with the chemostats MgATP, MgADP, Pi, H, Cai and Casr, its rate
  constants, thermodynamic constants and chemostat amounts.  The expected
  values are the constitutive relations the tutorial prints once the
  parameters are set (its cell 15: ``dx_0 + 482504830082603/100000000000
  x_0 - ...``, states x_0 ... x_8 = P1, P2, P2a, P4, P5, P6, P8, P9, P10;
  the SR calcium left as the potential ``u_0`` of its chemostat).
* BondGraphTools' closed cycle (test/test_biochem.py, test_closed_cycle):
  X = Y = Z = X with K = 1, 2, 3 and r = 1, 2, 3, its printed relations.
* BondGraphTools' test_nlin_se: A + B = C with A held by an effort source;
  its relations ``dx_B = -E x_B + x_C``, ``dx_C = E x_B - x_C`` where ``E``
  is A's held amount (K = r = 1).
* BondGraphs.jl's ion pore as its documentation writes it (docs/src/examples.md,
  from Cudmore et al. 2021): a reaction charging a membrane capacitor through
  TF(F) and TF(+-z/2), for Na, Cl and K; the Nernst potential and the pole by
  hand (test_chemical.py has the same physics with one TF(zF/2) per side).
"""

from __future__ import annotations

import math

import pytest
import sympy

import bondgraph as bg
from bondgraph.library.chemical import Chemostat, ReactionNetwork, Re

#: BondGraphTools' gas constant (reaction_builder.R) and the tutorial's temperature
R_BGT, T_SERCA = 8.3144598, 310.0

RATES = {"R1_2": 0.00053004, "R2_2a": 8326784.0537, "R2_4": 1567.7476, "R4_5": 1567.7476,
         "R5_6": 3063.4006, "R6_8": 130852.3839, "R8_9": 11612934.8748,
         "R9_10": 11612934.8748, "R10_1": 0.049926}
K = {"P1": 5263.6085, "P2": 3803.6518, "P2a": 3110.4445, "P4": 16520516.1239, "P5": 0.82914,
     "P6": 993148.433, "P8": 37.7379, "P9": 2230.2717, "P10": 410.6048, "Cai": 1.9058,
     "Casr": 31.764, "MgATP": 244.3021, "MgADP": 5.8126e-7, "Pi": 0.014921, "H": 1862.5406}
HELD = {"Cai": 0.0057, "H": 0.004028, "MgADP": 1.3794, "MgATP": 3.8, "Pi": 570.0}
STATES = ("P1", "P2", "P2a", "P4", "P5", "P6", "P8", "P9", "P10")     # BGT's x_0 ... x_8

#: the tutorial's printed relations dx_i + sum_j c_ij x_j = 0, as dx_i/dt = sum_j a_ij x_j
#: (a_ij = -c_ij); the x_6 terms of rows 5 and 6 carry exp(k u_0), k = 387975470350209/5e17
F = sympy.Rational
PRINTED = {
    0: {0: -F(482504830082603, 100000000000), 1: F(252010950009, 125000000000),
        8: F(1601551191, 78125000)},
    1: {0: F(129500971360511, 50000000000), 1: -F(29701834891466, 125),
        2: F(64749999156297, 2500), 3: F(51799999008011, 2000)},
    2: {1: F(118807339213011, 500), 2: -F(64749999156297, 2500)},
    3: {1: F(351844898712793, 500000000000), 3: -F(517999990080109, 10000),
        4: F(731634931235523, 10000000000)},
    4: {3: F(51799999008011, 2000), 4: -F(757034810970363, 10000000000),
        5: F(243937525489403, 100000000000)},
    5: {4: F(634996993371, 250000000), 5: -F(64977921231987, 500),
        6: ("exp", F(493809417837981, 100000000))},
    6: {5: F(129955840024599, 1000), 6: ("exp-", -F(49333296450869, 2000)),
        7: F(129500000026047, 5000)},
    7: {6: F(49333296450869, 2000), 7: -F(518000000104189, 10000),
        8: F(357734827121321, 10000)},
    8: {0: F(223502887361581, 100000000000), 7: F(129500000026047, 5000),
        8: -F(4471685341579, 125)},
}
EXP_K = F(387975470350209, 500000000000000000)       # 2/(R T) as the tutorial prints it


def _serca(casr_amount):
    net = ReactionNetwork("SERCA", temperature=T_SERCA, gas_constant=R_BGT)
    sp = {n: net.species(n, K=K[n]) for n in STATES}
    for n, amount in {**HELD, "Casr": casr_amount}.items():
        sp[n] = net.chemostat(n, K=K[n], amount=amount)
    P1, P2, P2a, P4, P5, P6, P8, P9, P10 = (sp[n] for n in STATES)
    MgATP, MgADP, Pi, H, Cai, Casr = (sp[n] for n in ("MgATP", "MgADP", "Pi", "H", "Cai", "Casr"))
    for name, subs, prods in (("R1_2", P1 + MgATP, P2), ("R2_2a", P2 + H, P2a),
                              ("R2_4", P2 + 2 * Cai, P4), ("R4_5", P4, P5 + 2 * H),
                              ("R5_6", P5, P6 + MgADP), ("R6_8", P6, P8 + 2 * Casr),
                              ("R8_9", P8 + 2 * H, P9), ("R9_10", P9, P10 + H),
                              ("R10_1", P10, P1 + Pi)):
        net.reaction(name, subs, prods, r=RATES[name])
    return net


def test_serca_relations_are_the_tutorials_printed_ones():
    a = 0.05 * 2.28                  # the tutorial's SR calcium at t = 0: (0.05 + 0.01 t) vol_sr
    u0 = R_BGT * T_SERCA * math.log(K["Casr"] * a)          # its chemostat's potential
    model = bg.derive(_serca(a).graph())
    names = [f"q_{n}" for n in STATES]
    assert model.state_names == tuple(names)
    # the printed exponent is 2/(R T) of R6_8's two Casr
    assert float(EXP_K) == pytest.approx(2 / (R_BGT * T_SERCA), rel=1e-14)
    exp_term = math.exp(float(EXP_K) * u0)
    for i, row in PRINTED.items():
        rhs = sympy.expand(model.rhs[i])
        assert rhs.free_symbols <= set(model.states)
        for j, state in enumerate(model.states):
            got = float(rhs.coeff(state))
            c = row.get(j, 0)
            if isinstance(c, tuple):             # R6_8's reverse term, with the SR calcium
                kind, base = c
                want = float(base) * (exp_term if kind == "exp" else 1.0)
                if kind == "exp-":               # row 6: -4938094.17 e^{k u0} x_6 - 24666.6 x_6
                    want = float(base) - float(PRINTED[5][6][1]) * exp_term
            else:
                want = float(c)
            assert got == pytest.approx(want, rel=1e-9, abs=1e-12), (STATES[i], STATES[j])


def test_serca_stoichiometry_cycle_and_the_pump_moiety():
    from bondgraph.library.chemical import conservation_laws, stoichiometric_matrix

    g = _serca(0.114).graph()
    st = stoichiometric_matrix(g)
    assert st.species == STATES
    # by hand: P1 -> P2 -> (P2a) / P4 -> P5 -> P6 -> P8 -> P9 -> P10 -> P1; the pump is conserved
    assert conservation_laws(g) == ({n: 1 for n in STATES},)
    cycle = sympy.Matrix([1, 0, 1, 1, 1, 1, 1, 1, 1])        # every reaction once but R2_2a
    assert st.matrix * cycle == sympy.zeros(len(STATES), 1)


def test_closed_cycle_relations_bondgraphtools():
    net = ReactionNetwork("closed_cycle", temperature=1, gas_constant=1)
    X, Y, Z = net.species("X", K=1), net.species("Y", K=2), net.species("Z", K=3)
    net.reaction("r1", X, Y, r=1)
    net.reaction("r2", Y, Z, r=2)
    net.reaction("r3", Z, X, r=3)
    model = bg.derive(net.graph())
    x0, x1, x2 = model.states
    # BondGraphTools: dx0 + 4 x0 - 2 x1 - 9 x2, dx1 - x0 + 6 x1 - 6 x2, dx2 - 3 x0 - 4 x1 + 15 x2
    assert [sympy.expand(r) for r in model.rhs] == [-4 * x0 + 2 * x1 + 9 * x2,
                                                    x0 - 6 * x1 + 6 * x2,
                                                    3 * x0 + 4 * x1 - 15 * x2]


def test_held_species_bondgraphtools_nlin_se():
    E = sympy.Symbol("E", positive=True)
    net = ReactionNetwork("nlin_se", temperature=1, gas_constant=1)
    A = net.chemostat("A", K=1, amount=E)
    B, C = net.species("B", K=1), net.species("C", K=1)
    net.reaction("r", A + B, C, r=1)
    model = bg.derive(net.graph())
    x1, x2 = model.states
    assert [sympy.expand(r) for r in model.rhs] == [-E * x1 + x2, E * x1 - x2]


# ------------------------------------------------------------------ BondGraphs.jl's ion pore
def _ion_pore_bondgraphs_jl(z, c_e, c_i):
    """docs/src/examples.md, "Electrochemical System: Ion Pore Transport" (Cudmore et al. 2021).

    As written there: a membrane C = 1 behind TF(F) (n = 96485) on the membrane
    potential's 0-junction, TF(z/2) from it to the reverse side of the pore and
    TF(-z/2) to the forward side, chemostats of K = 1, r = 1e-7, R = 8.314,
    T = 310.  BondGraphs.jl's TF is ``e2 = n e1`` with its ports numbered; ours
    is ``e1 = n e2`` with port 1 the bond in.  Its TF(F) and TF(z/2) have their
    bond in at port 2, so our moduli are the same, F and z/2; its TF(-z/2)
    has its bond in at port 1, so ours is -2/z.
    """
    thermo = dict(temperature=310.0, gas_constant=8.314)
    g = bg.BondGraph("ion_pore")
    g.add(bg.C("mem", 1), Chemostat("Ie", K=1, amount=c_e, **thermo),
          Chemostat("Ii", K=1, amount=c_i, **thermo), bg.Zero("potential_mem"),
          bg.One("flow_f"), bg.One("flow_r"), bg.TF("F", 96485), bg.TF("zf", sympy.Rational(-2, z)),
          bg.TF("zr", sympy.Rational(z, 2)), Re("pore", r=1e-7, **thermo))
    for t, h in [("Ie", "flow_f"), ("flow_f", "pore"), ("pore", "flow_r"), ("flow_r", "Ii"),
                 ("flow_r", "zr"), ("zr", "potential_mem"), ("potential_mem", "zf"),
                 ("zf", "flow_f"), ("potential_mem", "F"), ("F", "mem")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"V": bg.effort("mem")})


@pytest.mark.parametrize("ion, z, c_e, c_i, nernst_mV", [
    ("Na", 1, 0.155, 0.019, 56.07), ("Cl", -1, 0.112, 0.078, -9.664),
    ("K", 1, 0.005, 0.136, -88.24)])
def test_ion_pore_as_bondgraphs_jl_writes_it_reaches_the_nernst_potential(ion, z, c_e, c_i,
                                                                           nernst_mV):
    """By hand: equilibrium mu_e - z F V/2 = mu_i + z F V/2, V = RT/(zF) ln(c_e/c_i) (the
    values above, with RT/F = 26.712 mV); the pole -(zF)^2 r sqrt(c_e c_i)/(RT C).  The
    example plots 1000 ms from V = 0: nine time constants or more, V within 1e-3 of Nernst."""
    model = _ion_pore_bondgraphs_jl(z, c_e, c_i)
    RT, F = 8.314 * 310.0, 96485.0
    V_star = RT / (z * F) * math.log(c_e / c_i)
    assert V_star * 1e3 == pytest.approx(nernst_mV, abs=0.01)
    (q,) = model.states
    f = sympy.lambdify(q, model.rhs[0])
    assert abs(f(V_star)) <= 1e-12 * abs(f(0.0))            # C = 1: q = V
    slope = float(sympy.diff(model.rhs[0], q).subs(q, V_star))
    pole = -(z * F) ** 2 * 1e-7 * math.sqrt(c_e * c_i) / RT
    assert slope == pytest.approx(pole, rel=1e-9)
    res = bg.simulate(model, {}, (0.0, 1000.0), [0.0], t_eval=[1000.0], method="LSODA",
                      rtol=1e-10, atol=1e-14)
    assert res["V"][-1] == pytest.approx(V_star, rel=1e-3)


@pytest.mark.parametrize("x0, published", [
    ((1.0, 2.0, 3.0), (1.23606, 2.23606, 2.76393)),
    ((-1.0, 2.0, 3.0), (0.44949, 3.44949, 1.55051))], ids=["positive", "negative-A"])
def test_a_plus_b_from_a_negative_amount_bondgraphs_jl(x0, published):
    """BondGraphs.jl "Simple Biochemical Simulation", both of its runs (the second starts A at
    -1 to check that no log(q) is left in the equations).  By hand: A - B and A + C are
    conserved and at t = 3 the run has reached C = A B, so A solves
    A^2 + (1 + B0 - A0) A - (A0 + C0) = 0 (sqrt(5) - 1 and sqrt(6) - 2)."""
    net = ReactionNetwork("ABC")
    A, B, C = (net.species(n, K=1) for n in "ABC")
    net.reaction("r1", A + B, C, r=1)
    model = bg.derive(net.graph())
    a0, b0, c0 = x0
    res = bg.simulate(model, {}, (0.0, 3.0), dict(zip(model.state_names, x0)), t_eval=[3.0],
                      method="LSODA", rtol=1e-10, atol=1e-12)
    got = [res[n][-1] for n in model.state_names]
    a = (-(1 + b0 - a0) + math.sqrt((1 + b0 - a0) ** 2 + 4 * (a0 + c0))) / 2
    hand = (a, a + b0 - a0, a0 + c0 - a)
    assert got == pytest.approx(list(published), abs=1e-5)
    assert got == pytest.approx(list(hand), abs=1e-5)
