"""Measurement records for grey-box identification: :class:`TimeData`, :class:`FrequencyData`.

Both are frozen, hold read-only arrays and check their contents on
construction (finite values, consistent lengths, positive sample time or
frequencies), so :func:`~bondgraph.identification.greybox_fit` can trust them.

Examples
--------
>>> TimeData([0.0, 1.0], [0.0, 0.5], 0.01).time
array([0.  , 0.01])
>>> FrequencyData([1.0, 2.0], [1.0, 0.5j]).response.dtype
dtype('complex128')
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ._validation import IdentificationError, check_positive_float, finite_array, readonly_copy
from .frf import FRFResult

__all__ = ["TimeData", "FrequencyData"]


@dataclass(frozen=True, eq=False)
class TimeData:
    """Sampled input/output record on a uniform grid.

    Parameters
    ----------
    u : array_like
        Input samples, shape ``(N,)`` or ``(N, m)`` (one column per input).
    y : array_like
        Output samples, shape ``(N,)`` or ``(N, p)`` (one column per output).
    dt : float
        Sample time in seconds.

    Raises
    ------
    IdentificationError
        On NaN/inf samples, mismatched lengths, fewer than 2 samples or
        ``dt <= 0``.

    Examples
    --------
    >>> d = TimeData([0.0, 1.0, 1.0], [0.0, 0.0, 0.5], 0.01)
    >>> d.n_samples, d.u.shape, d.y.shape
    (3, (3, 1), (3, 1))
    >>> TimeData([0.0, float("nan")], [0.0, 0.0], 0.01)
    Traceback (most recent call last):
    ...
    bondgraph.identification.IdentificationError: u: expected finite values, found 1 NaN/inf entries
    """

    u: NDArray[np.float64]
    y: NDArray[np.float64]
    dt: float

    def __post_init__(self) -> None:
        u = finite_array(self.u, "u")
        y = finite_array(self.y, "y")
        u = u.reshape(u.shape[0], -1) if u.ndim == 2 else u[:, None]
        y = y.reshape(y.shape[0], -1) if y.ndim == 2 else y[:, None]
        if u.shape[0] != y.shape[0]:
            raise IdentificationError(
                f"y: expected the same number of samples as u ({u.shape[0]}), got {y.shape[0]}")
        if u.shape[0] < 2:
            raise IdentificationError(f"u: expected at least 2 samples, got {u.shape[0]}")
        object.__setattr__(self, "u", readonly_copy(u))
        object.__setattr__(self, "y", readonly_copy(y))
        object.__setattr__(self, "dt", check_positive_float(self.dt, "dt"))

    @property
    def n_samples(self) -> int:
        """Number of samples ``N``."""
        return int(self.u.shape[0])

    @property
    def time(self) -> NDArray[np.float64]:
        """Sample times ``k dt``."""
        return np.arange(self.n_samples, dtype=np.float64) * float(self.dt)


@dataclass(frozen=True, eq=False)
class FrequencyData:
    """Complex frequency-response samples of one input/output channel.

    Parameters
    ----------
    omega : array_like
        Angular frequencies in rad/s, ``> 0`` and distinct.
    response : array_like of complex
        ``H(j omega_k)``.
    weights : array_like, optional
        Non-negative weights of the squared errors (e.g. the coherence).

    Examples
    --------
    >>> d = FrequencyData([1.0, 2.0], [1 + 0j, 0.5 - 0.5j])
    >>> d.weights
    array([1., 1.])
    """

    omega: NDArray[np.float64]
    response: NDArray[np.complex128]
    weights: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        w = finite_array(self.omega, "omega", ndim=(1,))
        h = finite_array(self.response, "response", dtype=complex, ndim=(1,))
        if h.shape != w.shape:
            raise IdentificationError(
                f"response: expected the same length as omega ({w.size}), got {h.size}")
        if w.size < 1:
            raise IdentificationError("omega: expected at least 1 frequency, got 0")
        if np.any(w <= 0):
            raise IdentificationError("omega: expected angular frequencies > 0 rad/s")
        if np.unique(w).size != w.size:
            raise IdentificationError("omega: expected distinct frequencies")
        if self.weights is None:
            wt = np.ones(w.size)
        else:
            wt = finite_array(self.weights, "weights", ndim=(1,))
            if wt.shape != w.shape:
                raise IdentificationError(
                    f"weights: expected the same length as omega ({w.size}), got {wt.size}")
            if np.any(wt < 0) or not np.any(wt > 0):
                raise IdentificationError("weights: expected non-negative values, not all zero")
        object.__setattr__(self, "omega", readonly_copy(w))
        object.__setattr__(self, "response", readonly_copy(h, complex))
        object.__setattr__(self, "weights", readonly_copy(wt))

    @classmethod
    def from_frf(cls, frf: FRFResult, *, fmin: float | None = None, fmax: float | None = None,
                 estimator: str = "h1", coherence_weights: bool = True) -> "FrequencyData":
        """Frequency data from a Welch FRF estimate, within ``[fmin, fmax]`` Hz.

        Bins at 0 Hz and bins where the estimate is undefined (NaN) are dropped.

        Parameters
        ----------
        frf : FRFResult
        fmin, fmax : float, optional
            Band in Hz (inclusive).
        estimator : {"h1", "h2"}
        coherence_weights : bool
            Weight each bin by its coherence (default) or equally.

        Examples
        --------
        >>> import numpy as np
        >>> from bondgraph.identification import estimate_frf
        >>> x = np.random.default_rng(1).standard_normal(2048)
        >>> d = FrequencyData.from_frf(estimate_frf(x, 3.0 * x, fs=100.0, nperseg=128), fmax=10.0)
        >>> d.omega.size, bool(np.allclose(d.response, 3.0))
        (12, True)
        """
        if not isinstance(frf, FRFResult):
            raise IdentificationError(f"frf: expected an FRFResult, got {type(frf).__name__}")
        if estimator not in ("h1", "h2"):
            raise IdentificationError(f"estimator: expected 'h1' or 'h2', got {estimator!r}")
        f = frf.frequencies
        h = frf.h1 if estimator == "h1" else frf.h2
        keep = (f > 0) & np.isfinite(h)
        if fmin is not None:
            keep &= f >= float(fmin)
        if fmax is not None:
            keep &= f <= float(fmax)
        if not np.any(keep):
            raise IdentificationError(
                f"fmin, fmax: no usable FRF bin in [{fmin}, {fmax}] Hz")
        wt = frf.coherence[keep] if coherence_weights else None
        return cls(2 * np.pi * f[keep], h[keep], wt)
