"""Algebraic loops and derivative-causality blocks: exact linear solves.

The unknowns that break zero-order causal loops (and the state derivatives of
a model with derivative causality) satisfy ``u = expr(u, ...)``.  They are
solved block by block (strongly connected components, in causal order).  A
block with parameter coefficients and a right-hand side linear in the knowns
(states, inputs, their derivatives) is solved exactly by fraction-free
elimination (:mod:`bondgraph.equations.fraction_free`): every coefficient
comes out as one reduced fraction, never nested, so what follows (state
space, transfer functions) stays small.  Other blocks (nonlinear laws) use
sympy's ``LUsolve``.

Budget.  A reduced fraction can be too large to write down: the symbolic
resistive ladder's Thevenin resistance has Fibonacci-many monomials in the
number of sections.  An elimination whose working matrix passes
:data:`LOOP_TERM_BUDGET` polynomial terms stops; the block's unknowns are
then kept as linear algebraic unknowns ``z`` with residuals ``0 = g(x, z,
u)`` (an implicit model, solved numerically: plants, simulation,
equilibria), or refused (:class:`LoopBudgetError`) where no implicit form
applies.
"""

from __future__ import annotations

from typing import Mapping, Optional

import networkx as nx
import sympy
from sympy.polys.matrices import DomainMatrix
from sympy.polys.polyerrors import CoercionFailed
from sympy.solvers.solveset import NonlinearError

from .._support.zero import reduced
from ..errors import AlgebraicLoopError
from .fraction_free import SINGULAR, TOO_LARGE, solve_fraction_free, to_field

__all__ = ["LOOP_TERM_BUDGET", "LoopBudgetError", "SingularLoopError", "compact_linear",
           "field_matrix", "rate_coefficients", "solve_blocks"]

#: Largest number of polynomial terms an exact loop solve may hold while it
#: eliminates (the 6-section symbolic ladder needs about 1,000 and derives in 3 s;
#: 7 sections need 2,000 and 13 s; the loops of 600 random graphs stay
#: under 300).  Past it, the loop is kept as linear algebraic unknowns.
LOOP_TERM_BUDGET = 1200


class LoopBudgetError(AlgebraicLoopError):
    """A linear loop whose exact solution passes :data:`LOOP_TERM_BUDGET` where no
    implicit form applies (a derivative-causality block)."""


class SingularLoopError(AlgebraicLoopError):
    """A singular loop block; ``storage`` names the integral storage elements in it."""

    storage: tuple[str, ...] = ()
    block: tuple = ()


def field_matrix(M: sympy.Matrix) -> Optional[DomainMatrix]:
    """``M`` over the field of rational functions of its symbols (QQ), or None.

    The domain is built directly (``QQ.frac_field``) and each entry converted by
    field arithmetic: sympy's automatic domain construction runs ``together``
    over every entry and is much slower on large loop solutions.  Floats are
    refused (None): exact arithmetic only.
    """
    syms = sorted(M.free_symbols, key=sympy.default_sort_key)
    dom = sympy.QQ.frac_field(*syms) if syms else sympy.QQ
    try:
        rows = [[dom.from_sympy(M[i, j]) for j in range(M.cols)] for i in range(M.rows)]
    except (CoercionFailed, NotImplementedError, ValueError, ZeroDivisionError):
        return None
    return DomainMatrix(rows, (M.rows, M.cols), dom)


def _solve_linear_in_knowns(M: sympy.Matrix, rhs: sympy.Matrix, knowns: set):
    """Solve ``M z = rhs`` exactly when ``M`` holds parameters only and ``rhs`` is
    linear in the knowns: the coefficients are solved by fraction-free
    elimination (reduced fractions, no nesting), so that ``z = X k + x0`` stays
    compact.  None when that form does not apply; ``SINGULAR`` when ``M`` is
    singular; ``TOO_LARGE`` past :data:`LOOP_TERM_BUDGET`."""
    n = M.rows
    if any(M[i, j].free_symbols & knowns for i in range(n) for j in range(n)):
        return None
    ks = sorted(set().union(*(r.free_symbols for r in rhs)) & knowns, key=sympy.default_sort_key)
    try:
        coeffs, const = sympy.linear_eq_to_matrix(list(rhs), ks)
    except (NonlinearError, ValueError):
        return None
    if any(c.free_symbols & knowns for c in coeffs):
        return None
    R = coeffs.row_join(-const)
    if any(e.has(sympy.Float) for e in M) or any(e.has(sympy.Float) for e in R):
        return None         # exact arithmetic only
    X = solve_fraction_free(M, R, budget=LOOP_TERM_BUDGET)
    if X is None or isinstance(X, str):
        return X
    return [sympy.Add(*(X[i, j] * k for j, k in enumerate(ks))) + X[i, len(ks)]
            for i in range(n)]



def _block_matrix(block: list, eqs: list, model: str, what: str, keep: bool):
    """``(M, rhs, nonlinear)`` with ``M u = rhs`` the block's equations ``u = expr(u)``.

    A block linear in its unknowns is read in one pass over its terms
    (``sympy.linear_eq_to_matrix``, cost proportional to its size); otherwise
    each coefficient is a derivative, zero decided exactly, and a block that
    stays nonlinear is refused unless ``keep``.
    """
    try:
        M, rhs = sympy.linear_eq_to_matrix([u - ex for u, ex in zip(block, eqs)], block)
        return M, rhs, False
    except (NonlinearError, ValueError):
        pass
    zero = {u: 0 for u in block}
    M = sympy.zeros(len(block))
    rhs = sympy.zeros(len(block), 1)
    nonlinear = False
    for i, (u, ex) in enumerate(zip(block, eqs)):
        for j, w in enumerate(block):
            a = sympy.diff(ex, w)
            if a.free_symbols & set(block):
                a = reduced(a)          # zero coefficients of unknowns, decided exactly
            if a.free_symbols & set(block):
                if not keep:
                    raise AlgebraicLoopError(
                        f"model {model!r}: the {what} in {', '.join(map(str, block))} "
                        "is nonlinear in its unknowns; give an explicit (inverse) law for "
                        "the R or storage element involved"
                    )
                nonlinear = True
            M[i, j] = (1 if i == j else 0) - a
        rhs[i] = ex.xreplace(zero)
    return M, rhs, nonlinear


def rate_coefficients(expr: sympy.Expr, rates: list) -> list[tuple[int, sympy.Expr]]:
    """``[(j, d expr / d rates[j])]`` for the rates ``expr`` holds, read in one pass over
    its terms when it is linear in them (a derivative per rate otherwise).

    Examples
    --------
    >>> import sympy
    >>> a, b, x, y = sympy.symbols("a b x y")
    >>> rate_coefficients(a*x + b*(x + y) + 1, [x, y])
    [(0, a + b), (1, b)]
    """
    held = [(j, r) for j, r in enumerate(rates) if r in expr.free_symbols]
    if not held:
        return []
    try:
        M, _ = sympy.linear_eq_to_matrix([expr], [r for _, r in held])
        return [(j, M[0, k]) for k, (j, _) in enumerate(held) if M[0, k] != 0]
    except (NonlinearError, ValueError):
        return [(j, sympy.diff(expr, r)) for j, r in held]


def solve_blocks(unknowns: dict[sympy.Symbol, sympy.Expr], *, knowns: set, what: str,
                 model: str, states: Mapping[str, sympy.Symbol],
                 implicit: Optional[list] = None) -> dict:
    """Solve ``u = expr(u, ...)`` for the unknowns, block by block in causal order.

    Blocks are the strongly connected components of "unknown appears in the
    expression of unknown"; each block must be linear in its own unknowns.

    Parameters
    ----------
    unknowns : dict
        Unknown -> its expression (which may hold unknowns).
    knowns : set
        Symbols that are not parameters (states, inputs, derivatives, time).
    what : str
        What the unknowns are, for messages ("algebraic loop").
    model : str
        Model name, for messages.
    states : mapping
        Storage element name -> state symbol, to name the storage in a singular block.
    implicit : list, optional
        When given, a block nonlinear in its unknowns, or linear but past
        :data:`LOOP_TERM_BUDGET`, is not refused: its unknowns stay unsolved
        (symbols in what follows) and ``(block, residuals, nature)`` is
        appended, with ``residuals[i] = u_i - expr_i = 0`` and ``nature``
        ``"nonlinear"`` or ``"linear"``.

    Raises
    ------
    AlgebraicLoopError
        A block nonlinear in its unknowns.
    SingularLoopError
        A singular block; ``storage`` names the storage elements in it.
    LoopBudgetError
        A linear block past :data:`LOOP_TERM_BUDGET` with no ``implicit`` list.

    Examples
    --------
    >>> import sympy
    >>> z, x, R = sympy.symbols("z x R")
    >>> solve_blocks({z: x - R*z}, knowns={x}, what="loop", model="m", states={})
    {z: x/(R + 1)}
    """
    if not unknowns:
        return {}
    dg = nx.DiGraph()
    dg.add_nodes_from(unknowns)
    for u, ex in unknowns.items():
        for s in ex.free_symbols:
            if s in unknowns:
                dg.add_edge(s, u)
    sol: dict[sympy.Symbol, sympy.Expr] = {}
    cond = nx.condensation(dg)
    for c in nx.topological_sort(cond):
        block = sorted(cond.nodes[c]["members"], key=sympy.default_sort_key)
        eqs = [unknowns[u].xreplace(sol) for u in block]
        if len(block) == 1 and block[0] not in eqs[0].free_symbols:
            sol[block[0]] = eqs[0]
            continue
        M, rhs, nonlinear = _block_matrix(block, eqs, model, what, implicit is not None)
        if nonlinear and implicit is not None:      # kept as residuals u - expr(u) = 0 (an implicit model)
            implicit.append((tuple(block), tuple(u - ex for u, ex in zip(block, eqs)),
                             "nonlinear"))
            continue
        singular = SingularLoopError(
            f"model {model!r}: the {what} in {', '.join(u.name for u in block)} "
            "is singular: the junction structure does not determine these variables (a "
            "node whose potential is defined only up to a constant, such as a circuit "
            "drawn with a 0-junction for every node including ground: remove the ground "
            "node's junction; or storage elements joined so that they cannot be "
            "independent)")
        singular.block = tuple(block)
        singular.storage = tuple(sorted(
            n for n, x in states.items()
            if any(x in (eq.free_symbols if hasattr(eq, "free_symbols") else ())
                   for eq in list(rhs) + list(M))))
        exact = _solve_linear_in_knowns(M, rhs, knowns)
        if exact is TOO_LARGE:
            if implicit is not None:    # kept as linear residuals u - expr(u) = 0
                implicit.append((tuple(block), tuple(u - ex for u, ex in zip(block, eqs)),
                                 "linear"))
                continue
            raise LoopBudgetError(
                f"model {model!r}: the {what} in {', '.join(map(str, block))} is too large to "
                f"solve symbolically (its exact solution passes {LOOP_TERM_BUDGET} polynomial "
                "terms while eliminating); give numeric values to some of its parameters, or "
                "raise bondgraph.equations.loops.LOOP_TERM_BUDGET")
        if exact is not None:
            if exact is SINGULAR:
                raise singular
            sol.update(zip(block, exact))
            continue
        M = M.applyfunc(sympy.cancel)
        det = M[0, 0] if len(block) == 1 else sympy.cancel(M.det(method="bareiss"))
        if det == 0:
            raise singular
        if len(block) == 1:
            sol[block[0]] = rhs[0] / det
        else:
            x = M.LUsolve(rhs)
            for u, val in zip(block, x):
                sol[u] = val
    return sol


def compact_linear(exprs: list, knowns: set) -> list:
    """Each expression linear in the knowns rewritten ``sum_k c_k k + c_0`` with every
    coefficient one reduced fraction of the parameters (nonlinear ones unchanged).

    After loop solutions are substituted, a coefficient is a sum of products of
    fractions; reducing it in sympy's field of rational functions (sparse
    polynomial arithmetic) is far cheaper than ``together``/``cancel`` on the
    expression tree, and keeps what follows (state space, transfer functions)
    small.

    Examples
    --------
    >>> import sympy
    >>> x, a, b = sympy.symbols("x a b")
    >>> compact_linear([x/(a*b) + x/b - 2], {x})
    [-2 + x*(a + 1)/(a*b)]
    """
    from sympy.polys.fields import field

    params: set = set()
    for ex in exprs:
        params |= ex.free_symbols - knowns
    if not params:
        return list(exprs)
    K, *_ = field(sorted(params, key=sympy.default_sort_key), sympy.QQ)
    out = []
    for ex in exprs:
        ks = sorted(ex.free_symbols & knowns, key=sympy.default_sort_key)
        parts = []
        try:
            # one pass over the terms (NonlinearError, a ValueError, when not linear)
            coeffs, const = sympy.linear_eq_to_matrix([ex], ks) if ks else (
                sympy.zeros(1, 0), sympy.Matrix([-ex]))
            for k, c in zip(ks, coeffs):
                if c.free_symbols & knowns:
                    raise ValueError("nonlinear")
                parts.append(to_field(K, c).as_expr() * k)
            const = -const[0]
            parts.append(to_field(K, const).as_expr() if const != 0 else sympy.Integer(0))
        except (ValueError, CoercionFailed, ZeroDivisionError):
            out.append(ex)
            continue
        out.append(sympy.Add(*parts))
    return out
