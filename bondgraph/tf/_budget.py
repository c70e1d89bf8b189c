"""Term budgets of symbolic transfer functions: an estimate before expansion (private).

The determinants ``det(sE - A)`` and ``det([[sE - A, B_j], [-C_i, D_ij]])``
expand into at most as many terms as the *permanent* of the matrix of term
counts of the entries (each product of one term per entry along a
permutation is one monomial; cancellation and merging only lower the
count).  :func:`term_bound` computes that permanent with the memoized
expansion over row subsets that the determinants use (the same column order,
so it costs what the plan of the determinant costs, on small integers), and
falls back to the product of the row (or column) sums of the counts when the
plan is too large.  Where the determinant lifts a rank-one block out
(:mod:`bondgraph.tf._lift`), so does the bound
(:func:`~bondgraph.tf._lift.lifted_counts`): FLEXCAM's tip deflection with 12
modes bounds at 102,400 terms for 77,824 computed (34 trillion without the lift).  :func:`check_budget` refuses, with
:class:`~bondgraph.tf.errors.TermBudgetError`, a transfer function whose
bound exceeds ``max_terms`` before anything is expanded.

Examples
--------
>>> from bondgraph.tf._rings import make_ring
>>> R = make_ring(3)
>>> s, a, b = R.gen(0), R.gen(1), R.gen(2)
>>> term_bound([[s + a + b, a], [b, s + a]], R)       # 3*2 + 1*1: det has 7 products
7
"""

from __future__ import annotations

from math import prod
from typing import Any, Optional, Sequence

from ._determinants import _laplace_plan
from ._encode import EncodedSystem
from ._lift import lifted_counts
from ._rings import Ring
from .errors import InvalidOptionError, TermBudgetError

__all__ = ["DEFAULT_MAX_TERMS", "term_bound", "check_budget"]

#: default ``max_terms`` of :func:`~bondgraph.tf.transfer_function`: no budget.  The
#: bound is close for a modal beam (9 modes: 330,000 bounded, 197,000 in the answer;
#: FLEXCAM's paper form through its lifted hub coupling, 12 modes: 102,400 bounded,
#: 77,824 computed) but loose where entries cancel (the 20-state chain: 21 million
#: bounded, 699,071 terms; FLEXCAM's 18-state system form in notebook 02: 3.9 billion
#: bounded), and computing it costs time of its own on large pencils, so the guard is
#: asked for explicitly (``max_terms=30_000_000`` refuses the 14-mode beam in under a
#: second)
DEFAULT_MAX_TERMS: Optional[int] = None

#: subset states the permanent's expansion may visit before the cheap bound is used
_PLAN_LIMIT = 2_000_000


def _permanent(counts: Sequence[Sequence[int]], order: Sequence[int]) -> int:
    """Permanent of a non-negative integer matrix by expansion over row subsets, columns in
    ``order`` (rows required after each step as in the determinant's Laplace expansion)."""
    n = len(counts)
    colrows = [[i for i in range(n) if counts[i][c]] for c in order]
    last = [0] * n
    for t, rows in enumerate(colrows):
        for r in rows:
            last[r] = t
    required = [0] * n
    for r in range(n):
        required[last[r]] |= 1 << r
    dp = {0: 1}
    req = 0
    for t, c in enumerate(order):
        req |= required[t]
        new: dict[int, int] = {}
        for mask, val in dp.items():
            for r in colrows[t]:
                bit = 1 << r
                if mask & bit:
                    continue
                nm = mask | bit
                if nm & req != req:
                    continue
                new[nm] = new.get(nm, 0) + val * counts[r][c]
        dp = new
        if not dp:
            return 0
    return dp.get((1 << n) - 1, 0)


def term_bound(M: Sequence[Sequence[Any]], ring: Ring) -> int:
    """An upper bound on the number of terms of ``det(M)`` (ring elements), before expanding.

    Examples
    --------
    >>> from bondgraph.tf._rings import make_ring
    >>> R = make_ring(2)
    >>> x, y = R.gen(0), R.gen(1)
    >>> term_bound([[x + y, R.zero], [R.zero, x - y]], R)
    4
    """
    n = len(M)
    if n == 0:
        return 1
    # through the rank-one lifts the determinant takes (see _lift.lifted_counts)
    counts = lifted_counts(M, ring)
    pattern = [[c > 0 for c in row] for row in counts]
    best = None
    for transpose in (False, True):
        pat = pattern if not transpose else [list(r) for r in zip(*pattern)]
        plan = _laplace_plan(pat, _PLAN_LIMIT)
        if plan is not None and (best is None or plan[1] < best[2]):
            best = (transpose, plan[0], plan[1])
    if best is not None:
        transpose, order, _ = best
        if not order:
            return 0
        return _permanent(counts if not transpose else [list(r) for r in zip(*counts)], order)
    rows = prod(sum(r) for r in counts)
    cols = prod(sum(c) for c in zip(*counts))
    return min(rows, cols)


def check_budget(enc: EncodedSystem, pairs: Sequence[tuple[int, int]],
                 max_terms: Optional[int], what: str) -> int:
    """The bound on the terms of ``det(sE - A)`` and the numerators of ``pairs``; raises
    :class:`TermBudgetError` when it exceeds ``max_terms`` (None: no budget, nothing
    estimated, returns 0)."""
    if max_terms is None:
        return 0
    if isinstance(max_terms, bool) or not isinstance(max_terms, int) or max_terms < 1:
        raise InvalidOptionError(f"max_terms: expected a positive integer or None, "
                                 f"got {max_terms!r}")
    pencil = enc.pencil()
    den = term_bound(pencil, enc.ring)
    total = den
    for i, j in pairs:
        total += term_bound(enc.bordered(pencil, i, j), enc.ring)
        if total > max_terms:
            break
    if total > max_terms:
        raise TermBudgetError(
            f"{what}: det(sE - A) ({enc.n} states, {len(enc.params)} parameters) and its "
            f"numerator(s) may expand to {total:,} terms (an upper bound from the terms of "
            f"each matrix entry), more than max_terms={max_terms:,}; refused before "
            "expansion.  Give some parameters numeric values, ask for fewer "
            "inputs/outputs, or pass a larger max_terms (None: no budget)")
    return total
