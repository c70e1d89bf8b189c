"""A transfer function's polynomials before they become sympy objects.

The determinants leave the exact algebra as exponent arrays
(:class:`~bondgraph.tf._packed.Terms`); turning a 700,000-term denominator
into a sympy ``Poly`` takes seconds and about 400 bytes a term.  A
:class:`Deferred` keeps the cancelled numerator and denominator as they are
and builds the normalized sympy ``Poly`` objects only when asked
(:meth:`Deferred.polys`, the same call the eager path made).  The degree in
``s`` and the exact values at numbers (:meth:`Deferred.values`) are read
from the arrays: ``P_k(x) / pivot(x)`` for each coefficient ``P_k`` of ``s**k``,
``pivot`` the normalization's constant or monomial divisor, which is the
normalized coefficient's value wherever the pivot does not vanish.

Examples
--------
>>> import sympy as sp
>>> from fractions import Fraction
>>> from bondgraph.tf.symbolic import transfer_function
>>> m, k = sp.symbols("m k", positive=True)
>>> G = transfer_function([[0, 1/m], [-k, 0]], [0, 1], [[1, 0]])
>>> src = G._source
>>> src.params, src.den_degree
((k, m), 2)
>>> src.values([Fraction(3), Fraction(2)])           # 1/(s**2 + 3/2) at k=3, m=2
([Fraction(1, 2)], [Fraction(1, 1), Fraction(0, 1), Fraction(3, 2)])
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Sequence

import numpy as np
import sympy as sp

from ._convert import _Converter
from ._packed import Terms
from ._packed_ops import _content, _lead_sign, normalize_terms

__all__ = ["Deferred"]


@dataclass(frozen=True, eq=False)
class Deferred:
    """Cancelled numerator and denominator (:class:`Terms` or s-dicts) and the
    normalization still to apply."""

    conv: _Converter
    num: Any
    den: Any
    normalize: str
    s: sp.Symbol

    @property
    def params(self) -> tuple[sp.Expr, ...]:
        """The parameters, one per exponent column after ``s``."""
        return tuple(self.conv.ZZr.symbols) if self.conv.k else ()

    @property
    def arrays(self) -> bool:
        """Whether both polynomials are exponent arrays."""
        return isinstance(self.num, Terms) and isinstance(self.den, Terms)

    def polys(self) -> tuple[sp.Poly, sp.Poly]:
        """``(num, den)``, normalized sympy ``Poly`` objects."""
        Pd, (Pn,) = normalize_terms(self.conv, self.den, [self.num], self.normalize, self.s)
        return Pn, Pd

    @property
    def den_degree(self) -> int:
        """Degree in ``s`` of the denominator (requires :attr:`arrays`)."""
        return int(self.den.exps[:, 0].max())

    @property
    def num_degree(self) -> int:
        """Degree in ``s`` of the numerator, -1 for zero (requires :attr:`arrays`)."""
        return int(self.num.exps[:, 0].max()) if len(self.num) else -1

    def pivot(self) -> tuple[Any, np.ndarray] | None:
        """The normalization's divisor ``(c, e)``, ``c * params**e``, as
        :func:`~bondgraph.tf._packed_ops.normalize_terms` chooses it; ``None``
        when it is a polynomial of several terms (or the inputs are s-dicts)."""
        if not self.arrays:
            return None
        dd = self.den
        e0 = dd.exps[:, 0]
        top = int(e0.max())
        k = self.conv.k
        if self.normalize == "as-derived":
            return _content(dd.coeffs) * _lead_sign(dd, top), np.zeros(k, dtype=np.int64)
        at = top if self.normalize == "monic" else int(e0.min())
        sel = np.nonzero(e0 == at)[0]
        if len(sel) != 1:
            return None
        return Fraction(dd.coeffs[sel[0]]), dd.exps[sel[0], 1:].astype(np.int64)

    def used(self) -> set:
        """The parameters the normalized polynomials hold (as ``_exact._used_symbols``
        reads them from the sympy Polys); requires :meth:`pivot`."""
        found = self.pivot()
        assert found is not None
        pe = found[1]
        hit = np.zeros(self.conv.k, dtype=bool)
        for p in (self.num, self.den):
            if not len(p) or not self.conv.k:
                continue
            for d in np.unique(p.exps[:, 0]).tolist():
                rows = p.exps[p.exps[:, 0] == d, 1:]
                g = np.minimum(rows.min(axis=0), pe)
                hit |= (rows != g).any(axis=0) | (pe != g)
        return {x for x, h in zip(self.params, hit.tolist()) if h}

    def values(self, point: Sequence[Fraction]) -> tuple[list[Fraction], list[Fraction]] | None:
        """Exact coefficients (highest power first) of the normalized numerator and
        denominator at ``point`` (one value per parameter); ``None`` when the pivot
        vanishes there (the sympy form decides what that means)."""
        found = self.pivot()
        assert found is not None
        c, pe = found
        scale = Fraction(c)
        for v, e in zip(point, pe.tolist()):
            if e:
                scale *= Fraction(v) ** e
        if scale == 0:
            return None
        out = []
        for p in (self.num, self.den):
            if not len(p):
                out.append([Fraction(0)])
                continue
            sums = _coefficient_values(p, point)
            out.append([sums.get(d, Fraction(0)) / scale
                        for d in range(int(p.exps[:, 0].max()), -1, -1)])
        return out[0], out[1]


#: terms evaluated at once (bounds the memory of the big-integer products)
CHUNK = 1 << 16


def _coefficient_values(p: Terms, point: Sequence[Fraction]) -> dict[int, Fraction]:
    """``{d: P_d(point)}`` for ``p = sum_d s**d P_d``, exactly.

    Each value ``a_i/b_i`` enters as integers: a term is ``c * prod a_i**e_i *
    b_i**(E_i - e_i)`` over the common denominator ``prod b_i**E_i``
    (``E_i`` the largest exponent of parameter ``i``), the products taken a
    column at a time on object arrays, :data:`CHUNK` terms at a time.
    """
    e = p.exps
    tables = []
    denom = 1
    for i, v in enumerate(point):
        top = int(e[:, 1 + i].max())
        if not top:
            continue
        v = Fraction(v)
        a, b = v.numerator, v.denominator
        table = np.empty(top + 1, dtype=object)
        table[:] = [a ** j * b ** (top - j) for j in range(top + 1)]
        tables.append((1 + i, table))
        denom *= b ** top
    sums: dict[int, Any] = {}
    for lo in range(0, len(p), CHUNK):
        rows = e[lo:lo + CHUNK]
        prod = np.empty(len(rows), dtype=object)
        prod[:] = p.coeffs[lo:lo + CHUNK]
        for col, table in tables:
            prod *= table[rows[:, col]]
        e0 = rows[:, 0]
        order = np.argsort(e0, kind="stable")
        powers, starts = np.unique(e0[order], return_index=True)
        for d, x in zip(powers.tolist(), np.add.reduceat(prod[order], starts).tolist()):
            sums[d] = sums.get(d, 0) + x
    return {int(d): Fraction(x) / denom for d, x in sums.items()}
