"""The numeric plant at an operating point: a model linearized there at parameter values.

:meth:`bondgraph.Model.linearize` calls :func:`linear_plant` when it is given
numeric parameter values or an :class:`~bondgraph.linear.Equilibrium`.

Examples
--------
>>> from bondgraph import examples
>>> from bondgraph.equations import derive_equations
>>> from bondgraph.numeric import linear_plant
>>> plant = linear_plant(derive_equations(examples.rc()), {"q_C": 1.0}, {"V": 1.0},
...                      {"R": 2.0, "C": 1.0}, tol=1e-9)
>>> plant.A, plant.B
(array([[-0.5]]), array([[0.5]]))
"""

from __future__ import annotations

from typing import Any, Mapping, Optional

import numpy as np
import sympy

from ..equations import StateEquations
from ..errors import BondGraphError
from ..linear import Equilibrium, EquilibriumError, linearize
from ..linear.operating import equilibrium_scaled
from ..errors import ParameterValueError
from ..parameters import ParameterValues, match_values, real_value
from ..elements.rules import check_model_values
from .implicit import implicit_plant
from .statespace import NumericStateSpace

__all__ = ["linear_plant"]


def linear_plant(model: StateEquations, point: Equilibrium | Mapping, inputs: Optional[Mapping],
                 values: ParameterValues, tol: float, equilibrium: bool = True) -> Any:
    """Numeric plant of ``model`` linearized at ``point`` (see :meth:`Model.linearize`).

    ``equilibrium=False`` linearizes about a point that is not an equilibrium
    (the drift ``f(x0, u0)`` is dropped) instead of refusing it.  The plant's
    ``operating_point`` holds ``x0``, ``u0`` and the outputs there.
    """
    plant = _linear_plant(model, point, inputs, values, tol, equilibrium)
    return plant.with_operating_point(_point_of(model, point, inputs, values, equilibrium))


def _point_of(model: StateEquations, point, inputs, values, equilibrium: bool):
    """The numeric :class:`~bondgraph.linear.OperatingPoint` of ``point``."""
    from ..linear import numeric_operating_point

    if isinstance(point, Equilibrium):
        return numeric_operating_point(model, point)
    where = f"model {model.name!r}: "
    params = match_values(model.parameters, values, known=model.known_parameters, where=where)
    x0 = {str(getattr(k, "name", k)): real_value(v, str(getattr(k, "name", k)), where)
          for k, v in dict(point or {}).items()}
    u0 = {str(getattr(k, "name", k)): real_value(v, str(getattr(k, "name", k)), where)
          for k, v in dict(inputs or {}).items()}
    eq = Equilibrium({s.name: x0.get(s.name, 0.0) for s in model.states},
                     {u.name: u0.get(u.name, 0.0) for u in model.inputs},
                     {p.name: real_value(v, p.name, where) for p, v in params.items()},
                     method="given", how="given" if equilibrium else
                     "given (not checked as an equilibrium)")
    return numeric_operating_point(model, eq)


def _linear_plant(model: StateEquations, point: Equilibrium | Mapping, inputs: Optional[Mapping],
                  values: ParameterValues, tol: float, equilibrium: bool = True) -> Any:
    if model.algebraic:       # implicit: the implicit-function theorem
        return implicit_plant(model, point, inputs, values, tol, equilibrium=equilibrium)
    where = f"model {model.name!r}: "
    if isinstance(point, Equilibrium):
        x0, u0 = dict(point.states), dict(point.inputs)
        if inputs is not None:
            raise BondGraphError(f"{where}give the inputs in the Equilibrium, not again as u0")
    else:
        x0, u0 = dict(point or {}), dict(inputs or {})
    params = match_values(model.parameters, values, known=model.known_parameters, where=where,
                          inputs=model.input_names)
    pvals = {p: sympy.Float(real_value(v, p.name, where), 17) for p, v in params.items()}
    check_model_values(model, {p.name: float(v) for p, v in pvals.items()}, where=where)
    if _at_kink(model, x0, u0, pvals):
        # sign(0)**2 = 0 in a symbolic slope that is a/(2 sqrt b) from both sides: the mean
        # of the plants just beside the point (the point itself is checked first)
        _check_point(model, x0, u0, pvals, tol, equilibrium, where)
        return _beside_mean(model, x0, u0, values, tol)
    lin = linearize(model, x0, u0, equilibrium=False)
    num = lin.subs({p.name: v for p, v in pvals.items()}, partial=False) if lin.parameters else lin
    _check_point(model, x0, u0, pvals, tol, equilibrium, where)

    def arr(M):
        return np.array([[float(M[i, j]) for j in range(M.cols)] for i in range(M.rows)],
                        dtype=float).reshape(M.shape)
    return NumericStateSpace(arr(num.A), arr(num.B), arr(num.C), arr(num.D), lin.state_names,
                             lin.input_names, lin.output_names,
                             {p.name: float(v) for p, v in pvals.items()}, model.name,
                             D_derivatives=tuple(arr(M) for M in num.D_derivatives))


def _check_point(model: StateEquations, x0: Mapping, u0: Mapping, pvals: Mapping, tol: float,
                 equilibrium: bool, where: str) -> None:
    """:class:`EquilibriumError` when ``equilibrium`` is asked and ``f(x0, u0) != 0``."""
    if not equilibrium:
        return
    f0 = [float(r.xreplace({**{s: sympy.Float(x0[s.name], 17) for s in model.states},
                            **{u: sympy.Float(u0.get(u.name, 0.0), 17) for u in model.inputs},
                            **pvals})) for r in model.rhs]
    if f0 and max(abs(v) for v in f0) > tol * max(1.0, max(abs(v) for v in x0.values()) if x0 else 1.0) \
            and not equilibrium_scaled(model, x0, u0, pvals, tol):
        raise EquilibriumError(
            f"{where}the operating point is not an equilibrium at these values: "
            + ", ".join(f"d{s.name}/dt = {v:.3g}" for s, v in zip(model.states, f0) if abs(v) > tol)
            + "; use model.equilibrium(...) to find one")


def _at_kink(model: StateEquations, x0: Mapping, u0: Mapping, pvals: Mapping) -> bool:
    """An argument of ``sign``, ``Abs`` or ``Heaviside`` is exactly 0 at the point."""
    from ..linear.trim import at_kink

    at = {**{s: sympy.Float(x0[s.name], 17) for s in model.states if s.name in x0},
          **{u: sympy.Float(u0.get(u.name, 0.0), 17) for u in model.inputs}, **pvals}
    return at_kink(list(model.rhs) + list(model.output_exprs), at)


def _beside_mean(model: StateEquations, x0: Mapping, u0: Mapping, values: ParameterValues,
                 tol: float) -> NumericStateSpace:
    """The mean of the plants at ``(x0, u0) +- h`` (:func:`bondgraph.linear.trim.beside`)."""
    from ..linear.trim import beside

    names = [s.name for s in model.states] + [u.name for u in model.inputs]
    base = np.array([float(x0[n]) if n in x0 else float(u0.get(n, 0.0)) for n in names])
    h = beside(base)
    plants = []
    for sgn in (1.0, -1.0):
        v = dict(zip(names, (base + sgn * h).tolist()))
        plants.append(_linear_plant(model, {s.name: v[s.name] for s in model.states},
                                   {u.name: v[u.name] for u in model.inputs}, values, tol,
                                   equilibrium=False))
    a, b = plants
    return NumericStateSpace(0.5 * (a.A + b.A), 0.5 * (a.B + b.B), 0.5 * (a.C + b.C),
                             0.5 * (a.D + b.D), a.state_names, a.input_names, a.output_names,
                             dict(a.parameters), model.name,
                             D_derivatives=tuple(0.5 * (p + q) for p, q in
                                                 zip(a.D_derivatives, b.D_derivatives)))
