"""Displacement and momentum outputs expressed through existing states.

An output such as ``bg.displacement("m")`` is the time integral of a flow.
:func:`bondgraph.derive` first gives it an integrator state ``x' = f``; when
``f`` is a constant linear combination of the other state derivatives,
``f = sum_j c_j x_j'``, that integrator is redundant (it would make the plant
uncontrollable: a pole at 0 that no input moves) and the output is
``sum_j c_j x_j`` instead.  The integration constant is then fixed by the
states: the displacement is measured from the configuration where those
states are zero (for a mass on a spring, from the spring's free length).

The combination is found numerically at random parameter values (a least
squares solve that gives its support).  Constant coefficients (``1``, ``-1``,
the usual case) are then solved exactly at random rational parameter values
and the identity is checked exactly, column by column, at five such points
(Schwartz-Zippel: a nonzero rational function of the parameters vanishes at
such a point with probability below its degree over 10**5).  Coefficients
that depend on the parameters (a transformer modulus) are solved and checked
symbolically over the field of rational functions, for expressions of modest
size; otherwise the integrator stays (``NumericStateSpace.minimal`` removes
it numerically).

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("msd")
>>> v = bg.One("v")
>>> g.add(bg.Se("F"), v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
>>> for t, h in [("F", v), (v, "m"), (v, "b"), (v, "k")]: _ = g.connect(t, h)
>>> model = bg.derive(g, outputs={"x": bg.displacement("m")})
>>> model.state_names, model.output_exprs
(('p_m', 'q_k'), (q_k,))
"""

from __future__ import annotations

from typing import Optional, Sequence

import numpy as np
import sympy
from sympy.polys.matrices.exceptions import DMNonInvertibleMatrixError
from sympy.polys.polyerrors import CoercionFailed
from sympy.solvers.solveset import NonlinearError

from .loops import field_matrix
from ..signals import t as T_SYM

__all__ = ["state_combination"]

def _fmpq(v):
    """A float or a sympy Rational as an exact flint rational."""
    import flint

    if isinstance(v, float):
        return flint.fmpq(*v.as_integer_ratio())
    return flint.fmpq(int(v.p), int(v.q))


#: Above this many storage states the search is skipped (dense least squares).
MAX_STATES = 400


def _linear_row(expr: sympy.Expr, variables: Sequence[sympy.Symbol]) -> Optional[dict]:
    """``{var: coefficient, 1: constant}`` of an expression affine in ``variables``
    (read in one pass over its terms)."""
    vs = set(variables)
    free = expr.free_symbols
    if T_SYM in free:
        return None
    held = sorted(free & vs, key=sympy.default_sort_key)
    try:
        coeffs, const = sympy.linear_eq_to_matrix([expr], held) if held else (
            sympy.zeros(1, 0), sympy.Matrix([-expr]))
    except (NonlinearError, ValueError):
        return None
    row: dict = {}
    for v, c in zip(held, coeffs):
        if c.free_symbols & vs:
            return None
        if c != 0:
            row[v] = c
    if const[0] != 0:
        row[1] = -const[0]
    return row


class _Evaluator:
    """Exact values of rational functions of the parameters at points (python-flint).

    Each coefficient is converted once to a reduced fraction of flint
    polynomials and evaluated exactly at rational points: the cost does not
    grow with the size of its sympy expression tree, and the value does not
    depend on how the expression is written.  Coefficients that are not
    rational functions (a ``sqrt``) are substituted by sympy instead.
    """

    def __init__(self, params: list) -> None:
        self.params = params
        self.F = None
        if params:
            from sympy.polys.fields import field

            from ._flint_fractions import Fractions

            self.F = Fractions(field(params, sympy.QQ)[0])
        self.memo: dict = {}

    def _fraction(self, c: sympy.Expr):
        if c not in self.memo:
            try:
                self.memo[c] = self.F.fraction(c) if self.F is not None else None
            except (CoercionFailed, NotImplementedError, ValueError, ZeroDivisionError,
                    TypeError):
                self.memo[c] = None
        return self.memo[c]

    def exact(self, c, point: dict, qpoint: list):
        """``c`` at ``point`` (sympy Rationals; ``qpoint`` the same as flint fmpq), or a
        non-rational sympy number."""
        if isinstance(c, int) or not c.free_symbols:
            return sympy.sympify(c, strict=True)
        nd = self._fraction(c)
        if nd is None:
            return c.xreplace(point)
        d = nd[1](*qpoint)
        if d == 0:
            return sympy.zoo
        v = nd[0](*qpoint) / d
        return sympy.Rational(int(v.p), int(v.q))

    def number(self, c, values: dict, qvalues: list) -> float:
        """``c`` at float parameter values, evaluated exactly then rounded."""
        if not c.free_symbols:
            return float(c)
        nd = self._fraction(c)
        if nd is None:
            return float(complex(c.xreplace(values)).real)
        d = nd[1](*qvalues)
        if d == 0:
            raise ValueError("a coefficient's denominator vanishes")
        v = nd[0](*qvalues) / d
        return int(v.p) / int(v.q)


def state_combination(flow: sympy.Expr, states: Sequence[sympy.Symbol],
                      rhs: Sequence[sympy.Expr], inputs: Sequence[sympy.Symbol],
                      *, seed: int = 0) -> Optional[sympy.Expr]:
    """``sum_j c_j x_j`` with constant ``c`` such that ``flow == sum_j c_j rhs_j``, or None.

    Parameters
    ----------
    flow : sympy.Expr
        The integrand, an expression of states and inputs.
    states, rhs : sequences
        Storage states and their derivatives ``x_j' = rhs_j``.
    inputs : sequence of sympy.Symbol

    Examples
    --------
    >>> import sympy
    >>> x1, x2, u, k = sympy.symbols("x1 x2 u k")
    >>> state_combination(2*x1 + u, [x1, x2], [k*x1, x1 + u], [u])
    x2 + x1/k
    >>> state_combination(x1, [x1], [u], [u]) is None
    True
    """
    n = len(states)
    if n == 0 or n > MAX_STATES:
        return None
    variables = list(states) + list(inputs)
    target = _linear_row(flow, variables)
    if target is None or not target:
        return None
    rows = []
    for r in rhs:
        row = _linear_row(r, variables)
        if row is None:
            return None
        rows.append(row)
    cols = variables + [1]
    col_index = {c: i for i, c in enumerate(cols)}
    params = set()
    for row in rows + [target]:
        for c in row.values():
            params |= c.free_symbols
    rng = np.random.default_rng(seed)
    plist = sorted(params, key=sympy.default_sort_key)
    ev = _Evaluator(plist)
    floats = [rng.uniform(0.5, 2.0) for _ in plist]
    values = {p: sympy.Float(v) for p, v in zip(plist, floats)}
    qvalues = [_fmpq(v) for v in floats]

    def number(c) -> float:
        return ev.number(c, values, qvalues)

    try:
        M = np.zeros((n, len(cols)))
        for j, row in enumerate(rows):
            for v, c in row.items():
                M[j, col_index[v]] = number(c)
        t = np.zeros(len(cols))
        for v, c in target.items():
            t[col_index[v]] = number(c)
    except (TypeError, ValueError):
        return None
    c, *_ = np.linalg.lstsq(M.T, t, rcond=None)
    residual = float(np.linalg.norm(M.T @ c - t))
    if not np.all(np.isfinite(c)) or residual > 1e-9 * max(1.0, float(np.linalg.norm(t))):
        return None
    scale = float(np.abs(c).max())
    support = [j for j in range(n) if abs(c[j]) > 1e-12 * max(1.0, scale)]
    if not support:
        return None
    # symbolic solve on the support: independent columns chosen numerically
    sub = M[support].T                       # (columns, |support|)
    chosen: list[int] = []
    for i in np.argsort(-np.abs(sub).sum(axis=1), kind="stable"):
        trial = chosen + [int(i)]
        if np.linalg.matrix_rank(sub[trial], tol=1e-10) == len(trial):
            chosen = trial
        if len(chosen) == len(support):
            break
    if len(chosen) < len(support):
        return None
    used = sorted({col_index[v] for j in support for v in rows[j]} |
                  {col_index[v] for v in target})
    pick = [used.index(i) for i in chosen]
    table = [[rows[j].get(cols[i], 0) for i in used] for j in support] + \
        [[target.get(cols[i], 0) for i in used]]
    constant = _constant_combination(table, pick, plist, rng, ev)
    coeffs = constant if constant is not None else _symbolic_combination(table, pick)
    if coeffs is None:
        return None
    return sympy.Add(*(cj * states[j] for cj, j in zip(coeffs, support)))


#: Above this size (characters of the coefficients) no symbolic solve is tried.
MAX_SYMBOLIC_SIZE = 4000


def _exact_points(params: list, rng: np.random.Generator, count: int) -> list[dict]:
    """Random rational parameter values (numerators up to 10**6): exact test points."""
    out = []
    for _ in range(count):
        out.append({p: sympy.Rational(int(rng.integers(10**5, 10**6)), int(rng.integers(10**5, 10**6)))
                    for p in params})
    return out


def _constant_combination(table: list, pick: list[int], params: list,
                          rng: np.random.Generator, ev: _Evaluator) -> Optional[list]:
    """The coefficients when they are the same rational numbers at every parameter value.

    Solved exactly at three random rational points; accepted when they agree and
    the identity holds, column by column, at five points (a rational function
    that vanishes at random points of this height is zero but with probability
    below degree/10**5 per point: Schwartz-Zippel).
    """
    k = len(table) - 1
    found = None
    for n, point in enumerate(_exact_points(params, rng, 5)):
        qpoint = [_fmpq(point[p]) for p in params]
        try:
            num = [[sympy.Integer(c) if isinstance(c, int) else ev.exact(c, point, qpoint)
                    for c in row] for row in table]
        except (ZeroDivisionError, TypeError):
            return None
        if any(not x.is_Rational for row in num for x in row):
            return None
        if n < 3:
            A = sympy.Matrix([[num[j][i] for j in range(k)] for i in pick])
            b = sympy.Matrix([num[k][i] for i in pick])
            if A.det() == 0:
                return None
            c = list(A.LUsolve(b))
            if found is None:
                found = c
            elif c != found:
                return None
        assert found is not None
        if any(sum(found[j] * num[j][i] for j in range(k)) != num[k][i]
               for i in range(len(num[0]))):
            return None
    return found


def _symbolic_combination(table: list, pick: list[int]) -> Optional[list]:
    """Coefficients that depend on the parameters: solved over their rational functions."""
    if sum(len(str(c)) for row in table for c in row) > MAX_SYMBOLIC_SIZE:
        return None
    dm = field_matrix(sympy.Matrix(table))
    if dm is None:
        return None
    k = len(table) - 1
    rows_m, goal = dm[:k, :], dm[k:, :]
    try:
        coeff = rows_m.extract(list(range(k)), pick).transpose().lu_solve(
            goal.extract([0], pick).transpose())
    except DMNonInvertibleMatrixError:
        return None
    if coeff.transpose().matmul(rows_m) != goal:
        return None
    return [coeff.to_Matrix()[i, 0] for i in range(k)]
