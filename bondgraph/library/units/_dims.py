"""Dimensions as exponent vectors over the SI base dimensions, from sympy.physics.units.

sympy gives the units and their dimensions (``SI.get_dimensional_expr``,
``dimsys_SI.get_dimensional_dependencies``, ``convert_to``); this module
only walks a constitutive relation whose symbols stand for quantities of
known dimension, the way ``SI._collect_factor_and_dimension`` walks an
expression of ``Quantity`` objects.

Examples
--------
>>> import sympy.physics.units as u
>>> unit_dims(u.newton / u.meter) == unit_dims(u.kilogram / u.second**2)
True
>>> text(unit_dims(u.volt))
'volt'
"""

from __future__ import annotations

import functools

from typing import Mapping, Optional

import sympy
import sympy.physics.units as u
from sympy.physics.units import Dimension
from sympy.physics.units.prefixes import Prefix
from sympy.physics.units.systems.si import SI, dimsys_SI

__all__ = ["Dim", "ZERO", "unit_dims", "text", "Mismatch", "Unknown", "dims_of", "si_value", "BadQuantity",
           "BASE_UNITS", "NAMED"]

#: the SI base dimensions, in order, and a probe slot (last) used to find exponents
_BASE = ("mass", "length", "time", "current", "temperature", "amount_of_substance",
         "luminous_intensity")
BASE_UNITS = (u.kilogram, u.meter, u.second, u.ampere, u.kelvin, u.mole, u.candela)

Dim = tuple   # of sympy Rationals, len(_BASE) + 1
ZERO: Dim = (sympy.Integer(0),) * (len(_BASE) + 1)

#: named units tried when printing a dimension (first match wins)
NAMED = [("volt", u.volt), ("ampere", u.ampere), ("ohm", u.ohm), ("henry", u.henry),
          ("farad", u.farad), ("coulomb", u.coulomb), ("newton", u.newton), ("pascal", u.pascal),
          ("watt", u.watt), ("joule", u.joule), ("kelvin", u.kelvin), ("watt/kelvin", u.watt / u.kelvin),
          ("joule/kelvin", u.joule / u.kelvin), ("joule/mole", u.joule / u.mole),
          ("mole/second", u.mole / u.second), ("mole", u.mole), ("kelvin/watt", u.kelvin / u.watt),
          ("joule/kelvin", u.joule / u.kelvin), ("newton/meter", u.newton / u.meter),
          ("newton*second/meter", u.newton * u.second / u.meter), ("meter/second", u.meter / u.second),
          ("meter", u.meter), ("kilogram", u.kilogram), ("kilogram*meter**2", u.kilogram * u.meter**2),
          ("meter**3/second", u.meter**3 / u.second), ("meter**3", u.meter**3),
          ("pascal*second/meter**3", u.pascal * u.second / u.meter**3),
          ("meter**3/pascal", u.meter**3 / u.pascal), ("second", u.second), ("1/second", 1 / u.second)]


class Mismatch(Exception):
    """Terms of different dimensions added, or a dimensional function argument."""


class Unknown(Exception):
    """A symbol of unknown dimension: the relation cannot be checked."""


@functools.lru_cache(maxsize=1024)
def unit_dims(unit: sympy.Expr) -> Dim:
    """The dimension vector of a sympy.physics.units expression."""
    deps = dimsys_SI.get_dimensional_dependencies(Dimension(SI.get_dimensional_expr(unit)))
    by_name = {str(d.name): sympy.nsimplify(p) for d, p in deps.items()}
    return tuple(by_name.get(b, sympy.Integer(0)) for b in _BASE) + (sympy.Integer(0),)


@functools.lru_cache(maxsize=1024)
def text(d: Dim) -> str:
    """A dimension as a named unit when one matches, else as SI base units."""
    if all(x == 0 for x in d[:-1]):
        return "1 (dimensionless)"
    for name, unit in NAMED:
        if unit_dims(unit) == d:
            return name
    return str(sympy.Mul(*[b**p for b, p in zip(BASE_UNITS, d)]))


class BadQuantity(ValueError):
    """A unit-carrying value that is not a finite real number times a unit (the caller
    names the parameter)."""


def _term(term: sympy.Expr) -> tuple[sympy.Expr, sympy.Expr]:
    """``(number, unit)`` of one term ``c * unit``: ``c`` a finite real number, ``unit`` a
    product of powers of quantities."""
    coeff, unit = term.as_coeff_Mul()
    factors = []
    for f in sympy.Mul.make_args(unit):
        base = f.base if isinstance(f, sympy.Pow) and f.exp.is_Rational else f
        if isinstance(base, (u.Quantity, Prefix)):
            factors.append(f)
        else:
            coeff = coeff * f
    if coeff.free_symbols:
        raise BadQuantity(f"its coefficient {coeff} is symbolic; a value with units is a "
                          "number times a unit (give a symbol its number with the others)")
    if not factors:
        raise BadQuantity(f"the term {term} has no unit")
    if not (coeff.is_number and coeff.is_extended_real and coeff.is_finite):
        raise BadQuantity(f"its coefficient {coeff} is not a finite real number")
    return coeff, sympy.Mul(*factors)


def si_value(value: sympy.Expr) -> tuple[float, Dim, str]:
    """``(SI number, dimension, unit text)`` of a value carrying units, e.g. ``2*u.newton/u.mm``.

    A sum is accepted when its terms have one dimension (``1*u.m + 20*u.cm``).

    Raises
    ------
    BadQuantity
        A symbolic, complex or infinite coefficient, or terms of different
        dimensions (``500*u.gram + 1*u.meter``), naming both units.

    Examples
    --------
    >>> si_value(2 * u.newton / u.millimeter)[::2]
    (2000.0, 'newton/millimeter')
    >>> si_value(1 * u.meter + 20 * u.centimeter)[::2]
    (1.2, 'centimeter')
    >>> si_value(500 * u.gram + 1 * u.meter)
    Traceback (most recent call last):
    ...
    bondgraph.library.units._dims.BadQuantity: it adds 500*gram (mass) and meter (length), which have different units
    """
    expr = sympy.sympify(value, strict=True)
    terms = [_term(t) for t in sympy.Add.make_args(expr)]
    dims = [unit_dims(unit) for _, unit in terms]
    for (c, unit), d in zip(terms[1:], dims[1:]):
        if d != dims[0]:
            c0, u0 = terms[0]
            raise BadQuantity(f"it adds {c0 * u0} ({_dimension_name(u0)}) and {c * unit} "
                              f"({_dimension_name(unit)}), which have different units")
    total = sum((c * _si_factor(unit) for c, unit in terms), sympy.Integer(0))
    try:
        number = float(total)
    except (TypeError, ValueError, OverflowError):
        raise BadQuantity(f"its value {total} is not a finite real number") from None
    if number != number or number in (float("inf"), float("-inf")):
        raise BadQuantity(f"its value {total} is not finite")
    return number, dims[0], str(terms[0][1])


def _dimension_name(unit: sympy.Expr) -> str:
    try:
        return str(SI.get_dimensional_expr(unit))
    except Exception:  # pragma: no cover - a unit sympy cannot name
        return str(unit)


@functools.lru_cache(maxsize=1024)
def _si_factor(unit: sympy.Expr) -> sympy.Expr:
    """The number a unit is in SI base units (``convert_to`` is slow: once per unit)."""
    base = u.convert_to(unit, list(BASE_UNITS) + [u.radian])
    number = base.xreplace({q: sympy.Integer(1) for q in base.atoms(u.Quantity)})
    return number.xreplace({p: p.scale_factor for p in number.atoms(Prefix)})


def _add(a: Dim, b: Dim) -> Dim:
    return tuple(x + y for x, y in zip(a, b))


def _scale(a: Dim, k) -> Dim:
    return tuple(x * k for x in a)


_DIMENSIONLESS_ARG = (sympy.exp, sympy.log, sympy.sin, sympy.cos, sympy.tan, sympy.sinh,
                      sympy.cosh, sympy.tanh, sympy.atan, sympy.asin, sympy.acos)


def dims_of(expr: sympy.Expr, known: Mapping[sympy.Symbol, Optional[Dim]]) -> Dim:
    """The dimension of ``expr`` whose symbols have the dimensions ``known``.

    Raises
    ------
    Unknown
        A symbol not in ``known`` (or mapped to None), or a function not understood.
    Mismatch
        Two added terms differ, or ``exp``/``log``/... of a dimensional argument.
    """
    if expr.is_Number or expr.is_NumberSymbol:
        return ZERO
    if isinstance(expr, u.Quantity):
        return unit_dims(expr)
    if expr.is_Symbol:
        d = known.get(expr)
        if d is None:
            raise Unknown(str(expr))
        return d
    if expr.is_Add:
        dims = [dims_of(a, known) for a in expr.args]
        for d in dims[1:]:
            if d != dims[0]:
                raise Mismatch(f"{text(dims[0])} + {text(d)} in {expr}")
        return dims[0]
    if expr.is_Mul:
        out = ZERO
        for a in expr.args:
            out = _add(out, dims_of(a, known))
        return out
    if expr.is_Pow:
        base, ex = expr.args
        db = dims_of(base, known)
        if db == ZERO:
            return ZERO
        if not ex.is_number:
            raise Mismatch(f"{text(db)} raised to the symbolic power {ex} in {expr}")
        return _scale(db, sympy.nsimplify(ex))
    if isinstance(expr, sympy.sign):
        dims_of(expr.args[0], known)
        return ZERO
    if isinstance(expr, sympy.Abs):
        return dims_of(expr.args[0], known)
    if isinstance(expr, _DIMENSIONLESS_ARG):
        d = dims_of(expr.args[0], known)
        if d[:-1] != ZERO[:-1]:
            raise Mismatch(f"{type(expr).__name__} of {text(d)} in {expr}")
        return ZERO
    if isinstance(expr, (sympy.Max, sympy.Min)):
        dims = [dims_of(a, known) for a in expr.args]
        if any(d != dims[0] for d in dims):
            raise Mismatch(f"{expr}: arguments of different dimensions")
        return dims[0]
    raise Unknown(f"{type(expr).__name__}")
