"""Unilateral contact (hybrid.Contact, mechanical.UnilateralContact) against hand solutions.

The references are written here from Newton's law, phase by phase:

* free flight: constant velocity, or constant acceleration ``g`` under gravity;
* in contact: the mass on the spring ``k`` and damper ``b`` (and gravity),
  ``m x'' + b x' + k x = m g``, the closed-form damped oscillation from the
  state at closing; the contact opens when its force ``k x + b x'`` falls
  through zero (``brentq`` on the closed form), not when ``x`` returns to 0;
* open again: the contact spring relaxes through the damper,
  ``x_s = x_r exp(-k (t - t_r)/b)``, and the contact re-closes when the mass
  catches that surface (``brentq`` on the gap ``x_s - x``).

``x`` is the mass's position measured from the stop (towards it positive),
so the mass starts at ``x = -gap``.
"""

from __future__ import annotations

import math
import shutil
import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

import bondgraph as bg
from bondgraph.hybrid import Contact, ControlledSwitch, Mode, SwitchedModel, library
from bondgraph.library.mechanical import Mass, UnilateralContact

OUT = {"x": bg.displacement("m"), "v": bg.flow("m"), "F": bg.effort("K")}
TOL = {"rtol": 1e-10, "atol": 1e-12}


def oscillation(m, k, b, g, x0, v0):
    """x(t), v(t) of m x'' + b x' + k x = m g from (x0, v0) at t = 0 (underdamped)."""
    s, wn = b / (2 * m), math.sqrt(k / m)
    wd, xe = math.sqrt(wn * wn - s * s), m * g / k
    y0 = x0 - xe
    c = (v0 + s * y0) / wd

    def x(t):
        return xe + math.exp(-s * t) * (y0 * math.cos(wd * t) + c * math.sin(wd * t))

    def v(t):
        return math.exp(-s * t) * ((c * wd - s * y0) * math.cos(wd * t) - (s * c + wd * y0) * math.sin(wd * t))
    return x, v


def first_fall(f, t0, t1, n=4001):
    """The first time in (t0, t1] at which f falls through zero (grid, then brentq)."""
    ts = np.linspace(t0, t1, n)
    fv = np.array([f(t) for t in ts])
    j = int(np.nonzero((fv[1:] < 0) & (fv[:-1] >= 0))[0][0]) + 1
    return brentq(f, ts[j - 1], ts[j], xtol=1e-15, rtol=1e-15)


def transitions(res):
    return [(e.time, str(e.after)) for e in res.events]


# ---------------------------------------------------------------- elastic drop
def test_elastic_drop_rebounds_with_the_opposite_velocity_and_returns_to_its_height():
    m, k, g, h = 0.5, 400.0, 9.81, 0.3
    sm = SwitchedModel(library.contact_stop(damper=False, gravity=True), outputs=OUT)
    t_end = 1.0
    w = math.sqrt(k / m)
    t_in = math.sqrt(2 * h / g)
    v_in = g * t_in
    A, B = g / w**2, v_in / w
    t_out = t_in + (2 * math.pi - 2 * math.atan(B / A)) / w
    apex = t_out + v_in / g
    deepest = t_in + (math.pi - math.atan(B / A)) / w          # v = 0 in contact: tan(w t) = -B/A
    res = bg.simulate(sm, {"m": m, "k": k, "g": g, "gap": h}, (0, t_end), {"x": -h},
                      t_eval=[0, deepest, apex, t_end],
                      **TOL)
    # free fall onto the stop, then x = A (1 - cos wt) + B sin wt until k x = 0 again:
    # tan(w t/2) = -B/A, w t = 2 pi - 2 atan(B/A)
    t_back = t_out + 2 * v_in / g                 # up to the apex and down again
    assert transitions(res)[:3] == [pytest.approx((t_in, "K off"), abs=1e-9),
                                    pytest.approx((t_out, "K on"), abs=1e-9),
                                    pytest.approx((t_back, "K off"), abs=1e-8)]
    k_out = list(res.t).index(res.events[1].time) + 1
    assert res.outputs["v"][k_out] == pytest.approx(-v_in, rel=1e-8)          # elastic rebound
    assert res.outputs["x"][list(res.t).index(apex)] == pytest.approx(-h, abs=1e-9)   # back at h
    assert res.outputs["x"][list(res.t).index(deepest)] == pytest.approx(A + math.hypot(A, B), abs=1e-9)
    assert res.energy_loss == 0


# ---------------------------------------------------------------- damped contact, no gravity
M, K, BD, V0, GAP = 0.5, 80.0, 1.2, 1.5, 0.3


def damped_by_hand(t_end):
    """Event times, exit velocity and x(t), q_k(t) of the damped contact without gravity."""
    t_in = GAP / V0
    x, v = oscillation(M, K, BD, 0.0, 0.0, V0)
    tr = first_fall(lambda s: K * x(s) + BD * v(s), 1e-9, 2 * math.pi * math.sqrt(M / K))
    xr, vr = x(tr), v(tr)

    def position(t):
        if t <= t_in:
            return -GAP + V0 * t
        if t <= t_in + tr:
            return x(t - t_in)
        return xr + vr * (t - t_in - tr)

    def spring(t):            # the contact spring's compression
        if t <= t_in:
            return 0.0
        if t <= t_in + tr:
            return x(t - t_in)
        return xr * math.exp(-K * (t - t_in - tr) / BD)
    return t_in, t_in + tr, xr, vr, position, spring


def test_damped_contact_releases_at_zero_force_while_still_compressed():
    t_end = 1.5
    t_in, t_out, xr, vr, position, spring = damped_by_hand(t_end)
    sm = SwitchedModel(library.contact_stop(), outputs=OUT)
    samples = np.linspace(0, t_end, 301)
    res = bg.simulate(sm, {"m": M, "k": K, "b": BD, "gap": GAP}, (0, t_end), {"x": -GAP, "p_m": M * V0},
                      t_eval=samples,
                      **TOL)
    assert transitions(res) == [pytest.approx((t_in, "K off"), abs=1e-9),
                                pytest.approx((t_out, "K on"), abs=1e-9)]
    # it opens with the spring still compressed (x_r > 0), moving away at the hand exit velocity;
    # k x + b x' = 0 with x = (V0/wd) exp(-s t) sin(wd t) is also tan(wd t) = -b wd/(k - b s)
    s = BD / (2 * M)
    wd = math.sqrt(K / M - s * s)
    assert t_out - t_in == pytest.approx((math.pi - math.atan(BD * wd / (K - BD * s))) / wd, abs=1e-12)
    assert xr > 0.01 and vr < 0
    k_out = list(res.t).index(res.events[1].time) + 1
    assert res.outputs["v"][k_out] == pytest.approx(vr, rel=1e-8)
    assert res.outputs["v"][-1] == pytest.approx(vr, rel=1e-8)               # free flight after it
    on_grid = np.isin(res.t, samples)
    assert res.outputs["x"][on_grid] == pytest.approx([position(t) for t in samples], abs=1e-9)
    assert res.stored["q_k"][on_grid] == pytest.approx([spring(t) for t in samples], abs=1e-9)
    assert res.outputs["F"].min() >= -2e-9                                   # it never pulls
    assert res.energy_loss == 0


def test_a_position_gate_pulls_the_mass_back_where_the_contact_lets_it_go():
    # the same mass, spring and damper behind a gate closed while x > 0: it opens at x = 0, after
    # half a damped period, with v = -V0 exp(-s pi/wd); the contact lets go earlier and faster
    g = bg.BondGraph("gate")
    g.add(bg.One("v"), bg.I("m"), bg.Zero("c"), ControlledSwitch("K", gate=-bg.displacement("m"), on=True),
          bg.One("s"), bg.C("k", stiffness="k"), bg.R("b"))
    for tail, head in [("v", "m"), ("v", "c"), ("c", "K"), ("c", "s"), ("s", "k"), ("s", "b")]:
        g.connect(tail, head)
    res = bg.simulate(SwitchedModel(g, outputs=OUT), {"m": M, "k": K, "b": BD}, (0, 1.5),
                      {"x": -GAP, "p_m": M * V0}, **TOL)
    s = BD / (2 * M)
    wd = math.sqrt(K / M - s * s)
    v_gate = -V0 * math.exp(-s * math.pi / wd)
    assert res.events[1].time == pytest.approx(GAP / V0 + math.pi / wd, abs=1e-9)
    assert res.outputs["v"][-1] == pytest.approx(v_gate, rel=1e-8)
    assert res.outputs["F"].min() < -0.1                                      # the gate pulled
    _, _, _, vr, _, _ = damped_by_hand(1.5)
    assert abs(vr) > abs(v_gate) + 0.01


# ---------------------------------------------------------------- re-closing on a relaxing surface
def test_damped_drop_recloses_on_a_surface_that_is_still_relaxing():
    m, k, b, g, h = 1.0, 100.0, 8.0, 9.81, 2.0
    t_in = math.sqrt(2 * h / g)
    x1, v1 = oscillation(m, k, b, g, 0.0, g * t_in)
    tr = first_fall(lambda s: k * x1(s) + b * v1(s), 1e-9, 2.0)
    xr, vr = x1(tr), v1(tr)

    def gap(s):         # the surface relaxes, the mass flies under gravity
        return xr * math.exp(-k * s / b) - (xr + vr * s + g * s * s / 2)
    sc = first_fall(gap, 1e-6, 2.0)
    xc, vc = xr + vr * sc + g * sc * sc / 2, vr + g * sc
    x2, v2 = oscillation(m, k, b, g, xc, vc)
    t_close2 = t_in + tr + sc
    t_end = t_close2 + 0.3
    assert xc > 0.005      # the surface had not come back: the second contact is not at x = 0
    sm = SwitchedModel(library.contact_stop(gravity=True), outputs=OUT)
    samples = np.linspace(t_close2, t_end, 31)
    res = bg.simulate(sm, {"m": m, "k": k, "b": b, "g": g, "gap": h}, (0, t_end), {"x": -h},
                      t_eval=samples, **TOL)
    assert transitions(res)[:3] == [pytest.approx((t_in, "K off"), abs=1e-9),
                                    pytest.approx((t_in + tr, "K on"), abs=1e-9),
                                    pytest.approx((t_close2, "K off"), abs=1e-8)]
    k_close = list(res.t).index(res.events[2].time)
    assert res.outputs["x"][k_close] == pytest.approx(xc, abs=1e-8)
    assert res.stored["q_k"][k_close] == pytest.approx(xc, abs=1e-8)     # the mass meets the surface
    assert res.outputs["v"][k_close + 1] == pytest.approx(vc, abs=1e-7)          # no jump: a massless surface
    later = np.isin(res.t, samples[1:])
    assert res.outputs["x"][later] == pytest.approx([x2(t - t_close2) for t in samples[1:]], abs=1e-7)
    assert res.energy_loss == 0


# ---------------------------------------------------------------- initial state
def test_a_contact_starting_touching_closes_or_opens_with_the_initial_velocity():
    # clearance 0: pushed onto the stop it starts closed (the force b v > 0), pulled away it stays open
    sm = SwitchedModel(library.contact_stop(), outputs=OUT)
    vals = {"m": M, "k": K, "b": BD, "gap": 0.0}
    onto = bg.simulate(sm, vals, (0, 0.01), {"p_m": M * V0}, **TOL)
    away = bg.simulate(sm, vals, (0, 0.01), {"p_m": -M * V0}, **TOL)
    assert str(onto.modes[onto.mode_index[-1]]) == "K off" and [str(m) for m in away.modes] == ["K on"]
    assert all(e.time == 0 for e in onto.events)
    x, v = oscillation(M, K, BD, 0.0, 0.0, V0)
    assert onto.outputs["x"][-1] == pytest.approx(x(0.01), abs=1e-10)
    assert away.outputs["x"][-1] == pytest.approx(-V0 * 0.01, abs=1e-12)


# ---------------------------------------------------------------- the library component
def test_the_component_in_a_graph_releases_at_zero_force_like_the_hand_solution():
    g = bg.BondGraph("rig")
    g.add(Mass("cart", mass="m"), bg.One("v"),
          UnilateralContact("stop", stiffness="k", damping="b", clearance="gap", grounded=True))
    g.connect("v", "cart.p")
    g.connect("v", "stop.a")
    sm = SwitchedModel(g, outputs={"x": bg.displacement("v"), "v": bg.flow("v")})
    assert sm.switches == ("stop.K",)
    t_in, t_out, _, vr, _, _ = damped_by_hand(1.0)
    res = bg.simulate(sm, {"m": M, "k": K, "b": BD, "gap": GAP}, (0, 1.0), {"x": -GAP, "p_cart.I": M * V0},
                      **TOL)
    assert [e.time for e in res.events] == pytest.approx([t_in, t_out], abs=1e-9)
    assert res.outputs["v"][-1] == pytest.approx(vr, rel=1e-8)


def test_an_elastic_component_between_two_masses_exchanges_their_velocities():
    # equal masses, one at rest 0.2 m ahead: an elastic contact swaps the velocities (momentum and
    # energy conserved, e = 1), after half a period of the relative motion pi sqrt(mu/k), mu = m/2
    m, k, v1 = 2.0, 800.0, 1.0
    g = bg.BondGraph("pair")
    g.add(Mass("m1", mass="m"), Mass("m2", mass="m"), bg.One("v1"), bg.One("v2"),
          UnilateralContact("c", stiffness="k", damping=0, clearance=0.2))
    for tail, head in [("v1", "m1.p"), ("v2", "m2.p"), ("v1", "c.a"), ("c.b", "v2")]:
        g.connect(tail, head)
    sm = SwitchedModel(g, outputs={"v1": bg.flow("v1"), "v2": bg.flow("v2")})
    res = bg.simulate(sm, {"m": m, "k": k}, (0, 0.5), {"p_m1.I": m * v1}, **TOL)
    t_in = 0.2 / v1
    assert [e.time for e in res.events] == pytest.approx([t_in, t_in + math.pi * math.sqrt(m / 2 / k)],
                                                         abs=1e-9)
    assert (res.outputs["v1"][-1], res.outputs["v2"][-1]) == pytest.approx((0.0, v1), abs=1e-9)


def _two_body_case(seed):
    """A random damped contact between two masses, built in a random order and orientation."""
    rng = np.random.default_rng(seed)
    m1, m2 = 10 ** rng.uniform(-1, 1, 2)                  # two decades of masses
    mu = m1 * m2 / (m1 + m2)
    k = 10 ** rng.uniform(1, 3)
    b = rng.uniform(0.05, 0.9) * 2 * math.sqrt(k * mu)    # underdamped relative motion
    v1, v2 = rng.uniform(-1, 2), rng.uniform(-2, 1)
    if v1 - v2 < 0.2:
        v1 += 0.5 - (v1 - v2)                              # approaching
    clearance = rng.uniform(0.01, 0.5)
    flip = bool(rng.integers(2))                           # which body is port a of the contact
    g = bg.BondGraph(f"pair{seed}")
    parts = [Mass("m1", mass="m1"), Mass("m2", mass="m2"), bg.One("v1"), bg.One("v2"),
             UnilateralContact("c", stiffness="k", damping="b", clearance="gap")]
    for i in rng.permutation(len(parts)):
        g.add(parts[i])
    a, bb = ("v2", "v1") if flip else ("v1", "v2")
    bonds = [("v1", "m1.p"), ("v2", "m2.p"), (a, "c.a"), ("c.b", bb)]
    for i in rng.permutation(len(bonds)):
        g.connect(*bonds[i])
    if flip:                                               # the contact then closes as v2 - v1 > 0
        v1, v2 = v2, v1
    return g, dict(m1=m1, m2=m2, k=k, b=b, gap=clearance), (v1, v2), flip


@pytest.mark.parametrize("seed", range(8))
def test_random_two_body_contacts_conserve_momentum_and_release_at_zero_force(seed):
    # relative motion: mu x'' + b x' + k x = 0 from x = 0, x' = w0 (the closing speed), released
    # when k x + b x' = 0: wd t = atan2(b wd, b s - k); the centre of mass moves on unchanged
    g, vals, (v1, v2), flip = _two_body_case(seed)
    m1, m2, k, b = vals["m1"], vals["m2"], vals["k"], vals["b"]
    mu = m1 * m2 / (m1 + m2)
    s = b / (2 * mu)
    wd = math.sqrt(k / mu - s * s)
    va, vb, ma, mb = (v2, v1, m2, m1) if flip else (v1, v2, m1, m2)
    w0 = va - vb
    t_in = vals["gap"] / w0
    t_r = math.atan2(b * wd, b * s - k) / wd
    w_out = w0 * math.exp(-s * t_r) * (math.cos(wd * t_r) - s / wd * math.sin(wd * t_r))
    V = (m1 * v1 + m2 * v2) / (m1 + m2)
    va_out, vb_out = V + mb / (m1 + m2) * w_out, V - ma / (m1 + m2) * w_out
    sm = SwitchedModel(g, outputs={"va": bg.flow("v2" if flip else "v1"), "vb": bg.flow("v1" if flip else "v2")})
    t_end = t_in + t_r + 0.1
    res = bg.simulate(sm, vals, (0, t_end), {"p_m1.I": m1 * v1, "p_m2.I": m2 * v2}, **TOL)
    assert [e.time for e in res.events] == pytest.approx([t_in, t_in + t_r], rel=1e-8, abs=1e-10)
    assert w_out < 0                                        # they separate
    assert (res.outputs["va"][-1], res.outputs["vb"][-1]) == pytest.approx((va_out, vb_out), rel=1e-7,
                                                                           abs=1e-9)


# ---------------------------------------------------------------- bad input
def test_bad_contact_parameters_are_named():
    with pytest.raises(bg.BondGraphError, match=r"Ct:K: clearance flow\[m\] must be .*no signals"):
        Contact("K", clearance=bg.flow("m"))
    with pytest.raises(bg.BondGraphError, match=r"Ct:K: clearance must be finite"):
        Contact("K", clearance=float("inf"))
    with pytest.raises(bg.BondGraphError, match=r"Ct:K: clearance must be >= 0 \(the gap at t = 0\), got -0.1"):
        Contact("K", clearance=-0.1)
    with pytest.raises(bg.BondGraphError, match=r"UnilateralContact 'stop'.*stiffness must be positive"):
        UnilateralContact("stop", stiffness=-1.0, damping=1.0)
    with pytest.raises(bg.BondGraphError, match=r"Ct:K: built closed \(on=False\) with a clearance of 0.2"):
        Contact("K", clearance=0.2, on=False)


def test_a_contact_bonded_out_of_it_warns_which_way_its_variables_point():
    g = bg.BondGraph("backwards")
    g.add(bg.One("v"), bg.I("m"), bg.Zero("c"), Contact("K"), bg.C("k"))
    for tail, head in [("v", "m"), ("v", "c"), ("K", "c"), ("c", "k")]:
        g.connect(tail, head)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        SwitchedModel(g).mode(off={"K"})
    assert any("points out of Ct:K" in str(w.message) and "opposite sign" in str(w.message)
               for w in caught)


# ---------------------------------------------------------------- the FMU
@pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None, reason="no C compiler")
def test_fmu_of_the_damped_contact_agrees_with_the_hand_solution_and_simulate(tmp_path):
    fmpy = pytest.importorskip("fmpy")
    from fmpy.validation import validate_fmu
    from bondgraph.fmu import build_fmu

    t_end = 1.5
    t_in, t_out, _, vr, position, _ = damped_by_hand(t_end)
    sm = SwitchedModel(library.contact_stop(), outputs=OUT)
    path = tmp_path / "contact.fmu"
    path.write_bytes(build_fmu(sm, fmi=2, kind="both", values={"m": M, "k": K, "b": BD, "gap": GAP},
                               step=1e-4))
    assert validate_fmu(str(path)) == []
    ref = bg.simulate(sm, {"m": M, "k": K, "b": BD, "gap": GAP}, (0, t_end), {"x": -GAP, "p_m": M * V0},
                      **TOL)
    for kind, tol in (("ModelExchange", 5e-8), ("CoSimulation", 1e-9)):
        res = fmpy.simulate_fmu(str(path), fmi_type=kind, stop_time=t_end, output_interval=0.01,
                                relative_tolerance=1e-10, start_values={"x": -GAP, "p_m": M * V0}, output=["x", "v", "F"])
        t = res["time"]
        if kind == "ModelExchange":       # an event is sampled twice, before and after the change
            assert t[1:][np.diff(t) == 0] == pytest.approx([t_in, t_out], abs=10 * tol)
        assert res["v"][-1] == pytest.approx(vr, abs=tol)
        assert res["v"][-1] == pytest.approx(ref.outputs["v"][-1], abs=tol)
        assert res["x"] == pytest.approx([position(tk) for tk in t], abs=10 * tol)
        assert res["F"].min() >= -2e-9
