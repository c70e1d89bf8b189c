"""Numeric form of one mode: right-hand side, outputs, guards, and the state re-initialisation.

The state of a switched simulation is kept mode-independently as the stored
quantities of every storage element (``q_all``: the momentum of each I, the
displacement of each C, in the order of :attr:`SwitchedModel.energy_signals`)
plus the integrator states of displacement/momentum signals, by signal.

Entering a mode, its states ``x`` are found from ``q_all``.  When the mode
puts storage in derivative causality, its stored quantities are an affine
function of its states, ``q = M x + c(t, u)``, and a jump may be needed.  The
new state is the projection of ``q_old`` on that set in the metric of the
energy Hessian ``Q`` (exact for linear storage, the Hessian at ``q_old``
otherwise)::

    x = (M^T Q M)^-1 M^T Q (q_old - c)

which is what an impulse along the constraint forces gives: the impulse
``q_new - q_old`` is orthogonal (in ``Q``) to every motion the new mode
allows.  Two inertias locked: the total momentum is conserved and the common
velocity is ``(J1 w1 + J2 w2)/(J1 + J2)``; a capacitor shorted: its charge
goes to zero.  The energy lost, ``H(q_old) - H(q_new)``, is reported.
"""

from __future__ import annotations

import math
from typing import Callable, Optional, Sequence

import numpy as np
import sympy

from ..signals import Signal
from ..signals import t as T_SYM
from .errors import HybridError
from .modes import Mode, ModeModel, ModeSet

__all__ = ["CompiledMode", "EnergyMetric"]


def _lambdify(args: Sequence, exprs: Sequence[sympy.Expr]) -> Callable:
    return sympy.lambdify(list(args), list(exprs), modules="numpy", cse=True)


class EnergyMetric:
    """The total stored energy and its Hessian as numeric functions of ``q_all``."""

    def __init__(self, sm: ModeSet, subs: dict) -> None:
        qs, H = sm.energy()
        H = H.xreplace(subs)
        self.n = len(qs)
        self._H = _lambdify(qs, [H])
        hess = sympy.hessian(H, qs) if qs else None
        self._Q = _lambdify(qs, list(hess)) if hess is not None else None
        #: the Hessian when the energy is quadratic (a constant), else None
        self.constant: Optional[np.ndarray] = None
        if hess is not None and not hess.free_symbols:
            self.constant = np.array(hess.tolist(), dtype=np.float64)

    def energy(self, q: np.ndarray) -> float:
        return float(self._H(*q)[0]) if self.n else 0.0

    def hessian(self, q: np.ndarray) -> np.ndarray:
        if self.constant is not None:
            return self.constant
        if self._Q is None:
            return np.zeros((0, 0))
        return np.asarray(self._Q(*q), dtype=np.float64).reshape(self.n, self.n)


class CompiledMode:
    """One mode with its numbers substituted, as numpy functions of ``(t, x, u)``.

    Attributes
    ----------
    mode : Mode
    states : tuple of str
    storage_rows : tuple
        For each storage state, the index in ``q_all`` it is (None for none).
    integrators : tuple of (str, str)
        Integrator states and the signal each integrates.
    guards : tuple of (str, callable)
        For each switch with a guard in this mode, ``g(t, x, u)`` (>= 0 while consistent).
    """

    def __init__(self, sm: ModeSet, mm: ModeModel, subs: dict,
                 inputs: Sequence[sympy.Symbol], periods: Optional[dict] = None) -> None:
        periods = dict(periods or {})
        full = mm.full
        self.mode: Mode = mm.mode
        self.model = full
        if full.input_derivatives:
            needed = ", ".join(str(s) for s in full.input_derivatives)
            raise HybridError(
                f"mode ({mm.mode}) of model {sm.name!r} needs the input derivatives {needed} "
                "(a storage element in derivative causality driven by an input): give that "
                "source a value= expression of time bondgraph.t so it can be differentiated")
        x = tuple(full.states)
        self.states = tuple(s.name for s in x)
        self.n_storage = full.storage_states
        self.integrators = tuple(full.integrators)
        args = (T_SYM, *x, *inputs)
        outs = {name: ex.xreplace(subs) for name, ex in zip(full.output_names, full.output_exprs)}
        self.signal_names = tuple(str(s) for s in sm.guard_signals)
        self.user_names = tuple(n for n in full.output_names if not n.startswith(("hyb_E", "hyb_S")))
        self.rhs = _lambdify(args, [e.xreplace(subs) for e in full.rhs])
        nq = len(sm.energy_signals)
        q_exprs = [outs[f"hyb_E{k}"] for k in range(nq)]
        s_exprs = [outs[f"hyb_S{k}"] for k in range(len(sm.guard_signals))]
        self._outs = _lambdify(args, [outs[n] for n in self.user_names])
        self._q = _lambdify(args, q_exprs)
        self._s = _lambdify(args, s_exprs)
        # which q_all entry each storage state is, and the affine map q = M x + c
        xs = x[: self.n_storage]
        rows = []
        for sym in xs:
            hit = [k for k, e in enumerate(q_exprs) if e == sym]
            rows.append(hit[0] if hit else None)
        self.storage_rows = tuple(rows)
        self.dependent = tuple(full.augmented.derivative)
        J = sympy.Matrix(q_exprs).jacobian(list(xs)) if xs and q_exprs else sympy.zeros(nq, len(xs))
        self.affine = not (J.free_symbols & set(x))
        zero = {s: 0 for s in x}
        self._M = _lambdify((T_SYM, *inputs), list(J)) if self.affine else None
        #: the re-initialisation's affine map does not read time or inputs
        self._constant_map = self.affine and not ((J.free_symbols | set().union(
            *(sympy.sympify(e, strict=True).free_symbols for e in q_exprs)) - set(x)) & ({T_SYM} | set(inputs)))
        self._projection: Optional[tuple] = None
        self._c = _lambdify((T_SYM, *inputs), [e.xreplace(zero) for e in q_exprs]) if self.affine else None
        # guards in this mode's variables: each switch's guard with its signals replaced
        sig_map = dict(zip(sm.guard_signals, s_exprs))
        names: list[str] = []
        exprs: list = []
        timed: dict[str, Callable] = {}
        periodic: dict[str, float] = {}
        constant: set = set()
        explicit: list = []
        for name in sm.switches:
            g = sm.element(name).guard(mm.mode.is_on(name))
            if g is None:
                continue
            g = g.xreplace(sig_map).xreplace(subs)
            left = [s for s in g.free_symbols if isinstance(s, Signal)]
            if left:
                raise HybridError(f"guard of switch {name!r} reads {left[0]}, which mode "
                                  f"({mm.mode}) does not define")
            _refuse_complex(g, f"the guard of switch {name!r} in mode ({mm.mode})")
            names.append(name)
            exprs.append(g)
            free = g.free_symbols
            if not free & set(x) and not free & set(inputs):
                if T_SYM not in free:
                    constant.add(name)
                else:
                    timed[name] = sympy.lambdify([T_SYM], g, modules="numpy")
                    if name in periods:
                        periodic[name] = periods[name]
            if (T_SYM in free or free & set(inputs)) and name not in periodic:
                explicit.append(name)
        self.guard_names: tuple[str, ...] = tuple(names)
        self._g = _lambdify(args, exprs) if exprs else None
        self.guards = tuple((n, _lambdify(args, [e])) for n, e in zip(names, exprs))
        #: the guards that depend on time only, as vectorized functions of t
        self.time_guards: dict[str, Callable] = timed
        #: the time-only guards of a switch with a period (found by scanning one period)
        self.periodic: dict[str, float] = periodic
        #: the guards that are constants in this mode (they never cross)
        self.constant_guards: frozenset = frozenset(constant)
        #: the guards that read time or an input: the step resolves them as if integrated
        self.explicit_guards: tuple[str, ...] = tuple(explicit)
        self._gx = (_lambdify(args, [exprs[names.index(n)] for n in explicit])
                    if explicit else None)
        self._guard_exprs = tuple(exprs)
        self._rates: Optional[list] = None
        self._index: dict = {}
        self._flow: Optional[object] = None
        self._flow_done = False
        self._rhs_exprs = tuple(e.xreplace(subs) for e in full.rhs)
        self._args = args
        self._x_syms = x
        self._u_syms = tuple(inputs)
        for what, group in (("right-hand side", full.rhs), ("outputs", full.output_exprs)):
            for e in group:
                _refuse_complex(e.xreplace(subs), f"the {what} of mode ({mm.mode})")

    # ------------------------------------------------------------ evaluation
    def f(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return np.asarray(self.rhs(t, *x, *u), dtype=float).reshape(-1)

    def outputs(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return np.asarray(self._outs(t, *x, *u), dtype=float).reshape(-1)

    def stored(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return np.asarray(self._q(t, *x, *u), dtype=float).reshape(-1)

    def signals(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return np.asarray(self._s(t, *x, *u), dtype=float).reshape(-1)

    def guard_values(self, t: float, x: np.ndarray, u: np.ndarray) -> dict[str, float]:
        return dict(zip(self.guard_names, self.guard_array(t, x, u)))

    def guard_array(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        """Every guard of the mode at one instant, in the order of :attr:`guard_names`."""
        if self._g is None:
            return np.zeros(0)
        return np.asarray(self._g(t, *x, *u), dtype=float).reshape(-1)

    def index_of(self, names: tuple) -> tuple:
        """``(name, index)`` of those of ``names`` that have a guard in this mode (cached)."""
        hit = self._index.get(names)
        if hit is None:
            pos = {n: j for j, n in enumerate(self.guard_names)}
            hit = self._index[names] = tuple((n, pos[n]) for n in names if n in pos)
        return hit

    def guard_matrix(self, ts: np.ndarray, xs: np.ndarray, us: np.ndarray) -> np.ndarray:
        """Every guard at many instants (``xs``: ``(n, m)``, ``us``: ``(n_u, m)``): ``(k, m)``."""
        if self._g is None:
            return np.zeros((0, ts.size))
        vals = self._g(ts, *xs, *us)
        return np.vstack([np.broadcast_to(np.asarray(v, dtype=float), ts.shape) for v in vals])

    def explicit_values(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        """The guards that read time or inputs (what the integration also resolves)."""
        if self._gx is None:
            return np.zeros(0)
        return np.asarray(self._gx(t, *x, *u), dtype=float).reshape(-1)

    @property
    def affine_flow(self):
        """The exact flow (:class:`~bondgraph.hybrid._affine.AffineFlow`) when the mode is
        ``x' = A x + b`` with constants and no guard reads time or inputs; else None."""
        if not self._flow_done:
            self._flow_done = True
            xs = list(self._x_syms)
            if xs and not self.explicit_guards and all(
                    e.free_symbols <= set(xs) for e in self._rhs_exprs):
                J = sympy.Matrix(self._rhs_exprs).jacobian(xs)
                if not J.free_symbols:
                    from ._affine import AffineFlow

                    b = [float(e.xreplace({v: 0 for v in xs})) for e in self._rhs_exprs]
                    self._flow = AffineFlow.of(np.array(J.tolist(), dtype=float), np.array(b))
        return self._flow

    def trend(self, name: str, t: float, x: np.ndarray, u: np.ndarray, u_dot: np.ndarray,
              rel: float) -> int:
        """The sign (1, 0, -1) of the first nonzero time derivative of guard ``name`` along this
        mode's equations (first, then second); 0 when both vanish within ``rel`` of their
        terms' magnitudes (the guard stays at zero)."""
        if self._rates is None:
            self._rates = [_rate_terms(e, self._x_syms, self._rhs_exprs, self._u_syms, self._args)
                           for e in self._guard_exprs]
        k = self.guard_names.index(name)
        for fn, n_u in self._rates[k]:
            terms = np.asarray(fn(t, *x, *u), dtype=float).reshape(-1)
            if n_u:
                terms = np.concatenate([terms[:-n_u], terms[-n_u:] * u_dot])
            total, scale = float(terms.sum()), float(np.abs(terms).sum())
            if not math.isfinite(total):
                return 0
            if total > rel * scale:
                return 1
            if total < -rel * scale:
                return -1
        return 0

    # ------------------------------------------------------------ entering the mode
    def enter(self, t: float, q_old: np.ndarray, integ: dict, u: np.ndarray,
              metric: EnergyMetric, sm: ModeSet) -> tuple[np.ndarray, np.ndarray, float]:
        """The mode's state from the stored quantities ``q_old`` and integrator values:
        ``(x, q_new, energy_loss)``."""
        n = self.n_storage
        x = np.zeros(len(self.states))
        for j, (name, signal) in enumerate(self.integrators):
            if signal not in integ:
                raise HybridError(f"mode ({self.mode}) of model {sm.name!r}: no value for the "
                                  f"integrator {name!r} of {signal}")
            x[n + j] = integ[signal]
        if not self.dependent:
            for j, row in enumerate(self.storage_rows):
                x[j] = q_old[row]
            return x, q_old.copy(), 0.0
        if not self.affine:
            raise HybridError(
                f"mode ({self.mode}) of model {sm.name!r} puts {', '.join(self.dependent)} in "
                "derivative causality with stored quantities that are not affine in the "
                "mode's states; the state re-initialisation needs linear storage laws there")
        assert self._M is not None and self._c is not None     # affine, checked above
        proj = self._projection
        if proj is not None:        # M, c and the energy metric constant: found once
            P, M, c = proj
            xs = P @ (q_old - c)
            x[:n] = xs
            q_new = M @ xs + c
        else:
            M = np.asarray(self._M(t, *u), dtype=np.float64).reshape(len(q_old), n)
            c = np.asarray(self._c(t, *u), dtype=np.float64).reshape(-1)
            if n:
                Q = metric.hessian(q_old)
                P = np.linalg.solve(M.T @ Q @ M, M.T @ Q)
                xs = P @ (q_old - c)
                x[:n] = xs
                q_new = M @ xs + c
                if self._constant_map and metric.constant is not None:
                    self._projection = (P, M, c)
            else:
                q_new = c
                if self._constant_map:
                    self._projection = (np.zeros((0, len(q_old))), M, c)
        loss = metric.energy(q_old) - metric.energy(q_new)
        return x, q_new, loss


def _piecewise_constant(expr: sympy.Expr) -> tuple[sympy.Expr, dict]:
    """``expr`` with its piecewise-constant parts (floor, ceiling, sign, Heaviside) replaced by
    constants, for differentiation between their jumps; and the map back."""
    back: dict = {}

    def const(e):
        d = sympy.Dummy("pc", real=True)
        back[d] = e
        return d

    out = expr.replace(lambda e: isinstance(e, sympy.frac), lambda e: e.args[0] - const(sympy.floor(e.args[0])))
    out = out.replace(lambda e: isinstance(e, (sympy.floor, sympy.ceiling, sympy.sign, sympy.Heaviside)),
                      const)
    return out, back


def _rate_terms(g: sympy.Expr, xs: Sequence, rhs: Sequence, us: Sequence, args: Sequence) -> list:
    """For the first and second time derivatives of ``g`` along ``x' = rhs``: a function of
    ``args`` giving the terms whose sum is the derivative (``dg/dt``, ``dg/dx_i rhs_i``, then
    ``dg/du_k``, which the caller multiplies by the inputs' rates), and the number of input terms."""
    expr, back = _piecewise_constant(g)
    out = []
    for _ in range(2):
        # each product split along the sums of the right-hand side, so that the scale the sum
        # is compared with is that of its parts (a rate that cancels to rounding is a tie)
        terms = list(sympy.Add.make_args(sympy.diff(expr, T_SYM)))
        for xi, fi in zip(xs, rhs):
            d = sympy.diff(expr, xi)
            if d != 0:
                terms += [d * a for a in sympy.Add.make_args(fi)]
        n_own = len(terms)
        terms += [sympy.diff(expr, uk) for uk in us]
        clean = [e.replace(lambda a: isinstance(a, sympy.DiracDelta), lambda a: sympy.Integer(0))
                 .xreplace(back) for e in terms]
        out.append((_lambdify(args, clean), len(us)))
        expr = sympy.Add(*terms[:n_own])
    return out


def _refuse_complex(expr: sympy.Expr, where: str) -> None:
    """A guard or equation that became complex or non-finite with the numbers substituted."""
    if sympy.sympify(expr, strict=True).has(sympy.I):
        raise HybridError(f"{where} is complex ({expr}); a switched model's equations and "
                          "guards must be real")


def integrated(sm: ModeSet, cm: CompiledMode, t: float, x: np.ndarray,
               u: np.ndarray) -> dict:
    """The value of every tracked signal (by its string) in mode ``cm`` at ``(t, x)``."""
    vals = cm.signals(t, x, u)
    return dict(zip(cm.signal_names, vals.tolist()))


def pick(candidates: list) -> Optional[tuple]:
    """The chosen candidate: consistent guards, then no energy lost, then fewest flips."""
    ok = [c for c in candidates if c[0]]
    if not ok:
        return None
    return min(ok, key=lambda c: (c[1], c[2]))
