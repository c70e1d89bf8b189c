"""Sensor placement on a modal beam: which modes a sensor at ``x`` sees.

In the modal bond graph of a beam (:mod:`bondgraph.beam.fragment`) a sensor at
position ``x`` reads ``y = sum_i g_i(x) q_i`` from the modal displacements
``q_i`` (the states of the modal springs ``C:k_i``), with the gain

* ``phi_i(x)`` for a deflection sensor (a camera, a laser),
* ``phi_i'(x)`` for a slope sensor (an inclinometer),
* ``phi_i''(x)`` for a strain gauge (surface strain ``(h/2) w''``).

The causal path from mode ``i``'s storage elements to the sensor goes through
that gain: where ``g_i(x) = 0`` (a node of mode ``i`` for that quantity) the
path is cut, mode ``i`` is unobservable, and in the transfer function its
poles cancel against zeros (Miu 1991).  :func:`sensor_placement` tabulates the
gains over positions and finds the nodes (roots of the gain between sample
points, by :func:`scipy.optimize.brentq`); :func:`position_sweep` follows the
zeros of the transfer function from an input to the sensor along the beam and
says where it turns non-minimum-phase.

Examples
--------
>>> from bondgraph.beam import modal_beam
>>> from bondgraph.structure import sensor_placement
>>> beam = modal_beam(1.0, 1.0, 1.0, 3, boundary="pinned-free")
>>> sp = sensor_placement(beam)
>>> [round(x, 4) for x in sp.nodes[1]]          # nodes of mode 2 along (0, L]
[0.4464, 0.8531]
>>> sp.observed_at(sp.nodes[1][0])              # a camera there does not see mode 2
(1, 3)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping, Optional, Sequence

import numpy as np
import scipy.linalg
import scipy.optimize

from ..model import Model
from ._generic import StructureError

__all__ = ["SensorPlacement", "sensor_placement", "PositionSweep", "position_sweep"]

_DERIVATIVE = {"deflection": 0, "slope": 1, "strain": 2}


@dataclass(frozen=True)
class SensorPlacement:
    """Modal gains of a sensor along a beam, and the nodes of each mode (immutable).

    Attributes
    ----------
    kind : {"deflection", "slope", "strain"}
    length : float
    modes : tuple of int
        Mode numbers (1 = first flexible mode).
    positions : tuple of float
        Sample positions.
    gains : tuple of tuple of float
        ``gains[k][i]``: gain of mode ``modes[i]`` at ``positions[k]``.
    nodes : tuple of tuple of float
        Per mode, the positions in ``(0, L]`` where its gain vanishes.
    tol : float
        A gain below ``tol`` times the mode's largest gain counts as zero.
    """

    kind: str
    length: float
    modes: tuple[int, ...]
    positions: tuple[float, ...]
    gains: tuple[tuple[float, ...], ...]
    nodes: tuple[tuple[float, ...], ...]
    tol: float
    _beam: Any = None

    def gain(self, x: float) -> tuple[float, ...]:
        """The gain of every mode at ``x``."""
        d = _DERIVATIVE[self.kind]
        return tuple(float(m.shape(x, d)) for m in self._beam.modes)

    def observed_at(self, x: float) -> tuple[int, ...]:
        """The modes a sensor at ``x`` observes (gain above ``tol`` of the mode's largest)."""
        g = self.gain(x)
        peak = np.max(np.abs(np.array(self.gains)), axis=0)
        return tuple(m for m, gi, p in zip(self.modes, g, peak) if abs(gi) > self.tol * p)

    def plot(self):
        """The gains along the beam with the nodes marked
        (:func:`bondgraph.structure.plots.plot_placement`); a matplotlib Figure."""
        from .plots import plot_placement

        return plot_placement(self)

    def __str__(self) -> str:
        lines = [f"{self.kind} sensor along a beam of length {self.length:g}: nodes (mode unseen)"]
        for m, xs in zip(self.modes, self.nodes):
            lines.append(f"  mode {m}: " + (", ".join(f"x = {x:.6g}" for x in xs) or "none"))
        return "\n".join(lines)


def sensor_placement(beam, positions: Optional[Sequence[float]] = None, *,
                     kind: str = "deflection", tol: float = 1e-6) -> SensorPlacement:
    """Gains of a sensor along a :class:`~bondgraph.beam.ModalBeam` and the nodes of its modes.

    Parameters
    ----------
    beam : ModalBeam
    positions : sequence of float, optional
        Sample positions (default 401 points over ``[0, L]``); nodes are
        searched between consecutive samples of a 2,001-point grid.
    kind : {"deflection", "slope", "strain"}
    tol : float

    Returns
    -------
    SensorPlacement

    Raises
    ------
    StructureError
        Unknown ``kind`` or a position outside ``[0, L]``.
    """
    if kind not in _DERIVATIVE:
        raise StructureError(f"kind: expected one of {', '.join(_DERIVATIVE)}, got {kind!r}")
    L = float(beam.length) if hasattr(beam, "length") else float(beam.L)
    pos = np.linspace(0.0, L, 401) if positions is None else np.asarray(positions, float)
    if np.any(pos < 0) or np.any(pos > L * (1 + 1e-12)):
        raise StructureError(f"positions: expected values in [0, {L:g}]")
    d = _DERIVATIVE[kind]
    gains = np.array([[float(m.shape(x, d)) for m in beam.modes] for x in pos])
    grid = np.linspace(0.0, L, 2001)
    nodes = []
    for m in beam.modes:
        f = lambda x, m=m: float(m.shape(x, d))  # noqa: E731
        vals = np.array([f(x) for x in grid])
        scale = np.max(np.abs(vals)) or 1.0
        found = []
        for a, b, fa, fb in zip(grid[:-1], grid[1:], vals[:-1], vals[1:]):
            if a == 0.0 and abs(fa) <= 1e-12 * scale:
                continue                       # the root itself (pinned or clamped end)
            if fa == 0.0:
                found.append(float(a))
            elif fa * fb < 0:
                found.append(float(scipy.optimize.brentq(f, a, b, xtol=1e-14, rtol=1e-14)))
        if abs(vals[-1]) <= 1e-12 * scale:
            found.append(float(grid[-1]))
        nodes.append(tuple(found))
    return SensorPlacement(kind=kind, length=L, modes=tuple(m.number for m in beam.modes),
                           positions=tuple(float(x) for x in pos),
                           gains=tuple(tuple(float(g) for g in row) for row in gains),
                           nodes=tuple(nodes), tol=tol, _beam=beam)


@dataclass(frozen=True)
class PositionSweep:
    """Zeros of ``sensor(x)/input`` along a beam (immutable).

    Attributes
    ----------
    input : str
    positions : tuple of float
    zeros : tuple of tuple of complex
        Invariant zeros at each position.
    nonminimum_phase : tuple of bool
        A zero in the right half plane at that position.
    """

    input: str
    positions: tuple[float, ...]
    zeros: tuple[tuple[complex, ...], ...]
    nonminimum_phase: tuple[bool, ...]

    @property
    def first_nonminimum_phase(self) -> Optional[float]:
        """The first position (from the root) where the pair is non-minimum-phase."""
        return next((x for x, f in zip(self.positions, self.nonminimum_phase) if f), None)

    def plot(self, placement: Optional[SensorPlacement] = None):
        """The zeros along the beam, non-minimum-phase positions shaded, the nodes of
        ``placement`` marked (:func:`bondgraph.structure.plots.plot_sweep`)."""
        from .plots import plot_sweep

        return plot_sweep(self, placement)

    def __str__(self) -> str:
        x = self.first_nonminimum_phase
        where = "nowhere" if x is None else f"from x = {x:.4g}"
        return (f"sensor along the beam driven by {self.input}: {len(self.positions)} positions, "
                f"non-minimum-phase {where}")


def position_sweep(model: Model, input: str, modal_outputs: Sequence[str],
                   gains: Sequence[Sequence[float]], positions: Sequence[float],
                   values: Mapping[str, float], *, tol: float = 1e-7) -> PositionSweep:
    """Zeros of ``y(x)/input`` with ``y(x) = sum_i gains[x][i] * modal_outputs[i]``.

    ``modal_outputs`` are outputs of ``model`` that read the modal
    displacements (``bg.displacement('link.k_1')``, ...); the sensor output at
    each position is their combination with that position's gains (from
    :func:`sensor_placement`), and the zeros come from the Rosenbrock pencil
    at ``values``.

    Raises
    ------
    StructureError
        Unknown output names, or gains that do not match the outputs.
    """
    from ._generic import linear_form

    lf = linear_form(model)
    idx = []
    for name in modal_outputs:
        if name not in lf.outputs:
            raise StructureError(f"model {model.name!r} has no output {name!r}")
        idx.append(lf.outputs.index(name))
    gains = [list(map(float, g)) for g in gains]
    if any(len(g) != len(idx) for g in gains) or len(gains) != len(positions):
        raise StructureError("gains: expected one row per position, one gain per modal output")
    if len(lf.Bs) > 1 or len(lf.Ds) > 1:
        raise StructureError(f"model {model.name!r}: input derivatives are not supported here")
    j = lf.inputs.index(input) if input in lf.inputs else None
    if j is None:
        raise StructureError(f"model {model.name!r} has no input {input!r}")
    sub = {s: values[s.name] for s in lf.parameters if s.name in values}
    missing = sorted(s.name for s in lf.parameters if s.name not in values)
    if missing:
        raise StructureError(f"values: missing {', '.join(missing)}")
    A = np.array(lf.A.xreplace(sub).evalf(), dtype=float)
    b = np.array(lf.Bs[0][:, j].xreplace(sub).evalf(), dtype=float)
    Cm = np.array(lf.C[idx, :].xreplace(sub).evalf(), dtype=float)
    Dm = np.array(lf.Ds[0][idx, j].xreplace(sub).evalf(), dtype=float)
    n = A.shape[0]
    zs, flags = [], []
    for g in gains:
        c = np.asarray(g) @ Cm
        d = float(np.asarray(g) @ Dm.ravel())
        M = np.block([[A, b], [-c[None, :], -np.array([[d]])]])
        E = np.zeros_like(M)
        E[:n, :n] = np.eye(n)
        alpha, beta = scipy.linalg.eig(M, E, right=False, homogeneous_eigvals=True)
        fin = np.abs(beta) > 1e-9 * np.abs(alpha)
        z = alpha[fin] / beta[fin]
        scale = max(1.0, float(np.max(np.abs(z), initial=0.0)))
        zs.append(tuple(complex(w) for w in z))
        flags.append(bool(np.any(z.real > tol * scale)))
    return PositionSweep(input=input, positions=tuple(map(float, positions)), zeros=tuple(zs),
                         nonminimum_phase=tuple(flags))
