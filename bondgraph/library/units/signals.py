"""The units of a derived model's signals: states, inputs, outputs and parameters.

:func:`model_units` gives each signal's dimension (SI base exponents) from
the graph's dimensional check (:func:`bondgraph.library.units.check_units`)
and the unit-carrying parameter values; :func:`unit_text` prints one as a
named unit where one matches (``'newton'``, ``'meter/second'``), else in
SI base units; :func:`ratio_text` prints the unit of a transfer function
(output over input).  These are what a
:class:`~bondgraph.modelfile.ModelDefinition` with unit-carrying
parameters hands to its plants, the command line's tables and the exports.

Examples
--------
>>> import bondgraph as bg, sympy.physics.units as u
>>> g = bg.BondGraph("mass")
>>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
>>> model = bg.derive(g, outputs={"v": bg.flow("m")})
>>> dims = model_units(model, g, {"m": 2 * u.kilogram}, domains={"F": "translation"})
>>> {k: unit_text(d) for k, d in dims.items()}
{'p_m': 'kilogram*meter/second', 'F': 'newton', 'v': 'meter/second', 'm': 'kilogram'}
>>> ratio_text(dims["v"], dims["F"])
'(meter/second)/newton'
"""

from __future__ import annotations

from typing import Any, Mapping, Optional

import sympy
import sympy.physics.units as u

from ...graph import BondGraph
from ...model import Model
from ...numeric import NumericStateSpace
from ...signals import t as T_SYM
from ._dims import NAMED, Dim, Mismatch, Unknown, dims_of, si_value, text, unit_dims

__all__ = ["model_units", "plant_with_units", "unit_text", "ratio_text", "unit_dims"]


def model_units(model: Model, graph: BondGraph, values: Mapping[str, Any], *,
                domains: Optional[Mapping] = None) -> dict[str, Dim]:
    """Dimensions of the model's states, inputs and outputs, and of unit-carrying parameters.

    Runs :func:`bondgraph.library.units.check_units` on ``graph`` (so a wrong unit is
    refused here too); an output whose dimension cannot be known (a
    parameter without units in it) is left out.
    """
    from .check import UnitError, check_units

    if not hasattr(model, "states") and hasattr(model, "switches"):
        raise UnitError(f"model {getattr(model, 'name', '?')!r} is switched (a SwitchedModel): "
                        "plant_with_units and export_fmu_with_units take an ordinary model; export "
                        "a switched model with bondgraph.fmu.export_fmu and SI values")
    report = check_units(graph, values, domains=domains)
    out: dict[str, Dim] = {}
    known: dict = {T_SYM: unit_dims(u.second)}
    for sym in (*model.states, *model.inputs):
        if sym.name in report.dims:
            out[sym.name] = known[sym] = report.dims[sym.name]
    for name, v in values.items():
        if isinstance(v, sympy.Basic) and v.atoms(u.Quantity):
            d = si_value(v)[1]
            for p in model.parameters:
                if p.name == name:
                    known[p] = d
    for name, ex in zip(model.output_names, model.output_exprs):
        try:
            out[name] = dims_of(ex, known)
        except (Unknown, Mismatch):
            continue
    for p in model.parameters:
        if p in known:
            out[p.name] = known[p]
    return out


def plant_with_units(model: Model, graph: BondGraph, values: Mapping[str, Any], *,
                     domains: Optional[Mapping] = None) -> NumericStateSpace:
    """The numeric plant at unit-carrying ``values`` (in SI), carrying its signals' units.

    ``values`` as for :func:`model_units` (numbers carrying units are converted
    to SI, bare numbers taken as SI); the plant's
    :attr:`~bondgraph.numeric.NumericStateSpace.units` are those of its
    states, inputs and outputs, which its ``to_control()`` and the ``.mat`` and
    JSON exports keep.

    Examples
    --------
    >>> import bondgraph as bg, sympy.physics.units as u
    >>> g = bg.BondGraph("rc")
    >>> g.add(bg.Se("V"), bg.One("i"), bg.R("R"), bg.C("C"))
    >>> for t, h in [("V", "i"), ("i", "R"), ("i", "C")]: _ = g.connect(t, h)
    >>> model = bg.derive(g, outputs={"vC": bg.effort("C")})
    >>> p = plant_with_units(model, g, {"R": 2 * u.kilo * u.ohm, "C": 5 * u.micro * u.farad},
    ...                      domains={"V": "electrical"})
    >>> float(p.A[0, 0]), dict(p.units)          # -1/(R C) = -100 per second
    (-100.0, {'q_C': 'coulomb', 'V': 'volt', 'vC': 'volt'})
    """
    from ...numeric import compile_plant
    from .check import si_values

    dims = model_units(model, graph, values, domains=domains)
    plant = compile_plant(model).plant(si_values(values))
    signals = {*plant.state_names, *plant.input_names, *plant.output_names}
    return plant.with_units({k: text(d) for k, d in dims.items() if k in signals})


def unit_text(d: Dim) -> str:
    """A dimension (as :func:`model_units` gives it) as a unit text.

    Examples
    --------
    >>> unit_text(unit_dims(u.kilogram * u.meter / u.second**2))
    'newton'
    """
    return text(tuple(d))


def ratio_text(num: Dim, den: Dim) -> str:
    """The unit of ``num / den``: a transfer function's unit from its output's and input's.

    A named unit when one matches the ratio, else the two units as a quotient.

    Examples
    --------
    >>> ratio_text(unit_dims(u.volt), unit_dims(u.ampere))
    'ohm'
    >>> ratio_text(unit_dims(u.meter / u.second), unit_dims(u.volt))
    '(meter/second)/volt'
    """
    d = tuple(a - b for a, b in zip(num, den))
    named = text(d)
    if all(x == 0 for x in d[:-1]) or any(name == named for name, _ in NAMED):
        return named
    a, b = text(tuple(num)), text(tuple(den))
    return f"{_grouped(a)}/{_grouped(b)}"


def _grouped(t: str) -> str:
    return t if t.isidentifier() else f"({t})"
