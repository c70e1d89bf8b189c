"""Fast paths of the linear forms (``bondgraph.linear.forms``) against sympy's own constructors.

``sparse_matrix`` must build the very object ``ImmutableSparseMatrix`` builds
(same ``args``, hash and representation), and the term helpers must agree
with ``Mul(*args)`` and ``free_symbols`` on every shape of term.
"""

from __future__ import annotations

import random

import sympy

from bondgraph.linear.forms import _free_symbols, _mul_rest, sparse_matrix

a, b, c = sympy.symbols("a b c", positive=True)
x, y = sympy.symbols("x y")
POOL = [a, -b / c, a * b + 1, sympy.Rational(3, 2), sympy.Integer(-1), sympy.Integer(1),
        a**2 / (b + c), sympy.sqrt(2) * a, 2 * (a + b), sympy.Float(0.5), sympy.sin(a) * b,
        -x / a, x * y, sympy.Integer(0), 3 * x**2 * b / c]


def test_sparse_matrix_is_sympys_matrix():
    rng = random.Random(1)
    for _ in range(300):
        rows, cols = rng.randint(1, 6), rng.randint(1, 6)
        entries = {(rng.randrange(rows), rng.randrange(cols)): rng.choice(POOL)
                   for _ in range(rng.randint(0, 14))}
        want = sympy.ImmutableSparseMatrix(rows, cols, entries)
        got = sparse_matrix(rows, cols, entries)
        assert type(got) is type(want)
        assert got.args == want.args and hash(got) == hash(want) and got == want
        assert got._rep == want._rep and got._rep.domain == want._rep.domain
        assert got.todok() == want.todok() and got.shape == want.shape


def test_mul_rest_and_free_symbols_match_sympy():
    rng = random.Random(2)
    factors = [x, y, a, b, 1 / c, sympy.Integer(-1), sympy.Rational(2, 3), sympy.Float(0.25),
               a + b, x + 1, sympy.sqrt(2), c**2, sympy.exp(a), x**-2, sympy.pi]
    for _ in range(500):
        term = sympy.Mul(*rng.sample(factors, rng.randint(1, 5)))
        for e in [term] + list(term.args):
            assert _free_symbols(e) == e.free_symbols
        if term.is_Mul:
            for drop in term.args:
                rest = [f for f in term.args if f != drop]
                want = sympy.Mul(*rest)
                got = _mul_rest(rest)
                assert got == want and got.args == want.args and type(got) is type(want)
