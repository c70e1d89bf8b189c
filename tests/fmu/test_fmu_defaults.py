"""FMUs that an importer runs well with its default settings (DefaultExperiment, state nominals).

References:

* the default experiment and nominals of a damped oscillator against the
  hand formulas: the modes ``-sigma +- i omega_d`` (``sigma = b / 2m``),
  settling ``ln(100) / sigma``, the step response's peak displacement
  ``F/k (1 + exp(-pi zeta / sqrt(1 - zeta^2)))`` and peak momentum
  ``m F / (m omega_d) exp(-sigma t*) sin(omega_d t*)`` at
  ``tan(omega_d t*) = omega_d / sigma``;
* fmpy's ``simulate_fmu`` with no option but the input's start value (so
  its stop time, tolerance and absolute tolerances come from the FMU)
  against ``bg.simulate`` (DOP853, rtol 1e-10) on FLEXCAM and a 100-cell
  mass-spring-damper chain: within 1e-4 of each output's largest magnitude.
"""

import math
import shutil
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest

import bondgraph as bg

fmpy = pytest.importorskip("fmpy")
from fmpy import simulate_fmu  # noqa: E402

from bondgraph.fmu import build_fmu, export_fmu  # noqa: E402

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler")
REPO = Path(__file__).resolve().parents[2]


def oscillator():
    g = bg.BondGraph("osc")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
    for a, b in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "k")]:
        g.connect(a, b)
    return bg.derive(g, outputs={"x": bg.displacement("k")})


def chain(n):
    """``n`` masses with dampers to ground and springs between neighbours; force on the first."""
    g = bg.BondGraph(f"chain{n}")
    g.add(bg.Se("F"))
    prev = None
    values = {}
    for i in range(n):
        v = bg.One(f"v{i}")
        g.add(v, bg.I(f"m{i}"), bg.R(f"b{i}"))
        g.connect(v, f"m{i}")
        g.connect(v, f"b{i}")
        values.update({f"m{i}": 1.0, f"b{i}": 0.5})
        if prev is None:
            g.connect("F", v)
        else:
            s = bg.Zero(f"s{i}")
            g.add(s, bg.C(f"k{i}", stiffness=f"k{i}"))
            g.connect(prev, s)
            g.connect(s, v)
            g.connect(s, f"k{i}")
            values[f"k{i}"] = 400.0
        prev = v
    return bg.derive(g, outputs={"v_last": bg.flow(f"m{n - 1}"), "v_first": bg.flow("m0")}), values


def description(data):
    return ET.fromstring(zipfile.ZipFile(__import__("io").BytesIO(data)).read("modelDescription.xml"))


@pytest.mark.parametrize("fmi", [2, 3])
def test_oscillator_defaults_match_the_hand_formulas(fmi):
    m, b, k = 2.0, 0.4, 50.0
    model = oscillator()
    values = {"m": m, "b": b, "k": k}
    root = description(build_fmu(model, fmi=fmi, values=values, binary=False))
    sigma = b / (2 * m)
    wn = math.sqrt(k / m)
    wd = math.sqrt(wn ** 2 - sigma ** 2)
    zeta = sigma / wn
    # stop: settling to 1 % (ln 100 / sigma = 46 s) or 20 periods (40 pi / wn = 25.1 s): 25.1 -> 50 s
    exp = root.find("DefaultExperiment")
    assert exp is not None
    assert float(exp.get("startTime")) == 0.0
    assert float(exp.get("stopTime")) == 50.0
    # step: 0.05 / wn = 0.01 s
    assert float(exp.get("stepSize")) == 0.01
    # periods of the fastest mode: 50 wn / 2 pi = 39.8 < 100: tolerance 1e-6
    assert float(exp.get("tolerance")) == 1e-6
    tag = "ScalarVariable" if fmi == 2 else "Float64"
    nominal = {}
    for v in root.iter(tag):
        el = v.find("Real") if fmi == 2 else v
        if el.get("nominal") is not None:
            nominal[v.get("name")] = float(el.get("nominal"))
    assert set(nominal) == {"p_m", "q_k"}
    q_peak = 1.0 / k * (1 + math.exp(-math.pi * zeta / math.sqrt(1 - zeta ** 2)))
    t_star = math.atan2(wd, sigma) / wd
    p_peak = m * 1.0 / (m * wd) * math.exp(-sigma * t_star) * math.sin(wd * t_star)
    assert nominal["q_k"] == pytest.approx(q_peak, rel=0.01)
    assert nominal["p_m"] == pytest.approx(p_peak, rel=0.01)
    # units: the model declares none, and the description claims none
    assert root.find("UnitDefinitions") is None
    assert not any(v.get("unit") for v in root.iter())


def _check_default_run(path, model, values, u):
    """fmpy with its defaults (ME) against bg.simulate; returns the worst relative error."""
    res = simulate_fmu(str(path), fmi_type="ModelExchange", start_values=u)
    t = res["time"]
    ref = bg.simulate(model, values, (0.0, float(t[-1])), None, u=[u[n] for n in model.input_names],
                      t_eval=t, method="DOP853", rtol=1e-10, atol=1e-15)
    worst = 0.0
    for name in model.output_names:
        want = ref[name]
        worst = max(worst, float(np.max(np.abs(res[name] - want)) / np.max(np.abs(want))))
    return worst, res


@pytest.mark.parametrize("fmi", [2, 3])
def test_flexcam_runs_with_fmpy_defaults(tmp_path, fmi):
    defn = bg.load_model(REPO / "models" / "flexcam.py")
    model = defn.derive()
    values = {p.name: defn.parameters[p.name] for p in model.parameters}
    path = export_fmu(defn, tmp_path / "flexcam.fmu", fmi=fmi, kind="me")
    md = fmpy.read_model_description(str(path))
    assert md.defaultExperiment is not None and md.defaultExperiment.stopTime is not None
    states = [v for v in md.modelVariables if v.name in model.state_names]
    assert len(states) == 6 and all(v.nominal is not None and float(v.nominal) < 0.1 for v in states)
    worst, res = _check_default_run(path, model, values, {"hub.e_in": 1.0})
    assert worst <= 1e-4
    # the run covers the slowest flexible mode's settling: it has decayed to a few % of its peak
    y = res["y"]
    tail = y[len(y) * 9 // 10:]
    assert np.ptp(tail) < 0.1 * np.ptp(y)


def test_hundred_cell_chain_runs_with_fmpy_defaults(tmp_path):
    model, values = chain(100)
    path = export_fmu(model, tmp_path / "chain.fmu", fmi=2, kind="me", values=values)
    worst, _ = _check_default_run(path, model, values, {"F": 1.0})
    assert worst <= 1e-4
