"""FMUs of implicit models (issue 29), checked by fmpy.

A diode ``i = Is (exp(v/Vt) - 1)`` in series with a resistor, driven by a
5 V source, charges a capacitor; the loop current is an algebraic unknown
solved by the FMU's own Newton method.  For FMI 2 and 3:

* ``fmpy.validation.validate_fmu`` finds no problem, and the derivative
  depends on the state and the input (through the algebraic unknown);
* Model Exchange (fmpy's CVode, relative tolerance 1e-10) agrees with
  ``bg.simulate`` (DOP853, rtol 1e-12) to 1e-6 of each output's largest
  magnitude, and the current at the end with the independent solution:
  ``V - q/C = R i + v`` by :func:`scipy.optimize.brentq` on the hand-written
  residual, the state ``q`` taken from the reference run;
* Co-Simulation (the FMU's fixed-step RK4) agrees to 1e-6;
* the other two models of the issue agree with ``bg.simulate`` and their
  independent solutions the same way: two quadratic orifices in series
  between two accumulators (``Q = sqrt(dp / (1/K1^2 + 1/K2^2))``), and a
  driven mass whose ``tanh`` friction is in series with a viscous damper
  (the common force by ``brentq`` on ``Ff tanh(v_f/v0) = b (v - v_f)``);
* a law that cannot take the imposed effort (``Ff (tanh f + tanh^3 f) <=
  2 Ff`` driven by ``3 Ff``) makes the FMU return an error, and its logger
  message names the unknown ``f_fr`` and the element.
"""

import math
import shutil

import numpy as np
import pytest
import sympy
from scipy.optimize import brentq

import bondgraph as bg

fmpy = pytest.importorskip("fmpy")
from fmpy import read_model_description, simulate_fmu  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

from bondgraph.fmu import export_fmu  # noqa: E402

pytestmark = pytest.mark.skipif((shutil.which("cc") or shutil.which("gcc")) is None,
                                reason="no C compiler (cc) on PATH")
VALUES = {"C": 1e-6, "Is": 1e-12, "R": 1e3, "Vt": 0.025}
V, T_END = 5.0, 5e-3


def diode_rc() -> bg.Model:
    Is, Vt = sympy.symbols("Is Vt", positive=True)
    g = bg.BondGraph("diode_rc")
    g.add(bg.Se("V"), bg.One("s"), bg.R("R"), bg.R("D", inverse=Is * (sympy.exp(bg.e / Vt) - 1)),
          bg.C("C"))
    for t, h in [("V", "s"), ("s", "R"), ("s", "D"), ("s", "C")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"i": bg.flow("D"), "vd": bg.effort("D")})


def hand_current(q: float) -> float:
    C, Is, R, Vt = (VALUES[k] for k in ("C", "Is", "R", "Vt"))
    w = V - q / C
    v = brentq(lambda v: R * Is * math.expm1(v / Vt) + v - w, -abs(w) - 1, abs(w) + 1, xtol=1e-15)
    return Is * math.expm1(v / Vt)


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    folder = tmp_path_factory.mktemp("implicit_fmus")
    model = diode_rc()
    return model, {fmi: export_fmu(model, folder / f"diode_rc{fmi}.fmu", fmi=fmi, values=VALUES)
                   for fmi in (2, 3)}


@pytest.mark.parametrize("fmi", [2, 3])
def test_valid_with_dependencies_through_the_loop(fmus, fmi):
    model, paths = fmus
    assert validate_fmu(str(paths[fmi])) == []
    md = read_model_description(str(paths[fmi]))
    (der,) = md.derivatives
    assert sorted(d.name for d in der.dependencies) == ["V", "q_C"]
    assert set(der.dependenciesKind) == {"dependent"}
    outputs = {u.variable.name: sorted(d.name for d in u.dependencies) for u in md.outputs}
    assert outputs == {"i": ["V", "q_C"], "vd": ["V", "q_C"]}      # both only through f_D


@pytest.mark.parametrize("kind", ["ModelExchange", "CoSimulation"])
@pytest.mark.parametrize("fmi", [2, 3])
def test_simulation_matches_simulate_and_the_hand_solution(fmus, fmi, kind):
    model, paths = fmus
    res = simulate_fmu(str(paths[fmi]), fmi_type=kind, stop_time=T_END, output_interval=T_END / 100,
                       start_values={"V": V}, relative_tolerance=1e-10)
    ref = bg.simulate(model, VALUES, (0.0, T_END), {"q_C": 0.0}, u=[V], t_eval=res["time"],
                      method="DOP853", rtol=1e-12, atol=1e-16)
    for name in ("i", "vd"):
        err = np.max(np.abs(res[name] - ref[name])) / np.max(np.abs(ref[name]))
        assert err <= 1e-6, f"{name}: relative error {err:.3g}"
    # the capacitor charges through the forward-biased diode: the current falls, v_d stays ~0.45 V
    assert res["i"][-1] == pytest.approx(hand_current(ref["q_C"][-1]), rel=1e-5)
    assert 0.4 < res["vd"][-1] < 0.6 and res["i"][-1] < 0.05 * res["i"][1]


def orifices() -> bg.Model:
    K1, K2 = sympy.symbols("K1 K2", positive=True)
    g = bg.BondGraph("pipes")
    g.add(bg.C("A1"), bg.Zero("n1"), bg.One("s"), bg.R("o1", law=bg.f * abs(bg.f) / K1**2),
          bg.R("o2", law=bg.f * abs(bg.f) / K2**2), bg.Zero("n2"), bg.C("A2"))
    for t, h in [("n1", "A1"), ("n1", "s"), ("s", "o1"), ("s", "o2"), ("s", "n2"), ("n2", "A2")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"Q": bg.flow("o1")})


def pipes_hand(x, values):
    dp = x["q_A1"] / values["A1"] - x["q_A2"] / values["A2"]
    return math.copysign(math.sqrt(abs(dp) / (1 / values["K1"]**2 + 1 / values["K2"]**2)), dp)


def friction() -> bg.Model:
    Ff, v0 = sympy.symbols("Ff v0", positive=True)
    g = bg.BondGraph("drive")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.Zero("c"),
          bg.R("fr", law=Ff * sympy.tanh(bg.f / v0)), bg.R("b"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "c"), ("c", "fr"), ("c", "b")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"force": bg.effort("b")})


def friction_hand(x, values):
    Ff, v0, b = values["Ff"], values["v0"], values["b"]
    v = x["p_m"] / values["m"]
    vf = brentq(lambda w: Ff * math.tanh(w / v0) - b * (v - w), -abs(v) - 1, abs(v) + 1, xtol=1e-15)
    return b * (v - vf)


OTHERS = {  # model, values, start, inputs, stop time, output, hand solution of the output
    "pipes": (orifices, {"A1": 2.0, "A2": 0.5, "K1": 3.0, "K2": 4.0}, {"q_A1": 10.0}, {}, 0.5,
              "Q", pipes_hand),
    "drive": (friction, {"m": 2.0, "Ff": 1.5, "v0": 0.1, "b": 3.0}, {"p_m": 0.5}, {"F": 2.0}, 4.0,
              "force", friction_hand),
}


@pytest.mark.parametrize("case, fmi", [("pipes", 3), ("drive", 2)])
def test_orifices_and_friction_match_simulate_and_hand_solutions(tmp_path, case, fmi):
    build, values, x0, u, t_end, out, hand_out = OTHERS[case]
    model = build()
    assert model.algebraic
    path = export_fmu(model, tmp_path / f"{case}.fmu", fmi=fmi, values=values)
    assert validate_fmu(str(path)) == []
    for kind in ("ModelExchange", "CoSimulation"):
        res = simulate_fmu(str(path), fmi_type=kind, stop_time=t_end, output_interval=t_end / 50,
                           start_values={**u, **x0}, relative_tolerance=1e-10)
        ref = bg.simulate(model, values, (0.0, t_end), x0, u=[u[n] for n in model.input_names],
                          t_eval=res["time"], method="DOP853", rtol=1e-12, atol=1e-14)
        err = np.max(np.abs(res[out] - ref[out])) / np.max(np.abs(ref[out]))
        assert err <= 1e-6, f"{case} {kind}: relative error {err:.3g}"
        states = {name: ref[name][-1] for name in model.state_names}
        assert res[out][-1] == pytest.approx(hand_out(states, values), rel=1e-6)


@pytest.mark.parametrize("fmi", [2, 3])
def test_newton_failure_is_an_error_logged_naming_the_unknown(tmp_path, fmi):
    Ff = sympy.Symbol("Ff", positive=True)
    g = bg.BondGraph("sat")
    g.add(bg.Se("F"), bg.Zero("n"), bg.R("fr", law=Ff * (sympy.tanh(bg.f) + sympy.tanh(bg.f)**3)),
          bg.One("j"), bg.I("m"))
    for t, h in [("F", "n"), ("n", "fr"), ("n", "j"), ("j", "m")]:
        g.connect(t, h)
    path = export_fmu(bg.derive(g, outputs={"f": bg.flow("fr")}), tmp_path / "sat.fmu", fmi=fmi,
                      values={"Ff": 1.0})
    messages = []
    with pytest.raises(Exception, match="failed with status 3"):
        simulate_fmu(str(path), fmi_type="ModelExchange", stop_time=1.0, start_values={"F": 3.0},
                     logger=lambda *args: messages.append(args[-1].decode()))
    assert any("f_fr (the flow of R:fr" in m and "no solution" in m and m.startswith("at t = 0")
               for m in messages), messages
    # solvable below 2 Ff: the flow is artanh(s), s^3 + s = 1
    res = simulate_fmu(str(path), fmi_type="CoSimulation", stop_time=0.1, start_values={"F": 1.0})
    s = [r.real for r in np.roots([1, 0, 1, -1]) if abs(r.imag) < 1e-12][0]
    assert res["f"][-1] == pytest.approx(np.arctanh(s), rel=1e-12)


def test_fmu_state_carries_the_warm_start(fmus):
    """A serialized FMU state holds the Newton warm start: the run after restoring it repeats
    the run after saving it bit for bit (FMI 2, Co-Simulation)."""
    from fmpy import extract, instantiate_fmu

    _, paths = fmus
    md = read_model_description(str(paths[2]))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = instantiate_fmu(extract(str(paths[2])), md, fmi_type="CoSimulation")
    fmu.setupExperiment(startTime=0.0)
    fmu.setReal([vr["V"]], [V])
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    fmu.doStep(0.0, 1e-3)
    blob = fmu.serializeFMUstate(fmu.getFMUstate())
    fmu.doStep(1e-3, 1e-3)
    first = fmu.getReal([vr["q_C"], vr["i"], vr["vd"]])
    fmu.setReal([vr["V"]], [-V])           # elsewhere: the warm start moves far away
    fmu.doStep(2e-3, 1e-3)
    restored = fmu.deSerializeFMUstate(blob)
    fmu.setFMUstate(restored)
    fmu.freeFMUstate(restored)
    fmu.doStep(1e-3, 1e-3)
    assert fmu.getReal([vr["q_C"], vr["i"], vr["vd"]]) == first
    assert first[1] == pytest.approx(hand_current(first[0]), rel=1e-9)
    fmu.terminate()
    fmu.freeInstance()
