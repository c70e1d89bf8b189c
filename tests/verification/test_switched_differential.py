"""Switched differential verification in CI: random switched circuits simulated by
``bondgraph.hybrid.simulate`` against the independent reference
(``verification/switched_reference.py``, no bondgraph code), and the reference itself
against closed forms.

The long run (thousands of circuits) is ``python bench/verify_switched.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from verification import switched_generator as sg
from verification.switched_reference import IllPosed, Netlist, Part, SwitchedReference

#: seeds checked here: about 0.3 CPU seconds each (the package's simulation dominates).
#: Among them, the ones that found the package's errors (issue 34, fixed since): a diode
#: idle at zero current and voltage chattering (25, 54, 73, 101, 112, 116), diode guards
#: that follow a source stepped over while the state was quiescent (6, 34, 70, 91), a diode
#: in series with an inductor refused as chattering when its current starts as t^2 (107,
#: 144, 190), a turn-on found a step late and not refined, with a spurious jump (182)
CI_SEEDS = range(200)


def test_reference_half_wave_rectifier_against_the_closed_form():
    """1 Hz source Vm sin(w t), ideal diode, R || C with R C = 0.5 s, from an empty capacitor.
    Conducting, v = Vm sin(w t) and the diode current C v' + v/R vanishes at
    tan(w t) = -w R C; blocking, v = v_off exp(-(t - t_off)/(R C)) until the source
    catches up with it (brentq)."""
    Vm, w, R, C = 1.0, 2 * math.pi, 1.0, 0.5
    net = Netlist(2, (Part("u", "V", 1, 0, wave=(0.0, Vm, w, 0.0)), Part("D", "D", 1, 2),
                      Part("R", "R", 2, 0, R), Part("C", "C", 2, 0, C)))
    t_end = 3.0
    grid = np.linspace(0.0, t_end, 200)
    res = SwitchedReference(net).simulate(t_end, {}, grid)
    offs, ons = [], []
    for k in range(3):
        t_off = (math.pi - math.atan(w * R * C)) / w + k
        v_off = Vm * math.sin(w * t_off)
        t_on = brentq(lambda t: Vm * math.sin(w * t) - v_off * math.exp(-(t - t_off) / (R * C)),
                      k + 1, k + 1.25, xtol=1e-15)
        offs.append(t_off)
        ons.append(t_on)
    expected = [(0.0, {"D"})]
    for t_off, t_on in zip(offs, ons):
        expected += [(t_off, set()), (t_on, {"D"})] if t_on < t_end else [(t_off, set())]
    assert [set(on) for _, on, _ in res.events] == [on for _, on in expected]
    np.testing.assert_allclose([t for t, _, _ in res.events], [t for t, _ in expected],
                               rtol=0, atol=1e-12)

    def v(t):
        for t_off, t_on in zip(offs, ons):
            if t < t_off:
                return Vm * math.sin(w * t)
            if t < t_on:
                return Vm * math.sin(w * t_off) * math.exp(-(t - t_off) / (R * C))
        return Vm * math.sin(w * t)
    np.testing.assert_allclose(res.states["C"], [C * v(t) for t in grid], rtol=0, atol=1e-10)


def test_reference_charge_sharing_through_a_diode():
    """C1 = 1 charged to 2 V, a diode into C2 = 3 with R = 0.5 across it: at t = 0 the
    charge is shared (v = C1*2/(C1 + C2) = 0.5 V, charge conserved), then both discharge
    through R: v = 0.5 exp(-t/(R (C1 + C2))), the diode conducting C1's current."""
    net = Netlist(2, (Part("C1", "C", 1, 0, 1.0), Part("D", "D", 1, 2), Part("C2", "C", 2, 0, 3.0),
                      Part("R", "R", 2, 0, 0.5)))
    grid = np.linspace(0.1, 1.0, 10)
    res = SwitchedReference(net).simulate(1.0, {"C1": 2.0}, grid)
    assert [(t, set(on)) for t, on, _ in res.events] == [(0.0, {"D"})]
    assert res.jumps == [0.0]
    v = 0.5 * np.exp(-grid / 2.0)
    np.testing.assert_allclose(res.states["C1"], 1.0 * v, rtol=1e-12)
    np.testing.assert_allclose(res.states["C2"], 3.0 * v, rtol=1e-12)


def test_reference_pwm_switch_and_freewheeling_diode():
    """A buck stage: E = 2 through a PWM switch (duty 0.5, period 1, delay 0.25) to node A,
    a diode from the ground to A, L = 1 from A through R = 1 to the ground.  Switch on:
    L i' = E - R i; off: the diode conducts the inductor current, L i' = -R i."""
    net = Netlist(3, (Part("E", "V", 1, 0, wave=(2.0, 0.0, 0.0, 0.0)),
                      Part("S", "S", 1, 2, gate=("pwm", 0.5, 1.0, 0.25)),
                      Part("D", "D", 0, 2), Part("L", "L", 2, 3, 1.0), Part("R", "R", 3, 0, 1.0)))
    res = SwitchedReference(net).simulate(2.0, {}, [2.0])
    # from rest the diode need not conduct until the switch first opens at t = 0.75
    assert [(t, set(on)) for t, on, _ in res.events] == [
        (0.0, set()), (0.25, {"S"}), (0.75, {"D"}), (1.25, {"S"}), (1.75, {"D"})]
    i = 0.0
    for t0, t1, on in [(0.25, 0.75, True), (0.75, 1.25, False), (1.25, 1.75, True),
                       (1.75, 2.0, False)]:
        target = 2.0 if on else 0.0
        i = target + (i - target) * math.exp(-(t1 - t0))
    assert res.states["L"][0] == pytest.approx(i, rel=1e-12)


def test_reference_inductor_current_cut_by_a_switch():
    """E = 1 through a switch (on for the first half of a period of 2) into L = 0.5 and
    R = 1: i = 1 - exp(-t R/L) until the switch opens at t = 1, where the current jumps
    to zero (an inductor cutset) and stays there."""
    net = Netlist(3, (Part("E", "V", 1, 0, wave=(1.0, 0.0, 0.0, 0.0)),
                      Part("S", "S", 1, 2, gate=("pwm", 0.5, 2.0, 0.0)),
                      Part("L", "L", 2, 3, 0.5), Part("R", "R", 3, 0, 1.0)))
    res = SwitchedReference(net).simulate(1.5, {}, [0.5, 1.25])
    assert [(t, set(on)) for t, on, _ in res.events] == [(0.0, {"S"}), (1.0, set())]
    assert res.jumps == [1.0]
    assert res.states["L"] == pytest.approx([0.5 * (1 - math.exp(-1.0)), 0.0], abs=1e-13)


def test_reference_refuses_a_source_shorted_by_a_diode():
    """A 1 V source straight across a forward diode: no mode is consistent."""
    net = Netlist(1, (Part("u", "V", 1, 0, wave=(1.0, 0.0, 0.0, 0.0)), Part("D", "D", 1, 0),
                      Part("C", "C", 1, 0, 1.0)))
    with pytest.raises(IllPosed, match="no consistent mode"):
        SwitchedReference(net).simulate(1.0, {}, [0.5])


@pytest.mark.parametrize("seed", CI_SEEDS, ids=lambda s: f"seed{s}")
def test_random_switched_circuit_agrees_with_the_reference(seed):
    o = sg.check(sg.generate(seed), timeout=20.0)
    assert o.cls not in sg.FAILURES, (seed, o.cls, o.detail)
    if o.cls == "agree":
        assert o.checks["compared"] >= 80         # 100 instants, minus those near events
