"""Plots: Figures with the right axes and lines, and the plotted data right.

Expected values are closed forms: |1/(jw+1)| at w=1 is 1/sqrt(2) (-3.0103 dB)
with phase -45 deg; the step response of 1/(s+1) is 1 - exp(-t), its impulse
response exp(-t); poles are the roots of the denominator.
"""

from __future__ import annotations

import control
import numpy as np
import pytest
from matplotlib.figure import Figure

from bondgraph.drawing.plots import PlotError, bode, frf_overlay, impulse, pole_zero, step

FIRST = control.tf([1], [1, 1])
DB_3 = 20 * np.log10(1 / np.sqrt(2))   # -3.0103 dB


def test_bode_first_order_at_corner_from_plotted_data():
    fig = bode(FIRST)
    assert isinstance(fig, Figure) and len(fig.axes) == 2
    mag_ax, ph_ax = fig.axes
    assert len(mag_ax.lines) == len(ph_ax.lines) == 1
    w, mag = mag_ax.lines[0].get_xdata(), mag_ax.lines[0].get_ydata()
    assert w[0] < 1 < w[-1]                  # the default range holds the corner
    at_1 = np.interp(0.0, np.log10(w), mag)
    assert at_1 == pytest.approx(DB_3, abs=0.01)
    assert np.interp(0.0, np.log10(w), ph_ax.lines[0].get_ydata()) == pytest.approx(-45, abs=0.1)


def test_bode_exact_point_and_hz_axis():
    omega = np.array([0.5, 1.0, 2.0])
    fig = bode(FIRST, omega=omega, hz=True)
    line = fig.axes[0].lines[0]
    assert np.allclose(line.get_xdata(), omega / (2 * np.pi))
    assert line.get_ydata()[1] == pytest.approx(DB_3, abs=1e-9)
    assert fig.axes[1].get_xlabel() == "Frequency [Hz]"


def test_bode_accepts_pairs_callables_and_several_systems():
    omega = np.logspace(-1, 1, 7)
    fig = bode([FIRST, ([1], [1, 1]), lambda s: 1 / (s + 1)], omega=omega,
               labels=["tf", "pair", "callable"])
    mag_ax, ph_ax = fig.axes
    assert len(mag_ax.lines) == len(ph_ax.lines) == 3
    ref = 20 * np.log10(np.abs(1 / (1j * omega + 1)))
    for ln in mag_ax.lines:
        np.testing.assert_allclose(ln.get_xdata(), omega)
        np.testing.assert_allclose(ln.get_ydata(), ref, rtol=0, atol=1e-9)
    assert [t.get_text() for t in mag_ax.get_legend().get_texts()] == ["tf", "pair", "callable"]


def test_bode_phase_is_unwrapped():
    third = control.tf([1], [1, 3, 3, 1])    # (s+1)^-3: phase to -270 deg
    ph = bode(third, omega=np.logspace(-2, 3, 200)).axes[1].lines[0].get_ydata()
    assert ph[-1] == pytest.approx(-270, abs=1.0)
    assert np.all(np.diff(ph) < 1e-9)


@pytest.mark.parametrize("bad, match", [
    ([], "empty"),
    ("tf", "expected a python-control system"),
], ids=["empty", "string"])
def test_bode_bad_input(bad, match):
    with pytest.raises(PlotError, match=match):
        bode(bad)


def test_bode_label_count_and_mimo_are_errors():
    with pytest.raises(PlotError, match="labels"):
        bode([FIRST, FIRST], labels=["one"])
    mimo = control.ss([[-1]], [[1, 1]], [[1]], [[0, 0]])
    with pytest.raises(PlotError, match="select a channel"):
        bode(mimo)
    with pytest.raises(PlotError, match="positive"):
        bode(FIRST, omega=[0.0, 1.0])


def test_pole_zero_markers_are_the_roots():
    num, den = [1, 2], [1, 2, 5]
    ax = pole_zero(control.tf(num, den)).axes[0]
    lines = {ln.get_label().split()[0]: ln for ln in ax.lines}
    assert set(lines) == {"poles", "zeros", "imaginary"}
    poles = lines["poles"].get_xdata() + 1j * lines["poles"].get_ydata()
    assert np.allclose(np.sort_complex(poles), np.sort_complex(np.roots(den)))
    assert np.allclose(lines["zeros"].get_xdata(), [-2.0])


def test_pole_zero_discrete_draws_the_unit_circle():
    ax = pole_zero(control.tf([1], [1, -0.5], 0.1)).axes[0]
    labels = [ln.get_label() for ln in ax.lines]
    assert "unit circle" in labels
    assert labels[1] == "zeros (0)"


def test_step_first_order():
    fig = step(FIRST, T=np.linspace(0, 5, 101))
    assert len(fig.axes) == 1 and len(fig.axes[0].lines) == 1
    t, y = fig.axes[0].lines[0].get_data()
    assert np.allclose(y, 1 - np.exp(-t), atol=1e-3)


def test_impulse_first_order():
    fig = impulse(([1], [1, 1]), T=np.linspace(0, 5, 101))
    t, y = fig.axes[0].lines[0].get_data()
    assert np.allclose(y, np.exp(-t), atol=1e-3)


def test_step_mimo_has_one_axis_per_channel_named():
    A = [[0, 1], [-4, -0.4]]
    sys = control.ss(A, [[0, 0], [1, 2]], np.eye(2), np.zeros((2, 2)),
                     inputs=["F", "T"], outputs=["x", "v"])
    fig = step(sys, T=10.0)
    assert len(fig.axes) == 4
    assert all(len(ax.lines) == 1 for ax in fig.axes)
    assert [ax.get_title() for ax in fig.axes] == ["F \u2192 x", "T \u2192 x", "F \u2192 v", "T \u2192 v"]
    # DC gains: x = u/4 per unit force, 2/4 per unit torque
    assert fig.axes[0].lines[0].get_ydata()[-1] == pytest.approx(0.25, abs=0.02)
    assert fig.axes[1].lines[0].get_ydata()[-1] == pytest.approx(0.5, abs=0.04)


def test_frf_overlay_measured_model_and_coherence():
    f = np.linspace(0.0, 5.0, 101)               # with the 0 Hz bin of a Welch estimate
    sys = control.tf([100], [1, 2, 100])
    H = np.asarray(sys(2j * np.pi * f[1:]))
    H = np.concatenate([[1.0 + 0j], H])
    coh = np.linspace(1.0, 0.5, f.size)
    fig = frf_overlay(f, H, coh, sys)
    assert len(fig.axes) == 3
    mag, ph, co = fig.axes
    assert len(mag.lines) == len(ph.lines) == 2 and len(co.lines) == 1
    assert mag.lines[0].get_xdata()[0] > 0        # 0 Hz left out
    assert np.allclose(mag.lines[0].get_ydata(), mag.lines[1].get_ydata())
    assert np.allclose(ph.lines[0].get_ydata(), ph.lines[1].get_ydata())
    assert np.allclose(co.lines[0].get_ydata(), coh[1:])
    assert co.get_ylim()[1] <= 1.1


def test_frf_overlay_without_coherence_or_model():
    f = np.linspace(0.1, 1, 10)
    fig = frf_overlay(f, 1 / (2j * np.pi * f + 1))
    assert len(fig.axes) == 2 and [len(ax.lines) for ax in fig.axes] == [1, 1]
    with pytest.raises(PlotError, match="one value per frequency"):
        frf_overlay(f, np.ones(3))
