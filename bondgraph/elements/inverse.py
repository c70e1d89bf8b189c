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
   derivation keeps the law as an implicit equation (solved numerically);
3. every candidate is checked: applied to the law's value at probes of both
   signs it must give the probe back.  ``sympy.solve`` inverts the orifice
   ``sign(e) sqrt|e|`` as ``e = f**2``, which is wrong for negative flows; such a
   candidate is dropped (the law is then kept implicit, or a real branch
   among several is kept when it is the only one that holds).

Examples
--------
>>> import sympy
>>> f, e = sympy.symbols("f e", real=True)
>>> closed_form_inverse(2 * sympy.sinh(f / 0.7304), f, e)
[0.7304*asinh(e/2)]
>>> closed_form_inverse(0.5689 * f + 0.7251 * sympy.tanh(f / 0.7304), f, e) is None
True
>>> closed_form_inverse(sympy.sign(f) * sympy.sqrt(abs(f)), f, e) is None    # not e**2
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
            sols = [c for c in sols if _valid(expr, var, c, new_var)]
            if sols:
                return sols
    if _hopeless(expr, var):
        return None
    sols = list(sympy.solve(sympy.Eq(expr, new_var), var, dict=False))
    if len(sols) > 1:
        # several branches: keep the real ones that invert the law wherever it is real
        sols = [c for c in sols if not c.has(sympy.I)]
    sols = [c for c in sols if _valid(expr, var, c, new_var)]
    return sols or None


#: values of the law's variable at which a candidate inverse is checked, both signs
_PROBES = (-1.7, -0.45, -0.02, 0.03, 0.3, 1.3, 4.1)


def _valid(expr: sympy.Expr, var: sympy.Symbol, candidate: sympy.Expr,
           new_var: sympy.Symbol) -> bool:
    """``candidate(expr(v)) == v`` at every probe ``v`` where the law is real and finite,
    with the other symbols at positive values.  ``sympy.solve`` answers
    ``sign(e) sqrt|e| = f`` with ``e = f**2``, true for ``f >= 0`` only: the probes
    at negative values refuse it."""
    others = sorted((expr.free_symbols | candidate.free_symbols) - {var, new_var},
                    key=lambda x: x.name)
    at = {p: sympy.Float(0.7 + 0.37 * k) for k, p in enumerate(others)}
    law, inv = expr.xreplace(at), candidate.xreplace(at)
    for v in _PROBES:
        try:
            y = complex(law.xreplace({var: sympy.Float(v)}).evalf(30))
        except (TypeError, ValueError, ZeroDivisionError):
            continue
        if not (abs(y.imag) <= 1e-12 * max(1.0, abs(y.real)) and abs(y.real) < 1e12):
            continue
        try:
            back = complex(inv.xreplace({new_var: sympy.Float(y.real)}).evalf(30))
        except (TypeError, ValueError, ZeroDivisionError):
            return False
        if not abs(back - v) <= 1e-9 * max(1.0, abs(v)):       # nan included
            return False
    return True         # every probe that could be evaluated agreed (none: nothing to refute)
