"""ARX least squares and inverse-ZOH conversion, checked against closed forms.

Reference systems are continuous transfer functions with known coefficients;
their exact zero-order-hold equivalents come from python-control
(``sample_system(..., "zoh")``), independently of the code under test.
"""

import control
import numpy as np
import pytest
from scipy.signal import lfilter

from bondgraph.identification import (ARXResult, IdentificationError, arx, d2c_zoh,
                                      fit_percent, prbs)

FS = 200.0          # Hz, sampling rate of the FLEXCAM hub experiment
DT = 1.0 / FS
HUB_GAIN, HUB_POLE = 377.8, 42.4   # G(s) = 377.8 / (s (s + 42.4)), Barbosa & Goes Eq. (3)


def _zoh(G, dt=DT):
    Gd = control.sample_system(G, dt, method="zoh")
    return np.asarray(Gd.num[0][0], float), np.asarray(Gd.den[0][0], float)


def _coeffs(G):
    """(num, den) of a SISO TF with den monic, num padded to len(den) - 1."""
    num = np.atleast_1d(np.asarray(G.num[0][0], float))
    den = np.asarray(G.den[0][0], float)
    num, den = num / den[0], den / den[0]
    out = np.zeros(den.size - 1)
    out[out.size - num.size:] = num[-out.size:] if num.size > out.size else num
    return out, den


def _simulate(num_d, den_d, u):
    """Noise-free output of the discrete ZOH model B(z)/A(z) (num shorter than den)."""
    b = np.concatenate((np.zeros(den_d.size - num_d.size), num_d))
    return lfilter(b, den_d, u)


CONTINUOUS_CASES = {
    # name: (num, den) of G(s)
    "hub_integrator": ([HUB_GAIN], [1.0, HUB_POLE, 0.0]),
    "double_integrator": ([2.0], [1.0, 0.0, 0.0]),
    "underdamped": ([100.0], [1.0, 4.0, 100.0]),
    "third_order_with_zero": ([20.0, 100.0], np.polymul([1.0, 2.0], [1.0, 2.0, 50.0])),
}


@pytest.mark.parametrize("name", CONTINUOUS_CASES)
def test_roundtrip_continuous_zoh_arx_d2c(name):
    num_c, den_c = CONTINUOUS_CASES[name]
    G = control.tf(num_c, den_c)
    n = len(den_c) - 1
    num_d, den_d = _zoh(G)
    u = prbs(9, clock_divider=2)
    y = _simulate(num_d, den_d, u)
    model = arx(y, u, na=n, nb=n, nk=1, dt=DT)
    # ARX recovers the exact ZOH polynomials (python-control's c2d)
    np.testing.assert_allclose(model.a, den_d, rtol=0, atol=1e-9)
    np.testing.assert_allclose(model.b[1:], num_d[-n:], rtol=1e-7, atol=1e-12)
    assert model.b[0] == 0.0
    assert model.noise_variance < 1e-20
    # Inverse ZOH recovers the continuous coefficients
    Gc = model.to_continuous()
    assert Gc.dt == 0
    num, den = _coeffs(Gc)
    num_true, den_true = _coeffs(G)
    scale = np.max(np.abs(den_true))
    np.testing.assert_allclose(den, den_true, rtol=1e-6, atol=1e-6 * scale)
    np.testing.assert_allclose(num, num_true, rtol=1e-6, atol=1e-6 * np.max(np.abs(num_true)))


def test_d2c_zoh_statespace_and_tf_agree():
    G = control.tf([HUB_GAIN], [1.0, HUB_POLE, 0.0])
    Gd_ss = control.sample_system(control.ss(G), DT, method="zoh")
    Gc_ss = d2c_zoh(Gd_ss)
    assert isinstance(Gc_ss, control.StateSpace) and Gc_ss.dt == 0
    np.testing.assert_allclose(np.sort(np.linalg.eigvals(Gc_ss.A).real), [-HUB_POLE, 0.0],
                               atol=1e-8)
    w = np.array([1.0, 10.0, 100.0])
    np.testing.assert_allclose(Gc_ss(1j * w).ravel(), HUB_GAIN / (1j * w * (1j * w + HUB_POLE)),
                               rtol=1e-9)


def test_hub_validation_output_measurement_noise():
    """Hub 377.8/(s(s+42.4)), ZOH at 200 Hz, PRBS input, white measurement noise on y.

    Output-error noise makes least-squares ARX biased; the bias grows with the
    noise-to-signal ratio.  Here the noise std is 3e-4 rad (about the
    quantisation noise of a 4096-count encoder, 2*pi/4096/sqrt(12) = 4.4e-4)
    against an output std of about 1.6 rad, small enough that the bias is well
    inside 2 %.  Record: one period of an order-10 PRBS held 4 samples
    (4092 samples = 20.46 s), amplitude 1 V.
    """
    G = control.tf([HUB_GAIN], [1.0, HUB_POLE, 0.0])
    num_d, den_d = _zoh(G)
    u = prbs(10, clock_divider=4)
    assert u.size == 4092
    y_clean = control.forced_response(control.tf(num_d, den_d, DT), U=u).outputs
    noise_std = 3e-4
    y = y_clean + noise_std * np.random.default_rng(2024).standard_normal(u.size)

    model = arx(y, u, na=2, nb=2, nk=1, dt=DT)
    Gc = model.to_continuous()
    num, den = _coeffs(Gc)
    poles = np.sort(np.roots(den).real)
    gain_err = num[-1] / HUB_GAIN - 1
    pole_err = -poles[0] / HUB_POLE - 1
    assert abs(gain_err) < 0.02, gain_err
    assert abs(pole_err) < 0.02, pole_err
    assert abs(poles[1]) < 0.02 * HUB_POLE          # integrator pole near s = 0
    # the fitted model's frequency response matches the hub over 1..200 rad/s
    w = np.logspace(0, np.log10(200), 30)
    G_true = HUB_GAIN / (1j * w * (1j * w + HUB_POLE))
    np.testing.assert_allclose(np.abs(Gc(1j * w)) / np.abs(G_true), 1.0, atol=0.02)
    # and its simulation reproduces the measured output
    assert model.fit_percent(y, u) > 98.0
    # the noise-variance estimate is of the order of the measurement noise
    # (the equation error is e_k + a1 e_{k-1} + a2 e_{k-2}, variance (1+a1^2+a2^2) s^2)
    expected = (1 + den_d[1] ** 2 + den_d[2] ** 2) * noise_std**2
    assert model.noise_variance == pytest.approx(expected, rel=0.15)


def test_hub_validation_equation_error_noise_is_consistent():
    """Equation-error noise A(q) y = B(q) u + e (white e, std 1e-3): ARX is consistent.

    Record: one period of an order-12 PRBS held 4 samples (16380 samples = 81.9 s).
    """
    num_d, den_d = _zoh(control.tf([HUB_GAIN], [1.0, HUB_POLE, 0.0]))
    u = prbs(12, clock_divider=4)
    e = 1e-3 * np.random.default_rng(7).standard_normal(u.size)
    y = _simulate(num_d, den_d, u) + lfilter([1.0], den_d, e)
    model = arx(y, u, na=2, nb=2, nk=1, dt=DT)
    num, den = _coeffs(model.to_continuous())
    poles = np.sort(np.roots(den).real)
    assert num[-1] == pytest.approx(HUB_GAIN, rel=0.02)
    assert -poles[0] == pytest.approx(HUB_POLE, rel=0.02)
    assert model.noise_variance == pytest.approx(1e-6, rel=0.05)
    # One-step prediction errors are the white equation noise itself
    resid = y - model.predict(y, u)
    assert np.std(resid[10:]) == pytest.approx(1e-3, rel=0.05)


def test_covariance_matches_monte_carlo_spread():
    """sigma^2 (X^T X)^-1 predicts the spread of estimates over noise realisations."""
    rng = np.random.default_rng(11)
    u = prbs(9)
    y0 = lfilter([0.0, 0.5], [1.0, -0.9], u)
    sigma = 0.05
    est, reported = [], []
    for _ in range(200):
        y = y0 + lfilter([1.0], [1.0, -0.9], sigma * rng.standard_normal(u.size))
        m = arx(y, u, na=1, nb=1, nk=1)
        est.append(m.parameters)
        reported.append(m.std)
    est = np.array(est)
    np.testing.assert_allclose(est.mean(axis=0), [-0.9, 0.5], atol=0.01)
    np.testing.assert_allclose(est.std(axis=0), np.mean(reported, axis=0), rtol=0.15)


def test_result_structure_and_conversions():
    u = prbs(8)
    y = lfilter([0.0, 0.0, 0.3, 0.1], [1.0, -1.2, 0.5], u)   # nk = 2, nb = 2, na = 2
    m = arx(y, u, na=2, nb=2, nk=2, dt=0.1)
    assert isinstance(m, ARXResult)
    np.testing.assert_allclose(m.a, [1.0, -1.2, 0.5], atol=1e-10)
    np.testing.assert_allclose(m.b, [0.0, 0.0, 0.3, 0.1], atol=1e-10)
    assert m.parameters.shape == (4,) and m.covariance.shape == (4, 4)
    with pytest.raises(AttributeError):
        m.na = 3  # frozen
    with pytest.raises(ValueError):
        m.a[0] = 2.0  # read-only array
    # Simulation equals the generating filter; fit 100 %
    np.testing.assert_allclose(m.simulate(u), y, atol=1e-9)
    assert m.fit_percent(y, u, mode="prediction") == pytest.approx(100.0)
    # Discrete TF: z^-2 (0.3 + 0.1 z^-1)/(1 - 1.2 z^-1 + 0.5 z^-2)
    tf = m.to_tf()
    #              = (0.3 z + 0.1) / (z^3 - 1.2 z^2 + 0.5 z): the delay adds a pole at z = 0
    assert tf.dt == 0.1
    np.testing.assert_allclose(np.sort_complex(tf.poles()),
                               np.sort_complex(np.r_[np.roots([1.0, -1.2, 0.5]), 0.0]),
                               atol=1e-9)
    np.testing.assert_allclose(tf(np.exp(0.3j)), (0.3 * np.exp(-0.6j) + 0.1 * np.exp(-0.9j))
                               / (1 - 1.2 * np.exp(-0.3j) + 0.5 * np.exp(-0.6j)), rtol=1e-8)
    np.testing.assert_allclose(np.sort_complex(m.poles),
                               np.sort_complex(np.roots([1.0, -1.2, 0.5])), atol=1e-9)
    # A two-sample delay has discrete poles at z = 0: no continuous ZOH equivalent
    with pytest.raises(IdentificationError, match="z = 0"):
        m.to_continuous()


def test_fit_percent_closed_form():
    y = np.array([1.0, 2.0, 3.0, 4.0])        # mean 2.5, ||y - mean|| = sqrt(5)
    assert fit_percent(y, y) == 100.0
    assert fit_percent(y, np.full(4, 2.5)) == pytest.approx(0.0)
    assert fit_percent(y, y + 1.0) == pytest.approx(100 * (1 - 2 / np.sqrt(5)))


# ---------------------------------------------------------------- bad input
U = prbs(6)
Y = lfilter([0.0, 0.5], [1.0, -0.8], U)


@pytest.mark.parametrize("call, match", [
    (lambda: arx(Y[:5], U[:5], na=2, nb=2, nk=1), r"y: expected at least 7 samples for ARX\(2, 2, 1\)"),
    (lambda: arx(Y, U, na=40, nb=30, nk=1), r"y: expected at least 111 samples"),
    (lambda: arx(Y, U[:-1], na=1, nb=1), r"u: expected the same length as y \(63\), got 62"),
    (lambda: arx(np.r_[Y[:-1], np.nan], U, na=1, nb=1), r"y: expected finite values, found 1 NaN/inf"),
    (lambda: arx(Y, np.r_[np.inf, U[1:]], na=1, nb=1), r"u: expected finite values"),
    (lambda: arx(Y, U, na=-1, nb=1), r"na: expected an integer >= 0"),
    (lambda: arx(Y, U, na=1, nb=0), r"nb: expected an integer >= 1"),
    (lambda: arx(Y, U, na=1, nb=1, nk=-1), r"nk: expected an integer >= 0"),
    (lambda: arx(Y, U, na=1.5, nb=1), r"na: expected an integer"),
    (lambda: arx(Y, U, na=1, nb=1, dt=0.0), r"dt: expected a finite number > 0"),
    (lambda: arx(Y.reshape(-1, 1), U, na=1, nb=1), r"y: expected a 1-D array"),
    (lambda: arx(Y, np.ones_like(U), na=1, nb=2), r"u: expected a persistently exciting input"),
    (lambda: fit_percent(np.ones(4), np.zeros(4)), r"y: expected a non-constant signal"),
    (lambda: fit_percent(Y, Y[:-2]), r"y_model: expected the same length as y"),
    (lambda: arx(Y, U, na=1, nb=1).fit_percent(Y, U, mode="x"), r"mode: expected 'simulation' or 'prediction'"),
    (lambda: d2c_zoh(control.tf([1.0], [1.0, 1.0])), r"sys: expected a discrete-time system"),
    (lambda: d2c_zoh(control.tf([1.0], [1.0, 0.5], True)), r"sys: expected a discrete-time system"),
    (lambda: d2c_zoh(control.tf([1.0], [1.0, 0.5], 0.1)), r"sys: expected no discrete pole on the negative real axis"),
    (lambda: d2c_zoh(np.eye(2)), r"sys: expected a control.TransferFunction"),
])
def test_bad_input(call, match):
    with pytest.raises(IdentificationError, match=match):
        call()
