"""Fields checked at the numbers a simulation is given, as ``plant()`` does (issue 23, item 10)."""

from __future__ import annotations

from typing import Any, Mapping, Sequence

from ..errors import ParameterValueError

__all__ = ["check_fields_at"]


def check_fields_at(model: Any, values: Any, names: Sequence[str], resolved: Sequence[float]) -> None:
    """Ask each element of ``model`` that answers ``check_values`` (the fields) at these values.

    ``values`` is what the user gave (names or Symbols to numbers), ``names``
    and ``resolved`` the model's parameters as resolved.  A field whose
    matrix the equations do not use (so no value was needed) is not checked.
    """
    given: dict[str, Any] = {}
    if isinstance(values, Mapping):
        given = {str(getattr(k, "name", k)): v for k, v in values.items()}
    at = {**given, **dict(zip(names, resolved))}
    augmented = getattr(model, "augmented", None)
    try:
        for element in (augmented.flat.elements if augmented is not None else ()):
            check = getattr(element, "check_values", None)      # the fields answer
            if check is not None:
                check(at)
    except ParameterValueError:
        pass
