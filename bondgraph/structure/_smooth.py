"""Derivatives of a trajectory as distributions, to tell whether it is smooth enough.

:func:`bondgraph.structure.invert` states that the output must be ``r`` times
differentiable; :func:`derivatives` checks it.  Kinks and jumps are written
with ``Heaviside``, ``Abs``, ``sign``, ``Max``/``Min`` or a ``Piecewise`` of
conditions on ``t`` (each rewritten with ``Heaviside``); sympy differentiates
them into Dirac impulses, and an impulse whose weight vanishes at its point
(``(t - 1) DiracDelta(t - 1)``) is dropped.  An impulse left in a derivative
of order ``k <= r`` means the trajectory is not ``r`` times differentiable
there.

Examples
--------
>>> import sympy
>>> from bondgraph.signals import t
>>> sympy.factor(derivatives((t - 1)**3 * sympy.Heaviside(t - 1), 2)[2])
6*(t - 1)*Heaviside(t - 1)
>>> derivatives(sympy.Abs(t), 2)
Traceback (most recent call last):
...
bondgraph.structure._generic.StructureError: trajectory Abs(t) is not 2 times differentiable: its derivative 2 has a Dirac impulse at t = 0 (a kink or a jump there)
"""

from __future__ import annotations

from typing import Optional

import sympy

from ..signals import t as T
from ._generic import StructureError

__all__ = ["derivatives"]


def _piecewise(expr: sympy.Expr, shown: sympy.Expr) -> sympy.Expr:
    """Every ``Piecewise`` of ``expr`` written with ``Heaviside`` (conditions ``t < a``,
    ``t <= a``, ``t > a``, ``t >= a`` and ``True``)."""
    def convert(pw: sympy.Piecewise) -> sympy.Expr:
        pieces = list(pw.args)
        value, last_cond = pieces[-1]
        if last_cond is not sympy.true:
            raise StructureError(f"trajectory {shown}: its Piecewise has no otherwise branch "
                                 "(a last condition True); it is undefined somewhere")
        for e, cond in reversed(pieces[:-1]):
            if not isinstance(cond, (sympy.StrictLessThan, sympy.LessThan,
                                     sympy.StrictGreaterThan, sympy.GreaterThan)):
                raise StructureError(f"trajectory {shown}: the Piecewise condition {cond} is not "
                                     "a comparison of t with a number; write the trajectory with "
                                     "Heaviside")
            g = sympy.expand(cond.lhs - cond.rhs)
            slope = sympy.diff(g, T)
            if not (slope.is_number and slope != 0 and sympy.diff(g, T, 2) == 0):
                raise StructureError(f"trajectory {shown}: the Piecewise condition {cond} is not "
                                     "linear in t; write the trajectory with Heaviside")
            a = sympy.solve(g, T)[0]
            below = isinstance(cond, (sympy.StrictLessThan, sympy.LessThan)) == (slope > 0)
            step = sympy.Heaviside(T - a)
            value = (e + (value - e) * step) if below else (value + (e - value) * step)
        return value
    return expr.replace(lambda x: isinstance(x, sympy.Piecewise), convert)


def _point(delta: sympy.Expr) -> Optional[tuple]:
    """``(a, scale)`` of ``DiracDelta(g(t), k)`` with ``g`` linear: ``delta = scale *
    DiracDelta(t - a, k)``; None when ``g`` is not linear in t."""
    g = delta.args[0]
    k = int(delta.args[1]) if len(delta.args) > 1 else 0
    c = sympy.diff(g, T)
    if not (c.is_number and c != 0 and sympy.diff(g, T, 2) == 0):
        return None
    a = sympy.solve(g, T)[0]
    return a, k, 1 / (c**k * abs(c))


def _reduce(expr: sympy.Expr) -> sympy.Expr:
    """``c(t) DiracDelta^(k)(t - a)`` written as ``sum_j (-1)^j C(k, j) c^(j)(a)
    DiracDelta^(k-j)(t - a)``, so an impulse of weight zero disappears."""
    out = []
    for term in sympy.Add.make_args(sympy.expand(expr)):
        deltas = [d for d in term.atoms(sympy.DiracDelta) if d.has(T)]
        if len(deltas) != 1:
            out.append(term)
            continue
        (d,) = deltas
        c = sympy.simplify(term / d)
        found = _point(d)
        if c.has(sympy.DiracDelta) or found is None:
            out.append(term)
            continue
        a, k, scale = found
        for j in range(k + 1):
            w = sympy.simplify(((-1)**j * sympy.binomial(k, j) * scale *
                                sympy.diff(c, T, j)).subs(T, a))
            if w != 0:
                out.append(w * sympy.DiracDelta(T - a, k - j) if k - j else
                           w * sympy.DiracDelta(T - a))
    return sympy.Add(*out)


def derivatives(trajectory: sympy.Expr, order: int) -> list:
    """``[y, y', ..., y^(order)]`` of a trajectory, refused when it is not ``order`` times
    differentiable (a Dirac impulse in one of them, a function sympy cannot differentiate,
    nan or an infinity).

    Raises
    ------
    StructureError
        Naming the trajectory, the derivative and the point of the impulse.
    """
    if trajectory.has(sympy.nan, sympy.zoo, sympy.oo, -sympy.oo):
        raise StructureError(f"trajectory {trajectory} is not a finite function of t")
    y = _piecewise(trajectory, trajectory)
    y = y.replace(lambda x: isinstance(x, (sympy.Max, sympy.Min)) and x.has(T),
                  lambda x: x.rewrite(sympy.Heaviside))
    out = [y]
    for k in range(1, order + 1):
        out.append(_reduce(sympy.diff(out[-1], T)))
    for k, d in enumerate(out):
        if d.has(sympy.Derivative):
            raise StructureError(f"trajectory {trajectory} is not differentiable {order} times "
                                 f"in t (sympy cannot differentiate {d} further)")
        impulses = [x for x in d.atoms(sympy.DiracDelta) if x.has(T)]
        if impulses:
            found = _point(impulses[0])
            where = f" at t = {found[0]}" if found else ""
            raise StructureError(f"trajectory {trajectory} is not {order} times differentiable: "
                                 f"its derivative {k} has a Dirac impulse{where} (a kink or a "
                                 "jump there)")
    return out
