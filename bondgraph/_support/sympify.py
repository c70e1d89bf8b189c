"""Parameter values given by the user, turned into sympy expressions and checked.

Text is never parsed: strings must be (dotted) identifiers and become positive
symbols.  Numbers must be finite and real; an exact zero is refused where an
element divides by it.  Used by :mod:`bondgraph.elements`.

Examples
--------
>>> to_expr("Rm", owner="R:Rm", what="parameter")
Rm
>>> to_expr(float("nan"), owner="R:b", what="parameter")
Traceback (most recent call last):
...
bondgraph.errors.ParameterError: R:b: parameter must be finite, got nan
"""

from __future__ import annotations

import keyword
import math
import numbers
import re
from typing import Optional, Union

import sympy

from ..errors import BondGraphError, ParameterError
from ..signals import LawVariable

__all__ = ["ParameterLike", "to_expr", "nonzero", "as_expr", "as_matrix", "parameter_symbols"]

ParameterLike = Union[None, numbers.Real, str, sympy.Expr]

_DOTTED = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*$")


def as_expr(value: object, *, what: str,
            error: type[BondGraphError] = ParameterError) -> sympy.Expr:
    """A number or sympy expression as a sympy expression; text is refused, never parsed.

    The one way the package turns a user value into an expression where an
    identifier string is not meaningful (``D`` of a transfer function, an
    expression in ``s``, a mass ratio).  ``sympify`` runs strictly, so no
    string ever reaches its parser.

    Parameters
    ----------
    value : number or sympy.Expr
    what : str
        The argument's name, for the message.
    error : BondGraphError subclass, optional
        The class raised (the caller's own error family).

    Examples
    --------
    >>> as_expr(0.5, what="mass_ratio")
    0.500000000000000
    >>> as_expr("__import__('os')", what="mass_ratio")
    Traceback (most recent call last):
    ...
    bondgraph.errors.ParameterError: mass_ratio: expected a number or a sympy expression, got the string "__import__('os')" (text is never parsed)
    """
    if isinstance(value, str):
        raise error(f"{what}: expected a number or a sympy expression, got the string "
                    f"{value!r} (text is never parsed)")
    if isinstance(value, bool):
        raise error(f"{what}: expected a number or a sympy expression, got a bool")
    try:
        out = sympy.sympify(value, strict=True)
    except (sympy.SympifyError, TypeError, ValueError):
        raise error(f"{what}: expected a number or a sympy expression, got "
                    f"{type(value).__name__}") from None
    if not isinstance(out, sympy.Expr):
        raise error(f"{what}: expected a number or a sympy expression, got "
                    f"{type(out).__name__}")
    return out


def _has_text(obj: object) -> bool:
    if isinstance(obj, (str, bytes, bytearray)):
        return True
    return isinstance(obj, (list, tuple)) and any(_has_text(x) for x in obj)


def as_matrix(value: object, *, what: str,
              error: type[BondGraphError] = ParameterError) -> sympy.ImmutableMatrix:
    """A sympy matrix, a nested list or a numpy array as an immutable sympy matrix.

    Entries are numbers or sympy expressions; a string entry is refused (it
    would otherwise be parsed by sympy).

    Examples
    --------
    >>> as_matrix([[1, 2]], what="C")
    Matrix([[1, 2]])
    >>> as_matrix([["1"]], what="D")
    Traceback (most recent call last):
    ...
    bondgraph.errors.ParameterError: D: expected a matrix of numbers or sympy expressions; an entry is a string or bytes (text is never parsed)
    """
    if isinstance(value, sympy.MatrixBase):
        return sympy.ImmutableMatrix(value)
    obj = value.tolist() if hasattr(value, "tolist") and not isinstance(value, sympy.Basic) else value
    if _has_text(obj):
        raise error(f"{what}: expected a matrix of numbers or sympy expressions; an entry is a "
                    "string or bytes (text is never parsed)")
    try:
        return sympy.ImmutableMatrix(obj)
    except (TypeError, ValueError, sympy.SympifyError) as exc:
        raise error(f"{what}: expected a matrix (sympy Matrix, nested list or numpy array), "
                    f"got {type(value).__name__}: {exc}") from None


def to_expr(value: ParameterLike, *, owner: str, what: str,
            law: bool = False) -> Optional[sympy.Expr]:
    """Turn a user-supplied parameter into a sympy expression, never parsing text.

    Strings must be (dotted) identifiers and become positive symbols.  Law
    variables (``bg.p``, ``bg.q``, ``bg.e``, ``bg.f``) are accepted only in a
    law (``law=True``): in a parameter they would silently become a parameter.
    """
    if value is None:
        return None
    if isinstance(value, bool):
        raise ParameterError(f"{owner}: {what} must be a number, symbol or expression, got a bool")
    if isinstance(value, sympy.Basic):
        if not isinstance(value, sympy.Expr):
            raise ParameterError(f"{owner}: {what} must be a sympy expression, got {type(value).__name__}")
        if not law:
            own = sorted(str(s) for s in value.free_symbols if isinstance(s, LawVariable))
            if own:
                raise ParameterError(
                    f"{owner}: {what} {value} uses the law variable(s) {', '.join(own)}; "
                    "a law in the element's own variable is given with law= (for example "
                    "bg.R('d', law=c*bg.f*abs(bg.f))), a parameter is a number, symbol or "
                    "expression of parameters and signals"
                )
        _check_numbers(value, owner=owner, what=what)
        return value
    if isinstance(value, numbers.Integral):
        return sympy.Integer(int(value))
    if isinstance(value, numbers.Real):
        fval = float(value)
        if fval != fval or fval in (float("inf"), float("-inf")):
            raise ParameterError(f"{owner}: {what} must be finite, got {value!r}")
        return sympy.Float(fval)
    if isinstance(value, str):
        if not _DOTTED.fullmatch(value) or keyword.iskeyword(value):
            raise ParameterError(
                f"{owner}: {what} {value!r} is not a parameter name; give an identifier "
                "such as 'Rm', a number, or a sympy expression (text is never parsed)"
            )
        return sympy.Symbol(value, positive=True)
    raise ParameterError(
        f"{owner}: {what} must be a number, an identifier string or a sympy expression; "
        f"got {type(value).__name__}"
    )


def _check_numbers(value: sympy.Expr, *, owner: str, what: str) -> None:
    """Refuse nan, infinities, complex numbers and overflowing floats in an expression."""
    bad = value.has(sympy.nan, sympy.oo, -sympy.oo, sympy.zoo, sympy.I)
    if not bad:
        for atom in value.atoms(sympy.Number):
            if not math.isfinite(float(atom)):
                bad = True
    if bad:
        text = sympy.sstr(value.evalf(4) if value.is_number and not value.has(sympy.I) else value)
        text = text if len(text) <= 60 else text[:57] + "..."
        raise ParameterError(
            f"{owner}: {what} {text} is not a finite real value (nan, infinity, beyond the float range or a complex "
            "number); parameters are finite reals (negative values are allowed for active "
            "elements)"
        )


def nonzero(value: Optional[sympy.Expr], *, owner: str, what: str) -> Optional[sympy.Expr]:
    """Refuse an exact zero where the element divides by the value."""
    if value is not None and value.is_zero:
        raise ParameterError(
            f"{owner}: {what} is 0, but the element divides by it; remove the element or "
            "join its bonds with a junction instead"
        )
    return value


def parameter_symbols(element: object) -> set:
    """The parameter symbols an element's fields hold (not signals, law variables or time).

    Examples
    --------
    >>> import bondgraph as bg
    >>> sorted(s.name for s in parameter_symbols(bg.R("d", law=sympy.Symbol("c") * bg.f**3)))
    ['c']
    """
    import dataclasses

    from ..signals import Signal
    from ..signals import t as time

    out: set = set()
    for fld in dataclasses.fields(element):  # type: ignore[arg-type]
        val = getattr(element, fld.name)
        if isinstance(val, sympy.Basic):
            out |= {s for s in val.free_symbols
                    if not isinstance(s, (Signal, LawVariable)) and s != time}
    return out

