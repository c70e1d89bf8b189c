"""Component library: mechanical, hydraulic and electromechanical components.

Expectations are hand derivations (Newton, the gas law, the orifice law,
reflected inertia) or the independently written ``models/srv02.py``.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.library import electrical as el, hydraulic as hy, mechanical as me
from bondgraph.library.catalogue import check_component, load_all
from bondgraph.library.electromechanical import DCMotor

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "models"))
import srv02  # noqa: E402

s = sympy.Symbol("s")


def _connect(g, pairs):
    for t, h in pairs:
        g.connect(t, h)
    return g


def _tf(model, inp, out):
    return sympy.cancel(model.transfer_function(inp, out).expr)


@pytest.mark.parametrize("key", sorted(load_all()), ids=str)
def test_every_component_passes_the_sub_model_check(key):
    cls = load_all()[key]
    assert check_component(cls).startswith(key)


def test_gear_is_an_n_to_1_reduction_reflected_inertia_by_hand():
    N, Jm, Jl = sympy.symbols("N J_m J_l", positive=True)
    g = bg.BondGraph("gearbox")
    g.add(me.TorqueSource("tau"), me.Inertia("motor", inertia=Jm), me.Gear("gb", ratio=N),
          me.Inertia("load", inertia=Jl), bg.One("wm"), bg.One("wl"))
    _connect(g, [("tau.p", "wm"), ("wm", "motor.p"), ("wm", "gb.a"), ("gb.b", "wl"),
                 ("wl", "load.p")])
    model = bg.derive(g, outputs={"wm": bg.flow("wm"), "wl": bg.flow("wl")})
    # Newton with the constraint omega_l = omega_m / N, tau_l = N tau_g:
    # (Jm N^2 + Jl) domega_l/dt = N tau
    assert sympy.simplify(_tf(model, "tau.tau", "wl") - N / ((Jm * N**2 + Jl) * s)) == 0
    assert sympy.simplify(_tf(model, "tau.tau", "wm") - N**2 / ((Jm * N**2 + Jl) * s)) == 0


@pytest.mark.parametrize("make, ratio", [
    (lambda: me.Lever("t", arm_a=0.3, arm_b=0.1), 0.1 / 0.3),
    (lambda: me.RackPinion("t", radius=0.02), 0.02),
    (lambda: me.Belt("t", radius_a=0.05, radius_b=0.2), 0.25),
], ids=["lever", "rack_pinion", "belt"])
def test_transmissions_velocity_ratio_by_hand(make, ratio):
    # a velocity source on port a, a damper b on port b: v_b = ratio v_a, F_a = ratio**2 b v_a
    # (a plain Sf: port a is a rotation for a rack and pinion or a belt, and the library's
    # VelocitySource is a translation, which the domain check refuses there)
    g = bg.BondGraph("drive")
    g.add(bg.Sf("src"), make(), bg.One("va"), bg.One("vb"), bg.R("b", 3.0))
    _connect(g, [("src", "va"), ("va", "t.a"), ("t.b", "vb"), ("vb", "b")])
    model = bg.derive(g, outputs={"vb": bg.flow("vb"), "Fa": bg.effort("src")})
    D = np.array(model.state_space().D, dtype=float)
    assert D[0, 0] == pytest.approx(ratio, rel=1e-12)
    assert D[1, 0] == pytest.approx(3.0 * ratio**2, rel=1e-12)


def test_orifice_and_accumulator_equilibrium_and_pole_by_hand():
    Q0, cd, A, rho = 2e-4, 0.61, 1.2e-6, 850.0
    V0, p0, n = 2e-3, 3e6, 1.4
    g = bg.BondGraph("circuit")
    g.add(hy.FlowSource("pump", value=Q0), hy.Accumulator("acc", volume=V0, precharge=p0,
                                                          exponent=n),
          hy.Orifice("o", area=A, discharge=cd, density=rho), hy.Tank("tank"), bg.Zero("p1"))
    _connect(g, [("pump.p", "p1"), ("p1", "acc.p"), ("p1", "o.a"), ("o.b", "tank.p")])
    model = bg.derive(g, outputs={"p": bg.effort("p1")})
    (q,) = model.states
    # equilibrium: the orifice passes Q0, Q0 = cd A sqrt(2 p/rho) => p* = rho Q0^2 / (2 cd^2 A^2)
    p_star = rho * Q0**2 / (2 * cd**2 * A**2)
    q_star = V0 * (1 - (p0 / p_star) ** (1 / n))          # the gas law p V^n = p0 V0^n
    f = sympy.lambdify(q, model.rhs[0])
    assert abs(f(q_star)) < 1e-12 * Q0
    assert float(model.output_exprs[0].subs(q, q_star)) == pytest.approx(p_star, rel=1e-12)
    # pole: d(dq/dt)/dq = -(Q0 / (2 p*)) dp/dq with dp/dq = n p / (V0 - q)
    pole = -n * Q0 / (2 * (V0 - q_star))
    assert 0 < q_star < V0
    h = 1e-6 * q_star                                       # central difference of the model
    assert (f(q_star + h) - f(q_star - h)) / (2 * h) == pytest.approx(pole, rel=1e-6)


def test_cylinder_driving_a_mass_transfer_function_by_hand():
    Rv, V, beta, A, m, b, k = sympy.symbols("R_v V beta A m b k", positive=True)
    g = bg.BondGraph("actuator")
    g.add(hy.PressureSource("ps"), bg.One("line"), bg.R("Rv", Rv),
          hy.Cylinder("cyl", area=A, volume=V, bulk_modulus=beta),
          me.Mass("load", mass=m), me.Damper("d", damping=b, grounded=True),
          me.Spring("spring", stiffness=k, grounded=True), bg.One("v"))
    _connect(g, [("ps.p", "line"), ("line", "Rv"), ("line", "cyl.a"), ("cyl.rod", "v"),
                 ("v", "load.p"), ("v", "d.a"), ("v", "spring.a")])
    model = bg.derive(g, outputs={"x": bg.displacement("spring.C")})
    # by hand: C dp/dt = (Ps - p)/R - A v (C = V/beta), m dv/dt = A p - b v - k x
    C = V / beta
    hand = A / (Rv * C * m * s**3 + (m + Rv * C * b) * s**2 + (b + Rv * C * k + Rv * A**2) * s + k)
    assert sympy.simplify(_tf(model, "ps.P", "x") - hand) == 0
    # steady state: x = A Ps / k
    assert sympy.simplify(hand.subs(s, 0) - A / k) == 0


def test_proportional_valve_flow_follows_the_spool():
    g = bg.BondGraph("valve")
    g.add(hy.PressureSource("ps", value=1e6), hy.ProportionalValve("v", gradient=0.01,
                                                                   discharge=0.6, density=850),
          hy.Tank("tank"), me.VelocitySource("spool", value=1e-3))
    _connect(g, [("ps.p", "v.a"), ("v.b", "tank.p"), ("spool.p", "v.spool")])
    model = bg.derive(g, outputs={"Q": bg.flow("v.Q")})
    res = bg.simulate(model, {}, (0.0, 2.0), None, t_eval=[0.5, 2.0], rtol=1e-10, atol=1e-14)
    x = 1e-3 * np.array([0.5, 2.0])                 # spool displacement
    hand = 0.6 * 0.01 * x * math.sqrt(2 * 1e6 / 850)
    np.testing.assert_allclose(res["Q"], hand, rtol=1e-8)


def test_srv02_hub_rebuilt_from_components_equals_models_srv02():
    S = srv02.SYMBOLS
    g = bg.BondGraph("srv02_lib")
    g.add(bg.Se("e_in"),
          DCMotor("motor", resistance=S["Rm"], inductance=S["Lm"], back_emf=S["km"],
                  torque_constant=S["kt"], efficiency=S["eta_m"], inertia=S["Jm"],
                  damping=False),
          me.Gear("gear", ratio=S["Kg"], efficiency=S["eta_g"]), bg.One("w_l"),
          me.RotaryDamper("Beq", damping=S["Beq"], grounded=True))
    _connect(g, [("e_in", "motor.elec"), ("motor.shaft", "gear.a"), ("gear.b", "w_l"),
                 ("w_l", "Beq.a")])
    lib = bg.derive(g, outputs={"theta": bg.displacement("w_l"), "omega": bg.flow("w_l"),
                                "i_m": bg.flow("motor.i")})
    ref = bg.derive(srv02.build(), outputs={"theta": bg.displacement("w_l"),
                                            "omega": bg.flow("w_l"), "i_m": bg.flow("i")})
    assert lib.states.__len__() == ref.states.__len__() == 3
    for out in ("theta", "omega", "i_m"):
        G_lib, G_ref = _tf(lib, "e_in", out), _tf(ref, "e_in", out)
        assert sympy.simplify(G_lib - G_ref) == 0, out
    values = {k: v for k, v in srv02.PARAMETERS.items() if k not in ("J_l", "k_pot", "k_tach")}
    P_lib = bg.numeric_plant(lib, values)
    P_ref = bg.numeric_plant(ref, values)
    np.testing.assert_allclose(np.sort_complex(np.linalg.eigvals(P_lib.A)),
                               np.sort_complex(np.linalg.eigvals(P_ref.A)), rtol=1e-9)


def test_component_errors_name_the_component_and_parameter():
    with pytest.raises(bg.ParameterError, match="Gear 'g': ratio must be positive, got -3"):
        me.Gear("g", ratio=-3)
    with pytest.raises(bg.ParameterError, match="Orifice 'o': area"):
        hy.Orifice("o", area=0)
    g = bg.BondGraph("g")
    g.add(el.Resistor("R1"))
    with pytest.raises(bg.PortError, match="not a port of sub-model 'R1'; its ports are: p, n"):
        g.connect("R1.x", "R1.n")


def test_two_tanks_through_orifices_equilibrium_and_poles_by_hand():
    """The classic two-tank cascade (MTT's TwoTanks shape) with square-root outlets.

    By hand: at equilibrium each orifice passes Q0: p2 = (Q0/c2)**2 (to the
    drain), p1 = p2 + (Q0/c1)**2 (into tank 2), q_i = C_i p_i with
    C_i = A_i/(rho g).  Linearized, each orifice is a conductance
    g_i = Q0/(2 dp_i): dq1/dt = -g1 (p1 - p2), dq2/dt = g1 (p1 - p2) - g2 p2.
    """
    Q0, rho, g0 = 1e-3, 1000.0, 9.81
    A1, A2, c1, c2 = 0.5, 0.8, 2.0e-5, 3.0e-5          # c = Cd a sqrt(2/rho)
    cd, rho_o = 0.6, rho
    a1, a2 = c1 / (cd * math.sqrt(2 / rho_o)), c2 / (cd * math.sqrt(2 / rho_o))
    g = bg.BondGraph("two_tanks")
    g.add(hy.FlowSource("pump", value=Q0),
          hy.GravityTank("t1", area=A1, density=rho, gravity=g0),
          hy.GravityTank("t2", area=A2, density=rho, gravity=g0),
          hy.Orifice("o1", area=a1, discharge=cd, density=rho_o),
          hy.Orifice("o2", area=a2, discharge=cd, density=rho_o),
          hy.Tank("drain"), bg.Zero("p1"), bg.Zero("p2"))
    _connect(g, [("pump.p", "p1"), ("p1", "t1.p"), ("p1", "o1.a"), ("o1.b", "p2"),
                 ("p2", "t2.p"), ("p2", "o2.a"), ("o2.b", "drain.p")])
    model = bg.derive(g)
    q = model.states
    C1, C2 = A1 / (rho * g0), A2 / (rho * g0)
    p2 = (Q0 / c2) ** 2
    p1 = p2 + (Q0 / c1) ** 2
    x_star = [C1 * p1, C2 * p2]
    f = sympy.lambdify(q, list(model.rhs))
    assert np.allclose(f(*x_star), 0.0, atol=1e-12 * Q0)
    g1, g2 = Q0 / (2 * (p1 - p2)), Q0 / (2 * p2)
    J = np.empty((2, 2))
    for j in range(2):          # central differences of the model's right-hand side
        h = 1e-6 * x_star[j]
        up, dn = list(x_star), list(x_star)
        up[j] += h
        dn[j] -= h
        J[:, j] = (np.array(f(*up)) - np.array(f(*dn))) / (2 * h)
    hand = [[-g1 / C1, g1 / C2], [g1 / C1, -(g1 + g2) / C2]]
    np.testing.assert_allclose(J, hand, rtol=1e-6)


def test_pipe_inertance_drives_the_orifice_inverse_law():
    """Flow causality on the orifice: the pipe's inertance fixes Q, the orifice gives dp.

    Steady state by hand: Ps = R Q + Q**2/c**2, the positive root.
    """
    Ps, L, d, mu, rho = 2e5, 3.0, 0.01, 0.03, 850.0
    cd, a = 0.6, 2e-5
    g = bg.BondGraph("line")
    g.add(hy.PressureSource("ps", value=Ps), hy.Pipe("pipe", length=L, diameter=d, viscosity=mu,
                                                     density=rho),
          hy.Orifice("o", area=a, discharge=cd, density=rho), hy.Tank("drain"), bg.Zero("n"))
    _connect(g, [("ps.p", "pipe.a"), ("pipe.b", "n"), ("n", "o.a"), ("o.b", "drain.p")])
    model = bg.derive(g, outputs={"Q": bg.flow("pipe.Q")})
    assert len(model.states) == 1                      # the pipe's pressure momentum
    R = 128 * mu * L / (math.pi * d**4)
    c = cd * a * math.sqrt(2 / rho)
    Q = (-R + math.sqrt(R**2 + 4 * Ps / c**2)) / (2 / c**2)
    I = rho * L / (math.pi * d**2 / 4)
    rhs = sympy.lambdify(model.states, model.rhs[0])
    assert abs(rhs(I * Q)) < 1e-9 * Ps
