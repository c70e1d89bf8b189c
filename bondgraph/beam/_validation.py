"""Exception type and argument checks shared by the beam modules."""

from __future__ import annotations

import numbers
from collections.abc import Iterable, Sequence
from typing import cast

import numpy as np
from numpy.typing import ArrayLike

from ..errors import BondGraphError

__all__ = ["BeamParameterError"]


class BeamParameterError(BondGraphError, ValueError):
    """Invalid argument passed to a modal-beam routine.

    Subclass of :class:`ValueError` (and of
    :class:`bondgraph.errors.BondGraphError`).  The message names the
    offending argument and states what was expected.

    Examples
    --------
    >>> from bondgraph.beam import BeamParameterError, modal_beam
    >>> try:
    ...     modal_beam(-1.0, 0.1, 0.5, 3)
    ... except BeamParameterError as exc:
    ...     print(exc)
    EI: expected a finite number > 0, got -1.0
    """


def check_int(value: object, name: str, *, minimum: int = 1) -> int:
    """Return ``value`` as ``int`` or raise if it is not an integer >= minimum."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise BeamParameterError(
            f"{name}: expected an integer >= {minimum}, got {value!r} "
            f"({type(value).__name__})")
    out = int(value)
    if out < minimum:
        raise BeamParameterError(f"{name}: expected an integer >= {minimum}, got {out}")
    return out


def check_float(value: object, name: str, *, allow_zero: bool = False) -> float:
    """Return ``value`` as a finite ``float`` > 0 (or >= 0 if ``allow_zero``)."""
    bound = ">= 0" if allow_zero else "> 0"
    if isinstance(value, (bool, np.bool_)):
        raise BeamParameterError(f"{name}: expected a finite number {bound}, got {value!r}")
    try:
        out = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise BeamParameterError(
            f"{name}: expected a finite number {bound}, got {value!r}") from None
    if not np.isfinite(out) or out < 0 or (out == 0 and not allow_zero):
        raise BeamParameterError(f"{name}: expected a finite number {bound}, got {value!r}")
    return out


def check_choice(value: object, name: str, choices: Sequence[str]) -> str:
    """Return ``value`` if it is one of ``choices``; otherwise raise listing them."""
    if not isinstance(value, str) or value not in choices:
        valid = ", ".join(repr(c) for c in choices)
        raise BeamParameterError(f"{name}: expected one of {valid}, got {value!r}")
    return value


def check_per_mode(value: object, name: str, n: int) -> tuple[float, ...]:
    """Return a scalar-or-sequence option as an ``n``-tuple of floats >= 0."""
    if isinstance(value, (str, bytes)):
        raise BeamParameterError(
            f"{name}: expected a number >= 0 or a sequence of {n} such numbers, got {value!r}")
    # np.ndim takes any object (0 for scalars and non-sequences)
    if np.ndim(cast(ArrayLike, value)) == 0:
        v = check_float(value, name, allow_zero=True)
        return (v,) * n
    items = list(cast(Iterable[object], value))  # ndim >= 1: a sequence or an array
    if len(items) != n:
        raise BeamParameterError(
            f"{name}: expected a number or a sequence of {n} numbers (one per mode), "
            f"got a sequence of length {len(items)}")
    return tuple(check_float(v, f"{name}[{k}]", allow_zero=True) for k, v in enumerate(items))
