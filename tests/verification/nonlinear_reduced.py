"""Independent index reduction for the nonlinear reference: storage in derivative causality.

Nothing here comes from bondgraph.  When some storage elements are rigidly
constrained by the others (two inertias on one 1-junction, a compliance fed
through an MTF from a node another compliance holds), the reference's
all-bond system with every storage quantity given is singular: those
quantities are not free, and their rates are not algebraic.

:class:`ReducedReference` keeps the independent storage quantities ``x`` as
states.  Given ``x`` and a value ``r`` for the rate of each dependent storage
element (the effort on a dependent I, the flow into a dependent C), its
algebraic unknowns are every bond's effort and flow *and* the dependent
quantities ``x_D``; its equations ``F(w; x, u) = 0`` are the bond graph's (the
dependent elements' laws written with ``x_D``) and ``rate variable = r``.  The
rates must be the time derivatives of ``x_D`` along the motion ``(x + s x', t +
s)``: by the implicit-function theorem ``dw/ds = -F_w^-1 dF/ds``, with
``dF/ds`` the derivative of the residual along the motion by the five-point
stencil (``F_w`` by the hand-written law slopes, its ``x_D`` columns by
differences), and ``r`` is found by Newton's method on ``r = rate(r)``.  The
constraint is differentiated numerically, never symbolically (the package
differentiates it symbolically).

Examples
--------
Two inertias (1 and 3) on one 1-junction driven by a force 2: the effective
inertia is 4, so ``p1' = 2/4``.

>>> g = NGraph(elements=(NElement("F", "Se", "input"), NElement("v", "One"),
...     NElement("a", "I", "linear", (1.0,)), NElement("b", "I", "linear", (3.0,))),
...     bonds=(("F", "v"), ("v", "a"), ("v", "b")), inputs={"F": (2.0, 0.0, 1.0)})
>>> ref = ReducedReference(g, {"b"})
>>> ref.state_names, round(float(ref.f([0.3], [2.0])[0]), 9)
(('p_a',), 0.5)
"""

from __future__ import annotations

import warnings
from typing import Optional, Sequence

import numpy as np
from scipy.optimize import root

from verification.nonlinear_reference import (DAEReference, NElement, NGraph,  # noqa: F401
                                              ReferenceError_)

__all__ = ["ReducedReference"]

#: the stencil's step in time (scaled down when the states move fast)
STEP = 1e-3


class ReducedReference(DAEReference):
    """The reference with the storage elements ``dependent`` constrained (see the module
    docstring); states, inputs and :meth:`f` as :class:`DAEReference`'s."""

    def __init__(self, graph: NGraph, dependent: set):
        super().__init__(graph)
        self.dep = [(n, k) for n, k in self.states if n in dependent]
        self.states = [(n, k) for n, k in self.states if n not in dependent]
        self.state_names = tuple(("p_" if self.els[n].kind == "I" else "q_") + n
                                 for n, _ in self.states)
        self._index = {n: i for i, (n, _) in enumerate(self.states)}
        self._w = np.zeros(2 * self.B + len(self.dep))
        self._r = np.zeros(len(self.dep))
        self._J: Optional[np.ndarray] = None     # d(rate(r) - r)/dr, kept between calls
        self._rate_col = [k if self.els[n].kind == "I" else self.B + k for n, k in self.dep]

    # ------------------------------------------------------------------ algebraic part
    def _reduced(self, w: np.ndarray, x: np.ndarray, u: np.ndarray, r: np.ndarray,
                 dxd: Optional[np.ndarray] = None) -> tuple[np.ndarray, np.ndarray]:
        """Residual and Jacobian in ``w = (bond variables, x_D)``; the ``x_D`` columns by
        central differences unless given (``dxd``)."""
        B2, nd = 2 * self.B, len(self.dep)
        q = {n: x[i] for i, (n, _) in enumerate(self.states)}

        def at(xd):
            return self._system(w[:B2], {**q, **{n: xd[j] for j, (n, _) in
                                                  enumerate(self.dep)}}, u)
        res, Jz = at(w[B2:])
        J = np.zeros((B2 + nd, B2 + nd))
        J[:B2, :B2] = Jz
        if dxd is not None:
            J[:B2, B2:] = dxd
        for j in range(nd if dxd is None else 0):
            d = 1e-7 * max(1.0, abs(w[B2 + j]))
            up, dn = w[B2:].copy(), w[B2:].copy()
            up[j] += d
            dn[j] -= d
            J[:B2, B2 + j] = (at(up)[0] - at(dn)[0]) / (2 * d)
        rows = np.array([w[c] for c in self._rate_col]) - r
        for j, c in enumerate(self._rate_col):
            J[B2 + j, c] = 1.0
        return np.concatenate([res, rows]), J

    def solve_reduced(self, x: Sequence[float], u: Sequence[float], r: np.ndarray,
                      w0: Optional[np.ndarray] = None) -> np.ndarray:
        """Bond variables and ``x_D`` at ``(x, u)`` with the dependent rates ``r``: Newton
        (the ``x_D`` columns of the Jacobian from its first step) polished to rounding,
        scipy's ``root`` if it does not converge."""
        x, u = np.asarray(x, dtype=float), np.asarray(u, dtype=float)
        w = (self._w if w0 is None else w0).copy()
        B2 = 2 * self.B
        dxd, last = None, np.inf
        with np.errstate(all="ignore"):
            for _ in range(60):
                res, J = self._reduced(w, x, u, r, dxd)
                dxd = J[:B2, B2:].copy()
                scale = 1.0 + float(np.max(np.abs(w)))
                if last <= 1e-13 * scale and float(np.max(np.abs(res))) <= 1e-11 * scale:
                    self._w = w
                    return w
                try:
                    step = np.linalg.solve(J, res)
                except np.linalg.LinAlgError:
                    break
                if not np.all(np.isfinite(step)):
                    break
                w = w - step
                last = float(np.max(np.abs(step)))
        # next to an orifice's kink (an infinite slope) the residual stalls near 1e-11:
        # accepted below 1e-10, as the full reference does
        # (there the analytic slope is huge: differences step over the kink)
        zero = np.zeros_like(self._w)
        for start, method, jac in ((self._w, "hybr", True), (zero, "hybr", True),
                                   (zero, "lm", True), (zero, "lm", False),
                                   (self._w, "lm", False)):
            with warnings.catch_warnings(), np.errstate(all="ignore"):
                warnings.simplefilter("ignore")
                sol = root(lambda ww: self._reduced(ww, x, u, r)[0], start, method=method,
                           jac=(lambda ww: self._reduced(ww, x, u, r)[1]) if jac else None)
            if np.all(np.isfinite(sol.x)):
                res = self._reduced(sol.x, x, u, r)[0]
                if float(np.max(np.abs(res))) <= 1e-10 * (1.0 + float(np.max(np.abs(sol.x)))):
                    self._w = sol.x
                    return sol.x
        raise ReferenceError_(f"constrained algebraic part not solved at x={list(x)}, "
                              f"u={list(u)}")

    # ------------------------------------------------------------------ state equations
    def _rates(self, w: np.ndarray) -> np.ndarray:
        e, fl = w[:self.B], w[self.B:2 * self.B]
        return np.array([e[k] if self.els[n].kind == "I" else fl[k] for n, k in self.states])

    def _mismatch(self, x, u, t, r) -> tuple[np.ndarray, np.ndarray]:
        """``rate(r) - r`` and ``x'``: the rate is ``dx_D/ds`` of the solution along the
        motion ``(x + s x', t + s)``, from the implicit-function theorem with the
        residual's derivative in ``s`` by the five-point stencil."""
        w = self.solve_reduced(x, u, r)
        xdot = self._rates(w)
        _, J = self._reduced(w, x, u, r)
        B2 = 2 * self.B
        h = STEP / max(1.0, float(np.max(np.abs(xdot), initial=0.0)))

        def moved(k: int) -> np.ndarray:
            us = u if t is None else self.u_of_t(t + k * h)
            return self._reduced(w, x + k * h * xdot, us, r, J[:B2, B2:])[0]
        dF = (moved(-2) - 8 * moved(-1) + 8 * moved(1) - moved(2)) / (12 * h)
        try:
            rate = -np.linalg.solve(J, dF)[B2:]
        except np.linalg.LinAlgError as exc:   # a saturating law near its limit: x_D -> inf
            raise ReferenceError_(f"the constraint is singular at x={list(x)}, u={list(u)}"
                                  ) from exc
        return rate - r, xdot

    def f(self, x: Sequence[float], u: Sequence[float], t: Optional[float] = None
          ) -> np.ndarray:
        """``x' = f(x, u)`` of the independent storage (inputs held at ``u`` along the
        motion, or following their time law from ``t`` when given)."""
        x, u = np.asarray(x, dtype=float), np.asarray(u, dtype=float)
        r = self._r.copy()
        for it in range(8):
            F, xdot = self._mismatch(x, u, t, r)
            scale = 1.0 + float(np.max(np.abs(r), initial=0.0))
            # the stencil's rounding leaves F near 1e-11 where the constraint is stiff (a
            # saturating spring near its limit): converged below 1e-10
            if float(np.max(np.abs(F), initial=0.0)) <= 1e-10 * scale:
                break
            if self._J is None or it >= 2:     # the last point's Jacobian first (F is
                self._J = np.zeros((len(r), len(r)))     # nearly affine in r)
                for j in range(len(r)):
                    d = 1e-4 * max(1.0, abs(r[j]))
                    rp = r.copy()
                    rp[j] += d
                    self._J[:, j] = (self._mismatch(x, u, t, rp)[0] - F) / d
            try:
                step = np.linalg.solve(self._J, F)
            except np.linalg.LinAlgError as exc:
                raise ReferenceError_(f"the dependent rates are not determined at x={list(x)}"
                                      ) from exc
            r = r - step
            if float(np.max(np.abs(step), initial=0.0)) <= 1e-10 * scale:
                break       # x' moves by about the step
        else:
            raise ReferenceError_(f"the dependent rates did not converge at x={list(x)}")
        self._r = r
        return xdot

    def f_at(self, t: float, x: Sequence[float]) -> np.ndarray:
        return self.f(x, self.u_of_t(t), t)

    def jacobians(self, x: Sequence[float], u: Sequence[float], h: float = 1e-6
                  ) -> tuple[np.ndarray, np.ndarray]:
        """``df/dx`` and ``df/du`` by the five-point stencil with steps ``100 h max(1, |v|)``
        (the rates come from differences: rounding of 1e-13 in ``f`` would pass 1e-7 with
        steps of 1e-6; the stencil's truncation, of order ``h^4``, stays below it)."""
        x, u = np.asarray(x, dtype=float), np.asarray(u, dtype=float)

        def column(v: np.ndarray, j: int, at) -> np.ndarray:
            d = 100 * h * max(1.0, abs(v[j]))
            out = []
            for k in (-2, -1, 1, 2):
                w = v.copy()
                w[j] += k * d
                out.append(at(w))
            return (out[0] - 8 * out[1] + 8 * out[2] - out[3]) / (12 * d)
        A = np.zeros((len(x), len(x)))
        B = np.zeros((len(x), len(u)))
        for j in range(len(x)):
            A[:, j] = column(x, j, lambda w: self.f(w, u))
        for j in range(len(u)):
            B[:, j] = column(u, j, lambda w: self.f(x, w))
        return A, B
