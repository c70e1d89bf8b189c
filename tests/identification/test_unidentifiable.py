"""Issue 23, item 11 (audit I14, I18, I28, I38, I39, I40): identification refuses what it cannot identify."""

import numpy as np
import pytest

import bondgraph as bg
from bondgraph.identification import (FrequencyData, IdentificationError, TimeData, estimate_frf,
                                      fit_rational, greybox_fit)
from bondgraph.numeric import compile_plant


@pytest.fixture(scope="module")
def msd():
    g = bg.BondGraph("msd")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
    for a, b in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "k")]:
        g.connect(a, b)
    return compile_plant(bg.derive(g, outputs={"x": bg.displacement("k")}))


START = {"m": 1.0, "b": 0.5, "k": 3.0}


def test_zero_time_data_refused(msd):
    """I39: zero input and output gave success=True, rank 0, estimates = initial values."""
    with pytest.raises(IdentificationError, match="the input is zero at every sample"):
        greybox_fit(msd, TimeData(np.zeros(200), np.zeros(200), 0.05), free=["m", "b", "k"],
                    initial=START)


def test_zero_frequency_data_refused(msd):
    """I38: all-zero frequency data gave success=True with b = 2e6, NaN standard errors."""
    w = np.linspace(0.1, 10, 50)
    with pytest.raises(IdentificationError, match="the frequency response is zero at every frequency"):
        greybox_fit(msd, FrequencyData(w, np.zeros(50, complex)), free=["m", "b", "k"], initial=START)


def test_max_nfev_zero_refused(msd):
    """I40: scipy's ValueError escaped."""
    w = np.linspace(0.1, 10, 50)
    h = 1.0 / (-(w**2) + 0.4j * w + 4.0)          # m = 1, b = 0.4, k = 4 by hand
    with pytest.raises(IdentificationError, match="max_nfev: expected None or an integer >= 1, got 0"):
        greybox_fit(msd, FrequencyData(w, h), free=["m", "b", "k"], initial=START, max_nfev=0)


def test_fit_rational_overflow_refused():
    """I28: omega ~ 1e300 returned -inf coefficients."""
    w = np.linspace(1e299, 1e300, 20)
    with pytest.raises(IdentificationError, match="omega: the coefficients of the fitted B\\(s\\)/A\\(s\\) overflow"):
        fit_rational(w, 1.0 / (1j * w + 1.0), num_order=0, den_order=2, scale=False)
    with pytest.raises(IdentificationError, match="overflow"):   # the audit's call
        fit_rational([1e300, 2e300, 3e300], [1, 0.7, 0.5], num_order=1, den_order=2)


def test_estimate_frf_constant_input_refused():
    """I14: a constant input gave all-NaN H1/H2 without a word."""
    with pytest.raises(IdentificationError, match="x: the input has no power at any frequency"):
        estimate_frf(np.ones(1024), np.random.default_rng(0).standard_normal(1024), fs=100.0)


def test_estimate_frf_unknown_window_refused():
    """I18: scipy's ValueError escaped (the name is only looked up, never run)."""
    rng = np.random.default_rng(0)
    x = rng.standard_normal(1024)
    with pytest.raises(IdentificationError, match="window: scipy refused '__import__"):
        estimate_frf(x, x, fs=100.0, window='__import__("os")')
