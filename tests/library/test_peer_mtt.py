"""MTT's examples written natively with the component library, against hand and published results.

* ``Control/SimpleStateSpace/TwoTanks`` (MTT's teaching example, its
  ``TwoTanks_desc.tex`` and ``TwoTanks_lbl.txt``): two identical tanks of unit
  cross-section (``C lin effort,1``), each receiving the same inflow ``u``
  (the source on a 1-junction), each emptying through a linear outlet of
  conductance ``sigma_i`` (``R lin effort,sigma_i``) into a common drain;
  states the volumes ``v_i``, output the net outflow
  ``y = sigma_1 v_1 + sigma_2 v_2``.  By hand: ``A = diag(-sigma_1, -sigma_2)``,
  ``B = (1, 1)``, ``C = (sigma_1, sigma_2)`` and
  ``y/u = sigma_1/(s + sigma_1) + sigma_2/(s + sigma_2)``.
* Ogata's interacting two-tank liquid-level system (*Modern Control
  Engineering*, 5th ed., Sec. 4-2): ``Q2(s)/Q(s) = 1/(R1 C1 R2 C2 s^2 +
  (R1 C1 + R2 C2 + R2 C1) s + 1)``, the published formula.
* ``Thermal/ThermalConduction/HeatedRod``: a copper rod heated by a current,
  its ends held at ambient temperature, in a *true* thermal bond graph
  (``RS`` heating each lump, the lump a capacity in entropy form, conduction
  between lumps producing entropy), with MTT's parameter file
  (``HeatedRod_numpar.txt``: 20 segments, resistivity 16.8e-9 Ohm m, thermal
  resistivity 1/390 m K/W, 380 J/(kg K), density 8.96 as MTT writes it,
  radius 1 mm, length 1 m, ambient 300 K; a current of 10 A,
  ``HeatedRod_input.txt``).  By hand: the steady state solves the discrete
  Poisson problem ``2 T_k - T_{k-1} - T_{k+1} = r_t I^2 r`` with
  ``T_0 = T_{N+1} = 300``, so ``T_k = 300 + I^2 r r_t k (N + 1 - k)/2``; about
  the uniform 300 K state with no current the entropy form linearizes to
  ``dS/dt = -L S/(r_t c_t)``, ``L`` the Dirichlet path Laplacian, whose
  eigenvalues ``2 - 2 cos(j pi/(N + 1))`` give the poles.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.library import hydraulic as hy
from bondgraph.library.thermal import RS, EntropyStore, TrueConduction


def _connect(g, pairs):
    for t, h in pairs:
        g.connect(t, h)


# ------------------------------------------------------------------ MTT TwoTanks
def _mtt_two_tanks(s1, s2) -> bg.Model:
    g = bg.BondGraph("TwoTanks")
    g.add(hy.FlowSource("f_1"), bg.One("inflow"), bg.Zero("v_1"), bg.Zero("v_2"),
          hy.GravityTank("c_1", area=1, density=1, gravity=1),
          hy.GravityTank("c_2", area=1, density=1, gravity=1),
          hy.LaminarRestriction("r_1", resistance=1 / s1),
          hy.LaminarRestriction("r_2", resistance=1 / s2), bg.Zero("out"), hy.Tank("f_2"))
    _connect(g, [("f_1.p", "inflow"), ("inflow", "v_1"), ("inflow", "v_2"),
                 ("v_1", "c_1.p"), ("v_2", "c_2.p"), ("v_1", "r_1.a"), ("v_2", "r_2.a"),
                 ("r_1.b", "out"), ("r_2.b", "out"), ("out", "f_2.p")])
    return bg.derive(g, outputs={"y": bg.flow("r_1.R") + bg.flow("r_2.R")})


def test_mtt_two_tanks_state_space_and_transfer_function_by_hand():
    s1, s2 = sympy.symbols("sigma_1 sigma_2", positive=True)
    model = _mtt_two_tanks(s1, s2)
    assert model.state_names == ("q_c_1.C", "q_c_2.C")        # the volumes v_1, v_2
    ss = model.state_space()
    assert ss.A == sympy.Matrix([[-s1, 0], [0, -s2]])
    assert ss.B == sympy.Matrix([[1], [1]])
    assert ss.C == sympy.Matrix([[s1, s2]]) and ss.D == sympy.zeros(1, 1)
    s = sympy.Symbol("s")
    G = model.transfer_function("f_1.Q", "y").expr
    assert sympy.simplify(G - (s1 / (s + s1) + s2 / (s + s2))) == 0


def test_mtt_two_tanks_numeric_plant_and_step():
    model = _mtt_two_tanks(sympy.Rational(1, 2), 2)
    plant = bg.compile_plant(model).plant({})
    np.testing.assert_allclose(np.sort(plant.eigenvalues().real), [-2.0, -0.5])
    # unit step of u from empty tanks: v_i = (1 - exp(-sigma_i t))/sigma_i, y = 2 - e^-t/2 - e^-2t
    ts = np.array([0.5, 1.0, 3.0])
    res = bg.simulate(model, {}, (0.0, 3.0), None, u=[1.0], t_eval=ts, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res["y"], 2 - np.exp(-ts / 2) - np.exp(-2 * ts), rtol=1e-8)


# ------------------------------------------------------------------ Ogata's interacting tanks
def test_ogata_interacting_two_tanks_published_transfer_function():
    A1, A2, rho, g0, R1, R2 = sympy.symbols("A_1 A_2 rho g R_1 R_2", positive=True)
    g = bg.BondGraph("ogata")
    g.add(hy.FlowSource("q"), bg.Zero("h1"), bg.Zero("h2"),
          hy.GravityTank("t1", area=A1, density=rho, gravity=g0),
          hy.GravityTank("t2", area=A2, density=rho, gravity=g0),
          hy.LaminarRestriction("r1", resistance=R1), hy.LaminarRestriction("r2", resistance=R2),
          hy.Tank("drain"))
    _connect(g, [("q.p", "h1"), ("h1", "t1.p"), ("h1", "r1.a"), ("r1.b", "h2"),
                 ("h2", "t2.p"), ("h2", "r2.a"), ("r2.b", "drain.p")])
    model = bg.derive(g, outputs={"q2": bg.flow("r2.R")})
    C1, C2 = A1 / (rho * g0), A2 / (rho * g0)          # capacitances in pressure units
    s = sympy.Symbol("s")
    ogata = 1 / (R1 * C1 * R2 * C2 * s**2 + (R1 * C1 + R2 * C2 + R2 * C1) * s + 1)
    G = model.transfer_function("q.Q", "q2").expr
    assert sympy.simplify(G - ogata) == 0


# ------------------------------------------------------------------ MTT HeatedRod
N_SEG = 20
_AREA = math.pi * 1e-3**2
_DX = 1.0 / N_SEG
C_T = 380.0 * _AREA * _DX * 8.96              # thermal_capacity * mass, MTT's numbers
R_EL = 16.8e-9 * _DX / _AREA                  # electrical resistance of one segment
R_T = (1 / 390.0) * _DX / _AREA               # thermal resistance of one segment (= r_2)
T_AMB = 300.0


def _heated_rod() -> bg.Model:
    g = bg.BondGraph("HeatedRod")
    g.add(bg.Sf("I_r"), bg.One("i"), bg.Se("T_1", value=T_AMB), bg.Se("T_2", value=T_AMB))
    g.connect("I_r", "i")
    nodes = ["T_1"] + [f"n{k}" for k in range(1, N_SEG + 1)] + ["T_2"]
    for k in range(1, N_SEG + 1):
        g.add(bg.Zero(f"n{k}"), RS(f"r{k}", R_EL),
              EntropyStore(f"c{k}", heat_capacity=C_T, reference_temperature=T_AMB))
        _connect(g, [("i", f"r{k}"), (f"r{k}", f"n{k}"), (f"n{k}", f"c{k}.p")])
    for k in range(N_SEG + 1):                 # N + 1 conductions: T_1 - n1 - ... - nN - T_2
        g.add(TrueConduction(f"k{k}", resistance=R_T))
        _connect(g, [(nodes[k], f"k{k}.a"), (f"k{k}.b", nodes[k + 1])])
    outputs = {f"T{k}": bg.effort(f"c{k}.S") for k in range(1, N_SEG + 1)}
    return bg.derive(g, outputs=outputs)


@pytest.fixture(scope="module")
def heated_rod():
    return _heated_rod()


def test_mtt_heated_rod_steady_state_is_the_discrete_poisson_profile(heated_rod):
    """The model's equations vanish at the hand profile (the steady state of a linear conduction
    problem is unique), and each lump's temperature output is that profile."""
    I = 10.0
    k = np.arange(1, N_SEG + 1)
    hand = T_AMB + I**2 * R_EL * R_T * k * (N_SEG + 1 - k) / 2
    x_star = [C_T * math.log(T / T_AMB) for T in hand]          # S = c ln(T/T0)
    args = (*heated_rod.states, *heated_rod.inputs)
    f = sympy.lambdify(args, list(heated_rod.rhs))
    y = sympy.lambdify(args, list(heated_rod.output_exprs))
    scale = I**2 * R_EL / T_AMB                                 # one lump's entropy production
    np.testing.assert_allclose(f(*x_star, I), 0.0, atol=1e-10 * scale)
    np.testing.assert_allclose(y(*x_star, I), hand, rtol=1e-12)
    # a uniform 300 K rod is not a steady state while the current flows
    assert np.max(np.abs(f(*[0.0] * N_SEG, I))) == pytest.approx(scale, rel=1e-12)
    assert hand.max() - T_AMB == pytest.approx(60.0, abs=0.3)      # about 60 K at the middle


def test_mtt_heated_rod_poles_are_the_discrete_laplacian(heated_rod):
    x0 = {n: 0.0 for n in heated_rod.state_names}
    plant = heated_rod.linearize(x0, {"I_r": 0.0}, values={})
    j = np.arange(1, N_SEG + 1)
    hand = -(2 - 2 * np.cos(j * np.pi / (N_SEG + 1))) / (R_T * C_T)
    np.testing.assert_allclose(np.sort(plant.eigenvalues().real), np.sort(hand), rtol=1e-9)
    assert np.all(np.abs(plant.eigenvalues().imag) == 0)


def test_models_two_tanks_in_units_gives_ogatas_numbers():
    """models/two_tanks.py: areas 2 and 1 m^2, R = 0.02 and 0.03 bar s/l (= 2e6, 3e6 Pa s/m^3
    by hand: 1 bar = 1e5 Pa, 1 l = 1e-3 m^3), water; C = A/(rho g)."""
    from pathlib import Path

    from bondgraph.modelfile import load_model

    d = load_model(Path(__file__).resolve().parents[2] / "models" / "two_tanks.py")
    assert d.parameters["R1"] == pytest.approx(2e6) and d.parameters["R2"] == pytest.approx(3e6)
    R1, R2, C1, C2 = 2e6, 3e6, 2 / (1000 * 9.81), 1 / (1000 * 9.81)
    plant = d.plant()
    hand = np.roots([R1 * C1 * R2 * C2, R1 * C1 + R2 * C2 + R2 * C1, 1.0])
    np.testing.assert_allclose(np.sort(plant.eigenvalues().real), np.sort(hand), rtol=1e-10)
    G = plant.to_tf(input="q.Q", output="q_out")
    assert float(np.real(G.dcgain())) == pytest.approx(1.0, rel=1e-12)      # Ogata: q2/q(0) = 1
    assert dict(plant.units) == {"q_t1.C": "meter**3", "q_t2.C": "meter**3",
                                 "q.Q": "meter**3/second", "q_out": "meter**3/second",
                                 "p1": "pascal", "p2": "pascal"}
