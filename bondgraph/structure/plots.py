"""Plots of the structural results: sensor gains along a beam, the position sweep, poles
and zeros.

Each function returns a new :class:`matplotlib.figure.Figure` (no pyplot, no
global state); matplotlib is imported only when a plot is asked for, so
``import bondgraph`` stays free of it.  The result objects call these from
their ``plot`` methods.

Examples
--------
>>> from bondgraph.beam import modal_beam
>>> from bondgraph.structure import sensor_placement
>>> sp = sensor_placement(modal_beam(1.0, 1.0, 1.0, 2, boundary="pinned-free"))
>>> fig = sp.plot()
>>> fig.axes[0].get_xlabel(), [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
('position x', ['mode 1', 'mode 2'])
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping, Optional

import numpy as np

from ._generic import StructureError

if TYPE_CHECKING:      # pragma: no cover
    from matplotlib.figure import Figure

# the results (SensorPlacement, PositionSweep, ZeroStructure) call these from their plot
# methods; they are typed Any here so that this module imports none of theirs (no circle)

__all__ = ["plot_placement", "plot_sweep", "plot_pole_zero"]


def _figure(rows: int = 1, height: float = 3.2) -> "Figure":
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, height * rows), layout="constrained")
    fig.subplots(rows, 1, sharex=True, squeeze=False)
    return fig


def plot_placement(sp: Any) -> "Figure":
    """The gain of each mode along the beam, its nodes marked (a sensor there does not see it).

    One line per mode (``gains`` normalised by the mode's largest gain), a
    marker at each node.
    """
    fig = _figure()
    ax = fig.axes[0]
    x = np.asarray(sp.positions)
    g = np.asarray(sp.gains)
    peak = np.max(np.abs(g), axis=0)
    peak[peak == 0] = 1.0
    for i, m in enumerate(sp.modes):
        (line,) = ax.plot(x, g[:, i] / peak[i], label=f"mode {m}")
        if sp.nodes[i]:
            ax.plot(sp.nodes[i], np.zeros(len(sp.nodes[i])), "o", color=line.get_color(),
                    markerfacecolor="none", label=f"_nodes of mode {m}")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("position x")
    ax.set_ylabel(f"{sp.kind} gain (normalised)")
    ax.set_title(f"{sp.kind} sensor along the beam: a mode is unseen at its nodes (o)")
    ax.legend(loc="best", fontsize="small")
    return fig


def plot_sweep(sweep: Any, placement: Optional[Any] = None
               ) -> "Figure":
    """The zeros of ``sensor(x)/input`` along the beam; non-minimum-phase positions shaded.

    Top: the largest real part of the zeros at each position (above 0:
    non-minimum-phase).  Bottom: the frequencies ``|Im z|`` of the zeros, and
    the nodes of ``placement`` (where a zero cancels a pole) as vertical lines.
    """
    fig = _figure(2, 2.8)
    top, bottom = fig.axes
    x = np.asarray(sweep.positions)
    re = np.array([max((z.real for z in zs), default=np.nan) for zs in sweep.zeros])
    top.plot(x, re, color="C0", label="largest Re(zero)")
    top.axhline(0.0, color="0.6", lw=0.6)
    flags = np.asarray(sweep.nonminimum_phase, dtype=bool)
    for k, (a, b) in enumerate(_runs(x, flags)):
        for ax in (top, bottom):
            ax.axvspan(a, b, color="C3", alpha=0.15, lw=0,
                       label="non-minimum-phase" if ax is top and k == 0 else None)
    top.set_ylabel("Re(zero)")
    top.set_title(f"zeros of the sensor output / {sweep.input} along the beam")
    top.legend(loc="best", fontsize="small")
    xs = [xi for xi, zs in zip(x, sweep.zeros) for _ in zs]
    ws = [abs(z.imag) for zs in sweep.zeros for z in zs]
    bottom.plot(xs, ws, ".", ms=2, color="C0")
    if placement is not None:
        for i, nodes in enumerate(placement.nodes):
            for xn in nodes:
                bottom.axvline(xn, color=f"C{i + 1}", lw=0.8, ls="--")
    bottom.set_yscale("symlog", linthresh=1.0)
    bottom.set_xlabel("position x")
    bottom.set_ylabel("|Im(zero)| [rad/s]")
    return fig


def _runs(x: np.ndarray, flags: np.ndarray) -> list[tuple[float, float]]:
    """Intervals of ``x`` over which ``flags`` holds (half a step past each end)."""
    out = []
    i = 0
    n = len(x)
    while i < n:
        if flags[i]:
            j = i
            while j + 1 < n and flags[j + 1]:
                j += 1
            lo = x[i] - (x[i] - x[i - 1]) / 2 if i > 0 else x[i]
            hi = x[j] + (x[j + 1] - x[j]) / 2 if j + 1 < n else x[j]
            out.append((float(lo), float(hi)))
            i = j + 1
        else:
            i += 1
    return out


def plot_pole_zero(zs: Any, values: Mapping[str, float]) -> "Figure":
    """Poles (x) and invariant zeros (o) of the pair at parameter ``values``."""
    if not values and zs.n:
        raise StructureError("plot: give the parameter values of the poles and zeros")
    fig = _figure(1, 4.0)
    ax = fig.axes[0]
    p = zs.poles_at(values)
    z = zs.zeros_at(values)
    ax.plot(p.real, p.imag, "x", ms=8, color="C3", label="poles")
    ax.plot(z.real, z.imag, "o", ms=7, markerfacecolor="none", color="C0", label="zeros")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.axvline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("Re")
    ax.set_ylabel("Im")
    ax.set_title(f"{zs.output}/{zs.input}: relative degree {zs.relative_degree}")
    ax.legend(loc="best", fontsize="small")
    return fig
