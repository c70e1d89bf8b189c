"""PRBS: maximum-length sequence properties checked against closed forms."""

import numpy as np
import pytest

from bondgraph.identification import IdentificationError, prbs, prbs_period


@pytest.mark.parametrize("order", range(2, 17))
def test_period_balance_autocorrelation_spectrum(order):
    n = 2**order - 1
    x = prbs(order, periods=2)
    assert x.size == 2 * n
    one = x[:n]
    # Exactly periodic with period 2**order - 1 and no shorter period
    np.testing.assert_array_equal(x[n:], one)
    assert not any(np.array_equal(one, np.roll(one, k)) for k in range(1, min(n, 64)))
    # Balance: 2**(order-1) ones and one fewer minus ones
    assert np.count_nonzero(one == 1.0) == 2 ** (order - 1)
    assert np.count_nonzero(one == -1.0) == 2 ** (order - 1) - 1
    # Two-valued circular autocorrelation: 1 at lag 0, -1/N elsewhere
    X = np.fft.fft(one)
    r = np.fft.ifft(np.abs(X) ** 2).real / n
    assert r[0] == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(r[1:], -1.0 / n, atol=1e-12)
    # Flat spectrum: |X_k|^2 = N + 1 for every k != 0, |X_0|^2 = 1
    np.testing.assert_allclose(np.abs(X[1:]) ** 2, n + 1, rtol=1e-9)
    assert abs(X[0]) ** 2 == pytest.approx(1.0)


def test_amplitude_offset_and_clock_divider():
    a, c, k = 0.3, 1.5, 5
    base = prbs(7)
    x = prbs(7, amplitude=a, offset=c, clock_divider=k)
    assert x.size == prbs_period(7, clock_divider=k) == 127 * k
    assert set(np.unique(x)) == {c - a, c + a}
    # each bit held k samples
    np.testing.assert_array_equal(x.reshape(-1, k), np.repeat(x[::k, None], k, axis=1))
    np.testing.assert_allclose(x[::k], c + a * base)
    # mean of one period: offset + a/N
    assert x.mean() == pytest.approx(c + a / 127)


def test_length_truncates_periodic_extension():
    x = prbs(5, clock_divider=3, length=200)
    full = prbs(5, clock_divider=3, periods=3)
    assert x.size == 200
    np.testing.assert_array_equal(x, full[:200])


def test_initial_state_gives_circular_shift():
    x = prbs(6)
    y = prbs(6, state=[1, 0, 0, 1, 1, 0])
    assert not np.array_equal(x, y)
    shifts = [k for k in range(x.size) if np.array_equal(np.roll(x, k), y)]
    assert len(shifts) == 1


def test_large_order_only_generates_requested_length():
    x = prbs(31, length=1000)
    assert x.size == 1000
    assert set(np.unique(x)) == {-1.0, 1.0}


@pytest.mark.parametrize("kwargs, match", [
    (dict(order=1), r"order: expected an integer in \[2, 32\], got 1"),
    (dict(order=33), r"order: expected an integer in \[2, 32\], got 33"),
    (dict(order=4.0), r"order: expected an integer"),
    (dict(order=4, amplitude=0.0), r"amplitude: expected a finite number > 0"),
    (dict(order=4, amplitude=np.inf), r"amplitude"),
    (dict(order=4, offset=np.nan), r"offset: expected a finite number"),
    (dict(order=4, clock_divider=0), r"clock_divider: expected an integer >= 1"),
    (dict(order=4, periods=0), r"periods: expected an integer >= 1"),
    (dict(order=4, periods=2, length=10), r"periods: expected None when length is given"),
    (dict(order=4, length=0), r"length: expected an integer >= 1"),
    (dict(order=4, state=[0, 0, 0, 0]), r"state: expected 4 bits"),
    (dict(order=4, state=[1, 0, 1]), r"state: expected 4 bits"),
])
def test_bad_arguments(kwargs, match):
    with pytest.raises(IdentificationError, match=match):
        prbs(**kwargs)


def test_error_is_value_error():
    with pytest.raises(ValueError):
        prbs_period(40)
