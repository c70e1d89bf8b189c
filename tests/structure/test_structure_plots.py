"""Plots of the structural results: what is drawn is what the physics says.

* the pinned-free beam: the node markers of mode 2 sit at the roots of the
  mode shape ``sin(b x) + (sin(b L)/sinh(b L)) sinh(b x)`` (``tan l = tanh l``),
  found here by :func:`scipy.optimize.brentq`;
* the position sweep: a sweep written by hand (zeros with real parts
  -1, -1, 1, 1, -1 at x = 0..4) shades exactly [1.5, 3.5];
* the pole-zero map of a mass on a spring, force to velocity:
  ``v/F = s / (m s^2 + k)``, poles ``+-j sqrt(k/m)``, one zero at 0.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.optimize

import bondgraph as bg
from bondgraph.beam import modal_beam
from bondgraph.structure import PositionSweep, StructureError, sensor_placement, zero_structure

L = 1.5


def _nodes_mode_two() -> list[float]:
    f = lambda lam: np.sin(lam) * np.cosh(lam) - np.cos(lam) * np.sinh(lam)  # noqa: E731
    lam = scipy.optimize.brentq(f, 2.25 * np.pi - 0.5, 2.25 * np.pi + 0.5)
    b = lam / L
    phi = lambda x: np.sin(b * x) + np.sin(lam) / np.sinh(lam) * np.sinh(b * x)  # noqa: E731
    xs = np.linspace(1e-6, L, 4001)
    v = phi(xs)
    return [scipy.optimize.brentq(phi, a, c) for a, c, fa, fc in
            zip(xs[:-1], xs[1:], v[:-1], v[1:]) if fa * fc < 0]


def test_placement_plot_marks_the_nodes_of_mode_two():
    sp = sensor_placement(modal_beam(2.0, 0.5, L, 3, boundary="pinned-free"))
    ax = sp.plot().axes[0]
    markers = [ln for ln in ax.lines if ln.get_label() == "_nodes of mode 2"]
    assert len(markers) == 1
    np.testing.assert_allclose(markers[0].get_xdata(), _nodes_mode_two(), rtol=1e-9)
    np.testing.assert_allclose(markers[0].get_ydata(), 0.0)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["mode 1", "mode 2", "mode 3"]


def test_sweep_plot_shades_the_non_minimum_phase_positions():
    re = [-1.0, -1.0, 1.0, 1.0, -1.0]
    sweep = PositionSweep(input="tau", positions=(0.0, 1.0, 2.0, 3.0, 4.0),
                          zeros=tuple(((r + 2j), (r - 2j), (-5 + 0j)) for r in re),
                          nonminimum_phase=tuple(r > 0 for r in re))
    fig = sweep.plot()
    top, bottom = fig.axes
    np.testing.assert_allclose(top.lines[0].get_ydata(), re)
    spans = [p for p in top.patches]
    assert len(spans) == 1
    x0, x1 = spans[0].get_x(), spans[0].get_x() + spans[0].get_width()
    assert (x0, x1) == pytest.approx((1.5, 3.5))
    assert sorted(set(np.round(bottom.lines[0].get_ydata(), 12))) == [0.0, 2.0]


def test_pole_zero_plot_of_a_collocated_mass_spring():
    g = bg.BondGraph("ms")
    v = bg.One("v")
    g.add(bg.Se("F"), v, bg.I("m"), bg.C("k", stiffness="k"))
    for t, h in [("F", v), (v, "m"), (v, "k")]:
        g.connect(t, h)
    z = zero_structure(bg.derive(g, outputs={"v": bg.flow("m")}))
    m, k = 2.0, 8.0
    ax = z.plot({"m": m, "k": k}).axes[0]
    poles, zeros = ax.lines[0], ax.lines[1]
    w = np.sqrt(k / m)
    np.testing.assert_allclose(sorted(poles.get_ydata()), [-w, w], rtol=1e-12)
    np.testing.assert_allclose(poles.get_xdata(), 0.0, atol=1e-12)
    np.testing.assert_allclose(zeros.get_xdata(), [0.0], atol=1e-12)
    with pytest.raises(StructureError, match="values"):
        z.plot({})
