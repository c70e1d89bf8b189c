"""Implicit models numerically: ``0 = g(x, z, u)`` solved for ``z`` at each evaluation.

A model whose derivation kept algebraic unknowns ``z`` (a nonlinear
algebraic loop, a law with no closed-form inverse; see
:mod:`bondgraph.equations.implicit`) is ``x' = f(x, z, u)``,
``0 = g(x, z, u)``, ``y = h(x, z, u)``.  :class:`ImplicitSolver` solves
``g = 0`` by Newton's method with the analytic Jacobian ``dg/dz``
(lambdified once), warm-started from the last solution, with
:func:`scipy.optimize.root` as the fallback; :class:`NumericDynamics
<bondgraph.numeric.NumericDynamics>` calls it before every evaluation of
``f`` and ``h``.  :func:`implicit_plant` linearizes at an operating point by
the implicit-function theorem: ``A = f_x - f_z g_z^-1 g_x`` (and ``B``,
``C``, ``D`` likewise).

Examples
--------
Two quadratic orifices ``dp = Q |Q| / K^2`` in series between two
accumulators: ``Q = sqrt(dp / (1/K1^2 + 1/K2^2))``.

>>> import numpy as np, sympy, bondgraph as bg
>>> K1, K2 = sympy.symbols("K1 K2", positive=True)
>>> g = bg.BondGraph("pipes")
>>> g.add(bg.C("A1"), bg.Zero("n1"), bg.One("s"), bg.R("o1", law=bg.f*abs(bg.f)/K1**2),
...       bg.R("o2", law=bg.f*abs(bg.f)/K2**2), bg.Zero("n2"), bg.C("A2"))
>>> for t, h in [("n1", "A1"), ("n1", "s"), ("s", "o1"), ("s", "o2"), ("s", "n2"), ("n2", "A2")]:
...     _ = g.connect(t, h)
>>> dyn = bg.numeric.compile_dynamics(bg.derive(g, outputs={"Q": bg.flow("o1")}))
>>> p = dyn.parameter_vector({"A1": 1.0, "A2": 1.0, "K1": 3.0, "K2": 4.0})
>>> Q = dyn.outputs(0.0, [5.0, 1.0], [], p)[0]
>>> bool(np.isclose(Q, np.sqrt(4.0 / (1 / 9 + 1 / 16))))
True
"""

from __future__ import annotations

import warnings
from typing import Any, Mapping, Optional

import numpy as np
import sympy

from ..equations import StateEquations
from ..errors import BondGraphError
from ..linear import Equilibrium, EquilibriumError
from ..errors import ParameterValueError
from ..parameters import ParameterValues, match_values, real_value
from ..elements.rules import check_model_values
from ..signals import t as T_SYM
from ._compile import CompiledFunction, guard_user_functions, placeholders
from .errors import SimulationError
from .statespace import NumericStateSpace
from ..linear.trim import dirac_free as _dirac_free

__all__ = ["ImplicitSolver", "with_algebraic", "implicit_plant", "NEWTON_ITERATIONS"]

#: Newton iterations before the :func:`scipy.optimize.root` fallback
NEWTON_ITERATIONS = 40


class ImplicitSolver:
    """``z`` with ``g(t, x, z, u, p) = 0``: Newton with ``dg/dz``, warm-started, root as fallback.

    Parameters
    ----------
    model : StateEquations
        An implicit model (``model.algebraic`` not empty).
    params : tuple of sympy.Symbol
        The parameter order of ``p``.
    """

    def __init__(self, model: StateEquations, params: tuple) -> None:
        self.model = model
        (tt,) = placeholders("t", 1)
        xs = placeholders("x", len(model.states))
        us = placeholders("u", len(model.inputs))
        ps = placeholders("p", len(params))
        zs = placeholders("z", len(model.algebraic))
        swap = {T_SYM: tt, **dict(zip(model.states, xs)), **dict(zip(model.inputs, us)),
                **dict(zip(params, ps)), **dict(zip(model.algebraic, zs))}
        res = guard_user_functions(model.residuals, lambda f: str(f))
        # differentiated in the model's real symbols (d|z|/dz = sign(z)), then renamed
        # DiracDelta (the derivative of sign or Heaviside) is 0 away from the jump
        jac = _dirac_free(sympy.Matrix(res).jacobian(list(model.algebraic)))
        args = [tt, xs, us, ps, zs]
        self._g = CompiledFunction(args, [r.xreplace(swap) for r in res])
        self._jac = CompiledFunction(args, [j.xreplace(swap) for j in jac])
        self.n = len(zs)
        self.last = np.zeros(self.n)

    def residual(self, t, x, z, u, p) -> np.ndarray:
        return np.asarray(self._g(t, x, u, p, z), dtype=float).reshape(self.n)

    def jacobian(self, t, x, z, u, p) -> np.ndarray:
        return np.asarray(self._jac(t, x, u, p, z), dtype=float).reshape(self.n, self.n)

    def extend(self, t: float, x, u, p) -> np.ndarray:
        """``p`` followed by ``z`` solved at ``(t, x, u)``: what the compiled ``f`` and ``h`` take."""
        return np.concatenate([p, self.solve(t, x, u, p)])

    def solve(self, t: float, x, u, p, guess: Optional[np.ndarray] = None) -> np.ndarray:
        """``z`` solving ``g = 0`` at ``(t, x, u)``; remembered as the next start.

        Raises
        ------
        SimulationError
            Neither Newton nor :func:`scipy.optimize.root` converged; the
            message names the unknowns, what they are, the time and the state.
        """
        z0 = self.last if guess is None else np.asarray(guess, dtype=float).reshape(self.n)
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            z = self._newton(t, x, u, p, z0.copy())
            if z is None:
                z = self._fallback(t, x, u, p, z0)
            # last resorts: the warm start may lie in another basin (a diode's loop left in
            # reverse bias near f = -Is, where dg/dz is huge), and dg/dz may be singular at
            # z = 0 (orifices f |f| in a network: every slope 0 there); a non-monotone law
            # (f**3 - 3 f) whose Newton from 0 cycles between its humps: starts beyond them
            for v in (0.0, 1e-3, 1.0, -1.0, 10.0, -10.0, 100.0, -100.0):
                start = np.full(self.n, v)
                if z is None and not np.array_equal(start, z0):
                    z = self._newton(t, x, u, p, start)
        if z is None:
            m = self.model
            state = ", ".join(f"{s} = {v:g}" for s, v in zip(m.state_names, np.ravel(x)))
            inputs = ", ".join(f"{s} = {v:g}" for s, v in zip(m.input_names, np.ravel(u)))
            raise SimulationError(
                f"model {m.name!r}: the algebraic equations 0 = g(x, z, u) have no solution "
                f"found for {', '.join(m.algebraic_names)} ({'; '.join(m.algebraic_origin)}) at "
                f"t = {float(t):g}, with {state or 'no state'}"
                + (f" and inputs {inputs}" if inputs else "")
                + " (Newton from the last solution and scipy.optimize.root both failed); the "
                "loop may have no solution there (a law saturating below the imposed value) "
                "or the laws may be evaluated outside their domain")
        self.last = z
        return z

    def _newton(self, t, x, u, p, z: np.ndarray) -> Optional[np.ndarray]:
        r = self.residual(t, x, z, u, p)
        norm = start = np.linalg.norm(r)
        for _ in range(NEWTON_ITERATIONS):
            if not np.isfinite(norm):
                return None
            if norm == 0.0:
                return z
            J = self.jacobian(t, x, z, u, p)
            if not np.all(np.isfinite(J)):
                return None
            try:
                step = np.linalg.solve(J, -r)
            except np.linalg.LinAlgError:     # singular dg/dz (|z| at 0): the fallback's turn
                return None
            alpha = 1.0
            for _ in range(30):       # backtracking: the residual must decrease
                trial = z + alpha * step
                r_new = self.residual(t, x, trial, u, p)
                n_new = np.linalg.norm(r_new)
                if np.isfinite(n_new) and n_new < norm or n_new == 0.0:
                    break
                alpha *= 0.5
            else:      # no decrease: converged to rounding if the Newton step is tiny
                small = np.max(np.abs(step)) <= 1e-9 * (1.0 + np.max(np.abs(z)))
                return z if small else None
            z, r, norm = trial, r_new, n_new
            # a small full Newton step that also shrank the residual a millionfold: quadratic
            # convergence (a small step alone proves nothing when dg/dz is huge)
            if (alpha == 1.0 and np.max(np.abs(step)) <= 1e-9 * (1.0 + np.max(np.abs(z)))
                    and norm <= 1e-6 * start):
                return z
        return None

    def _fallback(self, t, x, u, p, z0: np.ndarray) -> Optional[np.ndarray]:
        from scipy.optimize import root

        def fun(z):
            return self.residual(t, x, z, u, p)

        start = np.linalg.norm(fun(z0))
        # the analytic Jacobian first; then differences, which step off a singular point
        for jac, method in ((lambda z: self.jacobian(t, x, z, u, p), "hybr"), (None, "hybr"),
                            (None, "lm")):
            sol = root(fun, z0, method=method, jac=jac, tol=1e-13)
            if not np.all(np.isfinite(sol.x)):
                continue
            # hybr may stop short of its tolerance at rounding level: judge by the residual
            end = np.linalg.norm(fun(sol.x))
            if np.isfinite(end) and (sol.success and end <= 1e-8 * (1.0 + start)
                                     or end <= 1e-12 * (1.0 + start)):
                z = np.asarray(sol.x, dtype=float)     # polished by Newton where it can
                polished = self._newton(t, x, u, p, z.copy()) if np.any(z) else None
                return polished if polished is not None else z
        return None


class _WithZ:
    """A compiled ``fn(t, x, u, p + z)`` called as ``fn(t, x, u, p)``: ``z`` solved first
    (sample by sample when ``t`` is an array: ``z`` differs per sample)."""

    def __init__(self, solver: ImplicitSolver, fn) -> None:
        self.solver, self.fn = solver, fn

    def __call__(self, t, x, u, p):
        if np.shape(t):
            x, u = np.asarray(x, dtype=float), np.asarray(u, dtype=float)
            return np.array([np.asarray(self(tk, x[:, k], u[:, k], p), dtype=float).ravel()
                             for k, tk in enumerate(np.asarray(t, dtype=float))]).T
        return self.fn(t, x, u, self.solver.extend(t, x, u, p))


def with_algebraic(model: StateEquations, params: tuple, f, g) -> tuple:
    """``(f, g)`` unchanged for an explicit model; for an implicit one, each wrapped to solve
    ``0 = g(x, z, u)`` for ``z`` (one shared, warm-started :class:`ImplicitSolver`) first."""
    if not model.algebraic:
        return f, g
    solver = ImplicitSolver(model, params)
    return _WithZ(solver, f), _WithZ(solver, g)


def implicit_plant(model: StateEquations, point: Any, inputs: Optional[Mapping],
                   values: ParameterValues, tol: float, equilibrium: bool = True
                   ) -> NumericStateSpace:
    """The numeric plant of an implicit model at an operating point (implicit-function theorem).

    ``A = f_x - f_z g_z^-1 g_x``, ``B = f_u - f_z g_z^-1 g_u``,
    ``C = h_x - h_z g_z^-1 g_x``, ``D = h_u - h_z g_z^-1 g_u``, all at
    ``(x0, z0, u0)``; ``z0`` comes from the :class:`Equilibrium` or is solved
    for at ``(x0, u0)``.  Where a Jacobian is not finite (a law with an infinite
    slope at the point), central differences of the reduced model instead.  ``equilibrium=False`` accepts a point where
    ``f(x0, z0, u0) != 0`` (the drift is dropped).

    Raises
    ------
    EquilibriumError
        The point is not an equilibrium, or ``g_z`` is singular there (the
        algebraic unknowns are not determined locally).
    """
    where = f"model {model.name!r}: "
    z_given: dict = {}
    if isinstance(point, Equilibrium):
        x0, u0 = dict(point.states), dict(point.inputs)
        z_given = dict(getattr(point, "algebraic", {}) or {})
        if inputs is not None:
            raise BondGraphError(f"{where}give the inputs in the Equilibrium, not again as u0")
    else:
        x0, u0 = dict(point or {}), dict(inputs or {})
    missing = [s.name for s in model.states if s.name not in x0]
    if missing:
        raise EquilibriumError(f"{where}the operating point gives no value for the state(s) "
                               f"{', '.join(missing)}")
    params = match_values(model.parameters, values, known=model.known_parameters, where=where,
                          inputs=model.input_names)
    pvals = {p: real_value(v, p.name, where) for p, v in params.items()}
    check_model_values(model, {p.name: v for p, v in pvals.items()}, where=where)
    at = {**{s: float(x0[s.name]) for s in model.states},
          **{u: float(u0.get(u.name, 0.0)) for u in model.inputs}, **pvals}
    z_syms = list(model.algebraic)
    g = [r.xreplace(at) for r in model.residuals]
    gz = sympy.lambdify([z_syms], _dirac_free(sympy.Matrix(g).jacobian(z_syms)), modules="numpy")
    gf = sympy.lambdify([z_syms], g, modules="numpy")
    z_start = np.array([float(z_given.get(z.name, 0.0)) for z in z_syms])
    z0 = None
    if z_given and all(z.name in z_given for z in z_syms):
        # the Equilibrium's own z, kept when the trim's acceptance holds there (at an
        # orifice's kink a residual of 5e-8 is a distance of 1e-15 from the root)
        from ..linear import trim

        a = trim.assess(trim.Equations(g, z_syms, [], []), z_start, list(range(len(z_syms))))
        if a.scaled_residual <= 1e-8:
            z0 = z_start
    if z0 is None:
        z0 = _solve_z(gf, gz, z_start)
    if z0 is None:        # Newton from the start failed (an infinite slope there, sqrt|z|
        z0 = _search_z(g, z_syms, z_start)   # at 0): the trim's search with its starts
    if z0 is None:
        raise EquilibriumError(f"{where}the algebraic equations have no solution found for "
                               f"{', '.join(model.algebraic_names)} at this point")
    at.update(zip(z_syms, z0.tolist()))
    # an Equilibrium (it carries z) was accepted by the trim, whose test is scaled: not again
    f0 = np.array([float(r.xreplace(at)) for r in model.rhs])
    scale = max(1.0, max((abs(v) for v in x0.values()), default=1.0))
    if equilibrium and not z_given and f0.size and np.max(np.abs(f0)) > tol * scale:
        raise EquilibriumError(
            f"{where}the operating point is not an equilibrium at these values: "
            + ", ".join(f"d{s.name}/dt = {v:.3g}" for s, v in zip(model.states, f0)
                        if abs(v) > tol * scale)
            + "; use model.equilibrium(...) to find one")

    def jac(exprs, wrt) -> np.ndarray:
        if not exprs or not wrt:
            return np.zeros((len(exprs), len(wrt)))
        M = _dirac_free(sympy.Matrix(list(exprs)).jacobian(list(wrt)))
        if M.atoms(sympy.Derivative, sympy.Subs):
            raise ValueError("an unevaluated derivative")     # a user function's slope
        return np.array(M.xreplace(at).evalf(), dtype=float).reshape(len(exprs), len(wrt))

    def plant(A, B, C, D) -> NumericStateSpace:
        return NumericStateSpace(A, B, C, D, model.state_names, model.input_names,
                                 model.output_names, {p.name: float(v) for p, v in pvals.items()},
                                 model.name)
    x, u = list(model.states), list(model.inputs)
    from ..linear.trim import at_kink

    if at_kink(list(model.rhs) + list(model.residuals) + list(model.output_exprs), at):
        # sign(0)**2 = 0 in a slope that is the same from both sides: central differences
        return plant(*_reduced_differences(model, pvals, x0, u0, z0))
    try:
        Gz, Gx, Gu = (jac(model.residuals, w) for w in (z_syms, x, u))
        Fz, Hz = jac(model.rhs, z_syms), jac(model.output_exprs, z_syms)
        Fx, Fu = jac(model.rhs, x), jac(model.rhs, u)
        Hx, Hu = jac(model.output_exprs, x), jac(model.output_exprs, u)
    except (ValueError, TypeError):
        # no analytic Jacobian at this point: central differences of the reduced model
        return plant(*_reduced_differences(model, pvals, x0, u0, z0))
    if not all(np.all(np.isfinite(M)) for M in (Gz, Gx, Gu, Fz, Hz, Fx, Fu, Hx, Hu)):
        # a law with an infinite slope at the point (an orifice f = K sign(e) sqrt|e| at
        # e = 0): dz/dx exists only as a limit; central differences of the reduced model
        return plant(*_reduced_differences(model, pvals, x0, u0, z0))
    if np.linalg.matrix_rank(Gz) < len(z_syms):
        try:            # the reduced model may still be differentiable (a zero slope in g)
            return plant(*_reduced_differences(model, pvals, x0, u0, z0))
        except EquilibriumError:
            pass
        raise EquilibriumError(
            f"{where}dg/dz is singular at the operating point: the algebraic unknowns "
            f"{', '.join(model.algebraic_names)} are not determined locally "
            "(the implicit-function theorem does not apply)")
    Sx, Su = np.linalg.solve(Gz, Gx), np.linalg.solve(Gz, Gu)
    return plant(Fx - Fz @ Sx, Fu - Fz @ Su, Hx - Hz @ Sx, Hu - Hz @ Su)


def _reduced_differences(model: StateEquations, pvals: Mapping, x0: Mapping, u0: Mapping,
                         z0: np.ndarray) -> tuple[np.ndarray, ...]:
    """``A, B, C, D`` of ``x' = f(x, z(x, u), u)``, ``y = h(x, z(x, u), u)`` by central
    differences, ``z(x, u)`` solved from ``g = 0`` at every perturbed point."""
    x_syms, u_syms, z_syms = list(model.states), list(model.inputs), list(model.algebraic)
    args = [x_syms, u_syms, z_syms]
    fh = sympy.lambdify(args, [e.xreplace(pvals) for e in model.rhs + model.output_exprs],
                        modules="numpy")
    res = [e.xreplace(pvals) for e in model.residuals]
    xv = np.array([float(x0[s.name]) for s in x_syms])
    uv = np.array([float(u0.get(v.name, 0.0)) for v in u_syms])

    def reduced(xx: np.ndarray, uu: np.ndarray) -> np.ndarray:
        g = [r.xreplace({**dict(zip(x_syms, xx.tolist())), **dict(zip(u_syms, uu.tolist()))})
             for r in res]
        gf = sympy.lambdify([z_syms], g, modules="numpy")
        gz = sympy.lambdify([z_syms], _dirac_free(sympy.Matrix(g).jacobian(z_syms)),
                            modules="numpy")
        z = _solve_z(gf, gz, z0)
        if z is None:
            z = _search_z(g, z_syms, z0)
        if z is None:
            raise EquilibriumError(f"model {model.name!r}: the algebraic equations have no "
                                   "solution near the operating point (central differences)")
        with np.errstate(all="ignore"):
            return np.asarray(fh(xx, uu, z), dtype=float).reshape(-1)

    def quotient(v: np.ndarray, which: int, i: int, h: float) -> np.ndarray:
        up, dn = v.copy(), v.copy()
        up[i] += h
        dn[i] -= h
        a, b = ((up, uv), (dn, uv)) if which == 0 else ((xv, up), (xv, dn))
        return (reduced(*a) - reduced(*b)) / (2 * h)

    names = [s.name for s in x_syms] + [s.name for s in u_syms]

    def columns(v: np.ndarray, which: int) -> np.ndarray:
        cols = []
        for i in range(v.size):
            h = 1e-5 * max(1.0, abs(v[i]))
            wide, narrow = quotient(v, which, i, h), quotient(v, which, i, h / 8)
            # a slope that exists agrees at both steps; one that grows as the step shrinks
            # (z = x**(1/3) where the law has zero slope) is infinite: no linearization
            gap = np.abs(wide - narrow) > 1e-2 * np.maximum(1.0, np.abs(narrow))
            if np.any(gap) or not np.all(np.isfinite(narrow)):
                name = names[i if which == 0 else len(x_syms) + i]
                raise EquilibriumError(
                    f"model {model.name!r}: the model is not differentiable in {name} at the "
                    f"operating point: the algebraic unknowns {', '.join(model.algebraic_names)} "
                    "are determined by a law whose slope is zero there (their own slope is "
                    "infinite: the difference quotients grow as the step shrinks, "
                    f"{float(np.max(np.abs(wide))):.4g} then {float(np.max(np.abs(narrow))):.4g}); "
                    "linearize about another point")
            cols.append(narrow)
        n_out = len(model.rhs) + len(model.output_exprs)
        return np.array(cols).T if cols else np.zeros((n_out, 0))
    n = len(x_syms)
    X, U = columns(xv, 0), columns(uv, 1)
    return X[:n], U[:n], X[n:], U[n:]


def _search_z(g: list, z_syms: list, start: np.ndarray) -> Optional[np.ndarray]:
    """``g(z) = 0`` by :func:`bondgraph.linear.trim.solve` (both root methods, the
    finite-difference Jacobian, starts spread over the unknowns' natural scales)."""
    from ..linear import trim

    system = trim.Equations(g, z_syms, [], [])
    idx = list(range(len(z_syms)))
    found, _, _, best = trim.solve(system, start, idx, 1e-12, homotopy=False)
    if found is not None and found.max_residual <= 1e-9:
        return np.asarray(found.x, dtype=float)
    for cand in (found, best):
        # next to an orifice's kink the residual cannot fall below ~1e-8 while the point is
        # within 1e-15 of the root: the trim's scaled test decides then
        if cand is not None and cand.scaled_residual <= 1e-8:
            return np.asarray(cand.x, dtype=float)
    return None


def _solve_z(gf, gz, start: np.ndarray) -> Optional[np.ndarray]:
    from scipy.optimize import root

    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        sol = root(lambda z: np.asarray(gf(z), dtype=float), start,
                   jac=lambda z: np.asarray(gz(z), dtype=float), tol=1e-14)
    if not np.all(np.isfinite(sol.x)):
        return None
    res = np.asarray(gf(sol.x), dtype=float)
    return np.asarray(sol.x, dtype=float) if np.max(np.abs(res), initial=0.0) < 1e-9 else None
