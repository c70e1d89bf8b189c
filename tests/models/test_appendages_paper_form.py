"""The hub with two appendages written as seed 001 writes it (issue 13, item 4).

``models/appendages.py`` builds the model two ways: the coupled
Rayleigh-Ritz ``M, K`` diagonalised into system modes (one-port I and C per
mode, the ``"system"`` form) and the paper's Eqs. (15-17) with ``M`` as an
inertia field and ``K`` as a compliance field on ``(theta, eta_j)`` (the
``"paper"`` form).  Both must agree: eigenvalues to 1e-9 relative, and the
four sensor transfer functions of Eq. (26), evaluated here by hand as
``C (sI - A)^-1 B + D`` with numpy.  The frequencies are checked against the
exact unconstrained modes of the hub + arms (``hub_beam_modes``, the
transcendental frequency equation, independent of Rayleigh-Ritz) with the
tolerance of ``tests/models/test_flexible.py``: with 3 assumed modes the
Rayleigh-Ritz frequencies are within 1e-5 of the exact ones.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import bondgraph as bg

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "models"))
import appendages  # noqa: E402

T = appendages.TABLE1
SENSORS = ("e_ac", "e_p", "e_s", "e_t")


def numeric(model, params):
    """(A, B, C, D) as float arrays, outputs in the order of SENSORS."""
    ss = model.state_space()
    rows = [list(ss.output_names).index(name) for name in SENSORS]
    out = []
    for M in (ss.A, ss.B, ss.C.extract(rows, list(range(ss.C.cols))),
              ss.D.extract(rows, list(range(ss.D.cols)))):
        sub = {s: params[s.name] for s in M.free_symbols}
        out.append(np.array(M.xreplace(sub).tolist(), dtype=float).reshape(M.shape))
    return out


@pytest.fixture(scope="module")
def forms():
    out = {}
    for formulation in appendages.FORMULATIONS:
        g, outs, params = appendages.build(3, formulation=formulation)
        out[formulation] = numeric(bg.derive(g, outputs=outs), params)
    return out


def test_paper_form_is_the_coupled_mass_matrix_as_one_inertia_field():
    g, outs, params = appendages.build(3, formulation="paper")
    model = bg.derive(g, outputs=outs)
    assert model.state_names == ("p_M_1", "p_M_2", "p_M_3", "p_M_4", "q_K_1", "q_K_2", "q_K_3",
                                 "x_hub")
    flat = model.augmented.flat
    M = flat.element("M")
    assert isinstance(M, bg.IField) and M.ports == 4 and flat.element("K").ports == 3
    # I_T of Eq. (17) by hand (no tip mass): hub + two arms clamped at radius r
    rhoA, L, r = T["rho"] * T["A"], T["L"], T["r"]
    assert params["I_T"] == pytest.approx(T["I_hub"] + 2 * rhoA * ((r + L) ** 3 - r**3) / 3,
                                          rel=1e-12)
    # the torque drives the hub coordinate only: dp_theta/dt = tau, dp_eta_j/dt = -k_j eta_j
    assert str(model.rhs[0]) == "tau"
    assert [str(x) for x in model.rhs[1:4]] == [f"-k_{j}*q_K_{j}" for j in (1, 2, 3)]


def test_both_forms_have_the_same_eigenvalues(forms):
    eig = {k: np.linalg.eigvals(v[0]) for k, v in forms.items()}
    assert eig["system"].shape == eig["paper"].shape == (8,)
    scale = max(np.abs(eig["system"]).max(), 1.0)
    for form in eig:
        assert np.abs(eig[form].real).max() < 1e-9 * scale       # undamped
    wa = np.sort(np.abs(eig["system"].imag))
    wb = np.sort(np.abs(eig["paper"].imag))
    flexible = wa > 1e-6 * scale
    assert flexible.sum() == 6 and np.array_equal(flexible, wb > 1e-6 * scale)
    np.testing.assert_allclose(wb[flexible], wa[flexible], rtol=1e-9)
    assert np.abs(wb[~flexible]).max() < 1e-9 * scale           # the rigid rotation: 0, 0


def test_both_forms_have_the_same_four_sensor_transfer_functions(forms):
    def G(arrays, s):
        A, B, C, D = arrays
        return C @ np.linalg.solve(s * np.eye(A.shape[0]) - A, B) + D

    for w in (0.3, 2.0, 17.0, 80.0, 250.0, 900.0):        # rad/s, around and between modes
        s = 1j * w
        a, b = G(forms["system"], s), G(forms["paper"], s)
        assert a.shape == (4, 1)
        np.testing.assert_allclose(b, a, rtol=1e-8, atol=1e-14 * np.abs(a).max())


def test_paper_form_frequencies_are_the_exact_unconstrained_modes(forms):
    from bondgraph.beam import hub_beam_modes

    exact = hub_beam_modes(T["E"] * T["I"], T["rho"] * T["A"], T["L"], 3,
                           hub_inertia=T["I_hub"], hub_radius=T["r"], n_arms=2).omega
    w = np.sort(np.abs(np.linalg.eigvals(forms["paper"][0]).imag))[2::2]
    np.testing.assert_allclose(w, exact, rtol=1e-5)
    assert np.round(w / (2 * np.pi), 2).tolist() == [4.78, 22.36, 61.65]


def test_damped_paper_form_matches_the_damped_system_form():
    eig = []
    for formulation in appendages.FORMULATIONS:
        g, outs, params = appendages.build(3, formulation=formulation, damping_ratio=0.02)
        eig.append(np.sort_complex(np.linalg.eigvals(
            numeric(bg.derive(g, outputs=outs), params)[0])))
    flexible = np.abs(eig[0]) > 1e-6
    np.testing.assert_allclose(eig[1][flexible], eig[0][flexible], rtol=1e-9)
    # modal damping ratio 0.02 on each flexible system mode
    lam = eig[1][flexible]
    np.testing.assert_allclose(-lam.real / np.abs(lam), 0.02, rtol=1e-9)


def test_formulation_is_checked():
    with pytest.raises(ValueError, match="formulation must be 'system' or 'paper'"):
        appendages.build(3, formulation="modal")
    with pytest.raises(ValueError, match="n_system_modes truncates"):
        appendages.build(3, formulation="paper", n_system_modes=2)
    definition = appendages.model(formulation="paper")
    assert "paper formulation" in definition.description
