"""Exceptions of :mod:`bondgraph.numeric`.

Examples
--------
>>> from bondgraph.numeric.errors import ParameterValueError, NumericError
>>> issubclass(ParameterValueError, NumericError) and issubclass(ParameterValueError, ValueError)
True
"""

from __future__ import annotations

from ..errors import BondGraphError

__all__ = ["NumericError", "ParameterValueError", "SimulationError", "ImproperPlantError"]


class NumericError(BondGraphError, ValueError):
    """A numeric plant cannot be built or used as asked (shapes, names)."""


class ParameterValueError(NumericError):
    """Parameter values are missing, unknown, or not finite real numbers.

    Attributes
    ----------
    missing, unknown : tuple of str
        Parameter names that were not given / that the model does not have.
    """

    def __init__(self, message: str, *, missing: tuple = (), unknown: tuple = ()) -> None:
        super().__init__(message)
        self.missing = tuple(missing)
        self.unknown = tuple(unknown)


class SimulationError(BondGraphError, RuntimeError):
    """The ODE solver failed (stiffness, a singularity, a non-finite derivative)."""


class ImproperPlantError(NumericError):
    """A plant with input-derivative feedthrough (``D_derivatives`` nonzero) was asked
    for a form that cannot hold it (python-control or scipy ``StateSpace``)."""
