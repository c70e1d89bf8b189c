"""FRF estimation (H1, H2, coherence) and spectral peak picking.

Reference: a two-mode lightly damped system with known closed form

    G(s) = w1^2/(s^2 + 2 z1 w1 s + w1^2) + 0.5 w2^2/(s^2 + 2 z2 w2 s + w2^2),
    f1 = 5 Hz, z1 = 0.02;  f2 = 12 Hz, z2 = 0.03,

driven by white Gaussian noise (unit variance) sampled at fs = 200 Hz, 2**16
samples (327.7 s), simulated with python-control ``forced_response`` (input
linearly interpolated between samples; this scales the sampled FRF by
sinc^2(f/fs), under 2.3 % for f <= 15 Hz, and adds no phase).
"""

import control
import numpy as np
import pytest
from scipy.signal import coherence as scipy_coherence

from bondgraph.identification import (FRFResult, IdentificationError, SpectralPeaks,
                                      estimate_frf, find_modal_peaks)

FS = 200.0
N = 2**16
NPERSEG = 4096          # 0.049 Hz resolution, 31 Hann segments with 50 % overlap
F1, Z1, F2, Z2 = 5.0, 0.02, 12.0, 0.03
W1, W2 = 2 * np.pi * F1, 2 * np.pi * F2
FD = np.array([F1 * np.sqrt(1 - Z1**2), F2 * np.sqrt(1 - Z2**2)])   # damped frequencies, Hz
OUTPUT_NOISE_STD = 0.5


def G_true(s):
    return W1**2 / (s**2 + 2 * Z1 * W1 * s + W1**2) + 0.5 * W2**2 / (s**2 + 2 * Z2 * W2 * s + W2**2)


@pytest.fixture(scope="module")
def records():
    s = control.tf("s")
    G = G_true(s)
    rng = np.random.default_rng(1)
    x = rng.standard_normal(N)
    t = np.arange(N) / FS
    y = control.forced_response(G, T=t, U=x).outputs
    y_noisy = y + OUTPUT_NOISE_STD * rng.standard_normal(N)
    return x, y, y_noisy


@pytest.fixture(scope="module")
def frf_clean(records):
    x, y, _ = records
    return estimate_frf(x, y, fs=FS, nperseg=NPERSEG)


@pytest.fixture(scope="module")
def frf_noisy(records):
    x, _, y_noisy = records
    return estimate_frf(x, y_noisy, fs=FS, nperseg=NPERSEG)


def test_result_metadata(frf_clean):
    r = frf_clean
    assert isinstance(r, FRFResult)
    assert r.nperseg == NPERSEG and r.noverlap == NPERSEG // 2
    assert r.n_segments == 1 + (N - NPERSEG) // (NPERSEG // 2) == 31
    assert r.resolution == pytest.approx(FS / NPERSEG)
    np.testing.assert_allclose(r.frequencies, np.arange(NPERSEG // 2 + 1) * FS / NPERSEG)
    np.testing.assert_allclose(r.omega, 2 * np.pi * r.frequencies)
    with pytest.raises(AttributeError):
        r.fs = 1.0
    with pytest.raises(ValueError):
        r.h1[3] = 0.0


def test_h1_matches_true_frf_without_noise(frf_clean):
    r = frf_clean
    band = (r.frequencies >= 0.5) & (r.frequencies <= 15.0)
    G = G_true(1j * r.omega)
    ratio = np.abs(r.h1) / np.abs(G)
    # noise-free coherence ~ 1; leakage at the 5 Hz peak (half-power width
    # 0.2 Hz = 4 bins) lowers it to ~0.94 there
    assert np.median(r.coherence[band]) > 0.999
    assert np.min(r.coherence[band]) > 0.9
    good = band & (r.coherence > 0.95)
    assert good.sum() > 0.9 * band.sum()
    np.testing.assert_allclose(ratio[good], 1.0, atol=0.05)
    assert np.median(np.abs(ratio[band] - 1)) < 0.01
    np.testing.assert_allclose(np.angle(r.h1[good] / G[good]), 0.0, atol=0.1)
    # without noise H1 and H2 coincide up to leakage: H2 = H1 / coherence
    np.testing.assert_allclose(r.h2[band], r.h1[band] / r.coherence[band], rtol=1e-9)


def test_coherence_reduced_by_output_noise_as_predicted(frf_clean, frf_noisy):
    r, rn = frf_clean, frf_noisy
    band = (r.frequencies >= 0.5) & (r.frequencies <= 15.0)
    # white input (variance 1) and white output noise (variance sn^2) have flat
    # one-sided PSDs 2/fs and 2 sn^2/fs, so gamma^2 = |G|^2 / (|G|^2 + sn^2)
    G = G_true(1j * rn.omega)
    gamma2 = np.abs(G) ** 2 / (np.abs(G) ** 2 + OUTPUT_NOISE_STD**2)
    assert np.mean(np.abs(rn.coherence[band] - gamma2[band])) < 0.05
    low = band & (gamma2 < 0.5)          # around the 7.46 Hz anti-resonance
    assert low.sum() > 10
    assert np.all(rn.coherence[low] < r.coherence[low])
    assert np.median(rn.coherence[low]) < 0.5
    # H1 stays unbiased by output noise; H2 is biased up by 1/gamma^2
    assert np.median(np.abs(rn.h1[band]) / np.abs(G[band])) == pytest.approx(1.0, abs=0.02)
    assert np.median(np.abs(rn.h2[low]) / np.abs(G[low])) > 1.5
    assert np.median(np.abs(rn.h2[band]) * gamma2[band] / np.abs(G[band])) == pytest.approx(1.0, abs=0.03)
    # |H1| <= |H2| always
    assert np.all(np.abs(rn.h1[1:]) <= np.abs(rn.h2[1:]) * (1 + 1e-12))


def test_coherence_equals_scipy_coherence(records, frf_noisy):
    x, _, y_noisy = records
    f, c = scipy_coherence(x, y_noisy, fs=FS, nperseg=NPERSEG)
    np.testing.assert_allclose(frf_noisy.frequencies, f)
    np.testing.assert_allclose(frf_noisy.coherence[1:], c[1:], atol=1e-12)


@pytest.mark.parametrize("which", ["clean", "noisy"])
@pytest.mark.parametrize("interpolate", [True, False])
def test_autospectrum_peaks_at_damped_natural_frequencies(which, interpolate, frf_clean, frf_noisy):
    r = frf_clean if which == "clean" else frf_noisy
    peaks = find_modal_peaks(r.frequencies, r.gyy, prominence=10.0, fmax=40.0,
                             interpolate=interpolate)
    assert isinstance(peaks, SpectralPeaks)
    assert peaks.frequencies.size == 2
    np.testing.assert_allclose(peaks.frequencies, FD, rtol=0.02)
    assert np.all(peaks.prominences > 10.0)
    # peak values are those of the autospectrum near the peak bins
    np.testing.assert_allclose(peaks.values, r.gyy[peaks.indices], rtol=0.5)


def test_peaks_on_exact_resonance_curve():
    """|G(j w)|^2 on a 0.05 Hz grid: interpolated peaks at the resonance f sqrt(1 - 2 z^2)."""
    f = np.arange(0.05, 30.0, 0.05)
    mag2 = np.abs(G_true(2j * np.pi * f)) ** 2
    p = find_modal_peaks(f, mag2, n_peaks=2)
    # modes are far apart, so each peak is essentially its mode's resonance
    f_res = np.array([F1 * np.sqrt(1 - 2 * Z1**2), F2 * np.sqrt(1 - 2 * Z2**2)])
    np.testing.assert_allclose(p.frequencies, f_res, rtol=2e-3)
    # n_peaks keeps the most prominent (in dB the 12 Hz peak is, as it rises
    # above the deep 7.46 Hz anti-resonance and the high-frequency roll-off)
    one = find_modal_peaks(f, mag2, n_peaks=1)
    assert p.prominences[1] > p.prominences[0]
    assert one.frequencies[0] == pytest.approx(f_res[1], rel=2e-3)
    # band limits exclude a peak
    hi = find_modal_peaks(f, mag2, fmin=8.0)
    assert hi.frequencies.size == 1 and hi.frequencies[0] == pytest.approx(f_res[1], rel=2e-3)
    # complex input is treated as |H|^2
    pc = find_modal_peaks(f, G_true(2j * np.pi * f))
    np.testing.assert_allclose(pc.frequencies, p.frequencies)


def test_default_segment_length():
    x = np.random.default_rng(3).standard_normal(10000)
    r = estimate_frf(x, 3.0 * x, fs=10.0)
    assert r.nperseg == 1024 and r.n_segments == 18
    np.testing.assert_allclose(r.h1[1:], 3.0, rtol=1e-9)
    np.testing.assert_allclose(r.coherence[1:], 1.0, rtol=1e-9)


X = np.random.default_rng(0).standard_normal(512)


@pytest.mark.parametrize("call, match", [
    (lambda: estimate_frf(X, X[:-1], fs=1.0), r"y: expected the same length as x \(512\), got 511"),
    (lambda: estimate_frf(X, np.r_[X[:-1], np.nan], fs=1.0), r"y: expected finite values"),
    (lambda: estimate_frf(X, X, fs=0.0), r"fs: expected a finite number > 0"),
    (lambda: estimate_frf(X, X, fs=1.0, nperseg=1024), r"nperseg: expected at most the record length 512"),
    (lambda: estimate_frf(X, X, fs=1.0, nperseg=512), r"x: expected a record long enough for at least 2"),
    (lambda: estimate_frf(X, X, fs=1.0, nperseg=64, noverlap=64), r"noverlap: expected an integer in \[0, 63\]"),
    (lambda: estimate_frf(X[:1], X[:1], fs=1.0), r"nperseg: expected at most the record length 1"),
    (lambda: find_modal_peaks([0.0, 1.0, 2.0], [1.0, 2.0]), r"spectrum: expected the same length as frequencies"),
    (lambda: find_modal_peaks([0.0, 2.0, 1.0], [1.0, 2.0, 1.0]), r"frequencies: expected a strictly increasing grid"),
    (lambda: find_modal_peaks([0.0, 1.0, 2.0], [1.0, -2.0, 1.0]), r"spectrum: expected non-negative"),
    (lambda: find_modal_peaks([0.0, 1.0, 2.0], [1.0, np.inf, 1.0]), r"spectrum: expected finite values"),
    (lambda: find_modal_peaks([0.0, 1.0, 2.0], [1.0, 2.0, 1.0], prominence=0), r"prominence: expected a finite number > 0"),
    (lambda: find_modal_peaks([0.0, 1.0, 2.0], [1.0, 2.0, 1.0], fmin=5.0), r"fmin, fmax: expected a band containing at least 3"),
])
def test_bad_input(call, match):
    with pytest.raises(IdentificationError, match=match):
        call()
