"""Parameter values checked by the element that owns them, whichever path they take.

An element states what its parameters must be (:meth:`Element.value_rules`):
a mass, a compliance and an inertance positive, a resistance not negative, a
species' ``K`` and the temperature of its law positive.  The same rule is
checked

* at construction, when the parameter is a number (``bg.I("m", -2)``,
  ``Ce("A", K=-2)``): a :class:`~bondgraph.errors.ParameterError`;
* at every numeric evaluation, when the parameter is a symbol (or an
  expression of symbols) given a number later: ``plant()``, ``batch()``,
  ``simulate``, equilibria, ``subs`` of a symbolic form, code-generation
  defaults: a :class:`~bondgraph.errors.ParameterValueError` naming the
  element, the parameter and the value.

An element that is active on purpose (a negative resistance modelling a
tunnel diode's slope, an amplifier) opts out with ``active=True``
(``bg.R("Rn", -1, active=True)``); its rules are then not checked.

Examples
--------
>>> import bondgraph as bg
>>> bg.I("m", -2)
Traceback (most recent call last):
...
bondgraph.errors.ParameterError: I:m: its mass (inertance) -2 must be positive; pass active=True for an element that is negative on purpose
>>> bg.R("Rn", -1, active=True).parameter
-1
>>> check_values([bg.R("b", "b")], {"b": -0.5})
Traceback (most recent call last):
...
bondgraph.errors.ParameterValueError: R:b: its resistance b = -0.5 must not be negative; pass active=True for an element that is negative on purpose
"""

from __future__ import annotations

from typing import Any, Iterable, Mapping, NamedTuple, Optional

import numpy as np
import sympy

from ..errors import ParameterError, ParameterValueError

__all__ = ["ValueRule", "rule", "check_numbers", "check_values", "check_model_values"]

#: relation -> (the test on a float array, how the message says it)
_RELATIONS = {
    "positive": (lambda x: x > 0, "must be positive"),
    "nonnegative": (lambda x: x >= 0, "must not be negative"),
    "fraction": (lambda x: (x > 0) & (x <= 1), "must be in (0, 1]"),
}


class ValueRule(NamedTuple):
    """What one parameter of an element must be.

    ``expr`` is the parameter as the element holds it (a number, a symbol or
    an expression of symbols), ``what`` its meaning for messages (``'mass
    (inertance)'``), ``relation`` one of ``'positive'``, ``'nonnegative'``
    and ``'fraction'`` (in (0, 1]); ``opt_out`` whether ``active=True``
    lifts it.
    """

    expr: sympy.Expr
    what: str
    relation: str
    opt_out: bool = True


def rule(expr: Any, what: str, relation: str = "positive", *, opt_out: bool = True) -> tuple:
    """A one-rule tuple for a constant parameter expression, or ``()`` when there is
    nothing to check (None, or an expression of signals, time or law variables).

    Examples
    --------
    >>> rule(sympy.Symbol("m"), "mass")
    (ValueRule(expr=m, what='mass', relation='positive', opt_out=True),)
    >>> rule(None, "mass")
    ()
    """
    if relation not in _RELATIONS:  # pragma: no cover - a library bug
        raise ValueError(f"unknown relation {relation!r}")
    if not isinstance(expr, sympy.Expr):
        return ()
    from ..signals import t as time
    if any(type(s) is not sympy.Symbol or s == time for s in expr.free_symbols):
        return ()           # signals, time, law variables, dummies: not a constant parameter
    return (ValueRule(expr, what, relation, opt_out),)


def _hint(r: ValueRule) -> str:
    return ("; pass active=True for an element that is negative on purpose"
            if r.opt_out and r.relation != "fraction" else "")


def check_numbers(label: str, rules: Iterable[ValueRule], *, active: bool = False) -> None:
    """Check the rules whose expression is a number (at construction).

    Raises
    ------
    ParameterError
        Naming the element (``label``) and the parameter.
    """
    for r in rules:
        if (active and r.opt_out) or not r.expr.is_number:
            continue
        test, says = _RELATIONS[r.relation]
        try:
            x = float(r.expr)
        except (TypeError, ValueError):
            continue            # complex or nan: to_expr refuses those with its own message
        if not test(x):
            shown = f"{x:g}" if isinstance(r.expr, sympy.Float) else str(r.expr)
            raise ParameterError(f"{label}: its {r.what} {shown} {says}{_hint(r)}")


def _by_name(values: Mapping) -> dict[str, Any]:
    out = {}
    for k, v in values.items():
        name = getattr(k, "name", k)
        if isinstance(name, str):
            out[name] = v
    return out


def _numeric(v: Any) -> Optional[np.ndarray]:
    """A float array of a number or an array of numbers, or None (symbolic, text, ...)."""
    if isinstance(v, sympy.Basic):
        if not v.is_number:
            return None
        try:
            return np.asarray(float(v))
        except (TypeError, ValueError):
            return None
    if isinstance(v, (bool, str, bytes)):
        return None
    try:
        arr = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        return None
    return arr if arr.ndim <= 1 else None


def _evaluate(expr: sympy.Expr, given: Mapping[str, np.ndarray]) -> Optional[np.ndarray]:
    syms = sorted(expr.free_symbols, key=lambda s: s.name)
    if not syms or any(s.name not in given for s in syms):
        return None
    if len(syms) == 1 and expr == syms[0]:
        return given[syms[0].name]
    fn = sympy.lambdify(syms, expr, "numpy")
    with np.errstate(all="ignore"):
        return np.asarray(fn(*[given[s.name] for s in syms]), dtype=float)


def check_values(elements: Iterable[Any], values: Mapping, *, where: str = "") -> None:
    """Check every element's rules at parameter ``values`` (numbers or 1-D arrays of sets).

    A rule whose parameters are not all given is skipped (the form that needs
    them asks for them); a rule of an ``active`` element is skipped.

    Raises
    ------
    ParameterValueError
        Naming the element, the parameter, its value (and the parameter set
        of a batch).
    """
    given = {}
    for name, v in _by_name(values).items():
        arr = _numeric(v)
        if arr is not None:
            given[name] = arr
    if not given:
        return
    for el in elements:
        answer = getattr(el, "value_rules", None)
        if answer is None:
            continue
        active = bool(getattr(el, "active", False))
        for r in answer():
            if (active and r.opt_out) or r.expr.is_number:
                continue
            x = _evaluate(r.expr, given)
            if x is None:
                continue
            test, says = _RELATIONS[r.relation]
            bad = ~test(x) & np.isfinite(x)
            if not np.any(bad):
                continue
            label = el.label() if hasattr(el, "label") else str(el)
            shown = r.expr if r.expr.is_Symbol else f"{r.expr}"
            if x.ndim == 0:
                text = f"{shown} = {float(x):g}"
            else:
                i = int(np.argmax(bad))
                text = f"{shown} = {float(x[i]):g} in parameter set {i}"
            raise ParameterValueError(f"{where}{label}: its {r.what} {text} {says}{_hint(r)}")


def check_model_values(model: Any, values: Mapping, *, where: str = "") -> None:
    """:func:`check_values` over the elements of a derived model (its augmented graph).

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("m")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> _ = g.connect("F", "m")
    >>> check_model_values(bg.derive(g), {"m": 0.0}, where="model 'm': ")
    Traceback (most recent call last):
    ...
    bondgraph.errors.ParameterValueError: model 'm': I:m: its mass (inertance) m = 0 must be positive; pass active=True for an element that is negative on purpose
    """
    augmented = getattr(model, "augmented", None)
    if augmented is None:
        return
    check_values(augmented.flat.elements, values, where=where)

