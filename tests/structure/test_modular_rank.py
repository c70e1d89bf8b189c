"""Kalman ranks modulo primes against exact rational ranks, on small random systems.

The reference is sympy's exact rank over the rationals of the Kalman matrix
``[B AB ... A^(n-1) B]`` and its left kernel (written here, independent of the
modular route in :mod:`bondgraph.structure.reach`).
"""

from __future__ import annotations

import random

import pytest
import sympy

from bondgraph.structure import reach
from bondgraph.structure.reach import _kalman_rank_and_lost


def _random_system(rng: random.Random):
    n, m = rng.randint(1, 6), rng.randint(1, 2)
    density = rng.choice([0.2, 0.4, 0.7])
    A = sympy.Matrix(n, n, lambda i, j: sympy.Rational(rng.randint(-9, 9), rng.randint(1, 7))
                     if rng.random() < density else 0)
    B = sympy.Matrix(n, m, lambda i, j: rng.randint(-3, 3) if rng.random() < density else 0)
    if rng.random() < 0.3:        # an uncontrollable block: a state no one drives
        k = rng.randrange(n)
        for j in range(n):
            if j != k:
                A[k, j] = 0
        B[k, :] = sympy.zeros(1, m)
    return A, B


@pytest.mark.parametrize("exact_max", [40, 0], ids=["exact-confirms", "primes-only"])
@pytest.mark.parametrize("seed", range(40))
def test_kalman_rank_and_lost_states(seed, exact_max, monkeypatch):
    monkeypatch.setattr(reach, "KALMAN_EXACT_MAX", exact_max)
    A, B = _random_system(random.Random(seed))
    n = A.rows
    K = sympy.Matrix.hstack(*[A**k * B for k in range(n)])
    rank = K.rank()
    left = K.T.nullspace()
    lost = tuple(i for i in range(n) if any(v[i] != 0 for v in left))
    assert _kalman_rank_and_lost([A.row_join(B)], n) == (rank, lost if rank < n else ())
