"""Thermal domain: pseudo bond graphs, radiation, true thermal graphs and RS.

Every expectation is a closed form derived in the test (exponential
equalisation, Stefan--Boltzmann cooling, first-order heating, a wall's
series resistances) or an energy balance.
"""

from __future__ import annotations


import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.library.electrical import Inductor
from bondgraph.library.thermal import (RS, Conduction, Convection, EntropyStore, HeatCapacity,
                                       RadiationExchange, TemperatureSource, TrueConduction,
                                       STEFAN_BOLTZMANN)

TIGHT = dict(rtol=1e-10, atol=1e-10, method="LSODA")


def _connect(g, pairs):
    for t, h in pairs:
        g.connect(t, h)


def test_two_heat_capacities_through_a_conductor_closed_form():
    C1, C2, Rth, T10, T20 = 2.0, 3.0, 5.0, 400.0, 300.0
    g = bg.BondGraph("two_bodies")
    g.add(HeatCapacity("b1", capacity=C1), HeatCapacity("b2", capacity=C2),
          Conduction("rod", resistance=Rth), bg.Zero("T1"), bg.Zero("T2"))
    _connect(g, [("T1", "b1.p"), ("T2", "b2.p"), ("T1", "rod.a"), ("rod.b", "T2")])
    model = bg.derive(g, outputs={"T1": bg.effort("b1.C"), "T2": bg.effort("b2.C")})
    ts = np.array([0.5, 3.0, 12.0])
    res = bg.simulate(model, {}, (0.0, 12.0), {"q_b1.C": C1 * T10, "q_b2.C": C2 * T20},
                      t_eval=ts, **TIGHT)
    tau = Rth * C1 * C2 / (C1 + C2)              # by hand: d(T1-T2)/dt = -(T1-T2)/tau
    Tf = (C1 * T10 + C2 * T20) / (C1 + C2)
    np.testing.assert_allclose(res["T1"], Tf + (T10 - Tf) * np.exp(-ts / tau), rtol=1e-8)
    np.testing.assert_allclose(res["T2"], Tf + (T20 - Tf) * np.exp(-ts / tau), rtol=1e-8)


def test_radiative_cooling_to_zero_kelvin_closed_form():
    C, A, eps, T0 = 50.0, 0.3, 0.8, 900.0
    g = bg.BondGraph("cooling")
    g.add(HeatCapacity("body", capacity=C), RadiationExchange("rad", area=A, emissivity=eps),
          TemperatureSource("space", value=0), bg.Zero("T"))
    _connect(g, [("T", "body.p"), ("T", "rad.a"), ("rad.b", "space.p")])
    model = bg.derive(g, outputs={"T": bg.effort("body.C")})
    k = eps * STEFAN_BOLTZMANN * A / C           # dT/dt = -k T^4 => T = (T0^-3 + 3 k t)^(-1/3)
    ts = np.array([10.0, 100.0, 1000.0])
    res = bg.simulate(model, {"sigma_SB": STEFAN_BOLTZMANN}, (0.0, 1000.0), [C * T0],
                      t_eval=ts, **TIGHT)
    np.testing.assert_allclose(res["T"], (T0**-3 + 3 * k * ts) ** (-1 / 3), rtol=1e-8)


def test_wall_with_convection_both_sides_steady_state_by_hand():
    h_in, h_out, k, L, A, C = 8.0, 25.0, 0.8, 0.2, 10.0, 4.0e5
    T_in, T_out = 293.0, 263.0
    g = bg.BondGraph("wall")
    g.add(TemperatureSource("room", value=T_in), TemperatureSource("air", value=T_out),
          Convection("hin", h=h_in, area=A), Convection("hout", h=h_out, area=A),
          Conduction("k1", length=L / 2, conductivity=k, area=A),
          Conduction("k2", length=L / 2, conductivity=k, area=A),
          HeatCapacity("mass", capacity=C), bg.Zero("s1"), bg.Zero("m"), bg.Zero("s2"))
    _connect(g, [("room.p", "hin.a"), ("hin.b", "s1"), ("s1", "k1.a"), ("k1.b", "m"),
                 ("m", "mass.p"), ("m", "k2.a"), ("k2.b", "s2"), ("s2", "hout.a"),
                 ("hout.b", "air.p")])
    model = bg.derive(g, outputs={"Ts1": bg.effort("s1"), "Ts2": bg.effort("s2"),
                                  "Q": bg.flow("hin.Q")})
    # steady state: one state, rhs(q) = 0
    (q,) = model.states
    q_star = sympy.solve(model.rhs[0], q)[0]
    R_tot = 1 / (h_in * A) + L / (k * A) + 1 / (h_out * A)      # series resistances by hand
    Q = (T_in - T_out) / R_tot
    T_mid = T_in - Q * (1 / (h_in * A) + L / 2 / (k * A))
    assert float(q_star) / C == pytest.approx(T_mid, rel=1e-12)
    at = {q: q_star}
    assert float(model.output_exprs[0].xreplace(at)) == pytest.approx(T_in - Q / (h_in * A), rel=1e-12)
    assert float(model.output_exprs[1].xreplace(at)) == pytest.approx(T_out + Q / (h_out * A), rel=1e-12)
    assert float(model.output_exprs[2].xreplace(at)) == pytest.approx(Q, rel=1e-12)


def _heater(*, loss: bool):
    """Se:V -> 1:i (with L) -> RS:heater -> body (entropy form), optionally losing heat."""
    g = bg.BondGraph("heater")
    g.add(bg.Se("V"), bg.One("i"), RS("Rh", 4.0), bg.Zero("T"),
          EntropyStore("body", heat_capacity=200.0, reference_temperature=300.0))
    _connect(g, [("V", "i"), ("i", "Rh"), ("Rh", "T"), ("T", "body.p")])
    if loss:
        g.add(TrueConduction("wall", resistance=0.5), TemperatureSource("amb", value=300.0))
        _connect(g, [("T", "wall.a"), ("wall.b", "amb.p")])
    else:
        g.add(Inductor("coil", inductance=0.3))
        g.connect("i", "coil.p")
        g.add(bg.Se("gnd", value=0))
        g.connect("coil.n", "gnd")
    return g


def test_resistor_heating_a_mass_through_rs_energy_balance():
    model = bg.derive(_heater(loss=False),
                      outputs={"T": bg.effort("body.S"), "i": bg.flow("i"),
                               "charge": bg.displacement("i")})
    V, L, c, T0 = 12.0, 0.3, 200.0, 300.0
    ts = np.linspace(0.05, 2.0, 5)
    res = bg.simulate(model, {}, (0.0, 2.0), None, u=[V], t_eval=ts, **TIGHT)
    electrical = V * res["charge"]                  # energy delivered by the source
    stored = L * res["i"] ** 2 / 2 + c * (res["T"] - T0)     # magnetic + heat in the body
    np.testing.assert_allclose(stored, electrical, rtol=1e-7)
    # and the current is the RL step response by hand
    np.testing.assert_allclose(res["i"], V / 4.0 * (1 - np.exp(-4.0 * ts / L)), rtol=1e-7)


def test_heated_body_losing_heat_closed_form():
    model = bg.derive(_heater(loss=True), outputs={"T": bg.effort("body.S")})
    V, Rh, c, Rth, Ta = 12.0, 4.0, 200.0, 0.5, 300.0
    P = V**2 / Rh
    tau = Rth * c                # c dT/dt = P - (T - Ta)/Rth
    ts = np.array([10.0, 100.0, 400.0])
    res = bg.simulate(model, {}, (0.0, 400.0), None, u=[V], t_eval=ts, **TIGHT)
    np.testing.assert_allclose(res["T"], Ta + P * Rth * (1 - np.exp(-ts / tau)), rtol=1e-8)


def test_rs_conserves_power_symbolically():
    g = bg.BondGraph("rs")
    g.add(bg.Sf("I"), bg.One("i"), RS("Rh"), bg.Zero("T"),
          EntropyStore("body", heat_capacity=1, reference_temperature=1))
    _connect(g, [("I", "i"), ("i", "Rh"), ("Rh", "T"), ("T", "body.p")])
    model = bg.derive(g, outputs={"T": bg.effort("body.S"), "Sdot": bg.flow("body.S")})
    I, Rh = sympy.Symbol("I", real=True), sympy.Symbol("Rh", positive=True)
    heat = model.output_exprs[0] * model.output_exprs[1]
    assert sympy.simplify(heat - Rh * I**2) == 0      # T * S' = R i^2


def test_rs_refuses_a_flow_source_on_its_thermal_port():
    g = bg.BondGraph("bad")
    g.add(bg.Se("V"), bg.One("i"), RS("Rh"), bg.Sf("S"))
    _connect(g, [("V", "i"), ("i", "Rh"), ("Rh", "S")])
    with pytest.raises(bg.CausalityError, match="RS:Rh"):
        bg.derive(g)
