"""Division-free determinants of matrices of ring elements.

Third stage of the exact algebra (:mod:`bondgraph.tf._algebra`): a memoized
Laplace expansion over row subsets (cheap for the sparse pencils of lumped
models), fraction-free Bareiss elimination for dense matrices, and sympy's
``DomainMatrix.charpoly`` (Berkowitz) for cross-checking.

Examples
--------
>>> from bondgraph.tf._rings import make_ring
>>> R = make_ring(1)
>>> x = R.gen(0)
>>> sorted(R.terms(determinant([[x, R.one], [-R.one, x]], R)))
[((0,), 1), ((2,), 1)]
"""

from __future__ import annotations

from collections import defaultdict
from fractions import Fraction
from typing import Any, Sequence

import sympy as sp

from ._encode import EncodedSystem
from ._rings import Ring
from .errors import InvalidOptionError

__all__ = ["determinant", "charpoly_berkowitz", "split_s", "LAPLACE_MIN", "laplace_cost",
           "laplace_limit"]

#: ``method='auto'`` uses the Laplace expansion while it needs at most
#: ``max(n**3, LAPLACE_MIN)`` ring products (about what Bareiss needs, but with
#: far smaller intermediate polynomials), Bareiss otherwise.
LAPLACE_MIN = 64


def determinant(M: Sequence[Sequence[Any]], ring: Ring, *, method: str = "auto"):
    """Determinant of a square matrix of ring elements, division free.

    ``method`` is ``'auto'`` (Laplace expansion over row subsets when it is
    cheap, else Bareiss), ``'laplace'`` or ``'bareiss'``.

    Examples
    --------
    >>> from bondgraph.tf._rings import make_ring
    >>> R = make_ring(1)
    >>> x = R.gen(0)
    >>> d = determinant([[x, R.one], [R.one, x]], R)
    >>> sorted(R.terms(d))
    [((0,), -1), ((2,), 1)]
    """
    n = len(M)
    if n == 0:
        return ring.one
    if method not in ("auto", "laplace", "bareiss"):
        raise InvalidOptionError(f"method: expected 'auto', 'laplace' or 'bareiss', "
                                 f"got {method!r}")
    if method == "bareiss":
        return _bareiss(M, ring)
    best = _best_plan(M, ring, None if method == "laplace" else laplace_limit(n))
    if best is None:
        return _bareiss(M, ring)
    transpose, order, _ = best
    if transpose:
        M = [list(r) for r in zip(*M)]
    return _laplace(M, ring, order)


def laplace_limit(n: int) -> int:
    """The most ring products ``method='auto'`` spends on a Laplace expansion of order ``n``."""
    return max(n ** 3, LAPLACE_MIN)


def laplace_cost(M: Sequence[Sequence[Any]], ring: Ring, limit: int | None) -> int | None:
    """Ring products of the Laplace expansion of ``M`` (the cheaper of ``M`` and its
    transpose), or ``None`` past ``limit``.

    Examples
    --------
    >>> from bondgraph.tf._rings import make_ring
    >>> R = make_ring(1)
    >>> x, o, z = R.gen(0), R.one, R.zero
    >>> laplace_cost([[x, o, z], [z, x, o], [o, z, x]], R, None)
    6
    """
    best = _best_plan(M, ring, limit)
    return None if best is None else best[2]


def _best_plan(M, ring: Ring, limit: int | None) -> tuple[bool, list[int], int] | None:
    n = len(M)
    pattern = [[ring.is_zero(M[i][j]) is False for j in range(n)] for i in range(n)]
    best = None
    for transpose in (False, True):
        pat = pattern if not transpose else [list(r) for r in zip(*pattern)]
        plan = _laplace_plan(pat, limit)
        if plan is not None and (best is None or plan[1] < best[2]):
            best = (transpose, plan[0], plan[1])
    return best


def _laplace_plan(pattern: Sequence[Sequence[bool]],
                  limit: int | None) -> tuple[list[int], int] | None:
    """Column order for the Laplace expansion and its number of ring products.

    Returns ``None`` when the expansion would exceed ``limit`` products.
    """
    n = len(pattern)
    colrows = [frozenset(i for i in range(n) if pattern[i][j]) for j in range(n)]
    rowcount = [sum(1 for j in range(n) if pattern[i][j]) for i in range(n)]
    if any(not c for c in colrows) or any(c == 0 for c in rowcount):
        return [], 0  # structurally singular: determinant is zero
    # greedy order: keep the set of open rows (touched, not finished) small
    remaining = set(range(n))
    seen_count = [0] * n
    touched: set[int] = set()
    order = []
    while remaining:
        def key(c):
            rows = colrows[c]
            opened = len(touched | rows)
            closed = sum(1 for r in touched | rows
                         if seen_count[r] + (r in rows) == rowcount[r])
            return (opened - closed, len(rows), c)
        c = min(remaining, key=key)
        order.append(c)
        remaining.discard(c)
        for r in colrows[c]:
            seen_count[r] += 1
        touched |= colrows[c]
    # required rows after each step
    last = [0] * n
    for t, c in enumerate(order):
        for r in colrows[c]:
            last[r] = t
    required = [0] * n
    for r in range(n):
        required[last[r]] |= 1 << r
    states = {0}
    cost = 0
    req = 0
    for t, c in enumerate(order):
        req |= required[t]
        new = set()
        for mask in states:
            for r in colrows[c]:
                bit = 1 << r
                if not mask & bit:
                    nm = mask | bit
                    if nm & req == req:
                        new.add(nm)
                        cost += 1
        if limit is not None and cost > limit:
            return None
        states = new
        if not states:
            return order, cost
    return order, cost


def _laplace(M: Sequence[Sequence[Any]], ring: Ring, order: Sequence[int]) -> Any:
    n = len(M)
    if not order:
        return ring.zero
    is_zero = ring.is_zero
    colrows = [[i for i in range(n) if not is_zero(M[i][c])] for c in order]
    last = [0] * n
    for t, rows in enumerate(colrows):
        for r in rows:
            last[r] = t
    required = [0] * n
    for r in range(n):
        required[last[r]] |= 1 << r
    # sign of the column permutation
    sign = _perm_sign(order)
    dp = {0: ring.one if sign > 0 else -ring.one}
    req = 0
    for t, c in enumerate(order):
        req |= required[t]
        new: dict[int, Any] = {}
        for mask, val in dp.items():
            for r in colrows[t]:
                bit = 1 << r
                if mask & bit:
                    continue
                nm = mask | bit
                if nm & req != req:
                    continue
                term = val * M[r][c]
                if bin(mask >> (r + 1)).count("1") & 1:
                    term = -term
                if nm in new:
                    new[nm] = new[nm] + term
                else:
                    new[nm] = term
        dp = {k: v for k, v in new.items() if not is_zero(v)}
        if not dp:
            return ring.zero
    return dp.get((1 << n) - 1, ring.zero)


def _perm_sign(perm) -> int:
    perm = list(perm)
    sign = 1
    seen = [False] * len(perm)
    for i in range(len(perm)):
        if seen[i]:
            continue
        j, length = i, 0
        while not seen[j]:
            seen[j] = True
            j = perm[j]
            length += 1
        if length % 2 == 0:
            sign = -sign
    return sign


def _bareiss(M, ring):
    """Fraction-free Gaussian elimination (exact divisions in the ring)."""
    n = len(M)
    M = [list(row) for row in M]
    is_zero = ring.is_zero
    sign = 1
    prev = ring.one
    for k in range(n - 1):
        candidates = [i for i in range(k, n) if not is_zero(M[i][k])]
        if not candidates:
            return ring.zero
        p = min(candidates, key=lambda i: ring.nterms(M[i][k]))
        if p != k:
            M[k], M[p] = M[p], M[k]
            sign = -sign
        pivot = M[k][k]
        for i in range(k + 1, n):
            mik = M[i][k]
            for j in range(k + 1, n):
                v = M[i][j] * pivot
                if not is_zero(mik) and not is_zero(M[k][j]):
                    v = v - mik * M[k][j]
                M[i][j] = ring.exquo(v, prev) if not is_zero(v) else v
        prev = pivot
    d = M[n - 1][n - 1]
    return d if sign > 0 else -d


def charpoly_berkowitz(enc: EncodedSystem) -> tuple[Any, list[Any]]:
    """``det(sI - A)`` and the numerators via sympy's ``DomainMatrix.charpoly``.

    Numerators by the matrix determinant lemma,
    ``C_i adj(sI - A) B_j = det(sI - A + B_j C_i) - det(sI - A)``.
    Only for ``E = I``.  Returns ``(den, nums)`` with ``nums[i][j]``.
    """
    from sympy.polys.matrices import DomainMatrix

    ring, n = enc.ring, enc.n
    nv = ring.nvars - 1
    R = sp.polys.rings.PolyRing([sp.Dummy(f"y{i}") for i in range(max(nv, 1))], sp.QQ)
    dom = R.to_domain()

    def to_dom(p):
        d = {}
        for exps, c in ring.terms(p):
            d[exps[1:] if nv else (0,)] = sp.QQ(c.numerator, c.denominator)
        return R.from_dict(d)

    def from_coeffs(coeffs):
        terms = {}
        deg = len(coeffs) - 1
        for k, c in enumerate(coeffs):
            for exps, v in c.items():
                key = (deg - k,) + (tuple(exps) if nv else ())
                terms[key] = Fraction(int(sp.QQ.numer(v)), int(sp.QQ.denom(v)))
        return ring.from_terms(terms)

    Ad = [[to_dom(x) for x in row] for row in enc.A]
    dA = DomainMatrix(Ad, (n, n), dom)
    den = from_coeffs(dA.charpoly())
    s = ring.gen(0)
    nums = []
    for i, crow in enumerate(enc.C):
        row = []
        for j in range(len(enc.B[0]) if enc.B else 0):
            # B_j(s) = sum_k s**k B_jk (input derivatives): one lemma per power of s
            parts: dict[int, list] = defaultdict(lambda: [ring.zero] * n)
            for r in range(n):
                for k, piece in split_s(enc.B[r][j], ring).items():
                    parts[k][r] = piece
            num = enc.D[i][j] * den
            for k, col in parts.items():
                bc = [[to_dom(col[r] * crow[c]) for c in range(n)] for r in range(n)]
                pert = from_coeffs((dA - DomainMatrix(bc, (n, n), dom)).charpoly())
                term = pert - den
                for _ in range(k):
                    term = term * s
                num = num + term
            row.append(num)
        nums.append(row)
    return den, nums


def split_s(p, ring: Ring) -> dict[int, Any]:
    """``{k: p_k}`` with ``p = sum s**k p_k`` and no ``s`` in the ``p_k``.

    Examples
    --------
    >>> from bondgraph.tf._rings import make_ring
    >>> R = make_ring(2)
    >>> s, a = R.gen(0), R.gen(1)
    >>> {k: R.terms(v) for k, v in split_s(s**2 * a + a + 1, R).items()} == {
    ...     0: [((0, 1), 1), ((0, 0), 1)], 2: [((0, 1), 1)]}
    True
    """
    groups: dict[int, dict] = defaultdict(dict)
    for exps, c in ring.terms(p):
        groups[exps[0]][(0,) + tuple(exps[1:])] = c
    return {k: ring.from_terms(v) for k, v in groups.items()}
