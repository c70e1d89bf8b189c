"""FMUs of switched models (bondgraph.fmu with a hybrid.SwitchedModel), checked by fmpy.

The half-wave rectifier and the clutch are built once per FMI version (Model
Exchange and Co-Simulation in one archive), validated by
``fmpy.validation.validate_fmu`` and simulated by ``fmpy.simulate_fmu``:

* Model Exchange (fmpy's CVode with the FMU's event indicators): the
  switching instants fmpy records (a time sampled twice: before and after
  the event) against their closed forms -- the rectifier's ``tan(w t) = -w R
  C`` and the transcendental re-conduction equation solved here by brentq,
  the clutch's ``t_lock`` -- and the outputs against the piecewise closed
  forms (the decaying capacitor voltage; Newton before the lock, the
  momentum-conserving common velocity ``(J1 w1 + J2 w2)/(J1 + J2)`` and
  ``(J1 + J2) w' = tau`` after, the energy lost ``J1 J2 (w1 - w2)^2 / (2 (J1 +
  J2))``) and against ``bg.simulate`` of the switched model;
* Co-Simulation (the FMU's RK4 stepping through the events located by
  bisection inside a communication step) against the same closed forms;
* a mass on an end stop (an integrated displacement in the state): contact
  time ``pi sqrt(m/k)`` (undamped half period);
* a mode whose re-initialisation is not a linear map is refused naming it.
"""

import math
import shutil
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest
import sympy
from scipy.optimize import brentq

import bondgraph as bg
from bondgraph.hybrid import ControlledSwitch, SwitchedModel, library

fmpy = pytest.importorskip("fmpy")
from fmpy import read_model_description, simulate_fmu  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

from bondgraph.fmu import FMUError, build_fmu  # noqa: E402

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler on PATH")

VM, F, RL, CL = 10.0, 50.0, 100.0, 1e-4
W, TAU = 2 * math.pi * F, RL * CL
RECT = {"Vm": VM, "w": W, "R": RL, "C": CL}
J1, J2, T_LOCK, TORQUE, W20 = 1.0, 2.0, 1.0, 1.0, 3.0
CLUTCH = {"J1": J1, "J2": J2, "t_lock": T_LOCK}


def rectifier_by_hand(t_end):
    """Switching instants and v(t) of the ideal half-wave rectifier (closed forms).

    Conducting, v = Vm sin(w t) and the diode current C v' + v/R vanishes at
    tan(w t) = -w R C; blocking, v = v_off exp(-(t - t_off)/(R C)) until Vm
    sin(w t) catches up with it.
    """
    t_off0 = (math.pi - math.atan(W * TAU)) / W
    offs, ons = [], []
    for k in range(100):
        t_off = t_off0 + k * 2 * math.pi / W
        if t_off > t_end:
            break
        offs.append(t_off)
        v_off = VM * math.sin(W * t_off)
        lo = (k + 1) * 2 * math.pi / W
        t_on = brentq(lambda t, v_off=v_off, t_off=t_off: VM * math.sin(W * t)
                      - v_off * math.exp(-(t - t_off) / TAU),
                      lo, lo + math.pi / (2 * W), xtol=1e-15)
        if t_on > t_end:
            break
        ons.append(t_on)

    def v(t):
        for t_off, t_on in zip(offs, ons + [math.inf]):
            if t < t_off:
                return VM * math.sin(W * t)
            if t < t_on:
                return VM * math.sin(W * t_off) * math.exp(-(t - t_off) / TAU)
        return VM * math.sin(W * t)
    return offs, ons, v


def clutch_by_hand(t):
    """(w1, w2) of the clutch: Newton before t_lock, momentum conserved at it, one body after."""
    if t < T_LOCK:
        return TORQUE * t / J1, W20
    wc = (J1 * TORQUE * T_LOCK / J1 + J2 * W20) / (J1 + J2)
    w = wc + TORQUE * (t - T_LOCK) / (J1 + J2)
    return w, w


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    folder = tmp_path_factory.mktemp("switched_fmus")
    rect = SwitchedModel(library.rectifier(), outputs={"v": bg.effort("C"), "i": bg.flow("D")})
    clutch = SwitchedModel(library.clutch(), outputs={"w1": bg.flow("J1"), "w2": bg.flow("J2")})
    out = {}
    for fmi in (2, 3):
        for name, sm, vals, step in (("rectifier", rect, RECT, 1e-4), ("clutch", clutch, CLUTCH, 0.03)):
            path = folder / f"{name}{fmi}.fmu"
            path.write_bytes(build_fmu(sm, fmi=fmi, kind="both", values=vals, step=step))
            out[name, fmi] = path
    out["rect_model"], out["clutch_model"] = rect, clutch
    return out


def event_times(res):
    t = res["time"]
    return t[1:][np.diff(t) == 0]


@pytest.mark.parametrize("fmi", [2, 3])
def test_switched_fmus_are_valid_with_event_indicators(fmus, fmi):
    for name, states, n_ind in (("rectifier", ["q_C"], 1), ("clutch", ["p_J1", "p_J2"], 1)):
        path = fmus[name, fmi]
        assert validate_fmu(str(path)) == []
        md = read_model_description(str(path))
        assert md.numberOfEventIndicators == n_ind
        assert [v.name for v in md.modelVariables if v.derivative is not None] == [f"der({s})" for s in states]
        files = zipfile.ZipFile(path).namelist()
        assert "sources/bg_fmu_events.h" in files
        root = ET.fromstring(zipfile.ZipFile(path).read("modelDescription.xml"))
        if fmi == 3:
            assert len(root.findall("ModelStructure/EventIndicator")) == n_ind


@pytest.mark.parametrize("fmi", [2, 3])
def test_rectifier_me_events_and_voltage_against_the_closed_form(fmus, fmi):
    t_end = 0.05
    res = simulate_fmu(str(fmus["rectifier", fmi]), fmi_type="ModelExchange", stop_time=t_end,
                       output_interval=2.5e-4, relative_tolerance=1e-10, output=["v", "i"])
    offs, ons, v = rectifier_by_hand(t_end)
    # the diode's switching instants: off at tan(w t) = -w R C, on again where the source
    # catches up with the decaying capacitor; each event is located by CVode's root finding
    expect = sorted(offs + ons)
    got = event_times(res)
    assert len(got) == len(expect) == 5
    np.testing.assert_allclose(got, expect, rtol=0, atol=1e-8)
    vt = np.array([v(t) for t in res["time"]])
    np.testing.assert_allclose(res["v"], vt, rtol=0, atol=1e-6 * VM)
    # and the switched model's own simulation on the FMU's output grid
    grid = np.linspace(0, t_end, 201)
    ref = bg.simulate(fmus["rect_model"], RECT, (0, t_end), t_eval=grid, rtol=1e-10, atol=1e-13)
    keep = np.isin(ref.t, grid) & np.r_[np.diff(ref.t) != 0, True]
    on_grid = np.isin(res["time"], grid) & np.r_[np.diff(res["time"]) != 0, True]
    np.testing.assert_allclose(res["v"][on_grid], ref.outputs["v"][keep], rtol=0, atol=1e-6 * VM)


@pytest.mark.parametrize("fmi", [2, 3])
def test_rectifier_cs_steps_through_the_events(fmus, fmi):
    t_end = 0.05
    # communication step 1 ms: each holds 10 RK4 steps of 0.1 ms, and every switching instant
    # falls inside one: the FMU locates it by bisection of that RK4 step
    res = simulate_fmu(str(fmus["rectifier", fmi]), fmi_type="CoSimulation", stop_time=t_end,
                       output_interval=1e-3, output=["v", "i"])
    _, _, v = rectifier_by_hand(t_end)
    vt = np.array([v(t) for t in res["time"]])
    # RK4 with h w = 0.031: global error about T w^5 h^4/120 relative, under 1e-7 of Vm; an
    # event off by one RK4 step would leave a 1e-2 error in v while blocking
    np.testing.assert_allclose(res["v"], vt, rtol=0, atol=1e-6 * VM)
    assert np.all(res["i"] >= -1e-9)


@pytest.mark.parametrize("fmi", [2, 3])
@pytest.mark.parametrize("kind", ["ModelExchange", "CoSimulation"])
def test_clutch_lock_conserves_momentum(fmus, fmi, kind):
    t_end = 2.0
    tau = np.array([(0.0, TORQUE), (t_end, TORQUE)], dtype=[("time", np.float64), ("tau", np.float64)])
    res = simulate_fmu(str(fmus["clutch", fmi]), fmi_type=kind, stop_time=t_end, output_interval=0.1,
                       relative_tolerance=1e-10, start_values={"p_J2": J2 * W20}, input=tau,
                       output=["w1", "w2", "p_J1", "p_J2"])
    for t, w1, w2 in zip(res["time"], res["w1"], res["w2"]):
        if abs(t - T_LOCK) > 1e-9:
            assert (w1, w2) == pytest.approx(clutch_by_hand(t), rel=1e-8, abs=1e-9)
    if kind == "ModelExchange":
        (te,) = event_times(res)
        assert te == pytest.approx(T_LOCK, abs=1e-9)
        k = int(np.nonzero(res["time"] == te)[0][0])
        before, after = res[k], res[k + 1]
        w1, w2 = before["w1"], before["w2"]
        wc = (J1 * w1 + J2 * w2) / (J1 + J2)
        assert after["w1"] == pytest.approx(wc, rel=1e-9) and after["w2"] == pytest.approx(wc, rel=1e-9)
        assert after["p_J1"] + after["p_J2"] == pytest.approx(before["p_J1"] + before["p_J2"], rel=1e-12)
        lost = (J1 * w1**2 + J2 * w2**2 - (J1 + J2) * wc**2) / 2
        assert lost == pytest.approx(J1 * J2 * (w1 - w2) ** 2 / (2 * (J1 + J2)), rel=1e-9)
        assert lost == pytest.approx(4 / 3, rel=1e-6)          # w1 = 1, w2 = 3: 1*2*2**2/(2*3)
    # the switched model's own simulation at the end
    ref = bg.simulate(fmus["clutch_model"], CLUTCH, (0, t_end), {"p_J2": J2 * W20}, u={"tau": TORQUE},
                      rtol=1e-10, atol=1e-12)
    assert res["w2"][-1] == pytest.approx(ref.outputs["w2"][-1], rel=1e-8)


def test_end_stop_contact_time_in_an_me_fmu(tmp_path):
    m, k, v0, gap = 2.0, 50.0, 1.0, 1.0
    sm = SwitchedModel(library.end_stop(), outputs={"x": bg.displacement("m"), "v": bg.flow("m")})
    path = tmp_path / "end_stop.fmu"
    path.write_bytes(build_fmu(sm, fmi=2, kind="me", values={"m": m, "k": k}))
    assert validate_fmu(str(path)) == []
    md = read_model_description(str(path))
    assert [v.name for v in md.modelVariables if v.derivative is not None] == ["der(p_m)", "der(q_k)", "der(x)"]
    res = simulate_fmu(str(path), fmi_type="ModelExchange", stop_time=3.0, output_interval=0.05,
                       relative_tolerance=1e-10, start_values={"p_m": m * v0, "x": -gap}, output=["x", "v"])
    t_in, t_out = event_times(res)
    # free flight to the stop, then half a period of the mass on the spring; elastic rebound
    assert t_in == pytest.approx(gap / v0, abs=1e-8)
    assert t_out - t_in == pytest.approx(math.pi * math.sqrt(m / k), abs=1e-7)
    assert res["v"][-1] == pytest.approx(-v0, abs=1e-7)
    assert res["x"][-1] == pytest.approx(-v0 * (3.0 - t_out), abs=1e-6)


def test_a_nonlinear_re_initialisation_is_refused_naming_the_mode():
    k, k3 = sympy.symbols("k k3", positive=True)
    g = bg.BondGraph("caps")
    g.add(bg.Zero("v1"), bg.C("C1"), bg.One("s"), bg.Zero("v2"), bg.C("C2", law=k * bg.q + k3 * bg.q**3),
          ControlledSwitch("S", gate=bg.t - 1))
    for tail, head in [("v1", "C1"), ("v1", "s"), ("s", "v2"), ("v2", "C2"), ("s", "S")]:
        g.connect(tail, head)
    with pytest.raises(FMUError, match=r"mode \(S on\): C2 in derivative causality .* not a linear map"):
        build_fmu(SwitchedModel(g), values={"C1": 1, "k": 1, "k3": 1}, binary=False)


def test_a_chattering_switch_stops_the_fmu_naming_it(tmp_path):
    # q' = I = 1 while S is open; S closes when q > 0 and then drains (q + 3)/R > I: the switch
    # is driven back and forth at q = 0 from t = 2 on (a sliding mode)
    g = bg.BondGraph("relay")
    g.add(bg.Sf("I", value=1), bg.Zero("v"), bg.C("C"), bg.One("b"),
          ControlledSwitch("S", gate=bg.displacement("C")), bg.R("R"), bg.Se("E", value=3))
    for tail, head in [("I", "v"), ("v", "C"), ("v", "b"), ("b", "S"), ("b", "R"), ("E", "b")]:
        g.connect(tail, head)
    path = tmp_path / "relay.fmu"
    path.write_bytes(build_fmu(SwitchedModel(g), fmi=2, values={"C": 1, "R": 1}, step=1e-3))
    for kind in ("ModelExchange", "CoSimulation"):
        messages = []

        def logger(env, instance, status, category, message, messages=messages):
            messages.append(message.decode())

        with pytest.raises(fmpy.fmi1.FMICallException):
            simulate_fmu(str(path), fmi_type=kind, stop_time=5.0, start_values={"q_C": -2.0},
                         logger=logger, timeout=60)
        (msg,) = [m for m in messages if "chatters" in m]
        t = float(msg.split("up to t = ")[1].split()[0])
        assert msg.startswith("switch S chatters") and t == pytest.approx(2.0, abs=1e-6)   # q = -2 + t
