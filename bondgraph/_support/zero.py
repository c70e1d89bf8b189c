"""Exact zero recognition: coefficients decided over the field of rational functions.

A coefficient assembled from loop solutions can be identically zero without
looking like it: ``-90*R/(64*R + 180) + 45*R/(32*R + 90)`` is 0 for every
``R``, but ``expr != 0`` compares printed structure and says it is not.
Deciding zero by structure made a well-posed linear graph look nonlinear (a
term in an unknown times that coefficient), and only in one insertion order.
Here an expression is brought into sympy's field of rational functions over
its generators (:func:`sympy.polys.fields.sfield`, sparse polynomial
arithmetic, the same exact arithmetic :mod:`bondgraph.loops` uses), where zero
is zero.  Generators that are not symbols (``sqrt(R)``, ``sin(q)``) are kept as
independent generators: an expression found zero is zero; one that is zero
only through an identity between generators is not recognised (it stays as it
was, never wrongly dropped).

Examples
--------
>>> import sympy
>>> R, x = sympy.symbols("R x", positive=True)
>>> c = -90*R/(64*R + 180) + 45*R/(32*R + 90)
>>> c == 0, is_zero(c)
(False, True)
>>> reduced(c * x + 2 * x)
2*x
"""

from __future__ import annotations

import sympy

__all__ = ["is_zero", "reduced"]


def _field_element(expr: sympy.Expr):
    from sympy.polys.fields import sfield

    return sfield(expr)[1]


def is_zero(expr) -> bool:
    """Whether ``expr`` is identically zero as a rational function (False when undecided)."""
    expr = sympy.sympify(expr, strict=True) if not isinstance(expr, sympy.Basic) else expr
    if expr == 0:
        return True
    if expr.is_number:
        return bool(expr.is_zero)
    try:
        return bool(_field_element(expr) == 0)
    except (sympy.PolynomialError, sympy.polys.polyerrors.CoercionFailed,
            sympy.polys.polyerrors.GeneratorsError, ZeroDivisionError, TypeError,
            ValueError, NotImplementedError):
        return False


def reduced(expr: sympy.Expr) -> sympy.Expr:
    """``expr`` as one reduced fraction over its generators (unchanged when that fails), so
    that symbols whose coefficients vanish identically disappear."""
    if not isinstance(expr, sympy.Basic) or expr.is_number or expr == 0:
        return expr
    try:
        return _field_element(expr).as_expr()
    except (sympy.PolynomialError, sympy.polys.polyerrors.CoercionFailed,
            sympy.polys.polyerrors.GeneratorsError, ZeroDivisionError, TypeError,
            ValueError, NotImplementedError):
        return expr
