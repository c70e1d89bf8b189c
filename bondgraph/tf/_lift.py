"""Rank-one couplings lifted out of a matrix before its determinant.

Eliminating a junction from bond-graph equations couples every storage element
it joins: the state matrix of a hub driving ``n`` flexible modes holds the
dense block ``-c a_i a_j / m_j`` (the hub's damping and back-emf seen by each
pair of modes), and its pencil is a star of second-order blocks around that
rank-one block.  No Laplace expansion order is cheap on a dense block, and
fraction-free elimination builds every intermediate minor (FLEXCAM's
tip deflection: 2.5 s for 10 modes, no answer for 14).  Writing the block as
``u w^T / d`` and lifting it into one more row and column,

.. math:: \\det\\begin{bmatrix} S & u \\\\ -w^T & d \\end{bmatrix}
          = d \\det(S + u w^T / d) = d \\det M,

gives back a sparse matrix (the junction variable restored) whose Laplace
expansion runs block by block; one exact division by ``d`` at the end.  The
determinant is the same polynomial whichever way it is computed.

The block is found on the ``s``-free parts of the entries: rows linked when
they are proportional on at least three common columns, the largest linked
group's common columns checked to be exactly rank one.

Examples
--------
A diagonal plus the rank-one block ``[[a*a, a*b], [b*a, b*b]]`` of three rows:

>>> from bondgraph.tf._rings import make_ring
>>> R = make_ring(4)
>>> s, a, b, c = (R.gen(i) for i in range(4))
>>> v = [a, b, c]
>>> M = [[(s if i == j else R.zero) + v[i] * v[j] for j in range(3)] for i in range(3)]
>>> L, d, *_ = rank_one_lift(M, R)
>>> len(L), R.exquo(determinant(L, R), d) == determinant(M, R, method="bareiss")
(4, True)
"""

from __future__ import annotations

from typing import Any, NamedTuple, Sequence

from ._determinants import determinant, laplace_cost, laplace_limit
from ._rings import Ring

__all__ = ["Lift", "rank_one_lift", "lift_steps", "lifted", "lifted_counts",
           "lifted_determinant", "MIN_BLOCK"]

#: smallest side of a rank-one block worth lifting
MIN_BLOCK = 3

#: most blocks lifted out of one matrix
MAX_LIFTS = 8


def _s_free(p, ring: Ring):
    if ring.is_zero(p):
        return p
    return ring.from_terms({e: c for e, c in ring.terms(p) if e[0] == 0})


def _find(parent: list[int], x: int) -> int:
    while parent[x] != x:
        parent[x] = parent[parent[x]]
        x = parent[x]
    return x


class Lift(NamedTuple):
    """One rank-one block ``f`` of ``M`` (rows ``rows``, columns ``cols``) lifted:
    ``det(matrix) = divisor * det M``."""

    matrix: list[list[Any]]
    divisor: Any
    rows: tuple[int, ...]
    cols: tuple[int, ...]
    #: per row of the block, the most terms of an entry ``f_ij``
    row_terms: tuple[int, ...]


def rank_one_lift(M: Sequence[Sequence[Any]], ring: Ring) -> Lift | None:
    """:class:`Lift` ``(L, d, ...)`` with ``det L = d * det M`` and ``M``'s largest
    rank-one block (of ``s``-free parts) moved into one more row and column;
    ``None`` when there is no such block of at least :data:`MIN_BLOCK` rows and
    columns.

    Variable 0 of ``ring`` is ``s``.  See the module docstring.
    """
    n = len(M)
    if n < MIN_BLOCK:
        return None
    f = [[_s_free(p, ring) for p in row] for row in M]
    supp = [frozenset(j for j in range(n) if not ring.is_zero(f[i][j])) for i in range(n)]
    parent = list(range(n))
    for i in range(n):
        for i2 in range(i + 1, n):
            common = supp[i] & supp[i2]
            if len(common) < MIN_BLOCK or _find(parent, i) == _find(parent, i2):
                continue
            k0 = min(common)
            if all(f[i][k] * f[i2][k0] == f[i2][k] * f[i][k0] for k in common):
                parent[_find(parent, i2)] = _find(parent, i)
    groups: dict[int, list[int]] = {}
    for i in range(n):
        groups.setdefault(_find(parent, i), []).append(i)
    rows = max(groups.values(), key=len)
    if len(rows) < MIN_BLOCK:
        return None
    cols = sorted(frozenset.intersection(*(supp[i] for i in rows)))
    if len(cols) < MIN_BLOCK:
        return None
    i0, j0 = min(((i, j) for i in rows for j in cols), key=lambda ij: ring.nterms(f[ij[0]][ij[1]]))
    d = f[i0][j0]
    if not all(f[i][j] * d == f[i][j0] * f[i0][j] for i in rows for j in cols):
        return None
    rset, cset = set(rows), set(cols)
    L = []
    for i in range(n):
        row = [M[i][j] - f[i][j] if i in rset and j in cset else M[i][j] for j in range(n)]
        row.append(f[i][j0] if i in rset else ring.zero)
        L.append(row)
    L.append([-f[i0][j] if j in cset else ring.zero for j in range(n)] + [d])
    return Lift(L, d, tuple(rows), tuple(cols),
                tuple(max(ring.nterms(f[i][j]) for j in cols) for i in rows))


def lifted(M: Sequence[Sequence[Any]], ring: Ring,
           method: str = "auto") -> tuple[Sequence[Sequence[Any]], list[Any]]:
    """``(L, divisors)``: ``det M = det L / prod(divisors)``.

    With ``method='auto'``, rank-one blocks are lifted (:func:`rank_one_lift`)
    while each lift makes the Laplace expansion cheaper (or possible where
    ``auto`` would otherwise fall back to Bareiss); any other method, or no
    such block, returns ``(M, [])``.

    Examples
    --------
    >>> from bondgraph.tf._rings import make_ring
    >>> R = make_ring(2)
    >>> s, a = R.gen(0), R.gen(1)
    >>> lifted([[s, a], [a, s]], R)[1]          # no block of three
    []
    """
    if method != "auto":
        return M, []
    steps = lift_steps(M, ring)
    return (steps[-1].matrix if steps else M), [x.divisor for x in steps]


def lift_steps(M: Sequence[Sequence[Any]], ring: Ring) -> list[Lift]:
    """The lifts :func:`lifted` takes, in order: each while it makes the Laplace
    expansion cheaper (or possible where ``auto`` would fall back to Bareiss)."""
    steps: list[Lift] = []
    cost: int | None = None
    for _ in range(MAX_LIFTS):
        found = rank_one_lift(M, ring)
        if found is None:
            break
        if not steps:        # planned only when there is something to lift
            cost = laplace_cost(M, ring, laplace_limit(len(M)))
        new = laplace_cost(found.matrix, ring,
                           laplace_limit(len(found.matrix)) if cost is None else cost - 1)
        if new is None:
            break
        M, cost = found.matrix, new
        steps.append(found)
    return steps


def lifted_counts(M: Sequence[Sequence[Any]], ring: Ring) -> list[list[int]]:
    """Term counts whose permanent bounds the terms of ``det M`` through its lifts.

    A rank-one block ``f`` adds to ``det S`` (``S = M - f``) only first-order
    terms: ``det M = det S + sum_ij f_ij C_ij(S)`` with ``C_ij`` the cofactors of
    ``S``.  So ``terms(det M) <= perm(|S|) + sum_ij |f_ij| perm(|S_ij|)``, the
    permanent of ``|S|`` bordered by the column ``max_j |f_ij|`` (the block's
    rows), the row of ones (its columns) and a corner 1, where ``|x|`` counts
    terms.  Without a lift: the counts of ``M``.

    Examples
    --------
    >>> from bondgraph.tf._rings import make_ring
    >>> R = make_ring(3)
    >>> s, a, b = (R.gen(i) for i in range(3))
    >>> M = [[s + (a + b) * a if i == j else (a + b) * a for j in range(3)] for i in range(3)]
    >>> lifted_counts(M, R)[-1], [row[-1] for row in lifted_counts(M, R)]
    ([1, 1, 1, 1], [2, 2, 2, 1])
    """
    counts = [[0 if ring.is_zero(p) else ring.nterms(p) for p in row] for row in M]
    for step in lift_steps(M, ring):
        n = len(counts)
        L = step.matrix
        block = set(step.rows), set(step.cols)
        counts = [[(0 if ring.is_zero(L[i][j]) else ring.nterms(L[i][j]))
                   if i in block[0] and j in block[1] else counts[i][j] for j in range(n)]
                  for i in range(n)]
        for i, top in zip(step.rows, step.row_terms):
            counts[i].append(top)
        for i in set(range(n)) - block[0]:
            counts[i].append(0)
        counts.append([1 if j in block[1] else 0 for j in range(n)] + [1])
    return counts


def lifted_determinant(M: Sequence[Sequence[Any]], ring: Ring, *, method: str = "auto"):
    """:func:`~bondgraph.tf._determinants.determinant` through :func:`lifted`.

    Examples
    --------
    >>> from bondgraph.tf._rings import make_ring
    >>> R = make_ring(1)
    >>> x = R.gen(0)
    >>> sorted(R.terms(lifted_determinant([[x, R.one], [-R.one, x]], R)))
    [((0,), 1), ((2,), 1)]
    """
    L, divisors = lifted(M, ring, method)
    det = determinant(L, ring, method=method)
    for d in divisors:
        det = ring.exquo(det, d)
    return det
