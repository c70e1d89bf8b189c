"""Exception type, argument checks and read-only results shared by the identification modules."""

from __future__ import annotations

import numbers

import numpy as np
from numpy.typing import ArrayLike, DTypeLike, NDArray

from ..errors import BondGraphError

__all__ = ["IdentificationError"]


class IdentificationError(BondGraphError, ValueError):
    """Invalid data or options passed to a system-identification routine.

    Subclass of :class:`ValueError`, so ``except ValueError`` also catches it.
    The message names the offending argument and states what was expected.

    Examples
    --------
    >>> from bondgraph.identification import IdentificationError, prbs
    >>> try:
    ...     prbs(1)
    ... except IdentificationError as exc:
    ...     print(exc)
    order: expected an integer in [2, 32], got 1
    """


def check_int(value: object, name: str, *, minimum: int | None = None,
              maximum: int | None = None) -> int:
    """Return ``value`` as ``int`` or raise if it is not an integer in range."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise IdentificationError(
            f"{name}: expected an integer, got {value!r} ({type(value).__name__})")
    value = int(value)
    if (minimum is not None and value < minimum) or (maximum is not None and value > maximum):
        if maximum is None:
            expected = f"an integer >= {minimum}"
        elif minimum is None:
            expected = f"an integer <= {maximum}"
        else:
            expected = f"an integer in [{minimum}, {maximum}]"
        raise IdentificationError(f"{name}: expected {expected}, got {value}")
    return value


def check_positive_float(value: object, name: str, *, allow_zero: bool = False) -> float:
    """Return ``value`` as a finite ``float`` > 0 (or >= 0) or raise."""
    try:
        out = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise IdentificationError(
            f"{name}: expected a real number, got {value!r}") from None
    if not np.isfinite(out) or out < 0 or (out == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise IdentificationError(f"{name}: expected a finite number {bound}, got {value!r}")
    return out


def check_finite_float(value: object, name: str) -> float:
    """Return ``value`` as a finite ``float`` or raise."""
    try:
        out = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise IdentificationError(
            f"{name}: expected a real number, got {value!r}") from None
    if not np.isfinite(out):
        raise IdentificationError(f"{name}: expected a finite number, got {value!r}")
    return out


def as_signal(x: ArrayLike, name: str, *, min_length: int = 1,
              dtype: type = float) -> NDArray:
    """Return ``x`` as a finite 1-D array of at least ``min_length`` samples."""
    _refuse_text_and_complex(x, name, dtype)
    try:
        arr: NDArray = np.asarray(x, dtype=dtype)
    except (TypeError, ValueError):
        raise IdentificationError(
            f"{name}: expected a 1-D array of {np.dtype(dtype).name} numbers") from None
    if arr.ndim != 1:
        raise IdentificationError(
            f"{name}: expected a 1-D array, got an array of shape {arr.shape}")
    if arr.size < min_length:
        raise IdentificationError(
            f"{name}: expected at least {min_length} samples, got {arr.size}")
    if not np.all(np.isfinite(arr)):
        bad = int(np.count_nonzero(~np.isfinite(arr)))
        raise IdentificationError(
            f"{name}: expected finite values, found {bad} NaN/inf entries")
    return arr


def _refuse_text_and_complex(x: object, name: str, dtype: DTypeLike) -> None:
    """Text is not parsed into numbers; complex data is not cast to real (issue 23, items 9, 11)."""
    from .._support.numeric_input import dtype_problem

    try:
        raw = np.asarray(x)
    except (TypeError, ValueError):
        return                                  # ragged: the caller's conversion names it
    problem = dtype_problem(raw, complex_ok=np.dtype(dtype).kind == "c")
    if problem is not None:
        raise IdentificationError(f"{name}: expected an array of real numbers; it {problem}")


def check_same_length(a: NDArray, name_a: str, b: NDArray, name_b: str) -> None:
    """Raise if two signals differ in length."""
    if a.shape[0] != b.shape[0]:
        raise IdentificationError(
            f"{name_b}: expected the same length as {name_a} ({a.shape[0]}), "
            f"got {b.shape[0]}")


def readonly_copy(x: ArrayLike, dtype: DTypeLike = float) -> NDArray:
    """A read-only copy of ``x`` as an array of ``dtype`` (for frozen result objects)."""
    arr = np.array(x, dtype=dtype, copy=True)
    arr.setflags(write=False)
    return arr


def finite_array(x: ArrayLike, name: str, *, dtype: DTypeLike = float,
                 ndim: tuple[int, ...] = (1, 2)) -> NDArray:
    """``x`` as an array of ``dtype`` with ``ndim`` dimensions and no NaN/inf, or raise.

    Examples
    --------
    >>> finite_array([[1, 2]], "u").shape
    (1, 2)
    >>> finite_array([1.0, float("inf")], "y")
    Traceback (most recent call last):
    ...
    bondgraph.identification.IdentificationError: y: expected finite values, found 1 NaN/inf entries
    """
    _refuse_text_and_complex(x, name, dtype)
    try:
        arr = np.asarray(x, dtype=dtype)
    except (TypeError, ValueError):
        raise IdentificationError(f"{name}: expected an array of numbers") from None
    if arr.ndim not in ndim:
        raise IdentificationError(
            f"{name}: expected an array with {' or '.join(map(str, ndim))} dimension(s), "
            f"got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        bad = int(np.count_nonzero(~np.isfinite(arr)))
        raise IdentificationError(f"{name}: expected finite values, found {bad} NaN/inf entries")
    return arr
