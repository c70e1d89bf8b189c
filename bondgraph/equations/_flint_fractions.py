"""Rational functions of the parameters in python-flint, handed back in sympy's normal form.

The exact loop solves (:mod:`bondgraph.equations.fraction_free`) and the
compaction of loop solutions (:func:`bondgraph.equations.loops.compact_linear`)
add and multiply fractions of polynomials; every sum needs a gcd.  sympy's
sparse polynomials compute it with the heuristic gcd in pure Python, which
took 94 % of the derivation of some random graphs with algebraic loops (tens
of seconds).  Here numerators and denominators are python-flint ``fmpq_mpoly``
(the ring of :func:`bondgraph.tf._rings.make_ring`), reduced by flint's gcd,
and each result leaves as the element of sympy's field
(:class:`sympy.polys.fields.FracField`) that sympy itself would have built:
the same numerator and denominator, scaled and signed by the rule of
``PolyElement.cancel`` (so ``as_expr`` gives the identical expression).

Private: used by :mod:`bondgraph.equations.fraction_free`.

Examples
--------
>>> import sympy
>>> from sympy.polys.fields import field
>>> a, b = sympy.symbols("a b")
>>> K, *_ = field([a, b], sympy.QQ)
>>> F = Fractions(K)
>>> n, d = F.fraction(1/(2*a) - b/(a*b + a))
>>> F.to_field(n, d) == K.from_expr(1/(2*a) - b/(a*b + a))
True
"""

from __future__ import annotations

import math
from functools import reduce
from typing import Any

import sympy

__all__ = ["Fractions"]


class Fractions:
    """Fractions ``(numerator, denominator)`` of flint polynomials in the generators of ``K``.

    Parameters
    ----------
    K : sympy.polys.fields.FracField
        The field the results are handed back in (its generators, in order,
        are the flint ring's variables; its monomial order must be ``lex``).
    """

    def __init__(self, K) -> None:
        import flint

        self.K = K
        self.ring = K.ring
        self.gens = set(self.ring.symbols)
        # the variables x0, x1, ... in lex order, as the transfer functions' flint ring has them
        names = tuple(f"x{i}" for i in range(max(len(self.ring.symbols), 1)))
        self.ctx = flint.fmpq_mpoly_ctx.get(names, "lex")
        self.one = self.ctx.constant(1)
        self.zero = self.ctx.from_dict({})
        self._fmpq = flint.fmpq

    # ------------------------------------------------------------ conversions
    def from_poly(self, p) -> Any:
        """A sympy ``PolyElement`` of ``K.ring`` as a flint polynomial."""
        fmpq = self._fmpq
        if len(self.ring.symbols) == 0:     # pragma: no cover - FracField needs a generator
            raise ValueError("no generators")
        return self.ctx.from_dict({m: fmpq(int(c.numerator), int(c.denominator))
                                   for m, c in p.items()})

    def to_poly(self, p) -> Any:
        """A flint polynomial as a sympy ``PolyElement`` of ``K.ring``."""
        QQ = self.ring.domain
        return self.ring.from_dict({tuple(int(e) for e in m): QQ(int(c.p), int(c.q))
                                    for m, c in zip(p.monoms(), p.coeffs())})

    def poly(self, expr: sympy.Expr) -> Any:
        """A polynomial expression in the generators (no gcd: built in the ring)."""
        return self.from_poly(self.ring.from_expr(expr))

    # ------------------------------------------------------------ arithmetic
    @staticmethod
    def reduce(n, d) -> tuple:
        """``n/d`` in lowest terms (``d`` nonzero)."""
        if n.is_zero():
            return n, d / d
        g = n.gcd(d)
        if not g.is_one():
            n, d = n / g, d / g
        return n, d

    def new(self, n, d) -> tuple:
        if d.is_zero():
            raise ZeroDivisionError("zero denominator")
        return self.reduce(n, d)

    def add(self, x: tuple, y: tuple) -> tuple:
        (a, b), (c, d) = x, y
        if a.is_zero():
            return y
        if c.is_zero():
            return x
        if b == d:
            return self.reduce(a + c, b)
        g = b.gcd(d)
        b1, d1 = b / g, d / g
        return self.reduce(a * d1 + c * b1, b1 * d)

    def mul(self, x: tuple, y: tuple) -> tuple:
        (a, b), (c, d) = x, y
        if a.is_zero() or c.is_zero():
            return self.zero, self.one
        g1, g2 = a.gcd(d), c.gcd(b)
        return (a / g1) * (c / g2), (b / g2) * (d / g1)

    def power(self, x: tuple, k: int) -> tuple:
        n, d = x
        if k < 0:
            if n.is_zero():
                raise ZeroDivisionError("zero to a negative power")
            n, d, k = d, n, -k
        return n ** k, d ** k

    # ------------------------------------------------------------ sympy expressions
    def fraction(self, expr: sympy.Expr) -> tuple:
        """``expr`` (a rational function of the generators) as a reduced flint fraction.

        A polynomial part is built in the ring (no gcd); terms over the same
        denominator are added there, one reduction per denominator.  Anything
        else goes through sympy's own conversion (``K.from_expr``), whose
        errors (``CoercionFailed``, ``ValueError``...) pass through.
        """
        gens = self.gens

        def polynomial(e: sympy.Expr) -> bool:      # linear in the size of e (is_polynomial is not)
            if e.is_Symbol:
                return e in gens
            if e.is_Rational:
                return True
            if e.is_Add or e.is_Mul:
                return all(polynomial(a) for a in e.args)
            if e.is_Pow:
                return bool(e.exp.is_Integer and e.exp >= 0 and polynomial(e.base))
            return False

        if expr.is_Add:
            over: dict = {}
            rest: list = []
            for arg in expr.args:
                num, den = sympy.fraction(arg, exact=True)
                if polynomial(num) and polynomial(den):
                    over.setdefault(den, []).append(num)
                else:
                    rest.append(arg)
            total = (self.zero, self.one)
            for den, nums in over.items():
                top = self.poly(sympy.Add(*nums))
                total = self.add(total, (top, self.one) if den == 1 else
                                 self.new(top, self.poly(den)))
            for arg in rest:
                total = self.add(total, self.fraction(arg))
            return total
        if expr.is_Mul:
            num, den = sympy.fraction(expr, exact=True)
            if den != 1 and polynomial(num) and polynomial(den):
                return self.new(self.poly(num), self.poly(den))
            out = (self.one, self.one)
            for arg in expr.args:
                out = self.mul(out, self.fraction(arg))
            return out
        if expr.is_Pow and expr.exp.is_Integer:
            return self.power(self.fraction(expr.base), int(expr.exp))
        if polynomial(expr):
            return self.poly(expr), self.one
        f = self.K.from_expr(expr)
        return self.from_poly(f.numer), self.from_poly(f.denom)

    def to_field(self, n, d) -> Any:
        """The reduced fraction ``n/d`` as the element of ``K`` sympy would build.

        sympy's ``PolyElement.cancel`` over QQ clears the denominators of the
        numerator (factor ``cf``) and of the denominator (``cg``), divides
        both by their gcd over ZZ (for coprime polynomials, the gcd of their
        integer contents), multiplies the numerator by ``cg`` and the
        denominator by ``cf`` (each divided by ``gcd(cf, cg)``), and makes the
        denominator's leading coefficient positive.
        """
        K = self.K
        if n.is_zero():
            return K.zero
        cf = reduce(math.lcm, (int(c.q) for c in n.coeffs()), 1)
        cg = reduce(math.lcm, (int(c.q) for c in d.coeffs()), 1)
        F = [int(c.p) * (cf // int(c.q)) for c in n.coeffs()]
        G = [int(c.p) * (cg // int(c.q)) for c in d.coeffs()]
        h = math.gcd(math.gcd(*F), math.gcd(*G))
        gam = math.gcd(cf, cg)
        a, b = cg // gam, cf // gam
        QQ = self.ring.domain
        num = self.ring.from_dict({tuple(int(e) for e in m): QQ(f // h * a)
                                   for m, f in zip(n.monoms(), F)})
        den = self.ring.from_dict({tuple(int(e) for e in m): QQ(g // h * b)
                                   for m, g in zip(d.monoms(), G)})
        if den.LC < 0:
            num, den = -num, -den
        return K.raw_new(num, den)
