"""Discrete-to-continuous conversion: the exact inverse of zero-order hold.

Zero-order-hold sampling of ``dx/dt = A x + B u`` with period ``T`` gives

.. math::

    \\exp\\left(\\begin{bmatrix} A & B \\\\ 0 & 0 \\end{bmatrix} T\\right)
    = \\begin{bmatrix} A_d & B_d \\\\ 0 & I \\end{bmatrix},

so the continuous pair is recovered from the principal matrix logarithm
(:func:`scipy.linalg.logm`) of the right-hand block matrix divided by ``T``.
``C`` and ``D`` are unchanged.  The principal logarithm exists and is real
when no eigenvalue of ``A_d`` lies on the closed negative real axis;
eigenvalues at ``z = 1`` (integrators, including the Jordan block they form
with the input columns) are handled.  A discrete pole at ``z = 0`` (pure
delay) or on the negative real axis has no continuous ZOH pre-image and is
rejected.
"""

from __future__ import annotations

import control
import numpy as np
import scipy.linalg

from ._validation import IdentificationError

__all__ = ["d2c_zoh"]


def _check_dt(sys: control.LTI) -> float:
    dt = sys.dt
    if dt is None or dt is True or isinstance(dt, bool) or not (float(dt) > 0):
        raise IdentificationError(
            f"sys: expected a discrete-time system with a numeric sample time dt > 0, "
            f"got dt={dt!r}")
    return float(dt)


def d2c_zoh(sys: control.TransferFunction | control.StateSpace, *,
            imag_tol: float = 1e-8) -> control.TransferFunction | control.StateSpace:
    """Convert a discrete-time system to continuous time by inverse zero-order hold.

    Parameters
    ----------
    sys : control.TransferFunction or control.StateSpace
        Discrete-time system with numeric sample time ``sys.dt > 0``.
    imag_tol : float, optional
        Largest imaginary part (relative to the norm of the logarithm)
        tolerated in the matrix logarithm before the conversion is declared
        impossible.

    Returns
    -------
    control.TransferFunction or control.StateSpace
        Continuous-time system of the same kind as ``sys`` whose ZOH
        discretisation with period ``sys.dt`` is ``sys``.

    Raises
    ------
    IdentificationError
        If ``sys`` is not discrete with a numeric ``dt``, or has a pole at
        ``z = 0`` or on the negative real axis.

    Examples
    --------
    The DC-motor hub of the FLEXCAM paper, sampled at 200 Hz and recovered:

    >>> import control
    >>> G = control.tf([377.8], [1, 42.4, 0])
    >>> Gd = control.sample_system(G, 0.005, method="zoh")
    >>> Gc = d2c_zoh(Gd)
    >>> round(float(Gc.num[0][0][-1]), 6)
    377.8
    >>> sorted(round(float(p.real), 6) + 0.0 for p in Gc.poles())
    [-42.4, 0.0]
    """
    if not isinstance(sys, (control.TransferFunction, control.StateSpace)):
        raise IdentificationError(
            f"sys: expected a control.TransferFunction or control.StateSpace, "
            f"got {type(sys).__name__}")
    dt = _check_dt(sys)
    is_tf = isinstance(sys, control.TransferFunction)
    ss = control.ss(sys) if is_tf else sys
    Ad, Bd, C, D = (np.asarray(m, dtype=float) for m in (ss.A, ss.B, ss.C, ss.D))
    n, m = Bd.shape

    if n == 0:
        ct = control.ss(Ad, Bd, C, D)  # static gain
    else:
        eig = np.linalg.eigvals(Ad)
        scale = max(1.0, float(np.max(np.abs(eig))))
        bad_zero = np.abs(eig) <= 1e-10 * scale
        if np.any(bad_zero):
            raise IdentificationError(
                "sys: expected no discrete pole at z = 0 (a pure delay has no "
                "continuous-time ZOH equivalent); remove the delay first")
        bad_neg = (np.abs(eig.imag) <= 1e-10 * scale) & (eig.real < 0)
        if np.any(bad_neg):
            raise IdentificationError(
                f"sys: expected no discrete pole on the negative real axis (no real "
                f"continuous ZOH equivalent), got poles {np.sort_complex(eig[bad_neg])}")
        M = np.block([[Ad, Bd], [np.zeros((m, n)), np.eye(m)]])
        L = scipy.linalg.logm(M)
        L = np.asarray(L)
        if np.iscomplexobj(L):
            if np.max(np.abs(L.imag)) > imag_tol * max(1.0, float(np.linalg.norm(L.real))):
                raise IdentificationError(
                    "sys: the matrix logarithm is not real; the system has no real "
                    "continuous-time ZOH equivalent (poles aliased past Nyquist?)")
            L = L.real
        L = L / dt
        ct = control.ss(L[:n, :n], L[:n, n:], C, D)

    if is_tf:
        return control.ss2tf(ct)
    return ct
