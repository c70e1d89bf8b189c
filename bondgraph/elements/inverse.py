"""Closed-form inverses of scalar constitutive laws, with a bounded cost.

A law met in the causality that needs its inverse (``f = phi^-1(e)`` for a
resistor given as ``e = phi(f)``) is inverted here.  ``sympy.solve`` alone is
not safe: on a law whose variable sits inside ``exp``, ``tanh`` or ``sinh``
with a float coefficient (``2*sinh(f/0.7304)``) it rewrites the function as a
polynomial in ``exp(f/N)`` with ``N`` from the float's digits and does not
return for minutes.  So:

1. the variable occurs once: the law is unwound function by function
   (``sympy.solvers.solveset.invert_real``), in milliseconds, floats or not;
2. otherwise ``sympy.solve``, unless the variable sits inside a transcendental
   function and the law holds a float: that combination has no closed form
   worth minutes (``0.57 f + 0.73 tanh(f/0.73)``) and is refused at once, so the
   derivation keeps the law as an implicit equation (solved numerically).

Examples
--------
>>> import sympy
>>> f, e = sympy.symbols("f e", real=True)
>>> closed_form_inverse(2 * sympy.sinh(f / 0.7304), f, e)
[0.7304*asinh(e/2)]
>>> closed_form_inverse(0.5689 * f + 0.7251 * sympy.tanh(f / 0.7304), f, e) is None
True
"""

from __future__ import annotations

from typing import Optional

import sympy
from sympy.functions.elementary.hyperbolic import HyperbolicFunction
from sympy.functions.elementary.trigonometric import (InverseTrigonometricFunction,
                                                      TrigonometricFunction)

__all__ = ["closed_form_inverse"]

_TRANSCENDENTAL = (sympy.exp, sympy.log, sympy.LambertW, HyperbolicFunction,
                   TrigonometricFunction, InverseTrigonometricFunction,
                   sympy.asinh, sympy.acosh, sympy.atanh, sympy.acoth)


def _unwound(expr: sympy.Expr, var: sympy.Symbol, new_var: sympy.Symbol
             ) -> Optional[list[sympy.Expr]]:
    from sympy.solvers.solveset import invert_real

    try:
        lhs, sols = invert_real(expr, new_var, var)
    except (NotImplementedError, ValueError, TypeError):
        return None
    if lhs != var:
        return None
    if isinstance(sols, sympy.Intersection):        # {x} restricted to the reals
        finite = [a for a in sols.args if isinstance(a, sympy.FiniteSet)]
        rest = [a for a in sols.args if not isinstance(a, sympy.FiniteSet)]
        if len(finite) == 1 and all(a == sympy.S.Reals for a in rest):
            sols = finite[0]
    if isinstance(sols, sympy.FiniteSet):
        return list(sols.args)
    return None


def _hopeless(expr: sympy.Expr, var: sympy.Symbol) -> bool:
    """``var`` inside a transcendental function of a law that holds a float."""
    if not expr.atoms(sympy.Float):
        return False
    return any(var in node.free_symbols for node in expr.atoms(sympy.Function)
               if isinstance(node, _TRANSCENDENTAL))


def closed_form_inverse(expr: sympy.Expr, var: sympy.Symbol, new_var: sympy.Symbol
                        ) -> Optional[list[sympy.Expr]]:
    """The solutions ``var`` of ``new_var = expr(var)``, or None when none is attempted.

    Raises what ``sympy.solve`` raises (``NotImplementedError`` and the like)
    when it is attempted and fails.
    """
    if expr.count(var) == 1:
        sols = _unwound(expr, var, new_var)
        if sols is not None:
            return sols
    if _hopeless(expr, var):
        return None
    return list(sympy.solve(sympy.Eq(expr, new_var), var, dict=False))
