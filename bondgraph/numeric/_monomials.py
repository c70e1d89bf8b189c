"""Numeric compilation of many matrix entries without printing code (private).

The entries of a bond-graph plant are overwhelmingly products of integer
powers of parameters with a rational coefficient (``-1/m_k``, ``b_k/m_k``,
``1/C_k``, ``n*r``) or short sums of them.  :func:`compile_entries` sorts
each entry into one of three classes:

* a **monomial** ``c * p_i1 * p_i2 ... / (p_j1 * p_j2 ...)`` (integer
  exponents, a power ``p**3`` being the factor three times): kept as a row
  of parameter indices for the numerator and one for the denominator (padded
  with a column of ones) and a float coefficient;
* a **sum of monomials**: its terms are monomials of the same table, added
  up per entry (``numpy.add.reduceat``);
* a **general** expression (anything else: ``sqrt``, ``exp``, a product of
  sums, a user function): compiled by ``sympy.lambdify`` with
  common-subexpression elimination, as before, each distinct expression once.

:class:`CompiledEntries` evaluates all of them for one parameter set or a
batch with a few vectorised numpy operations: multiplying and dividing
gathered columns follows IEEE arithmetic exactly as the lambdified code does
(a zero divisor gives ``inf``/``nan``, signs are those of the factors), with
at most a few units in the last place of difference from the order of the
operations.  It pickles as plain arrays plus the general part (a
:class:`~bondgraph.numeric._compile.CompiledFunction`, recompiled lazily).

Examples
--------
>>> import numpy as np, sympy
>>> m, b, k = sympy.symbols("m b k", positive=True)
>>> ce = compile_entries([m, b, k], [-b/m, 1/m, k + 2*b, sympy.sqrt(k)])
>>> ce.counts
{'monomial': 2, 'sum': 1, 'general': 1}
>>> ce.evaluate([np.float64(2.0), np.float64(3.0), np.float64(4.0)], None)
array([-1.5,  0.5, 10. ,  2. ])
>>> ce.evaluate([np.array([2.0, 4.0]), np.array([3.0, 3.0]), np.array([4.0, 9.0])], 2)
array([[-1.5 ,  0.5 , 10.  ,  2.  ],
       [-0.75,  0.25, 15.  ,  3.  ]])
"""

from __future__ import annotations

from typing import Optional, Sequence

import numpy as np
import sympy

from ._compile import CompiledFunction, placeholders

__all__ = ["compile_entries", "CompiledEntries", "MAX_FACTORS"]

#: a monomial with more factors than this (in numerator or denominator, powers
#: counted with their multiplicity) is compiled as a general expression
MAX_FACTORS = 16

_Mono = tuple  # (coefficient: float, numerator indices: tuple, denominator indices: tuple)


def _number(ex: sympy.Basic) -> Optional[float]:
    """A real rational or float coefficient as a float, else None."""
    if isinstance(ex, sympy.Rational):
        return ex.p / ex.q            # correctly rounded (sympy's float() goes through mpmath)
    if isinstance(ex, sympy.Float):
        return float(ex)
    return None


_MISSING = object()


def _factor_uncached(ex: sympy.Basic, index: dict):
    """What ``index`` remembers for ``ex`` (see :func:`_monomial`), found the first time."""
    if ex.is_Number:
        return _number(ex)
    if ex.is_Pow and ex.base.is_Symbol and isinstance(ex.exp, sympy.Integer):
        i = index.get(ex.base)
        n = int(ex.exp)
        if type(i) is not int or n == 0 or abs(n) > MAX_FACTORS:
            return None
        return ((i,) * n, ()) if n > 0 else ((), (i,) * -n)
    return None                       # a symbol that is not a parameter, or anything else


def _monomial(ex: sympy.Basic, index: dict) -> Optional[_Mono]:
    """``ex`` as a monomial ``(coef, num, den)``, or None.

    ``index`` maps each parameter to its column (an int) and remembers every
    factor already met: a float (a number: the coefficient), a tuple
    ``(numerator indices, denominator indices)`` (a power of a parameter), or
    None (anything else), so that ``1/m_k`` is analysed once per model.
    """
    coef, num, den = None, [], []
    for arg in (ex.args if ex.is_Mul else (ex,)):
        got = index.get(arg, _MISSING)
        if got is _MISSING:
            got = index[arg] = _factor_uncached(arg, index)
        kind = type(got)
        if kind is int:
            num.append(got)
        elif kind is tuple:
            num.extend(got[0])
            den.extend(got[1])
        elif kind is float and coef is None:
            coef = got
        else:
            return None
    if len(num) > MAX_FACTORS or len(den) > MAX_FACTORS:
        return None
    return (1.0 if coef is None else coef, tuple(num), tuple(den))


def classify(ex: sympy.Basic, index: dict):
    """``("monomial", mono)``, ``("sum", [mono, ...])`` or ``("general", None)``.

    Examples
    --------
    >>> x, y = sympy.symbols("x y")
    >>> classify(-3*x**2/y, {x: 0, y: 1})
    ('monomial', (-3.0, (0, 0), (1,)))
    >>> classify(x + 2*y, {x: 0, y: 1})[0], classify(sympy.exp(x), {x: 0})[0]
    ('sum', 'general')
    """
    mono = _monomial(ex, index)
    if mono is not None:
        return "monomial", mono
    if ex.is_Add:
        terms = []
        for arg in ex.args:
            mono = _monomial(arg, index)
            if mono is None:
                return "general", None
            terms.append(mono)
        return "sum", terms
    return "general", None


class _MonomialTable:
    """Monomials ``coef * prod(P[num]) / prod(P[den])`` evaluated together.

    ``P`` is the parameter vector (or ``(size, k)`` stack) with a column of
    ones appended (index ``k``), which pads the rows of ``num`` and ``den``.
    """

    __slots__ = ("coef", "num", "den")

    def __init__(self, monos: Sequence[_Mono], ones: int) -> None:
        fn = max((len(m[1]) for m in monos), default=0)
        fd = max((len(m[2]) for m in monos), default=0)
        self.coef = np.array([m[0] for m in monos], dtype=float)
        pad = (ones,) * max(fn, fd)
        self.num = np.array([m[1] + pad[:fn - len(m[1])] for m in monos],
                            dtype=np.intp).reshape(len(monos), fn)
        self.den = np.array([m[2] + pad[:fd - len(m[2])] for m in monos],
                            dtype=np.intp).reshape(len(monos), fd)

    def evaluate(self, P: np.ndarray) -> np.ndarray:
        """Values ``(M,)`` or ``(size, M)`` for ``P`` of shape ``(k + 1,)`` or ``(size, k + 1)``."""
        out = np.broadcast_to(self.coef, P.shape[:-1] + self.coef.shape).copy()
        for f in range(self.num.shape[1]):
            out *= P[..., self.num[:, f]]
        if self.den.shape[1]:
            den = P[..., self.den[:, 0]]
            for f in range(1, self.den.shape[1]):
                den = den * P[..., self.den[:, f]]
            out /= den
        return out


class CompiledEntries:
    """Values of many expressions in ``k`` parameters, evaluated together.

    Built by :func:`compile_entries`.  :meth:`evaluate` takes the parameter
    columns (numpy scalars for one set, arrays of length ``size`` for a
    batch) and gives ``(n,)`` or ``(size, n)``.

    Attributes
    ----------
    counts : dict
        How many expressions were compiled as ``monomial``, ``sum`` and
        ``general`` (duplicates counted once each time they occur).
    general : CompiledFunction or None
        The lambdified part (distinct general expressions only).
    """

    __slots__ = ("n", "k", "counts", "_mono", "_mono_pos", "_terms", "_sum_pos", "_sum_starts",
                 "general", "_gen_pos", "_gen_take")

    def __init__(self, n: int, k: int, counts: dict, monos: list, mono_pos: list,
                 terms: list, sum_pos: list, sum_starts: list,
                 general: Optional[CompiledFunction], gen_pos: list, gen_take: list) -> None:
        self.n, self.k, self.counts = n, k, counts
        self._mono = _MonomialTable(monos, k) if monos else None
        self._mono_pos = np.array(mono_pos, dtype=np.intp)
        self._terms = _MonomialTable(terms, k) if terms else None
        self._sum_pos = np.array(sum_pos, dtype=np.intp)
        self._sum_starts = np.array(sum_starts, dtype=np.intp)
        self.general = general
        self._gen_pos = np.array(gen_pos, dtype=np.intp)
        self._gen_take = np.array(gen_take, dtype=np.intp)

    def __repr__(self) -> str:
        parts = ", ".join(f"{v} {k}" for k, v in self.counts.items())
        gen = "" if self.general is None else f"; general part {self.general!r}"
        return f"<CompiledEntries {self.n} values: {parts}{gen}>"

    def evaluate(self, columns: Sequence, size: Optional[int]) -> np.ndarray:
        """The values ``(n,)`` (``size`` None, numpy scalar columns) or ``(size, n)``."""
        lead = () if size is None else (size,)
        out = np.empty(lead + (self.n,))
        if self._mono is not None or self._terms is not None:
            P = np.empty(lead + (self.k + 1,))
            for j, col in enumerate(columns):
                P[..., j] = col
            P[..., self.k] = 1.0
            if self._mono is not None:
                out[..., self._mono_pos] = self._mono.evaluate(P)
            if self._terms is not None:
                out[..., self._sum_pos] = np.add.reduceat(self._terms.evaluate(P),
                                                          self._sum_starts, axis=-1)
        if self.general is not None:
            vals = self.general(*columns)
            if size is None:
                out[self._gen_pos] = np.array(vals, dtype=float)[self._gen_take]
            else:
                stack = np.empty((len(vals), size))
                for r, v in enumerate(vals):
                    stack[r] = v
                out[:, self._gen_pos] = stack[self._gen_take].T
        return out


def compile_entries(params: Sequence[sympy.Symbol], exprs: Sequence[sympy.Expr]) -> CompiledEntries:
    """Compile ``exprs`` (functions of ``params``) into a :class:`CompiledEntries`.

    Parameters
    ----------
    params : sequence of sympy.Symbol
        The parameters, in the order of the columns given to
        :meth:`CompiledEntries.evaluate`.
    exprs : sequence of sympy.Expr
        The expressions.  Monomials and sums of monomials in ``params``
        (integer exponents, rational or float coefficients) are evaluated by
        numpy gathers and products; every other distinct expression is
        lambdified once (``sympy.lambdify`` with CSE).

    Returns
    -------
    CompiledEntries

    Examples
    --------
    >>> x, y = sympy.symbols("x y")
    >>> ce = compile_entries([x, y], [x*y, x*y, x/y - 1, sympy.sin(x), sympy.sin(x)])
    >>> ce.counts, len(ce.general._exprs)
    ({'monomial': 2, 'sum': 1, 'general': 2}, 1)
    """
    index: dict = {p: i for i, p in enumerate(params)}     # and the factors seen (see _monomial)
    seen: dict = {}
    monos: list = []
    terms: list = []
    mono_pos: list[int] = []
    sum_pos: list[int] = []
    sum_starts: list[int] = []
    general: list = []
    gen_first: dict = {}
    gen_pos, gen_take = [], []
    counts = {"monomial": 0, "sum": 0, "general": 0}
    for pos, ex in enumerate(exprs):
        got = seen.get(ex)
        if got is None:
            got = seen[ex] = classify(ex, index)
        kind, data = got
        counts[kind] += 1
        if kind == "monomial":
            mono_pos.append(pos)
            monos.append(data)
        elif kind == "sum":
            sum_pos.append(pos)
            sum_starts.append(len(terms))
            terms.extend(data)
        else:
            slot = gen_first.get(ex)
            if slot is None:
                slot = gen_first[ex] = len(general)
                general.append(ex)
            gen_pos.append(pos)
            gen_take.append(slot)
    fn = None
    if general:
        dummies = placeholders("p", len(params))
        swap = dict(zip(params, dummies))
        fn = CompiledFunction(dummies, [ex.xreplace(swap) for ex in general])
    return CompiledEntries(len(exprs), len(params), counts, monos, mono_pos, terms, sum_pos,
                           sum_starts, fn, gen_pos, gen_take)
