"""Fields checked at the numbers a simulation is given, as ``plant()`` does (issue 23, item 10)."""

from __future__ import annotations

from typing import Any, Mapping, Sequence

from ..elements.rules import check_values
from ..errors import ParameterValueError

__all__ = ["check_fields_at"]


def check_fields_at(model: Any, values: Any, names: Sequence[str], resolved: Sequence[float]) -> None:
    """Check every element's :meth:`~bondgraph.Element.value_rules` at these values, and ask
    each field (``check_values``) whether its matrix is definite there.

    ``values`` is what the user gave (names or Symbols to numbers), ``names``
    and ``resolved`` the model's parameters as resolved.  A field whose
    matrix the equations do not use (so no value was needed) is not checked.
    """
    given: dict[str, Any] = {}
    if isinstance(values, Mapping):
        given = {str(getattr(k, "name", k)): v for k, v in values.items()}
    at = {**given, **dict(zip(names, resolved))}
    augmented = getattr(model, "augmented", None)
    elements = augmented.flat.elements if augmented is not None else ()
    check_values(elements, at, where=f"model {model.name!r}: ")   # every element's own rules
    try:
        for element in elements:
            if getattr(element, "matrix", None) is not None:       # the fields answer
                element.check_values(at)
    except ParameterValueError:
        pass
