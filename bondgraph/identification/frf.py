"""Non-parametric frequency-response estimation and spectral peak picking.

With input ``x`` and output ``y`` (Bendat & Piersol; Eq. (35) of Soares,
Góes & Souza):

.. math::

    H_1 = \\frac{G_{xy}}{G_{xx}}, \\qquad H_2 = \\frac{G_{yy}}{G_{yx}}, \\qquad
    \\gamma^2_{xy} = \\frac{|G_{xy}|^2}{G_{xx} G_{yy}},

where the one-sided auto- and cross-spectral densities are Welch averages
(:func:`scipy.signal.welch`, :func:`scipy.signal.csd`).  ``H1`` is unbiased
by output noise, ``H2`` by input noise; ``|H1| <= |H2|`` and
``|H1| / |H2| = gamma^2``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.signal import csd, find_peaks, welch

from ._validation import (IdentificationError, as_signal, check_int, check_positive_float,
                          check_same_length, readonly_copy)

__all__ = ["FRFResult", "estimate_frf", "SpectralPeaks", "find_modal_peaks"]


@dataclass(frozen=True, eq=False)
class FRFResult:
    """Welch-averaged frequency-response estimate.

    Attributes
    ----------
    frequencies : numpy.ndarray
        Frequencies in Hz (``0 .. fs/2``).
    h1, h2 : numpy.ndarray
        Complex FRF estimates ``Gxy/Gxx`` and ``Gyy/Gyx``; NaN where the
        denominator is zero (e.g. the DC bin after mean removal).
    coherence : numpy.ndarray
        Ordinary coherence ``|Gxy|^2 / (Gxx Gyy)`` in ``[0, 1]``.
    gxx, gyy : numpy.ndarray
        One-sided input and output autospectral densities (units²/Hz).
    gxy : numpy.ndarray
        One-sided cross-spectral density ``E[conj(X) Y]``.
    fs : float
        Sampling frequency in Hz.
    nperseg, noverlap, n_segments : int
        Segment length, overlap and number of averaged segments.
    window : str or tuple
        Window specification passed to SciPy.

    Examples
    --------
    Returned by :func:`estimate_frf`; here for a pure gain of 3:

    >>> import numpy as np
    >>> x = np.random.default_rng(1).standard_normal(2048)
    >>> r = estimate_frf(x, 3.0 * x, fs=50.0, nperseg=128)
    >>> float(r.frequencies[-1]), r.n_segments, r.noverlap, r.resolution
    (25.0, 31, 64, 0.390625)
    >>> bool(np.allclose(r.h1[1:], 3.0) and np.allclose(r.coherence[1:], 1.0))
    True
    """

    frequencies: NDArray[np.float64]
    h1: NDArray[np.complex128]
    h2: NDArray[np.complex128]
    coherence: NDArray[np.float64]
    gxx: NDArray[np.float64]
    gyy: NDArray[np.float64]
    gxy: NDArray[np.complex128]
    fs: float
    nperseg: int
    noverlap: int
    n_segments: int
    window: Any

    @property
    def omega(self) -> NDArray[np.float64]:
        """Frequencies in rad/s (``2 pi f``)."""
        return 2.0 * np.pi * self.frequencies

    @property
    def resolution(self) -> float:
        """Frequency spacing ``fs / nperseg`` in Hz."""
        return self.fs / self.nperseg


def estimate_frf(x: ArrayLike, y: ArrayLike, *, fs: float,
                 nperseg: int | None = None, noverlap: int | None = None,
                 window: str | tuple = "hann", detrend: str | bool = "constant"
                 ) -> FRFResult:
    """Estimate ``H1``, ``H2`` and coherence from input/output records.

    Parameters
    ----------
    x : array_like
        Input (excitation) record, 1-D.
    y : array_like
        Output (response) record, same length as ``x``.
    fs : float
        Sampling frequency in Hz (> 0).
    nperseg : int, optional
        Samples per Welch segment.  Default: the largest power of two not
        exceeding ``len(x) / 8`` (about 15 averages with 50 % overlap), at
        least 16.
    noverlap : int, optional
        Overlapping samples between segments, ``0 <= noverlap < nperseg``.
        Default ``nperseg // 2``.
    window : str or tuple, optional
        Window passed to :func:`scipy.signal.get_window` (default Hann).
    detrend : str or False, optional
        Per-segment detrending passed to SciPy (default ``"constant"``).

    Returns
    -------
    FRFResult

    Raises
    ------
    IdentificationError
        On non-finite or mismatched records, ``fs <= 0``, a segment length
        larger than the record, or fewer than two averaged segments (the
        coherence of a single segment is identically 1).

    Examples
    --------
    A pure gain of 2 with a one-sample delay, driven by white noise:

    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> x = rng.standard_normal(4096)
    >>> y = 2.0 * np.concatenate(([0.0], x[:-1]))
    >>> r = estimate_frf(x, y, fs=100.0, nperseg=256)
    >>> r.n_segments, r.resolution
    (31, 0.390625)
    >>> bool(np.allclose(np.abs(r.h1[1:20]), 2.0, rtol=0.02))
    True
    >>> bool(np.all(r.coherence[1:20] > 0.99))
    True
    """
    x = as_signal(x, "x")
    y = as_signal(y, "y")
    check_same_length(x, "x", y, "y")
    fs = check_positive_float(fs, "fs")
    n = x.size
    if nperseg is None:
        nperseg = max(16, 2 ** int(np.floor(np.log2(max(n / 8.0, 1.0)))))
    nperseg = check_int(nperseg, "nperseg", minimum=2)
    if nperseg > n:
        raise IdentificationError(
            f"nperseg: expected at most the record length {n}, got {nperseg} "
            f"(record too short for this segment length)")
    if noverlap is None:
        noverlap = nperseg // 2
    noverlap = check_int(noverlap, "noverlap", minimum=0, maximum=nperseg - 1)
    n_segments = 1 + (n - nperseg) // (nperseg - noverlap)
    if n_segments < 2:
        raise IdentificationError(
            f"x: expected a record long enough for at least 2 averaged segments of "
            f"{nperseg} samples (overlap {noverlap}), i.e. at least "
            f"{2 * nperseg - noverlap} samples, got {n}")

    kw = dict(fs=fs, window=window, nperseg=nperseg, noverlap=noverlap, detrend=detrend)
    try:
        f, gxx = welch(x, **kw)
        _, gyy = welch(y, **kw)
        _, gxy = csd(x, y, **kw)
    except ValueError as exc:           # an unknown window name, a window of the wrong length
        raise IdentificationError(f"window: scipy refused {window!r}: {exc}") from None
    if not np.any(gxx):
        raise IdentificationError(
            "x: the input has no power at any frequency (a constant or zero record, removed by "
            "detrend): H1 and H2 would be NaN everywhere; excite the system with a varying input")
    with np.errstate(divide="ignore", invalid="ignore"):
        h1 = gxy / gxx
        h2 = gyy / np.conj(gxy)
        coh = np.abs(gxy) ** 2 / (gxx * gyy)
    h1 = np.where(gxx > 0, h1, np.nan)
    h2 = np.where(np.abs(gxy) > 0, h2, np.nan)
    coh = np.where((gxx > 0) & (gyy > 0), np.clip(coh, 0.0, 1.0), 0.0)
    return FRFResult(frequencies=readonly_copy(f), h1=readonly_copy(h1, complex),
                     h2=readonly_copy(h2, complex), coherence=readonly_copy(coh),
                     gxx=readonly_copy(gxx), gyy=readonly_copy(gyy),
                     gxy=readonly_copy(gxy, complex), fs=fs, nperseg=nperseg,
                     noverlap=noverlap, n_segments=int(n_segments), window=window)


@dataclass(frozen=True, eq=False)
class SpectralPeaks:
    """Peaks picked in a spectrum, sorted by frequency.

    Attributes
    ----------
    frequencies : numpy.ndarray
        Peak frequencies (same unit as the input grid), refined by parabolic
        interpolation when requested.
    values : numpy.ndarray
        Spectrum value at each peak (interpolated when requested).
    indices : numpy.ndarray
        Index of each peak's grid sample.
    prominences : numpy.ndarray
        Prominence of each peak in dB (``10 log10`` of the spectrum).

    Examples
    --------
    Returned by :func:`find_modal_peaks`:

    >>> import numpy as np
    >>> f = np.arange(0, 20, 0.25)
    >>> p = find_modal_peaks(f, 1 / ((f - 3.3)**2 + 0.04) + 0.5 / ((f - 7.1)**2 + 0.04))
    >>> p.indices, np.round(p.frequencies, 1), np.round(p.prominences, 1)
    (array([13, 28]), array([3.3, 7.1]), array([23.7, 14. ]))
    """

    frequencies: NDArray[np.float64]
    values: NDArray[np.float64]
    indices: NDArray[np.int64]
    prominences: NDArray[np.float64]


def find_modal_peaks(frequencies: ArrayLike, spectrum: ArrayLike, *,
                     prominence: float = 10.0, n_peaks: int | None = None,
                     fmin: float | None = None, fmax: float | None = None,
                     distance: int | None = None, interpolate: bool = True
                     ) -> SpectralPeaks:
    """Pick resonance peaks in an autospectrum (or ``|H|**2``) for modal frequencies.

    Peaks are located with :func:`scipy.signal.find_peaks` on
    ``10 log10(spectrum)``, so ``prominence`` is in dB.  Each peak is refined
    by fitting a parabola through the dB values of the peak sample and its
    two neighbours.

    Parameters
    ----------
    frequencies : array_like
        Strictly increasing frequency grid (any unit).
    spectrum : array_like
        Non-negative spectrum (a power quantity) on that grid; complex input
        is replaced by its squared magnitude.
    prominence : float, optional
        Minimum peak prominence in dB (> 0), default 10 dB.
    n_peaks : int, optional
        Keep only the ``n_peaks`` most prominent peaks.
    fmin, fmax : float, optional
        Search band (inclusive).
    distance : int, optional
        Minimum separation in samples between peaks.
    interpolate : bool, optional
        Refine frequency and value by parabolic interpolation (default True).

    Returns
    -------
    SpectralPeaks

    Examples
    --------
    Two exact Lorentzian lines at 3.3 Hz and 7.1 Hz on a 0.25 Hz grid:

    >>> import numpy as np
    >>> f = np.arange(0, 20, 0.25)
    >>> s = 1 / ((f - 3.3)**2 + 0.04) + 0.5 / ((f - 7.1)**2 + 0.04)
    >>> p = find_modal_peaks(f, s)
    >>> p.indices
    array([13, 28])
    >>> np.round(p.frequencies, 1)
    array([3.3, 7.1])
    """
    f = as_signal(frequencies, "frequencies", min_length=3)
    raw = np.asarray(spectrum)
    if np.iscomplexobj(raw):
        raw = np.abs(raw) ** 2
    s = as_signal(raw, "spectrum")
    check_same_length(f, "frequencies", s, "spectrum")
    if np.any(np.diff(f) <= 0):
        raise IdentificationError("frequencies: expected a strictly increasing grid")
    if np.any(s < 0):
        raise IdentificationError("spectrum: expected non-negative values (a power spectrum)")
    prominence = check_positive_float(prominence, "prominence")
    if n_peaks is not None:
        n_peaks = check_int(n_peaks, "n_peaks", minimum=1)
    if distance is not None:
        distance = check_int(distance, "distance", minimum=1)

    tiny = np.finfo(float).tiny
    db = 10.0 * np.log10(np.maximum(s, tiny))
    lo = 0 if fmin is None else int(np.searchsorted(f, float(fmin), side="left"))
    hi = f.size if fmax is None else int(np.searchsorted(f, float(fmax), side="right"))
    if hi - lo < 3:
        raise IdentificationError(
            f"fmin, fmax: expected a band containing at least 3 grid points, got "
            f"[{fmin}, {fmax}] with {max(hi - lo, 0)} points")
    # Search only inside the band: samples at its edges cannot be peaks.
    idx, props = find_peaks(db[lo:hi], prominence=prominence, distance=distance)
    idx = idx + lo
    prom = props["prominences"]
    if n_peaks is not None and idx.size > n_peaks:
        keep = np.sort(np.argsort(prom)[::-1][:n_peaks])
        idx, prom = idx[keep], prom[keep]

    freqs = f[idx].astype(float)
    vals = s[idx].astype(float)
    if interpolate:
        for j, k in enumerate(idx):
            if 0 < k < f.size - 1:
                c2, c1, c0 = np.polyfit(f[k - 1:k + 2] - f[k], db[k - 1:k + 2], 2)
                if c2 < 0:
                    df = -c1 / (2 * c2)
                    if abs(df) <= max(f[k] - f[k - 1], f[k + 1] - f[k]):
                        freqs[j] = f[k] + df
                        vals[j] = 10.0 ** ((c0 + c1 * df + c2 * df * df) / 10.0)
    return SpectralPeaks(frequencies=readonly_copy(freqs), values=readonly_copy(vals),
                         indices=readonly_copy(idx, np.int64), prominences=readonly_copy(prom))
