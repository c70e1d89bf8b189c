"""Checking numeric parameter values against a model's parameter symbols.

Values are given as a mapping keyed by sympy Symbol or by its name (``"Ra"``,
``"motor.Ra"``).  Every parameter must be given exactly once and nothing else:
missing and unknown names are reported together in one error.

Examples
--------
>>> import sympy
>>> Ra, La = sympy.symbols("Ra La", positive=True)
>>> resolve_parameters((La, Ra), {"Ra": 2, La: 0.5})
array([0.5, 2. ])
>>> resolve_parameters((La, Ra), {"Ra": 2, "Rb": 1})
Traceback (most recent call last):
...
bondgraph.numeric.errors.ParameterValueError: parameter values do not match the model: missing La; unknown Rb. Expected exactly: La, Ra
"""

from __future__ import annotations

import math
import numbers
from typing import Any, Mapping, Sequence, Union

import numpy as np
import sympy

from .errors import ParameterValueError

__all__ = ["ParameterValues", "resolve_parameters", "resolve_batch", "parameter_name"]

ParameterValues = Mapping[Union[sympy.Symbol, str], Any]


def parameter_name(key: object) -> str:
    """The name a parameter key stands for (a Symbol's name, or the str itself).

    Parameters
    ----------
    key : sympy.Symbol or str
        A key of a parameter-value mapping.

    Raises
    ------
    ParameterValueError
        For any other kind of key.

    Examples
    --------
    >>> import sympy
    >>> parameter_name(sympy.Symbol("motor.Ra")), parameter_name("J")
    ('motor.Ra', 'J')
    """
    if isinstance(key, sympy.Symbol):
        return key.name
    if isinstance(key, str):
        return key
    raise ParameterValueError(
        f"parameter keys must be sympy Symbols or their names (str); got {type(key).__name__} {key!r}")


def _match(names: Sequence[str], values: Mapping, where: str) -> dict[str, Any]:
    if not isinstance(values, Mapping):
        raise ParameterValueError(
            f"{where}parameter values must be a mapping of name (or Symbol) to number; "
            f"got {type(values).__name__}")
    given: dict[str, Any] = {}
    for key, value in values.items():
        name = parameter_name(key)
        if name in given:
            raise ParameterValueError(f"{where}parameter {name!r} is given twice (as a name and as a Symbol)")
        given[name] = value
    expected = set(names)
    missing = [n for n in names if n not in given]
    unknown = sorted(n for n in given if n not in expected)
    if missing or unknown:
        parts = []
        if missing:
            parts.append("missing " + ", ".join(missing))
        if unknown:
            parts.append("unknown " + ", ".join(unknown))
        raise ParameterValueError(
            f"{where}parameter values do not match the model: {'; '.join(parts)}. "
            f"Expected exactly: {', '.join(names) if names else '(no parameters)'}",
            missing=tuple(missing), unknown=tuple(unknown))
    return given


def _scalar(value: Any, name: str, where: str) -> float:
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, bool) or isinstance(value, np.bool_):
        raise ParameterValueError(f"{where}parameter {name!r} must be a finite real number; got a bool")
    if isinstance(value, numbers.Complex) and not isinstance(value, numbers.Real):
        raise ParameterValueError(
            f"{where}parameter {name!r} must be a finite real number; got the complex value {value!r}")
    if not isinstance(value, numbers.Real):
        raise ParameterValueError(
            f"{where}parameter {name!r} must be a finite real number; got {type(value).__name__} {value!r}")
    out = float(value)
    if not math.isfinite(out):
        raise ParameterValueError(f"{where}parameter {name!r} must be finite; got {out!r}")
    return out


def resolve_parameters(parameters: Sequence[sympy.Symbol], values: ParameterValues, *,
                       model: str = "") -> np.ndarray:
    """Values in the order of ``parameters``, checked.

    Parameters
    ----------
    parameters : sequence of sympy.Symbol
        The model's parameters (``Model.parameters``).
    values : mapping of Symbol or str to float
        One finite real number per parameter.
    model : str, optional
        Model name used in error messages.

    Returns
    -------
    numpy.ndarray
        Shape ``(len(parameters),)``, float64.

    Raises
    ------
    ParameterValueError
        Listing all missing and unknown names at once, or naming the first
        parameter whose value is not a finite real number.

    Examples
    --------
    >>> import sympy
    >>> k, m = sympy.symbols("k m", positive=True)
    >>> resolve_parameters((k, m), {"k": 4.0, "m": float("nan")})
    Traceback (most recent call last):
    ...
    bondgraph.numeric.errors.ParameterValueError: parameter 'm' must be finite; got nan
    """
    where = f"model {model!r}: " if model else ""
    names = [p.name for p in parameters]
    given = _match(names, values, where)
    return np.array([_scalar(given[n], n, where) for n in names], dtype=float)


def resolve_batch(parameters: Sequence[sympy.Symbol],
                  values: Union[ParameterValues, np.ndarray], *, model: str = "") -> np.ndarray:
    """A ``(P, k)`` array of parameter sets, one row per set, columns in order.

    Parameters
    ----------
    parameters : sequence of sympy.Symbol
    values : mapping or array
        Either a mapping of name (or Symbol) to a 1-D array of length ``P``
        or a scalar (broadcast to every set), or an array of shape ``(P, k)``
        with columns in the order of ``parameters``.
    model : str, optional
        Model name used in error messages.

    Returns
    -------
    numpy.ndarray
        Shape ``(P, k)``, float64.

    Raises
    ------
    ParameterValueError
        Missing or unknown names (all at once), arrays of different lengths,
        or a value that is not a finite real number (naming the parameter and
        the index of the first bad set).

    Examples
    --------
    >>> import sympy
    >>> k, m = sympy.symbols("k m", positive=True)
    >>> resolve_batch((k, m), {"k": [1.0, 2.0, 3.0], "m": 0.5})
    array([[1. , 0.5],
           [2. , 0.5],
           [3. , 0.5]])
    """
    where = f"model {model!r}: " if model else ""
    names = [p.name for p in parameters]
    k = len(names)
    if isinstance(values, Mapping):
        given = _match(names, values, where)
        cols = [_column(given[n], n, where) for n in names]
        lengths = {c.shape[0] for c in cols if c.ndim == 1}
        if len(lengths) > 1:
            detail = ", ".join(f"{n}: {c.shape[0]}" for n, c in zip(names, cols) if c.ndim == 1)
            raise ParameterValueError(
                f"{where}parameter arrays must all have the same length; got {detail}")
        size = lengths.pop() if lengths else 1
        out = np.empty((size, k))
        for j, c in enumerate(cols):
            out[:, j] = c
        return out
    arr = _array(values, "parameter sets", where)
    if arr.ndim != 2 or arr.shape[1] != k:
        raise ParameterValueError(
            f"{where}a parameter array must have shape (P, {k}) with columns "
            f"{', '.join(names) if names else '(none)'}; got shape {arr.shape}")
    bad = ~np.isfinite(arr)
    if bad.any():
        i, j = np.argwhere(bad)[0]
        raise ParameterValueError(
            f"{where}parameter {names[j]!r} must be finite; set {i} has {arr[i, j]!r}")
    return arr


def _array(value: Any, name: str, where: str) -> np.ndarray:
    arr = np.asarray(value)
    if arr.dtype.kind == "b":
        raise ParameterValueError(f"{where}{name} must be finite real numbers; got bools")
    if arr.dtype.kind == "c":
        raise ParameterValueError(f"{where}{name} must be finite real numbers; got complex values")
    if arr.dtype.kind not in "iuf":
        try:
            arr = arr.astype(float)
        except (TypeError, ValueError):
            raise ParameterValueError(
                f"{where}{name} must be finite real numbers; got {arr.dtype} values") from None
    return arr.astype(float, copy=False)


def _column(value: Any, name: str, where: str) -> np.ndarray:
    arr = _array(value, f"parameter {name!r}", where)
    if arr.ndim > 1:
        raise ParameterValueError(
            f"{where}parameter {name!r} must be a number or a 1-D array; got shape {arr.shape}")
    bad = ~np.isfinite(arr)
    if bad.any():
        if arr.ndim == 0:
            raise ParameterValueError(f"{where}parameter {name!r} must be finite; got {arr[()]!r}")
        i = int(np.argmax(bad))
        raise ParameterValueError(
            f"{where}parameter {name!r} must be finite; set {i} has {arr[i]!r}")
    return arr
