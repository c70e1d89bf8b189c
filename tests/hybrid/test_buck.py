"""Buck converter: the averaged duty-to-output TF and the switched ripple against the textbook."""

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.hybrid import Mode, ModeError, SwitchedModel, library, simulate

Vin, L, C, R = sympy.symbols("Vin L C R", positive=True)
s = sympy.Symbol("s")
ON = Mode(on={"S"}, off={"D"})
OFF = Mode(on={"D"}, off={"S"})


def _plain(expr):
    return expr.xreplace({x: sympy.Symbol(x.name) for x in expr.free_symbols})


@pytest.fixture(scope="module")
def buck():
    return SwitchedModel(library.buck(), outputs={"v": bg.effort("C"), "iL": bg.flow("L")})


def test_averaged_duty_to_output_transfer_function(buck):
    avg = buck.average("d", active=ON, passive=OFF)
    G = avg.transfer_function("d", "v").expr
    # textbook (Erickson and Maksimovic, ideal buck in CCM): Gvd = Vin/(L C s^2 + (L/R) s + 1)
    textbook = Vin / (L * C * s ** 2 + (L / R) * s + 1)
    assert sympy.simplify(_plain(G) - _plain(textbook)) == 0
    assert avg.input_names == ("d",)


def test_averaged_equilibrium_and_linearization(buck):
    avg = buck.average("d", active=ON, passive=OFF)
    vals = {"Vin": 12.0, "L": 1e-4, "C": 1e-4, "R": 4.0}
    eq = avg.equilibrium(vals, {"d": 0.25})
    # averaged steady state: v = d Vin, iL = v/R
    assert eq.states["q_C"] == pytest.approx(1e-4 * 3.0)
    assert eq.states["p_L"] == pytest.approx(1e-4 * 0.75)
    lin = avg.linearize(eq)
    A, B = np.asarray(lin.A, float), np.asarray(lin.B, float)
    Cm, D = np.asarray(lin.C, float), np.asarray(lin.D, float)
    row, col = list(lin.output_names).index("v"), list(lin.input_names).index("d")
    for w in (0.0, 1e3, 5e4):
        sv = 1j * w
        G = (Cm @ np.linalg.solve(sv * np.eye(len(A)) - A, B) + D)[row, col]
        assert G == pytest.approx(12.0 / (1e-8 * sv ** 2 + 2.5e-5 * sv + 1), rel=1e-9)


def test_averaging_refuses_modes_with_different_states(buck):
    with pytest.raises(ModeError, match="states differ"):
        buck.average("d", active=ON, passive=Mode(off={"S", "D"}))
    with pytest.raises(ModeError, match="duty name 'L' is already"):
        buck.average("L", active=ON, passive=OFF)


def test_switched_mean_and_ripple_against_the_averaged_model(buck):
    vin, d, T, Lv, Cv, Rv = 10.0, 0.5, 1e-5, 1e-4, 1e-4, 5.0
    vals = {"Vin": vin, "duty": d, "T": T, "L": Lv, "C": Cv, "R": Rv}
    # start on the periodic steady state of the ideal converter: at the start of the on-time
    # the inductor current is its mean d Vin/R less half its ripple Vin (1-d) d T/L
    i0 = d * vin / Rv - vin * (1 - d) * d * T / Lv / 2
    grid = np.linspace(30 * T, 40 * T, 2001)
    res = simulate(buck, (0, 40 * T), {"p_L": Lv * i0, "q_C": Cv * d * vin}, values=vals,
                   t_eval=grid)
    keep = res.t >= 30 * T
    t, v = res.t[keep], res.outputs["v"][keep]
    mean = np.trapezoid(v, t) / (t[-1] - t[0])
    assert mean == pytest.approx(d * vin, rel=1e-3)                   # averaged equilibrium
    ripple = v.max() - v.min()
    textbook = vin * (1 - d) * d * T ** 2 / (8 * Lv * Cv)             # small-ripple formula
    assert ripple == pytest.approx(textbook, rel=0.05)
    # continuous conduction: only the two averaged modes are visited, without any loss
    assert {str(m) for m in res.modes} == {"D off, S on", "D on, S off"}
    assert res.energy_loss == 0
    on_times = res.event_times("S")
    assert np.diff(on_times[on_times < 30 * T]) == pytest.approx(d * T, rel=1e-6)
