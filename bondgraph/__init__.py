"""bondgraph: bond graphs to symbolic state equations, transfer functions and plants.

The pipeline, one module each: :mod:`~bondgraph.graph` (build) ->
:mod:`~bondgraph.flatten` (sub-models) -> :mod:`~bondgraph.causality` (SCAP) ->
:mod:`~bondgraph.equations` (derive) -> :mod:`~bondgraph.model` (state space).

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("dc_motor")
>>> V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
>>> g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
>>> for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
...     _ = g.connect(tail, head)
>>> model = bg.derive(g, outputs={"omega": bg.flow("J")})
>>> model.state_space().A
Matrix([
[-Ra/La, -K/J],
[  K/La, -b/J]])
"""

from .causality import AugmentedBondGraph, CausalBond, assign_causality
from .elements import GY, MGY, MTF, TF, C, Element, I, One, Port, R, Se, Sf, Zero
from .equations import derive
from .fields import CField, FieldError, ICField, IField, RField
from .errors import (AlgebraicLoopError, BondGraphError, BondGraphWarning, CausalityConflictError,
                     CausalityError, DuplicateNameError, LawError, ModelStructureError,
                     MissingValueError, NameClashError, NonlinearModelError, OutputError,
                     ParameterError, ParameterValueError, PortError, UnknownElementError)
from .flatten import FlatGraph, flatten
from .graph import Bond, BondGraph
from .model import Model
from .signals import Signal, displacement, e, effort, f, flow, momentum, p, q, t
from .statespace import SymbolicStateSpace
from .modelfile import ModelDefinition, ModelFileError, load_model
from .numeric import (BatchStateSpace, ImproperPlantError, NumericModel, NumericStateSpace,
                      SimulationResult, compile_plant, numeric_plant, simulate,
                      to_nonlinear_iosys)
from .export import ExportError
from .drawing import draw

__version__ = "0.1.0"

__all__ = [
    "BondGraph", "Bond", "FlatGraph", "flatten",
    "Element", "Se", "Sf", "I", "C", "R", "TF", "GY", "MTF", "MGY", "Zero", "One", "Port",
    "IField", "CField", "ICField", "RField", "FieldError",
    "AugmentedBondGraph", "CausalBond", "assign_causality",
    "derive", "Model", "SymbolicStateSpace",
    "Signal", "effort", "flow", "displacement", "momentum", "p", "q", "e", "f", "t",
    "BondGraphError", "ModelStructureError", "DuplicateNameError", "UnknownElementError",
    "PortError", "ParameterError", "LawError", "CausalityError", "CausalityConflictError",
    "AlgebraicLoopError", "OutputError", "NonlinearModelError", "NameClashError",
    "BondGraphWarning",
    "ModelDefinition", "ModelFileError", "load_model",
    "compile_plant", "numeric_plant", "NumericModel", "NumericStateSpace", "BatchStateSpace",
    "simulate", "SimulationResult", "to_nonlinear_iosys", "ParameterValueError", "MissingValueError",
    "ImproperPlantError",
    "ExportError", "draw",
]

__all__ += ["sweep", "sensitivity"]


def __getattr__(name: str):
    """``bg.sweep`` / ``bg.sensitivity`` on first use: ``import bondgraph`` loads no pandas or dask."""
    if name in ("sweep", "sensitivity"):
        from . import study

        return getattr(study, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
