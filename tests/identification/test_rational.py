"""Rational fit (Levy + Sanathanan-Koerner, the role of MATLAB invfreqs).

Exact-recovery cases use closed-form transfer functions with prescribed
poles; the noisy case fits an H1 estimate computed from simulated time data.
"""

import control
import numpy as np
import pytest

from bondgraph.identification import (IdentificationError, RationalFit, estimate_frf,
                                      fit_rational, fit_rational_detailed)


def modal_den(wn, zeta):
    """Monic denominator with poles -z w +- j w sqrt(1 - z^2)."""
    roots = []
    for w, z in zip(wn, zeta):
        roots += [complex(-z * w, w * np.sqrt(1 - z**2)), complex(-z * w, -w * np.sqrt(1 - z**2))]
    return np.real(np.poly(roots)), np.array(roots)


def max_rel_pole_error(found, true):
    found = np.asarray(found)
    assert found.size == len(true)
    return max(np.min(np.abs(found - p)) / abs(p) for p in true)


# FLEXCAM tip-deflection modes of Barbosa & Goes Table 2 (2.4, 7.7, 16.0 rad/s),
# given light damping, and a numerator with the non-minimum-phase zero pairs
# -2.5 +- 11.2j and 2.5 +- 11.2j (|z|^2 = 131.69).
DEN6, POLES6 = modal_den([2.4, 7.7, 16.0], [0.01, 0.02, 0.03])
NUM6 = -0.0117 * np.polymul([1.0, 5.0, 131.69], [1.0, -5.0, 131.69])
ZEROS6 = np.array([-2.5 + 11.2j, -2.5 - 11.2j, 2.5 + 11.2j, 2.5 - 11.2j])

# Two-mode system: 5 Hz (z = 0.02) and 12 Hz (z = 0.03)
W1, W2 = 2 * np.pi * 5.0, 2 * np.pi * 12.0
DEN4, POLES4 = modal_den([W1, W2], [0.02, 0.03])
NUM4 = np.polyadd(W1**2 * np.poly(POLES4[2:]).real, 0.5 * W2**2 * np.poly(POLES4[:2]).real)


@pytest.mark.parametrize("sk_iterations", [0, 30])
def test_exact_recovery_sixth_order(sk_iterations):
    w = np.logspace(-1, np.log10(50.0), 300)
    h = np.polyval(NUM6, 1j * w) / np.polyval(DEN6, 1j * w)
    r = fit_rational_detailed(w, h, num_order=4, den_order=6, sk_iterations=sk_iterations)
    assert isinstance(r, RationalFit) and r.converged
    assert max_rel_pole_error(r.poles, POLES6) < 1e-6
    assert max_rel_pole_error(r.zeros, ZEROS6) < 1e-6
    np.testing.assert_allclose(r.den, DEN6, rtol=1e-6, atol=1e-9 * np.abs(DEN6).max())
    np.testing.assert_allclose(r.num, NUM6, rtol=1e-6, atol=1e-9 * np.abs(NUM6).max())
    assert r.weighted_rms_error < 1e-9 * np.sqrt(np.mean(np.abs(h) ** 2))


def test_exact_recovery_fourteenth_order():
    """The order used with invfreqs in Soares, Goes & Souza: 7 modes, 12 real zeros."""
    den14, poles14 = modal_den([2.4, 7.7, 16.0, 30.0, 45.0, 70.0, 100.0], [0.02] * 7)
    zeros12 = -np.array([1.0, 3.0, 5.0, 8.0, 12.0, 20.0, 35.0, 50.0, 60.0, 80.0, 90.0, 110.0])
    num12 = np.real(np.poly(zeros12))
    w = np.logspace(-1, np.log10(200.0), 2000)
    h = np.polyval(num12, 1j * w) / np.polyval(den14, 1j * w)
    r = fit_rational_detailed(w, h, num_order=12, den_order=14)
    assert max_rel_pole_error(r.poles, poles14) < 1e-6


def test_exact_recovery_fourth_order_returns_continuous_tf():
    w = 2 * np.pi * np.linspace(0.5, 30.0, 400)
    h = np.polyval(NUM4, 1j * w) / np.polyval(DEN4, 1j * w)
    G = fit_rational(w, h, num_order=2, den_order=4)
    assert isinstance(G, control.TransferFunction) and G.dt == 0
    assert max_rel_pole_error(G.poles(), POLES4) < 1e-6
    np.testing.assert_allclose(G(1j * w), h, rtol=1e-8)


def test_without_frequency_scaling_still_solves_small_problem():
    w = np.linspace(0.1, 10.0, 60)
    h = 4.0 / ((1j * w) ** 2 + 0.4j * w + 4.0)
    r = fit_rational_detailed(w, h, num_order=0, den_order=2, scale=False)
    np.testing.assert_allclose(r.den, [1.0, 0.4, 4.0], rtol=1e-9)


def test_integrator_pole_recovered():
    # hub 377.8 / (s (s + 42.4)), data away from w = 0
    w = np.logspace(-1, 3, 200)
    h = 377.8 / (1j * w * (1j * w + 42.4))
    r = fit_rational_detailed(w, h, num_order=0, den_order=2, stable=True)
    np.testing.assert_allclose(r.den, [1.0, 42.4, 0.0], atol=1e-8)
    np.testing.assert_allclose(r.num, [377.8], rtol=1e-9)
    assert r.reflected_poles == 0


def test_zero_weight_points_are_ignored():
    w = np.logspace(-1, np.log10(50.0), 300)
    h = np.polyval(NUM6, 1j * w) / np.polyval(DEN6, 1j * w)
    weights = np.ones_like(w)
    corrupt = np.arange(0, 300, 7)
    h = h.copy()
    h[corrupt] = 100.0 + 50.0j                 # garbage at zero coherence
    weights[corrupt] = 0.0
    r = fit_rational_detailed(w, h, num_order=4, den_order=6, weights=weights)
    assert max_rel_pole_error(r.poles, POLES6) < 1e-6


def test_stable_option_reflects_unstable_poles():
    # Poles 0.3 +- 5j and -1 +- 12j; reflecting keeps |H(jw)|, only phase changes
    unstable = np.array([0.3 + 5j, 0.3 - 5j, -1 + 12j, -1 - 12j])
    den = np.real(np.poly(unstable))
    num = np.array([2.0, 150.0])
    w = np.linspace(0.5, 30.0, 300)
    h = np.polyval(num, 1j * w) / np.polyval(den, 1j * w)
    free = fit_rational_detailed(w, h, num_order=1, den_order=4)
    assert max_rel_pole_error(free.poles, unstable) < 1e-6        # fits what is there
    r = fit_rational_detailed(w, h, num_order=1, den_order=4, stable=True)
    assert r.reflected_poles == 2
    expected = np.array([-0.3 + 5j, -0.3 - 5j, -1 + 12j, -1 - 12j])
    assert max_rel_pole_error(r.poles, expected) < 1e-6
    assert np.all(r.tf.poles().real < 0)


def test_noisy_frf_weighted_by_coherence_recovers_poles():
    """H1 from time data: white-noise input (unit variance), fs = 200 Hz, 2**16 samples,
    white output noise std 0.5, Welch with 4096-sample Hann segments; fit 0.5-30 Hz
    with the coherence as weights."""
    fs = 200.0
    G = control.tf(NUM4, DEN4)
    rng = np.random.default_rng(1)
    x = rng.standard_normal(2**16)
    y = control.forced_response(G, T=np.arange(x.size) / fs, U=x).outputs
    y = y + 0.5 * rng.standard_normal(x.size)
    r = estimate_frf(x, y, fs=fs, nperseg=4096)
    band = (r.frequencies >= 0.5) & (r.frequencies <= 30.0)
    assert np.min(r.coherence[band]) < 0.2          # the data really are noisy somewhere
    fit = fit_rational_detailed(r.omega[band], r.h1[band], num_order=2, den_order=4,
                                weights=r.coherence[band], stable=True)
    assert fit.converged
    assert max_rel_pole_error(fit.poles, POLES4) < 0.01
    # damped natural frequencies within 0.5 %
    np.testing.assert_allclose(np.sort(np.abs(fit.poles.imag))[::2],
                               np.sort(np.abs(POLES4.imag))[::2], rtol=5e-3)


W = np.linspace(0.1, 10.0, 20)
H = 1.0 / (1j * W + 1.0)


@pytest.mark.parametrize("call, match", [
    (lambda: fit_rational(W, H[:-1], num_order=0, den_order=1), r"h: expected the same length as omega \(20\), got 19"),
    (lambda: fit_rational(W, np.r_[H[:-1], np.nan], num_order=0, den_order=1), r"h: expected finite values"),
    (lambda: fit_rational(np.r_[W[:-1], np.inf], H, num_order=0, den_order=1), r"omega: expected finite values"),
    (lambda: fit_rational(-W, H, num_order=0, den_order=1), r"omega: expected angular frequencies >= 0"),
    (lambda: fit_rational(np.ones(20), H, num_order=0, den_order=1), r"omega: expected distinct frequencies"),
    (lambda: fit_rational(W, H, num_order=-1, den_order=1), r"num_order: expected an integer >= 0"),
    (lambda: fit_rational(W, H, num_order=0, den_order=2.5), r"den_order: expected an integer"),
    (lambda: fit_rational(W[:3], H[:3], num_order=3, den_order=4), r"omega: expected enough frequency points for 8 unknowns"),
    (lambda: fit_rational(W, H, num_order=0, den_order=1, weights=-np.ones(20)), r"weights: expected non-negative"),
    (lambda: fit_rational(W, H, num_order=0, den_order=1, weights=np.ones(3)), r"weights: expected the same length as omega"),
    (lambda: fit_rational(W, H, num_order=0, den_order=1, tol=0.0), r"tol: expected a finite number > 0"),
    (lambda: fit_rational(W, H, num_order=0, den_order=1, sk_iterations=-1), r"sk_iterations: expected an integer >= 0"),
])
def test_bad_input(call, match):
    with pytest.raises(IdentificationError, match=match):
        call()
