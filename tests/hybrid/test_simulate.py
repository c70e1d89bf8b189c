"""Switched simulations against closed forms solved in the test (rectifier, clutch, end stop)."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import bondgraph as bg
from bondgraph.hybrid import (ChatteringError, ControlledSwitch, Diode, EventBudgetError, HybridError,
                              SwitchedModel, library, simulate)


# ---------------------------------------------------------------- half-wave rectifier
VM, F, RL, CL = 10.0, 50.0, 100.0, 1e-4
W, TAU = 2 * math.pi * F, RL * CL


def rectifier_by_hand(t_end):
    """Switching instants and v(t) of the ideal half-wave rectifier, from the closed forms.

    Conducting, v = Vm sin(w t) and the diode current C v' + v/R = Vm (w C cos + sin/R)
    vanishes at tan(w t) = -w R C; blocking, v = v_off exp(-(t - t_off)/(R C)) until
    Vm sin(w t) catches up with it.
    """
    t_off0 = (math.pi - math.atan(W * TAU)) / W
    offs, ons = [], []
    k = 0
    while True:
        t_off = t_off0 + k * 2 * math.pi / W
        if t_off > t_end:
            break
        offs.append(t_off)
        v_off = VM * math.sin(W * t_off)
        gap = lambda t: VM * math.sin(W * t) - v_off * math.exp(-(t - t_off) / TAU)
        lo = (k + 1) * 2 * math.pi / W
        t_on = brentq(gap, lo, lo + math.pi / (2 * W), xtol=1e-15)
        if t_on > t_end:
            break
        ons.append(t_on)
        k += 1

    def v(t):
        for t_off, t_on in zip(offs, ons + [math.inf]):
            if t < t_off:
                return VM * math.sin(W * t)
            if t < t_on:
                return VM * math.sin(W * t_off) * math.exp(-(t - t_off) / TAU)
        return VM * math.sin(W * t)
    return offs, ons, v


def test_half_wave_rectifier_switching_instants_and_voltage():
    sm = SwitchedModel(library.rectifier(), outputs={"v": bg.effort("C"), "i": bg.flow("D")})
    t_end = 0.05
    grid = np.linspace(0, t_end, 401)
    res = simulate(sm, (0, t_end), values={"Vm": VM, "w": W, "R": RL, "C": CL}, t_eval=grid)
    offs, ons, v = rectifier_by_hand(t_end)
    got_off = [e.time for e in res.events if str(e.after) == "D off"]
    got_on = [e.time for e in res.events if str(e.after) == "D on"]
    assert len(got_off) == len(offs) == 3 and len(got_on) == len(ons) == 2
    np.testing.assert_allclose(got_off, offs, rtol=0, atol=1e-9)
    np.testing.assert_allclose(got_on, ons, rtol=0, atol=1e-9)
    assert all(e.energy_loss == 0 for e in res.events)
    expect = np.array([v(t) for t in res.t])
    np.testing.assert_allclose(res.outputs["v"], expect, rtol=0, atol=1e-6 * VM)
    # while blocking the diode carries no current; while conducting it is forward
    assert np.all(res.outputs["i"] >= -1e-9)


def test_rectifier_starts_blocking_when_the_capacitor_is_charged():
    sm = SwitchedModel(library.rectifier(), outputs={"v": bg.effort("C")})
    res = simulate(sm, (0, 1e-3), {"q_C": CL * 5.0}, values={"Vm": VM, "w": W, "R": RL, "C": CL})
    # built with the diode on, but v = 5 > Vs(0) = 0: the consistent initial mode is off,
    # reached without any loss; then v = 5 exp(-t/RC)
    assert str(res.modes[0]) == "D off" and res.events[0].energy_loss == 0
    assert res.outputs["v"][-1] == pytest.approx(5 * math.exp(-1e-3 / TAU), rel=1e-8)


# ---------------------------------------------------------------- clutch
def test_clutch_lock_momentum_energy_and_newton_after():
    J1, J2, T, w20, t_lock = 1.0, 2.0, 1.0, 3.0, 1.0
    sm = SwitchedModel(library.clutch(), outputs={"w1": bg.flow("J1"), "w2": bg.flow("J2"),
                                                  "torque": bg.effort("K")})
    grid = np.array([0.5, 1.5, 2.0])
    res = simulate(sm, (0, 2), {"p_J2": J2 * w20}, values={"J1": J1, "J2": J2, "t_lock": t_lock},
                   inputs={"tau": T}, t_eval=grid)
    (ev,) = res.events
    assert ev.time == pytest.approx(t_lock, abs=1e-12) and ev.elements == ("K",)
    # before the lock (Newton): w1 = T t/J1, w2 constant
    w1, w2 = T * t_lock / J1, w20
    i = list(res.t).index(0.5)
    assert res.outputs["w1"][i] == pytest.approx(0.5 * T / J1) and res.outputs["w2"][i] == w20
    # at the lock: total momentum conserved, the common velocity and the energy lost
    wc = (J1 * w1 + J2 * w2) / (J1 + J2)
    assert ev.energy_loss == pytest.approx(J1 * J2 * (w1 - w2) ** 2 / (2 * (J1 + J2)), rel=1e-9)
    assert ev.jumps["p_J1"][1] == pytest.approx(J1 * wc, rel=1e-9)
    assert ev.jumps["p_J2"][1] == pytest.approx(J2 * wc, rel=1e-9)
    # after: (J1 + J2) w' = T, and the clutch carries J2 w' = J2 T/(J1 + J2)
    for t in (1.5, 2.0):
        k = list(res.t).index(t)
        assert res.outputs["w1"][k] == pytest.approx(wc + T * (t - t_lock) / (J1 + J2), rel=1e-9)
        assert res.outputs["w2"][k] == pytest.approx(res.outputs["w1"][k], rel=1e-12)
        assert res.outputs["torque"][k] == pytest.approx(J2 * T / (J1 + J2), rel=1e-9)
    assert res.energy_loss == pytest.approx(ev.energy_loss)


# ---------------------------------------------------------------- end stop
def test_mass_on_an_end_stop_contact_time():
    m, k, v0, gap = 2.0, 50.0, 1.0, 1.0
    sm = SwitchedModel(library.end_stop(), outputs={"x": bg.displacement("m"), "v": bg.flow("m")})
    res = simulate(sm, (0, 3), {"p_m": m * v0, "x": -gap}, values={"m": m, "k": k})
    t_in, t_out = res.event_times("K")
    # free flight to the stop, then half a period of the mass on the spring (undamped)
    assert t_in == pytest.approx(gap / v0, abs=1e-9)
    assert t_out - t_in == pytest.approx(math.pi * math.sqrt(m / k), abs=1e-8)
    assert res.outputs["v"][-1] == pytest.approx(-v0, abs=1e-8)        # elastic rebound
    assert res.outputs["x"].max() == pytest.approx(v0 * math.sqrt(m / k), rel=1e-3)
    assert res.energy_loss == 0


# ---------------------------------------------------------------- shorted capacitor
def test_capacitor_shorted_by_a_switch_loses_its_energy():
    g = bg.BondGraph("short")
    g.add(bg.Zero("v"), bg.C("C"), bg.R("R"), ControlledSwitch("S", gate=bg.t - 1))
    for t, h in [("v", "C"), ("v", "R"), ("v", "S")]:
        g.connect(t, h)
    sm = SwitchedModel(g, outputs={"v": bg.effort("C"), "i_R": bg.flow("R")})
    C, R, q0 = 2.0, 3.0, 4.0
    res = simulate(sm, (0, 2), {"q_C": q0}, values={"C": C, "R": R})
    (ev,) = res.events
    q1 = q0 * math.exp(-1 / (R * C))          # RC discharge until the switch closes at t = 1
    assert ev.time == pytest.approx(1.0, abs=1e-12)
    assert ev.jumps["q_C"] == pytest.approx((q1, 0.0), rel=1e-8)
    assert ev.energy_loss == pytest.approx(q1 ** 2 / (2 * C), rel=1e-8)
    assert res.outputs["v"][-1] == 0 and res.outputs["i_R"][-1] == 0


# ---------------------------------------------------------------- chattering and budgets
def relay():
    """q' = I (= 1) while S is off; S closes when q > 0 and then drains (q + 3)/R > I: the
    switch is driven back and forth at q = 0 (a sliding mode)."""
    g = bg.BondGraph("relay")
    g.add(bg.Sf("I", value=1), bg.Zero("v"), bg.C("C"), bg.One("b"),
          ControlledSwitch("S", gate=bg.displacement("C")), bg.R("R"), bg.Se("E", value=3))
    for t, h in [("I", "v"), ("v", "C"), ("v", "b"), ("b", "S"), ("b", "R"), ("E", "b")]:
        g.connect(t, h)
    return SwitchedModel(g)


def test_chattering_is_reported_with_time_and_switch():
    with pytest.raises(ChatteringError, match=r"switch 'S' chatters") as info:
        simulate(relay(), (0, 5), {"q_C": -2.0}, values={"C": 1, "R": 1})
    assert info.value.element == "S"
    assert info.value.time == pytest.approx(2.0, abs=1e-6)       # q = -2 + t reaches 0


def test_event_budget_returns_the_partial_run():
    sm = SwitchedModel(library.buck(), outputs={"v": bg.effort("C")})
    vals = {"Vin": 10, "duty": 0.5, "T": 1e-5, "L": 1e-4, "C": 1e-4, "R": 5}
    with pytest.raises(EventBudgetError, match="event budget of 3") as info:
        simulate(sm, (0, 1e-3), values=vals, max_events=3)
    part = info.value.result
    assert len(part.events) == 3 and part.t[-1] == pytest.approx(2e-5, rel=1e-6)


def test_bad_initial_state_and_inputs_are_named():
    sm = SwitchedModel(library.clutch())
    vals = {"J1": 1, "J2": 2, "t_lock": 1}
    with pytest.raises(HybridError, match=r"x0 names 'p_J3'.*p_J1, p_J2"):
        simulate(sm, (0, 1), {"p_J3": 1}, values=vals, inputs={"tau": 1})
    with pytest.raises(HybridError, match=r"no value for input 'tau'"):
        simulate(sm, (0, 1), values=vals)
    with pytest.raises(bg.MissingValueError, match="t_lock"):
        simulate(sm, (0, 1), values={"J1": 1, "J2": 2}, inputs={"tau": 1})


def test_bg_simulate_runs_a_switched_model_with_events():
    sm = SwitchedModel(library.clutch(), outputs={"w2": bg.flow("J2")})
    res = bg.simulate(sm, {"J1": 1, "J2": 2, "t_lock": 1}, (0, 2), {"p_J2": 6.0}, u={"tau": 1.0},
                      rtol=1e-9, atol=1e-12)
    # common velocity (1*1 + 2*3)/3 at the lock, then (J1 + J2) w' = tau
    assert res.outputs["w2"][-1] == pytest.approx(7 / 3 + 1 / 3, rel=1e-9)
    with pytest.raises(bg.BondGraphError, match="is switched"):
        bg.simulate(sm, {"J1": 1, "J2": 2, "t_lock": 1}, (0, 2), u=[1.0])


def test_an_input_driving_a_derivative_storage_is_refused_naming_the_mode():
    g = bg.BondGraph("rect_in")
    g.add(bg.Se("Vs"), bg.One("i"), Diode("D", on=True), bg.Zero("v"), bg.R("R"), bg.C("C"))
    for t, h in [("Vs", "i"), ("i", "D"), ("i", "v"), ("v", "R"), ("v", "C")]:
        g.connect(t, h)
    sm = SwitchedModel(g)
    # diode on: C is driven by the input Vs directly, so i_C = C dVs/dt needs the input's derivative
    with pytest.raises(HybridError, match=r"mode \(D on\).*input derivatives.*value="):
        simulate(sm, (0, 1), values={"R": 1, "C": 1}, inputs={"Vs": lambda t: math.sin(t)})


def test_time_budget_bounds_a_run():
    sm = SwitchedModel(library.buck(), outputs={"v": bg.effort("C")})
    vals = {"Vin": 10, "duty": 0.5, "T": 1e-5, "L": 1e-4, "C": 1e-4, "R": 5}
    with pytest.raises(EventBudgetError, match="time budget of 1e-09 s used up") as info:
        simulate(sm, (0, 1.0), values=vals, time_budget=1e-9)
    assert info.value.result.t[-1] < 1.0
