"""FLEXCAM and the hub with two appendages, against beam and rigid-body theory."""

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.tf import transfer_function

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "models"))
import appendages  # noqa: E402
import flexcam  # noqa: E402

T = appendages.TABLE1


def numeric_tf(model, params, inp, out):
    ss = model.state_space()
    G = transfer_function(ss.A, ss.B, ss.C, ss.D, input=inp, output=out,
                          input_names=ss.input_names, output_names=ss.output_names)
    # one output's TF uses a subset of the model's parameters: declare the rest as known
    G = dataclasses.replace(G, known_parameters=ss.known_parameters)
    return G, G.subs({p: params[p.name] for p in model.parameters})


@pytest.fixture(scope="module")
def app3():
    g, outs, params = appendages.build(4)
    return bg.derive(g, outputs=outs), params


def test_appendages_frequencies_converge_to_exact_unconstrained_modes():
    from bondgraph.beam import hub_beam_modes
    exact = hub_beam_modes(T["E"] * T["I"], T["rho"] * T["A"], T["L"], 3, hub_inertia=T["I_hub"],
                           hub_radius=T["r"], n_arms=2).omega
    errs = []
    for n in (3, 4, 6):
        _, _, w2, _ = appendages.system_modes(n)
        errs.append(np.max(np.abs(np.sqrt(w2[1:4]) - exact) / exact))
    assert errs[0] < 1e-5 and errs[2] < errs[0]
    # bounds from beam theory: between the clamped-free and pinned-free first modes
    W = np.sqrt(T["E"] * T["I"] / (T["rho"] * T["A"] * T["L"] ** 4))
    assert 1.875104**2 * W < exact[0] < 3.926602**2 * W


def test_collocated_zeros_are_the_clamped_arm_frequencies(app3):
    # hub angle / torque: zeros = modes with the hub held still = clamped-free arms
    model, params = app3
    _, G = numeric_tf(model, params, "tau", "e_p")
    W = np.sqrt(T["E"] * T["I"] / (T["rho"] * T["A"] * T["L"] ** 4))
    z = np.sort(np.abs(G.zeros()))[::2][:2]
    np.testing.assert_allclose(z, np.array([1.875104, 4.694091]) ** 2 * W, rtol=1e-4)


def test_rigid_body_inertia_at_low_frequency(app3):
    model, params = app3
    _, G = numeric_tf(model, params, "tau", "e_p")
    I_tot = T["I_hub"] + 2 * T["rho"] * T["A"] * ((T["r"] + T["L"]) ** 3 - T["r"] ** 3) / 3
    s = 1e-3j
    assert (G(s) * s**2).real == pytest.approx(1 / I_tot, rel=1e-5)


def test_tip_accelerometer_is_non_minimum_phase(app3):
    # seed 002: non-collocated sensors have right-half-plane zeros
    model, params = app3
    _, G = numeric_tf(model, params, "tau", "e_ac")
    assert np.any(G.zeros().real > 1e-6)


def test_flexcam_paper_form_is_sixth_order_and_even_numerator():
    g, outs, params = flexcam.build(3, formulation="paper")
    model = bg.derive(g, outputs=outs)
    G, Gn = numeric_tf(model, params, "hub.e_in", "y")
    assert G.den.degree() == 6
    # undamped modes: the numerator has only even powers (printed as noise in the paper)
    num = Gn.num
    assert all(c == 0.0 for c in num[::-1][1::2])
    # pinned-free frequencies of the link appear as the open-circuit resonances when the
    # motor damping is removed (back-emf and Beq are the only coupling to damping)
    EI, rhoA, L = flexcam.link_properties()
    W = np.sqrt(EI / (rhoA * L**4))
    den0 = G.subs({**{p: params[p.name] for p in model.parameters},
                   sympy.Symbol("Beq", positive=True): 0.0, sympy.Symbol("km", positive=True): 0.0})
    w = np.sort(np.abs(den0.poles()))[::2]
    np.testing.assert_allclose(w, np.array([3.926602, 7.068583, 10.210176]) ** 2 * W, rtol=1e-6)
