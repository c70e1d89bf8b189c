"""One policy for parameter values, shared by every call that takes them.

``plant``, ``batch``, ``subs`` (state space, transfer function, transfer
matrix), ``simulate``, code-generation defaults and grey-box fits all match
the values they are given with :func:`match_values`:

* keys are sympy Symbols or their names (``"Ra"``, ``"motor.Ra"``);
* a name the model does not know is an error that lists the valid names
  (and suggests the nearest one: ``'Rmm'`` → ``'Rm'``);
* a name the model *definition* knows but this derived form no longer uses
  (a parameter that dropped out when linearizing, the load inertia of a
  variant that leaves it out) is accepted and ignored;
* a parameter without a value is an error, unless ``partial=True``;
* values are numbers (``int``, ``float``, numpy scalars, sympy numbers):
  text is never parsed, and ``nan``, infinities, complex values and bools
  are refused naming the parameter.  Negative values are allowed (active
  elements, negative stiffness).

Examples
--------
>>> import sympy
>>> k, m = sympy.symbols("k m", positive=True)
>>> match_values((k, m), {"k": 4, m: 0.5})
{k: 4, m: 0.5}
>>> match_values((k, m), {"k": 4, "m": 0.5, "J_l": 1e-3}, known=("J_l",))
{k: 4, m: 0.5}
>>> match_values((k, m), {"kk": 4, "m": 0.5})
Traceback (most recent call last):
...
bondgraph.errors.ParameterValueError: unknown parameter 'kk' (did you mean 'k'?); missing k. Valid names: k, m
>>> match_values((k, m), {"k": 4, "m": 0.5, "F": 1.0}, inputs=("F",))
Traceback (most recent call last):
...
bondgraph.errors.ParameterValueError: 'F' is an input of the model, not a parameter (give it as an input: u= when simulating). Valid names: k, m
"""

from __future__ import annotations

import difflib
import math
import numbers
from typing import Any, Iterable, Mapping, Optional, Sequence, Union

import numpy as np
import sympy

from .errors import MissingValueError, ParameterValueError

__all__ = ["ParameterValues", "parameter_name", "match_values", "real_value", "exact_value"]

ParameterValues = Mapping[Union[sympy.Symbol, str], Any]


def parameter_name(key: object, where: str = "") -> str:
    """The name a parameter key stands for (a Symbol's name, or the str itself).

    Raises
    ------
    ParameterValueError
        For any other kind of key.

    Examples
    --------
    >>> parameter_name(sympy.Symbol("motor.Ra")), parameter_name("J")
    ('motor.Ra', 'J')
    """
    if isinstance(key, sympy.Symbol):
        return key.name
    if isinstance(key, str):
        return key
    raise ParameterValueError(
        f"{where}parameter keys must be sympy Symbols or their names (str); "
        f"got {type(key).__name__} {key!r}")


def match_values(parameters: Sequence[sympy.Symbol], values: Optional[ParameterValues], *,
                 known: Iterable[str] = (), partial: bool = False,
                 where: str = "", inputs: Iterable[str] = ()) -> dict[sympy.Symbol, Any]:
    """Match ``values`` to ``parameters`` by name; the policy of the module docstring.

    Parameters
    ----------
    parameters : sequence of sympy.Symbol
        The parameters this form uses.
    values : mapping of Symbol or str to value, or None
        The values given (``None`` is an empty mapping).
    known : iterable of str, optional
        Further names the model definition knows; their values are ignored.
    partial : bool, optional
        Allow parameters without a value (they are left out of the result).
    where : str, optional
        Prefix of error messages (``"model 'srv02': "``).
    inputs : iterable of str, optional
        The model's input names: one given as a parameter is named as an
        input in the error, not as an unknown parameter.

    Returns
    -------
    dict
        Parameter symbol to the value given (not yet converted), in the
        order of ``parameters``.

    Raises
    ------
    ParameterValueError
        An unknown name, a name given twice, or not a mapping; the message
        lists the valid names.  :class:`MissingValueError` (a subclass) when
        values are missing and ``partial`` is false.
    """
    if values is None:
        values = {}
    if not isinstance(values, Mapping):
        raise ParameterValueError(
            f"{where}parameter values must be a mapping of name (or Symbol) to number; "
            f"got {type(values).__name__}")
    by_name = {p.name: p for p in parameters}
    known = set(known) | set(by_name)
    given: dict[str, Any] = {}
    for key, value in values.items():
        name = parameter_name(key, where)
        if name in given:
            raise ParameterValueError(
                f"{where}parameter {name!r} is given twice (as a name and as a Symbol)")
        given[name] = value
    unknown = sorted(n for n in given if n not in known)
    missing = [] if partial else [n for n in by_name if n not in given]
    if unknown or missing:
        valid = ", ".join(sorted(known)) if known else "(no parameters)"
        parts = []
        inputs = set(inputs)
        for n in unknown:
            if n in inputs:
                parts.append(f"{n!r} is an input of the model, not a parameter (give it as an "
                             "input: u= when simulating)")
                continue
            near = difflib.get_close_matches(n, sorted(known), n=1)
            parts.append(f"unknown parameter {n!r}" + (f" (did you mean {near[0]!r}?)" if near else ""))
        if missing:
            parts.append("missing " + ", ".join(missing))
        cls = ParameterValueError if unknown else MissingValueError
        raise cls(f"{where}{'; '.join(parts)}. Valid names: {valid}",
                  missing=tuple(missing), unknown=tuple(unknown))
    return {p: given[p.name] for p in parameters if p.name in given}


def _bad(name: str, where: str, got: str) -> ParameterValueError:
    return ParameterValueError(f"{where}parameter {name!r} must be a finite real number; got {got}")


def real_value(value: Any, name: str, where: str = "") -> float:
    """``value`` as a finite float, or an error naming parameter ``name``.

    Examples
    --------
    >>> real_value(2, "k"), real_value(sympy.Rational(1, 4), "m")
    (2.0, 0.25)
    >>> real_value("2", "k")
    Traceback (most recent call last):
    ...
    bondgraph.errors.ParameterValueError: parameter 'k' must be a finite real number; got str '2' (text is never parsed)
    """
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, (bool, np.bool_)):
        raise _bad(name, where, "a bool")
    if isinstance(value, str):
        raise _bad(name, where, f"str {value!r} (text is never parsed)")
    if isinstance(value, sympy.Basic):
        if not (value.is_number and value.is_extended_real is True and value.is_finite):
            raise _bad(name, where, f"{value}")
        value = float(value)
    elif isinstance(value, numbers.Complex) and not isinstance(value, numbers.Real):
        raise _bad(name, where, f"the complex value {value!r}")
    elif not isinstance(value, numbers.Real):
        raise _bad(name, where, f"{type(value).__name__} {value!r}")
    try:
        out = float(value)
    except OverflowError:
        raise _bad(name, where, "an integer too large for a float") from None
    if not math.isfinite(out):
        raise _bad(name, where, repr(out))
    return out


def exact_value(value: Any, name: str, where: str = "") -> sympy.Expr:
    """``value`` as an exact sympy number for symbolic substitution.

    Integers and sympy rationals stay exact, floats become the rational of
    their decimal representation (``0.1`` → ``1/10``), sympy numbers such as
    ``sqrt(2)`` or ``pi`` are kept; anything else is refused like
    :func:`real_value`.

    Examples
    --------
    >>> exact_value(0.1, "R"), exact_value(3, "L"), exact_value(sympy.pi, "a")
    (1/10, 3, pi)
    """
    if isinstance(value, sympy.Basic):
        real_value(value, name, where)
        return value
    if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)):
        real_value(value, name, where)  # refuses integers beyond the float range
        return sympy.Integer(int(value))
    x = real_value(value, name, where)
    return sympy.Rational(repr(x))
