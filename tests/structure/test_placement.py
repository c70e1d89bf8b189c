"""Sensor placement on the pinned-free beam and the FLEXCAM paper form.

References written here: the pinned-free mode shape
``phi(x) = sin(b x) + (sin(b L)/sinh(b L)) sinh(b x)`` with ``b L`` a root of
``sin l cosh l - cos l sinh l = 0`` (``tan l = tanh l``), both found with
:func:`scipy.optimize.brentq`; the natural frequency
``omega = (b L)^2 sqrt(EI/(rhoA L^4))``.  A deflection sensor at a node of
mode 2 loses mode 2: the transfer function from the hub torque has zeros at
``+-j omega_2`` that cancel its poles.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import scipy.optimize

import bondgraph as bg
from bondgraph.beam import modal_beam
from bondgraph.beam.fragment import beam_fragment
from bondgraph.structure import (StructureError, position_sweep, sensor_placement,
                                 zero_structure)

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "models"))
import flexcam  # noqa: E402

EI, RHOA, L = 2.0, 0.5, 1.5


def pinned_free_lambda(k: int) -> float:
    f = lambda lam: np.sin(lam) * np.cosh(lam) - np.cos(lam) * np.sinh(lam)  # noqa: E731
    guess = (k + 0.25) * np.pi
    return scipy.optimize.brentq(f, guess - 0.5, guess + 0.5)


def mode_nodes(k: int) -> list[float]:
    lam = pinned_free_lambda(k)
    b = lam / L
    phi = lambda x: np.sin(b * x) + np.sin(lam) / np.sinh(lam) * np.sinh(b * x)  # noqa: E731
    xs = np.linspace(1e-6, L, 4001)
    v = phi(xs)
    return [scipy.optimize.brentq(phi, a, c) for a, c, fa, fc in
            zip(xs[:-1], xs[1:], v[:-1], v[1:]) if fa * fc < 0]


@pytest.fixture(scope="module")
def beam():
    return modal_beam(EI, RHOA, L, 3, boundary="pinned-free")


def test_nodes_of_mode_two_match_the_root_finder(beam):
    sp = sensor_placement(beam)
    for k in (1, 2, 3):
        np.testing.assert_allclose(sp.nodes[k - 1], mode_nodes(k), rtol=1e-9)
    x2 = sp.nodes[1][0]
    assert sp.observed_at(x2) == (1, 3)
    assert sp.observed_at(0.3 * L) == (1, 2, 3)
    assert sp.observed_at(0.0) == ()               # the pin: no deflection at all
    assert "mode 2: x = " in str(sp)
    with pytest.raises(StructureError, match="kind"):
        sensor_placement(beam, kind="acceleration")


def _torque_model(beam, gains):
    frag = beam_fragment(beam, name="link", rigid=False)
    g = bg.BondGraph("torque_beam")
    g.add(bg.Se("tau"), frag.graph)
    g.connect("tau", "link.hub")
    y = sum(gi * bg.displacement(f"link.k_{i + 1}") for i, gi in enumerate(gains))
    outs = {"y": y}
    outs.update({f"q{i + 1}": bg.displacement(f"link.k_{i + 1}") for i in range(len(gains))})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return bg.derive(g, outputs=outs), dict(frag.values)


def test_camera_at_a_node_of_mode_two_cancels_it(beam):
    sp = sensor_placement(beam)
    x2 = mode_nodes(2)[0]
    m, vals = _torque_model(beam, sp.gain(x2))
    w2 = pinned_free_lambda(2) ** 2 * np.sqrt(EI / (RHOA * L**4))
    z = zero_structure(m, "tau", "y", max_states=0).zeros_at(vals)
    assert np.min(np.abs(z - 1j * w2)) < 1e-6 * w2 and np.min(np.abs(z + 1j * w2)) < 1e-6 * w2
    # elsewhere no zero sits on mode 2's pole
    m2, vals2 = _torque_model(beam, sp.gain(0.3 * L))
    z2 = zero_structure(m2, "tau", "y", max_states=0).zeros_at(vals2)
    assert np.min(np.abs(z2 - 1j * w2)) > 1e-3 * w2
    # the sweep along the beam: the same cancellation, seen from the modal outputs
    sweep = position_sweep(m, "tau", ["q1", "q2", "q3"], [sp.gain(x2)], [x2], vals)
    assert np.min(np.abs(np.array(sweep.zeros[0]) - 1j * w2)) < 1e-6 * w2


@pytest.fixture(scope="module")
def flexcam_paper():
    g, outs, params = flexcam.build(3, formulation="paper")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = bg.derive(g, outputs={"y": outs["y"], "theta": outs["theta"],
                                  **{f"q{i}": bg.displacement(f"link.k_{i}") for i in (1, 2, 3)}})
    return m, {p.name: params[p.name] for p in m.parameters}


def test_flexcam_tip_is_non_minimum_phase_and_hub_angle_is_not(flexcam_paper):
    m, vals = flexcam_paper
    tip = zero_structure(m, "hub.e_in", "y", max_states=0)
    hub = zero_structure(m, "hub.e_in", "theta", max_states=0)
    assert tip.rhp_zeros(vals).size > 0 and not tip.minimum_phase(vals)
    assert hub.rhp_zeros(vals).size == 0


def test_flexcam_sweep_turns_non_minimum_phase_along_the_link(flexcam_paper):
    m, vals = flexcam_paper
    beam = modal_beam(*flexcam.link_properties(), 3, boundary="pinned-free")
    xs = np.linspace(0.02, 1.0, 25) * beam.L
    sp = sensor_placement(beam, xs)
    sweep = position_sweep(m, "hub.e_in", ["q1", "q2", "q3"], sp.gains, xs, vals)
    assert not sweep.nonminimum_phase[0] and sweep.nonminimum_phase[-1]
    assert 0 < sweep.first_nonminimum_phase < beam.L
    assert "non-minimum-phase from x = " in str(sweep)
