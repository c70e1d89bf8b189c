"""Exceptions of switched (hybrid) bond graphs, under :class:`bondgraph.BondGraphError`."""

from __future__ import annotations

from ..errors import BondGraphError

__all__ = ["HybridError", "ModeError", "ChatteringError", "EventBudgetError"]


class HybridError(BondGraphError):
    """Base of the errors of switched bond graphs."""


class ModeError(HybridError, ValueError):
    """A combination of switch states is not a consistent mode, or names no switch."""


class ChatteringError(HybridError, RuntimeError):
    """A switch flips back and forth without time advancing (a sliding mode).

    Attributes
    ----------
    time : float
    element : str
    """

    def __init__(self, message: str, *, time: float, element: str) -> None:
        super().__init__(message)
        self.time = time
        self.element = element


class EventBudgetError(HybridError, RuntimeError):
    """A simulation used up its event or wall-time budget.

    Attributes
    ----------
    result : SwitchedResult
        What was computed up to ``result.t[-1]``.
    """

    def __init__(self, message: str, *, result=None) -> None:
        super().__init__(message)
        self.result = result
