"""Defaults that let an importer run the FMU well with its own default settings (private).

An importer left to its defaults integrates a Model Exchange FMU with an
absolute tolerance of ``relative tolerance x nominal`` per state (nominal 1
when the FMU gives none) over ``[0, 1]`` s, or with a fixed Euler step.  A
bond-graph model's states are momenta and displacements whose size follows
from the parameters (FLEXCAM's are of size 1e-4), so neither default fits.
:func:`run_defaults` reads the time scales and the state sizes from the
linearization at rest (``x = 0``, ``u = 0``, the parameters' values):

* ``stop`` (``DefaultExperiment stopTime``): the slowest mode's settling to
  1 % (``ln 100 / |Re lambda|``), at most 20 periods of an undamped or
  lightly damped mode (``40 pi / |lambda|``), the largest over the modes
  with ``|lambda| > 1e-9 rho`` (``rho`` the spectral radius; pure
  integrators give no time scale), rounded *up* to 1, 2 or 5 times a power
  of ten; 1 s when no mode gives a time;
* ``step`` (``stepSize``): ``0.05 / rho`` rounded *down* to 1, 2 or 5 times a
  power of ten, at most ``stop / 100``: RK4 is accurate to about ``5e-8``
  per unit time there, and explicit Euler is stable for a mode of damping
  ratio ``zeta`` when ``zeta > h |lambda| / 2 = 0.025``;
* ``tolerance`` (the importer's relative tolerance): :data:`TOLERANCE`
  times ``min(1, 100 / N)`` rounded down to a power of ten, ``N = stop rho /
  (2 pi)`` the periods of the fastest mode in the run, at least 1e-10.  An
  importer's global error grows with ``N`` (measured with fmpy's CVode BDF:
  FLEXCAM, ``N = 200``, error 12 x tolerance; a 100-cell chain, ``N = 1270``,
  error 730 x tolerance), so a long run of fast modes gets a tighter one;
* ``nominal`` of state ``i``: the largest ``|x_i(t)|`` over ``[0, stop]``
  of the linearization's response to a unit step on each input (the
  largest over the inputs), computed exactly at 2000 instants with the
  matrix exponential of ``[[A, B], [0, 0]]``, 3 significant digits; 1 when
  the state does not respond (it then stays at its start value, which the
  importer sets).

Nothing here changes the model: these are attributes of the model
description (and the values ``fmi2GetNominalsOfContinuousStates`` returns).
A model of more than :data:`MAX_STATES` states keeps FMI's defaults (no
``DefaultExperiment``, nominals 1): the dense eigenvalues and matrix
exponential would take minutes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from ..model import Model

__all__ = ["Experiment", "RunDefaults", "run_defaults", "linearization_at_rest", "TOLERANCE"]

#: relative tolerance proposed to the importer (``DefaultExperiment tolerance``)
TOLERANCE = 1e-6
#: instants of the step response that give the nominals
SAMPLES = 2000
#: above this many states the dense analysis is too slow: FMI's defaults are kept
MAX_STATES = 2000


@dataclass(frozen=True)
class Experiment:
    """``DefaultExperiment``: start and stop time (s), relative tolerance, step (s)."""

    start: float
    stop: float
    tolerance: float
    step: float


@dataclass(frozen=True)
class RunDefaults:
    """The default experiment (None: none proposed) and one nominal value per state (model order)."""

    experiment: Optional[Experiment]
    nominals: tuple[float, ...]


def _round_125(value: float, *, up: bool) -> float:
    """``value`` rounded up or down to 1, 2 or 5 times a power of ten.

    Examples
    --------
    >>> _round_125(1.18, up=True), _round_125(7.9e-5, up=False), _round_125(2.0, up=True)
    (2.0, 5e-05, 2.0)
    """
    exponent = math.floor(math.log10(value))
    candidates = [m * 10.0 ** e for e in (exponent - 1, exponent, exponent + 1) for m in (1.0, 2.0, 5.0)]
    if up:
        chosen = min(c for c in candidates if c >= value * (1 - 1e-12))
    else:
        chosen = max(c for c in candidates if c <= value * (1 + 1e-12))
    return float(f"{chosen:.1e}")


def linearization_at_rest(model: Model, parameters: Sequence[float]) -> Optional[tuple[np.ndarray, np.ndarray]]:
    """``(A, B)`` of ``x' = f(0, x, u)`` at ``x = 0``, ``u = 0``.

    A linear model's own matrices (:func:`bondgraph.numeric.compile_plant`);
    a nonlinear one's by central differences of the compiled equations.
    None when the equations cannot be evaluated there (a law singular at
    rest) or give a value that is not finite.
    """
    from ..errors import NonlinearModelError
    from ..numeric import compile_dynamics, compile_plant

    n, m = len(model.states), len(model.inputs)
    p = np.asarray(parameters, dtype=float)
    try:
        plant = compile_plant(model, sparse=False).plant(dict(zip(model.parameters, p)))
        A, B = np.asarray(plant.A, dtype=float), np.asarray(plant.B, dtype=float)
        return (A, B) if np.all(np.isfinite(A)) and np.all(np.isfinite(B)) else None
    except NonlinearModelError:
        pass
    except Exception:
        return None
    try:
        dyn = compile_dynamics(model)
        x0, u0 = np.zeros(n), np.zeros(m)
        A, B = np.empty((n, n)), np.empty((n, m))
        for i in range(n):
            d = np.zeros(n)
            d[i] = 1e-6
            A[:, i] = (dyn.derivatives(0.0, x0 + d, u0, p) - dyn.derivatives(0.0, x0 - d, u0, p)) / 2e-6
        for k in range(m):
            d = np.zeros(m)
            d[k] = 1e-6
            B[:, k] = (dyn.derivatives(0.0, x0, u0 + d, p) - dyn.derivatives(0.0, x0, u0 - d, p)) / 2e-6
    except Exception:
        return None
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(B))):
        return None
    return A, B


def _stop_time(eigenvalues: np.ndarray) -> float:
    if eigenvalues.size == 0:
        return 1.0
    rho = float(np.max(np.abs(eigenvalues)))
    times = []
    for lam in eigenvalues:
        size = abs(lam)
        if size <= 1e-9 * rho or size == 0.0:
            continue
        decay = abs(lam.real)
        settle = math.log(100.0) / decay if decay > 0.0 else math.inf
        times.append(min(settle, 40.0 * math.pi / size))
    return _round_125(max(times), up=True) if times else 1.0


def _nominals(A: np.ndarray, B: np.ndarray, stop: float) -> tuple[float, ...]:
    from scipy.linalg import expm

    n, m = B.shape
    if n == 0:
        return ()
    peak = np.zeros(n)
    if m:
        M = np.zeros((n + m, n + m))
        M[:n, :n], M[:n, n:] = A, B
        # one exact step of the zero-order-hold discretization, repeated
        phi = expm(M * (stop / SAMPLES))
        Ad, Bd = phi[:n, :n], phi[:n, n:]
        X = np.zeros((n, m))
        for _ in range(SAMPLES):
            X = Ad @ X + Bd
            if not np.all(np.isfinite(X)):
                break
            np.maximum(peak, np.max(np.abs(X), axis=1), out=peak)
    out = []
    for value in peak:
        ok = math.isfinite(value) and value > 1e-300
        out.append(float(f"{value:.3g}") if ok else 1.0)
    return tuple(out)


def run_defaults(model: Model, parameters: Sequence[float]) -> RunDefaults:
    """Default experiment and state nominals of ``model`` (see the module docstring).

    Examples
    --------
    A mass ``m = 2`` on a damper ``b = 4`` (one mode ``-b/m = -2`` 1/s):
    settling to 1 % takes ``ln(100)/2 = 2.3`` s, so the stop time is 5 s;
    the step ``0.05/2`` rounds down to 0.02 s; a unit force brings the
    momentum to ``m F / b (1 - exp(-b t / m))``, 0.5 at the end.

    >>> import bondgraph as bg
    >>> g = bg.BondGraph("md")
    >>> g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"))
    >>> for a, b in [("F", "v"), ("v", "m"), ("v", "b")]: _ = g.connect(a, b)
    >>> d = run_defaults(bg.derive(g), [4.0, 2.0])
    >>> d.experiment.stop, d.experiment.step, d.experiment.tolerance, d.nominals
    (5.0, 0.02, 1e-06, (0.5,))
    """
    n = len(model.states)
    if n > MAX_STATES:
        return RunDefaults(None, (1.0,) * n)
    lin = linearization_at_rest(model, parameters)
    if lin is None or n == 0:
        return RunDefaults(Experiment(0.0, 1.0, TOLERANCE, 1e-3), (1.0,) * n)
    A, B = lin
    eigenvalues = np.linalg.eigvals(A)
    if not np.all(np.isfinite(eigenvalues)):
        return RunDefaults(Experiment(0.0, 1.0, TOLERANCE, 1e-3), (1.0,) * n)
    stop = _stop_time(eigenvalues)
    rho = float(np.max(np.abs(eigenvalues)))
    step = stop / 100.0 if rho == 0.0 else min(0.05 / rho, stop / 100.0)
    step = _round_125(step, up=False)
    periods = stop * rho / (2.0 * math.pi)
    tolerance = max(1e-10, 10.0 ** math.floor(math.log10(TOLERANCE * min(1.0, 100.0 / max(periods, 1e-300)))))
    return RunDefaults(Experiment(0.0, stop, float(f"{tolerance:.0e}"), step), _nominals(A, B, stop))
