"""Clearing, cancelling and normalizing :class:`~bondgraph.tf._packed.Terms`.

The array counterparts of :func:`bondgraph.tf._cancel.clear_reciprocals`,
:func:`bondgraph.tf._cancel.cancel_common` and
:func:`bondgraph.tf._convert._normalize` for the fast path
(:mod:`bondgraph.tf._packed`).  Each handles the common case on the arrays
(reciprocals of single parameters; a transfer function whose numerator and
denominator share no factor in ``s``, proven modulo a prime at a random
point, and some coefficient a single term; a constant or monomial pivot) and
hands anything else to the general functions through s-dicts, so the
results are always the general path's.

Examples
--------
>>> import sympy as sp
>>> from bondgraph.tf._encode import encode_system
>>> from bondgraph.tf._packed import packed_determinants
>>> m, k, s = sp.symbols("m k s", positive=True)
>>> enc = encode_system(sp.Matrix([[0, 1/m], [-k, 0]]), sp.Matrix([[0], [1]]),
...                     sp.Matrix([[1, 0]]), sp.Matrix([[0]]), None, s)
>>> d0, nums = packed_determinants(enc, [(0, 0)])
>>> den, num = clear_terms([d0] + nums, enc)
>>> n, d = cancel_terms(num, den, enc.ring, 2)
>>> n.exps.tolist(), sorted(d.exps.tolist())         # 1/(m s**2 + k): params (k, m)
([[0, 0, 0]], [[0, 1, 0], [2, 0, 1]])
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Sequence

import numpy as np
import sympy as sp
from sympy.polys.polyclasses import DMP

from ._cancel import cancel_common
from ._convert import _Converter, _normalize
from ._encode import EncodedSystem
from ._packed import Terms

__all__ = ["clear_terms", "cancel_terms", "normalize_terms"]

def clear_terms(polys: Sequence[Terms], enc: EncodedSystem) -> list[Terms]:
    """Reciprocals ``r_j = 1/m_j`` (single parameters) cleared by one common
    ``prod m_j**d_j`` (``d_j`` the largest degree of ``r_j``); columns of the
    reciprocals dropped.  Same polynomials as
    :func:`bondgraph.tf._cancel.clear_reciprocals`."""
    k = len(enc.params)
    q = len(enc.recip_symbols)
    ncols = 1 + k
    if q == 0:
        return [Terms(p.exps[:, :ncols], p.coeffs, p.spec) for p in polys]
    ring = enc.ring
    pos = [ring.terms(fp)[0][0].index(1) for fp in enc.recip_polys]   # column of m_j
    dmax = [max((int(p.exps[:, ncols + j].max()) for p in polys if len(p)), default=0)
            for j in range(q)]
    out = []
    for p in polys:
        e = p.exps
        new = e[:, :ncols].copy()
        collide = False
        for j, col in enumerate(pos):
            r = e[:, ncols + j]
            new[:, col] += dmax[j] - r
            collide = collide or bool(np.any((e[:, col] > 0) & (r > 0)))
        coeffs = p.coeffs
        if collide:   # two terms may land on one monomial: add them (never overwrite)
            new, coeffs = _merge(new, coeffs)
        out.append(Terms(new, coeffs, p.spec))
    return out


def _merge(exps: np.ndarray, coeffs: list) -> tuple[np.ndarray, list]:
    """Sum the coefficients of equal rows; drop zero sums.  Rows stay in the order of
    their first occurrence (as a dict of the rows would keep them); vectorised: the
    rows grouped by ``numpy.unique``, the (exact, Python) coefficients added per group
    by ``numpy.add.reduceat`` on an object array."""
    if not len(coeffs):
        return np.zeros((0, exps.shape[1]), dtype=exps.dtype), []
    rows = np.ascontiguousarray(exps)
    keys = rows.view(np.dtype((np.void, rows.dtype.itemsize * rows.shape[1]))).ravel()
    _, first, inv = np.unique(keys, return_index=True, return_inverse=True)
    inv = inv.ravel()
    order = np.argsort(inv, kind="stable")
    starts = np.flatnonzero(np.r_[True, np.diff(inv[order]) != 0])
    vals = np.empty(len(coeffs), dtype=object)
    vals[:] = coeffs
    sums = np.add.reduceat(vals[order], starts)
    groups = np.argsort(first, kind="stable")          # first-occurrence order
    keep = [g for g in groups.tolist() if sums[g]]
    if not keep:
        return np.zeros((0, exps.shape[1]), dtype=exps.dtype), []
    return rows[first[keep]], [sums[g] for g in keep]


def _coprime_in_s(num: Terms, den: Terms) -> bool:
    """True when ``num`` and ``den`` provably share no factor involving ``s``.

    Their values at a random point of the parameters (``Terms.spec``, exact
    over the rationals) keep the degree in ``s`` when the leading
    coefficients do not vanish there, and then a common factor of s-degree
    ``d`` stays a common factor of degree ``d``: a constant gcd proves it.
    """
    if num.spec is None or den.spec is None:
        return False
    if num.spec.degree() != int(num.exps[:, 0].max()) or \
            den.spec.degree() != int(den.exps[:, 0].max()):
        return False       # a leading coefficient vanishes at the point: undecided
    return num.spec.gcd(den.spec).degree() == 0


def cancel_terms(num: Terms, den: Terms, ring, k: int) -> tuple[Terms, Terms] | tuple[dict, dict]:
    """Divide ``num`` and ``den`` by their gcd (up to a constant).

    Fast when they are coprime in ``s`` and some coefficient (in ``s``) of
    either is a single term: the gcd is then the monomial of the smallest
    exponents.  Otherwise the general :func:`~bondgraph.tf._cancel.cancel_common`
    on s-dicts (``ring`` is then required) and s-dicts are returned.
    """
    if not len(num):
        return cancel_common({}, {}, ring, k)
    if k and _coprime_in_s(num, den) and (_has_monomial_coeff(num)
                                          or _has_monomial_coeff(den)):
        g = np.minimum(num.exps[:, 1:].min(axis=0), den.exps[:, 1:].min(axis=0))
        if not g.any():
            return num, den
        shift = np.concatenate([[0], g])
        return (Terms(num.exps - shift, num.coeffs, num.spec),
                Terms(den.exps - shift, den.coeffs, den.spec))
    if not k and _coprime_in_s(num, den):
        return num, den
    return cancel_common(num.to_sdict(k), den.to_sdict(k), ring, k)


def _has_monomial_coeff(p: Terms) -> bool:
    counts = np.bincount(p.exps[:, 0])
    return bool(np.any(counts == 1))


# ----------------------------------------------------------------- normalization
def normalize_terms(conv: _Converter, dd, nds: Sequence, normalize: str,
                    s: sp.Symbol) -> tuple[sp.Poly, list[sp.Poly]]:
    """:func:`bondgraph.tf._convert._normalize` for :class:`Terms` (s-dicts pass through)."""
    if not isinstance(dd, Terms) or not all(isinstance(x, Terms) for x in nds):
        dd = dd.to_sdict(conv.k) if isinstance(dd, Terms) else dd
        nds = [x.to_sdict(conv.k) if isinstance(x, Terms) else x for x in nds]
        return _normalize(conv, dd, nds, normalize, s)
    k = conv.k
    e0 = dd.exps[:, 0]
    top = int(e0.max())
    if normalize == "as-derived":
        c = _content(dd.coeffs) * _lead_sign(dd, top)
        return _poly(conv, _scaled(dd, c), s), [_poly(conv, _scaled(x, c), s) for x in nds]
    at = top if normalize == "monic" else int(e0.min())
    sel = np.nonzero(e0 == at)[0]
    if len(sel) == 1:
        pe = dd.exps[sel[0], 1:]
        pc = dd.coeffs[sel[0]]
        if not pe.any():
            c = Fraction(pc)
            return _poly(conv, _scaled(dd, c), s), [_poly(conv, _scaled(x, c), s) for x in nds]
        return _frac_poly(conv, dd, pe, pc, s), [_frac_poly(conv, x, pe, pc, s) for x in nds]
    return _normalize(conv, dd.to_sdict(k), [x.to_sdict(k) for x in nds], normalize, s)


def _content(coeffs: list) -> Fraction:
    if all(type(c) is int for c in coeffs):
        return Fraction(math.gcd(*coeffs) or 1)
    nums = [c.numerator for c in coeffs]
    dens = [c.denominator for c in coeffs]
    g = math.gcd(*nums)
    return Fraction(g, math.lcm(*dens)) if g else Fraction(1)


def _lead_sign(dd: Terms, top: int) -> int:
    """Sign of the coefficient of the largest parameter monomial at ``s**top``."""
    sel = np.nonzero(dd.exps[:, 0] == top)[0]
    rows = dd.exps[sel, 1:]
    best = sel[np.lexsort(rows.T[::-1])[-1]] if rows.shape[1] else sel[0]
    return 1 if dd.coeffs[best] > 0 else -1


def _scaled(p: Terms, c: Fraction) -> Terms:
    if c == 1:
        return p
    if c == -1:
        return Terms(p.exps, [-x for x in p.coeffs])
    if c.denominator == 1 and all(type(x) is int and x % c.numerator == 0 for x in p.coeffs):
        n = c.numerator
        return Terms(p.exps, [x // n for x in p.coeffs])
    return Terms(p.exps, [_norm_frac(Fraction(x) / c) for x in p.coeffs])


def _norm_frac(x: Fraction):
    return x.numerator if x.denominator == 1 else x


def _groups(p: Terms) -> dict[int, np.ndarray]:
    """Row indices of each power of ``s``."""
    e0 = p.exps[:, 0]
    order = np.argsort(e0, kind="stable")
    powers, starts = np.unique(e0[order], return_index=True)
    bounds = list(starts[1:]) + [len(order)]
    return {int(d): order[a:b] for d, a, b in zip(powers, starts, bounds)}


def _integral(coeffs: list) -> bool:
    return all(c.denominator == 1 for c in coeffs)


def _ring_element(R, rows: np.ndarray, coeffs: list, integer: bool):
    dom = R.domain
    keys = map(tuple, rows.tolist())
    if integer:
        if not all(type(c) is int for c in coeffs):
            coeffs = [int(c) for c in coeffs]
        return R.dtype(dict(zip(keys, map(dom.dtype, coeffs))))
    return R.dtype(dict(zip(keys, (dom(c.numerator, c.denominator) if isinstance(c, Fraction)
                                   else dom(c) for c in coeffs))))


def _poly(conv: _Converter, p: Terms, s: sp.Symbol) -> sp.Poly:
    """The sympy ``Poly`` of ``p`` (coefficients in ``ZZ[params]`` or ``QQ[params]``)."""
    if not len(p):
        return sp.Poly(0, s, domain=sp.ZZ)
    integer = _integral(p.coeffs)
    groups = _groups(p)
    if conv.k:
        R = conv.ZZr if integer else conv.QQr
        K = R.to_domain()
        rep = _by_degree(groups, R.zero, lambda d, idx: _ring_element(
            R, p.exps[idx, 1:], [p.coeffs[i] for i in idx], integer))
    else:
        K = sp.ZZ if integer else sp.QQ

        def number(d, idx):
            c = Fraction(sum(p.coeffs[i] for i in idx))
            return K(int(c.numerator)) if integer else K(int(c.numerator), int(c.denominator))
        rep = _by_degree(groups, K.zero, number)
    return sp.Poly.new(DMP.from_list(rep, 0, K), s)


def _by_degree(groups: dict, zero, make) -> list:
    """``[make(d, rows of s**d) or zero for d = deg .. 0]``: a dense list for ``DMP``."""
    return [make(d, groups[d]) if d in groups else zero for d in range(max(groups), -1, -1)]


def _frac_poly(conv: _Converter, p: Terms, pe: np.ndarray, pc, s: sp.Symbol) -> sp.Poly:
    """``p / (pc * x**pe)`` coefficient by coefficient, each fraction reduced:
    the monomial gcd removed, then integer coefficients with coprime contents
    and a positive denominator (``_convert._integer_pair``)."""
    if not len(p):
        return sp.Poly(0, s, domain=sp.ZZ)
    groups = _groups(p)
    gcds = {d: np.minimum(p.exps[idx, 1:].min(axis=0), pe) for d, idx in groups.items()}
    if pc == 1 and all((g == pe).all() for g in gcds.values()):
        # every reduced denominator is 1: a polynomial (as _convert.frac_poly decides)
        return _poly(conv, Terms(p.exps - np.concatenate([[0], pe]), p.coeffs), s)
    F = conv.FF
    K = F.to_domain()
    R = F.ring

    def fraction(d, idx):
        g = gcds[d]
        num_c, den_c = _integer_pair([p.coeffs[i] for i in idx], pc)
        num = _ring_element(R, p.exps[idx, 1:] - g, num_c, True)
        den = R.dtype({tuple((pe - g).tolist()): R.domain.dtype(den_c)})
        return F.raw_new(num, den)

    rep = _by_degree(groups, K.zero, fraction)
    return sp.Poly.new(DMP.from_list(rep, 0, K), s)


def _integer_pair(coeffs: list, pc) -> tuple[list[int], int]:
    """Integer numerator coefficients and denominator constant, coprime, denominator > 0."""
    L = math.lcm(*(c.denominator for c in coeffs), pc.denominator)
    if L == 1:
        num = [c if type(c) is int else int(c) for c in coeffs]
        den = int(pc)
    else:
        num = [int(c * L) for c in coeffs]
        den = int(pc * L)
    g = math.gcd(*num, den)
    if den < 0:
        g = -g
    return [x // g for x in num], den // g
