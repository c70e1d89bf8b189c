"""Tests of bondgraph.beam against independent derivations.

Every reference value below is either tabulated in the literature, a closed
form derived here, or computed by an independent route (mpmath on the
classical unscaled equations, scipy.integrate.quad, the distributed-parameter
solution of the beam PDE written out in this file).
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from bondgraph.beam import (
    BOUNDARIES,
    BeamParameterError,
    beam_eigenvalues,
    beam_symbols,
    characteristic_expression,
    characteristic_function,
    hub_assumed_modes,
    hub_beam_eigenvalues,
    hub_beam_modes,
    hub_characteristic_expression,
    modal_beam,
    symbolic_modes,
)

# --------------------------------------------------------------------------- helpers

# Blevins, Formulas for Natural Frequency and Mode Shape, Table 8-1: beta_i L
BLEVINS_CF = np.array([1.875104, 4.694091, 7.854757, 10.995541, 14.137168])
BLEVINS_PF = np.array([3.926602, 7.068583, 10.210176, 13.351768, 16.493361])


def blevins_omega(EI, rhoA, L, n, boundary="clamped-free"):
    """omega_i = (beta_i L)^2 sqrt(EI / (rhoA L^4)) from the tabulated beta_i L."""
    betaL = (BLEVINS_CF if boundary == "clamped-free" else BLEVINS_PF)[:n]
    return betaL**2 * math.sqrt(EI / (rhoA * L**4))



def mp_roots(f, guesses, dps=30):
    """High-precision roots of a classical (unscaled) characteristic function."""
    with mp.workdps(dps):
        return [float(mp.findroot(f, mp.mpf(g))) for g in guesses]


def mp_det(rows_fn, lam, dps=40):
    """Determinant of a 4x4 boundary matrix in the classical cos/sin/cosh/sinh basis."""
    with mp.workdps(dps):
        return mp.det(mp.matrix(rows_fn(mp.mpf(lam))))


def classical_derivs(lam, xi):
    """d^n/dxi^n of (cos, sin, cosh, sinh)(lam xi), n = 0..3 (mpmath)."""
    c, s, ch, sh = mp.cos(lam * xi), mp.sin(lam * xi), mp.cosh(lam * xi), mp.sinh(lam * xi)
    return [[c, s, ch, sh],
            [-lam * s, lam * c, lam * sh, lam * ch],
            [-lam**2 * c, -lam**2 * s, lam**2 * ch, lam**2 * sh],
            [lam**3 * s, -lam**3 * c, lam**3 * sh, lam**3 * ch]]


def exact_tip_receptance(EI, rhoA, L, omega, tip_mass=0.0):
    """Distributed-parameter tip receptance w(L)/F of a clamped-free beam.

    Solves EI w'''' = rhoA omega^2 w with w = A cos bx + B sin bx + C cosh bx + D sinh bx,
    w(0) = w'(0) = 0, w''(L) = 0 and EI w'''(L) = -F - M_t omega^2 w(L)
    (a force F along +w at the tip; the tip mass adds its inertia force
    M_t omega^2 w(L) to it).
    """
    b = (rhoA * omega**2 / EI) ** 0.25
    c, s, ch, sh = np.cos(b * L), np.sin(b * L), np.cosh(b * L), np.sinh(b * L)
    w_L = np.array([c, s, ch, sh])
    w3_L = b**3 * np.array([s, -c, sh, ch])
    A = np.array([[1.0, 0.0, 1.0, 0.0],
                  [0.0, 1.0, 0.0, 1.0],
                  [-c, -s, ch, sh],
                  EI * w3_L + tip_mass * omega**2 * w_L])
    coef = np.linalg.solve(A, np.array([0.0, 0.0, 0.0, -1.0]))  # F = 1
    return float(w_L @ coef)


def inner(beam, i, j, *, stiffness=False):
    """Mass (or stiffness) inner product of modes i, j by adaptive quadrature."""
    mi, mj = beam.modes[i], beam.modes[j]
    if stiffness:
        f = lambda x: beam.EI * mi.d2phi(x) * mj.d2phi(x)  # noqa: E731
        tip = 0.0
    else:
        f = lambda x: beam.rhoA * mi.phi(x) * mj.phi(x)  # noqa: E731
        tip = (beam.tip_mass * mi.tip_value * mj.tip_value
               + beam.tip_inertia * mi.tip_slope * mj.tip_slope)
    scale = math.sqrt(mi.mass * mj.mass) * (mi.omega * mj.omega if stiffness else 1.0)
    return quad(f, 0.0, beam.L, limit=400, epsabs=1e-11 * scale, epsrel=1e-10)[0] + tip


# --------------------------------------------------------------------------- eigenvalues


def test_tabulated_eigenvalues():
    # Blevins, Table 8-1 (6 decimals).
    cf = beam_eigenvalues("clamped-free", 3)
    pf = beam_eigenvalues("pinned-free", 3)
    assert np.allclose(cf, [1.875104, 4.694091, 7.854757], atol=1e-6)
    assert np.allclose(pf, [3.926602, 7.068583, 10.210176], atol=1e-6)


def test_eigenvalues_match_high_precision_classical_equations():
    n = 12
    cf = beam_eigenvalues("clamped-free", n)
    pf = beam_eigenvalues("pinned-free", n)
    ks = range(1, n + 1)
    ref_cf = mp_roots(lambda z: 1 + mp.cos(z) * mp.cosh(z), [(k - 0.5) * math.pi for k in ks])
    ref_pf = mp_roots(lambda z: mp.tan(z) - mp.tanh(z), [(k + 0.25) * math.pi for k in ks])
    assert np.max(np.abs(np.subtract(cf, ref_cf))) < 1e-9
    assert np.max(np.abs(np.subtract(pf, ref_pf))) < 1e-9


def test_high_modes_no_overflow_and_asymptotics():
    # For large k the roots are (k - 1/2) pi (clamped-free) and (k + 1/4) pi
    # (pinned-free) up to terms of order exp(-betaL) < 1e-60 at k >= 50.
    cf = beam_eigenvalues("clamped-free", 300)
    pf = beam_eigenvalues("pinned-free", 300)
    for k in (50, 120, 300):
        assert abs(cf[k - 1] - (k - 0.5) * math.pi) < 1e-9
        assert abs(pf[k - 1] - (k + 0.25) * math.pi) < 1e-9
    assert np.all(np.diff(cf) > 2.8) and np.all(np.diff(pf) > 3.1)


def test_sympy_characteristic_expressions_vanish_at_roots():
    lam = sympy.Symbol("betaL", positive=True)
    for boundary, kw in [("clamped-free", {}), ("pinned-free", {}),
                         ("clamped-free", {"mass_ratio": 0.7, "inertia_ratio": 0.02}),
                         ("pinned-free", {"mass_ratio": 0.3, "inertia_ratio": 0.05})]:
        expr = characteristic_expression(boundary, **kw)
        f = sympy.lambdify(lam, expr, "mpmath")
        with mp.workdps(30):
            for r in beam_eigenvalues(boundary, 4, **kw):
                # relative to the size of the cosh-scaled terms
                assert abs(f(mp.mpf(r))) / mp.cosh(r) / (1 + r**4) < 1e-13


def test_stable_characteristic_function_does_not_overflow():
    lam = np.array([800.0, 5000.0])
    vals = characteristic_function("clamped-free", lam)
    assert np.all(np.isfinite(vals))
    assert np.allclose(vals, np.cos(lam), atol=1e-300)  # cos + sech, sech underflows


# --------------------------------------------------------------------------- tip mass


def test_tip_mass_limit_zero_is_bare_beam():
    # a vanishing tip mass gives the tabulated bare-beam values (6 decimals)
    np.testing.assert_allclose(beam_eigenvalues("clamped-free", 5, mass_ratio=1e-14), BLEVINS_CF,
                               rtol=0, atol=1e-6)
    np.testing.assert_allclose(beam_eigenvalues("pinned-free", 5, mass_ratio=1e-14), BLEVINS_PF,
                               rtol=0, atol=1e-6)


def test_tip_mass_published_values_and_independent_determinant():
    # M_t = rhoA L: 1.24792, 4.03114, 7.13413 (tabulated by Laura, Pombo &
    # Susemihl, J. Sound Vib. 37 (1974) 161-168).
    lams = beam_eigenvalues("clamped-free", 3, mass_ratio=1.0)
    assert np.allclose(lams, [1.24792, 4.03114, 7.13413], atol=1e-5)

    # Independent derivation: clamped root + tip body boundary conditions in the
    # classical basis, root of the 4x4 determinant found by mpmath.
    def rows(mu, j):
        def fn(lam):
            d0, d1 = classical_derivs(lam, 0), classical_derivs(lam, 1)
            return [d0[0], d0[1],
                    [d1[2][k] - j * lam**4 * d1[1][k] for k in range(4)],
                    [d1[3][k] + mu * lam**4 * d1[0][k] for k in range(4)]]
        return fn

    for mu, j in [(1.0, 0.0), (0.35, 0.04), (5.0, 0.2)]:
        mine = beam_eigenvalues("clamped-free", 3, mass_ratio=mu, inertia_ratio=j)
        with mp.workdps(40):
            ref = [float(mp.findroot(lambda z: mp.det(mp.matrix(rows(mu, j)(z))), mp.mpf(g)))
                   for g in mine]
        assert np.max(np.abs(np.subtract(mine, ref))) < 1e-10


def test_tip_mass_first_frequency_effective_mass_and_rayleigh():
    EI, rhoA, L = 3.0, 0.8, 1.3
    m = rhoA * L
    for Mt in (0.0, 0.1 * m, m, 10 * m):
        w1 = modal_beam(EI, rhoA, L, 1, tip_mass=Mt).omega[0]
        # Classical effective-mass approximation (33/140 ~ 0.2427 of the beam mass).
        approx = math.sqrt(3 * EI / L**3 / (0.2427 * m + Mt))
        assert abs(w1 / approx - 1) < 0.01
        # Rayleigh quotient with the static tip-load shape y = x^2 (3L - x): an
        # upper bound of omega_1^2, and close to it (3.567 vs 3.516 at M_t = 0).
        num = quad(lambda x: EI * (6 * L - 6 * x) ** 2, 0, L)[0]
        den = quad(lambda x: rhoA * (x**2 * (3 * L - x)) ** 2, 0, L)[0] + Mt * (2 * L**3) ** 2
        assert w1 <= math.sqrt(num / den) <= 1.015 * w1


# --------------------------------------------------------------------------- shapes


@pytest.mark.parametrize("kw", [
    {"boundary": "clamped-free"},
    {"boundary": "pinned-free"},
    {"boundary": "clamped-free", "tip_mass": 0.4, "tip_inertia": 0.03},
    {"boundary": "pinned-free", "tip_mass": 0.2},
])
def test_orthogonality_by_quadrature(kw):
    beam = modal_beam(2.5, 0.6, 1.4, 4, **kw)
    for i in range(4):
        for j in range(i, 4):
            m = inner(beam, i, j)
            k = inner(beam, i, j, stiffness=True)
            if i == j:
                assert m == pytest.approx(1.0, rel=1e-9)  # mass normalisation
                assert k == pytest.approx(beam.modes[i].omega ** 2, rel=1e-8)
            else:
                assert abs(m) < 1e-9 and abs(k) < 1e-7 * beam.modes[j].omega ** 2


def test_orthogonality_high_modes():
    beam = modal_beam(1.0, 1.0, 1.0, 40)
    for i, j in [(38, 39), (0, 39), (20, 39)]:
        assert abs(inner(beam, i, j)) < 1e-9
    assert inner(beam, 39, 39) == pytest.approx(1.0, rel=1e-9)


@pytest.mark.parametrize("n_modes", [4, 30])
def test_boundary_conditions_clamped_free(n_modes):
    beam = modal_beam(1.7, 0.9, 2.0, n_modes)
    for m in beam.modes:
        b = m.betaL / beam.L
        scale = abs(m.tip_value)
        assert abs(m.phi(0.0)) < 1e-12 * scale
        assert abs(m.dphi(0.0)) < 1e-11 * scale * b
        assert abs(m.d2phi(beam.L)) < 1e-11 * scale * b**2
        assert abs(m.d3phi(beam.L)) < 1e-11 * scale * b**3


def test_boundary_conditions_pinned_free_and_tip_body():
    pf = modal_beam(1.0, 2.0, 0.7, 5, boundary="pinned-free")
    for m in pf.modes:
        b, s = m.betaL / pf.L, abs(m.tip_value)
        assert abs(m.phi(0.0)) < 1e-12 * s and abs(m.d2phi(0.0)) < 1e-11 * s * b**2
        assert abs(m.d2phi(pf.L)) < 1e-11 * s * b**2 and abs(m.d3phi(pf.L)) < 1e-11 * s * b**3
    EI, Mt, Jt = 1.3, 0.5, 0.02
    tb = modal_beam(EI, 0.7, 1.1, 5, tip_mass=Mt, tip_inertia=Jt)
    for m in tb.modes:
        w2 = m.omega**2
        b = m.betaL / tb.L
        # EI w'''(L) = -M_t omega^2 w(L),  EI w''(L) = +J_t omega^2 w'(L)
        assert EI * m.d3phi(tb.L) == pytest.approx(-Mt * w2 * m.phi(tb.L), rel=1e-9)
        assert EI * m.d2phi(tb.L) == pytest.approx(Jt * w2 * m.dphi(tb.L),
                                                   abs=1e-10 * EI * b**2 * abs(m.tip_value))


def test_derivatives_consistent_with_finite_differences_and_ode():
    beam = modal_beam(1.0, 1.0, 1.0, 6, tip_mass=0.3)
    x = np.linspace(0.1, 0.9, 7)
    h = 1e-5
    for m in beam.modes:
        b4 = (m.betaL / beam.L) ** 4
        for n in range(4):
            fd = (m.shape(x + h, n) - m.shape(x - h, n)) / (2 * h)
            assert np.allclose(fd, m.shape(x, n + 1), rtol=1e-6,
                               atol=1e-6 * np.max(np.abs(m.shape(x, n + 1))))
        assert np.allclose(m.shape(x, 4), b4 * m.shape(x), rtol=1e-10, atol=1e-10 * b4)


def test_normalizations():
    EI, rhoA, L = 2.0, 0.5, 1.5
    beams = {n: modal_beam(EI, rhoA, L, 4, normalization=n) for n in ("mass", "tip", "length")}
    omega = blevins_omega(EI, rhoA, L, 4)     # tabulated beta L: 6 decimals, rel. error < 1e-6
    for bd in beams.values():
        np.testing.assert_allclose(bd.omega, omega, rtol=2e-6)
        np.testing.assert_allclose(bd.modal_stiffness / bd.modal_mass, omega**2, rtol=4e-6)
        assert np.all(bd.tip_value > 0)
    # "tip": m_i = rhoA L / 4 (closed form below), so k_i = (rhoA L / 4) omega_i^2
    np.testing.assert_allclose(beams["tip"].modal_stiffness, rhoA * L / 4 * omega**2, rtol=4e-6)
    assert np.allclose(beams["tip"].tip_value, 1.0)
    assert np.allclose(beams["mass"].modal_mass, 1.0)
    for i in range(4):
        int_sq = quad(lambda x: beams["length"].modes[i].phi(x) ** 2, 0, L, limit=200)[0]
        assert int_sq == pytest.approx(L, rel=1e-10)
    # Closed form: for psi'''' = b^4 psi, d/dx[3 psi psi''' - psi' psi''
    # + x (b^4 psi^2 - 2 psi' psi''' + psi''^2)] = 4 b^4 psi^2.  With a free tip and a
    # clamped or pinned root every boundary term except x b^4 psi^2 at x = L
    # vanishes, so int_0^L psi^2 dx = L psi(L)^2 / 4: the "length" normalisation
    # gives phi(L) = 2 and the "tip" one m_i = rhoA L / 4, for every mode.
    for boundary in BOUNDARIES:
        length = modal_beam(EI, rhoA, L, 5, boundary=boundary, normalization="length")
        tip = modal_beam(EI, rhoA, L, 5, boundary=boundary, normalization="tip")
        assert np.allclose(length.tip_value, 2.0, rtol=1e-12)
        assert np.allclose(tip.modal_mass, rhoA * L / 4, rtol=1e-12)


def test_couplings_quadrature_and_closed_form():
    EI, rhoA, L, Mt, Jt = 1.5, 0.8, 1.2, 0.3, 0.01
    for boundary in BOUNDARIES:
        beam = modal_beam(EI, rhoA, L, 4, boundary=boundary, tip_mass=Mt, tip_inertia=Jt)
        for m in beam.modes:
            lin = quad(lambda x: rhoA * m.phi(x), 0, L, limit=200)[0] + Mt * m.tip_value
            ang = (quad(lambda x: rhoA * x * m.phi(x), 0, L, limit=200)[0]
                   + Mt * L * m.tip_value + Jt * m.tip_slope)
            assert m.linear_coupling == pytest.approx(lin, rel=1e-9, abs=1e-12)
            assert m.angular_coupling == pytest.approx(ang, rel=1e-9, abs=1e-12)
            # Integrating rhoA omega^2 phi = EI phi'''' by parts with the tip BCs:
            # linear = -EI phi'''(0)/omega^2, angular = EI phi''(0)/omega^2.
            w2 = m.omega**2
            assert m.linear_coupling == pytest.approx(-EI * m.d3phi(0.0) / w2, rel=1e-9)
            assert m.angular_coupling == pytest.approx(EI * m.d2phi(0.0) / w2, abs=1e-10)
            assert m.hub_coupling(0.1) == pytest.approx(ang + 0.1 * lin, rel=1e-9, abs=1e-12)
        if boundary == "pinned-free":
            # flexible modes are mass-orthogonal to the rigid-body mode phi_0 = x
            assert np.allclose(beam.angular_coupling, 0.0, atol=1e-12)
            assert beam.rigid_inertia == pytest.approx(rhoA * L**3 / 3 + Mt * L**2 + Jt)


# --------------------------------------------------------------------------- convergence


def test_static_tip_compliance_sum_converges(capsys):
    EI, rhoA, L = 2.0, 0.4, 1.1
    beam = modal_beam(EI, rhoA, L, 20)
    exact = L**3 / (3 * EI)
    partial = np.cumsum(beam.tip_value**2 / beam.modal_stiffness) / exact
    with capsys.disabled():
        print("\nclamped-free sum_{i<=n} phi_i(L)^2/k_i / (L^3/3EI):",
              {n: round(float(partial[n - 1]), 6) for n in (1, 2, 3, 5, 10, 20)})
    assert np.all(np.diff(partial) > 0) and partial[-1] < 1.0
    assert 1 - partial[4] < 1e-3      # n = 5: 0.99968 (well within 1 %)
    assert 1 - partial[19] < 1e-5     # n = 20: 0.9999950
    # tail of sum 4/betaL^4 with betaL ~ (k - 1/2) pi behaves like 1/n^3
    tail = 1 - partial
    assert tail[9] / tail[19] == pytest.approx(8.0, rel=0.2)


@pytest.mark.parametrize("tip_mass", [0.0, 0.5])
def test_modal_frf_converges_to_distributed_frf(tip_mass, capsys):
    EI, rhoA, L = 2.0, 0.4, 1.1
    ref = modal_beam(EI, rhoA, L, 3, tip_mass=tip_mass).omega
    freqs = {"0.5*w1": 0.5 * ref[0], "(w1+w2)/2": 0.5 * (ref[0] + ref[1]),
             "(w2+w3)/2": 0.5 * (ref[1] + ref[2])}
    ns = (3, 5, 10, 20, 40)
    beams = {n: modal_beam(EI, rhoA, L, n, tip_mass=tip_mass) for n in ns}
    errors = {}
    for label, w in freqs.items():
        exact = exact_tip_receptance(EI, rhoA, L, w, tip_mass)
        errors[label] = [abs(beams[n].modal_receptance(w).real / exact - 1) for n in ns]
    with capsys.disabled():
        print(f"\nFRF rel. error, M_t={tip_mass}, n={ns}:",
              {k: [f"{e:.1e}" for e in v] for k, v in errors.items()})
    for errs in errors.values():
        assert all(a > b for a, b in zip(errs, errs[1:]))
        assert errs[-1] < 1e-4
        if tip_mass == 0.0:
            # truncation error ~ sum_{i>n} 1/k_i ~ n^-3: doubling n divides it by ~8
            assert 6.0 < errs[-2] / errs[-1] < 10.0
    assert errors["0.5*w1"][1] < 1e-3


# --------------------------------------------------------------------------- damping, symbolic


def test_modal_damping():
    EI, rhoA, L = 1.0, 2.0, 1.0
    beam = modal_beam(EI, rhoA, L, 3, damping_ratio=[0.01, 0.02, 0.05], normalization="tip")
    # c_i = 2 zeta_i m_i omega_i with the "tip" closed form m_i = rhoA L / 4 and Blevins' omega_i
    expected = 2 * np.array([0.01, 0.02, 0.05]) * (rhoA * L / 4) * blevins_omega(EI, rhoA, L, 3)
    np.testing.assert_allclose(beam.modal_damping, expected, rtol=2e-6)
    assert np.allclose(modal_beam(1.0, 2.0, 1.0, 3).modal_damping, 0.0)


@pytest.mark.parametrize("normalization", ["mass", "tip", "length"])
def test_symbolic_modes_match_numbers(normalization):
    EI, rhoA, L, x = beam_symbols()
    # evaluated at values other than those the modes were built from
    EI_v, rhoA_v, L_v = 3.0, 0.8, 0.9
    vals = {EI: EI_v, rhoA: rhoA_v, L: L_v}
    # bare beam, against closed forms: Blevins' omega_i, and from
    # int_0^L psi^2 dx = L psi(L)^2 / 4 (see test_normalizations) the modal mass and
    # tip value: "mass" m = 1, phi(L) = 2/sqrt(rhoA L); "tip" m = rhoA L/4, phi(L) = 1;
    # "length" m = rhoA L, phi(L) = 2
    bare = symbolic_modes(modal_beam(2.0, 0.5, 1.5, 3, normalization=normalization,
                                     damping_ratio=0.03))
    mass, tip = {"mass": (1.0, 2 / math.sqrt(rhoA_v * L_v)), "tip": (rhoA_v * L_v / 4, 1.0),
                 "length": (rhoA_v * L_v, 2.0)}[normalization]
    for sm, w in zip(bare, blevins_omega(EI_v, rhoA_v, L_v, 3)):
        assert float(sm.omega.subs(vals)) == pytest.approx(w, rel=2e-6)
        assert float(sm.mass.subs(vals)) == pytest.approx(mass, rel=1e-12)
        assert float(sm.stiffness.subs(vals)) == pytest.approx(mass * w**2, rel=4e-6)
        assert float(sm.damping.subs(vals)) == pytest.approx(2 * 0.03 * mass * w, rel=2e-6)
        assert float(sm.phi.subs(vals).subs(x, 0.0)) == pytest.approx(0.0, abs=1e-11)
        assert float(sm.phi.subs(vals).subs(x, L_v)) == pytest.approx(tip, rel=1e-10)
    # with a tip mass the modes depend on M_t / (rhoA L): against a numeric beam built
    # directly at the other values with the same mass ratio
    beam = modal_beam(2.0, 0.5, 1.5, 3, tip_mass=0.2, normalization=normalization,
                      damping_ratio=0.03)
    other = modal_beam(EI_v, rhoA_v, L_v, 3, tip_mass=0.2 / (0.5 * 1.5) * rhoA_v * L_v,
                       normalization=normalization, damping_ratio=0.03)
    for sm, m in zip(symbolic_modes(beam), other.modes):
        assert float(sm.omega.subs(vals)) == pytest.approx(m.omega, rel=1e-11)
        assert float(sm.mass.subs(vals)) == pytest.approx(m.mass, rel=1e-11)
        assert float(sm.stiffness.subs(vals)) == pytest.approx(m.stiffness, rel=1e-11)
        assert float(sm.damping.subs(vals)) == pytest.approx(m.damping, rel=1e-11)
        for xv in (0.0, 0.4, L_v):
            assert float(sm.phi.subs(vals).subs(x, xv)) == pytest.approx(
                m.phi(xv), rel=1e-10, abs=1e-11)
        # the expression satisfies phi'''' = (betaL/L)^4 phi for any L
        resid = sympy.diff(sm.phi, x, 4) - (sm.betaL / L) ** 4 * sm.phi
        assert abs(float(resid.subs({rhoA: 1.0, L: 0.8, x: 0.3}))) < 1e-8
    # omega scales as sqrt(EI/(rhoA L^4)) exactly when there is no tip body
    sm = symbolic_modes(modal_beam(1.0, 1.0, 1.0, 1))[0]
    assert sympy.simplify(sm.omega / sympy.sqrt(EI / (rhoA * L**4)) - sm.betaL**2) == 0
    assert beam.symbolic()[0].omega == symbolic_modes(beam)[0].omega


# --------------------------------------------------------------------------- hub systems


def test_hub_limits():
    pf = beam_eigenvalues("pinned-free", 4)
    cf = beam_eigenvalues("clamped-free", 4)
    assert np.allclose(hub_beam_eigenvalues(4, hub_ratio=0.0), pf, atol=1e-12)
    assert np.allclose(hub_beam_eigenvalues(4, hub_ratio=1e12, radius_ratio=0.3), cf, atol=1e-9)
    # interlacing: clamped_i < unconstrained_i < clamped_{i+1}
    un = hub_beam_eigenvalues(3, hub_ratio=0.8, radius_ratio=0.1)
    assert all(cf[i] < un[i] < cf[i + 1] for i in range(3))


def test_hub_exact_equation_independent_determinant_and_barbieri():
    eta, rho, mu, j = 0.6, 0.15, 0.4, 0.02

    def rows(lam):
        d0, d1 = classical_derivs(lam, 0), classical_derivs(lam, 1)
        # w(0) = r theta, w'(0)L = theta -> psi(0) = rho psi'(0)
        # -J_h omega^2 theta = EI (w''(0) - r w'''(0)) -> psi'' - rho psi''' + eta lam^4 psi' = 0
        return [[d0[0][k] - rho * d0[1][k] for k in range(4)],
                [d0[2][k] - rho * d0[3][k] + eta * lam**4 * d0[1][k] for k in range(4)],
                [d1[2][k] - j * lam**4 * d1[1][k] for k in range(4)],
                [d1[3][k] + mu * lam**4 * d1[0][k] for k in range(4)]]

    mine = hub_beam_eigenvalues(4, hub_ratio=eta, radius_ratio=rho, mass_ratio=mu,
                                inertia_ratio=j)
    with mp.workdps(40):
        ref = [float(mp.findroot(lambda z: mp.det(mp.matrix(rows(z))), mp.mpf(g))) for g in mine]
    assert np.max(np.abs(np.subtract(mine, ref))) < 1e-10
    # r = 0, no tip body: Barbieri & Özgüner (1988),
    # eta lam^3 (1 + cos cosh) + sin cosh - cos sinh = 0
    lam = sympy.Symbol("betaL", positive=True)
    f = sympy.lambdify(lam, hub_characteristic_expression(hub_ratio=eta), "mpmath")
    g = lambda z: eta * z**3 * (1 + mp.cos(z) * mp.cosh(z)) + mp.sin(z) * mp.cosh(z) \
        - mp.cos(z) * mp.sinh(z)  # noqa: E731
    r0 = hub_beam_eigenvalues(3, hub_ratio=eta)
    with mp.workdps(30):
        assert np.allclose(r0, [float(mp.findroot(g, mp.mpf(v))) for v in r0], atol=1e-10)
        assert all(abs(f(mp.mpf(v)) - g(mp.mpf(v))) < 1e-20 * mp.cosh(v) for v in r0)


def test_hub_modes_orthogonality_and_boundary_conditions():
    EI, rhoA, L, Jh, r, arms, Mt, Jt = 1.2, 0.9, 1.0, 0.5, 0.2, 2, 0.3, 0.01
    sys_ = hub_beam_modes(EI, rhoA, L, 4, hub_inertia=Jh, hub_radius=r, n_arms=arms,
                          tip_mass=Mt, tip_inertia=Jt)
    modes = sys_.modes

    def mass_ip(a, b):
        beam = quad(lambda x: rhoA * a.shape(x) * b.shape(x), 0, L, limit=200)[0]
        return Jh * a.hub_angle * b.hub_angle + arms * (
            beam + Mt * a.shape(L) * b.shape(L) + Jt * a.shape(L, 1) * b.shape(L, 1))

    for i, a in enumerate(modes):
        # zero angular momentum: orthogonal to the rigid mode w = r + x, theta = 1
        mom = Jh * a.hub_angle + arms * (
            quad(lambda x: rhoA * (r + x) * a.shape(x), 0, L, limit=200)[0]
            + Mt * (r + L) * a.shape(L) + Jt * a.shape(L, 1))
        assert abs(mom) < 1e-9
        for k, b in enumerate(modes[i:], start=i):
            assert mass_ip(a, b) == pytest.approx(1.0 if k == i else 0.0, abs=1e-9)
        w2 = a.omega**2
        assert a.shape(0.0) == pytest.approx(r * a.shape(0.0, 1), abs=1e-12)
        assert a.hub_angle == pytest.approx(a.shape(0.0, 1), rel=1e-12)
        assert -Jh * w2 * a.hub_angle == pytest.approx(
            arms * EI * (a.shape(0.0, 2) - r * a.shape(0.0, 3)), rel=1e-8)
        assert EI * a.shape(L, 3) == pytest.approx(-Mt * w2 * a.shape(L), rel=1e-8)
    assert sys_.total_inertia == pytest.approx(
        Jh + arms * (rhoA * ((r + L) ** 3 - r**3) / 3 + Mt * (r + L) ** 2 + Jt))


def test_assumed_modes_converge_to_exact_hub_modes(capsys):
    EI, rhoA, L, Jh, r, Mt, Jt = 1.0, 1.0, 1.0, 0.5, 0.2, 0.3, 0.01
    exact = hub_beam_modes(EI, rhoA, L, 4, hub_inertia=Jh, hub_radius=r, tip_mass=Mt,
                           tip_inertia=Jt).omega
    errs = {}
    for n in (4, 8, 16):
        beam = modal_beam(EI, rhoA, L, n, tip_mass=Mt, tip_inertia=Jt)
        w = hub_assumed_modes(beam, hub_inertia=Jh, hub_radius=r).frequencies()[:4]
        assert np.all(w >= exact * (1 - 1e-12))  # Rayleigh–Ritz upper bounds
        errs[n] = float(np.max(w / exact - 1))
    # pinned-free basis (r = 0): root moment not representable -> slow convergence
    exact0 = hub_beam_modes(EI, rhoA, L, 3, hub_inertia=Jh).omega
    pf_errs = {}
    for n in (8, 64):
        beam = modal_beam(EI, rhoA, L, n, boundary="pinned-free")
        pf_errs[n] = float(np.max(hub_assumed_modes(beam, hub_inertia=Jh).frequencies()[:3]
                                  / exact0 - 1))
    with capsys.disabled():
        print("\nhub Ritz (clamped-free basis) max rel. error, first 4:",
              {n: f"{e:.1e}" for n, e in errs.items()},
              "| pinned-free basis, first 3:", {n: f"{e:.1e}" for n, e in pf_errs.items()})
    assert errs[4] < 1e-4 and errs[16] < 1e-8
    assert pf_errs[64] < 1e-2 and pf_errs[64] < pf_errs[8]


def test_assumed_modes_receptance_matches_exact_modal_sum():
    EI, rhoA, L, Jh, r = 1.0, 1.0, 1.0, 0.4, 0.1
    exact = hub_beam_modes(EI, rhoA, L, 60, hub_inertia=Jh, hub_radius=r, n_arms=2,
                           normalization="tip")
    model = hub_assumed_modes(modal_beam(EI, rhoA, L, 20), hub_inertia=Jh, hub_radius=r,
                              n_arms=2)
    w1, w2 = exact.omega[:2]
    for w in (0.3 * w1, 0.5 * (w1 + w2)):
        for out in ("hub", "tip"):
            assert model.receptance(w, output=out).real == pytest.approx(
                exact.torque_receptance(w, output=out).real, rel=2e-5)
    M, C, K = model.matrices()
    assert np.allclose(M, M.T) and np.all(np.linalg.eigvalsh(M) > 0) and not C.any()


# --------------------------------------------------------------------------- papers


def test_flexcam_link_pinned_free_frequencies(capsys):
    # Seed 000, Table 1: link 0.8 mm x 0.02 m x 0.425 m, mass 0.06 kg.  rhoA is
    # taken from the listed mass (0.06/0.425 = 0.1412 kg/m; the implied density
    # 8824 kg/m^3 fits neither aluminium, 2700, nor steel, 7850: the listed mass
    # probably includes the clamp / light source).  I = b h^3/12 (bending about
    # the thin direction).  E is not listed: spring steel 200 GPa (Quanser
    # flexible links are steel) and, for comparison, aluminium 69 GPa.
    L, mass, b, h = 0.425, 0.06, 0.02, 0.8e-3
    rhoA, I = mass / L, b * h**3 / 12
    f = {}
    for name, E in (("steel E=200GPa", 200e9), ("aluminium E=69GPa", 69e9)):
        f[name] = modal_beam(E * I, rhoA, L, 3, boundary="pinned-free").frequency_hz
    with capsys.disabled():
        print("\nFLEXCAM link, pinned-free frequencies (Hz):",
              {k: np.round(v, 2).tolist() for k, v in f.items()},
              "| paper Tables 2/3: [0.38, 1.23, 2.55]")
    # Steel gives 14.94, 48.41, 101.0 Hz; aluminium 8.77, 28.43, 59.32 Hz.  The
    # paper's 0.38/1.23/2.55 Hz are ~40x (steel) lower: they would need
    # EI = 1.1e-4 N m^2 with this rhoA, a value that no material with these
    # dimensions gives -- the paper's absolute numbers cannot be reproduced from
    # Table 1.  Their ratios, however, are exactly the pinned-free ratios
    # (betaL_i/betaL_1)^2 = 1, 3.2406, 6.7613 (paper: 1.23/0.38 = 3.24,
    # 2.55/0.38 = 6.71, within the rounding of 0.38 Hz).
    ratios = f["steel E=200GPa"] / f["steel E=200GPa"][0]
    assert np.allclose(ratios, [1.0, (7.068583 / 3.926602) ** 2, (10.210176 / 3.926602) ** 2],
                       atol=1e-5)
    assert abs(1.23 / 0.38 - ratios[1]) < 0.04 and abs(2.55 / 0.38 - ratios[2]) < 0.09
    # closed form f_1 = (beta_1 L)^2 / (2 pi) sqrt(EI / (rhoA L^4)), Blevins' beta_1 L
    f1 = 3.926602**2 / (2 * math.pi) * math.sqrt(200e9 * I / (rhoA * L**4))
    assert f["steel E=200GPa"][0] == pytest.approx(f1, rel=1e-6)


def test_soares_hub_two_arms_frequencies(capsys):
    # Seed 001, Table 1 (aluminium, E = 68.9 GPa, rho = 2795 kg/m^3, A = 3.3281e-4 m^2,
    # I = 4.707e-10 m^4, L = 0.9715 m, I_hub = 0.76749 kg m^2, r = 0.09 m), two arms,
    # no tip mass (its value is not listed).  Table 1's I_b = 0.2843 = rhoA L^3/3.
    E, I, rho, A, L, Jh, r = 6.89e10, 4.707e-10, 2795.0, 3.3281e-4, 0.9715, 0.76749, 0.09
    sys_ = hub_beam_modes(E * I, rho * A, L, 3, hub_inertia=Jh, hub_radius=r, n_arms=2)
    cf = modal_beam(E * I, rho * A, L, 3).frequency_hz
    with capsys.disabled():
        print("\nSoares et al. hub + 2 arms, unconstrained (Hz):",
              np.round(sys_.frequency_hz, 2).tolist(), "| clamped-free:",
              np.round(cf, 2).tolist(), "| paper Table 2 analytical: [12.51, 31.11, 62.86]")
    # Model: 4.78, 22.36, 61.65 Hz (clamped-free 3.50, 21.94, 61.43).  The paper's
    # first two analytical values cannot be reproduced from Table 1 (a tip mass
    # would only lower them); the third agrees within 2 %.
    assert rho * A * L**3 / 3 == pytest.approx(0.2843, rel=1e-3)
    assert all(cf[i] < sys_.frequency_hz[i] < cf[i + 1] for i in range(2))


# --------------------------------------------------------------------------- properties, errors


@settings(max_examples=25, deadline=None)
@given(mu=st.floats(0.0, 20.0), j=st.floats(0.0, 0.5))
def test_tip_body_lowers_frequencies_and_keeps_orthogonality(mu, j):
    base = beam_eigenvalues("clamped-free", 3)
    lams = beam_eigenvalues("clamped-free", 3, mass_ratio=mu, inertia_ratio=j)
    assert all(a <= b + 1e-12 for a, b in zip(lams, base))
    beam = modal_beam(1.0, 1.0, 1.0, 3, tip_mass=mu, tip_inertia=j)
    # closed-form residual of the classical equation (divided by cosh)
    for lam in lams:
        c, s, ch, sh = math.cos(lam), math.sin(lam), math.cosh(lam), math.sinh(lam)
        F = (1 + c * ch + mu * lam * (c * sh - s * ch) - j * lam**3 * (s * ch + c * sh)
             + mu * j * lam**4 * (1 - c * ch))
        assert abs(F / ch) < 1e-11 * (1 + mu * j * lam**4 + j * lam**3 + mu * lam)
    x = np.linspace(0.0, 1.0, 2001)
    w = np.full(x.size, 1 / 2000)
    w[[0, -1]] /= 2  # trapezoid, enough for an orthogonality sanity check
    P = beam.shapes(x)
    G = (P * w) @ P.T + mu * np.outer(beam.tip_value, beam.tip_value) + j * np.outer(
        [m.tip_slope for m in beam.modes], [m.tip_slope for m in beam.modes])
    assert np.allclose(G, np.eye(3), atol=1e-4)


@pytest.mark.parametrize("call, fragment", [
    (lambda: modal_beam(-1.0, 1.0, 1.0, 2), "EI: expected a finite number > 0, got -1.0"),
    (lambda: modal_beam(1.0, 0.0, 1.0, 2), "rhoA: expected a finite number > 0"),
    (lambda: modal_beam(1.0, 1.0, float("nan"), 2), "L: expected a finite number > 0"),
    (lambda: modal_beam(1.0, 1.0, 1.0, 0), "n_modes: expected an integer >= 1, got 0"),
    (lambda: modal_beam(1.0, 1.0, 1.0, True), "n_modes: expected an integer >= 1"),
    (lambda: modal_beam(1.0, 1.0, 1.0, 2.0), "n_modes: expected an integer >= 1"),
    (lambda: modal_beam(1.0, 1.0, 1.0, 2, boundary="free-free"),
     "boundary: expected one of 'clamped-free', 'pinned-free', got 'free-free'"),
    (lambda: modal_beam(1.0, 1.0, 1.0, 2, tip_mass=-0.1),
     "tip_mass: expected a finite number >= 0"),
    (lambda: modal_beam(1.0, 1.0, 1.0, 2, normalization="unit"),
     "normalization: expected one of 'mass', 'tip', 'length'"),
    (lambda: modal_beam(1.0, 1.0, 1.0, 2, damping_ratio=[0.1]),
     "damping_ratio: expected a number or a sequence of 2 numbers"),
    (lambda: modal_beam(1.0, 1.0, 1.0, 2, damping_ratio=-0.1), "damping_ratio: expected"),
    (lambda: modal_beam(1.0, 1.0, 1.0, 1).modes[0].shape(1.5), "x: expected positions in [0, L]"),
    (lambda: modal_beam(1.0, 1.0, 1.0, 1).modes[0].shape(0.5, 5), "derivative: expected 0, 1"),
    (lambda: hub_beam_modes(1.0, 1.0, 1.0, 2, hub_inertia=-1.0), "hub_inertia: expected"),
    (lambda: hub_assumed_modes(modal_beam(1.0, 1.0, 1.0, 2, boundary="pinned-free"),
                               hub_inertia=1.0, hub_radius=0.1), "hub_radius: expected 0"),
    (lambda: hub_assumed_modes("beam", hub_inertia=1.0), "beam: expected a ModalBeam"),
    (lambda: hub_beam_modes(1.0, 1.0, 1.0, 2, hub_inertia=1.0).torque_receptance(1.0,
                                                                                  output="x"),
     "output: expected one of 'hub', 'tip'"),
])
def test_errors_name_argument(call, fragment):
    with pytest.raises(BeamParameterError) as info:
        call()
    assert fragment in str(info.value)
    assert isinstance(info.value, ValueError)


def test_results_are_frozen():
    beam = modal_beam(1.0, 1.0, 1.0, 2)
    with pytest.raises(AttributeError):
        beam.EI = 2.0  # type: ignore[misc]
    with pytest.raises(AttributeError):
        beam.modes[0].omega = 1.0  # type: ignore[misc]
    assert hash(beam.modes[0]) == hash(modal_beam(1.0, 1.0, 1.0, 2).modes[0])
