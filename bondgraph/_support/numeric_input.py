"""Arrays from users: numbers only, never text parsed by numpy (issue 23, item 9).

``np.asarray(["1", "2"], dtype=float)`` parses the strings, so a batch of
``{"m": ["1", "2"]}``, ``frequency_response("10")`` or string samples given
to ``arx`` were taken as numbers, while ``plant({"m": "2"})`` is refused.
:func:`numeric_array` is the one policy: integer, unsigned or float arrays
(dtype kinds ``i``, ``u``, ``f``) are accepted; text (``U``, ``S``), objects
(``O``), booleans and, unless ``complex_ok``, complex numbers are refused
with ``error(message)`` naming the argument.
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

__all__ = ["numeric_array", "dtype_problem"]

_WORDS = {"U": "text", "S": "bytes", "O": "Python objects", "b": "booleans", "c": "complex numbers",
          "M": "dates", "m": "time deltas", "V": "raw records"}


def dtype_problem(arr: np.ndarray, *, complex_ok: bool = False) -> str | None:
    """Why ``arr`` does not hold plain numbers (None if it does).

    Examples
    --------
    >>> import numpy as np
    >>> dtype_problem(np.array(["1", "2"])), dtype_problem(np.array([1, 2])), dtype_problem(np.array([1j]))
    ('holds text (dtype <U1), not numbers', None, 'holds complex numbers (dtype complex128), not numbers')
    """
    kinds = "iufc" if complex_ok else "iuf"
    if arr.dtype.kind in kinds:
        return None
    words = _WORDS.get(arr.dtype.kind, "values")
    return f"holds {words} (dtype {arr.dtype}), not {'numbers' if not complex_ok else 'numbers'}"


def numeric_array(value: Any, name: str, error: Callable[[str], Exception], *,
                  complex_ok: bool = False) -> np.ndarray:
    """``value`` as a float (or complex) array, refusing text, objects, booleans (and complex).

    Examples
    --------
    >>> numeric_array([1, 2.5], "omega", ValueError)
    array([1. , 2.5])
    >>> numeric_array("10", "omega", ValueError)
    Traceback (most recent call last):
    ...
    ValueError: omega holds text (dtype <U2), not numbers; give numbers (int or float), not strings
    """
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:         # ragged lists
        raise error(f"{name} must be an array of numbers: {exc}") from None
    problem = dtype_problem(arr, complex_ok=complex_ok)
    if problem is not None:
        raise error(f"{name} {problem}; give numbers (int or float), not strings"
                    if arr.dtype.kind in "USO" else f"{name} {problem}")
    return arr.astype(complex if arr.dtype.kind == "c" else float, copy=False)
