"""Modal beam fragments derived as bond graphs, against beam theory closed forms."""

import numpy as np
import pytest

import bondgraph as bg
from bondgraph.beam import hub_beam_modes, modal_beam
from bondgraph.beam.fragment import beam_fragment

EI, RHOA, L = 2.0, 0.5, 0.8
W = np.sqrt(EI / (RHOA * L**4))    # omega_i = (beta_i L)^2 W


def numeric(matrix, frag):
    subs = {frag.symbol(k.split(".", 1)[1]): v for k, v in frag.values.items()}
    return np.array(matrix.xreplace(subs), dtype=float)


def driven(frag, port="hub", outputs=None):
    g = bg.BondGraph("t")
    g.add(bg.Se("u"), frag.graph)
    g.connect("u", f"{frag.name}.{port}")
    return bg.derive(g, outputs=outputs or {})


@pytest.mark.parametrize("hub_inertia, betaL", [
    (1e6, (1.875104, 4.694091, 7.854757)),      # massive hub: clamped-free (tabulated)
    (0.0, (3.926602, 7.068583, 10.210176)),     # no hub: pinned-free (tabulated)
], ids=["clamped-limit", "pinned-limit"])
def test_hub_fragment_frequencies_tend_to_tabulated_limits(hub_inertia, betaL):
    frag = beam_fragment(hub_beam_modes(EI, RHOA, L, 3, hub_inertia=hub_inertia), name="b")
    model = driven(frag)
    A = numeric(model.state_space().A, frag)
    w = np.sort(np.abs(np.linalg.eigvals(A)))
    w = w[w > 1e-6][::2]                      # one of each +-j pair, rigid mode dropped
    np.testing.assert_allclose(w, np.array(betaL) ** 2 * W, rtol=2e-5 if hub_inertia else 1e-6)


def test_clamped_free_static_tip_compliance():
    # a static tip force F gives y(L) = F L^3 / (3 EI) (cantilever)
    frag = beam_fragment(modal_beam(EI, RHOA, L, 4, boundary="clamped-free"), name="b",
                         tip_port=True)
    assert frag.graph.ports == ("tip",)     # the root is clamped to ground
    g = bg.BondGraph("t")
    g.add(bg.Se("F"), frag.graph)
    g.connect("F", "b.tip")
    model = bg.derive(g, outputs={"y": frag.tip_deflection("b.")})
    ss = model.state_space()
    A, B, C = (numeric(m, frag) for m in (ss.A, ss.B, ss.C))
    dc = -(C @ np.linalg.solve(A, B))[0, 0]
    assert dc == pytest.approx(L**3 / (3 * EI), rel=1e-3)


def test_pinned_free_rigid_mode_low_frequency_inertia():
    # torque at the pin of a free beam: at low frequency the hub angle follows
    # tau / (J s^2) with J = rhoA L^3 / 3
    frag = beam_fragment(modal_beam(EI, RHOA, L, 3, boundary="pinned-free"), name="b")
    model = driven(frag, outputs={"theta": bg.displacement("b.m_0")})
    ss = model.state_space()
    A, B, C = (numeric(m, frag) for m in (ss.A, ss.B, ss.C))
    s = 1e-3j
    G = (C @ np.linalg.solve(s * np.eye(len(A)) - A, B))[0, 0]
    assert (G * s**2).real == pytest.approx(1 / (RHOA * L**3 / 3), rel=1e-5)


def test_damped_modes_get_resistors():
    frag = beam_fragment(modal_beam(EI, RHOA, L, 2, boundary="clamped-free"), name="b",
                         tip_port=True, damping_ratio=0.02)
    assert {"b.c_1", "b.c_2"} <= set(frag.values)
    assert frag.values["b.c_1"] == pytest.approx(2 * 0.02 * 1.0 * 1.875104**2 * W, rel=1e-6)
