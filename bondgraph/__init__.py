"""bondgraph: bond graphs to symbolic state equations, transfer functions and plants.

The pipeline, one stage per folder or module, each importing only the stages
before it (checked by ``tests/test_layering.py``)::

    elements/      Se, Sf, I, C, R, TF, GY, MTF, MGY, 0, 1, Port, fields, Bond
        |          (the element protocol: the algorithms ask, the element answers)
    graph          BondGraph            mutable builder of frozen elements
    flatten        FlatGraph            sub-models joined, hierarchical names
    causality      AugmentedBondGraph   SCAP strokes, derivative causality, loops
    equations/     StateEquations       x' = f(x, u), y = g(x, u): the frozen record
    tf/            SymbolicTF           transfer functions of (A, B, C, D, E)
    linear/        SymbolicStateSpace   linear forms, linearization, equilibria
    numeric/       NumericStateSpace    compiled plants, simulation, plants at a point
    hamiltonian/   PortHamiltonian      x' = (J - R) grad H + G u
    model          Model, derive        the record with its verbs (the facade)

then the consumers of a :class:`Model`: :mod:`~bondgraph.export`,
:mod:`~bondgraph.modelfile`, :mod:`~bondgraph.codegen`, :mod:`~bondgraph.fmu`,
:mod:`~bondgraph.drawing`, :mod:`~bondgraph.drawing.plots`,
:mod:`~bondgraph.identification`, :mod:`~bondgraph.study`,
:mod:`~bondgraph.beam`, :mod:`~bondgraph.cli`.  Beside them:
:mod:`~bondgraph.errors`, :mod:`~bondgraph.signals`,
:mod:`~bondgraph.parameters` (the parameter policy),
:mod:`~bondgraph.examples` (stock graphs) and :mod:`~bondgraph.testing`
(the element conformance checks).

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

import sys as _sys
import types as _types

from ._support import moved as _moved


def _load() -> None:
    """Bind the public names (the first time one is asked for): ``import bondgraph`` itself
    loads no sympy, so ``bondgraph --help`` and ``import bondgraph.errors`` start at once."""
    from .errors import (AlgebraicLoopError, BondGraphError, BondGraphWarning, CausalityConflictError,
                         CausalityError, DuplicateNameError, LawError, ModelStructureError,
                         MissingValueError, NameClashError, NonlinearModelError, OutputError,
                         ParameterError, ParameterValueError, PortError, UnknownElementError)
    from .signals import Signal, displacement, e, effort, f, flow, momentum, p, q, t
    from .elements import (GY, MGY, MTF, TF, Bond, C, CField, Element, FieldError, I, ICField, IField,
                           One, Port, R, RField, Se, Sf, Zero)
    from .graph import BondGraph
    from .flatten import FlatGraph, flatten
    from .causality import AugmentedBondGraph, CausalBond, assign_causality
    from .linear import SymbolicStateSpace
    from .model import Model, derive
    from .modelfile import ModelDefinition, ModelFileError, load_model

    # the notebook display, drawn by bondgraph.drawing when shown (imported then)
    for cls in (BondGraph, AugmentedBondGraph, Model):
        if not hasattr(cls, "_repr_svg_"):
            setattr(cls, "_repr_svg_", _repr_svg_)
    globals().update({k: v for k, v in locals().items() if k in __all__})


#: names bound from their own module on first use: numeric plants and simulation (scipy),
#: exports and drawings are loaded only by what uses them
_LATER = {**dict.fromkeys(("BatchStateSpace", "ImproperPlantError", "NumericModel",
                           "NumericStateSpace", "SimulationResult", "compile_plant", "numeric_plant",
                           "simulate", "to_nonlinear_iosys"), "numeric"),
          "ExportError": "export", "draw": "drawing"}


def _repr_svg_(self):
    """SVG of the bond graph for Jupyter (see :func:`bondgraph.drawing.repr_svg`)."""
    from .drawing import repr_svg

    return repr_svg(self)


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


_moved.install()


def __getattr__(name: str):
    """The public names, bound on first use (see :func:`_load`); ``bg.sweep`` /
    ``bg.sensitivity`` load the study package then (no pandas or dask before)."""
    if name in ("sweep", "sensitivity"):
        from . import study

        return getattr(study, name)
    if name in _LATER:
        import importlib

        value = getattr(importlib.import_module(f"{__name__}.{_LATER[name]}"), name)
        globals()[name] = value
        return value
    if name in __all__:
        _load()
        return globals()[name]
    if not name.startswith("_") and _is_submodule(name):     # bg.numeric, bg.export, ...
        import importlib

        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _is_submodule(name: str) -> bool:
    from pathlib import Path

    here = Path(__file__).parent
    return name.isidentifier() and ((here / name / "__init__.py").is_file() or (here / f"{name}.py").is_file())


def __dir__() -> list:
    return sorted(set(globals()) | set(__all__))


class _Package(_types.ModuleType):
    """The package module: importing the submodule ``bondgraph.flatten`` must not hide the
    function ``bondgraph.flatten`` (the import system sets the package attribute)."""

    def __setattr__(self, name: str, value) -> None:
        if name == "flatten" and isinstance(value, _types.ModuleType):
            value = value.flatten
        super().__setattr__(name, value)


_sys.modules[__name__].__class__ = _Package
