"""The algebra behind :mod:`bondgraph.elements.fields`: matrix checks and partial inversion.

A linear field relates two vectors of port variables by a square matrix,
``y = T w``.  In mixed causality some entries of ``w`` and the complementary
entries of ``y`` are known; :func:`partial_solve` returns the rest (a Schur
complement step).  A nonlinear law is inverted on the unknown ports only by
:func:`solve_law`, which refuses, naming the field and its ports, what sympy
cannot invert uniquely.
"""

from __future__ import annotations

import functools
from typing import Mapping, Sequence

import math

import numpy as np
import sympy

from ...errors import LawError
from ...signals import Signal, t as T_SYM
from ..._support.sympify import as_matrix, to_expr

__all__ = ["FIELD_TERM_BUDGET", "FieldError", "FieldSizeError", "determinant_terms", "field_matrix",
           "partial_solve", "solve_law", "inverse"]


class FieldError(LawError):
    """A multiport field is ill-defined or cannot take its causality.

    The message names the field (``IF:M``, ``CF:K``, ...) and, where it
    matters, its ports.
    """

    __module__ = "bondgraph"      # tracebacks name it where users import it: bondgraph.FieldError


def no_signals(expr: sympy.Expr, owner: str, what: str) -> None:
    dyn = sorted(str(s) for s in expr.free_symbols if isinstance(s, Signal) or s == T_SYM)
    if dyn:
        raise FieldError(f"{owner}: the {what} uses {', '.join(dyn)}; a field's matrix or "
                         "energy must be constant (modulated fields are not supported)")


def field_matrix(value: object, *, owner: str, what: str, ports: int | None = None,
                 definite: bool = True) -> sympy.ImmutableMatrix:
    """A square, symmetric matrix of parameters, checked positive definite when numeric.

    Parameters
    ----------
    value : sympy Matrix, nested list or numpy array
    owner : str
        The field's label, for messages.
    what : str
        The matrix's name (``'mass matrix'``).
    ports : int, optional
        The expected size.
    definite : bool
        Check positive definiteness when every entry is a number (``False``
        for a resistance matrix, checked positive semi-definite instead).

    Examples
    --------
    >>> field_matrix([[2, 1], [1, 2]], owner="IF:M", what="mass matrix")
    Matrix([
    [2, 1],
    [1, 2]])
    >>> field_matrix([[1, 2], [2, 1]], owner="IF:M", what="mass matrix")
    Traceback (most recent call last):
    ...
    bondgraph.FieldError: IF:M: the mass matrix is not positive definite (smallest eigenvalue -1); ...
    """
    M = as_matrix(value, what=f"{owner}: {what}", error=FieldError)
    if M.rows != M.cols or M.rows == 0:
        raise FieldError(f"{owner}: the {what} is {M.rows}x{M.cols}; expected a square matrix "
                         "with one row and one column per port")
    if ports is not None and M.rows != ports:
        raise FieldError(f"{owner}: the {what} is {M.rows}x{M.cols}; expected {ports}x{ports} "
                         f"(one row and column per port)")
    M = sympy.ImmutableMatrix(M.rows, M.cols, [to_expr(v, owner=owner, what=f"{what} entry")
                                               for v in M])
    no_signals(sympy.Add(*M), owner, what)
    for i in range(M.rows):
        for j in range(i):
            if sympy.simplify(M[i, j] - M[j, i]) != 0:
                raise FieldError(f"{owner}: the {what} is not symmetric: entry [{i + 1},{j + 1}] "
                                 f"is {M[i, j]} but [{j + 1},{i + 1}] is {M[j, i]}")
    if not M.free_symbols:
        check_definite(np.array(M.tolist(), dtype=float), owner=owner, what=what,
                       definite=definite)
    return M


def check_definite(values: np.ndarray, *, owner: str, what: str, definite: bool = True) -> None:
    """Refuse a numeric symmetric matrix that is not positive (semi-)definite.

    ``values`` is one ``(n, n)`` matrix or a ``(P, n, n)`` stack (one per
    parameter set of a batch); the error names the first failing set.
    """
    stack = np.asarray(values, dtype=float)
    lam = np.linalg.eigvalsh((stack + np.swapaxes(stack, -1, -2)) / 2)[..., 0]
    scale = np.maximum(1.0, np.abs(stack).max(axis=(-2, -1)))
    bad = np.atleast_1d(lam <= 1e-12 * scale if definite else lam < -1e-12 * scale)
    if bad.any():
        first = int(np.flatnonzero(bad)[0])
        low = float(np.atleast_1d(lam)[first])
        where = f"parameter set {first}: " if stack.ndim == 3 else ""
        raise FieldError(f"{owner}: {where}the {what} is not positive "
                         f"{'' if definite else 'semi-'}definite (smallest eigenvalue {low:.6g}); "
                         f"a passive field needs {'positive' if definite else 'non-negative'} "
                         "eigenvalues")


#: the largest determinant (in terms, as bounded by :func:`determinant_terms`) a symbolic
#: field matrix may have: a dense 6x6 matrix of symbols (720 terms) inverts in seconds,
#: a dense 8x8 one (40,320) did not in minutes
FIELD_TERM_BUDGET = 1000


class FieldSizeError(FieldError):
    """A symbolic field matrix too large to invert (past :data:`FIELD_TERM_BUDGET`)."""


def determinant_terms(M: sympy.MatrixBase) -> float:
    """An upper bound on the number of terms of ``det(M)`` expanded.

    Bregman's bound on the permanent of the pattern of non-constant entries
    (``prod (r_i!)^(1/r_i)``, exact for a dense matrix: ``n!``), times each
    row's largest number of terms.

    Examples
    --------
    >>> a, b, c, d = sympy.symbols("a b c d")
    >>> determinant_terms(sympy.Matrix([[a, b], [c, d]]))
    2.0
    >>> determinant_terms(sympy.Matrix([[a + b, 1], [0, d]]))
    2.0
    """
    bound = 1.0
    for i in range(M.rows):
        row = [M[i, j] for j in range(M.cols) if M[i, j].free_symbols]
        if not row:
            continue
        r = len(row)
        bound *= math.factorial(r) ** (1.0 / r) * max(len(sympy.Add.make_args(e)) for e in row)
    return round(bound, 6)


@functools.lru_cache(maxsize=64)
def inverse(M: sympy.ImmutableMatrix) -> sympy.ImmutableMatrix:
    """``M^-1``: numeric LU, or for symbols elimination over their fraction field (cached:
    derivation asks for each port of a field).

    Raises
    ------
    ValueError
        ``M`` is singular (sympy's ``NonInvertibleMatrixError``).
    """
    if M.rows == 0:
        return sympy.ImmutableMatrix(M)
    if not M.free_symbols:
        return sympy.ImmutableMatrix(M.inv())
    if M.is_diagonal():
        return sympy.ImmutableMatrix.diag(*[1 / M[i, i] for i in range(M.rows)])
    terms = determinant_terms(M)
    if terms > FIELD_TERM_BUDGET:
        raise FieldSizeError(
            f"its symbolic inverse is too large: the determinant of this {M.rows}x{M.rows} "
            f"matrix of symbols has up to {terms:,.0f} terms (budget {FIELD_TERM_BUDGET:,}, "
            "bondgraph.elements.fields.algebra.FIELD_TERM_BUDGET); give numbers for some "
            "entries, or split the field into smaller ones")
    try:       # fraction-field elimination: fast, one reduced fraction per entry
        return sympy.ImmutableMatrix(M.inv(method="DM"))
    except (NotImplementedError, sympy.polys.polyerrors.PolynomialError):
        det = sympy.factor(M.det())
        return sympy.ImmutableMatrix(M.adjugate().applyfunc(lambda v: sympy.factor(v) / det))


def partial_solve(T: sympy.MatrixBase, w_known: Mapping[int, sympy.Expr],
                  y_known: Mapping[int, sympy.Expr], *, owner: str = "a field",
                  what: str = "matrix") -> tuple[list, list]:
    """Both vectors of ``y = T w`` from ``w`` on some indices and ``y`` on the others.

    With ``S`` the indices of known ``w`` and ``U`` the rest:
    ``w_U = T_UU^-1 (y_U - T_US w_S)`` and ``y_S = T_SS w_S + T_SU w_U``.

    Examples
    --------
    >>> m1, m2, m12, p1, f2 = sympy.symbols("m1 m2 m12 p1 f2")
    >>> M = sympy.Matrix([[m1, m12], [m12, m2]])
    >>> w, y = partial_solve(M, {1: f2}, {0: p1})   # p = M f, known p1 and f2
    >>> w[0], y[1]
    ((-f2*m12 + p1)/m1, f2*m2 + m12*(-f2*m12 + p1)/m1)
    """
    n = T.rows
    S, U = sorted(w_known), [i for i in range(n) if i not in w_known]
    w: list = [None] * n
    y: list = [None] * n
    for i in S:
        w[i] = w_known[i]
    if U:
        wS = sympy.Matrix([w_known[i] for i in S]) if S else sympy.zeros(0, 1)
        yU = sympy.Matrix([y_known[i] for i in U])
        rhs = yU - (T.extract(U, S) * wS if S else sympy.zeros(len(U), 1))
        block = sympy.ImmutableMatrix(T.extract(U, U))
        try:
            wU = inverse(block) * rhs
        except FieldSizeError as exc:
            raise FieldSizeError(f"{owner}: the {what}: {exc}") from None
        except ValueError as exc:       # sympy's NonInvertibleMatrixError: singular for all values
            rows = ", ".join(str(i + 1) for i in U)
            raise FieldError(
                f"{owner}: the {what} is singular for every parameter value (its block on ports "
                f"{rows}, {block.tolist()}, has no inverse), so this causality cannot be solved; a "
                f"passive field needs a positive definite {what}") from exc
        for k, i in enumerate(U):
            w[i], y[i] = wU[k], y_known[i]
    full = sympy.Matrix(w)
    for i in S:
        y[i] = (T.row(i) * full)[0]
    return w, y


def solve_law(equations: Sequence[sympy.Expr], unknowns: Sequence[sympy.Symbol], *,
              owner: str, ports: Sequence[int], what: str) -> dict:
    """The unique solution of ``equations = 0`` for ``unknowns``, or a :class:`FieldError`.

    ``ports`` (1-based) and ``what`` name what the causality asks, for the message.
    """
    where = f"port{'s' if len(ports) > 1 else ''} {', '.join(str(p) for p in ports)}"
    try:
        sols = sympy.solve(list(equations), list(unknowns), dict=True)
    except (NotImplementedError, ValueError, TypeError) as exc:
        raise FieldError(f"{owner}: the causality puts {where} in {what}, which needs the "
                         f"law solved for {', '.join(map(str, unknowns))}; sympy cannot "
                         f"({str(exc).strip()[:80]}); give those ports integral causality, or "
                         "a linear (matrix) law") from exc
    sols = [s for s in sols if all(u in s for u in unknowns)]
    if len(sols) != 1:
        raise FieldError(f"{owner}: the causality puts {where} in {what}, which needs the law "
                         f"solved for {', '.join(map(str, unknowns))}; it has {len(sols)} "
                         "solutions (the law is not invertible there); give those ports "
                         "integral causality, or a linear (matrix) law")
    return sols[0]
