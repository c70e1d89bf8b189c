"""Numerics of :func:`bondgraph.linear.equilibrium`: checks, Jacobians, scaling, solvers.

The state equations ``f(x, u)`` of a physical model mix units: an SI
hydraulic circuit has compliances of 1e-14 and pressures of 1e7, the same
circuit in bar and litres numbers near 1.  Everything here is written so that
a change of units (a diagonal scaling of the states and of the equations)
changes nothing:

* the Jacobian ``J = df/dx`` is equilibrated (rows and columns scaled so that
  its nonzero entries are as near 1 as a diagonal scaling can bring them, Curtis
  and Reid's scaling; :func:`equilibrate`); its condition number and
  the isolation (rank) test are taken on the equilibrated matrix;
* each equation's residual is compared with the size of its own terms at the
  point, or, for an equation whose terms all vanish there (``dq/dt = p/m`` at
  rest), with the size its row of the equilibrated Jacobian gives it
  (:func:`Assessment.scaled_residual`);
* the solvers are MINPACK's (``hybr`` and ``lm`` through
  :func:`scipy.optimize.root`), which scale their variables internally and
  stop on relative steps.

When the first solve fails, :func:`solve` continues from an easy point (a
homotopy that raises the inputs from nearly zero to their values) and then
tries several starts spread over the natural scales of the states.

Jacobians are symbolic where ``lambdify`` can evaluate them: a ``DiracDelta``
(the derivative of ``sign`` or ``Heaviside``) is 0 away from its jump; a
Jacobian that still holds something numpy cannot evaluate, or that is not
finite at a point, is replaced there by finite differences
(:func:`scipy.optimize.approx_fprime`), and the result says so.
"""

from __future__ import annotations

import copy
import math
import warnings
from dataclasses import dataclass
from typing import Callable, Mapping, Optional, Sequence

import numpy as np
import sympy

from ..errors import NonlinearModelError, ParameterValueError

__all__ = ["check_tol", "check_mapping", "check_finite_equations", "Equations", "equilibrate",
           "Assessment", "solve", "stability"]

#: largest Bezout number (product of the equations' degrees) sent to sympy's exact solver
EXACT_MAX_DEGREE = 64
#: an equilibrated Jacobian whose smallest singular value is below this (relative) is singular
SINGULAR = 1e-10
#: what lambdify prints with (scipy for erf, gamma and the like)
MODULES = ["numpy", "scipy"]
#: deterministic extra starts tried after the homotopy
STARTS = 24


def check_tol(tol, where: str, error: type) -> float:
    """``tol`` as a float, or ``error`` if it is not a finite number > 0."""
    if isinstance(tol, bool) or not isinstance(tol, (int, float, np.integer, np.floating)) \
            or not math.isfinite(float(tol)) or not float(tol) > 0:
        raise error(f"{where}tol: expected a finite number > 0 (the largest accepted scaled "
                    f"residual), got {tol!r}")
    return float(tol)


def check_mapping(given, option: str, where: str, error: type) -> None:
    """``given`` is None or a mapping (name -> value); ``error`` naming ``option`` otherwise."""
    if given is not None and not isinstance(given, Mapping):
        raise error(f"{where}{option}: expected a mapping of names to numbers "
                    f"(such as {{'q_k': 0.1}}), got {type(given).__name__} {given!r:.60}")


def check_finite_equations(model, eqs: Sequence[sympy.Expr], pvals: Mapping, where: str) -> None:
    """A :class:`ParameterValueError` if a substituted equation holds ``zoo``/``nan``/``oo``
    (a zero mass, compliance or inductance that divides), naming the elements."""
    bad = (sympy.zoo, sympy.nan, sympy.oo, -sympy.oo)
    for x, ex in zip(model.states, eqs):
        if any(ex.has(b) for b in bad):
            zeros = sorted(p.name for p, v in pvals.items() if v == 0)
            culprits = [f"{el.label()} ({', '.join(f'{h} = 0' for h in hit)})"
                        for el in (model.augmented.flat.elements if model.augmented else ())
                        for hit in [sorted({s.name for s in el.free_parameters()} & set(zeros))
                                    if hasattr(el, "free_parameters") else
                                    sorted({s.name for s in _param_symbols(el)} & set(zeros))]
                        if hit]
            hint = (f"{', '.join(culprits)} divides by a parameter that is zero" if culprits
                    else "a parameter that divides (mass, inductance, compliance) is zero?")
            raise ParameterValueError(f"{where}the state equation d{x.name}/dt is not finite at "
                                      f"these values ({ex}); {hint}")


def _param_symbols(el):
    from .._support.sympify import parameter_symbols
    return parameter_symbols(el)


def dirac_free(expr: sympy.Expr) -> sympy.Expr:
    """``DiracDelta`` (the derivative of a jump: ``sign``, ``Heaviside``) is 0 away from the
    jump; so is ``Derivative(sign(g(z)), z)``, which sympy leaves unevaluated when it cannot
    tell that ``g`` is real."""
    expr = expr.replace(sympy.DiracDelta, lambda *a: sympy.S.Zero)
    return expr.replace(lambda e: isinstance(e, sympy.Derivative)
                        and isinstance(e.expr, (sympy.sign, sympy.Heaviside)),
                        lambda e: sympy.S.Zero)


class Equations:
    """``f(x)`` of the full state vector at fixed parameters and inputs, with its Jacobian.

    Parameters
    ----------
    eqs : sequence of sympy.Expr
        The state equations with parameters and inputs substituted.
    states : sequence of sympy.Symbol
    """

    def __init__(self, eqs: Sequence[sympy.Expr], states: Sequence[sympy.Symbol],
                 inputs: Sequence[sympy.Symbol], u: Sequence[float], where: str = ""):
        self.states, inputs = list(states), list(inputs)
        self.n = len(self.states)
        self.u = np.asarray(u, dtype=float)
        args = [self.states, inputs]
        self._f = sympy.lambdify(args, list(eqs), modules=MODULES)
        try:
            with np.errstate(all="ignore"):
                self._f(np.zeros(self.n) + 0.5, self.u)
        except NameError as exc:
            raise NonlinearModelError(
                f"{where}the state equations use {exc.name or exc}, which numpy and scipy cannot "
                "evaluate; write the law with functions numpy knows (sign, Abs, sqrt, exp, "
                "tanh, Piecewise, Min, Max, ...)") from None
        terms = [list(sympy.Add.make_args(e)) for e in eqs]
        self._sizes = sympy.lambdify(args, [[abs(t) for t in ts] for ts in terms],
                                     modules=MODULES)
        self.jacobian_kind = "symbolic"
        self._jac: Optional[Callable] = None
        self._rough: Optional[Callable] = None      # unevaluable derivatives as 0: for scales only
        J = sympy.Matrix(list(eqs)).jacobian(self.states).applyfunc(dirac_free)
        undefined = J.atoms(sympy.Derivative, sympy.Subs) | {
            a for a in J.atoms(sympy.Function) if isinstance(a, sympy.core.function.AppliedUndef)}
        self._jac = self._lambdify(args, J) if not undefined else None
        if self._jac is None:
            self.jacobian_kind = "finite differences"
            self._rough = self._lambdify(args, J.xreplace({a: sympy.S.Zero for a in undefined}))
        self.used_fd = False
        kinks = kink_arguments(eqs)
        self._kinks = sympy.lambdify(args, kinks, modules=MODULES) if kinks else None

    def _lambdify(self, args, J) -> Optional[Callable]:
        try:
            fn = sympy.lambdify(args, J, modules=MODULES)
            with np.errstate(all="ignore"), warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                fn(np.zeros(self.n) + 0.5, self.u)       # evaluates with numpy's functions
            return fn
        except Exception:          # noqa: BLE001 -- anything lambdify cannot print or run
            return None

    def with_inputs(self, u: Sequence[float]) -> "Equations":
        """The same equations at other input values (for the homotopy)."""
        other = copy.copy(self)
        other.u = np.asarray(u, dtype=float)
        return other

    def __call__(self, x: np.ndarray) -> np.ndarray:
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            out = self._f(np.asarray(x, dtype=float), self.u)
            return np.asarray(out, dtype=float).reshape(self.n)

    def sizes(self, x: np.ndarray) -> np.ndarray:
        """Per equation, the sum of the magnitudes of its terms at ``x``."""
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            rows = self._sizes(np.asarray(x, dtype=float), self.u)
        return np.array([float(np.sum(np.asarray(r, dtype=float))) for r in rows])

    def at_kink(self, x: np.ndarray) -> bool:
        """Whether an argument of ``sign``, ``Abs`` or ``Heaviside`` is exactly 0 at ``x``."""
        if self._kinks is None:
            return False
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            vals = np.asarray(self._kinks(np.asarray(x, dtype=float), self.u), dtype=float)
        return bool(np.any(vals == 0.0))

    def jac(self, x: np.ndarray) -> np.ndarray:
        """``df/dx`` at ``x``: symbolic if finite there, else finite differences.

        At a kink of ``sign``/``Abs`` (``(sqrt(a|p| + b) - c) sign(p)`` at ``p = 0``,
        whose slope is ``a/(2 sqrt b)`` from both sides) the symbolic form reads
        ``sign(0)**2 = 0``: the mean of the Jacobians just beside the point is taken.
        """
        x = np.asarray(x, dtype=float)
        if self.at_kink(x):
            h = beside(x)
            return 0.5 * (self._jac_at(x + h) + self._jac_at(x - h))
        return self._jac_at(x)

    def _jac_at(self, x: np.ndarray) -> np.ndarray:
        if self._jac is not None:
            with np.errstate(all="ignore"), warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                J = np.asarray(self._jac(x, self.u), dtype=float).reshape(self.n, self.n)
            if np.all(np.isfinite(J)):
                return J
        self.used_fd = True
        return self.fd_jac(x)

    def differentiable_at(self, x: np.ndarray) -> bool:
        """False where the symbolic ``df/dx`` is not finite (``sqrt`` at 0: an infinite
        slope); True where it is, or when there is no symbolic Jacobian to ask."""
        if self._jac is None:
            return True
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            J = np.asarray(self._jac(np.asarray(x, dtype=float), self.u), dtype=float)
        return bool(np.all(np.isfinite(J)))

    def nominal(self, x: np.ndarray) -> np.ndarray:
        """A size per state at ``x``: the equilibrated Jacobian's column scales times the
        largest equation size in its row units (0 where nothing is known)."""
        fn = self._jac or self._rough
        if fn is None:
            return np.zeros(self.n)
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            J = np.asarray(fn(np.asarray(x, dtype=float), self.u), dtype=float).reshape(self.n, self.n)
        J = np.where(np.isfinite(J), J, 0.0)
        r, c = equilibrate(J)
        sizes = np.abs(self.sizes(x))
        sizes = np.where(np.isfinite(sizes), sizes, 0.0)
        alpha = float(np.max(sizes * r)) if sizes.size else 0.0
        return alpha * c

    def fd_jac(self, x: np.ndarray) -> np.ndarray:
        """Forward differences, steps relative to ``max(|x|, nominal(x))`` (1 where both are 0)."""
        from scipy.optimize import approx_fprime

        x = np.asarray(x, dtype=float)
        ref = np.maximum(np.abs(x), self.nominal(x))
        ref = np.where(ref > 0, ref, 1.0)
        step = math.sqrt(np.finfo(float).eps) * ref
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            J = np.atleast_2d(approx_fprime(x, self.__call__, step))
        return J.reshape(self.n, self.n)


def kink_arguments(exprs: Sequence[sympy.Expr]) -> list[sympy.Expr]:
    """The arguments of ``sign``, ``Abs`` and ``Heaviside`` in ``exprs`` (where a symbolic
    derivative may read a one-sided value)."""
    found: dict = {}
    for e in exprs:
        for a in e.atoms(sympy.sign, sympy.Abs, sympy.Heaviside):
            found.setdefault(a.args[0], None)
    return list(found)


def at_kink(exprs: Sequence[sympy.Expr], at: Mapping) -> bool:
    """Whether an argument of ``sign``, ``Abs`` or ``Heaviside`` in ``exprs`` is exactly 0
    with the symbols of ``at`` replaced by its numbers."""
    for a in kink_arguments(exprs):
        try:
            if float(a.xreplace(at)) == 0.0:
                return True
        except (TypeError, ValueError):       # not a real number there
            continue
    return False


def beside(x: np.ndarray) -> np.ndarray:
    """A small step off ``x`` in a fixed direction with distinct components (so that
    ``sign(p1 - p2)`` at ``p1 = p2`` moves off its kink too)."""
    x = np.asarray(x, dtype=float)
    d = 1.0 + 0.618 * np.arange(x.size)
    return 1e-9 * np.maximum(1.0, np.abs(x)) * d


def equilibrate(J: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Row and column scales ``r, c`` that bring the nonzero ``|r_i J_ij c_j|`` nearest 1
    in the least-squares sense of their logarithms (Curtis and Reid's scaling).

    The scaled entries do not depend on the units: scaling the rows and columns
    of ``J`` beforehand changes ``r`` and ``c`` and leaves ``r_i J_ij c_j``
    as they were.  Zero rows and columns keep the scale 1.

    Examples
    --------
    >>> J = np.array([[1e8, 0.0], [1e-6, 1e-14]])
    >>> r, c = equilibrate(J)
    >>> np.round(np.abs(J * r[:, None] * c[None, :]), 9)
    array([[1., 0.],
           [1., 1.]])
    >>> D1, D2 = np.array([1e5, 1e-3]), np.array([7.0, 1e9])
    >>> r2, c2 = equilibrate(J * D1[:, None] * D2[None, :])
    >>> bool(np.allclose(J * r[:, None] * c[None, :],
    ...                  (J * D1[:, None] * D2[None, :]) * r2[:, None] * c2[None, :]))
    True
    """
    A = np.abs(np.asarray(J, dtype=float))
    m, n = A.shape
    rows, cols = np.nonzero(np.isfinite(A) & (A > 0))
    if rows.size == 0:
        return np.ones(m), np.ones(n)
    M = np.zeros((rows.size, m + n))
    M[np.arange(rows.size), rows] = 1.0
    M[np.arange(rows.size), m + cols] = 1.0
    logs = np.linalg.lstsq(M, -np.log(A[rows, cols]), rcond=None)[0]
    return np.exp(logs[:m]), np.exp(logs[m:])


@dataclass(frozen=True)
class Assessment:
    """How well ``x`` solves ``f = 0``, in units that do not depend on the model's units.

    ``scale[i]`` is what equation ``i`` is measured against: the sum of its
    terms' magnitudes at ``x``, or, if larger, ``alpha / r_i`` with ``r`` the
    row scales of the equilibrated Jacobian and ``alpha`` the largest equation
    size in those row units (so an equation whose terms all vanish, such as
    ``dq/dt = p/m`` at rest, is measured on the scale of the rest of the model).
    """

    x: np.ndarray
    residual: np.ndarray
    scale: np.ndarray
    jacobian: np.ndarray            # of the free states (rows: every equation)
    condition: float                # of the equilibrated free Jacobian
    singular: bool
    null: np.ndarray                # direction of the null space (free states)
    step: float = math.inf          # Newton correction relative to the states' sizes

    @property
    def relative_residual(self) -> float:
        """``max |f_i| / scale_i``."""
        if not np.all(np.isfinite(self.residual)):
            return math.inf
        with np.errstate(all="ignore"):
            q = np.where(self.scale > 0, np.abs(self.residual) / self.scale,
                         np.where(self.residual == 0, 0.0, math.inf))
        return float(np.max(q)) if q.size else 0.0

    @property
    def scaled_residual(self) -> float:
        """The smaller of :attr:`relative_residual` and :attr:`step`: a point is accepted when
        its residual is rounding noise of its equations' terms, or when the Newton correction
        that would remove it is rounding noise of the states (at ``q = pi`` of a pendulum
        every term of ``-m g l sin(q)`` is itself noise)."""
        return min(self.relative_residual, self.step)

    @property
    def max_residual(self) -> float:
        return float(np.max(np.abs(self.residual))) if self.residual.size else 0.0


def _max_scaled_condition(J: np.ndarray) -> float:
    """Condition number of ``J`` with its rows, then its columns, divided by their largest
    magnitude (independent of units, like :func:`equilibrate`)."""
    A = np.array(J, dtype=float)
    row = np.max(np.abs(A), axis=1, keepdims=True)
    A = A / np.where(row > 0, row, 1.0)
    col = np.max(np.abs(A), axis=0, keepdims=True)
    A = A / np.where(col > 0, col, 1.0)
    sv = np.linalg.svd(A, compute_uv=False)
    if not sv.size or len(sv) < A.shape[1] or sv[-1] == 0:
        return math.inf
    return float(sv[0] / sv[-1])


def _rounding(f: np.ndarray, J: np.ndarray, x: np.ndarray, sizes: np.ndarray) -> bool:
    """Every ``|f_i|`` within rounding of its row's ``sum_j |J_ij x_j|`` or term sizes."""
    with np.errstate(all="ignore"):
        jx = np.abs(np.where(np.isfinite(J), J, 0.0)) @ np.abs(x)
    ref = np.maximum(jx, np.where(np.isfinite(sizes), sizes, 0.0))
    return bool(np.all(np.abs(f) <= 1e3 * np.finfo(float).eps * ref))


def _newton_helps(eqs: Equations, x_full: np.ndarray, free_idx: Sequence[int], dx: np.ndarray,
                  f: np.ndarray) -> bool:
    """Whether the Newton-corrected point cuts the largest residual at least tenfold."""
    y = np.array(x_full, dtype=float)
    y[list(free_idx)] -= dx
    f_new = eqs(y)
    return bool(np.all(np.isfinite(f_new)) and np.max(np.abs(f_new)) <= 0.1 * np.max(np.abs(f)))


def assess(eqs: Equations, x_full: np.ndarray, free_idx: Sequence[int]) -> Assessment:
    """The residual, its scales, the conditioning and isolation of ``x_full``."""
    f = eqs(x_full)
    sizes = eqs.sizes(x_full)
    J = eqs.jac(x_full) if np.all(np.isfinite(f)) else np.full((eqs.n, eqs.n), np.nan)
    Jf = J[:, list(free_idx)]
    if not np.all(np.isfinite(Jf)):
        return Assessment(x_full, f, sizes, Jf, math.inf, True, np.ones(len(free_idx)))
    r, c = equilibrate(J)
    finite = np.isfinite(sizes)
    alpha = float(np.max(sizes[finite] * r[finite])) if finite.any() else 0.0
    scale = np.maximum(np.where(finite, sizes, 0.0), alpha / r)
    rf, cf = equilibrate(Jf)
    S = Jf * rf[:, None] * cf[None, :]
    if S.size:
        sv = np.linalg.svd(S, compute_uv=False)
        smax = sv[0] if sv.size else 0.0
        smin = sv[-1] if len(sv) >= S.shape[1] else 0.0
        condition = math.inf if smin == 0 else float(smax / smin)
        singular = bool(smax == 0 or smin <= SINGULAR * smax)
        if singular:
            # Curtis-Reid lifts every nonzero entry towards 1, rounding noise included (a
            # 1e-14 left by a cancellation inside an entry); a second unit-free scaling,
            # by the largest entry of each row then column, ignores such noise: the point
            # is singular only when both say so
            condition = min(condition, _max_scaled_condition(Jf))
            singular = bool(condition == math.inf or 1.0 / condition <= SINGULAR)
        null = np.linalg.svd(S)[2][-1] if singular else np.zeros(S.shape[1])
    else:
        condition, singular, null = 1.0, False, np.zeros(0)
    step = math.inf
    if not singular and np.all(np.isfinite(f)):
        dx = np.linalg.lstsq(Jf, f, rcond=None)[0]
        if np.max(np.abs(f - Jf @ dx)) > 1e-6 * np.max(np.abs(f)):
            dx = np.full_like(dx, np.inf)      # f is not in the range of J (more equations)
        elif not _rounding(f, J, x_full, sizes) and not _newton_helps(eqs, x_full, free_idx, dx, f):
            # a tiny Newton step that does not shrink f: the linear model is wrong here (a
            # slope of 1e77 at sqrt|x|'s x = 1e-155), the step says nothing of the distance
            dx = np.full_like(dx, np.inf)
        xs = np.abs(x_full[list(free_idx)])
        nominal = alpha * c[list(free_idx)] if alpha > 0 else np.zeros(len(free_idx))
        ref = np.maximum(xs, nominal)
        with np.errstate(all="ignore"):
            q = np.where(ref > 0, np.abs(dx) / ref, np.where(dx == 0, 0.0, math.inf))
        step = float(np.max(q)) if q.size else 0.0
    return Assessment(x_full, f, scale, Jf, condition, singular, null, step)


def _root(fun, jac, x0, method: str, tol: float):
    from scipy.optimize import root

    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        try:
            sol = root(fun, x0, jac=jac, method=method,
                       options={"xtol": min(1e-12, tol * 1e-2)} if method == "hybr" else
                       {"xtol": min(1e-12, tol * 1e-2), "ftol": 0.0, "maxiter": 2000})
        except (ValueError, FloatingPointError, np.linalg.LinAlgError, ZeroDivisionError):
            return None
    x = np.asarray(sol.x, dtype=float)
    return x if np.all(np.isfinite(x)) else None


def solve(eqs: Equations, x_start: np.ndarray, free_idx: Sequence[int], tol: float,
          homotopy: bool = True
          ) -> tuple[Optional[Assessment], str, list[str], Optional[Assessment]]:
    """Search an accepted root; returns ``(assessment, how, tried, best_failure)``.

    ``how`` names the method that succeeded; ``tried`` every method tried.
    """
    free_idx = list(free_idx)
    square = len(free_idx) == eqs.n
    tried: list[str] = []
    best: list[Optional[Assessment]] = [None]

    def embed(z, base):
        x = np.array(base, dtype=float)
        x[free_idx] = z
        return x

    def attempt(system: Equations, start_full: np.ndarray, method: str, analytic: bool):
        def fun(z):
            return system(embed(z, start_full))

        def jac(z):
            return system.jac(embed(z, start_full))[:, free_idx]
        z = _root(fun, jac if analytic else None, start_full[free_idx], method, tol)
        return None if z is None else embed(z, start_full)

    def accept(x_full, system=eqs):
        if x_full is None:
            return None
        a = assess(system, x_full, free_idx)
        if a.scaled_residual <= tol:
            return a
        if best[0] is None or a.scaled_residual < best[0].scaled_residual:
            best[0] = a
        return None

    methods = (["hybr", "lm"] if square else ["lm"])
    x_start = np.asarray(x_start, dtype=float)
    for method in methods:
        for analytic in ([True, False] if eqs.jacobian_kind == "symbolic" else [False]):
            name = f"{method} ({'symbolic' if analytic else 'finite-difference'} Jacobian)"
            tried.append(name + " from the guess")
            a = accept(attempt(eqs, x_start, method, analytic))
            if a is not None:
                return a, f"scipy.optimize.root {name} from the guess", tried, None
    if homotopy and np.any(eqs.u != 0):
        tried.append("homotopy in the inputs from zero (adaptive steps)")
        x = _continue(eqs, x_start, free_idx, tol, attempt, methods)
        if x is not None:
            a = accept(attempt(eqs, x, methods[0], eqs.jacobian_kind == "symbolic")) or accept(x)
            if a is not None:
                return a, "homotopy in the inputs from zero, then scipy.optimize.root " + \
                    methods[0], tried, None
    scales = _natural_scales(eqs, x_start, free_idx)
    rng = np.random.default_rng(0)
    tried.append(f"{STARTS} starts spread over the states' natural scales")
    for k in range(STARTS):
        mag = 10.0 ** rng.uniform(-3, 3)
        z = x_start[free_idx] + scales * mag * rng.choice([-1.0, 1.0], size=len(free_idx)) \
            * (1 if k % 2 else np.abs(rng.standard_normal(len(free_idx))) + 0.1)
        for method in methods:
            a = accept(attempt(eqs, embed(z, x_start), method, False))
            if a is not None:
                return a, (f"scipy.optimize.root {method} (finite-difference Jacobian) from "
                           f"start {k + 1} of {STARTS}"), tried, None
    return None, "", tried, best[0]


def _continue(eqs: Equations, x_start: np.ndarray, free_idx: Sequence[int], tol: float,
              attempt: Callable, methods: Sequence[str], max_steps: int = 200
              ) -> Optional[np.ndarray]:
    """Follow the root from inputs ``0`` to ``u`` (``u(lam) = lam u``), halving a step that
    fails and doubling one that succeeds; the last root, or None."""
    loose = max(tol, 1e-8)

    def step(target, x):
        system = eqs.with_inputs(eqs.u * target)
        for method in methods:
            y = attempt(system, x, method, False)
            if y is not None and assess(system, y, free_idx).scaled_residual <= loose:
                return y
        return None

    x = step(0.0, np.asarray(x_start, dtype=float))
    lam, h = 0.0, 1e-3
    for _ in range(max_steps if x is not None else 0):
        target = min(1.0, lam + h)
        y = step(target, x)
        if y is None:
            h /= 4.0
            if h < 1e-12:
                return None
            continue
        x, lam, h = y, target, 2.0 * h
        if lam >= 1.0:
            return x
    return None


def _natural_scales(eqs: Equations, x_start: np.ndarray, free_idx: Sequence[int]) -> np.ndarray:
    """A magnitude per free state: the equilibrated Jacobian's column scales, anchored so
    that the equations' sizes at the start are met (1 where nothing is known)."""
    x = np.array(x_start, dtype=float)
    J = eqs.jac(x)
    if not np.all(np.isfinite(J)):
        J = eqs.fd_jac(x)
    sizes = eqs.sizes(x)
    f = np.abs(eqs(x))
    r, c = equilibrate(np.where(np.isfinite(J), J, 0.0))
    base = np.where(np.isfinite(sizes), np.maximum(sizes, f), 0.0)
    alpha = float(np.max(base * r)) if base.size else 0.0
    s = (alpha if alpha > 0 else 1.0) * c
    s = np.where(np.abs(x) > s, np.abs(x), s)
    return s[list(free_idx)]


def stability(eqs: Equations, x_full: np.ndarray) -> tuple[tuple[complex, ...], str]:
    """Eigenvalues of ``df/dx`` (all states) and ``"stable"``, ``"unstable"`` or ``"marginal"``
    (an eigenvalue on the imaginary axis within 1e-9 of the largest; linearization decides
    nothing then)."""
    return stability_of(eqs.jac(x_full))


def stability_of(J: np.ndarray) -> tuple[tuple[complex, ...], str]:
    """:func:`stability` of a Jacobian matrix ``J`` (balanced before its eigenvalues)."""
    if not J.size:
        return (), "stable"
    if not np.all(np.isfinite(J)):
        return (), "unknown"
    r, c = equilibrate(J)
    # a similarity transform (D J D^-1) keeps the eigenvalues and balances the matrix
    d = np.sqrt(c / np.where(r > 0, r, 1.0))
    lam = np.linalg.eigvals((J * (1 / d)[:, None]) * d[None, :])
    size = float(np.max(np.abs(lam))) if lam.size else 0.0
    re = lam.real
    if np.all(re < -1e-9 * size):
        verdict = "stable"
    elif np.any(re > 1e-9 * size):
        verdict = "unstable"
    else:
        verdict = "marginal"
    return tuple(complex(v) for v in lam), verdict


def exact_budget(nums: Sequence[sympy.Expr], free: Sequence[sympy.Symbol]) -> bool:
    """Whether sympy's exact solver is worth trying: a Bezout number within the budget and
    at most one equation of degree above 1.  Two quadratics with the long rationals of
    float parameters already take sympy's Groebner basis 30 s, three cubics minutes (and
    two cubics came back with no solution at all); the numeric search does them in ms."""
    bezout, nonlinear = 1, 0
    for n in nums:
        try:
            deg = sympy.Poly(n, *free).total_degree()
        except (sympy.PolynomialError, sympy.GeneratorsNeeded):
            return False
        bezout *= max(1, deg)
        nonlinear += deg > 1
        if bezout > EXACT_MAX_DEGREE or nonlinear > 1:
            return False
    return True

