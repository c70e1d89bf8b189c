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
from typing import TYPE_CHECKING, Mapping, Optional

import numpy as np

from ..errors import ParameterValueError
from ..parameters import ParameterValues, match_values, real_value
from ..elements.rules import check_model_values
from ..signals import t as T_SYM
from .operating import Equilibrium, EquilibriumError, _named
from .operating import equilibrium as explicit_equilibrium

if TYPE_CHECKING:
    from ..equations import StateEquations as Model

__all__ = ["equilibrium", "implicit_equilibrium"]


def equilibrium(model: "Model", values: ParameterValues, inputs: Optional[Mapping] = None, *,
                guess: Optional[Mapping] = None, fixed: Optional[Mapping] = None,
                tol: float = 1e-10, exact: bool = True,
                totals: Optional[Mapping] = None) -> Equilibrium:
    """:func:`implicit_equilibrium` for an implicit model, else
    :func:`bondgraph.linear.operating.equilibrium` (same arguments; ``totals`` only for an
    explicit model)."""
    if model.algebraic:
        if totals:
            raise EquilibriumError(f"model {model.name!r}: totals= is not supported for an "
                                   "implicit model (algebraic unknowns "
                                   f"{', '.join(model.algebraic_names)}); fix the conserved "
                                   "states with fixed= instead")
        return implicit_equilibrium(model, values, inputs, guess=guess, fixed=fixed, tol=tol)
    return explicit_equilibrium(model, values, inputs, guess=guess, fixed=fixed, tol=tol,
                                exact=exact, totals=totals)


def implicit_equilibrium(model: "Model", values: ParameterValues, inputs: Optional[Mapping] = None,
                         *, guess: Optional[Mapping] = None, fixed: Optional[Mapping] = None,
                         tol: float = 1e-10) -> Equilibrium:
    """``f(x, z, u) = 0``, ``g(x, z, u) = 0`` for the free states and ``z`` (see
    :func:`bondgraph.linear.equilibrium`; ``guess`` may also name algebraic unknowns).

    The two are solved as one system with the explicit trim's search; the
    stability verdict comes from the eigenvalues of ``A = f_x - f_z g_z^-1 g_x``.

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
    from . import trim as _trim

    tol = _trim.check_tol(tol, where, EquilibriumError)
    params = match_values(model.parameters, values, known=model.known_parameters, where=where,
                          inputs=model.input_names)
    pvals = {p: real_value(v, p.name, where) for p, v in params.items()}
    check_model_values(model, {p.name: v for p, v in pvals.items()}, where=where)
    u0 = {u: 0.0 for u in model.inputs}
    u0.update(_named(model, inputs, model.inputs, "input"))
    held = _named(model, fixed, model.states, "fixed state")
    start = _named(model, guess, model.states + model.algebraic, "guess state or algebraic unknown")
    unknowns = list(model.states) + list(model.algebraic)
    eqs = [ex.xreplace(pvals) for ex in model.rhs + model.residuals]
    _trim.check_finite_equations(model, eqs, pvals, where)
    ins = list(model.inputs)
    # f = 0 and g = 0 as one square system in (x, z): the explicit trim's search (scaled
    # residuals, both methods, the homotopy in the inputs, starts over the natural scales)
    system = _trim.Equations(eqs, unknowns, ins, [u0[u] for u in ins], where)
    free_idx = [i for i, x in enumerate(unknowns) if x not in held]
    free = [unknowns[i] for i in free_idx]
    x_start = np.array([held.get(x, start.get(x, 0.0)) for x in unknowns], dtype=float)
    found, how, tried, failure = _trim.solve(system, x_start, free_idx, tol)
    if found is None:
        text = (f"{where}no equilibrium found from the guess "
                f"({', '.join(f'{x.name}={v:g}' for x, v in zip(unknowns, x_start))})")
        if failure is not None:
            text += (f": closest point {', '.join(f'{x.name}={v:.6g}' for x, v in zip(unknowns, failure.x))}"
                     f" (scaled residual of f and g {failure.scaled_residual:.3g} > tol={tol:g})")
        raise EquilibriumError(
            text + f"; methods tried: {'; '.join(tried)}. Give another guess= (states and the "
            f"algebraic unknowns {', '.join(model.algebraic_names)})")
    n = len(model.states)
    how = how + " (f = 0 and g = 0 together)"
    algebraic = {z.name: float(v) for z, v in zip(model.algebraic, found.x[n:])}
    states = {x.name: float(v) for x, v in zip(model.states, found.x[:n])}
    inputs_out = {u.name: float(v) for u, v in u0.items()}
    named_values = {p.name: v for p, v in pvals.items()}
    if not system.differentiable_at(found.x):
        how += ("; the Jacobian is not finite at this point (a law with an infinite slope "
                "there): its isolation and stability are not decided")
        return Equilibrium(states, inputs_out, named_values, found.max_residual, "numeric",
                           how=how, scaled_residual=found.scaled_residual, condition=math.inf,
                           jacobian="not finite at the point", algebraic=algebraic)
    if found.singular:
        raise EquilibriumError(
            f"{where}the equilibrium is not isolated (or a law has zero slope there, such as "
            f"f|f| at f = 0): the Jacobian of f and g is singular there, so "
            f"{', '.join(_undetermined(found.jacobian, free))} are not determined to first "
            "order; hold states that can take any value with fixed={...}")
    eig, verdict = _reduced_stability(system.jac(found.x), n)
    return Equilibrium(states, inputs_out, named_values, found.max_residual, "numeric",
                       how=how, scaled_residual=found.scaled_residual,
                       condition=found.condition, jacobian=system.jacobian_kind,
                       eigenvalues=eig, stability=verdict, algebraic=algebraic)


def _reduced_stability(J: np.ndarray, n: int) -> tuple[tuple[complex, ...], str]:
    """Eigenvalues of ``A = f_x - f_z g_z^-1 g_x`` (the implicit-function theorem) from the
    Jacobian of ``(f, g)`` in ``(x, z)``, and the verdict of
    :func:`bondgraph.linear.trim.stability_of`."""
    from .trim import stability_of

    fx, fz, gx, gz = J[:n, :n], J[:n, n:], J[n:, :n], J[n:, n:]
    if not np.all(np.isfinite(J)) or (gz.size and np.linalg.matrix_rank(gz) < gz.shape[0]):
        return (), "unknown"
    A = fx - fz @ np.linalg.solve(gz, gx) if gz.size else fx
    return stability_of(A)


def _undetermined(J: np.ndarray, free) -> list[str]:
    """Unknowns along the null space of ``J`` (the ones no equation pins down)."""
    _, _, vt = np.linalg.svd(J)
    picked = [x.name for x, c in zip(free, vt[-1]) if abs(c) > 1e-6]
    return picked or [x.name for x in free]
