"""Multivariate polynomial rings over QQ: python-flint's ``fmpq_mpoly`` or sympy's ``PolyRing``.

First stage of the exact algebra (:mod:`bondgraph.tf._algebra`): one small
interface, :class:`Ring`, over the two arithmetics, chosen by
:func:`backend_name` (environment variable ``BONDGRAPH_TF_BACKEND``).

Examples
--------
>>> R = make_ring(2)
>>> x, y = R.gen(0), R.gen(1)
>>> sorted(R.terms(x * y + 1))
[((0, 0), 1), ((1, 1), 1)]
"""

from __future__ import annotations

import operator
import os
from fractions import Fraction
from types import ModuleType
from typing import Any, Sequence

import sympy as sp

from .errors import InvalidOptionError

_flint: ModuleType | None
try:  # python-flint is a declared dependency; keep a pure-sympy fallback anyway
    import flint as _flint
except ImportError:  # pragma: no cover - exercised only without python-flint
    _flint = None

__all__ = ["Ring", "make_ring", "backend_name"]


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
