"""Encoding of sympy state-space matrices as elements of one polynomial ring.

Second stage of the exact algebra (:mod:`bondgraph.tf._algebra`): every entry
of ``A, B, C, D, E`` becomes a polynomial in ``s``, the parameters and one
reciprocal variable ``r_j = 1/f_j`` per irreducible denominator factor.

Examples
--------
>>> import sympy as sp
>>> m, s = sp.symbols("m s", positive=True)
>>> enc = encode_system(sp.Matrix([[-1/m]]), sp.Matrix([[1]]), sp.Matrix([[1]]),
...                     sp.Matrix([[0]]), None, s)
>>> enc.params, enc.recip_bases
((m,), (m,))
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Sequence

import sympy as sp
from sympy.polys.polyutils import parallel_dict_from_expr

from ._rings import Ring, make_ring
from .errors import MatrixEntryError

__all__ = ["EncodedSystem", "encode_system", "polys_from_exprs"]


@dataclass(frozen=True)
class EncodedSystem:
    """The system matrices as polynomials of ``ring``; variable 0 is ``s``.

    ``params`` are variables ``1..k``, the reciprocal variables ``k+1..k+q``
    stand for ``1/recip_bases[j]``.  ``E`` is ``None`` for the identity.
    """

    ring: Ring
    s: sp.Symbol
    params: tuple[sp.Expr, ...]
    recip_symbols: tuple[sp.Dummy, ...]
    recip_bases: tuple[sp.Expr, ...]
    recip_polys: tuple[Any, ...]
    A: tuple[tuple[Any, ...], ...]
    B: tuple[tuple[Any, ...], ...]
    C: tuple[tuple[Any, ...], ...]
    D: tuple[tuple[Any, ...], ...]
    E: tuple[tuple[Any, ...], ...] | None

    @property
    def n(self) -> int:
        return len(self.A)

    @property
    def all_symbols(self) -> tuple[sp.Expr, ...]:
        return (self.s,) + self.params + self.recip_symbols

    def pencil(self) -> list[list[Any]]:
        """``s E - A`` as a list of rows of ring elements."""
        R, n = self.ring, self.n
        s = R.gen(0)
        rows = []
        for i in range(n):
            row = []
            for j in range(n):
                if self.E is None:
                    e = s if i == j else R.zero
                else:
                    e = s * self.E[i][j]
                row.append(e - self.A[i][j])
            rows.append(row)
        return rows

    def bordered(self, pencil: list[list[Any]], i: int, j: int) -> list[list[Any]]:
        """``[[sE - A, B_j], [-C_i, D_ij]]``: its determinant is the numerator."""
        rows = [row + [self.B[r][j]] for r, row in enumerate(pencil)]
        rows.append([-c for c in self.C[i]] + [self.D[i][j]])
        return rows


def _rationalize(e: sp.Expr) -> sp.Expr:
    if e.has(sp.Float):
        e = sp.nsimplify(e, rational=True)
    return e


def encode_system(A, B, C, D, E, s: sp.Symbol, *, backend: str | None = None) -> EncodedSystem:
    """Encode sympy matrices (already shape-checked) as ring elements.

    Floats are read as the exact decimals they print as (``0.1 -> 1/10``).
    """
    mats = {"A": A, "B": B, "C": C, "D": D}
    if E is not None:
        mats["E"] = E
    recips: dict[sp.Expr, sp.Dummy] = {}
    den_cache: dict[sp.Expr, tuple] = {}
    exprs: list[sp.Expr] = []
    index: dict[str, list[list[int]]] = {}
    for name, M in mats.items():
        rows, cols = M.shape
        idx = []
        for i in range(rows):
            irow = []
            for j in range(cols):
                try:
                    e = sp.sympify(M[i, j], strict=True)
                except sp.SympifyError:
                    raise MatrixEntryError(
                        f"{name}[{i}, {j}]: expected a number or a sympy expression, got "
                        f"{type(M[i, j]).__name__} {M[i, j]!r:.60} (text and bytes are never "
                        "parsed)") from None
                irow.append(len(exprs))
                if name in ("B", "D") and isinstance(e, sp.Expr) and s in e.free_symbols:
                    # input derivatives: a polynomial in s with parameter coefficients
                    exprs.append(sp.expand(sp.Add(*[
                        s**k * _encode_entry(c, name, i, j, s, recips, den_cache)
                        for k, c in _s_coefficients(e, name, i, j, s)])))
                else:
                    exprs.append(_encode_entry(e, name, i, j, s, recips, den_cache))
            idx.append(irow)
        index[name] = idx
    bases = list(recips)
    rsyms = [recips[b] for b in bases]
    exprs_all = exprs + bases
    if exprs_all:
        dicts, gens = parallel_dict_from_expr(exprs_all, domain=sp.QQ)
    else:  # pragma: no cover - 0x0 system
        dicts, gens = [], ()
    gens = tuple(gens)
    rset = set(rsyms)
    params = tuple(sorted((g for g in gens if g not in rset and g != s),
                          key=sp.default_sort_key))
    order = list(params) + rsyms
    pos = {g: gens.index(g) if g in gens else None for g in order}
    pos_s = gens.index(s) if s in gens else None     # only in B and D entries
    ring = make_ring(1 + len(order), backend)

    def to_ring(d):
        terms = {}
        for exps, c in d.items():
            new = [exps[pos_s] if pos_s is not None else 0]
            for g in order:
                k = pos[g]
                new.append(exps[k] if k is not None else 0)
            c = sp.Rational(c)
            terms[tuple(new)] = Fraction(int(c.p), int(c.q))
        return ring.from_terms(terms)

    polys = [to_ring(d) for d in dicts]
    enc = {name: tuple(tuple(polys[k] for k in row) for row in idx)
           for name, idx in index.items()}
    return EncodedSystem(ring=ring, s=s, params=params, recip_symbols=tuple(rsyms),
                         recip_bases=tuple(bases),
                         recip_polys=tuple(polys[len(exprs):]),
                         A=enc["A"], B=enc["B"], C=enc["C"], D=enc["D"], E=enc.get("E"))


def _s_coefficients(e: sp.Expr, name: str, i: int, j: int, s: sp.Symbol):
    """``[(k, c_k)]`` with ``e = sum c_k s**k`` (``B``/``D`` entries of input derivatives)."""
    try:
        P = sp.Poly(e, s)
    except sp.PolynomialError:
        raise MatrixEntryError(f"{name}[{i}, {j}]: expected a polynomial in {s} (input "
                               f"derivatives), got {e}") from None
    out = []
    for (k,), c in P.terms():
        c = sp.sympify(P.domain.to_sympy(c), strict=True) if not isinstance(c, sp.Expr) else c
        if s in c.free_symbols:  # pragma: no cover - Poly keeps s out of coefficients
            raise MatrixEntryError(f"{name}[{i}, {j}]: expected a polynomial in {s}, got {e}")
        out.append((k, c))
    return out


def _encode_entry(e, name, i, j, s, recips, den_cache):
    if not isinstance(e, sp.Expr):
        raise MatrixEntryError(f"{name}[{i}, {j}]: expected a sympy expression, got {e!r}")
    if e.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        raise MatrixEntryError(f"{name}[{i}, {j}]: expected a finite expression, got {e}")
    if s in e.free_symbols:
        raise MatrixEntryError(f"{name}[{i}, {j}]: entries must not contain the Laplace "
                               f"variable {s}, got {e}")
    if e.has(sp.I):
        raise MatrixEntryError(f"{name}[{i}, {j}]: expected a real expression, got {e}")
    e = _rationalize(e)
    if e.is_Rational or e.is_Symbol:
        return e
    num, den = sp.fraction(sp.together(e))
    if den == 1:
        return sp.expand(num)
    if den not in den_cache:
        c, factors = sp.factor_list(den)
        den_cache[den] = (c, factors)
    c, factors = den_cache[den]
    out = sp.expand(num) / c
    for f, k in factors:
        if f.is_number:
            out = out / f ** k
            continue
        if f not in recips:
            recips[f] = sp.Dummy("r")
        out = out * recips[f] ** k
    return sp.expand(out)


def polys_from_exprs(exprs: Sequence[sp.Expr], s: sp.Symbol, *,
                     backend: str | None = None) -> tuple[Ring, tuple[sp.Expr, ...], list]:
    """Polynomial expressions in ``s`` and parameters as elements of one ring.

    Returns ``(ring, params, polys)``; variable 0 is ``s``, then ``params``
    (sorted).  Floats are rationalized.

    Examples
    --------
    >>> import sympy as sp
    >>> a, s = sp.symbols("a s")
    >>> R, params, (p,) = polys_from_exprs([a*s + 1], s)
    >>> params, sorted(R.terms(p))
    ((a,), [((0, 0), 1), ((1, 1), 1)])
    """
    exprs = [sp.expand(_rationalize(sp.sympify(e, strict=True))) for e in exprs]
    dicts, gens = parallel_dict_from_expr(exprs + [s], domain=sp.QQ)
    dicts = dicts[:-1]
    gens = tuple(gens)
    params = tuple(sorted((g for g in gens if g != s), key=sp.default_sort_key))
    order = (s,) + params
    pos = [gens.index(g) for g in order]
    ring = make_ring(len(order), backend)
    polys = []
    for d in dicts:
        terms = {}
        for exps, c in d.items():
            c = sp.Rational(c)
            terms[tuple(exps[k] for k in pos)] = Fraction(int(c.p), int(c.q))
        polys.append(ring.from_terms(terms))
    return ring, params, polys
