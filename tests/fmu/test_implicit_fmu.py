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
