"""Small control-design helpers for the exported plants (python-control does the rest).

Use python-control directly for loops, LQR, responses (``control.feedback``,
``control.lqr``, ``control.step_response``, ``control.step_info``).  This
module adds only what it lacks:

* :func:`specs_to_poles` -- a dominant pole pair from overshoot and settling time;
* :func:`pd_place` -- collocated PD gains ``(k_pot, k_taco)`` for a rigid
  inertia, closed form ``J s^2 + k_taco s + k_pot``;
* :func:`pid_place` -- PID gains placing the three closed-loop poles of a
  second-order plant ``b / (s^2 + a_1 s + a_0)`` (the SRV-02 hub, seed 000 Eq. 1);
* :func:`minimal_realization` -- controllable and observable part of a
  state-space system by orthogonal staircase reduction (python-control's
  ``minreal`` needs slycot for state-space systems).

Examples
--------
>>> from bondgraph.numeric.control import pd_place
>>> pd_place(2.0, [-1.0, -3.0])          # 2 (s + 1)(s + 3) = 2 s^2 + 8 s + 6
(6.0, 8.0)
"""

from __future__ import annotations

import math
from typing import Sequence

import control
import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["specs_to_poles", "pd_place", "pid_place", "minimal_realization"]


def _monic_from_poles(poles: ArrayLike, count: int, what: str) -> NDArray[np.float64]:
    p = np.atleast_1d(np.asarray(poles, dtype=complex))
    if p.ndim != 1 or p.size != count:
        raise ValueError(f"{what}: expected {count} poles, got {p.size}")
    if not np.all(np.isfinite(p)):
        raise ValueError(f"{what}: expected finite poles")
    c = np.poly(p)
    if np.max(np.abs(c.imag)) > 1e-9 * max(1.0, float(np.max(np.abs(c.real)))):
        raise ValueError(f"{what}: complex poles must come in conjugate pairs, got {p}")
    return c.real


def specs_to_poles(overshoot: float, settling_time: float) -> NDArray[np.complex128]:
    """Dominant second-order pole pair for a step overshoot and 2 % settling time.

    ``zeta = -ln(OS) / sqrt(pi^2 + ln(OS)^2)`` and ``omega_n = 4 / (zeta t_s)``
    (the usual ``4/(zeta omega_n)`` estimate of the 2 % settling time).

    Parameters
    ----------
    overshoot : float
        Fractional overshoot, ``0 < overshoot < 1`` (0.25 for 25 %).
    settling_time : float
        2 % settling time in seconds (> 0).

    Returns
    -------
    numpy.ndarray
        ``[-zeta w_n + j w_d, -zeta w_n - j w_d]``.

    Examples
    --------
    >>> p = specs_to_poles(0.25, 10.0)
    >>> round(float(-p[0].real), 6), round(float(abs(p[0])), 4)
    (0.4, 0.9908)
    """
    os_, ts = float(overshoot), float(settling_time)
    if not 0.0 < os_ < 1.0:
        raise ValueError(f"overshoot: expected a fraction in (0, 1), got {overshoot!r}")
    if not (math.isfinite(ts) and ts > 0):
        raise ValueError(f"settling_time: expected a finite time > 0, got {settling_time!r}")
    lo = math.log(os_)
    zeta = -lo / math.sqrt(math.pi**2 + lo**2)
    wn = 4.0 / (zeta * ts)
    wd = wn * math.sqrt(1.0 - zeta**2)
    return np.array([-zeta * wn + 1j * wd, -zeta * wn - 1j * wd])


def pd_place(inertia: float, poles: Sequence[complex]) -> tuple[float, float]:
    """Collocated PD gains placing the poles of a rigid inertia.

    With ``tau = k_pot (theta_ref - theta) - k_taco theta'`` on ``J theta'' = tau``
    the closed loop is ``J s^2 + k_taco s + k_pot``; matching
    ``J (s - p_1)(s - p_2)`` gives ``k_taco = -J (p_1 + p_2)`` and
    ``k_pot = J p_1 p_2``.

    Parameters
    ----------
    inertia : float
        ``J > 0`` (kg m^2, or the equivalent in the plant's input/output units).
    poles : sequence of two complex
        Desired poles (a real pair or a conjugate pair).

    Returns
    -------
    (k_pot, k_taco) : tuple of float

    Examples
    --------
    >>> k_pot, k_taco = pd_place(0.5, [-2 + 1j, -2 - 1j])   # 0.5 (s^2 + 4 s + 5)
    >>> k_pot, k_taco
    (2.5, 2.0)
    """
    J = float(inertia)
    if not (math.isfinite(J) and J > 0):
        raise ValueError(f"inertia: expected a finite value > 0, got {inertia!r}")
    c = _monic_from_poles(poles, 2, "poles")
    return float(J * c[2]), float(J * c[1])


def pid_place(gain: float, den: Sequence[float], poles: Sequence[complex]
              ) -> tuple[float, float, float]:
    """PID gains placing the closed-loop poles of ``b / (s^2 + a_1 s + a_0)``.

    With ``C(s) = k_p + k_i / s + k_d s`` in unity feedback the closed-loop
    characteristic polynomial is

    ``s^3 + (a_1 + b k_d) s^2 + (a_0 + b k_p) s + b k_i``,

    so matching ``(s - p_1)(s - p_2)(s - p_3) = s^3 + c_2 s^2 + c_1 s + c_0``
    gives ``k_d = (c_2 - a_1)/b``, ``k_p = (c_1 - a_0)/b``, ``k_i = c_0/b``.
    The derivative is ideal (unfiltered); a filter ``k_d s/(T_f s + 1)`` with
    ``T_f`` well below the closed-loop time constants changes the poles little.

    Parameters
    ----------
    gain : float
        ``b`` (non-zero).
    den : sequence of 3 float
        ``[1, a_1, a_0]`` (a leading coefficient other than 1 is divided out,
        together with ``gain``).
    poles : sequence of 3 complex
        Desired closed-loop poles (conjugate pairs).

    Returns
    -------
    (k_p, k_i, k_d) : tuple of float

    Examples
    --------
    The SRV-02 hub of seed 000, ``377.8 / (s (s + 42.4))``, with poles at -20, -20, -20:

    >>> kp, ki, kd = pid_place(377.8, [1.0, 42.4, 0.0], [-20, -20, -20])
    >>> round(kp, 4), round(ki, 4), round(kd, 4)
    (3.1763, 21.1752, 0.0466)
    """
    d = np.asarray(den, dtype=float)
    if d.shape != (3,) or not np.all(np.isfinite(d)) or d[0] == 0:
        raise ValueError(f"den: expected 3 finite coefficients [1, a1, a0], got {den!r}")
    b = float(gain) / d[0]
    if not (math.isfinite(b) and b != 0):
        raise ValueError(f"gain: expected a finite non-zero value, got {gain!r}")
    a1, a0 = d[1] / d[0], d[2] / d[0]
    c = _monic_from_poles(poles, 3, "poles")
    return float((c[2] - a0) / b), float(c[3] / b), float((c[1] - a1) / b)


def _krylov_basis(A: NDArray, B: NDArray, tol: float) -> NDArray:
    """Orthonormal basis of the controllable subspace span[B, AB, ...] (block Arnoldi)."""
    n = A.shape[0]

    def new_directions(W: NDArray, V: NDArray) -> NDArray:
        for _ in range(2):                          # re-orthogonalise against V
            if V.shape[1]:
                W = W - V @ (V.T @ W)
        if W.size == 0:
            return np.zeros((n, 0))
        U, s, _ = np.linalg.svd(W, full_matrices=False)
        return U[:, s > tol]

    V = new_directions(B, np.zeros((n, 0)))
    last = V
    while last.shape[1] and V.shape[1] < n:
        last = new_directions(A @ last, V)
        V = np.column_stack((V, last))
    return V[:, :n]


def minimal_realization(sys: control.StateSpace, tol: float | None = None) -> control.StateSpace:
    """Controllable and observable part of a state-space system (no slycot needed).

    Orthonormal bases of the controllable subspace of ``(A, B)`` and then of
    the observable subspace of the reduced ``(A, C)`` are built by block
    Krylov iteration with re-orthogonalisation; the system is projected on
    them.  The transfer function is unchanged; the states become
    combinations of the original ones (labels ``x[i]``).

    Parameters
    ----------
    sys : control.StateSpace
    tol : float, optional
        Directions whose new component is below ``tol`` are dropped.  Default
        ``1e-9 * max(1, ||A||, ||B||, ||C||)`` (Frobenius norms).

    Returns
    -------
    control.StateSpace
        Same inputs, outputs and sample time.

    Examples
    --------
    An uncontrollable integrator next to ``1/(s + 1)``:

    >>> import control
    >>> G = control.ss([[-1.0, 0.0], [0.0, 0.0]], [[1.0], [0.0]], [[1.0, 1.0]], [[0.0]])
    >>> m = minimal_realization(G)
    >>> m.nstates, m.poles().round(12)
    (1, array([-1.+0.j]))
    """
    if not isinstance(sys, control.StateSpace):
        raise TypeError(f"sys: expected a control.StateSpace, got {type(sys).__name__}")
    A, B, C, D = (np.asarray(M, dtype=float) for M in (sys.A, sys.B, sys.C, sys.D))
    if tol is None:
        tol = 1e-9 * max(1.0, *(float(np.linalg.norm(M)) for M in (A, B, C)))
    V = _krylov_basis(A, B, tol)
    A1, B1, C1 = V.T @ A @ V, V.T @ B, C @ V
    U = _krylov_basis(A1.T, C1.T, tol)
    A2, B2, C2 = U.T @ A1 @ U, U.T @ B1, C1 @ U
    return control.ss(A2, B2, C2, D, sys.dt, inputs=sys.input_labels,
                      outputs=sys.output_labels)
