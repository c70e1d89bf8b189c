"""Exceptions of :mod:`bondgraph.numeric`.

Examples
--------
>>> from bondgraph.numeric.errors import ParameterValueError, NumericError
>>> import bondgraph as bg
>>> ParameterValueError is bg.ParameterValueError and issubclass(NumericError, bg.BondGraphError)
True
"""

from __future__ import annotations

import pickle

from ..errors import BondGraphError, ParameterValueError

__all__ = ["NumericError", "ParameterValueError", "SimulationError", "ImproperPlantError",
           "NotPicklableError", "DenseConversionError", "DenseConversionWarning"]


class NumericError(BondGraphError, ValueError):
    """A numeric plant cannot be built or used as asked (shapes, names)."""


class SimulationError(BondGraphError, RuntimeError):
    """The ODE solver failed (stiffness, a singularity, a non-finite derivative)."""


class ImproperPlantError(NumericError):
    """A plant with input-derivative feedthrough (``D_derivatives`` nonzero) was asked
    for a form that cannot hold it (python-control or scipy ``StateSpace``)."""

    __module__ = "bondgraph"      # tracebacks name it where users import it: bondgraph.ImproperPlantError


class NotPicklableError(NumericError, pickle.PicklingError):
    """A compiled model cannot be pickled: its equations call a Python function
    (sympy ``implemented_function``) that cannot travel with them."""


class DenseConversionError(NumericError, MemoryError):
    """A sparse plant was asked for a dense form (python-control, scipy, all its
    eigenvalues) with ``dense="refuse"``; the message gives the memory it would take."""


class DenseConversionWarning(UserWarning):
    """A sparse plant is being made dense (``dense="warn"``, the default): the
    message gives the memory the dense ``n x n`` arrays take."""
