"""Equilibria of implicit models: ``f(x, z, u) = 0`` and ``g(x, z, u) = 0`` solved together.

An implicit model (:mod:`bondgraph.equations.implicit`) keeps algebraic
unknowns ``z`` with residuals ``0 = g(x, z, u)``.  Its operating point
solves the state equations and the residuals as one square system in the
free states and ``z``, with :func:`scipy.optimize.root` and the analytic
Jacobian; the point must be isolated (that Jacobian non-singular).
:func:`bondgraph.linear.equilibrium` calls :func:`implicit_equilibrium` for
such a model.

Examples
--------
A capacitor discharging through a resistor and a diode ``f = Is (exp(e/Vt) - 1)``
in series, charged from ``V`` through ``R1``: at equilibrium the current
through ``R1 + R`` and the diode is the same.

>>> import numpy as np, sympy, bondgraph as bg
>>> Is, Vt = sympy.symbols("Is Vt", positive=True)
>>> g = bg.BondGraph("charger")
>>> g.add(bg.Se("V"), bg.One("a"), bg.R("R1"), bg.Zero("n"), bg.C("C"), bg.One("s"), bg.R("R"),
...       bg.R("D", inverse=Is*(sympy.exp(bg.e/Vt) - 1)))
>>> for t, h in [("V", "a"), ("a", "R1"), ("a", "n"), ("n", "C"), ("n", "s"), ("s", "R"), ("s", "D")]:
...     _ = g.connect(t, h)
>>> vals = {"R1": 500.0, "R": 500.0, "C": 1e-6, "Is": 1e-12, "Vt": 0.025}
>>> eq = bg.derive(g).equilibrium(vals, {"V": 5.0})
>>> i = eq.algebraic["f_D"]
>>> bool(np.isclose(5.0 - 1000.0 * i, 0.025 * np.log1p(i / 1e-12)))   # KVL round the loop
True
"""

from __future__ import annotations

import math
import warnings
from typing import TYPE_CHECKING, Mapping, Optional

import numpy as np
import sympy

from ..parameters import ParameterValues, match_values, real_value
from ..signals import t as T_SYM
from .operating import Equilibrium, EquilibriumError, _named
from .operating import equilibrium as explicit_equilibrium

if TYPE_CHECKING:
    from ..equations import StateEquations as Model

__all__ = ["equilibrium", "implicit_equilibrium"]


def equilibrium(model: "Model", values: ParameterValues, inputs: Optional[Mapping] = None, *,
                guess: Optional[Mapping] = None, fixed: Optional[Mapping] = None,
                tol: float = 1e-10, exact: bool = True) -> Equilibrium:
    """:func:`implicit_equilibrium` for an implicit model, else
    :func:`bondgraph.linear.operating.equilibrium` (same arguments)."""
    if model.algebraic:
        return implicit_equilibrium(model, values, inputs, guess=guess, fixed=fixed, tol=tol)
    return explicit_equilibrium(model, values, inputs, guess=guess, fixed=fixed, tol=tol,
                                exact=exact)


def implicit_equilibrium(model: "Model", values: ParameterValues, inputs: Optional[Mapping] = None,
                         *, guess: Optional[Mapping] = None, fixed: Optional[Mapping] = None,
                         tol: float = 1e-10) -> Equilibrium:
    """``f(x, z, u) = 0``, ``g(x, z, u) = 0`` for the free states and ``z`` (see
    :func:`bondgraph.linear.equilibrium`; ``guess`` may also name algebraic unknowns).

    Raises
    ------
    EquilibriumError
        No solution within ``tol`` from the guess, a point that is not
        isolated, a model that depends on time.
    """
    where = f"model {model.name!r}: "
    bad = set(model.input_derivatives) | {T_SYM}
    for ex in model.rhs + model.residuals:
        if ex.free_symbols & bad:
            raise EquilibriumError(f"{where}the equations depend on "
                                   f"{', '.join(sorted(map(str, ex.free_symbols & bad)))}; "
                                   "an equilibrium needs a time-invariant model")
    params = match_values(model.parameters, values, known=model.known_parameters, where=where)
    pvals = {p: real_value(v, p.name, where) for p, v in params.items()}
    u0 = {u: 0.0 for u in model.inputs}
    u0.update(_named(model, inputs, model.inputs, "input"))
    held = _named(model, fixed, model.states, "fixed state")
    start = _named(model, guess, model.states + model.algebraic, "guess state or algebraic unknown")
    free = [x for x in model.states if x not in held] + list(model.algebraic)
    known = {**pvals, **u0, **held}
    eqs = [ex.xreplace(known) for ex in model.rhs + model.residuals]
    f = sympy.lambdify([free], eqs, modules="numpy")
    jac = sympy.lambdify([free], sympy.Matrix(eqs).jacobian(free).replace(     # DiracDelta: 0 off
        sympy.DiracDelta, lambda *a: sympy.S.Zero), modules="numpy")             # the jump

    def fun(v):
        return np.asarray(f(v), dtype=float)

    x_start = np.array([start.get(x, 0.0) for x in free])
    from scipy.optimize import root

    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)
        sol = root(fun, x_start, jac=lambda v: np.asarray(jac(v), dtype=float), tol=tol * 1e-2)
        solution = np.asarray(sol.x, dtype=float)
        res = fun(solution)
    residual = float(np.max(np.abs(res))) if res.size else 0.0
    if not np.all(np.isfinite(solution)) or not math.isfinite(residual) or residual > tol:
        raise EquilibriumError(
            f"{where}no equilibrium found from the guess "
            f"({', '.join(f'{x.name}={v:g}' for x, v in zip(free, x_start))}): the residual "
            f"max|f, g| reached {residual:.3g} > tol={tol:g}; give another guess= (states and "
            f"the algebraic unknowns {', '.join(model.algebraic_names)})")
    J = np.asarray(jac(solution), dtype=float)
    if J.size and np.linalg.matrix_rank(J, tol=1e-9 * max(1.0, np.abs(J).max())) < len(free):
        raise EquilibriumError(
            f"{where}the equilibrium is not isolated: the Jacobian of f and g is singular "
            f"there, so {', '.join(_undetermined(J, free))} can take any value; hold such "
            "states with fixed={...}")
    at = dict(zip(free, solution.tolist()))
    states = {x.name: float(held[x]) if x in held else float(at[x]) for x in model.states}
    return Equilibrium(states, {u.name: float(v) for u, v in u0.items()},
                       {p.name: v for p, v in pvals.items()}, residual, "numeric",
                       how="scipy.optimize.root (hybr) on f = 0 and g = 0 together, analytic "
                           "Jacobian, from the guess",
                       algebraic={z.name: float(at[z]) for z in model.algebraic})


def _undetermined(J: np.ndarray, free) -> list[str]:
    """Unknowns along the null space of ``J`` (the ones no equation pins down)."""
    _, _, vt = np.linalg.svd(J)
    picked = [x.name for x, c in zip(free, vt[-1]) if abs(c) > 1e-6]
    return picked or [x.name for x in free]
