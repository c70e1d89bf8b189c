"""Controllers on the exported plants (python-control), checked against closed forms.

* collocated PD (k_pot, k_taco) on the hub with two flexible appendages (seed 001);
* PID on the SRV-02 hub (seed 000 Eq. 1 form);
* LQR on the FLEXCAM plant (system formulation).
"""

import sys
from pathlib import Path

import control
import numpy as np
import pytest

import bondgraph as bg
from bondgraph.numeric.control import minimal_realization, pd_place, pid_place, specs_to_poles
from bondgraph.numeric import compile_plant

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "models"))
import appendages  # noqa: E402
import flexcam  # noqa: E402
import srv02  # noqa: E402


def plant_of(graph, outputs, params):
    model = bg.derive(graph, outputs=outputs)
    return compile_plant(model).plant({p.name: params[p.name] for p in model.parameters})


def total_inertia():
    """Hub + two uniform arms clamped at radius r, about the axis (no tip mass)."""
    T = appendages.TABLE1
    rhoA = T["rho"] * T["A"]
    return T["I_hub"] + 2 * rhoA * ((T["r"] + T["L"]) ** 3 - T["r"] ** 3) / 3


def pd_loop(P, k_pot, k_taco):
    """tau = k_pot (r - e_p) - k_taco e_t on the appendages plant; r -> all outputs."""
    K = np.zeros((1, P.noutputs))
    K[0, P.output_labels.index("e_p")] = k_pot
    K[0, P.output_labels.index("e_t")] = k_taco
    return control.feedback(P, K) * k_pot


@pytest.fixture(scope="module")
def arms():
    g, outs, params = appendages.build(3)
    return plant_of(g, outs, params), params


# ---------------------------------------------------------------- helpers, closed forms
@pytest.mark.parametrize("J, poles", [(2.0, [-1.0, -3.0]), (1.5, [-0.4 + 0.9j, -0.4 - 0.9j])])
def test_pd_place_closed_form(J, poles):
    k_pot, k_taco = pd_place(J, poles)
    np.testing.assert_allclose(np.sort_complex(np.roots([J, k_taco, k_pot])),
                               np.sort_complex(poles), atol=1e-12)


def test_specs_to_poles_gives_the_overshoot():
    p = specs_to_poles(0.25, 10.0)
    G = control.tf([abs(p[0]) ** 2], np.real(np.poly(p)))
    info = control.step_info(G, T=np.linspace(0, 40, 40001))
    assert info["Overshoot"] == pytest.approx(25.0, abs=0.01)
    assert 7.0 < info["SettlingTime"] <= 10.0      # 4/(zeta wn) is a conservative estimate


@pytest.mark.parametrize("bad", [dict(J=0.0, poles=[-1, -2]), dict(J=1.0, poles=[-1]),
                                 dict(J=1.0, poles=[-1 + 1j, -2])])
def test_pd_place_rejects(bad):
    with pytest.raises(ValueError):
        pd_place(bad["J"], bad["poles"])


def test_minimal_realization_keeps_transfer_function():
    # 1/(s+1) plus an uncontrollable integrator and an unobservable mode at -5
    A = np.diag([-1.0, 0.0, -5.0])
    B = np.array([[1.0], [0.0], [1.0]])
    C = np.array([[1.0, 1.0, 0.0]])
    G = control.ss(A, B, C, 0)
    m = minimal_realization(G)
    assert m.nstates == 1
    w = np.logspace(-2, 2, 30)
    np.testing.assert_allclose(m(1j * w), 1 / (1j * w + 1), rtol=1e-12)


# ---------------------------------------------------------------- appendages: collocated PD
def test_rigid_inertia_of_the_model(arms):
    _, params = arms
    assert params["arms.m_0"] == pytest.approx(total_inertia(), rel=1e-9)


def test_pd_on_rigid_model_places_poles_exactly():
    g, outs, params = appendages.build(3, n_system_modes=0)
    outs.pop("e_s")                                   # no flexible mode, no strain
    P = plant_of(g, outs, params).to_control()
    J = total_inertia()
    poles = specs_to_poles(0.25, 10.0)
    k_pot, k_taco = pd_place(J, poles)
    cl = minimal_realization(pd_loop(P, k_pot, k_taco))
    np.testing.assert_allclose(np.sort_complex(cl.poles()), np.sort_complex(poles), rtol=1e-9)
    # closed form J s^2 + k_taco s + k_pot
    np.testing.assert_allclose(np.sort_complex(np.roots([J, k_taco, k_pot])),
                               np.sort_complex(poles), rtol=1e-12)


def test_pd_on_flexible_model(arms):
    plant, _ = arms
    P = plant.to_control()
    poles = specs_to_poles(0.25, 10.0)                # seed 001: 25 % overshoot, ~10 s
    k_pot, k_taco = pd_place(total_inertia(), poles)
    cl = minimal_realization(pd_loop(P, k_pot, k_taco))
    ev = cl.poles()
    assert cl.nstates == 8                             # rigid pair + 3 flexible pairs
    assert np.all(ev.real < 0)
    slow = np.sort_complex(ev[np.abs(ev) < 5])         # flexible modes are above 30 rad/s
    np.testing.assert_allclose(slow, np.sort_complex(poles), rtol=0.02)
    dc = cl.dcgain().ravel()
    i_p, i_ac = P.output_labels.index("e_p"), P.output_labels.index("e_ac")
    T = appendages.TABLE1
    assert dc[i_p] == pytest.approx(1.0, rel=1e-9)                 # pot loop: type 1
    assert dc[i_ac] == pytest.approx(T["r"] + T["L"], rel=1e-9)    # tip moves (r+L) per rad
    info = control.step_info(cl[i_p, 0], T=np.linspace(0, 40, 8001))
    assert info["Overshoot"] == pytest.approx(25.0, abs=2.0)


@pytest.mark.parametrize("k_pot, k_taco", [(0.017, 0.017 * 37), (0.017 * 180 / np.pi, 0.017 * 37),
                                           (50.0, 0.1), (0.01, 100.0)])
def test_collocated_pd_is_stable_for_any_positive_gains(arms, k_pot, k_taco):
    # collocated position + rate feedback is passive: every mode seen by the hub is damped
    plant, _ = arms
    cl = minimal_realization(pd_loop(plant.to_control(), k_pot, k_taco))
    assert cl.nstates == 8
    assert np.all(cl.poles().real < 0)


# ---------------------------------------------------------------- SRV-02 hub: PID
@pytest.fixture(scope="module")
def hub_tf():
    model = bg.derive(srv02.build(inductance=False), outputs=srv02.outputs())
    plant = compile_plant(model).plant({p.name: srv02.PARAMETERS[p.name] for p in model.parameters})
    return plant.to_tf(input="e_in", output="theta")


def test_pid_places_the_hub_poles(hub_tf):
    G = hub_tf
    b, den = G.num[0][0][-1], G.den[0][0]
    poles = np.concatenate((specs_to_poles(0.05, 0.3), [-30.0]))
    kp, ki, kd = pid_place(b, den, poles)
    C = control.tf([kd, kp, ki], [1, 0])
    T = control.feedback(C * G, 1)
    np.testing.assert_allclose(np.sort_complex(T.poles()), np.sort_complex(poles), rtol=1e-8)
    assert T.dcgain() == pytest.approx(1.0, rel=1e-12)
    # closed form: s^3 + (a1 + b kd) s^2 + (a0 + b kp) s + b ki = prod (s - p_i)
    np.testing.assert_allclose([1, den[1] + b * kd, den[2] + b * kp, b * ki],
                               np.real(np.poly(poles)), rtol=1e-12)
    # I-PD (P and D on the measurement): same poles, no controller zeros
    # u = ki/s (r - y) - (kp + kd s) y:  T = (ki/s) G / (1 + C G)
    T_ipd = control.feedback(control.tf([ki], [1, 0]) * G, control.tf([kd, kp, ki], [ki]))
    np.testing.assert_allclose(np.sort_complex(T_ipd.poles()), np.sort_complex(poles), rtol=1e-8)
    assert T_ipd.zeros().size == 0
    assert T_ipd.dcgain() == pytest.approx(1.0, rel=1e-12)


def test_pid_robust_to_the_armature_inductance(hub_tf):
    G = hub_tf
    poles = np.concatenate((specs_to_poles(0.05, 0.3), [-30.0]))
    kp, ki, kd = pid_place(G.num[0][0][-1], G.den[0][0], poles)
    model = bg.derive(srv02.build(inductance=True), outputs=srv02.outputs())
    GL = compile_plant(model).plant({p.name: srv02.PARAMETERS[p.name] for p in model.parameters}
                                    ).to_tf(input="e_in", output="theta")
    ev = control.feedback(control.tf([kd, kp, ki], [1, 0]) * GL, 1).poles()
    assert np.all(ev.real < 0)
    slow = np.sort_complex(ev[np.abs(ev) < 100])
    np.testing.assert_allclose(slow, np.sort_complex(poles), rtol=0.05)


# ---------------------------------------------------------------- FLEXCAM: LQR
@pytest.fixture(scope="module")
def flex():
    g, outs, params = flexcam.build(3, formulation="system", damping_ratio=0.02)
    return plant_of(g, outs, params).to_control()


def lqr_design(P, q_theta, q_tip):
    C = P.C
    Ct, Cy = C[[P.output_labels.index("theta")]], C[[P.output_labels.index("y")]]
    Q = q_theta * Ct.T @ Ct + q_tip * Cy.T @ Cy
    Q = (Q + Q.T) / 2
    # scipy's ARE solver: with slycot installed python-control would default to SLICOT's
    # SB02MD, whose residual on this stiff plant is 1.6e-7 relative (scipy: below 1e-8)
    K, X, E = control.lqr(P.A, P.B, Q, np.eye(1), method="scipy")
    return Q, K, X, E


@pytest.mark.parametrize("q_tip", [0.0, 1e4])
def test_lqr_riccati_and_stability(flex, q_tip):
    P = flex
    A, B = P.A, P.B
    Q, K, X, E = lqr_design(P, 100.0, q_tip)
    residual = A.T @ X + X @ A - X @ B @ B.T @ X + Q
    assert np.abs(residual).max() < 1e-8 * np.abs(A.T @ X).max()
    np.testing.assert_allclose(X, X.T, atol=1e-9 * np.abs(X).max())
    assert np.linalg.eigvalsh((X + X.T) / 2).min() > -1e-9 * np.abs(X).max()
    np.testing.assert_allclose(K, B.T @ X, rtol=1e-9, atol=1e-12 * np.abs(K).max())
    ev = np.linalg.eigvals(A - B @ K)
    np.testing.assert_allclose(np.sort_complex(ev), np.sort_complex(E), rtol=1e-8)
    assert np.all(ev.real < 0)
    # integrator in the plant: theta follows a step after the feedforward gain
    cl = control.ss(A - B @ K, B, P.C, 0, outputs=P.output_labels)
    i_t = P.output_labels.index("theta")
    N = 1.0 / cl.dcgain()[i_t]
    assert N == pytest.approx(K[0, list(P.state_labels).index("theta")], rel=1e-9)


def test_lqr_tip_weight_damps_the_first_mode(flex):
    P = flex
    zeta = []
    for q_tip in (0.0, 1e4):
        _, K, _, E = lqr_design(P, 100.0, q_tip)
        mode1 = E[(np.abs(E) > 50) & (np.abs(E) < 150)]     # first flexible mode ~ 86 rad/s
        zeta.append(float(-mode1.real.max() / np.abs(mode1).max()))
    open_loop = np.linalg.eigvals(P.A)
    m1 = open_loop[(np.abs(open_loop) > 50) & (np.abs(open_loop) < 150)]
    zeta_ol = float(-m1.real[0] / abs(m1[0]))
    assert zeta[0] < 1.5 * zeta_ol            # hub-only weight barely touches the mode
    assert zeta[1] > 2.5 * zeta_ol            # tip weight damps it
