"""Exceptions raised by :mod:`bondgraph.tf`.

Every exception derives from :class:`TransferFunctionError`, itself a
:class:`bondgraph.BondGraphError` and a ``ValueError``, except the
parameter-value errors, which are the package-wide
:class:`bondgraph.ParameterValueError` and its :class:`MissingValueError`
(one class for every call that takes values).  Messages name the argument
at fault and say what was expected and what was given.

Examples
--------
>>> from bondgraph.tf.errors import ShapeError, TransferFunctionError
>>> issubclass(ShapeError, ValueError) and issubclass(ShapeError, TransferFunctionError)
True
"""

from __future__ import annotations

from ..errors import BondGraphError, MissingValueError, ParameterValueError

__all__ = [
    "TransferFunctionError",
    "ShapeError",
    "UnknownSignalError",
    "SingularPencilError",
    "ParameterValueError",
    "MissingValueError",
    "InvalidOptionError",
    "MatrixEntryError",
    "TermBudgetError",
]


class TransferFunctionError(BondGraphError, ValueError):
    """Base class of the errors raised by :mod:`bondgraph.tf`."""


class ShapeError(TransferFunctionError):
    """A matrix does not have the shape its role (A, B, C, D, E) requires."""


class UnknownSignalError(TransferFunctionError):
    """An input or output name (or index) that the system does not have."""


class SingularPencilError(TransferFunctionError):
    """``det(sE - A)`` is identically zero: the descriptor system has no TF."""


class InvalidOptionError(TransferFunctionError):
    """A keyword option has a value outside the accepted set."""


class MatrixEntryError(TransferFunctionError):
    """A matrix entry cannot be used (contains ``s``, is not finite, ...)."""


class TermBudgetError(TransferFunctionError):
    """The expanded transfer function would exceed its term budget (``max_terms``)."""
