"""Checking numeric parameter values against a model's parameter symbols.

Values are given as a mapping keyed by sympy Symbol or by its name (``"Ra"``,
``"motor.Ra"``), matched by the package-wide policy of
:mod:`bondgraph.parameters`: every parameter given once, unknown and missing
names reported together in one error, values of parameters the model
definition knows but this form does not use (``known=``) ignored.

Examples
--------
>>> import sympy
>>> Ra, La = sympy.symbols("Ra La", positive=True)
>>> resolve_parameters((La, Ra), {"Ra": 2, La: 0.5})
array([0.5, 2. ])
>>> resolve_parameters((La, Ra), {"Ra": 2, "Rb": 1})
Traceback (most recent call last):
...
bondgraph.errors.ParameterValueError: unknown parameter 'Rb'; missing La. Valid names: La, Ra
"""

from __future__ import annotations

from typing import Any, Iterable, Mapping, Sequence, Union

import numpy as np
import sympy

from ..parameters import ParameterValues, match_values, parameter_name, real_value
from .errors import ParameterValueError

__all__ = ["ParameterValues", "resolve_parameters", "resolve_batch", "parameter_name"]


def _match(parameters: Sequence[sympy.Symbol], values: Mapping, where: str,
           known: Iterable[str] = (), inputs: Iterable[str] = ()) -> dict[str, Any]:
    # matched by name: the model's own symbols serve (no Symbol built per name and call)
    return {p.name: v for p, v in match_values(parameters, values, known=known,
                                               where=where, inputs=inputs).items()}


def _scalar(value: Any, name: str, where: str) -> float:
    return real_value(value, name, where)


def resolve_parameters(parameters: Sequence[sympy.Symbol], values: ParameterValues, *,
                       model: str = "", known: Iterable[str] = (),
                       inputs: Iterable[str] = ()) -> np.ndarray:
    """Values in the order of ``parameters``, checked.

    Parameters
    ----------
    parameters : sequence of sympy.Symbol
        The model's parameters (``Model.parameters``).
    values : mapping of Symbol or str to float
        One finite real number per parameter.
    model : str, optional
        Model name used in error messages.
    known : iterable of str, optional
        Names the model definition knows beyond ``parameters``; their values
        are accepted and ignored (see :mod:`bondgraph.parameters`).
    inputs : iterable of str, optional
        The model's input names (one given as a parameter is named as an input).

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
    bondgraph.errors.ParameterValueError: parameter 'm' must be a finite real number; got nan
    """
    where = f"model {model!r}: " if model else ""
    names = [p.name for p in parameters]
    given = _match(parameters, values, where, known, inputs)
    return np.array([_scalar(given[n], n, where) for n in names], dtype=float)


def resolve_batch(parameters: Sequence[sympy.Symbol],
                  values: Union[ParameterValues, np.ndarray], *, model: str = "",
                  known: Iterable[str] = (), inputs: Iterable[str] = ()) -> np.ndarray:
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
        given = _match(parameters, values, where, known, inputs)
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
    if arr.dtype.kind not in "iuf":            # text is never parsed into numbers (issue 23, item 9)
        raise ParameterValueError(
            f"{where}{name} must be finite real numbers (int or float); got {arr.dtype} values")
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
