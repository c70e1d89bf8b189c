"""Karnopp stick-slip friction (hybrid.Slip, mechanical.Friction, FrictionClutch) against hand solutions.

The references are written here, phase by phase, from Newton's law with
piecewise-constant friction:

* a clutch between ``J1`` (driven by the ramp torque ``a t``) and ``J2``
  spinning at ``W``: slipping backwards (``w1 < w2``), ``J1 w1' = a t + Tk``,
  ``J2 w2' = -Tk`` until the slip closes (a quadratic's root); stuck,
  ``(J1 + J2) w' = a t`` and the clutch carries ``J2 a t/(J1 + J2)`` until that
  reaches ``Ts``; then slipping forwards, ``J1 w1' = a t - Tk``, ``J2 w2' = Tk``;
* a block pushed by ``F0 sin(w t)`` on a table: stuck until the push
  reaches ``Fs``, slipping with ``m v' = F0 sin(w t) - Fk`` until ``v`` returns
  to zero (``brentq`` on the closed-form velocity), stuck while ``|F| <= Fs``,
  then the mirror image half a period later.
"""

from __future__ import annotations

import math
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy
from scipy.optimize import brentq

import bondgraph as bg
from bondgraph.hybrid import Slip, SwitchedModel, library
from bondgraph.library.mechanical import ForceSource, Friction, FrictionClutch, Inertia, Mass

TOL = {"rtol": 1e-10, "atol": 1e-12}


def first_zero(f, t0, t1, n=4001):
    """The first time in (t0, t1] at which f falls from > 0 to < 0 (grid, then brentq)."""
    ts = np.linspace(t0, t1, n)
    fv = np.array([f(t) for t in ts])
    j = int(np.nonzero(fv < 0)[0][0])
    return brentq(f, ts[j - 1], ts[j], xtol=1e-15)

# ---------------------------------------------------------------- the clutch on a ramp torque
J1, J2, A, TK, TS, W = 1.0, 2.0, 3.0, 1.0, 2.0, 2.0
CLUTCH = {"J1": J1, "J2": J2, "a": A, "Tk": TK, "Ts": TS}
OUT = {"w1": bg.flow("J1"), "w2": bg.flow("J2"), "torque": bg.effort("c")}


def clutch_by_hand():
    """(t1, t2, w(t)): slip backwards until t1, stuck until t2, slipping forwards after."""
    qa, qb = A / (2 * J1), TK * (1 / J1 + 1 / J2)           # slip = qa t^2 + qb t - W
    t1 = (-qb + math.sqrt(qb * qb + 4 * qa * W)) / (2 * qa)
    t2 = TS * (J1 + J2) / (J2 * A)
    assert J2 * A * t1 / (J1 + J2) < TS and t1 < t2          # it sticks at t1
    wc1 = (A * t1**2 / 2 + TK * t1) / J1
    wc2 = wc1 + A * (t2**2 - t1**2) / (2 * (J1 + J2))

    def w(t):
        """(w1, w2, clutch torque) at t."""
        if t < t1:
            return (A * t**2 / 2 + TK * t) / J1, W - TK * t / J2, -TK
        if t < t2:
            wc = wc1 + A * (t**2 - t1**2) / (2 * (J1 + J2))
            return wc, wc, J2 * A * t / (J1 + J2)
        return (wc2 + (A * (t**2 - t2**2) / 2 - TK * (t - t2)) / J1, wc2 + TK * (t - t2) / J2, TK)
    return t1, t2, w


def clutch_model():
    return SwitchedModel(library.friction_clutch(torque=sympy.Symbol("a", positive=True) * bg.t),
                         outputs=OUT)


def test_clutch_slips_back_sticks_and_slips_forwards_at_the_hand_instants():
    t1, t2, w = clutch_by_hand()
    samples = np.linspace(0, 2, 201)
    res = bg.simulate(clutch_model(), CLUTCH, (0, 2), {"p_J2": J2 * W}, t_eval=samples, **TOL)
    changes = [(e.time, str(e.after)) for e in res.events]
    # built stuck; at t = 0 the speeds differ (w1 = 0 < w2 = W): it starts slipping backwards
    assert changes == [(0.0, "Kf off, Kr on"), pytest.approx((t1, "Kf off, Kr off"), abs=1e-9),
                       pytest.approx((t2, "Kf on, Kr off"), abs=1e-9)]
    away = np.isin(res.t, samples) & (np.abs(res.t - t1) > 1e-6) & (np.abs(res.t - t2) > 1e-6)
    ref = np.array([w(t) for t in res.t[away]])
    for j, name in enumerate(("w1", "w2", "torque")):
        assert res.outputs[name][away] == pytest.approx(ref[:, j], abs=1e-8), name
    # no jump at the lock (the speeds are equal when the slip closes) nor anywhere else
    assert all(e.jumps == {} for e in res.events) and res.energy_loss == 0


def test_clutch_energy_balance_the_friction_loss_is_the_kinetic_torque_times_the_slip():
    # the ramp's work on J1 = the kinetic energy gained + Tk |w1 - w2| integrated over both slip
    # phases (closed forms: polynomials in t); the kinetic energy from the simulated momenta
    t1, t2, _ = clutch_by_hand()
    t_end = 2.0
    res = bg.simulate(clutch_model(), CLUTCH, (0, t_end), {"p_J2": J2 * W}, **TOL)
    P = np.polynomial.Polynomial

    def integral(p, a, b):
        q = p.integ()
        return q(b) - q(a)
    qa, qb = A / (2 * J1), TK * (1 / J1 + 1 / J2)
    slip_back = P([W, -qb, -qa])                               # w2 - w1 while slipping back
    slip_fwd = P([A * t2**2 / (2 * J1) * -1 + TK * t2 * (1 / J1 + 1 / J2), -TK * (1 / J1 + 1 / J2),
                  A / (2 * J1)])                                # w1 - w2 after t2
    loss = TK * (integral(slip_back, 0, t1) + integral(slip_fwd, t2, t_end))
    wc1 = (A * t1**2 / 2 + TK * t1) / J1
    wc2 = wc1 + A * (t2**2 - t1**2) / (2 * (J1 + J2))
    w1_phases = ((P([0, TK / J1, A / (2 * J1)]), 0, t1),
                 (P([wc1 - A * t1**2 / (2 * (J1 + J2)), 0, A / (2 * (J1 + J2))]), t1, t2),
                 (P([wc2 - A * t2**2 / (2 * J1) + TK * t2 / J1, -TK / J1, A / (2 * J1)]), t2, t_end))
    work = sum(integral(P([0, A]) * p, a, b) for p, a, b in w1_phases)
    p1, p2 = res.stored["p_J1"][-1], res.stored["p_J2"][-1]
    kinetic = p1**2 / (2 * J1) + p2**2 / (2 * J2) - J2 * W**2 / 2
    assert loss > 0.5
    assert kinetic == pytest.approx(work - loss, abs=1e-8)


# ---------------------------------------------------------------- a block on a table
M, F0, FS, FK = 1.0, 1.5, 1.0, 0.9
OMEGA = 2 * math.pi                   # period 1 s


def block_by_hand():
    """Slip instants and v(t) of the block: stick, slip forwards, stick, slip backwards, ..."""
    ts1 = math.asin(FS / F0) / OMEGA                   # the push reaches Fs

    def v_fwd(t):
        return (F0 / OMEGA * (math.cos(OMEGA * ts1) - math.cos(OMEGA * t)) - FK * (t - ts1)) / M
    te1 = first_zero(v_fwd, ts1 + 1e-6, 1.0)
    assert abs(F0 * math.sin(OMEGA * te1)) < FS        # it sticks when the slip stops

    assert te1 < ts1 + 0.5                             # it sticks before slipping back

    def v(t):
        """Period 1 s, and the mirror image half a period later: v(t + 1/2) = -v(t)."""
        if ts1 < t % 1.0 < te1:
            return v_fwd(t % 1.0)
        if t >= 0.5 and ts1 < (t - 0.5) % 1.0 < te1:
            return -v_fwd((t - 0.5) % 1.0)
        return 0.0
    return ts1, te1, v


def block_model():
    F0s, FSs, FKs, w = sympy.symbols("F0 Fs Fk w", positive=True)
    g = bg.BondGraph("block")
    g.add(ForceSource("push", value=F0s * sympy.sin(w * bg.t)), Mass("m", mass="m"), bg.One("v"),
          Friction("table", kinetic=FKs, static=FSs, grounded=True))
    for tail, head in [("push.p", "v"), ("v", "m.p"), ("v", "table.a")]:
        g.connect(tail, head)
    return SwitchedModel(g, outputs={"v": bg.flow("v"), "friction": bg.effort("table.F")})


def test_block_on_a_table_sticks_and_slips_both_ways_at_the_hand_instants():
    ts1, te1, v = block_by_hand()
    samples = np.linspace(0, 1.5, 151)
    res = bg.simulate(block_model(), {"m": M, "F0": F0, "Fs": FS, "Fk": FK, "w": OMEGA}, (0, 1.5),
                      t_eval=samples, **TOL)
    expected = []
    for base, slip in ((0.0, "table.fwd on, table.rev off"), (0.5, "table.fwd off, table.rev on"),
                       (1.0, "table.fwd on, table.rev off")):
        expected += [(base + ts1, slip), (base + te1, "table.fwd off, table.rev off")]
    got = [(e.time, str(e.after)) for e in res.events]
    assert got == [pytest.approx(e, abs=1e-9) for e in expected[:5]]       # the sixth is at 1.56 s
    on_grid = np.isin(res.t, samples)
    assert res.outputs["v"][on_grid] == pytest.approx([v(t) for t in res.t[on_grid]], abs=1e-9)
    # stuck, the table holds the whole push; slipping, it carries Fk against the motion
    for t, f in zip(res.t[on_grid], res.outputs["friction"][on_grid]):
        slipping = v(t) != 0
        assert f == pytest.approx(FK * math.copysign(1, v(t)) if slipping else F0 * math.sin(OMEGA * t),
                                  abs=1e-9)


def test_a_block_pushed_hard_reverses_its_slip_without_sticking():
    # F0 = 2, Fk = 0.8: when the forward slip stops the push is already below -Fs, so the block
    # slips straight back (both slip guards are zero at that instant; the backward one grows)
    F0_, FK_ = 2.0, 0.8
    ts1 = math.asin(FS / F0_) / OMEGA

    def v_fwd(t):
        return (F0_ / OMEGA * (math.cos(OMEGA * ts1) - math.cos(OMEGA * t)) - FK_ * (t - ts1)) / M
    te1 = first_zero(v_fwd, ts1 + 1e-6, 1.0)
    assert F0_ * math.sin(OMEGA * te1) < -FS

    def v_back(t):
        return (F0_ / OMEGA * (math.cos(OMEGA * te1) - math.cos(OMEGA * t)) + FK_ * (t - te1)) / M
    te2 = first_zero(lambda t: -v_back(t), te1 + 1e-6, te1 + 1.0)
    assert F0_ * math.sin(OMEGA * te2) > FS                    # and forwards again
    samples = np.linspace(0, te2, 101)[1:-1]
    res = bg.simulate(block_model(), {"m": M, "F0": F0_, "Fs": FS, "Fk": FK_, "w": OMEGA}, (0, te2 + 0.01),
                      t_eval=samples, **TOL)
    got = [(e.time, str(e.after)) for e in res.events]
    assert got == [pytest.approx((ts1, "table.fwd on, table.rev off"), abs=1e-9),
                   pytest.approx((te1, "table.fwd off, table.rev on"), abs=1e-9),
                   pytest.approx((te2, "table.fwd on, table.rev off"), abs=1e-9)]
    hand = [0.0 if t < ts1 else v_fwd(t) if t < te1 else v_back(t) for t in samples]
    assert res.outputs["v"][np.isin(res.t, samples)] == pytest.approx(hand, abs=1e-9)


def test_the_clutch_component_between_two_shafts_matches_the_hand_solution():
    g = bg.BondGraph("drive")
    a = sympy.Symbol("a", positive=True)
    g.add(bg.Se("motor", value=a * bg.t), Inertia("J1", inertia="J1"), Inertia("J2", inertia="J2"),
          FrictionClutch("K", kinetic="Tk", static="Ts"), bg.One("w1"), bg.One("w2"))
    for tail, head in [("motor", "w1"), ("w1", "J1.p"), ("w1", "K.a"), ("K.b", "w2"), ("w2", "J2.p")]:
        g.connect(tail, head)
    sm = SwitchedModel(g, outputs={"w1": bg.flow("w1"), "w2": bg.flow("w2")})
    t1, t2, w = clutch_by_hand()
    res = bg.simulate(sm, CLUTCH, (0, 1.5), {"p_J2.I": J2 * W}, **TOL)
    assert [e.time for e in res.events] == pytest.approx([0.0, t1, t2], abs=1e-9)
    assert (res.outputs["w1"][-1], res.outputs["w2"][-1]) == pytest.approx(w(1.5)[:2], abs=1e-8)


def test_the_model_file_friction_clutch_is_the_hand_solution():
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "models"))
    import clutch

    assert clutch.KARNOPP == CLUTCH
    t1, t2, w = clutch_by_hand()
    res = bg.simulate(clutch.karnopp(), clutch.KARNOPP, (0, 2), {"p_J2": J2 * W}, **TOL)
    assert [e.time for e in res.events] == pytest.approx([0.0, t1, t2], abs=1e-9)
    assert [res.outputs[n][-1] for n in ("w1", "w2", "torque")] == pytest.approx(w(2.0), abs=1e-8)


# ---------------------------------------------------------------- generated code
def test_generated_python_guards_and_mode_choice_follow_karnopp():
    from bondgraph.codegen import generate_switched_python

    ns: dict = {}
    exec(compile(generate_switched_python(clutch_model()), "karnopp_gen", "exec"), ns)
    p = [CLUTCH[name] for name in ns["PARAMETER_NAMES"]]
    stuck = ns["MODES"].index("Kf off, Kr off")
    fwd = ns["MODES"].index("Kf on, Kr off")
    on_fwd = ns["MODE_ON"][fwd]
    t = 0.5          # stuck, the clutch carries J2 a t/(J1 + J2): guards Ts - T and Ts + T
    T = J2 * A * t / (J1 + J2)
    x = [J1 * 1.0, J2 * 1.0]
    assert ns["guards"](stuck, t, x, [], p) == pytest.approx([TS - T, TS + T], rel=1e-12)
    # from stuck at the breakaway instant t2, the forward slip is chosen (no energy lost, state kept)
    t2 = TS * (J1 + J2) / (J2 * A)
    mode, xn, loss = ns["select"](on_fwd, 0b11, 0b11, 1e-9, t2, x, [], p)
    assert (mode, xn, loss) == (fwd, x, 0.0)


# ---------------------------------------------------------------- bad input
def test_bad_friction_parameters_are_named():
    with pytest.raises(bg.BondGraphError, match=r"Slip:K: give kinetic="):
        Slip("K")
    with pytest.raises(bg.BondGraphError, match=r"Slip:K: direction must be \+1 or -1; got 2"):
        Slip("K", kinetic=1, direction=2)
    with pytest.raises(bg.BondGraphError, match=r"Slip:K: kinetic friction must be >= 0, got -1"):
        Slip("K", kinetic=-1)
    with pytest.raises(bg.BondGraphError, match=r"Slip:K: static friction 1 is below the kinetic friction 2"):
        Slip("K", kinetic=2, static=1)
    with pytest.raises(bg.BondGraphError, match=r"Slip:K: kinetic .* no signals"):
        Slip("K", kinetic=bg.effort("N"))
    with pytest.raises(bg.BondGraphError, match=r"FrictionClutch 'K'.*kinetic must be positive"):
        FrictionClutch("K", kinetic=-1.0, static=1.0)


# ---------------------------------------------------------------- the FMU
@pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None, reason="no C compiler")
def test_fmu_of_the_clutch_agrees_with_the_hand_solution_and_simulate(tmp_path):
    fmpy = pytest.importorskip("fmpy")
    from fmpy.validation import validate_fmu
    from bondgraph.fmu import build_fmu

    t1, t2, w = clutch_by_hand()
    sm = clutch_model()
    path = tmp_path / "karnopp.fmu"
    path.write_bytes(build_fmu(sm, fmi=3, kind="both", values=CLUTCH, step=1e-3))
    assert validate_fmu(str(path)) == []
    ref = bg.simulate(sm, CLUTCH, (0, 2), {"p_J2": J2 * W}, **TOL)
    for kind, tol in (("ModelExchange", 1e-7), ("CoSimulation", 1e-9)):
        res = fmpy.simulate_fmu(str(path), fmi_type=kind, stop_time=2.0, output_interval=0.01,
                                relative_tolerance=1e-10, start_values={"p_J2": J2 * W},
                                output=["w1", "w2", "torque"])
        t = res["time"]
        if kind == "ModelExchange":       # an event is sampled twice, before and after the change
            assert t[1:][np.diff(t) == 0] == pytest.approx([t1, t2], abs=1e-8)
        away = (np.abs(t - t1) > 1e-6) & (np.abs(t - t2) > 1e-6)
        ref_t = np.array([w(tk) for tk in t[away]])
        for j, name in enumerate(("w1", "w2", "torque")):
            assert res[name][away] == pytest.approx(ref_t[:, j], abs=tol), (kind, name)
        assert res["w1"][-1] == pytest.approx(ref.outputs["w1"][-1], abs=tol)
