"""Operating points: equilibria (trim) of a nonlinear model, and the plant there.

:func:`equilibrium` solves ``f(x, u) = 0`` for the states at given inputs
and parameter values: exactly with sympy for small polynomial systems (every
real solution, the one nearest ``guess`` returned), else numerically with
:func:`scipy.optimize.root` from ``guess``.  The point found must be
isolated (the Jacobian of the free states is non-singular there); states
that no equation determines (the angle of a freely spinning shaft) are given
with ``fixed=``.  :meth:`bondgraph.Model.linearize` accepts the result and
numeric parameter values and then returns a numeric plant
(:func:`bondgraph.numeric.linear_plant`).

Examples
--------
A mass hanging on a spring ``c`` (compliance) under gravity ``m g``: the
spring stretches ``m g c``.

>>> import sympy, bondgraph as bg
>>> m, g_ = sympy.symbols("m g", positive=True)
>>> gr = bg.BondGraph("hang")
>>> v = bg.One("v")
>>> gr.add(bg.Se("W", value=m * g_), v, bg.I("m", m), bg.C("c"), bg.R("b"))
>>> for t, h in [("W", v), (v, "m"), (v, "c"), (v, "b")]: _ = gr.connect(t, h)
>>> eq = bg.derive(gr).equilibrium({"m": 2.0, "g": 9.81, "c": 0.01, "b": 1.0})
>>> round(eq.states["q_c"], 6), eq.states["p_m"], eq.method
(0.1962, 0.0, 'exact')
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Mapping, Optional

import numpy as np
import sympy

from ..errors import NonlinearModelError
from ..parameters import ParameterValues, match_values, real_value
from ..signals import t as T_SYM

if TYPE_CHECKING:
    from ..equations import StateEquations as Model

__all__ = ["Equilibrium", "EquilibriumError", "equilibrium"]

#: largest number of free states tried with sympy's exact solver
EXACT_MAX_STATES = 4


class EquilibriumError(NonlinearModelError):
    """No equilibrium was found, or the one found is not isolated."""


@dataclass(frozen=True)
class Equilibrium:
    """An operating point ``f(x0, u0) = 0`` of a model at given parameter values.

    Attributes
    ----------
    states, inputs : mapping of name to float
        ``x0`` and ``u0``.
    values : mapping of name to float
        The parameter values it holds for.
    residual : float
        ``max |f(x0, u0)|``.
    method : {"exact", "numeric"}
        sympy's solution (evaluated to float) or :func:`scipy.optimize.root`.
    """

    states: Mapping[str, float]
    inputs: Mapping[str, float]
    values: Mapping[str, float] = field(repr=False)
    residual: float = 0.0
    method: str = "numeric"

    def __post_init__(self) -> None:
        for name in ("states", "inputs", "values"):
            object.__setattr__(self, name, MappingProxyType(dict(getattr(self, name))))

    def __reduce__(self):
        return (Equilibrium, (dict(self.states), dict(self.inputs), dict(self.values),
                              self.residual, self.method))


def _named(model: "Model", given: Optional[Mapping], symbols, what: str) -> dict[sympy.Symbol, float]:
    by_name = {s.name: s for s in symbols}
    out: dict[sympy.Symbol, float] = {}
    for key, value in dict(given or {}).items():
        name = key.name if isinstance(key, sympy.Symbol) else key
        if not isinstance(name, str) or name not in by_name:
            raise EquilibriumError(
                f"model {model.name!r}: {what} {name!r} is not one of "
                f"{', '.join(by_name) or '(none)'}")
        out[by_name[name]] = real_value(value, name, f"model {model.name!r}: {what} ")
    return out


def equilibrium(model: "Model", values: ParameterValues, inputs: Optional[Mapping] = None, *,
                guess: Optional[Mapping] = None, fixed: Optional[Mapping] = None,
                tol: float = 1e-10, exact: bool = True) -> Equilibrium:
    """Solve ``f(x, u) = 0`` for the states (trim).

    Parameters
    ----------
    model : Model
        Any derived model (nonlinear allowed); it must not depend on time or
        on input derivatives.
    values : mapping of parameter name (or Symbol) to number
        A value for every parameter (the package's parameter policy).
    inputs : mapping of input name to number, optional
        Input values ``u0``; inputs not given are 0.
    guess : mapping of state name to number, optional
        Starting point of the numeric solve and tie-break among exact
        solutions (nearest in the Euclidean norm); states not given start at 0.
    fixed : mapping of state name to number, optional
        States held at a value and left out of the solve (states that no
        equation determines, such as the angle of a free shaft).
    tol : float
        Largest accepted ``|f|`` at the solution.
    exact : bool
        Try sympy's exact solver first for up to :data:`EXACT_MAX_STATES`
        free states of polynomial equations.

    Returns
    -------
    Equilibrium

    Raises
    ------
    EquilibriumError
        No solution (the message gives the residual reached), a solution that
        is not isolated (singular Jacobian: a state no equation determines;
        fix it), a model that depends on time.
    ParameterValueError
        Parameter values that do not follow the package's policy.

    Examples
    --------
    A DC motor at constant voltage: ``omega = K V / (K^2 + Ra b)``.

    >>> import bondgraph as bg
    >>> g = bg.BondGraph("dc")
    >>> i, w = bg.One("i"), bg.One("w")
    >>> g.add(bg.Se("V"), i, bg.R("Ra"), bg.I("La"), bg.GY("K"), w, bg.I("J"), bg.R("b"))
    >>> for t, h in [("V", i), (i, "Ra"), (i, "La"), (i, "K"), ("K", w), (w, "J"), (w, "b")]:
    ...     _ = g.connect(t, h)
    >>> eq = bg.derive(g).equilibrium({"Ra": 2.0, "La": 1e-3, "K": 0.1, "J": 0.01, "b": 1e-3},
    ...                               {"V": 12.0})
    >>> round(eq.states["p_J"] / 0.01, 9)      # omega = 0.1*12/(0.01 + 2e-3)
    100.0
    """
    where = f"model {model.name!r}: "
    exprs = list(model.rhs)
    bad = set(model.input_derivatives) | {T_SYM}
    for ex in exprs:
        if ex.free_symbols & bad:
            raise EquilibriumError(f"{where}the state equations depend on "
                                   f"{', '.join(sorted(map(str, ex.free_symbols & bad)))}; "
                                   "an equilibrium needs a time-invariant model")
    params = match_values(model.parameters, values, known=model.known_parameters, where=where)
    pvals = {p: real_value(v, p.name, where) for p, v in params.items()}
    u0 = {u: 0.0 for u in model.inputs}
    u0.update(_named(model, inputs, model.inputs, "input"))
    held = _named(model, fixed, model.states, "fixed state")
    start = _named(model, guess, model.states, "guess state")
    free = [x for x in model.states if x not in held]
    if not free:
        raise EquilibriumError(f"{where}every state is fixed; nothing to solve")
    known = {**pvals, **u0, **held}
    eqs = [ex.xreplace(known) for ex in exprs]
    x_start = np.array([start.get(x, 0.0) for x in free])
    solution, method = None, "numeric"
    if exact and len(free) <= EXACT_MAX_STATES:
        solution = _exact(eqs, free, x_start)
        method = "exact" if solution is not None else method
    f = sympy.lambdify([free], eqs, modules="numpy")
    jac = sympy.lambdify([free], sympy.Matrix(eqs).jacobian(free), modules="numpy")

    def fun(x):
        return np.asarray(f(x), dtype=float)

    if solution is None:
        from scipy.optimize import root

        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore", RuntimeWarning)
            sol = root(fun, x_start, jac=lambda x: np.asarray(jac(x), dtype=float), tol=tol * 1e-2)
        solution = np.asarray(sol.x, dtype=float)
    res = fun(solution)
    residual = float(np.max(np.abs(res))) if res.size else 0.0
    if not np.all(np.isfinite(solution)) or not math.isfinite(residual) or residual > tol:
        raise EquilibriumError(
            f"{where}no equilibrium found from the guess "
            f"({', '.join(f'{x.name}={v:g}' for x, v in zip(free, x_start))}): the residual "
            f"max|f| reached {residual:.3g} > tol={tol:g}; give another guess=, or check that "
            "the inputs admit an equilibrium (a constant force on a free mass has none)")
    J = np.asarray(jac(solution), dtype=float)
    if J.size and np.linalg.matrix_rank(J, tol=1e-9 * max(1.0, np.abs(J).max())) < len(free):
        loose = _undetermined(J, free)
        raise EquilibriumError(
            f"{where}the equilibrium is not isolated: the Jacobian of the state equations is "
            f"singular there, so {', '.join(loose)} can take any value; hold such states "
            "with fixed={...}")
    states = {x.name: float(held[x]) if x in held else float(solution[free.index(x)])
              for x in model.states}
    return Equilibrium(states, {u.name: float(v) for u, v in u0.items()},
                       {p.name: v for p, v in pvals.items()}, residual, method)


def _exact(eqs, free, x_start) -> Optional[np.ndarray]:
    """The real solution of polynomial ``eqs`` nearest ``x_start``, or None."""
    nums = [sympy.together(e).as_numer_denom()[0] for e in eqs]
    if not all(n.is_polynomial(*free) for n in nums):
        return None
    nums = [sympy.nsimplify(n, rational=True) for n in nums]
    try:
        sols = sympy.solve(nums, free, dict=True)
    except (NotImplementedError, ValueError, TypeError):
        return None
    best, best_d = None, math.inf
    for sol in sols:
        if set(sol) != set(free):
            return None         # a family of solutions: not isolated; let the check say so
        try:
            vec = np.array([complex(sympy.N(sol[x], 30)) for x in free])
        except TypeError:
            continue
        if np.any(np.abs(vec.imag) > 1e-12 * (1 + np.abs(vec.real))):
            continue
        d = float(np.linalg.norm(vec.real - x_start))
        if d < best_d:
            best, best_d = vec.real, d
    return best


def _undetermined(J: np.ndarray, free) -> list[str]:
    """States along the null space of ``J`` (the ones no equation pins down)."""
    _, s, vt = np.linalg.svd(J)
    null = vt[-1]
    picked = [x.name for x, c in zip(free, null) if abs(c) > 1e-6]
    return picked or [x.name for x in free]
