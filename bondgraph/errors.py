"""Exceptions raised by bondgraph.

Every exception derives from :class:`BondGraphError`, and also from the
builtin that fits (``ValueError`` or ``TypeError``), so callers may catch
either.  Messages name the element, bond or port at fault and say what was
expected.
"""

from __future__ import annotations

__all__ = [
    "BondGraphError",
    "ModelStructureError",
    "DuplicateNameError",
    "UnknownElementError",
    "PortError",
    "ParameterError",
    "LawError",
    "CausalityError",
    "CausalityConflictError",
    "AlgebraicLoopError",
    "OutputError",
    "NonlinearModelError",
    "NameClashError",
    "ParameterValueError",
    "MissingValueError",
    "BondGraphWarning",
]


class BondGraphError(Exception):
    """Base class of every error raised by bondgraph."""


class ModelStructureError(BondGraphError, ValueError):
    """The graph is malformed: bad connection, wrong number of bonds, ..."""


class DuplicateNameError(ModelStructureError):
    """A name is used by two elements of one graph."""


class UnknownElementError(ModelStructureError):
    """A name or element that is not in the graph was referenced."""


class PortError(ModelStructureError):
    """A sub-model port is missing, dangling or connected twice."""


class ParameterError(BondGraphError, TypeError):
    """A parameter could not be turned into a sympy expression."""


class LawError(BondGraphError, ValueError):
    """A constitutive law is not a function of the element's own variable."""


class CausalityError(BondGraphError, ValueError):
    """Causality could not be assigned."""


class CausalityConflictError(CausalityError):
    """Two causal requirements contradict each other (e.g. two Sf on a 1)."""


class AlgebraicLoopError(BondGraphError, ValueError):
    """An algebraic loop or derivative-causality block cannot be solved."""


class OutputError(BondGraphError, ValueError):
    """An output names nothing in the graph, or cannot be computed."""


class NonlinearModelError(BondGraphError, ValueError):
    """A linear form was asked of a model that is not linear."""


class NameClashError(ModelStructureError):
    """Two different things of a model would print with the same name
    (an input named ``p_m`` beside the state ``p_m`` of ``I('m')``)."""


class ParameterValueError(BondGraphError, ValueError):
    """Values given for parameters cannot be used: an unknown name, a
    missing value, or a value that is not a finite real number.

    Every call that takes parameter values (``plant``, ``batch``, ``subs``,
    ``simulate``, code-generation defaults, grey-box fits) raises this one
    class.

    Attributes
    ----------
    missing, unknown : tuple of str
        Parameter names that were not given / that the model does not know.
    """

    def __init__(self, message: str, *, missing: tuple = (), unknown: tuple = ()) -> None:
        super().__init__(message)
        self.missing = tuple(missing)
        self.unknown = tuple(unknown)


class MissingValueError(ParameterValueError):
    """A numeric evaluation was asked while some parameters have no value."""


class BondGraphWarning(UserWarning):
    """A model that is valid but probably not what was meant (a bond that
    points out of an I, C or R element).  Silence with
    ``warnings.simplefilter("ignore", bondgraph.BondGraphWarning)``."""
