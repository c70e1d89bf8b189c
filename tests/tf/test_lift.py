"""Rank-one couplings lifted out of determinants (bondgraph.tf._lift).

The expected values are independent of the code under test: the modal star's
determinant and transfer function in closed form (matrix determinant lemma and
Sherman-Morrison, derived below), and sympy's own Berkowitz determinant of
random block-plus-rank-one matrices evaluated at random rational points.
"""

from __future__ import annotations

import random

import pytest
import sympy as sp

from bondgraph.tf import transfer_function
from bondgraph.tf._determinants import determinant
from bondgraph.tf._encode import encode_system
from bondgraph.tf._lift import lifted, lifted_determinant, rank_one_lift
from bondgraph.tf._rings import make_ring

s = sp.Symbol("s")


def modal_star(n: int):
    """Hub torque on ``n`` undamped modes, inductance neglected (FLEXCAM's paper form).

    States ``(p_i, q_i)`` per mode: ``q_i' = p_i/m_i``, ``p_i' = -k_i q_i + a_i tau``,
    ``tau = beta u - c w`` with the hub velocity ``w = sum_j a_j p_j / m_j``; output
    ``y = sum_i b_i q_i``.  Eliminating ``tau`` couples every pair of modes:
    ``A[p_i, p_j] = -c a_i a_j / m_j``, a rank-one block.
    """
    m = sp.symbols(f"m1:{n + 1}", positive=True)
    k = sp.symbols(f"k1:{n + 1}", positive=True)
    a = sp.symbols(f"a1:{n + 1}", positive=True)
    b = sp.symbols(f"b1:{n + 1}", positive=True)
    c, beta = sp.symbols("c beta", positive=True)
    A = sp.zeros(2 * n, 2 * n)
    B = sp.zeros(2 * n, 1)
    C = sp.zeros(1, 2 * n)
    for i in range(n):
        p, q = 2 * i, 2 * i + 1
        A[q, p] = 1 / m[i]
        A[p, q] = -k[i]
        for j in range(n):
            A[p, 2 * j] = -c * a[i] * a[j] / m[j]
        B[p, 0] = beta * a[i]
        C[0, q] = b[i]
    return A, B, C, (m, k, a, b, c, beta)


def star_closed_form(n: int, symbols):
    """``num/den`` of the modal star by hand.

    ``sI - A = D + c u w^T`` with ``D`` block diagonal (blocks ``[[s, k_i], [-1/m_i, s]]``,
    determinant ``d_i = s**2 + k_i/m_i``), ``u = a_i e_{p_i}``, ``w = a_j/m_j e_{p_j}``.
    Determinant lemma: ``det = prod d_i (1 + c w^T D^-1 u)`` and ``(D_i^-1)_{pp} = s/d_i``,
    so ``den = prod d_i + c s sum_i (a_i**2/m_i) prod_{j != i} d_j``.  Sherman-Morrison with
    ``B = beta u``: ``C (sI - A)^-1 B = beta C D^-1 u / (1 + c w^T D^-1 u)``, and
    ``(D_i^-1)_{qp} = (1/m_i)/d_i``: ``num = beta sum_i (a_i b_i/m_i) prod_{j != i} d_j``.
    """
    m, k, a, b, c, beta = symbols
    d = [s**2 + k[i] / m[i] for i in range(n)]

    def others(i):
        return sp.Mul(*[d[j] for j in range(n) if j != i])
    den = sp.Mul(*d) + c * s * sp.Add(*[a[i] ** 2 / m[i] * others(i) for i in range(n)])
    num = beta * sp.Add(*[a[i] * b[i] / m[i] * others(i) for i in range(n)])
    return num, den


def random_point(symbols, rng):
    return {x: sp.Rational(rng.randint(1, 40), rng.randint(1, 9)) for x in symbols}


@pytest.mark.parametrize("n", [3, 4, 6])
def test_modal_star_transfer_function_against_closed_form(n):
    A, B, C, syms = modal_star(n)
    # the lift is what computes it: the pencil's Laplace expansion alone is refused
    enc = encode_system(A, B, C, sp.zeros(1, 1), None, s)
    pencil = enc.pencil()
    L, divisors = lifted(pencil, enc.ring)
    assert len(divisors) == 1 and len(L) == 2 * n + 1
    G = transfer_function(A, B, C, 0)
    num, den = star_closed_form(n, syms)
    flat = [x for group in syms[:4] for x in group] + list(syms[4:])
    rng = random.Random(n)
    for _ in range(3):
        at = random_point(flat, rng)
        at[s] = sp.Rational(rng.randint(-20, 20), rng.randint(1, 5))
        want = num.xreplace(at) / den.xreplace(at)
        got = G.num.as_expr().xreplace(at) / G.den.as_expr().xreplace(at)
        assert got == want


def test_modal_star_determinant_is_a_product_plus_a_sum():
    # the determinant itself, as a polynomial: det(sI - A) times prod m_i is
    # prod (m_i s**2 + k_i) + c s sum_i a_i**2 prod_{j != i} (m_j s**2 + k_j)
    n = 5
    A, B, C, syms = modal_star(n)
    m, k, a, b, c, beta = syms
    G = transfer_function(A, B, C, 0, normalize="as-derived")
    e = [m[i] * s**2 + k[i] for i in range(n)]
    want = sp.Mul(*e) + c * s * sp.Add(*[a[i] ** 2 * sp.Mul(*[e[j] for j in range(n) if j != i])
                                         for i in range(n)])
    assert sp.expand(G.den.as_expr() - want) == 0


def _random_block_plus_rank_one(rng: random.Random, R, nvars: int):
    """Block diagonal (blocks of 1..3 with s on the diagonal and sparse random entries)
    plus ``u w^T`` on random rows and columns (at least three of each), where the
    blocks hold only their ``s`` (as the modal star's rows hold only ``s`` in its
    coupled block)."""
    gens = [R.gen(i) for i in range(nvars)]

    def entry():
        x = R.const(rng.randint(-3, 3))
        for _ in range(rng.randint(0, 2)):
            x = x + rng.randint(1, 3) * gens[rng.randint(1, nvars - 1)]
        return x
    sizes = []
    while sum(sizes) < 10:
        sizes.append(rng.randint(1, 3))
    n = sum(sizes)
    rows = set(rng.sample(range(n), rng.randint(3, n // 2)))
    cols = set(rng.sample(range(n), rng.randint(3, n // 2)))
    M = [[R.zero] * n for _ in range(n)]
    at = 0
    for size in sizes:
        for i in range(at, at + size):
            for j in range(at, at + size):
                free = R.zero if (i in rows and j in cols) or rng.random() < 0.3 else entry()
                M[i][j] = (gens[0] if i == j else R.zero) + free
        at += size
    u = {i: gens[rng.randint(1, nvars - 1)] + rng.randint(1, 2) for i in rows}
    w = {j: rng.randint(1, 3) * gens[rng.randint(1, nvars - 1)] for j in cols}
    for i in rows:
        for j in cols:
            M[i][j] = M[i][j] + u[i] * w[j]
    return M


@pytest.mark.parametrize("seed", range(12))
def test_lifted_determinant_matches_berkowitz_at_random_points(seed):
    rng = random.Random(seed)
    nvars = 5
    R = make_ring(nvars, "flint")
    M = _random_block_plus_rank_one(rng, R, nvars)
    symbols = sp.symbols(f"x0:{nvars}")
    found = rank_one_lift(M, R)
    assert found is not None
    L, d = found.matrix, found.divisor
    by_lift = R.exquo(determinant(L, R), d)
    det = lifted_determinant(M, R)
    Ms = sp.Matrix([[R.to_sympy(p, symbols) for p in row] for row in M])
    for _ in range(2):
        at = {x: sp.Rational(rng.randint(-30, 30), rng.randint(1, 7)) for x in symbols}
        want = Ms.xreplace(at).det(method="berkowitz")
        assert R.to_sympy(by_lift, symbols).xreplace(at) == want
        assert R.to_sympy(det, symbols).xreplace(at) == want


def test_rank_one_lift_finds_no_block_in_a_chain():
    # a tridiagonal chain has no three rows proportional on three common columns
    R = make_ring(3, "flint")
    x, a, b = R.gen(0), R.gen(1), R.gen(2)
    n = 6
    M = [[R.zero] * n for _ in range(n)]
    for i in range(n):
        M[i][i] = x + a
        if i + 1 < n:
            M[i][i + 1] = b
            M[i + 1][i] = -b
    assert rank_one_lift(M, R) is None
    assert lifted(M, R) == (M, [])


def test_lift_not_taken_for_other_methods():
    A, B, C, _ = modal_star(3)
    enc = encode_system(A, B, C, sp.zeros(1, 1), None, s)
    pencil = enc.pencil()
    for method in ("laplace", "bareiss"):
        assert lifted(pencil, enc.ring, method)[1] == []
    ref = transfer_function(A, B, C, 0, method="bareiss")
    G = transfer_function(A, B, C, 0)
    assert (G.num, G.den) == (ref.num, ref.den)


def test_flexcam_paper_form_matches_bareiss():
    # models/flexcam.py, 4 modes: the lifted path and fraction-free elimination (an
    # independent algorithm, no lift) give the same polynomials
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "models"))
    import flexcam

    import bondgraph as bg

    g, outputs, _ = flexcam.build(4)
    ss = bg.derive(g, outputs=outputs).state_space()
    i, j = ss.output_names.index("y"), ss.input_names.index("hub.e_in")
    args = (ss.A, ss.B[:, j], ss.C[i, :], ss.D[i:i + 1, j:j + 1])
    G = transfer_function(*args)
    ref = transfer_function(*args, method="bareiss")
    assert (G.num, G.den) == (ref.num, ref.den)


@pytest.mark.parametrize("n", [3, 5, 8])
def test_term_bound_of_the_modal_star_is_its_exact_size(n):
    # before clearing 1/m_i (a variable r_i each): prod_i (s**2 + k_i r_i) has 2**n terms
    # and c s sum_i a_i**2 r_i prod_{j != i} (s**2 + k_j r_j) n 2**(n-1), all distinct
    # monomials (by hand); the bound through the lift (the coupled block holds one term
    # per entry, the blocks [[s, k_i], [-r_i, s]] two per permanent) is exactly that
    from bondgraph.tf._budget import term_bound

    A, B, C, _ = modal_star(n)
    enc = encode_system(A, B, C, sp.zeros(1, 1), None, s)
    want = 2 ** n + n * 2 ** (n - 1)
    assert term_bound(enc.pencil(), enc.ring) == want
    assert enc.ring.nterms(lifted_determinant(enc.pencil(), enc.ring)) == want


def test_budget_refuses_the_flexcam_series_close_to_its_answer():
    # 12 modes: 53,248 + 24,576 terms before clearing; the bound says 102,400, so a
    # budget of 100,000 refuses before expanding and one of 110,000 lets it through
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))
    import bench_tf

    from bondgraph.tf.errors import TermBudgetError

    args = bench_tf.flexcam(12)
    with pytest.raises(TermBudgetError, match="102,400 terms"):
        transfer_function(*args, max_terms=100_000)
    G = transfer_function(*args, max_terms=110_000)
    assert G.order == 24
