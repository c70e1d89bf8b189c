"""The flint route of exact loop solves against sympy's own field arithmetic and closed forms.

``Fractions.to_field`` must hand back exactly the element sympy's field builds
(``K.from_expr``, an independent implementation of the same normal form), and
the fraction-free rank must match ranks known by construction.
"""

from __future__ import annotations

import random

import pytest
import sympy
from sympy.polys.fields import field

from bondgraph.equations._flint_fractions import Fractions
from bondgraph.equations.fraction_free import TOO_LARGE, rank_fraction_free, solve_fraction_free

a, b, c, d = sympy.symbols("a b c d", positive=True)


def _random_rational_function(rng: random.Random):
    syms = [a, b, c, d]

    def poly():
        return sympy.Add(*[sympy.Rational(rng.randint(-9, 9), rng.randint(1, 6))
                           * sympy.Mul(*[rng.choice(syms) ** rng.randint(0, 2)
                                         for _ in range(rng.randint(0, 3))])
                           for _ in range(rng.randint(1, 4))])
    out = sympy.Integer(0)
    for _ in range(rng.randint(1, 3)):
        den = poly()
        if den == 0:
            continue
        out += poly() / den * rng.choice([1, a, b - c])
    return out


@pytest.mark.parametrize("seed", range(40))
def test_to_field_is_sympys_normal_form(seed):
    rng = random.Random(seed)
    K, *_ = field([a, b, c, d], sympy.QQ)
    F = Fractions(K)
    expr = _random_rational_function(rng)
    mine = F.to_field(*F.fraction(expr))
    ref = K.from_expr(expr)
    assert mine.numer == ref.numer and mine.denom == ref.denom
    assert mine.as_expr() == ref.as_expr()


def test_solve_by_hand():
    # [[a, 1], [1, b]] z = [1, 0]: z = [b, -1] / (a b - 1)  (Cramer)
    M = sympy.Matrix([[a, 1], [1, b]])
    X = solve_fraction_free(M, sympy.Matrix([[1], [0]]), budget=100)
    assert sympy.simplify(X[0] - b / (a * b - 1)) == 0
    assert sympy.simplify(X[1] + 1 / (a * b - 1)) == 0


@pytest.mark.parametrize("seed", range(12))
def test_rank_of_products_of_known_rank(seed):
    """``U V`` with ``U`` (n x r), ``V`` (r x m) generic has rank ``r``."""
    rng = random.Random(seed)
    n, m, r = rng.randint(2, 4), rng.randint(2, 4), rng.randint(0, 3)
    r = min(r, n, m)
    syms = [a, b, c, d]
    U = sympy.Matrix(n, r, lambda i, j: rng.choice(syms) + rng.randint(-3, 3))
    V = sympy.Matrix(r, m, lambda i, j: 1 / (rng.choice(syms) + rng.randint(1, 3)))
    M = U * V if r else sympy.zeros(n, m)
    assert rank_fraction_free(M, budget=100_000) == r


def test_rank_past_its_budget():
    M = sympy.Matrix(4, 4, lambda i, j: (a + b + c + d) ** (i + j))
    assert rank_fraction_free(M, budget=5) == TOO_LARGE


@pytest.mark.parametrize("seed", range(15))
def test_rank_against_sympys_fraction_field(seed):
    """Random matrices with dependent rows: the rank over QQ(a, b, c, d) by sympy's
    ``DomainMatrix`` (elimination over the field, an independent implementation)."""
    from sympy.polys.matrices import DomainMatrix

    rng = random.Random(100 + seed)
    syms = [a, b, c, d]

    def entry():
        return (rng.choice(syms) + rng.randint(-2, 2)) / (rng.choice(syms) + rng.randint(1, 3)) \
            if rng.random() < 0.7 else 0
    rows = [[entry() for _ in range(3)] for _ in range(2)]
    rows.append([rows[0][j] * a + rows[1][j] / (b + 1) for j in range(3)])
    M = sympy.Matrix(rows)
    assert rank_fraction_free(M, budget=100_000) == DomainMatrix.from_Matrix(M).rank()
