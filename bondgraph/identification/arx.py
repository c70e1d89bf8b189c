"""ARX models estimated by linear least squares.

The ARX(na, nb, nk) model (Ljung's convention, as in MATLAB's ``arx``) is

.. math::

    A(q)\\,y_k = B(q)\\,u_k + e_k, \\qquad
    A(q) = 1 + a_1 q^{-1} + \\dots + a_{n_a} q^{-n_a}, \\qquad
    B(q) = q^{-n_k}\\,(b_{n_k} + b_{n_k+1} q^{-1} + \\dots + b_{n_k+n_b-1} q^{-n_b+1}),

i.e. ``nb`` numerator coefficients after a delay of ``nk`` samples.  Stacking
``y_k = phi_k^T theta + e_k`` with ``phi_k = [-y_{k-1} .. -y_{k-na},
u_{k-nk} .. u_{k-nk-nb+1}]`` gives ``theta`` by least squares
(:func:`numpy.linalg.lstsq`); see Eq. (2) of Barbosa & Góes.  The estimate
is consistent when ``e_k`` is white (*equation-error* noise).  White noise
added to the measured output instead (*output-error* noise) biases it, by an
amount that shrinks with the noise-to-signal ratio.
"""

from __future__ import annotations

from dataclasses import dataclass

import control
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.signal import lfilter

from ._validation import (IdentificationError, as_signal, check_int, check_positive_float,
                          check_same_length, readonly_copy)
from .conversion import d2c_zoh

__all__ = ["ARXResult", "arx", "fit_percent"]


def fit_percent(y: ArrayLike, y_model: ArrayLike) -> float:
    """Normalised-RMSE fit in percent, ``100 (1 - ||y - ŷ|| / ||y - mean(y)||)``.

    100 is a perfect match, 0 is no better than the mean of ``y``; the value
    can be negative.

    Parameters
    ----------
    y : array_like
        Measured output (1-D, finite, not constant).
    y_model : array_like
        Model output of the same length.

    Returns
    -------
    float

    Examples
    --------
    >>> fit_percent([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 2.0, 3.0])
    100.0
    >>> fit_percent([1.0, -1.0, 1.0, -1.0], [0.5, -0.5, 0.5, -0.5])
    50.0
    """
    y = as_signal(y, "y", min_length=2)
    y_model = as_signal(y_model, "y_model")
    check_same_length(y, "y", y_model, "y_model")
    denom = np.linalg.norm(y - y.mean())
    if denom == 0:
        raise IdentificationError("y: expected a non-constant signal (fit is undefined)")
    return float(100.0 * (1.0 - np.linalg.norm(y - y_model) / denom))


@dataclass(frozen=True, eq=False)
class ARXResult:
    """Least-squares ARX(na, nb, nk) estimate.

    Attributes
    ----------
    a : numpy.ndarray
        ``[1, a_1, ..., a_na]``, coefficients of ``A(q)`` in powers of ``q^-1``.
    b : numpy.ndarray
        ``[0]*nk + [b_nk, ..., b_{nk+nb-1}]``, coefficients of ``B(q)`` in
        powers of ``q^-1`` (leading zeros encode the delay, as in MATLAB).
    na, nb, nk : int
        Model orders and input delay.
    dt : float
        Sample time in seconds.
    parameters : numpy.ndarray
        ``theta = [a_1..a_na, b_nk..b_{nk+nb-1}]``.
    covariance : numpy.ndarray
        Parameter covariance ``sigma^2 (X^T X)^{-1}``.
    noise_variance : float
        ``sigma^2 = ||y - X theta||^2 / (N_eq - na - nb)``.
    n_equations : int
        Number of regression rows ``N_eq`` used.

    Examples
    --------
    Returned by :func:`arx`; noise-free data from ``y_k = 0.8 y_{k-1} + 0.5 u_{k-1}``:

    >>> import numpy as np
    >>> from scipy.signal import lfilter
    >>> from bondgraph.identification import prbs
    >>> u = prbs(6)
    >>> y = lfilter([0.0, 0.5], [1.0, -0.8], u)
    >>> m = arx(y, u, na=1, nb=1, dt=0.1)
    >>> m.na, m.nb, m.nk, m.n_equations, m.parameters.round(12) + 0.0, m.poles.round(12)
    (1, 1, 1, 62, array([-0.8,  0.5]), array([0.8]))
    >>> np.allclose(m.simulate(u), y), round(float(m.to_continuous().poles()[0].real), 4)
    (True, -2.2314)
    """

    a: NDArray[np.float64]
    b: NDArray[np.float64]
    na: int
    nb: int
    nk: int
    dt: float
    parameters: NDArray[np.float64]
    covariance: NDArray[np.float64]
    noise_variance: float
    n_equations: int

    @property
    def std(self) -> NDArray[np.float64]:
        """Standard deviations of :attr:`parameters` (square root of the covariance diagonal)."""
        return np.sqrt(np.diag(self.covariance))

    @property
    def poles(self) -> NDArray[np.inexact]:
        """Discrete-time poles (roots of ``z^na A(z)``; real dtype when all are real)."""
        return np.roots(self.a)

    def _check_u(self, u: ArrayLike) -> NDArray:
        return as_signal(u, "u")

    def simulate(self, u: ArrayLike) -> NDArray[np.float64]:
        """Simulated output ``ŷ = B(q)/A(q) u`` from zero initial conditions.

        Parameters
        ----------
        u : array_like
            Input sequence (1-D, finite).

        Returns
        -------
        numpy.ndarray
        """
        u = self._check_u(u)
        return lfilter(self.b, self.a, u)

    def predict(self, y: ArrayLike, u: ArrayLike) -> NDArray[np.float64]:
        """One-step-ahead prediction ``ŷ_k = (1 - A(q)) y_k + B(q) u_k``.

        Samples before the start of the record are taken as zero.

        Parameters
        ----------
        y, u : array_like
            Measured output and input, same length.

        Returns
        -------
        numpy.ndarray
        """
        y = as_signal(y, "y")
        u = self._check_u(u)
        check_same_length(y, "y", u, "u")
        ar = np.concatenate(([0.0], -self.a[1:]))
        return lfilter(ar, [1.0], y) + lfilter(self.b, [1.0], u)

    def fit_percent(self, y: ArrayLike, u: ArrayLike, *,
                    mode: str = "simulation") -> float:
        """NRMSE fit (percent) of the simulated or one-step predicted output.

        Parameters
        ----------
        y, u : array_like
            Measured output and input, same length.
        mode : {"simulation", "prediction"}, optional
            Compare ``y`` with :meth:`simulate` or :meth:`predict`.

        Returns
        -------
        float
        """
        if mode == "simulation":
            y_arr = as_signal(y, "y")
            u_arr = self._check_u(u)
            check_same_length(y_arr, "y", u_arr, "u")
            return fit_percent(y_arr, self.simulate(u_arr))
        if mode == "prediction":
            return fit_percent(y, self.predict(y, u))
        raise IdentificationError(
            f"mode: expected 'simulation' or 'prediction', got {mode!r}")

    def to_tf(self) -> control.TransferFunction:
        """Discrete transfer function ``B(z)/A(z)`` with sample time :attr:`dt`."""
        n = max(self.a.size, self.b.size)
        num = np.zeros(n)
        den = np.zeros(n)
        num[: self.b.size] = self.b
        den[: self.a.size] = self.a
        return control.tf(num, den, self.dt)

    def to_continuous(self) -> control.TransferFunction:
        """Continuous transfer function by inverse zero-order hold (:func:`d2c_zoh`).

        Requires ``nk + nb - 1 <= na`` (numerator not longer than the
        denominator in powers of ``q^-1``); otherwise the model has poles at
        ``z = 0`` (pure delays) and :class:`IdentificationError` is raised.
        Discrete poles on the negative real axis are rejected too.
        """
        return d2c_zoh(self.to_tf())


def arx(y: ArrayLike, u: ArrayLike, *, na: int, nb: int, nk: int = 1,
        dt: float = 1.0) -> ARXResult:
    """Estimate an ARX(na, nb, nk) model by linear least squares.

    Parameters
    ----------
    y : array_like
        Measured output, 1-D.
    u : array_like
        Input, 1-D, same length as ``y``.
    na : int
        Number of autoregressive coefficients (>= 0).
    nb : int
        Number of input coefficients (>= 1).
    nk : int, optional
        Input delay in samples (>= 0).  Default 1 (no direct feedthrough).
    dt : float, optional
        Sample time in seconds (> 0), stored for transfer-function conversion.

    Returns
    -------
    ARXResult

    Raises
    ------
    IdentificationError
        On non-finite or mismatched data, invalid orders, a record too short
        for the requested orders, or a rank-deficient regressor (input not
        persistently exciting).

    Examples
    --------
    Noise-free data from ``y_k = 0.8 y_{k-1} + 0.5 u_{k-1} + 0.2 u_{k-2}``:

    >>> from scipy.signal import lfilter
    >>> from bondgraph.identification import prbs
    >>> u = prbs(6)
    >>> y = lfilter([0.0, 0.5, 0.2], [1.0, -0.8], u)
    >>> m = arx(y, u, na=1, nb=2, nk=1, dt=0.01)
    >>> m.a.round(12) + 0.0, m.b.round(12) + 0.0
    (array([ 1. , -0.8]), array([0. , 0.5, 0.2]))
    >>> round(m.fit_percent(y, u), 6)
    100.0
    """
    y = as_signal(y, "y")
    u = as_signal(u, "u")
    check_same_length(y, "y", u, "u")
    na = check_int(na, "na", minimum=0)
    nb = check_int(nb, "nb", minimum=1)
    nk = check_int(nk, "nk", minimum=0)
    dt = check_positive_float(dt, "dt")

    n_par = na + nb
    start = max(na, nk + nb - 1)
    n = y.size
    n_eq = n - start
    if n_eq < n_par + 1:
        raise IdentificationError(
            f"y: expected at least {start + n_par + 1} samples for ARX({na}, {nb}, {nk}) "
            f"({n_par} parameters + 1 degree of freedom after {start} initial samples), "
            f"got {n}")

    rows = np.arange(start, n)
    cols = [-y[rows - i] for i in range(1, na + 1)]
    cols += [u[rows - nk - j] for j in range(nb)]
    X = np.column_stack(cols)
    target = y[rows]

    theta, _, rank, sv = np.linalg.lstsq(X, target, rcond=None)
    if rank < n_par:
        raise IdentificationError(
            f"u: expected a persistently exciting input; the ARX({na}, {nb}, {nk}) "
            f"regressor has rank {rank} < {n_par} parameters")
    resid = target - X @ theta
    sigma2 = float(resid @ resid) / (n_eq - n_par)
    # (X^T X)^{-1} = V diag(1/s^2) V^T from the SVD of X
    _, s, vt = np.linalg.svd(X, full_matrices=False)
    cov = sigma2 * (vt.T / s**2) @ vt

    a = np.concatenate(([1.0], theta[:na]))
    b = np.concatenate((np.zeros(nk), theta[na:]))
    return ARXResult(a=readonly_copy(a), b=readonly_copy(b), na=na, nb=nb, nk=nk, dt=dt,
                     parameters=readonly_copy(theta), covariance=readonly_copy(cov),
                     noise_variance=sigma2, n_equations=int(n_eq))
