"""SRV-02 hub against the motor equations written by hand and seed 000 Eq. (3)."""

import sys
from pathlib import Path

import numpy as np
import pytest
import sympy

import bondgraph as bg
from helpers import assert_same_tf, s, tf_of

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "models"))
import srv02  # noqa: E402

S = srv02.SYMBOLS


def quanser_theta_over_v(J_l=0, L=None):
    """Hand derivation (Quanser SRV-02 manual):
    armature  e_in = Rm i + Lm i' + km Kg w ;
    output    J_eq w' + Beq w = eta_g eta_m Kg kt i,  J_eq = eta_g Kg^2 Jm + J_l."""
    Rm, kt, km, em, eg, Kg, Jm, Beq = (S[n] for n in "Rm kt km eta_m eta_g Kg Jm Beq".split())
    Jeq = eg * Kg**2 * Jm + J_l
    Z = Rm + (L * s if L is not None else 0)
    return eg * em * Kg * kt / (s * (Z * (Jeq * s + Beq) + eg * em * Kg**2 * kt * km))


def hand_numbers(J_l=0.0):
    """Gain and pole of theta/e_in = gain / (s (s + pole)) (Lm neglected) and the two
    non-zero poles with Lm, from the hand equations above, in floats on PARAMETERS."""
    P = srv02.PARAMETERS
    Rm, Lm, kt, km, em, eg, Kg, Jm, Beq = (P[n] for n in "Rm Lm kt km eta_m eta_g Kg Jm Beq".split())
    Jeq = eg * Kg**2 * Jm + J_l
    gain = eg * em * Kg * kt / (Rm * Jeq)
    pole = (Rm * Beq + eg * em * Kg**2 * kt * km) / (Rm * Jeq)
    # with Lm: den = s [Lm Jeq s^2 + (Lm Beq + Rm Jeq) s + Rm Beq + eg em Kg^2 kt km]
    qa, qb, qc = Lm * Jeq, Lm * Beq + Rm * Jeq, Rm * Beq + eg * em * Kg**2 * kt * km
    disc = (qb**2 - 4 * qa * qc) ** 0.5
    lm_poles = ((-qb - disc) / (2 * qa), (-qb + disc) / (2 * qa))     # electrical, mechanical
    return gain, pole, lm_poles


def numeric_tf(G):
    num, den = sympy.fraction(sympy.cancel(G.subs({S[k]: v for k, v in srv02.PARAMETERS.items()})))
    return np.array(sympy.Poly(num, s).all_coeffs(), float), np.array(sympy.Poly(den, s).all_coeffs(), float)


def test_theta_over_ein_lm_neglected_has_eq1_form():
    m = bg.derive(srv02.build(inductance=False), outputs=srv02.outputs())
    G = tf_of(m, "e_in", "theta")
    assert_same_tf(G, quanser_theta_over_v())
    # Eq. (1): 1/(a s^2 + b s), with a and b expressions of the motor parameters
    num, den = sympy.fraction(sympy.cancel(G))
    den = sympy.Poly(den / num, s)
    a, b, c = den.all_coeffs()
    Rm, kt, km, em, eg, Kg, Jm, Beq = (S[n] for n in "Rm kt km eta_m eta_g Kg Jm Beq".split())
    assert c == 0
    assert sympy.simplify(a - Rm * Jm * Kg / (em * kt)) == 0
    assert sympy.simplify(b - (Rm * Beq + eg * em * Kg**2 * kt * km) / (eg * em * Kg * kt)) == 0


def test_hub_alone_matches_identified_eq3_within_one_percent():
    m = bg.derive(srv02.build(inductance=False), outputs=srv02.outputs())
    num, den = numeric_tf(tf_of(m, "e_in", "theta"))
    num, den = num / den[0], den / den[0]
    gain, pole = num[-1], den[1]
    assert den[2] == 0
    assert gain == pytest.approx(377.8, rel=0.01)     # 375.7
    assert pole == pytest.approx(42.4, rel=0.01)      # 42.54


def test_with_inductance_third_order_and_close_to_reduced():
    m = bg.derive(srv02.build(inductance=True), outputs=srv02.outputs())
    G = tf_of(m, "e_in", "theta")
    assert_same_tf(G, quanser_theta_over_v(L=S["Lm"]))
    num, den = numeric_tf(G)
    poles = np.sort(np.roots(den).real)
    _, pole, (p_el, p_mech) = hand_numbers()
    assert poles[0] == pytest.approx(p_el, rel=1e-8)
    assert poles[1] == pytest.approx(p_mech, rel=1e-8)
    assert abs(poles[2]) < 1e-9 * abs(p_el)                 # the integrator
    # electrical pole near -Rm/Lm = -14444, mechanical pole near the reduced model's -pole
    assert poles[0] == pytest.approx(-2.6 / 0.18e-3, rel=0.01)
    assert poles[1] == pytest.approx(-pole, rel=0.01)


def test_link_inertia_as_rigid_load():
    m = bg.derive(srv02.build(inductance=False, load_inertia=True), outputs=srv02.outputs())
    assert m.augmented.derivative == ("J_l",)       # rigid gear: one inertia dependent
    G = tf_of(m, "e_in", "theta")
    assert_same_tf(G, quanser_theta_over_v(J_l=S["J_l"]))
    num, den = numeric_tf(G)
    num, den = num / den[0], den / den[0]
    gain, pole, _ = hand_numbers(J_l=srv02.PARAMETERS["J_l"])     # about 6.01 and 0.684
    assert num[-1] == pytest.approx(gain, rel=1e-9)
    assert den[1] == pytest.approx(pole, rel=1e-9)


def test_sensors():
    m = bg.derive(srv02.build(inductance=False), outputs=srv02.outputs())
    G_pot = tf_of(m, "e_in", "v_pot")
    G_tach = tf_of(m, "e_in", "v_tach")
    assert_same_tf(G_pot, S["k_pot"] * quanser_theta_over_v())
    # tachometer on the motor shaft: w_m = Kg * w_l
    assert_same_tf(G_tach, S["k_tach"] * S["Kg"] * s * quanser_theta_over_v())
