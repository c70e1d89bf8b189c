"""Exact ring polynomials to sympy ``Poly`` objects, normalized.

The determinants leave the ring as *s-dicts* (``{s_exponent:
{parameter_exponents: coefficient}}``, see :mod:`bondgraph.tf._cancel`).
:class:`_Converter` builds sympy ``Poly`` objects in ``s`` from them, with
coefficients in ``ZZ[p]``/``QQ[p]`` or, for a normalization that divides by a
polynomial pivot, the fraction field ``ZZ(p)``; :func:`_normalize` scales
numerator and denominator by one common factor (``'monic'``,
``'as-derived'``, ``'leading-one-denominator'``).

Examples
--------
>>> import sympy as sp
>>> from bondgraph.tf import _algebra as alg
>>> a, s = sp.symbols("a s")
>>> ring, params, (den,) = alg.polys_from_exprs([2*a*s + 4], s)
>>> P, _ = _normalize(_Converter(ring, params), alg.to_sdict(den, ring, 1), [], "monic", s)
>>> P.as_expr()
s + 2/a
"""

from __future__ import annotations

from fractions import Fraction
from typing import Iterable, Sequence

import sympy as sp
from sympy.polys.fields import FracField
from sympy.polys.polyclasses import DMP
from sympy.polys.rings import PolyRing

from . import _algebra as alg

__all__: list[str] = []


class _Converter:
    """Turn normalized ring polynomials (in s and parameters) into sympy Polys."""

    def __init__(self, ring: alg.Ring, params: Sequence[sp.Expr]):
        self.ring = ring
        self.k = len(params)
        self.q = ring.nvars - 1 - self.k
        if self.k:
            self.ZZr = PolyRing(tuple(params), sp.ZZ)
            self.QQr = PolyRing(tuple(params), sp.QQ)
            self.FF = FracField(tuple(params), sp.ZZ)

    def ring_of(self, d: dict[tuple, int | Fraction]):
        """Ring element of one coefficient (a dict of parameter exponents)."""
        pad = (0,) * self.q
        return self.ring.from_terms({(0,) + e + pad: c for e, c in d.items()})

    def dict_of(self, p) -> dict[tuple, int | Fraction]:
        k = self.k
        return {e[1:1 + k]: c for e, c in self.ring.terms(p)}

    # -- building sympy Polys ----------------------------------------------------
    def poly(self, coeffs: dict[int, dict[tuple, Fraction]], s: sp.Symbol) -> sp.Poly:
        """Poly with polynomial coefficients (domain ZZ[...] or QQ[...])."""
        if not coeffs:
            return sp.Poly(0, s, domain=sp.ZZ)
        integer = all(c.denominator == 1 for d in coeffs.values() for c in d.values())
        deg = max(coeffs)
        if self.k:
            R = self.ZZr if integer else self.QQr
            K = R.to_domain()
            G = R.domain
            rep = [R.from_dict({e: G(c.numerator) if integer else G(c.numerator, c.denominator)
                                for e, c in coeffs.get(d, {}).items()})
                   for d in range(deg, -1, -1)]
        else:
            K = sp.ZZ if integer else sp.QQ
            rep = []
            for d in range(deg, -1, -1):
                c = coeffs.get(d, {}).get((), 0)
                rep.append(K(int(c.numerator)) if integer else
                           K(int(c.numerator), int(c.denominator)))
        return sp.Poly.new(DMP.from_list(rep, 0, K), s)

    def frac_poly(self, fracs: dict[int, tuple[dict, dict]], s: sp.Symbol) -> sp.Poly:
        """Poly whose coefficients are reduced fractions ``(num, den)`` of dicts."""
        if not fracs:
            return sp.Poly(0, s, domain=sp.ZZ)
        if all(list(den) == [(0,) * self.k] and den[(0,) * self.k] == 1
               for _, den in fracs.values()):
            return self.poly({d: num for d, (num, _) in fracs.items()}, s)
        deg = max(fracs)
        if not self.k:  # pragma: no cover - constant denominators handled above
            raise AssertionError
        F = self.FF
        K = F.to_domain()
        R = F.ring
        rep = []
        for d in range(deg, -1, -1):
            if d not in fracs:
                rep.append(K.zero)
                continue
            num, den = _integer_pair(*fracs[d])
            rep.append(F.raw_new(R.from_dict({e: sp.ZZ(int(c)) for e, c in num.items()}),
                                 R.from_dict({e: sp.ZZ(int(c)) for e, c in den.items()})))
        return sp.Poly.new(DMP.from_list(rep, 0, K), s)


def _lcm(a: int, b: int) -> int:
    from math import gcd
    return a // gcd(a, b) * b


def _integer_pair(num: dict, den: dict) -> tuple[dict, dict]:
    """Scale ``num/den`` to integer coefficients, coprime contents, den sign +."""
    from math import gcd
    L = 1
    for d in (num, den):
        for c in d.values():
            L = _lcm(L, c.denominator)
    num = {e: c * L for e, c in num.items()}
    den = {e: c * L for e, c in den.items()}
    g = 0
    for d in (num, den):
        for c in d.values():
            g = gcd(g, int(c))
    lead = den[max(den)]
    if lead < 0:
        g = -g
    return ({e: int(c) // g for e, c in num.items()}, {e: int(c) // g for e, c in den.items()})


def _lead_sign(d: dict) -> int:
    return 1 if d[max(d)] > 0 else -1


def _content(dicts: Iterable[dict]) -> Fraction:
    """Positive rational content: gcd of numerators / lcm of denominators."""
    from math import gcd
    g, L = 0, 1
    for d in dicts:
        for c in d.values():
            g = gcd(g, c.numerator)
            L = _lcm(L, c.denominator)
    return Fraction(g, L) if g else Fraction(1)


def _scale(sd: dict, c: Fraction) -> dict:
    return {k: {e: x / c for e, x in v.items()} for k, v in sd.items()}


def _normalize(converter: _Converter, dd: dict, nds: Sequence[dict], normalize: str,
               s: sp.Symbol) -> tuple[sp.Poly, list[sp.Poly]]:
    """Scale the s-dicts ``dd`` (denominator) and ``nds`` (numerators) by one
    common factor as ``normalize`` says; return sympy Polys."""
    ring = converter.ring
    top = max(dd)
    if normalize == "as-derived":
        c = _content(dd.values()) * _lead_sign(dd[top])
        return converter.poly(_scale(dd, c), s), [converter.poly(_scale(nd, c), s)
                                                  for nd in nds]
    pivot = dd[top] if normalize == "monic" else dd[min(dd)]
    if len(pivot) == 1 and not any(next(iter(pivot))):
        c = Fraction(next(iter(pivot.values())))
        return converter.poly(_scale(dd, c), s), [converter.poly(_scale(nd, c), s)
                                                  for nd in nds]
    if len(pivot) == 1:  # a monomial: gcds are monomials, no ring arithmetic needed
        (pe, pc), = pivot.items()

        def reduce(coeffs):
            out = {}
            for k, v in coeffs.items():
                g = tuple(min([pe[i]] + [e[i] for e in v]) for i in range(len(pe)))
                a = {tuple(x - y for x, y in zip(e, g)): c for e, c in v.items()}
                out[k] = (a, {tuple(x - y for x, y in zip(pe, g)): pc})
            return out
    else:
        pivot_ring = converter.ring_of(pivot)

        def reduce(coeffs):
            out = {}
            for k, v in coeffs.items():
                p = converter.ring_of(v)
                g = ring.gcd(p, pivot_ring)
                out[k] = (converter.dict_of(ring.exquo(p, g)),
                          converter.dict_of(ring.exquo(pivot_ring, g)))
            return out

    return (converter.frac_poly(reduce(dd), s),
            [converter.frac_poly(reduce(nd), s) for nd in nds])
