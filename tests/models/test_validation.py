"""Identification loop validated on synthetic data from our own models (truth known).

* SRV-02 hub (seed 000): PRBS at 200 Hz, potentiometer noise; ARX(2,2,1) +
  inverse ZOH recovers the continuous gain and pole, the grey-box fit recovers
  ``Jm`` and ``Beq``.  The truth is the model's own ``theta/e_in``, whose
  coefficients are computed here from the hand-derived Eq. (1) expressions
  (SRV-02 manual), not from the code under test; the data are that hand-derived
  transfer function ZOH-sampled by scipy.
* FLEXCAM (system formulation, 3 modes, 2 % modal damping): band-limited noise
  into the motor, tip deflection with camera noise, sampled at 1 kHz; the FRF
  peaks and the rational fit land on the model's modal frequencies / poles
  (eigenvalues of its A matrix); the data come from scipy ``lsim`` on the
  plant's matrices, not from the simulator the grey-box fit uses.
"""

import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.signal

import bondgraph as bg
from bondgraph.identification import (FrequencyData, TimeData, arx, estimate_frf,
                                      find_modal_peaks, fit_rational_detailed, greybox_fit, prbs)
from bondgraph.numeric import compile_plant

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "models"))
import flexcam  # noqa: E402
import srv02  # noqa: E402

# ---------------------------------------------------------------- SRV-02 hub
HUB_DT = 0.005            # 200 Hz, as in seed 000
HUB_N = 8000              # 40 s record
HUB_NOISE = 2e-4          # rad, white measurement noise on theta (about 0.01 deg)


def hub_truth():
    """Gain K and pole a of theta/e_in = K / (s (s + a)) from Eq. (1), by hand."""
    P = srv02.PARAMETERS
    Rm, kt, km, em, eg, Kg, Jm, Beq = (P[n] for n in "Rm kt km eta_m eta_g Kg Jm Beq".split())
    a2 = Rm * Jm * Kg / (em * kt)
    a1 = (Rm * Beq + eg * em * Kg**2 * kt * km) / (eg * em * Kg * kt)
    return 1.0 / a2, a1 / a2


@pytest.fixture(scope="module")
def hub():
    model = bg.derive(srv02.build(inductance=False), outputs=srv02.outputs())
    nm = compile_plant(model)
    values = {p.name: srv02.PARAMETERS[p.name] for p in model.parameters}
    plant = nm.plant(values)
    u = prbs(10, clock_divider=4, length=HUB_N)             # +-1 V, bits held 20 ms
    # data from the hand-derived K / (s (s + a)), states (theta, theta'), ZOH-sampled
    # by scipy: neither the model's matrices nor the simulator used inside the fit
    K, a = hub_truth()
    hand = (np.array([[0.0, 1.0], [0.0, -a]]), np.array([[0.0], [K]]),
            np.array([[1.0, 0.0]]), np.zeros((1, 1)))
    sysd = scipy.signal.cont2discrete(hand, HUB_DT, method="zoh")
    _, theta, _ = scipy.signal.dlsim(sysd[:4] + (HUB_DT,), u)
    theta = theta[:, 0]
    rng = np.random.default_rng(2024)
    y = theta + HUB_NOISE * rng.standard_normal(HUB_N)
    return nm, values, plant, u, y


def test_hub_truth_matches_model_transfer_function(hub):
    _, _, plant, _, _ = hub
    K, a = hub_truth()
    G = plant.to_tf(input="e_in", output="theta")
    num, den = G.num[0][0], G.den[0][0]
    assert num[-1] / den[0] == pytest.approx(K, rel=1e-9)
    np.testing.assert_allclose(den / den[0], [1.0, a, 0.0], rtol=1e-9, atol=1e-9)
    # and the numbers quoted in models/srv02.py against seed 000 Eq. (3)
    assert K == pytest.approx(375.7, abs=0.05) and a == pytest.approx(42.54, abs=0.01)


def test_hub_arx_recovers_gain_and_pole(hub):
    _, _, _, u, y = hub
    K, a = hub_truth()
    m = arx(y, u, na=2, nb=2, nk=1, dt=HUB_DT)
    Gc = m.to_continuous()
    num, den = Gc.num[0][0], Gc.den[0][0]
    K_hat = num[-1] / den[0]
    poles = np.sort(Gc.poles().real)
    assert K_hat == pytest.approx(K, rel=0.02)
    assert -poles[0] == pytest.approx(a, rel=0.02)
    assert abs(poles[1]) < 0.02 * a                    # the integrator stays near 0
    assert m.fit_percent(y, u) > 95


def test_hub_greybox_recovers_jm_and_beq(hub):
    nm, values, _, u, y = hub
    r = greybox_fit(nm, TimeData(u, y, HUB_DT), free=["Jm", "Beq"], values=values,
                    initial={"Jm": 2.0 * values["Jm"], "Beq": 0.5 * values["Beq"]},
                    input="e_in", output="theta")
    for name in ("Jm", "Beq"):
        assert r.estimates[name] == pytest.approx(values[name], rel=0.02)
        assert abs(r.estimates[name] - values[name]) < 4 * r.std_errors[name]
    assert r.noise_variance == pytest.approx(HUB_NOISE**2, rel=0.1)
    assert r.fit_percent[0] > 99


# ---------------------------------------------------------------- FLEXCAM
FC_FS = 1000.0            # Hz, measurement rate
FC_OVERSAMPLE = 4         # simulation grid 4 kHz, input linear between its samples
FC_T = 60.0               # s
FC_BAND = 200.0           # Hz, band limit of the excitation (8th-order Butterworth)
FC_NOISE = 0.02           # camera noise std relative to the tip-deflection std
FC_NPERSEG = 4096         # 0.244 Hz resolution, 28 Welch averages


@pytest.fixture(scope="module")
def flex():
    g, outs, params = flexcam.build(3, formulation="system", damping_ratio=0.02)
    model = bg.derive(g, outputs=outs)
    nm = compile_plant(model)
    values = {p.name: params[p.name] for p in model.parameters}
    plant = nm.plant(values)
    rng = np.random.default_rng(5)
    n = int(FC_T * FC_FS)
    fine = FC_FS * FC_OVERSAMPLE
    sos = scipy.signal.butter(8, FC_BAND, fs=fine, output="sos")
    uf = scipy.signal.sosfilt(sos, rng.standard_normal(n * FC_OVERSAMPLE))
    uf /= uf.std()                                           # 1 V rms
    # scipy lsim (input linear between samples) on the plant's matrices: a simulator
    # independent of the one used inside the fit
    i, j = plant.input_names.index("hub.e_in"), plant.output_names.index("y")
    t_fine = np.arange(uf.size) / fine
    _, yf, _ = scipy.signal.lsim((plant.A, plant.B[:, [i]], plant.C[[j]], plant.D[[j]][:, [i]]),
                                 uf, t_fine, interp=True)
    u, y = uf[::FC_OVERSAMPLE], yf[::FC_OVERSAMPLE]
    y = y + FC_NOISE * y.std() * rng.standard_normal(n)
    frf = estimate_frf(u, y, fs=FC_FS, nperseg=FC_NPERSEG)
    ev = np.linalg.eigvals(plant.A)                          # truth: the model's poles
    flex_poles = ev[ev.imag > 1.0]
    flex_poles = flex_poles[np.argsort(np.abs(flex_poles))]   # by natural frequency
    return nm, values, frf, flex_poles


def test_flexcam_frf_peaks_on_modal_frequencies(flex):
    _, _, frf, poles = flex
    f_modal = np.abs(poles) / (2 * np.pi)                    # ~13.6, 34.3, 65.6 Hz
    peaks = find_modal_peaks(frf.frequencies, np.abs(frf.h1) ** 2, fmin=1.0, fmax=150.0,
                             prominence=6.0)
    assert peaks.frequencies.size == 3
    np.testing.assert_allclose(np.sort(peaks.frequencies), f_modal, rtol=0.02)
    assert np.all(frf.coherence[peaks.indices] > 0.95)


def test_flexcam_rational_fit_recovers_flexible_poles(flex):
    _, _, frf, poles = flex
    band = (frf.frequencies >= 0.2) & (frf.frequencies <= 150.0)
    fit = fit_rational_detailed(frf.omega[band], frf.h1[band], num_order=5, den_order=7,
                                weights=frf.coherence[band], stable=True)
    fitted = fit.poles[fit.poles.imag > 1.0]
    assert fitted.size == 3
    for p in poles:
        assert np.min(np.abs(fitted - p)) / abs(p) < 0.01
    assert np.all(fit.poles.real < 0)


def test_flexcam_greybox_recovers_modal_stiffness(flex):
    nm, values, frf, poles = flex
    free = ["link.k_1", "link.k_2", "link.k_3"]
    start = {n: f * values[n] for n, f in zip(free, (0.85, 1.2, 0.9))}
    r = greybox_fit(nm, FrequencyData.from_frf(frf, fmin=1.0, fmax=150.0), free=free,
                    values=values, initial=start, input="hub.e_in", output="y")
    for n in free:
        assert r.estimates[n] == pytest.approx(values[n], rel=0.01)
