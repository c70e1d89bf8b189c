"""Exact polynomial algebra behind the symbolic transfer functions (private).

The matrices ``A, B, C, D, E`` are encoded in one multivariate polynomial ring
``QQ[s, p_1..p_k, r_1..r_q]`` where the ``p`` are the parameters (and any other
non-polynomial atoms such as ``sqrt(2)``) and each ``r_j`` stands for ``1/f_j``,
``f_j`` an irreducible denominator factor of some entry (``1/m``, ``1/L``,
``1/(J1 + n**2*J2)``).  All entries are then polynomials, determinants are
computed division free, and the reciprocals are cleared at the end by
multiplying every result by the same product ``prod f_j**d_j`` (this keeps
ratios exact because evaluation ``r_j -> 1/f_j`` is a ring homomorphism).

Determinants of the (sparse) matrices ``sE - A`` and of the bordered matrices
``[[sE - A, B_j], [-C_i, D_ij]]`` are computed by a memoized Laplace expansion
over row subsets (cheap for the banded / arrow-shaped matrices of lumped
models), with a fraction-free Bareiss elimination as the fallback for dense
matrices.  The ring arithmetic is python-flint's ``fmpq_mpoly`` when available,
otherwise sympy's ``PolyRing``.  sympy's ``DomainMatrix.charpoly`` (Berkowitz)
is available as ``method="berkowitz"`` for cross-checking.

Examples
--------
>>> import sympy as sp
>>> from bondgraph.tf._algebra import encode_system, determinant
>>> m, k, s = sp.symbols("m k s", positive=True)
>>> enc = encode_system(sp.Matrix([[0, 1/m], [-k, 0]]), sp.Matrix([[0], [1]]),
...                     sp.Matrix([[1, 0]]), sp.Matrix([[0]]), None, s)
>>> den = determinant(enc.pencil(), enc.ring)
>>> enc.ring.to_sympy(den, enc.all_symbols)
_r*k + s**2
"""

from __future__ import annotations

import operator
import os
from collections import defaultdict
from dataclasses import dataclass
from fractions import Fraction
from types import ModuleType
from typing import Any, Sequence

import sympy as sp
from sympy.polys.polyutils import parallel_dict_from_expr

from .errors import InvalidOptionError, MatrixEntryError

_flint: ModuleType | None
try:  # python-flint is a declared dependency; keep a pure-sympy fallback anyway
    import flint as _flint
except ImportError:  # pragma: no cover - exercised only without python-flint
    _flint = None

__all__ = ["Ring", "make_ring", "EncodedSystem", "encode_system", "determinant",
           "charpoly_berkowitz", "clear_reciprocals", "cancel_common", "backend_name",
           "polys_from_exprs"]

#: ``method='auto'`` uses the Laplace expansion while it needs at most
#: ``max(n**3, LAPLACE_MIN)`` ring products (about what Bareiss needs, but with
#: far smaller intermediate polynomials), Bareiss otherwise.
LAPLACE_MIN = 64


def backend_name() -> str:
    """Name of the polynomial arithmetic in use: ``'flint'`` or ``'sympy'``.

    Set the environment variable ``BONDGRAPH_TF_BACKEND=sympy`` to force the
    pure-sympy arithmetic.

    Examples
    --------
    >>> backend_name() in ("flint", "sympy")
    True
    """
    want = os.environ.get("BONDGRAPH_TF_BACKEND", "").lower()
    if want == "sympy" or _flint is None:
        return "sympy"
    return "flint"


# --------------------------------------------------------------------------- rings
class Ring:
    """Minimal common interface of the flint and sympy multivariate rings."""

    nvars: int
    zero: Any
    one: Any

    def from_terms(self, terms: dict) -> Any:  # exps -> Fraction
        raise NotImplementedError

    def terms(self, p) -> list[tuple[tuple[int, ...], int | Fraction]]:
        """``[(exponents, coefficient)]``; coefficients are ints when integral."""
        raise NotImplementedError

    def is_zero(self, p) -> bool:
        raise NotImplementedError

    def gcd(self, p, q) -> Any:
        raise NotImplementedError

    def exquo(self, p, q) -> Any:
        """Exact quotient ``p / q`` (``q`` must divide ``p``)."""
        raise NotImplementedError

    def degrees(self, p) -> tuple[int, ...]:
        """Degree of ``p`` in each variable."""
        raise NotImplementedError

    def nterms(self, p) -> int:
        raise NotImplementedError

    def gen(self, i: int) -> Any:
        exps = [0] * self.nvars
        exps[i] = 1
        return self.from_terms({tuple(exps): Fraction(1)})

    def const(self, c) -> Any:
        c = Fraction(c)
        if c == 0:
            return self.zero
        return self.from_terms({(0,) * self.nvars: c})

    def to_sympy(self, p, symbols: Sequence[sp.Expr]) -> sp.Expr:
        """The element as a sympy expression in ``symbols`` (one per variable)."""
        out = []
        for exps, c in self.terms(p):
            factors = [sp.Rational(c.numerator, c.denominator)]
            factors += [symbols[i] ** e for i, e in enumerate(exps) if e]
            out.append(sp.Mul(*factors))
        return sp.Add(*out)


class _FlintRing(Ring):
    def __init__(self, nvars: int):
        if _flint is None:  # pragma: no cover - make_ring checks this first
            raise InvalidOptionError("backend: python-flint is not installed")
        self.nvars = nvars
        names = tuple(f"x{i}" for i in range(max(nvars, 1)))
        self.ctx = _flint.fmpq_mpoly_ctx.get(names, "lex")
        self.zero = self.ctx.from_dict({})
        self.one = self.ctx.constant(1)

    def from_terms(self, terms):
        fmpq = _flint.fmpq
        return self.ctx.from_dict({e: (c if type(c) is int else fmpq(c.numerator, c.denominator))
                                   for e, c in terms.items() if c})

    def terms(self, p):
        # ints for integer coefficients (the common case), Fractions otherwise
        idx = operator.index
        out = []
        for e, c in zip(p.monoms(), p.coeffs()):
            q = c.q
            out.append((tuple(map(idx, e)),
                        int(c.p) if q == 1 else Fraction(int(c.p), int(q))))
        return out

    @staticmethod
    def is_zero(p) -> bool:
        return p.is_zero()

    @staticmethod
    def gcd(p, q):
        return p.gcd(q)

    @staticmethod
    def exquo(p, q):
        return p / q

    @staticmethod
    def degrees(p) -> tuple[int, ...]:
        return tuple(int(d) for d in p.degrees())

    @staticmethod
    def nterms(p) -> int:
        return len(p)


class _SympyRing(Ring):
    def __init__(self, nvars: int):
        self.nvars = nvars
        self.ring = sp.polys.rings.PolyRing(
            [sp.Dummy(f"x{i}") for i in range(max(nvars, 1))], sp.QQ)
        self.zero = self.ring.zero
        self.one = self.ring.one

    def from_terms(self, terms):
        QQ = sp.QQ
        return self.ring.from_dict({e: QQ(int(c.numerator), int(c.denominator))
                                    for e, c in terms.items() if c})

    def terms(self, p):
        out = []
        numer, denom = sp.QQ.numer, sp.QQ.denom
        for e, c in p.items():
            q = int(denom(c))
            out.append((tuple(e), int(numer(c)) if q == 1 else Fraction(int(numer(c)), q)))
        return out

    @staticmethod
    def is_zero(p) -> bool:
        return not p

    @staticmethod
    def gcd(p, q):
        return p.gcd(q)

    @staticmethod
    def exquo(p, q):
        return p.exquo(q)

    def degrees(self, p) -> tuple[int, ...]:
        if not p:
            return (0,) * self.nvars
        return tuple(max(e[i] for e in p.keys()) for i in range(self.nvars))

    @staticmethod
    def nterms(p) -> int:
        return len(p)


def make_ring(nvars: int, backend: str | None = None) -> Ring:
    """A polynomial ring over QQ in ``nvars`` variables.

    Examples
    --------
    >>> R = make_ring(2)
    >>> x, y = R.gen(0), R.gen(1)
    >>> sorted(R.terms((x + y) * (x - y)))
    [((0, 2), -1), ((2, 0), 1)]
    """
    backend = backend or backend_name()
    if backend == "flint":
        if _flint is None:  # pragma: no cover
            raise InvalidOptionError("backend: expected 'sympy' (python-flint is not "
                                     "installed), got 'flint'")
        return _FlintRing(nvars)
    if backend == "sympy":
        return _SympyRing(nvars)
    raise InvalidOptionError(f"backend: expected 'flint' or 'sympy', got {backend!r}")


# ------------------------------------------------------------------------ encoding
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
                e = sp.sympify(M[i, j], strict=True)
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


# -------------------------------------------------------------------- determinants
def determinant(M: Sequence[Sequence[Any]], ring: Ring, *, method: str = "auto"):
    """Determinant of a square matrix of ring elements, division free.

    ``method`` is ``'auto'`` (Laplace expansion over row subsets when it is
    cheap, else Bareiss), ``'laplace'`` or ``'bareiss'``.

    Examples
    --------
    >>> R = make_ring(1)
    >>> x = R.gen(0)
    >>> d = determinant([[x, R.one], [R.one, x]], R)
    >>> sorted(R.terms(d))
    [((0,), -1), ((2,), 1)]
    """
    n = len(M)
    if n == 0:
        return ring.one
    if method not in ("auto", "laplace", "bareiss"):
        raise InvalidOptionError(f"method: expected 'auto', 'laplace' or 'bareiss', "
                                 f"got {method!r}")
    if method == "bareiss":
        return _bareiss(M, ring)
    pattern = [[ring.is_zero(M[i][j]) is False for j in range(n)] for i in range(n)]
    limit = None if method == "laplace" else max(n ** 3, LAPLACE_MIN)
    best = None
    for transpose in (False, True):
        pat = pattern if not transpose else [list(r) for r in zip(*pattern)]
        plan = _laplace_plan(pat, limit)
        if plan is not None and (best is None or plan[1] < best[2]):
            best = (transpose, plan[0], plan[1])
    if best is None:
        return _bareiss(M, ring)
    transpose, order, _ = best
    if transpose:
        M = [list(r) for r in zip(*M)]
    return _laplace(M, ring, order)


def _laplace_plan(pattern: Sequence[Sequence[bool]],
                  limit: int | None) -> tuple[list[int], int] | None:
    """Column order for the Laplace expansion and its number of ring products.

    Returns ``None`` when the expansion would exceed ``limit`` products.
    """
    n = len(pattern)
    colrows = [frozenset(i for i in range(n) if pattern[i][j]) for j in range(n)]
    rowcount = [sum(1 for j in range(n) if pattern[i][j]) for i in range(n)]
    if any(not c for c in colrows) or any(c == 0 for c in rowcount):
        return [], 0  # structurally singular: determinant is zero
    # greedy order: keep the set of open rows (touched, not finished) small
    remaining = set(range(n))
    seen_count = [0] * n
    touched: set[int] = set()
    order = []
    while remaining:
        def key(c):
            rows = colrows[c]
            opened = len(touched | rows)
            closed = sum(1 for r in touched | rows
                         if seen_count[r] + (r in rows) == rowcount[r])
            return (opened - closed, len(rows), c)
        c = min(remaining, key=key)
        order.append(c)
        remaining.discard(c)
        for r in colrows[c]:
            seen_count[r] += 1
        touched |= colrows[c]
    # required rows after each step
    last = [0] * n
    for t, c in enumerate(order):
        for r in colrows[c]:
            last[r] = t
    required = [0] * n
    for r in range(n):
        required[last[r]] |= 1 << r
    states = {0}
    cost = 0
    req = 0
    for t, c in enumerate(order):
        req |= required[t]
        new = set()
        for mask in states:
            for r in colrows[c]:
                bit = 1 << r
                if not mask & bit:
                    nm = mask | bit
                    if nm & req == req:
                        new.add(nm)
                        cost += 1
        if limit is not None and cost > limit:
            return None
        states = new
        if not states:
            return order, cost
    return order, cost


def _laplace(M: Sequence[Sequence[Any]], ring: Ring, order: Sequence[int]) -> Any:
    n = len(M)
    if not order:
        return ring.zero
    is_zero = ring.is_zero
    colrows = [[i for i in range(n) if not is_zero(M[i][c])] for c in order]
    last = [0] * n
    for t, rows in enumerate(colrows):
        for r in rows:
            last[r] = t
    required = [0] * n
    for r in range(n):
        required[last[r]] |= 1 << r
    # sign of the column permutation
    sign = _perm_sign(order)
    dp = {0: ring.one if sign > 0 else -ring.one}
    req = 0
    for t, c in enumerate(order):
        req |= required[t]
        new: dict[int, Any] = {}
        for mask, val in dp.items():
            for r in colrows[t]:
                bit = 1 << r
                if mask & bit:
                    continue
                nm = mask | bit
                if nm & req != req:
                    continue
                term = val * M[r][c]
                if bin(mask >> (r + 1)).count("1") & 1:
                    term = -term
                if nm in new:
                    new[nm] = new[nm] + term
                else:
                    new[nm] = term
        dp = {k: v for k, v in new.items() if not is_zero(v)}
        if not dp:
            return ring.zero
    return dp.get((1 << n) - 1, ring.zero)


def _perm_sign(perm) -> int:
    perm = list(perm)
    sign = 1
    seen = [False] * len(perm)
    for i in range(len(perm)):
        if seen[i]:
            continue
        j, length = i, 0
        while not seen[j]:
            seen[j] = True
            j = perm[j]
            length += 1
        if length % 2 == 0:
            sign = -sign
    return sign


def _bareiss(M, ring):
    """Fraction-free Gaussian elimination (exact divisions in the ring)."""
    n = len(M)
    M = [list(row) for row in M]
    is_zero = ring.is_zero
    sign = 1
    prev = ring.one
    for k in range(n - 1):
        candidates = [i for i in range(k, n) if not is_zero(M[i][k])]
        if not candidates:
            return ring.zero
        p = min(candidates, key=lambda i: ring.nterms(M[i][k]))
        if p != k:
            M[k], M[p] = M[p], M[k]
            sign = -sign
        pivot = M[k][k]
        for i in range(k + 1, n):
            mik = M[i][k]
            for j in range(k + 1, n):
                v = M[i][j] * pivot
                if not is_zero(mik) and not is_zero(M[k][j]):
                    v = v - mik * M[k][j]
                M[i][j] = ring.exquo(v, prev) if not is_zero(v) else v
        prev = pivot
    d = M[n - 1][n - 1]
    return d if sign > 0 else -d


def charpoly_berkowitz(enc: EncodedSystem) -> tuple[Any, list[Any]]:
    """``det(sI - A)`` and the numerators via sympy's ``DomainMatrix.charpoly``.

    Numerators by the matrix determinant lemma,
    ``C_i adj(sI - A) B_j = det(sI - A + B_j C_i) - det(sI - A)``.
    Only for ``E = I``.  Returns ``(den, nums)`` with ``nums[i][j]``.
    """
    from sympy.polys.matrices import DomainMatrix

    ring, n = enc.ring, enc.n
    nv = ring.nvars - 1
    R = sp.polys.rings.PolyRing([sp.Dummy(f"y{i}") for i in range(max(nv, 1))], sp.QQ)
    dom = R.to_domain()

    def to_dom(p):
        d = {}
        for exps, c in ring.terms(p):
            d[exps[1:] if nv else (0,)] = sp.QQ(c.numerator, c.denominator)
        return R.from_dict(d)

    def from_coeffs(coeffs):
        terms = {}
        deg = len(coeffs) - 1
        for k, c in enumerate(coeffs):
            for exps, v in c.items():
                key = (deg - k,) + (tuple(exps) if nv else ())
                terms[key] = Fraction(int(sp.QQ.numer(v)), int(sp.QQ.denom(v)))
        return ring.from_terms(terms)

    Ad = [[to_dom(x) for x in row] for row in enc.A]
    dA = DomainMatrix(Ad, (n, n), dom)
    den = from_coeffs(dA.charpoly())
    s = ring.gen(0)
    nums = []
    for i, crow in enumerate(enc.C):
        row = []
        for j in range(len(enc.B[0]) if enc.B else 0):
            # B_j(s) = sum_k s**k B_jk (input derivatives): one lemma per power of s
            parts: dict[int, list] = defaultdict(lambda: [ring.zero] * n)
            for r in range(n):
                for k, piece in split_s(enc.B[r][j], ring).items():
                    parts[k][r] = piece
            num = enc.D[i][j] * den
            for k, col in parts.items():
                bc = [[to_dom(col[r] * crow[c]) for c in range(n)] for r in range(n)]
                pert = from_coeffs((dA - DomainMatrix(bc, (n, n), dom)).charpoly())
                term = pert - den
                for _ in range(k):
                    term = term * s
                num = num + term
            row.append(num)
        nums.append(row)
    return den, nums


def split_s(p, ring: Ring) -> dict[int, Any]:
    """``{k: p_k}`` with ``p = sum s**k p_k`` and no ``s`` in the ``p_k``.

    Examples
    --------
    >>> R = make_ring(2)
    >>> s, a = R.gen(0), R.gen(1)
    >>> {k: R.terms(v) for k, v in split_s(s**2 * a + a + 1, R).items()} == {
    ...     0: [((0, 1), 1), ((0, 0), 1)], 2: [((0, 1), 1)]}
    True
    """
    groups: dict[int, dict] = defaultdict(dict)
    for exps, c in ring.terms(p):
        groups[exps[0]][(0,) + tuple(exps[1:])] = c
    return {k: ring.from_terms(v) for k, v in groups.items()}


# ------------------------------------------------------------- clearing, cancelling
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
