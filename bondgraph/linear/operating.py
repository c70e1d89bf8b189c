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
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Mapping, Optional

import numpy as np
import sympy

from ..errors import NonlinearModelError
from ..errors import ParameterValueError
from ..parameters import ParameterValues, match_values, real_value
from ..elements.rules import check_model_values
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
        ``max |f(x0, u0)|`` (in the model's units).
    method : {"exact", "numeric"}
        sympy's solution (evaluated to float) or :func:`scipy.optimize.root`.
    how : str
        The method in words: the solver, its Jacobian and its start (the
        guess, a homotopy in the inputs, or one of several starts).
    scaled_residual : float
        The largest ``|f_i|`` divided by the size of equation ``i`` (the sum
        of its terms' magnitudes, or the scale the equilibrated Jacobian gives
        it); independent of the units.  It is at most ``tol``.
    condition : float
        Condition number of the Jacobian of the free states after row and
        column equilibration (independent of the units).
    jacobian : str
        ``"symbolic"`` (lambdified ``df/dx``), or ``"finite differences"``
        when the symbolic Jacobian could not be evaluated.
    eigenvalues : tuple of complex
        Of ``df/dx`` at the point (every state).
    stability : {"stable", "unstable", "marginal", "unknown"}
        From the eigenvalues' real parts (``"marginal"``: one on the
        imaginary axis, such as the angle of a free shaft; ``"unknown"``: ``df/dx`` is
        not finite at the point, as for a square-root orifice at zero flow).
    algebraic : mapping of name to float
        ``z0`` of an implicit model (its algebraic unknowns there); empty otherwise.
    """

    states: Mapping[str, float]
    inputs: Mapping[str, float]
    values: Mapping[str, float] = field(repr=False)
    residual: float = 0.0
    method: str = "numeric"
    how: str = field(default="", repr=False)
    scaled_residual: float = field(default=0.0, repr=False)
    condition: float = field(default=math.nan, repr=False)
    jacobian: str = field(default="symbolic", repr=False)
    eigenvalues: tuple = field(default=(), repr=False)
    stability: str = "unknown"
    algebraic: Mapping[str, float] = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        for name in ("states", "inputs", "values", "algebraic"):
            object.__setattr__(self, name, MappingProxyType(dict(getattr(self, name))))
        object.__setattr__(self, "eigenvalues", tuple(complex(v) for v in self.eigenvalues))

    def __reduce__(self):
        return (_rebuild, (dict(self.states), dict(self.inputs), dict(self.values),
                           self.residual, self.method, self.how, self.scaled_residual,
                           self.condition, self.jacobian, self.eigenvalues, self.stability,
                           dict(self.algebraic)))


def _rebuild(states, inputs, values, residual, method, how="", scaled_residual=0.0,
             condition=math.nan, jacobian="symbolic", eigenvalues=(), stability="unknown",
             algebraic=None):
    return Equilibrium(states, inputs, values, residual, method, how=how,
                       scaled_residual=scaled_residual, condition=condition, jacobian=jacobian,
                       eigenvalues=eigenvalues, stability=stability, algebraic=algebraic or {})


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
                tol: float = 1e-10, exact: bool = True,
                totals: Optional[Mapping] = None) -> Equilibrium:
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
        Largest accepted scaled residual: each ``|f_i|`` divided by the size
        of equation ``i`` (see :attr:`Equilibrium.scaled_residual`), so the
        test does not depend on the units.  A finite number > 0.
    exact : bool
        Try sympy's exact solver first for up to :data:`EXACT_MAX_STATES`
        free states of polynomial equations.
    totals : mapping, optional
        Totals of conserved quantities (chemical moieties, a floating charge):
        a key is a state name, a tuple of state names (their sum) or a sympy
        expression linear in the states; each replaces one equation the
        conservation makes dependent
        (:func:`bondgraph.linear.conserved.totals_equations`).  The stability
        verdict then leaves out one zero eigenvalue per total (the
        conserved directions).

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
    from . import trim as _trim

    where = f"model {model.name!r}: "
    tol = _trim.check_tol(tol, where, EquilibriumError)
    for option, given in (("inputs", inputs), ("guess", guess), ("fixed", fixed)):
        _trim.check_mapping(given, option, where, EquilibriumError)
    exprs = list(model.rhs)
    bad = set(model.input_derivatives) | {T_SYM}
    for ex in exprs:
        if ex.free_symbols & bad:
            raise EquilibriumError(f"{where}the state equations depend on "
                                   f"{', '.join(sorted(map(str, ex.free_symbols & bad)))}; "
                                   "an equilibrium needs a time-invariant model")
    params = match_values(model.parameters, values, known=model.known_parameters, where=where,
                          inputs=model.input_names)
    pvals = {p: real_value(v, p.name, where) for p, v in params.items()}
    check_model_values(model, {p.name: v for p, v in pvals.items()}, where=where)
    u0 = {u: 0.0 for u in model.inputs}
    u0.update(_named(model, inputs, model.inputs, "input"))
    held = _named(model, fixed, model.states, "fixed state")
    start = _named(model, guess, model.states, "guess state")
    free = [x for x in model.states if x not in held]
    if not free:
        raise EquilibriumError(f"{where}every state is fixed; nothing to solve")
    eqs_p = [ex.xreplace(pvals) for ex in exprs]
    _trim.check_finite_equations(model, eqs_p, pvals, where)
    states, ins = list(model.states), list(model.inputs)
    true_system = None
    if totals:
        from .conserved import totals_equations

        true_system = _trim.Equations(eqs_p, states, ins, [u0[u] for u in ins], where)
        eqs_p, _ = totals_equations(model, eqs_p, totals, u0)
        eqs_p = [e.xreplace(pvals) for e in eqs_p]
        unknown = set().union(*(e.free_symbols for e in eqs_p)) - set(states) - set(ins)
        if unknown:
            raise EquilibriumError(f"{where}totals: give numbers (or parameters with values), "
                                   f"not {', '.join(sorted(map(str, unknown)))}")
    system = _trim.Equations(eqs_p, states, ins, [u0[u] for u in ins], where)
    free_idx = [states.index(x) for x in free]
    x_start = np.array([held.get(x, start.get(x, 0.0)) for x in states])
    found, how, tried, failure = None, "", [], None
    if exact and len(free) <= EXACT_MAX_STATES and len(free) == len(states):
        known = {**u0, **held}
        solution = _exact([ex.xreplace(known) for ex in eqs_p], free, x_start[free_idx])
        if solution is not None:
            x_full = x_start.copy()
            x_full[free_idx] = solution
            a = _trim.assess(system, x_full, free_idx)
            if a.scaled_residual <= tol:
                found, how = a, "exact: sympy.solve, the real solution nearest the guess"
            tried.append("sympy.solve (exact)")
    method = "exact" if found is not None else "numeric"
    if found is None:
        found, how, more, failure = _trim.solve(system, x_start, free_idx, tol)
        tried += more
    if found is None:
        raise EquilibriumError(_failure(where, states, free, x_start, failure, tried, tol, held))
    if not system.differentiable_at(found.x):
        # f(x) = 0 holds, but df/dx does not exist there: neither isolation nor stability
        # can be read from a Jacobian; the point is returned, and says so
        return Equilibrium({x.name: float(v) for x, v in zip(states, found.x)},
                           {u.name: float(v) for u, v in u0.items()},
                           {p.name: v for p, v in pvals.items()}, found.max_residual, method,
                           how=how + "; df/dx is not finite at this point (a law with an "
                           "infinite slope there, such as sqrt at 0): its isolation and "
                           "stability are not decided", scaled_residual=found.scaled_residual,
                           condition=math.inf, jacobian="not finite at the point",
                           eigenvalues=(), stability="unknown")
    if found.singular:
        loose = [x.name for x, c in zip(free, found.null) if abs(c) > 1e-6] or \
            [x.name for x in free]
        raise EquilibriumError(
            f"{where}the equilibrium is not isolated (or a law has zero slope there, such as "
            f"f|f| at f = 0): the Jacobian of the state equations is "
            f"singular there (condition number {found.condition:.3g} after scaling), so "
            f"{', '.join(loose)} are not determined to first order; hold states that can "
            "take any value with fixed={...}"
            + ("" if totals else _conservation_hint(model)))
    if true_system is None:
        eig, verdict = _trim.stability(system, found.x)
    else:
        eig, verdict = _conserved_stability(true_system, found.x, len(totals or {}))
    jac_kind = ("finite differences" if system.jacobian_kind != "symbolic" else
                "symbolic" + (" (finite differences where it is not finite)"
                              if system.used_fd else ""))
    return Equilibrium({x.name: float(v) for x, v in zip(states, found.x)},
                       {u.name: float(v) for u, v in u0.items()},
                       {p.name: v for p, v in pvals.items()}, found.max_residual, method,
                       how=how, scaled_residual=found.scaled_residual,
                       condition=found.condition, jacobian=jac_kind,
                       eigenvalues=eig, stability=verdict)


def _conservation_hint(model) -> str:
    from .conserved import conservation_hint
    return conservation_hint(model)


def _conserved_stability(system, x, k: int) -> tuple:
    """Eigenvalues of the true ``df/dx`` and the verdict without its ``k`` zero eigenvalues
    (one per conserved total: directions the totals hold fixed)."""
    from . import trim as _trim

    eig, verdict = _trim.stability(system, x)
    if k and eig:
        rest = sorted(eig, key=abs)[k:]
        size = max((abs(v) for v in eig), default=0.0)
        if not rest or all(v.real < -1e-9 * size for v in rest):
            verdict = "stable"
        elif any(v.real > 1e-9 * size for v in rest):
            verdict = "unstable"
        else:
            verdict = "marginal"
    return eig, verdict


def _failure(where, states, free, x_start, failure, tried, tol, held) -> str:
    """The error text of a failed search: the worst equation, the states reached, the methods."""
    text = (f"{where}no equilibrium found from the guess "
            f"({', '.join(f'{x.name}={v:g}' for x, v in zip(states, x_start))})")
    if held and len(free) < len(states):
        text += (f"; with {', '.join(x.name for x in held)} fixed, {len(states)} equations remain "
                 f"for {len(free)} free state{'s' if len(free) > 1 else ''}, and no value of "
                 f"{', '.join(x.name for x in free)} satisfies them all")
    if failure is not None:
        with np.errstate(all="ignore"):
            q = np.abs(failure.residual) / np.where(failure.scale > 0, failure.scale, 1.0)
        i = int(np.nanargmax(np.where(np.isfinite(q), q, np.inf)))
        text += (f": closest point {', '.join(f'{x.name}={v:.6g}' for x, v in zip(states, failure.x))}"
                 f", where d{states[i].name}/dt = {failure.residual[i]:.3g} (scaled residual "
                 f"{failure.scaled_residual:.3g} > tol={tol:g})")
    text += (f"; methods tried: {'; '.join(tried)}. Give another guess=, or check that the inputs "
             "admit an equilibrium (a constant force on a free mass has none)"
             + (" and that the fixed values are ones an equilibrium can have" if held else ""))
    return text


def _exact(eqs, free, x_start) -> Optional[np.ndarray]:
    """The real solution of polynomial ``eqs`` nearest ``x_start``, or None."""
    nums = [sympy.together(e).as_numer_denom()[0] for e in eqs]
    if not all(n.is_polynomial(*free) for n in nums):
        return None
    nums = [sympy.nsimplify(n, rational=True) for n in nums]
    from .trim import exact_budget

    if not exact_budget(nums, free):
        return None
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


def output_derivative_feedthrough(model: "Model", jac) -> tuple:
    """``D_derivatives`` of a linearization: ``d y / d u^(k)`` for ``k = 1, 2, ...`` (``jac``
    differentiates and evaluates at the point), or ``()`` when no output needs them.

    Examples
    --------
    A flow source driving a mass: the force it needs is ``m dv/dt + b v``.

    >>> import bondgraph as bg
    >>> g = bg.BondGraph("push")
    >>> v = bg.One("v")
    >>> g.add(bg.Sf("v_in"), v, bg.I("m"), bg.R("b"), bg.C("k"))
    >>> for t, h in [("v_in", v), (v, "m"), (v, "b"), (v, "k")]: _ = g.connect(t, h)
    >>> model = bg.derive(g, outputs={"F": bg.effort("v_in"), "x": bg.displacement("k")})
    >>> lin = model.linearize({"q_k": 0}, {"v_in": 0}, equilibrium=False)
    >>> lin.D, lin.D_derivatives
    (Matrix([
    [b],
    [0]]), (Matrix([
    [m],
    [0]]),))
    """
    if not model.input_derivatives:
        return ()
    from .forms import derivative_orders

    orders = derivative_orders(model)
    out = []
    for k in range(1, max(order for _, order in orders.values()) + 1):
        cols: list[sympy.Symbol] = [sympy.Dummy() for _ in model.inputs]
        for sym, (j, order) in orders.items():
            if order == k:
                cols[j] = sym
        out.append(sympy.ImmutableMatrix(jac(model.output_exprs, cols)))
    while out and all(v == 0 for v in out[-1]):
        out.pop()
    return tuple(out)


def equilibrium_scaled(model: "Model", x0: Mapping, u0: Mapping, pvals: Mapping, tol: float) -> bool:
    """Whether ``f(x0, u0)`` vanishes by the unit-independent test of :func:`equilibrium`."""
    from . import trim as _trim

    try:
        system = _trim.Equations([r.xreplace(pvals) for r in model.rhs], model.states,
                                 model.inputs, [float(u0.get(u.name, 0.0)) for u in model.inputs])
        x = np.array([float(x0[s.name]) for s in model.states])
        return _trim.assess(system, x, range(len(x))).scaled_residual <= tol
    except (TypeError, ValueError, KeyError):
        return False
