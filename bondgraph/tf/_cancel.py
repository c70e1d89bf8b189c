"""Clearing the reciprocal variables and cancelling common factors.

Last stage of the exact algebra (:mod:`bondgraph.tf._algebra`): results leave
the ring as *s-dicts* (``{s_exponent: {parameter_exponents: coefficient}}``),
polynomials in ``s`` and the parameters only, and numerator/denominator pairs
are divided by their exact gcd.

Examples
--------
>>> from bondgraph.tf._rings import make_ring
>>> R = make_ring(2)
>>> s, a = R.gen(0), R.gen(1)
>>> cancel_common(to_sdict(s * a + a, R, 1), to_sdict(s * s - R.one, R, 1), R, 1)
({0: {(1,): 1}}, {1: {(0,): 1}, 0: {(0,): -1}})
"""

from __future__ import annotations

from collections import defaultdict
from fractions import Fraction
from typing import Any, Sequence

import sympy as sp

from ._encode import EncodedSystem
from ._rings import Ring, _SympyRing

__all__ = ["SDict", "to_sdict", "from_sdict", "clear_reciprocals", "cancel_common"]

#: An "s-dict": ``{s_exponent: {parameter_exponents: coefficient}}`` with int or
#: Fraction coefficients: the exchange format between the ring and sympy.
SDict = dict


def to_sdict(p, ring: Ring, k: int) -> SDict:
    """Split a ring element (in ``s`` and ``k`` parameters only) by powers of s."""
    out: SDict = {}
    for exps, c in ring.terms(p):
        d = out.get(exps[0])
        if d is None:
            d = out[exps[0]] = {}
        d[exps[1:1 + k]] = c
    return out


def from_sdict(sd: SDict, ring: Ring) -> Any:
    """Inverse of :func:`to_sdict` (reciprocal variables, if any, set to 0)."""
    k = None
    terms = {}
    for se, d in sd.items():
        for pe, c in d.items():
            if k is None:
                k = len(pe)
                pad = (0,) * (ring.nvars - 1 - k)
            terms[(se,) + pe + pad] = c
    return ring.from_terms(terms)


def clear_reciprocals(polys: Sequence[Any], enc: EncodedSystem) -> list[SDict]:
    """Substitute ``r_j -> 1/f_j`` and multiply all ``polys`` by one common
    ``prod f_j**d_j`` (``d_j`` the largest degree in ``r_j``): the results are
    polynomials in ``s`` and the parameters, returned as s-dicts."""
    ring = enc.ring
    q = len(enc.recip_symbols)
    k = len(enc.params)
    if q == 0:
        return [to_sdict(p, ring, k) for p in polys]
    k0 = ring.nvars - q
    dmax = [0] * q
    for p in polys:
        if ring.is_zero(p):
            continue
        degs = ring.degrees(p)
        for j in range(q):
            dmax[j] = max(dmax[j], degs[k0 + j])
    # fast path: every base is a single parameter (1/m, 1/L, ...): shift exponents
    single: list[int | None] = []
    for fp in enc.recip_polys:
        tl = list(ring.terms(fp))
        if len(tl) == 1 and tl[0][1] == 1 and sum(tl[0][0]) == 1:
            single.append(tl[0][0].index(1) - 1)
        else:
            single.append(None)
    positions = [x for x in single if x is not None]
    if len(positions) == len(single):
        shifts = list(zip(positions, dmax, range(k0, k0 + q)))
        out = []
        for p in polys:
            sd: SDict = {}
            for exps, c in ring.terms(p):
                e = list(exps[1:k0])
                for pos, dm, col in shifts:
                    e[pos] += dm - exps[col]
                d = sd.get(exps[0])
                if d is None:
                    d = sd[exps[0]] = {}
                # distinct ring monomials can collapse onto one monomial once the
                # reciprocals are cleared (1/(R1*C1) + 1/(R2*C1)): add, never overwrite
                key = tuple(e)
                total = d.get(key, 0) + c
                if total:
                    d[key] = total
                else:
                    d.pop(key, None)
            for key in [k for k, d in sd.items() if not d]:
                del sd[key]
            out.append(sd)
        return out
    pow_cache: dict[tuple[int, int], Any] = {}

    def fpow(j, e):
        if (j, e) not in pow_cache:
            pow_cache[(j, e)] = ring.one if e == 0 else fpow(j, e - 1) * enc.recip_polys[j]
        return pow_cache[(j, e)]

    out = []
    for p in polys:
        groups: dict[tuple[int, ...], dict] = defaultdict(dict)
        for exps, c in ring.terms(p):
            groups[exps[k0:]][exps[:k0] + (0,) * q] = c
        total = ring.zero
        for key, terms in groups.items():
            part = ring.from_terms(terms)
            for j, ej in enumerate(key):
                if dmax[j] - ej:
                    part = part * fpow(j, dmax[j] - ej)
            total = total + part
        out.append(to_sdict(total, ring, k))
    return out


def _eval_coeff(d: dict, point: Sequence[int]) -> Fraction:
    total = Fraction(0)
    for e, c in d.items():
        term = Fraction(c)
        for x, p in zip(point, e):
            if p:
                term *= x ** p
        total += term
    return total


def _coprime_in_s(num: SDict, den: SDict, k: int) -> bool | None:
    """True when ``num`` and ``den`` provably share no factor involving ``s``.

    Specializes the parameters at an integer point where both leading
    coefficients (in ``s``) are nonzero: a common factor of s-degree ``d``
    then stays a common factor of degree ``d`` of the specializations.
    Returns ``None`` when no such point was found (undecided).
    """
    import random

    rng = random.Random(12345)
    tn, td = max(num), max(den)
    if tn == 0 or td == 0:
        return True
    for _ in range(5):
        point = [rng.randint(2, 10**6) for _ in range(k)]
        if _eval_coeff(num[tn], point) == 0 or _eval_coeff(den[td], point) == 0:
            continue
        un = [_eval_coeff(num.get(i, {}), point) for i in range(tn, -1, -1)]
        ud = [_eval_coeff(den.get(i, {}), point) for i in range(td, -1, -1)]
        x = sp.Dummy("x")
        Pn = sp.Poly([sp.Rational(c.numerator, c.denominator) for c in un], x, domain=sp.QQ)
        Pd = sp.Poly([sp.Rational(c.numerator, c.denominator) for c in ud], x, domain=sp.QQ)
        return Pn.gcd(Pd).degree() == 0
    return None


def _dict_gcd(a: dict, b: dict, ring: Ring, k: int) -> dict:
    """gcd (up to a constant) of two coefficient dicts in the parameters."""
    for x, y in ((a, b), (b, a)):
        if len(x) == 1:
            (e0, _), = x.items()
            g = tuple(min([e0[i]] + [e[i] for e in y]) for i in range(k))
            return {g: 1}
    pad = (0,) * (ring.nvars - 1 - k)
    pa = ring.from_terms({(0,) + e + pad: c for e, c in a.items()})
    pb = ring.from_terms({(0,) + e + pad: c for e, c in b.items()})
    return {e[1:1 + k]: c for e, c in ring.terms(ring.gcd(pa, pb))}


def _cancel_by_specialization(num: SDict, den: SDict, ring: Ring, k: int):
    """Cheap cancellation when num and den are coprime in ``s`` (else ``None``)."""
    if not _coprime_in_s(num, den, k):
        return None
    g: dict | None = None
    for d in sorted(list(num.values()) + list(den.values()), key=len):
        g = d if g is None else _dict_gcd(g, d, ring, k)
        if all(not any(e) for e in g):
            return num, den            # only a constant in common
    if g is None:                      # pragma: no cover - num is never empty here
        return None
    if len(g) == 1:                    # a monomial: shift exponents
        (ge, _), = g.items()

        def div(sd):
            return {s_: {tuple(x - y for x, y in zip(e, ge)): c for e, c in d.items()}
                    for s_, d in sd.items()}
        return div(num), div(den)
    return None


def cancel_common(num: SDict, den: SDict, ring: Ring, k: int) -> tuple[SDict, SDict]:
    """Divide s-dicts ``num`` and ``den`` by their gcd; ``0/den`` becomes ``0/1``.

    With the pure-sympy arithmetic (slow multivariate gcd) a specialization
    test first proves the common case, no common factor involving ``s``.
    """
    if not num:
        return {}, {0: {(0,) * k: 1}}
    if isinstance(ring, _SympyRing) and k:
        done = _cancel_by_specialization(num, den, ring, k)
        if done is not None:
            return done
    pn, pd = from_sdict(num, ring), from_sdict(den, ring)
    g = ring.gcd(pn, pd)
    if ring.is_zero(g) or all(not any(e) for e, _ in ring.terms(g)):
        return num, den  # gcd is a constant
    return (to_sdict(ring.exquo(pn, g), ring, k), to_sdict(ring.exquo(pd, g), ring, k))
