"""Determinants in a Kronecker-packed ring and their results as exponent arrays.

The fast path of the exact algebra (:mod:`bondgraph.tf._algebra`) for the
common case, python-flint arithmetic and every reciprocal base a single
parameter (``1/m``, ``1/L``; or none).  Profiling the force -> last-mass
transfer function of a 10-mass chain (20 states, 30 parameters, 699,051
terms in the denominator) showed the determinants taking 0.5 s and the rest
(clearing the reciprocals, the gcd, normalizing) over 20 s and 1.6 GB, spent
turning each term into Python tuples several times over.  Here:

1. every variable ``x_i`` of the encoded system gets a bit field wide enough
   for its degree in any determinant (the sum over the rows of its largest
   degree in a row bounds the degree of every minor), and the entries are
   mapped into a ring of one or a few variables by ``x_i -> t**(2**offset_i)``
   (Kronecker substitution, a ring homomorphism that is injective on
   polynomials within the bounds); the determinants run there with word-size
   monomials;
2. each result is read back once into a :class:`Terms`, an integer array of
   exponents (column 0 is ``s``) and a list of coefficients;
3. reciprocals are cleared, common factors cancelled and the normalization
   applied on those arrays (:mod:`bondgraph.tf._packed_ops`), and sympy
   ``Poly`` objects are built from them directly.

The results are the same polynomials as the general path's, term for term.

Examples
--------
>>> import sympy as sp
>>> from bondgraph.tf._encode import encode_system
>>> m, k, s = sp.symbols("m k s", positive=True)
>>> enc = encode_system(sp.Matrix([[0, 1/m], [-k, 0]]), sp.Matrix([[0], [1]]),
...                     sp.Matrix([[1, 0]]), sp.Matrix([[0]]), None, s)
>>> den, (num,) = packed_determinants(enc, [(0, 0)])
>>> sorted(zip(map(tuple, den.exps.tolist()), den.coeffs))
[((0, 1, 0, 1), 1), ((2, 0, 0, 0), 1)]
"""

from __future__ import annotations

import random
from fractions import Fraction
from typing import Any, Sequence

import numpy as np

from ._determinants import determinant
from ._encode import EncodedSystem
from ._lift import lifted
from ._rings import Ring, _FlintRing

__all__ = ["Terms", "packed_determinants", "can_pack"]

#: bits of one packed variable (flint keeps one machine word per variable)
_WORD = 62


class Terms:
    """A polynomial as ``exps`` (int64 array, one row per term) and ``coeffs``.

    Coefficients are ints, or Fractions when not integral.
    """

    __slots__ = ("exps", "coeffs", "spec")

    def __init__(self, exps: np.ndarray, coeffs: list, spec: Any = None):
        self.exps = exps
        self.coeffs = coeffs
        #: the polynomial at a random point of the parameters, up to a nonzero
        #: constant (a python-flint ``fmpq_poly`` in ``s``), or None
        self.spec = spec

    def __len__(self) -> int:
        return len(self.coeffs)

    def to_sdict(self, k: int) -> dict:
        """The s-dict of :mod:`bondgraph.tf._cancel` (general-path exchange format)."""
        out: dict = {}
        for row, c in zip(self.exps.tolist(), self.coeffs):
            out.setdefault(row[0], {})[tuple(row[1:1 + k])] = c
        return out


def can_pack(enc: EncodedSystem) -> bool:
    """Whether the fast path applies: flint rings, reciprocals of single parameters."""
    if not isinstance(enc.ring, _FlintRing):
        return False
    for fp in enc.recip_polys:
        tl = enc.ring.terms(fp)
        if not (len(tl) == 1 and tl[0][1] == 1 and sum(tl[0][0]) == 1):
            return False
    return True


def _degree_bounds(mats: Sequence[Sequence[Sequence[Any]]], ring: Ring) -> list[int]:
    """Per variable, a bound on its degree in the determinant of every matrix."""
    nv = ring.nvars
    bound = [0] * nv
    for M in mats:
        total = [0] * nv
        for row in M:
            top = [0] * nv
            for p in row:
                if not ring.is_zero(p):
                    for v, d in enumerate(ring.degrees(p)):
                        if d > top[v]:
                            top[v] = d
            total = [a + b for a, b in zip(total, top)]
        bound = [max(a, b) for a, b in zip(bound, total)]
    return bound


class _Packing:
    """Bit fields of the variables and the packed ring."""

    def __init__(self, bounds: Sequence[int]):
        # a variable absent from every matrix (bound 0) takes no bits: it maps to 1
        self.bits = [int(b).bit_length() for b in bounds]
        self.group: list[int] = []
        self.offset: list[int] = []
        g, off = 0, 0
        for b in self.bits:
            if off + b > _WORD:
                g, off = g + 1, 0
            self.group.append(g)
            self.offset.append(off)
            off += b
        self.ring = _FlintRing(g + 1)
        gens = [self.ring.gen(i) for i in range(g + 1)]
        self.images = [gens[gi] ** (1 << off) if b else self.ring.one
                       for gi, off, b in zip(self.group, self.offset, self.bits)]

    def pack(self, p, ctx) -> Any:
        return p.compose(*self.images, ctx=ctx)

    def unpack(self, p) -> Terms:
        monoms = p.monoms()
        count = len(monoms)
        ngroups = self.ring.nvars
        cols = [np.fromiter((m[gi] for m in monoms), dtype=np.uint64, count=count)
                for gi in range(ngroups)]
        del monoms          # the largest transient: a tuple of ints per term
        # small integers: the arrays are copied and sliced, and their size is the memory;
        # int8 while a cleared exponent (at most twice a field's largest value) fits
        top = max(self.bits, default=0)
        dtype = np.int8 if top <= 6 else np.int16 if top <= 12 else np.int64
        exps = np.empty((count, len(self.bits)), dtype=dtype)
        for v, (gi, off, b) in enumerate(zip(self.group, self.offset, self.bits)):
            exps[:, v] = (cols[gi] >> np.uint64(off)) & np.uint64((1 << b) - 1) if b else 0
        del cols
        coeffs = [int(c.p) if c.q == 1 else Fraction(int(c.p), int(c.q)) for c in p.coeffs()]
        return Terms(exps, coeffs)


def packed_determinants(enc: EncodedSystem, pairs: Sequence[tuple[int, int]], *,
                        method: str = "auto") -> tuple[Terms, list[Terms]]:
    """``det(sE - A)`` and the bordered determinants of ``pairs`` ``(i, j)``.

    Returns :class:`Terms` over all the variables of ``enc.ring`` (``s``,
    parameters, reciprocals), reciprocals not yet cleared.
    """
    ring = enc.ring
    pencil = enc.pencil()
    # rank-one couplings (a junction's) lifted out: det M = det L / prod(divisors)
    mats = [lifted(M, ring, method) for M in [pencil] + [enc.bordered(pencil, i, j)
                                                          for i, j in pairs]]
    pk = _Packing(_degree_bounds([L for L, _ in mats], ring))
    R = pk.ring
    ctx = R.ctx
    cache: dict[int, Any] = {}

    def packed(M):
        out = []
        for row in M:
            prow = []
            for p in row:
                key = id(p)
                if key not in cache:
                    cache[key] = (p, R.zero if p.is_zero() else pk.pack(p, ctx))
                prow.append(cache[key][1])
            out.append(prow)
        return out

    def det(L, divisors):
        value = determinant(packed(L), R, method=method)
        for d in divisors:
            value = R.exquo(value, pk.pack(d, ctx))
        return value

    out = [pk.unpack(det(L, divisors)) for L, divisors in mats]
    for t, sp_ in zip(out, _specialized(enc, mats, method)):
        t.spec = sp_
    return out[0], out[1:]


class _UnivariateRing(Ring):
    """``QQ[s]`` (python-flint ``fmpq_poly``) for :func:`determinant`."""

    nvars = 1

    def __init__(self):
        import flint

        self.zero = flint.fmpq_poly(0)
        self.one = flint.fmpq_poly(1)

    @staticmethod
    def is_zero(p) -> bool:
        return p == 0

    @staticmethod
    def exquo(p, q):
        return p // q

    @staticmethod
    def nterms(p) -> int:
        return p.degree() + 1


def _specialized(enc: EncodedSystem, mats, method: str) -> list:
    """The determinants at a random integer point of the parameters, with each
    reciprocal ``r_j = 1/m_j`` at its base's value: the cleared polynomials
    there up to one nonzero constant (used to prove numerator and denominator
    coprime in ``s``).  ``mats``: pairs ``(L, divisors)`` of :func:`lifted`
    (a divisor vanishing at the point leaves the value undecided: ``None``)."""
    import flint

    ring = enc.ring
    k, q = len(enc.params), len(enc.recip_symbols)
    rng = random.Random(12345)
    point = [flint.fmpq(rng.randint(2, 10**6)) for _ in range(k)]
    recip = [1 / point[ring.terms(fp)[0][0].index(1) - 1] for fp in enc.recip_polys]
    s = flint.fmpq_poly([0, 1])
    U = _UnivariateRing()
    cache: dict[int, Any] = {}

    def value(p):
        key = id(p)
        if key not in cache:
            total = U.zero
            for exps, c in ring.terms(p):
                term = flint.fmpq(c.numerator, c.denominator) if isinstance(c, Fraction) \
                    else flint.fmpq(c)
                for v in range(1, 1 + k + q):
                    if exps[v]:
                        term *= (point[v - 1] if v <= k else recip[v - 1 - k]) ** exps[v]
                total += term * s ** exps[0]
            cache[key] = (p, total)
        return cache[key][1]

    out = []
    for L, divisors in mats:
        scale = U.one
        for d in divisors:
            scale *= value(d)
        out.append(None if scale == 0 else
                   determinant([[value(p) for p in row] for row in L], U, method=method) // scale)
    return out
