"""Exact evaluation of symbolic transfer-function coefficients at parameter values.

Values are matched to the parameters by the package-wide policy
(:func:`bondgraph.parameters.match_values`) and read as exact rationals
(floats as the decimals they print as); each coefficient of a sympy ``Poly``
is then evaluated in rational arithmetic and only the result is rounded to a
float, so a coefficient that vanishes at these values is exactly ``0.0``.

Examples
--------
>>> import sympy as sp
>>> a, b, s = sp.symbols("a b s")
>>> P = sp.Poly(a*s**2 + (a - b)*s, s)
>>> gens = _domain_gens(P)
>>> _poly_values(P, gens, _value_map(gens, {"a": 0.1, "b": 0.1}))
[0.1, 0.0, 0.0]
"""

from __future__ import annotations

from fractions import Fraction
from typing import Mapping, Sequence

import sympy as sp

from ..parameters import exact_value, match_values
from .errors import MissingValueError

__all__: list[str] = []


def _to_fraction(v, key) -> Fraction:
    """Exact rational value of a parameter (floats read as their decimal repr)."""
    e = exact_value(v, str(key))
    if e.is_Rational:
        return Fraction(int(e.p), int(e.q))
    return Fraction(str(sp.N(e, 40)))


def _eval_coeff(c, dom, values: list[Fraction]) -> Fraction:
    """Exact value of one Poly coefficient (domain element) at ``values``."""
    if dom.is_ZZ or dom.is_QQ:
        return Fraction(int(dom.numer(c)), int(dom.denom(c)))
    if dom.is_PolynomialRing:
        return _eval_ring_element(c, values)
    num = _eval_ring_element(c.numer, values)
    den = _eval_ring_element(c.denom, values)
    if den == 0:
        raise MissingValueError(
            f"values: a coefficient's denominator {c.denom.as_expr()} vanishes at the "
            f"given values; use normalize='as-derived'")
    return num / den


def _eval_ring_element(p, values: list[Fraction]) -> Fraction:
    dom = p.ring.domain
    total = Fraction(0)
    powers: dict[tuple[int, int], Fraction] = {}
    for exps, c in p.items():
        term = Fraction(int(dom.numer(c)), int(dom.denom(c)))
        for i, e in enumerate(exps):
            if e:
                key = (i, e)
                if key not in powers:
                    powers[key] = values[i] ** e
                term *= powers[key]
        total += term
    return total


def _poly_values(P: sp.Poly, gens: tuple[sp.Expr, ...], values: Mapping) -> list[float]:
    dom = P.domain
    if dom.is_ZZ or dom.is_QQ:
        vals = []
    else:
        dgens = dom.symbols if hasattr(dom, "symbols") else dom.gens
        vals = [values[g] for g in dgens]
    exact = [_eval_coeff(c, dom, vals) for c in P.rep.to_list()]
    try:
        return [float(c) for c in exact] or [0.0]
    except OverflowError:
        from ..errors import ParameterValueError
        given = ", ".join(f"{g} = {float(values[g]):.3g}" for g in gens if g in values)
        raise ParameterValueError(
            f"a coefficient of the transfer function is beyond the range of a float at {given} "
            "(a parameter near 1e-308 or 1e308?): rescale the units of the parameters") from None


def _domain_gens(P: sp.Poly) -> tuple[sp.Expr, ...]:
    dom = P.domain
    if dom.is_ZZ or dom.is_QQ:
        return ()
    return tuple(dom.symbols if hasattr(dom, "symbols") else dom.gens)


def _used_symbols(P: sp.Poly) -> set:
    """The domain generators' symbols that the coefficients of ``P`` hold, read from the
    domain elements' monomials (``P.as_expr()`` on a 10^4-term polynomial takes seconds)."""
    dom = P.domain
    if dom.is_ZZ or dom.is_QQ:
        return set()
    gens = list(dom.symbols if hasattr(dom, "symbols") else dom.gens)
    hit = [False] * len(gens)
    try:
        for c in P.rep.coeffs():
            parts = (c.numer, c.denom) if hasattr(c, "numer") else (c,)
            for part in parts:
                for m in part.monoms():
                    for i, k in enumerate(m):
                        hit[i] = hit[i] or k != 0
    except AttributeError:            # a domain of another kind: ask the expression
        return P.as_expr().free_symbols
    return set().union(*(g.free_symbols for g, h in zip(gens, hit) if h)) if any(hit) else set()


def _value_map(gens: Sequence[sp.Expr], values: Mapping | None,
               known: Sequence[str] = (), used: set | None = None) -> dict:
    """Exact value of each domain generator, by the package's parameter policy.

    ``used``: the symbols the polynomials hold.  A generator left in the domain
    after cancellation (``Poly(1, s, domain='ZZ[J2]')``) holds none of them: it
    needs no value (one given is accepted, as for any parameter the model knows)
    and gets 1.
    """
    idle = [g for g in gens if used is not None and not (g.free_symbols & used)]
    gens = [g for g in gens if g not in idle]
    params = sorted(set().union(*(g.free_symbols for g in gens)) if gens else set(),
                    key=lambda x: x.name)
    idle_names = tuple(sorted({x.name for g in idle for x in g.free_symbols}))
    given = match_values(params, values, known=tuple(known) + idle_names)
    exact = {p: exact_value(v, p.name) for p, v in given.items() if p in set(params)}
    out = {g: _to_fraction(g.xreplace(exact), g) for g in gens}
    out.update({g: Fraction(1) for g in idle})
    return out
