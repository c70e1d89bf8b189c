"""A stiffness check before an explicit solver starts (issue 23, item 3; audit R06a).

``simulate`` with the default ``RK45`` on a stiff plant (a pole at -1e9 over
100 s) ran past 90 s with growing memory, while ``Radau`` answers in under a
second.  An explicit Runge-Kutta method must keep ``h |lambda| <~ 3`` for the
fastest eigenvalue ``lambda`` of the Jacobian whatever the accuracy asked, so
it needs at least ``|lambda| (t1 - t0) / 3`` steps.  :func:`check_stiffness`
estimates the Jacobian at the initial point by finite differences (for models
of at most :data:`MAX_STATES` states), and refuses a run that would need more
than :data:`MAX_EXPLICIT_STEPS` steps, saying which implicit method to use.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .errors import SimulationError

__all__ = ["EXPLICIT", "MAX_EXPLICIT_STEPS", "MAX_STATES", "check_stiffness"]

#: the explicit methods of ``solve_ivp`` and the reach of their stability region on the real axis
EXPLICIT = {"RK45": 3.3, "RK23": 2.5, "DOP853": 6.0}
#: steps an explicit method may need before the run is refused as stiff
MAX_EXPLICIT_STEPS = 1_000_000
#: above this many states the finite-difference Jacobian is not formed (no check)
MAX_STATES = 200


def check_stiffness(rhs: Callable[[float, np.ndarray], np.ndarray], t0: float, t1: float,
                    x0: np.ndarray, method: str, model: str) -> None:
    """Refuse an explicit ``method`` that would need more than :data:`MAX_EXPLICIT_STEPS` steps.

    Examples
    --------
    >>> import numpy as np
    >>> check_stiffness(lambda t, x: -1e9 * x, 0.0, 100.0, np.ones(1), "RK45", "fast")
    Traceback (most recent call last):
    ...
    bondgraph.numeric.errors.SimulationError: model 'fast' is stiff: its fastest eigenvalue at the initial state is -1e+09 (time constant 1e-09 s), so RK45 needs at least 3.03e+10 steps over 100 s; use method='Radau', 'BDF' or 'LSODA' (implicit), which take steps as long as the slow dynamics allow
    >>> check_stiffness(lambda t, x: -x, 0.0, 100.0, np.ones(1), "RK45", "slow")
    """
    reach = EXPLICIT.get(method) if isinstance(method, str) else None
    n = x0.size
    if reach is None or n == 0 or n > MAX_STATES:
        return
    try:
        with np.errstate(all="ignore"):
            f0 = np.asarray(rhs(t0, x0), dtype=float)
            J = np.empty((n, n))
            for j in range(n):
                h = 1e-7 * max(1.0, abs(x0[j]))
                x = x0.copy()
                x[j] += h
                J[:, j] = (np.asarray(rhs(t0, x), dtype=float) - f0) / h
            if not np.all(np.isfinite(J)):
                return
            lam = np.linalg.eigvals(J)
    except Exception:       # the run itself reports a failing model, with its own message
        return
    fastest = lam[np.argmax(np.abs(lam))]
    if fastest.real >= 0:
        return              # growth, not stiffness: accuracy limits the steps anyway
    steps = abs(fastest) * (t1 - t0) / reach
    if steps > MAX_EXPLICIT_STEPS:
        value = f"{fastest.real:.3g}" if abs(fastest.imag) < 1e-9 * abs(fastest) else f"{fastest:.3g}"
        raise SimulationError(
            f"model {model!r} is stiff: its fastest eigenvalue at the initial state is {value} "
            f"(time constant {1 / abs(fastest):.3g} s), so {method} needs at least {steps:.3g} steps "
            f"over {t1 - t0:g} s; use method='Radau', 'BDF' or 'LSODA' (implicit), which take "
            "steps as long as the slow dynamics allow")
