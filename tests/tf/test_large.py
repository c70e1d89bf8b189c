"""Symbolic transfer functions of chains against closed forms written here.

The fast path (:mod:`bondgraph.tf._packed`) must give exactly the transfer
function of the hand derivation:

- masses ``m_i`` joined by a spring ``k_i`` and a damper ``b_i`` to the
  previous mass (the first to ground), force on mass 1, position of mass
  ``n``: the mechanical impedance matrix ``Z(s) = s**2 M + s Bd + K`` is
  tridiagonal with off-diagonal ``-(b_i s + k_i)``, so
  ``X_n/F = prod_{i>=2} (b_i s + k_i) / det Z(s)``, ``det Z`` from the
  three-term recurrence of tridiagonal determinants;
- the bond-graph chain of ``bench/bench_chain.py`` (dampers to ground,
  springs between masses), force to last-mass velocity: ``V = Z(s)^{-1} F``
  with ``Z(s) = s M + B + K/s`` assembled by hand (the C parameter is a
  compliance) and solved over the rationals at random rational points.
"""

from __future__ import annotations

import random
import sys
from fractions import Fraction
from pathlib import Path

import pytest
import sympy as sp

import bondgraph as bg
from bondgraph.tf import transfer_function, transfer_matrix

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))
import bench_chain  # noqa: E402  (the models; the expectations are derived here)
import bench_tf  # noqa: E402

s = sp.Symbol("s")


def chain_matrices(n):
    """State space of the position chain (states x_i, v_i) of ``bench/bench_tf.py``."""
    A, B, C, _ = bench_tf.chain(n)
    syms = {x.name: x for x in A.free_symbols | B.free_symbols}
    m, k, b = ([syms[f"{c}{i}"] for i in range(1, n + 1)] for c in "mkb")
    return (A, B, C), (tuple(m), tuple(k), tuple(b))


def closed_form(n, m, k, b):
    """``X_n/F`` of the position chain by the tridiagonal recurrence."""
    z = [b[i] * s + k[i] for i in range(n)]            # link impedances / s
    diag = [m[i] * s**2 + z[i] + (z[i + 1] if i + 1 < n else 0) for i in range(n)]
    d_prev, d = sp.Integer(1), diag[n - 1]              # determinants from the far end
    for i in range(n - 2, -1, -1):
        d_prev, d = d, sp.expand(diag[i] * d - z[i + 1] ** 2 * d_prev)
    return sp.Mul(*z[1:]), d


def at(expr, point):
    return sp.Rational(expr.xreplace(point))


@pytest.mark.parametrize("n", [2, 4, 6])
def test_position_chain_matches_recurrence(n):
    (A, B, C), (m, k, b) = chain_matrices(n)
    G = transfer_function(A, B, C, normalize="as-derived")
    num, den = closed_form(n, m, k, b)
    # compare the ratio exactly at random rational points (s included)
    rng = random.Random(n)
    gnum, gden = G.num.as_expr(), G.den.as_expr()
    for _ in range(3):
        point = {x: sp.Rational(rng.randint(1, 50), rng.randint(1, 9)) for x in m + k + b}
        point[s] = sp.Rational(rng.randint(-30, 30), rng.randint(1, 7))
        assert at(gnum, point) * at(den, point) == at(num, point) * at(gden, point)
    # the denominator is the whole det Z (no cancellation): same degree, same terms
    assert G.den.degree() == 2 * n and G.num.degree() == n - 1
    assert len(sp.Add.make_args(sp.expand(gden))) == len(sp.Add.make_args(den))


@pytest.mark.parametrize("normalize", ["monic", "leading-one-denominator"])
def test_position_chain_normalizations(normalize):
    n = 5
    (A, B, C), (m, k, b) = chain_matrices(n)
    G = transfer_function(A, B, C, normalize=normalize)
    num, den = closed_form(n, m, k, b)
    if normalize == "monic":
        lead = sp.Poly(den, s).LC()
        want = [sp.cancel(c / lead) for c in sp.Poly(den, s).all_coeffs()]
    else:
        low = den.coeff(s, 0)
        want = [sp.cancel(c / low) for c in sp.Poly(den, s).all_coeffs()]
    got = G.den_coeffs
    assert len(got) == len(want)
    assert all(sp.cancel(g - w) == 0 for g, w in zip(got, want))


def solve_exact(Z, rhs):
    """Gauss-Jordan over Fractions (independent of sympy and of the package)."""
    n = len(Z)
    M = [row[:] + [r] for row, r in zip(Z, rhs)]
    for c in range(n):
        p = next(r for r in range(c, n) if M[r][c] != 0)
        M[c], M[p] = M[p], M[c]
        for r in range(n):
            if r != c and M[r][c] != 0:
                f = M[r][c] / M[c][c]
                M[r] = [x - f * y for x, y in zip(M[r], M[c])]
    return [M[i][n] / M[i][i] for i in range(n)]


@pytest.mark.parametrize("n", [3, 6])
def test_bond_graph_chain_velocity(n):
    model = bg.derive(bench_chain.build(n), outputs={"v": bg.flow(f"m{n - 1}")})
    G = model.transfer_function("F", "v")
    syms = {x.name: x for x in G.num.as_expr().free_symbols | G.den.as_expr().free_symbols
            if x != s}
    rng = random.Random(10 + n)
    for _ in range(3):
        vals = {name: Fraction(rng.randint(1, 40), rng.randint(1, 6)) for name in
                [f"m{i}" for i in range(n)] + [f"b{i}" for i in range(n)]
                + [f"k{i}" for i in range(1, n)]}
        sv = Fraction(rng.randint(1, 25), rng.randint(1, 5))
        # Z(s) = s M + B + K/s, springs between masses i-1 and i; the C element's
        # parameter is a compliance (effort q/k_i), so the spring's impedance is 1/(k_i s)
        Z = [[Fraction(0)] * n for _ in range(n)]
        for i in range(n):
            Z[i][i] += sv * vals[f"m{i}"] + vals[f"b{i}"]
        for i in range(1, n):
            kk = 1 / (vals[f"k{i}"] * sv)
            Z[i][i] += kk
            Z[i - 1][i - 1] += kk
            Z[i][i - 1] -= kk
            Z[i - 1][i] -= kk
        want = solve_exact(Z, [Fraction(1)] + [Fraction(0)] * (n - 1))[n - 1]
        point = {x: sp.Rational(vals[name].numerator, vals[name].denominator)
                 for name, x in syms.items()}
        point[s] = sp.Rational(sv.numerator, sv.denominator)
        got = at(G.num.as_expr(), point) / at(G.den.as_expr(), point)
        assert got == sp.Rational(want.numerator, want.denominator)
    assert G.den.degree() == 2 * n - 1


def test_transfer_matrix_entries_share_the_chain_denominator():
    n = 4
    (A, B, C), (m, k, b) = chain_matrices(n)
    C2 = sp.zeros(2, 2 * n)
    C2[0, 0] = 1                    # position of mass 1
    C2[1, 2 * n - 2] = 1            # position of mass n
    M = transfer_matrix(A, B, C2, normalize="as-derived")
    num, den = closed_form(n, m, k, b)
    point = {x: sp.Rational(3 + i, 2) for i, x in enumerate(m + k + b)}
    point[s] = sp.Rational(5, 3)
    ratio = at(M.den.as_expr(), point) / at(den, point)
    assert at(M.nums[1][0].as_expr(), point) == ratio * at(num, point)
    # mass 1: the cofactor is det of the chain without mass 1 (masses 2..n)
    sub_num, sub_den = closed_form(n - 1, m[1:], k[1:], b[1:])
    assert at(M.nums[0][0].as_expr(), point) == ratio * at(sub_den, point)
