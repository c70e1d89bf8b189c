"""Rational transfer-function fit to frequency-response data (``invfreqs``).

Fits ``H(s) ~ B(s)/A(s)`` with ``deg B = num_order``, ``deg A = den_order``
and ``A`` monic, minimising approximately

.. math::

    \\sum_k w_k \\left| H_k - \\frac{B(j\\omega_k)}{A(j\\omega_k)} \\right|^2 .

1. *Levy* (1959): the nonlinear error is replaced by the linear equation
   error ``B(s_k) - H_k A(s_k)``, solved by real least squares
   (:func:`numpy.linalg.lstsq`, real and imaginary parts stacked).
2. *Sanathanan–Koerner* (1963) iterations: the equation error at iteration
   ``i`` is divided by ``|A_{i-1}(s_k)|``, which removes Levy's
   ``|A|``-weighting of the residual; iterate until the denominator stops
   changing.
3. Conditioning: ``s`` is scaled by ``1/max(omega)`` so all powers lie in
   ``[0, 1]``, and the regressor columns are normalised before solving;
   coefficients are scaled back at the end.
4. ``stable=True``: poles in the open right half plane are reflected
   (``p -> -conj(p)``) and the numerator is re-solved by linear least squares
   with the denominator fixed.
"""

from __future__ import annotations

from dataclasses import dataclass

import control
import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._validation import (IdentificationError, as_signal, check_int, check_positive_float,
                          check_same_length, readonly_copy)

__all__ = ["RationalFit", "fit_rational", "fit_rational_detailed"]


@dataclass(frozen=True, eq=False)
class RationalFit:
    """Result of :func:`fit_rational_detailed`.

    Attributes
    ----------
    tf : control.TransferFunction
        Continuous-time fitted model ``B(s)/A(s)``.
    num, den : numpy.ndarray
        Coefficients of ``B`` and monic ``A`` in descending powers of ``s``.
    iterations : int
        Sanathanan–Koerner iterations performed (0 = Levy only).
    converged : bool
        Whether the relative change of the scaled denominator fell below
        ``tol`` (always True when ``sk_iterations == 0``).
    reflected_poles : int
        Number of right-half-plane poles reflected when ``stable=True``.
    weighted_rms_error : float
        ``sqrt(sum w |H - B/A|^2 / sum w)`` of the returned model.

    Examples
    --------
    A first-order lag ``3/(s + 2)`` recovered from its samples:

    >>> import numpy as np
    >>> w = np.linspace(0.1, 10, 50)
    >>> r = fit_rational_detailed(w, 3.0 / (1j * w + 2.0), num_order=0, den_order=1)
    >>> r.num.round(10) + 0.0, r.den.round(10) + 0.0, r.poles.round(10) + 0.0
    (array([3.]), array([1., 2.]), array([-2.]))
    >>> r.converged, r.reflected_poles, r.zeros.size, bool(r.weighted_rms_error < 1e-10)
    (True, 0, 0, True)
    """

    tf: control.TransferFunction
    num: NDArray[np.float64]
    den: NDArray[np.float64]
    iterations: int
    converged: bool
    reflected_poles: int
    weighted_rms_error: float

    @property
    def poles(self) -> NDArray[np.inexact]:
        """Roots of the fitted denominator (real dtype when all roots are real)."""
        return np.roots(self.den)

    @property
    def zeros(self) -> NDArray[np.inexact]:
        """Roots of the fitted numerator (real dtype when all roots are real)."""
        return np.roots(self.num) if self.num.size > 1 else np.empty(0, complex)


def _vander(s: NDArray, order: int) -> NDArray:
    """Columns s**0 .. s**order (ascending)."""
    return s[:, None] ** np.arange(order + 1)[None, :]


def _solve_real(M: NDArray, rhs: NDArray) -> NDArray:
    """Least squares on stacked real/imaginary parts with column normalisation."""
    Mr = np.vstack((M.real, M.imag))
    rr = np.concatenate((rhs.real, rhs.imag))
    norms = np.linalg.norm(Mr, axis=0)
    norms[norms == 0] = 1.0
    x, *_ = np.linalg.lstsq(Mr / norms, rr, rcond=None)
    return x / norms


def fit_rational_detailed(omega: ArrayLike, h: ArrayLike, *, num_order: int,
                          den_order: int, weights: ArrayLike | None = None,
                          sk_iterations: int = 30, tol: float = 1e-12,
                          stable: bool = False, scale: bool = True) -> RationalFit:
    """Fit ``B(s)/A(s)`` to complex frequency-response samples; full result.

    Parameters
    ----------
    omega : array_like
        Angular frequencies ``omega_k >= 0`` in rad/s (distinct).
    h : array_like of complex
        Frequency response ``H(j omega_k)``.
    num_order : int
        Degree of the numerator ``B`` (>= 0).
    den_order : int
        Degree of the monic denominator ``A`` (>= 0).
    weights : array_like, optional
        Non-negative weights ``w_k`` multiplying the squared error at each
        frequency, e.g. the coherence.  Default all ones.
    sk_iterations : int, optional
        Maximum number of Sanathanan–Koerner iterations after the Levy
        solution (0 gives Levy's method alone).
    tol : float, optional
        Stop when the relative 2-norm change of the scaled denominator
        coefficients falls below ``tol``.
    stable : bool, optional
        Reflect right-half-plane poles into the left half plane and re-fit
        the numerator.
    scale : bool, optional
        Normalise frequencies by ``max(omega)`` for conditioning (default
        True; switch off only for comparison).

    Returns
    -------
    RationalFit

    Raises
    ------
    IdentificationError
        On NaN/inf or mismatched inputs, negative frequencies or weights,
        invalid orders, or fewer real equations (twice the number of points
        with positive weight) than unknowns ``num_order + den_order + 1``.

    Examples
    --------
    >>> import numpy as np
    >>> w = np.linspace(0.1, 10, 50)
    >>> h = 4.0 / ((1j * w) ** 2 + 0.4 * (1j * w) + 4.0)
    >>> r = fit_rational_detailed(w, h, num_order=0, den_order=2)
    >>> np.round(r.den, 10) + 0.0, np.round(r.num, 10) + 0.0
    (array([1. , 0.4, 4. ]), array([4.]))
    """
    omega = as_signal(omega, "omega", min_length=1)
    h = as_signal(h, "h", dtype=complex)
    check_same_length(omega, "omega", h, "h")
    if np.any(omega < 0):
        raise IdentificationError("omega: expected angular frequencies >= 0 rad/s")
    if np.unique(omega).size != omega.size:
        raise IdentificationError("omega: expected distinct frequencies")
    m = check_int(num_order, "num_order", minimum=0)
    n = check_int(den_order, "den_order", minimum=0)
    if weights is None:
        w = np.ones(omega.size)
    else:
        w = as_signal(weights, "weights")
        check_same_length(omega, "omega", w, "weights")
        if np.any(w < 0):
            raise IdentificationError("weights: expected non-negative values")
    sk_iterations = check_int(sk_iterations, "sk_iterations", minimum=0)
    tol = check_positive_float(tol, "tol")
    with np.errstate(over="ignore"):
        if omega.size and not np.isfinite(np.power(np.max(omega), float(max(m, n, 1))) * 1e3):
            raise _overflow(omega, max(m, n))

    n_unknown = m + 1 + n
    active = w > 0
    # A real-valued point (omega = 0) contributes one real equation, others two.
    n_eq = int(np.sum(np.where(omega[active] > 0, 2, 1)))
    if n_eq < n_unknown:
        raise IdentificationError(
            f"omega: expected enough frequency points for {n_unknown} unknowns "
            f"(num_order + den_order + 1), got {n_eq} real equations from "
            f"{int(active.sum())} points with positive weight")
    omega_a, h_a, sqw = omega[active], h[active], np.sqrt(w[active])

    ws = float(omega_a.max()) if (scale and omega_a.max() > 0) else 1.0
    s = 1j * omega_a / ws
    Vb = _vander(s, m)              # numerator columns
    Va = _vander(s, n)              # denominator columns incl. s**n
    Mden = -h_a[:, None] * Va[:, :n]
    rhs0 = h_a * Va[:, n]

    a_scaled = np.zeros(n + 1)
    a_scaled[n] = 1.0
    den_prev = np.ones(omega_a.size)   # Levy: no re-weighting
    iterations, converged = 0, sk_iterations == 0
    for it in range(sk_iterations + 1):
        row_w = sqw / den_prev
        M = np.hstack((Vb, Mden)) * row_w[:, None]
        x = _solve_real(M, rhs0 * row_w)
        b_scaled = x[: m + 1]
        a_new = np.concatenate((x[m + 1:], [1.0]))
        change = np.linalg.norm(a_new - a_scaled) / np.linalg.norm(a_new)
        a_scaled = a_new
        iterations = it
        den_prev = np.abs(Va @ a_scaled)
        if it > 0 and change < tol:
            converged = True
            break
        if np.any(den_prev == 0):
            raise IdentificationError(
                "h: the fitted denominator vanishes at a data frequency; "
                "reduce den_order or remove that frequency")

    reflected = 0
    if stable and n > 0:
        roots = np.roots(a_scaled[::-1])
        rhp = roots.real > 0
        reflected = int(np.count_nonzero(rhp))
        if reflected:
            roots = np.where(rhp, -roots.real + 1j * roots.imag, roots)
            a_scaled = np.real(np.poly(roots))[::-1]
            A = Va @ a_scaled
            b_scaled = _solve_real(Vb / A[:, None] * sqw[:, None], h_a * sqw)

    # Undo the frequency scaling and make A monic in s.
    pw_a = ws ** (n - np.arange(n + 1))
    pw_b = ws ** (n - np.arange(m + 1))
    a = a_scaled * pw_a
    b = b_scaled * pw_b
    num, den = b[::-1].copy(), a[::-1].copy()
    if not (np.all(np.isfinite(num)) and np.all(np.isfinite(den))):
        raise _overflow(omega, max(m, n))

    s_full = 1j * omega
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        model = np.polyval(num, s_full) / np.polyval(den, s_full)
    err = float(np.sqrt(np.sum(w * np.abs(h - model) ** 2) / np.sum(w)))
    tf = control.tf(num, den)
    return RationalFit(tf=tf, num=readonly_copy(num), den=readonly_copy(den),
                       iterations=iterations, converged=converged,
                       reflected_poles=reflected, weighted_rms_error=err)


def _overflow(omega: NDArray, order: int) -> IdentificationError:
    return IdentificationError(
        f"omega: the coefficients of the fitted B(s)/A(s) overflow (frequencies up to "
        f"{float(np.max(np.abs(omega))):.3g} rad/s raised to the power {order} exceed the range "
        "of a float); give the frequencies in a smaller unit (e.g. rad/ms) or lower the orders")


def fit_rational(omega: ArrayLike, h: ArrayLike, *, num_order: int, den_order: int,
                 weights: ArrayLike | None = None, sk_iterations: int = 30,
                 tol: float = 1e-12, stable: bool = False, scale: bool = True
                 ) -> control.TransferFunction:
    """Fit a continuous transfer function ``B(s)/A(s)`` to FRF data (like ``invfreqs``).

    Same parameters as :func:`fit_rational_detailed`, which also reports
    iteration count, convergence and the weighted error; this returns only
    the :class:`control.TransferFunction`.

    Parameters
    ----------
    omega : array_like
        Angular frequencies ``omega_k >= 0`` in rad/s (distinct).
    h : array_like of complex
        Frequency response ``H(j omega_k)``.
    num_order, den_order : int
        Degrees of the numerator and of the monic denominator (>= 0).
    weights : array_like, optional
        Non-negative weights of the squared errors; default all ones.
    sk_iterations : int, optional
        Maximum Sanathanan–Koerner iterations (0: Levy's method alone).
    tol : float, optional
        Convergence tolerance on the scaled denominator.
    stable : bool, optional
        Reflect right-half-plane poles and re-fit the numerator.
    scale : bool, optional
        Normalise frequencies by ``max(omega)`` for conditioning.

    Returns
    -------
    control.TransferFunction

    Examples
    --------
    A lightly damped mode at 2 rad/s with a zero at -1, fitted from samples:

    >>> import numpy as np
    >>> w = np.logspace(-1, 1, 40)
    >>> s = 1j * w
    >>> h = (s + 1.0) / (s**2 + 0.08 * s + 4.0)
    >>> G = fit_rational(w, h, num_order=1, den_order=2, stable=True)
    >>> np.round(G.poles(), 8)
    array([-0.04+1.99959996j, -0.04-1.99959996j])
    """
    return fit_rational_detailed(omega, h, num_order=num_order, den_order=den_order,
                                 weights=weights, sk_iterations=sk_iterations, tol=tol,
                                 stable=stable, scale=scale).tf
