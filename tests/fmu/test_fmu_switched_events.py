"""Switched FMUs against hand references and against ``bg.simulate`` (issue 34).

* The half-wave rectifier with a 1 Hz source and RC = 0.5 s from an empty
  capacitor (Model Exchange: fmpy's CVode with the FMU's event indicators;
  Co-Simulation: the FMU's RK4 with events located by bisection): turn-off
  instants from tan(w t) = -w R C, turn-on instants by brentq on the decay,
  v_C at 200 points over 3 periods within 1e-4 Vm.
* The buck converter in continuous conduction over 40 PWM periods against
  the exact piecewise-linear solution (the matrix exponential of each mode's
  equations, written here by Kirchhoff), the FMU and ``bg.simulate`` both.
* Zero storage parameters and a PWM period 0 refused when the FMU is built,
  naming the element or the switch.
"""

import math
import shutil

import numpy as np
import pytest
from scipy.linalg import expm

import bondgraph as bg
from bondgraph.hybrid import SwitchedModel, library

fmpy = pytest.importorskip("fmpy")
from fmpy import simulate_fmu  # noqa: E402

from bondgraph.fmu import FMUError, build_fmu  # noqa: E402

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler on PATH")

import importlib.util  # noqa: E402
import pathlib  # noqa: E402

_spec = importlib.util.spec_from_file_location(
    "_events_located", pathlib.Path(__file__).parents[1] / "hybrid" / "test_events_located.py")
_located = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_located)
rectifier_by_hand = _located.rectifier_by_hand
VM, W, R, C = _located.VM, _located.W, _located.R, _located.C


@pytest.fixture(scope="module")
def rect_fmus(tmp_path_factory):
    out = {}
    folder = tmp_path_factory.mktemp("rect1hz")
    for built, sm in (("on", SwitchedModel(library.rectifier(), outputs={"v": bg.effort("C")})),
                      ("off", _located.rectifier_built_blocking())):
        path = folder / f"rect_{built}.fmu"
        path.write_bytes(build_fmu(sm, fmi=2, kind="both", values={"Vm": VM, "w": W, "R": R, "C": C},
                                   step=1e-3))
        out[built] = path
    return out


@pytest.mark.parametrize("built", ["on", "off"])
@pytest.mark.parametrize("kind", ["ModelExchange", "CoSimulation"])
def test_slow_rectifier_fmu_against_the_closed_form(rect_fmus, kind, built):
    t_end = 3.0
    res = simulate_fmu(str(rect_fmus[built]), fmi_type=kind, stop_time=t_end, output_interval=t_end / 199,
                       relative_tolerance=1e-10, output=["v"])
    offs, ons, v = rectifier_by_hand(t_end)
    grid = np.linspace(0, t_end, 200)
    keep = np.isin(np.round(res["time"], 12), np.round(grid, 12))
    assert keep.sum() >= 200
    expect = np.array([v(t) for t in res["time"][keep]])
    np.testing.assert_allclose(res["v"][keep], expect, rtol=0, atol=1e-4 * VM)
    if kind == "ModelExchange":
        t = res["time"]
        events = t[1:][np.diff(t) == 0]
        if built == "off":      # built blocking: the FMU turns the diode on within 1e-9 V
            assert events[0] < 1e-9
            events = events[1:]
        np.testing.assert_allclose(events, sorted(offs + ons), rtol=0, atol=1e-7)


# ---------------------------------------------------------------- buck: exact piecewise-linear reference
VIN, D, T, LV, CV, RV = 10.0, 0.5, 1e-5, 1e-4, 1e-4, 5.0
BUCK = {"Vin": VIN, "duty": D, "T": T, "L": LV, "C": CV, "R": RV}


def buck_by_hand(x0, times):
    """(p_L, q_C) at ``times`` (in whole and half PWM periods' pieces) by Kirchhoff per mode:
    switch on, L p_L' ... p_L' = Vin - q_C/C; switch off (diode on), p_L' = -q_C/C; always
    q_C' = p_L/L - q_C/(R C).  Each piece x' = A x + b is exact: the matrix exponential of
    [[A, b], [0, 0]]."""
    A = np.array([[0.0, -1 / CV], [1 / LV, -1 / (RV * CV)]])

    def flow(x, h, on):
        M = np.zeros((3, 3))
        M[:2, :2], M[0, 2] = A, (VIN if on else 0.0)
        return (expm(M * h) @ np.append(x, 1.0))[:2]

    out, x, t = [], np.array(x0, dtype=float), 0.0
    for target in times:
        while t < target - 1e-15:
            k = math.floor(t / T + 1e-9)
            edge = k * T + (D * T if t < k * T + D * T - 1e-15 else T)
            nxt = min(edge, target)
            x = flow(x, nxt - t, on=t < k * T + D * T - 1e-15)
            t = nxt
        out.append(x.copy())
    return np.array(out)


def test_buck_fmu_and_simulate_against_the_exact_solution(tmp_path):
    i0 = D * VIN / RV - VIN * (1 - D) * D * T / LV / 2        # on the periodic steady state
    x0 = {"p_L": LV * i0, "q_C": CV * D * VIN}
    sm = SwitchedModel(library.buck(), outputs={"v": bg.effort("C"), "iL": bg.flow("L")})
    path = tmp_path / "buck.fmu"
    path.write_bytes(build_fmu(sm, fmi=2, kind="me", values=BUCK))
    times = np.linspace(0, 40 * T, 81)[1:]
    ref = buck_by_hand([x0["p_L"], x0["q_C"]], times)
    res = simulate_fmu(str(path), fmi_type="ModelExchange", stop_time=40 * T, output_interval=T / 2,
                       relative_tolerance=1e-10, start_values=x0, output=["v", "iL"])
    last = {round(t / (T / 2)): k for k, t in enumerate(res["time"])}   # after an event: the last
    rows = [last[j] for j in range(1, 81)]
    np.testing.assert_allclose(res["v"][rows], ref[:, 1] / CV, rtol=0, atol=1e-6 * VIN)
    np.testing.assert_allclose(res["iL"][rows], ref[:, 0] / LV, rtol=0, atol=1e-6)
    sim = bg.simulate(sm, BUCK, (0, 40 * T), x0, t_eval=times)
    at = np.isin(sim.t, times) & np.r_[np.diff(sim.t) != 0, True]
    np.testing.assert_allclose(sim.outputs["v"][at], ref[:, 1] / CV, rtol=0, atol=1e-6 * VIN)
    np.testing.assert_allclose(sim.outputs["iL"][at], ref[:, 0] / LV, rtol=0, atol=1e-6)


# ---------------------------------------------------------------- refused at build
def test_zero_storage_parameters_are_refused_when_building():
    sm = SwitchedModel(library.rectifier(), outputs={"v": bg.effort("C")})
    with pytest.raises(FMUError, match="C:C has C = 0"):
        build_fmu(sm, values={"Vm": VM, "w": W, "R": R, "C": 0.0}, binary=False)
    clutch = SwitchedModel(library.clutch(), outputs={"w2": bg.flow("J2")})
    with pytest.raises(FMUError, match="I:J2 has J2 = 0"):
        build_fmu(clutch, values={"J1": 1, "J2": 0, "t_lock": 1}, binary=False)


def test_a_pwm_period_zero_is_refused_when_building():
    sm = SwitchedModel(library.buck(), outputs={"v": bg.effort("C")})
    with pytest.raises(FMUError, match="T = 0"):
        build_fmu(sm, values=dict(BUCK, T=0.0), binary=False)


def test_bounce_fmu_first_contact_against_an_independent_solve(tmp_path):
    from scipy.integrate import solve_ivp

    vals = {"m": 1.0, "g": 9.81, "r": 1.0, "k_g": 100.0}
    # m h'' = -m g - r h' from h = 10 at rest; contact when h = 0 (solved here, not by bondgraph)
    fall = solve_ivp(lambda t, y: [y[1], -vals["g"] - vals["r"] * y[1] / vals["m"]], (0, 5),
                     [10.0, 0.0], events=lambda t, y: y[0], rtol=1e-12, atol=1e-12)
    t_hit = fall.t_events[0][0]
    sm = SwitchedModel(library.bounce(), outputs={"h": bg.displacement("ball")})
    path = tmp_path / "bounce.fmu"
    path.write_bytes(build_fmu(sm, fmi=2, kind="me", values=vals))
    res = simulate_fmu(str(path), fmi_type="ModelExchange", stop_time=3.0, output_interval=0.01,
                       relative_tolerance=1e-10, start_values={"h": 10.0}, output=["h"])
    t = res["time"]
    first = t[1:][np.diff(t) == 0][0]
    assert first == pytest.approx(t_hit, abs=1e-7)
    sim = bg.simulate(sm, vals, (0, 3.0), {"h": 10.0}, rtol=1e-10, atol=1e-12)
    assert sim.events[0].time == pytest.approx(t_hit, abs=1e-8)
    assert res["h"][-1] == pytest.approx(sim.outputs["h"][-1], abs=1e-6)
