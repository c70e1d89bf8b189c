"""Events never missed and modes chosen by complementarity (issue 34), against closed forms.

* The half-wave rectifier with a 1 Hz source and RC = 0.5 s from an empty
  capacitor: while the diode blocks the capacitor's state barely moves, so
  the solver's steps would grow past the source's period; the turn-off
  instants solve tan(w t) = -w R C, the turn-on instants the decay meeting
  the source (brentq here), and v_C is the piecewise closed form.
* A 50 Hz rectifier over (0, 2000 s) has its events (no sampling grid tied to
  the span).
* An end stop from a given position (free, and inside the contact where the
  spring is compressed by it); duty 0 from rest; a one-way clutch at rest.
"""

import math

import numpy as np
import pytest
import sympy
from scipy.optimize import brentq

import bondgraph as bg
from bondgraph.hybrid import (ChatteringError, ControlledSwitch, Diode, EventBudgetError, HybridError,
                              SwitchedModel, library, pwm, simulate)

VM, F, R, C = 10.0, 1.0, 1000.0, 5e-4          # R C = 0.5 s
W, TAU = 2 * math.pi * F, R * C


def rectifier_by_hand(t_end, vm=VM, w=W, tau=TAU):
    """Switching instants and v_C(t) of the ideal half-wave rectifier from an empty capacitor.

    Conducting (from t = 0: the source rises from 0), v = Vm sin(w t) and the diode
    current C v' + v/R vanishes at tan(w t) = -w R C; blocking, v = v_off
    exp(-(t - t_off)/(R C)) until Vm sin(w t) catches up with it.
    """
    period = 2 * math.pi / w
    t_off0 = (math.pi - math.atan(w * tau)) / w
    offs, ons = [], []
    for k in range(10**6):
        t_off = t_off0 + k * period
        if t_off > t_end:
            break
        offs.append(t_off)
        v_off = vm * math.sin(w * t_off)
        lo = (k + 1) * period
        t_on = brentq(lambda t: vm * math.sin(w * t) - v_off * math.exp(-(t - t_off) / tau),
                      lo, lo + period / 4, xtol=1e-15)
        if t_on > t_end:
            break
        ons.append(t_on)

    def v(t):
        for t_off, t_on in zip(offs, ons + [math.inf]):
            if t < t_off:
                return vm * math.sin(w * t)
            if t < t_on:
                return vm * math.sin(w * t_off) * math.exp(-(t - t_off) / tau)
        return vm * math.sin(w * t)
    return offs, ons, v


def rect_model():
    return SwitchedModel(library.rectifier(), outputs={"v": bg.effort("C"), "i": bg.flow("D")})


@pytest.mark.parametrize("entry", ["hybrid", "bg"])
def test_slow_rectifier_from_an_empty_capacitor(entry):
    sm, vals, t_end = rect_model(), {"Vm": VM, "w": W, "R": R, "C": C}, 3.0
    grid = np.linspace(0, t_end, 200)
    if entry == "hybrid":
        res = simulate(sm, (0, t_end), values=vals, t_eval=grid)
    else:
        res = bg.simulate(sm, vals, (0, t_end), t_eval=grid)
    offs, ons, v = rectifier_by_hand(t_end)
    assert len(offs) == 3 and len(ons) == 2
    got_off = [e.time for e in res.events if str(e.after) == "D off"]
    got_on = [e.time for e in res.events if str(e.after) == "D on"]
    np.testing.assert_allclose(got_off, offs, rtol=0, atol=1e-8)
    np.testing.assert_allclose(got_on, ons, rtol=0, atol=1e-8)
    on_grid = np.isin(res.t, grid)
    assert on_grid.sum() >= 200
    expect = np.array([v(t) for t in res.t[on_grid]])
    np.testing.assert_allclose(res.outputs["v"][on_grid], expect, rtol=0, atol=1e-4 * VM)
    # from t = 0 the diode conducts (the source rises from 0): no initial jump, no loss
    assert str(res.modes[0]) == "D on" and res.energy_loss == 0


def test_fifty_hertz_rectifier_over_two_thousand_seconds_has_its_events():
    sm, w = rect_model(), 2 * math.pi * 50
    vals = {"Vm": 10, "w": w, "R": 100, "C": 1e-4}
    with pytest.raises(EventBudgetError, match="event budget of 12") as info:
        simulate(sm, (0, 2000.0), values=vals, max_events=12)
    offs, ons, _ = rectifier_by_hand(0.2, vm=10, w=w, tau=1e-2)
    times = [e.time for e in info.value.result.events]
    np.testing.assert_allclose(times, sorted(offs + ons)[:12], rtol=0, atol=1e-9)


# ---------------------------------------------------------------- end stop from a given position
M, K = 2.0, 50.0


def end_stop():
    return SwitchedModel(library.end_stop(), outputs={"x": bg.displacement("m"), "v": bg.flow("m")})


def test_end_stop_from_a_given_position_rebounds_elastically():
    x0, v0 = -0.25, 1.0
    res = simulate(end_stop(), (0, 1.5), {"x": x0, "p_m": M * v0}, values={"m": M, "k": K})
    t_in, t_out = res.event_times("K")
    assert res.outputs["x"][0] == x0                           # honoured, not dropped
    assert t_in == pytest.approx(-x0 / v0, abs=1e-9)           # free flight to the stop
    assert t_out - t_in == pytest.approx(math.pi * math.sqrt(M / K), abs=1e-8)
    assert res.outputs["v"][-1] == pytest.approx(-v0, abs=1e-8)   # equal and opposite
    assert res.outputs["x"][-1] == pytest.approx(-v0 * (1.5 - t_out), abs=1e-7)


def test_end_stop_started_inside_the_contact_has_its_spring_compressed():
    # x = 0.1 at rest inside the stop: the contact spring holds q = 0.1, pushes the mass out
    # after a quarter period with k x^2/2 = m v^2/2
    res = simulate(end_stop(), (0, 1.0), {"x": 0.1}, values={"m": M, "k": K})
    assert str(res.modes[0]) == "K off" and res.outputs["x"][0] == pytest.approx(0.1, abs=1e-15)
    (t_out,) = res.event_times("K")                 # the initial choice (K off) names no switch
    assert t_out == pytest.approx(math.pi / 2 * math.sqrt(M / K), abs=1e-8)
    assert res.outputs["v"][-1] == pytest.approx(-0.1 * math.sqrt(K / M), rel=1e-8)


def test_a_given_signal_no_mode_can_take_is_refused_naming_it():
    # the contact spring given q_k = 0 explicitly while x = 0.1 puts the mass inside the stop
    with pytest.raises(bg.BondGraphError, match=r"x = 0\.1"):
        simulate(end_stop(), (0, 1.0), {"x": 0.1, "q_k": 0.0}, values={"m": M, "k": K})


# ---------------------------------------------------------------- at rest
def test_buck_with_duty_zero_stays_at_rest():
    sm = SwitchedModel(library.buck(), outputs={"v": bg.effort("C"), "i": bg.flow("L")})
    vals = {"Vin": 10, "duty": 0, "T": 1e-5, "L": 1e-4, "C": 1e-4, "R": 5}
    res = simulate(sm, (0, 1e-4), values=vals)
    assert np.all(res.outputs["v"] == 0) and np.all(res.outputs["i"] == 0)
    assert all(not e.elements for e in res.events)        # at most the initial choice: S off
    assert not res.modes[-1].is_on("S")


def one_way_clutch():
    """J1 (driven by tau) and J2 through a diode on the slip junction: it freewheels (diode on)
    while w2 - w1 >= 0 and locks (diode off) while it would transmit a driving torque."""
    g = bg.BondGraph("one_way")
    g.add(bg.Se("tau"), bg.One("w1"), bg.I("J1"), bg.Zero("c"), Diode("D", on=True), bg.One("w2"),
          bg.I("J2"))
    for a, b in [("tau", "w1"), ("w1", "J1"), ("w2", "c"), ("c", "w1"), ("c", "D"), ("w2", "J2")]:
        g.connect(a, b)
    return SwitchedModel(g, outputs={"w1": bg.flow("J1"), "w2": bg.flow("J2")})


def test_one_way_clutch_at_rest_freewheels():
    J1, J2 = 1.0, 2.0
    res = simulate(one_way_clutch(), (0, 1), {"p_J1": J1 * 1.0, "p_J2": J2 * 3.0},
                   values={"J1": J1, "J2": J2}, inputs={"tau": 0.0})
    assert not res.events and str(res.modes[0]) == "D on"
    assert res.outputs["w1"][-1] == 1.0 and res.outputs["w2"][-1] == 3.0


def test_one_way_clutch_locks_when_the_driver_catches_up():
    J1, J2, tau, w1, w2 = 1.0, 2.0, 4.0, 1.0, 3.0
    res = simulate(one_way_clutch(), (0, 1), {"p_J1": J1 * w1, "p_J2": J2 * w2},
                   values={"J1": J1, "J2": J2}, inputs={"tau": tau})
    (ev,) = res.events
    t_lock = J1 * (w2 - w1) / tau                       # Newton on J1 alone until w1 = w2
    assert ev.time == pytest.approx(t_lock, abs=1e-9) and str(ev.after) == "D off"
    assert ev.energy_loss == 0                          # equal velocities: no jump
    w = w2 + tau * (1 - t_lock) / (J1 + J2)             # then both together
    assert res.outputs["w1"][-1] == pytest.approx(w, rel=1e-9)
    assert res.outputs["w2"][-1] == pytest.approx(w, rel=1e-9)


# ---------------------------------------------------------------- refused, naming the culprit
def test_zero_capacitance_is_refused_naming_the_element():
    with pytest.raises(HybridError, match=r"C:C has C = 0"):
        simulate(rect_model(), (0, 1), values={"Vm": VM, "w": W, "R": R, "C": 0.0})


def test_zero_inductance_is_refused_naming_the_element():
    sm = SwitchedModel(library.buck(), outputs={"v": bg.effort("C")})
    vals = {"Vin": 10, "duty": 0.5, "T": 1e-5, "L": 0, "C": 1e-4, "R": 5}
    with pytest.raises(HybridError, match="I:L has L = 0"):
        simulate(sm, (0, 1e-4), values=vals)
    from bondgraph.codegen import generate_switched_c
    with pytest.raises(bg.BondGraphError, match="I:L has L = 0"):
        generate_switched_c(sm, defaults=vals)


def test_zero_inertia_of_a_clutch_is_refused():
    sm = SwitchedModel(library.clutch(), outputs={"w2": bg.flow("J2")})
    with pytest.raises(HybridError, match="I:J2 has J2 = 0"):
        simulate(sm, (0, 1), values={"J1": 1, "J2": 0, "t_lock": 0.5}, inputs={"tau": 1})


@pytest.mark.parametrize("option, value", [
    ("t_span", (0, 1, 2)), ("t_span", (1, 0)), ("t_span", (0, math.inf)), ("chatter_count", 0),
    ("chatter_count", 2.5), ("max_events", "10"), ("max_events", -1), ("max_step", 0),
    ("method", "Euler"), ("guard_tol", -1.0), ("guard_tol", math.nan), ("rtol", 0),
    ("time_budget", -1), ("t_eval", [0.5, 0.2])])
def test_every_option_is_checked_at_the_door(option, value):
    kw = {"t_span": (0, 1), option: value}
    with pytest.raises(HybridError, match=option):
        simulate(rect_model(), values={"Vm": VM, "w": W, "R": R, "C": C}, **kw)


def test_an_input_returning_text_is_refused_never_parsed():
    g = bg.BondGraph("g")
    g.add(bg.Se("E"), bg.One("i"), bg.R("R"), bg.I("L"), Diode("D", on=True))
    for a, b in [("E", "i"), ("i", "R"), ("i", "L"), ("i", "D")]:
        g.connect(a, b)
    sm = SwitchedModel(g, outputs={"iL": bg.flow("L")})
    with pytest.raises(HybridError, match="input 'E'.*str '1'"):
        simulate(sm, (0, 1), values={"R": 1, "L": 1}, inputs={"E": lambda t: "1"})
    with pytest.raises(HybridError, match="input 'E'"):
        simulate(sm, (0, 1), values={"R": 1, "L": 1}, inputs={"E": "1"})


def test_a_nan_guard_names_the_switch_and_the_time():
    g = bg.BondGraph("g")
    g.add(bg.Se("E", value=1), bg.One("i"), bg.R("R"), bg.I("L"),
          ControlledSwitch("S", gate=sympy.sqrt(1 - bg.t), on=True))
    for a, b in [("E", "i"), ("i", "R"), ("i", "L"), ("i", "S")]:
        g.connect(a, b)
    with pytest.raises(HybridError, match=r"switch 'S' is nan at t = 1\.0"), \
            np.errstate(invalid="ignore"):
        simulate(SwitchedModel(g), (0, 3), values={"R": 1, "L": 1})


def test_pwm_period_zero_or_negative_is_refused():
    with pytest.raises(bg.BondGraphError, match="period"):
        pwm(0.5, 0)
    with pytest.raises(bg.BondGraphError, match="period"):
        pwm(0.5, -1e-3)
    sm = SwitchedModel(library.buck(), outputs={"v": bg.effort("C")})
    with pytest.raises(HybridError, match="T = 0"):
        simulate(sm, (0, 1e-4), values={"Vin": 10, "duty": 0.5, "T": 0, "L": 1e-4, "C": 1e-4, "R": 5})


def test_a_sliding_relay_is_chattering_at_its_instant():
    g = bg.BondGraph("relay")
    g.add(bg.Sf("I", value=1), bg.Zero("v"), bg.C("C"), bg.One("b"),
          ControlledSwitch("S", gate=bg.displacement("C")), bg.R("R"), bg.Se("E", value=3))
    for a, b in [("I", "v"), ("v", "C"), ("v", "b"), ("b", "S"), ("b", "R"), ("E", "b")]:
        g.connect(a, b)
    with pytest.raises(ChatteringError) as info:
        simulate(SwitchedModel(g), (0, 5), {"q_C": -2.0}, values={"C": 1, "R": 1}, chatter_time=0)
    assert info.value.element == "S" and info.value.time == pytest.approx(2.0, abs=1e-9)


# ---------------------------------------------------------------- switches inside sub-models
def test_a_diode_inside_a_sub_model():
    inner = bg.BondGraph("cell")
    inner.add(bg.Port("a"), bg.One("i"), Diode("D", on=True), bg.R("Rs"), bg.Zero("v"), bg.R("R"),
              bg.C("C"))
    for a, b in [("a", "i"), ("i", "D"), ("i", "Rs"), ("i", "v"), ("v", "R"), ("v", "C")]:
        inner.connect(a, b)
    g = bg.BondGraph("top")
    g.add(bg.Se("E"), inner)
    g.connect("E", "cell.a")
    sm = SwitchedModel(g, outputs={"v": bg.effort("cell.C")})
    assert sm.switches == ("cell.D",)
    Rs, Rl, Cc, E = 1.0, 3.0, 0.5, 2.0
    res = simulate(sm, (0, 2), values={"cell.Rs": Rs, "cell.R": Rl, "cell.C": Cc}, inputs={"E": E})
    # diode on throughout: C charges through Rs with R in parallel (Thevenin)
    v_inf, tau = E * Rl / (Rs + Rl), Cc * Rs * Rl / (Rs + Rl)
    assert not res.events
    assert res.outputs["v"][-1] == pytest.approx(v_inf * (1 - math.exp(-2 / tau)), rel=1e-8)


def test_a_diode_bonded_away_from_itself_draws_a_warning():
    g = bg.BondGraph("rev")
    g.add(bg.Se("E", value=1), bg.One("i"), bg.R("R"), Diode("D"))
    for a, b in [("E", "i"), ("i", "R"), ("D", "i")]:
        g.connect(a, b)
    with pytest.warns(bg.BondGraphWarning, match=r"diode 'D' is bonded away from itself \(D -> i\)"):
        SwitchedModel(g)


def test_a_run_agrees_with_a_shorter_run_restarted_inside_it():
    # cost per event flat in the horizon (bench/hybrid_simulate.py); here the same numbers:
    # a buck run over 30 periods against one restarted at period 10 from its state
    sm = SwitchedModel(library.buck(), outputs={"v": bg.effort("C"), "iL": bg.flow("L")})
    vals = {"Vin": 10, "duty": 0.5, "T": 1e-5, "L": 1e-4, "C": 1e-4, "R": 5}
    grid = np.linspace(1e-4, 3e-4, 41)
    whole = simulate(sm, (0, 3e-4), values=vals, t_eval=grid)
    k = int(np.nonzero(whole.t == grid[0])[0][-1])
    x0 = {name: float(v[k]) for name, v in whole.stored.items()}
    part = simulate(sm, (grid[0], 3e-4), x0, values=vals, t_eval=grid)

    def on_grid(r):
        keep = np.isin(r.t, grid[1:]) & np.r_[np.diff(r.t) != 0, True]
        return r.outputs["v"][keep], r.outputs["iL"][keep]

    (v1, i1), (v2, i2) = on_grid(whole), on_grid(part)
    assert len(v1) == len(v2) == 40
    np.testing.assert_allclose(v1, v2, rtol=0, atol=1e-9)
    np.testing.assert_allclose(i1, i2, rtol=0, atol=1e-9)
    assert [round(e.time, 12) for e in part.events] == [
        round(e.time, 12) for e in whole.events if e.time > grid[0] + 1e-12]


def test_a_blocked_diode_touching_zero_is_neither_an_event_nor_chattering():
    # a capacitor charged to the source's peak behind a diode, no load: the reverse voltage
    # Vm (1 - sin w t) touches zero at every peak; the diode stays off (on, its current C Vs'
    # would fall below zero at the next instant), and no mode change is counted
    g = bg.BondGraph("peak")
    Vm, w = sympy.symbols("Vm w", positive=True)
    g.add(bg.Se("Vs", value=Vm * sympy.sin(w * bg.t)), bg.One("i"), Diode("D"), bg.Zero("v"),
          bg.C("C"))
    for a, b in [("Vs", "i"), ("i", "D"), ("i", "v"), ("v", "C")]:
        g.connect(a, b)
    sm = SwitchedModel(g, outputs={"v": bg.effort("C")})
    res = simulate(sm, (0, 0.2), {"q_C": 1e-4 * 10.0}, values={"Vm": 10, "w": 100 * math.pi, "C": 1e-4},
                   chatter_count=2)
    assert not res.events and {str(m) for m in res.modes} == {"D off"}
    assert np.all(res.outputs["v"] == 10.0)


def test_the_time_budget_is_checked_inside_one_long_segment():
    # a ball coming to rest on the ground spring: one endless segment without events
    sm = SwitchedModel(library.bounce(), outputs={"h": bg.displacement("ball")})
    with pytest.raises(EventBudgetError, match="time budget of 0.3 s") as info:
        simulate(sm, (0, 1e9), {"h": 1.0}, values={"m": 1, "g": 9.81, "r": 1, "k_g": 100},
                 time_budget=0.3)
    assert 0 < info.value.result.t[-1] < 1e9


def rectifier_built_blocking():
    """The library's rectifier with its diode built off (blocking)."""
    g = bg.BondGraph("rect_off")
    Vm, w = sympy.symbols("Vm w", positive=True)
    g.add(bg.Se("Vs", value=Vm * sympy.sin(w * bg.t)), bg.One("i"), Diode("D"), bg.Zero("v"),
          bg.R("R"), bg.C("C"))
    for a, b in [("Vs", "i"), ("i", "D"), ("i", "v"), ("v", "R"), ("v", "C")]:
        g.connect(a, b)
    return SwitchedModel(g, outputs={"v": bg.effort("C")})


def test_a_rectifier_built_blocking_conducts_from_the_start():
    # empty capacitor, source rising from 0: off, the reverse voltage -Vs would go negative at
    # once (its derivative -Vm w), so the consistent initial mode is on, without any jump
    res = simulate(rectifier_built_blocking(), (0, 3.0), values={"Vm": VM, "w": W, "R": R, "C": C},
                   t_eval=np.linspace(0, 3.0, 200))
    offs, ons, v = rectifier_by_hand(3.0)
    (first, *rest) = res.events
    assert first.time == 0 and str(first.after) == "D on" and first.energy_loss == 0
    np.testing.assert_allclose([e.time for e in rest], sorted(offs + ons), rtol=0, atol=1e-8)
    expect = np.array([v(t) for t in res.t])
    np.testing.assert_allclose(res.outputs["v"], expect, rtol=0, atol=1e-4 * VM)


def test_unit_carrying_exports_refuse_a_switched_model(tmp_path):
    import sympy.physics.units as u

    from bondgraph.library.units import export_fmu_with_units, plant_with_units

    sm = SwitchedModel(library.clutch(), outputs={"w2": bg.flow("J2")})
    vals = {"J1": 1 * u.kg * u.m**2, "J2": 2 * u.kg * u.m**2, "t_lock": 1 * u.s}
    with pytest.raises(bg.BondGraphError, match="'clutch' is switched"):
        plant_with_units(sm, library.clutch(), vals)
    with pytest.raises(bg.BondGraphError, match="'clutch' is switched"):
        export_fmu_with_units(sm, tmp_path / "c.fmu", graph=library.clutch(), values=vals)
    assert not (tmp_path / "c.fmu").exists()
