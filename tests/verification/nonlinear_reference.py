"""Independent reference for nonlinear bond graphs: every bond's effort and flow as a DAE.

Nothing here comes from bondgraph.  A graph description (plain data, see
:class:`NGraph`) is turned into the residual equations of the bond graph
itself, with every bond's effort ``e_b`` and flow ``f_b`` as unknowns:

* 0-junction: equal efforts on its bonds, ``sum(sign_b f_b) = 0``;
  1-junction: equal flows, ``sum(sign_b e_b) = 0`` (``sign_b = +1`` for a bond
  pointing into the junction, ``-1`` out of it);
* TF (port 1 the bond in, port 2 the bond out): ``e1 = n e2``, ``f2 = n f1``;
  GY: ``e1 = r f2``, ``e2 = r f1``; MTF / MGY the same with the modulus a
  function of a storage element's state;
* one-ports (their bond points into them): ``I``: ``f = law(p)``, ``dp/dt = e``;
  ``C``: ``e = law(q)``, ``dq/dt = f``; ``R``: its law as a residual, written in
  whichever direction it is given (``e - law(f)`` or ``f - law(e)``: no
  inversion, no causality);
* sources (their bond points away from them): ``Se``: ``e = u``, ``Sf``: ``f = u``,
  a modulated ``Se``: ``e = e0 - kp q_ref``.

At given states and time the algebraic part (all ``e_b``, ``f_b``) is solved
by :func:`scipy.optimize.root` from the previous solution; the storage states
are integrated by :func:`scipy.integrate.solve_ivp` with a multistep method
(``LSODA``), the package's simulation being a Runge-Kutta one (``RK45``).

Examples
--------
A mass on a cubic spring and a linear damper, pushed by a force 2:
``m p' = ...``; at rest ``q + q^3 = 2`` gives ``q = 1``.

>>> g = NGraph(elements=(NElement("F", "Se", "input"), NElement("v", "One"),
...     NElement("m", "I", "linear", (1.0,)), NElement("k", "C", "cubic", (1.0, 1.0)),
...     NElement("b", "R", "linear", (0.5,))),
...     bonds=(("F", "v"), ("v", "m"), ("v", "k"), ("v", "b")))
>>> ref = DAEReference(g)
>>> ref.state_names, ref.input_names
(('p_m', 'q_k'), ('F',))
>>> [round(float(v), 12) for v in ref.f([0.0, 1.0], [2.0])]
[0.0, 0.0]
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Callable, Optional, Sequence

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import root

__all__ = ["NElement", "NGraph", "DAEReference", "ReferenceError_", "LAWS"]


class ReferenceError_(Exception):
    """The reference could not solve its algebraic part (a singular or unsolvable DAE)."""


@dataclass(frozen=True)
class NElement:
    """One node: ``kind`` (Se, Sf, I, C, R, TF, GY, MTF, MGY, Zero, One), the law's name,
    its numeric parameters, and for modulated elements the storage element whose state
    modulates it."""

    name: str
    kind: str
    law: str = "linear"
    params: tuple = ()
    ref: Optional[str] = None


@dataclass(frozen=True)
class NGraph:
    elements: tuple
    bonds: tuple            # (tail, head) names
    seed: int = -1
    inputs: dict = field(default_factory=dict)      # input name -> (a, b, w): a + b sin(w t)

    def element(self, name: str) -> NElement:
        return next(e for e in self.elements if e.name == name)


def _sign_sqrt(x):
    return np.sign(x) * np.sqrt(np.abs(x))


#: one-port laws, numeric: (own-variable function, which side it gives)
#: "flow": the I's flow from p; "effort": the C's effort from q, the R's effort from f;
#: "R-flow": the R's flow from its effort (an orifice)
LAWS: dict[tuple[str, str], Callable] = {
    ("I", "linear"): lambda p, m: p / m,
    ("I", "cubic"): lambda p, m, a: p / m + a * p ** 3,
    ("C", "linear"): lambda q, c: q / c,
    ("C", "cubic"): lambda q, k, k3: k * q + k3 * q ** 3,
    ("C", "sat"): lambda q, Fs, qs: Fs * np.tanh(q / qs),
    ("R", "linear"): lambda f, r: r * f,
    ("R", "quad"): lambda f, r0, c: r0 * f + c * f * np.abs(f),
    ("R", "tanh"): lambda f, r0, c, v0: r0 * f + c * np.tanh(f / v0),
    ("R", "orifice"): lambda e, g, kv: g * e + kv * _sign_sqrt(e),
}


#: laws the generator gives in one direction only (to the package): the same physics
ONE_WAY = {"orifice1": "orifice", "quad1": "quad"}

#: derivatives of the R laws in their own variable (by hand)
SLOPES: dict[str, Callable] = {
    "linear": lambda v, r: r,
    "quad": lambda v, r0, c: r0 + 2 * c * abs(v),
    "tanh": lambda v, r0, c, v0: r0 + c / v0 * (1 - math.tanh(v / v0) ** 2),
    "orifice": lambda e, g, kv: g + kv / (2 * math.sqrt(max(abs(e), 1e-12))),
}


class DAEReference:
    """The residual equations of a graph, its state equations ``x' = f(x, u, t)`` by an
    algebraic solve, and their integration."""

    def __init__(self, graph: NGraph):
        self.graph = graph
        els = {e.name: e for e in graph.elements}
        self.els = els
        self.bonds = list(graph.bonds)
        self.B = len(self.bonds)
        self.states: list[tuple[str, int]] = []       # (element name, bond index)
        self.inputs: list[str] = []
        for e in graph.elements:
            if e.kind in ("I", "C"):
                self.states.append((e.name, self._bond_of(e.name)))
            if e.kind in ("Se", "Sf") and e.law == "input":
                self.inputs.append(e.name)
        self.state_names = tuple(("p_" if els[n].kind == "I" else "q_") + n for n, _ in self.states)
        self.input_names = tuple(self.inputs)
        self._index = {n: i for i, (n, _) in enumerate(self.states)}
        self._z = np.zeros(2 * self.B)
        self._ports = [(el, [(k, +1 if h == el.name else -1) for k, (t, h) in
                             enumerate(self.bonds) if el.name in (t, h)])
                       for el in graph.elements]

    def _bond_of(self, name: str) -> int:
        (i,) = [k for k, (t, h) in enumerate(self.bonds) if name in (t, h)]
        return i

    # ------------------------------------------------------------------ residual
    def residual(self, z: np.ndarray, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        """The bond graph's equations at bond variables ``z = (e_0.., f_0..)``."""
        return self.system(z, x, u)[0]

    def system(self, z: np.ndarray, x: np.ndarray, u: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
        """The residual and its Jacobian in ``z`` (hand derivatives of the laws)."""
        return self._system(z, {n: x[i] for i, (n, _) in enumerate(self.states)}, u)

    def _system(self, z: np.ndarray, q: dict, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`system` with the storage quantities ``q`` given by element name."""
        B = self.B
        e, f = z[:B], z[B:]
        r = np.zeros(2 * B)
        J = np.zeros((2 * B, 2 * B))
        row = [0]
        uu = dict(zip(self.inputs, u))

        def eq(value: float, coeffs: dict) -> None:
            i = row[0]
            r[i] = value
            for col, c in coeffs.items():
                J[i, col] += c
            row[0] += 1
        for el, mine in self._ports:
            kind, P = el.kind, el.params
            if kind in ("Zero", "One"):
                off_same, off_sum = (0, B) if kind == "Zero" else (B, 0)
                k0 = mine[0][0]
                for k, _ in mine[1:]:
                    eq(z[off_same + k] - z[off_same + k0], {off_same + k: 1.0, off_same + k0: -1.0})
                eq(sum(s * z[off_sum + k] for k, s in mine), {off_sum + k: float(s) for k, s in mine})
            elif kind in ("TF", "GY", "MTF", "MGY"):
                (k1,) = [k for k, s in mine if s > 0]
                (k2,) = [k for k, s in mine if s < 0]
                n = P[0]
                if kind == "MTF":
                    n = P[0] * math.cos(q[el.ref]) + P[1]
                elif kind == "MGY":
                    n = P[0] * (1 + 0.5 * math.tanh(q[el.ref]))
                if kind in ("TF", "MTF"):
                    eq(e[k1] - n * e[k2], {k1: 1.0, k2: -n})
                    eq(f[k2] - n * f[k1], {B + k2: 1.0, B + k1: -n})
                else:
                    eq(e[k1] - n * f[k2], {k1: 1.0, B + k2: -n})
                    eq(e[k2] - n * f[k1], {k2: 1.0, B + k1: -n})
            else:
                (k, s) = mine[0]
                name = ONE_WAY.get(el.law, el.law)
                law = LAWS.get((kind, name))
                if kind == "I":
                    eq(f[k] - law(q[el.name], *P), {B + k: 1.0})
                elif kind == "C":
                    eq(e[k] - law(q[el.name], *P), {k: 1.0})
                elif kind == "R" and name == "orifice":
                    eq(f[k] - law(e[k], *P), {B + k: 1.0, k: -SLOPES[name](e[k], *P)})
                elif kind == "R":
                    eq(e[k] - law(f[k], *P), {k: 1.0, B + k: -SLOPES[name](f[k], *P)})
                elif kind == "Se":
                    eq(e[k] - (uu[el.name] if el.law == "input" else P[0] - P[1] * q[el.ref]),
                       {k: 1.0})
                elif kind == "Sf":
                    eq(f[k] - uu[el.name], {B + k: 1.0})
        return r, J

    def solve(self, x: Sequence[float], u: Sequence[float], z0: Optional[np.ndarray] = None
              ) -> np.ndarray:
        """All bond efforts and flows at states ``x`` and inputs ``u``: Newton's method from
        the last solution, scipy's ``root`` if it does not converge."""
        x, u = np.asarray(x, dtype=float), np.asarray(u, dtype=float)
        z = (self._z if z0 is None else z0).copy()
        with np.errstate(all="ignore"):
            for _ in range(50):
                r, J = self.system(z, x, u)
                scale = 1.0 + float(np.max(np.abs(z)))
                if np.all(np.isfinite(r)) and float(np.max(np.abs(r))) <= 1e-12 * scale:
                    self._z = z
                    return z
                try:
                    step = np.linalg.solve(J, r)
                except np.linalg.LinAlgError:
                    break
                if not np.all(np.isfinite(step)):
                    break
                z = z - step
        for start, jac in ((self._z, True), (np.zeros(2 * self.B), True), (self._z, None)):
            with warnings.catch_warnings(), np.errstate(all="ignore"):
                warnings.simplefilter("ignore")
                sol = root(self.residual, start, args=(x, u), method="hybr",
                           jac=(lambda zz, xx, uu: self.system(zz, xx, uu)[1]) if jac else None,
                           options={"xtol": 1e-14})
            if np.all(np.isfinite(sol.x)):
                r = self.residual(sol.x, x, u)
                scale = 1.0 + float(np.max(np.abs(sol.x)))
                if float(np.max(np.abs(r))) <= 1e-10 * scale:
                    self._z = sol.x
                    return sol.x
        raise ReferenceError_(f"algebraic part not solved at x={list(x)}, u={list(u)}")

    def f(self, x: Sequence[float], u: Sequence[float]) -> np.ndarray:
        """``x' = f(x, u)``: ``dp/dt = e`` of each I's bond, ``dq/dt = f`` of each C's."""
        z = self.solve(x, u)
        e, fl = z[:self.B], z[self.B:]
        return np.array([e[k] if self.els[n].kind == "I" else fl[k] for n, k in self.states])

    def f_at(self, t: float, x: Sequence[float]) -> np.ndarray:
        """``x'`` at time ``t`` (the inputs from their time law)."""
        return self.f(x, self.u_of_t(t))

    def jacobians(self, x: Sequence[float], u: Sequence[float], h: float = 1e-6
                  ) -> tuple[np.ndarray, np.ndarray]:
        """``df/dx`` and ``df/du`` by central differences (steps ``h max(1, |v|)``)."""
        x, u = np.asarray(x, dtype=float), np.asarray(u, dtype=float)
        A = np.zeros((len(x), len(x)))
        B = np.zeros((len(x), len(u)))
        for j in range(len(x)):
            d = h * max(1.0, abs(x[j]))
            xp, xm = x.copy(), x.copy()
            xp[j] += d
            xm[j] -= d
            A[:, j] = (self.f(xp, u) - self.f(xm, u)) / (2 * d)
        for j in range(len(u)):
            d = h * max(1.0, abs(u[j]))
            up, um = u.copy(), u.copy()
            up[j] += d
            um[j] -= d
            B[:, j] = (self.f(x, up) - self.f(x, um)) / (2 * d)
        return A, B

    def u_of_t(self, t: float) -> np.ndarray:
        return np.array([a + b * math.sin(w * t) for a, b, w in
                         (self.graph.inputs[n] for n in self.inputs)])

    def simulate(self, t_end: float, t_eval: np.ndarray, x0: Sequence[float],
                 rtol: float = 1e-10, atol: float = 1e-12) -> np.ndarray:
        """States at ``t_eval`` (rows), integrated with LSODA (Adams / BDF multistep)."""
        sol = solve_ivp(self.f_at, (0.0, t_end), np.asarray(x0, dtype=float), method="LSODA",
                        t_eval=t_eval, rtol=rtol, atol=atol)
        if not sol.success:
            raise ReferenceError_(f"integration failed: {sol.message}")
        return sol.y.T

    def equilibria(self, u: Sequence[float], starts: int = 12, seed: int = 0) -> list:
        """Equilibria found from several starts (each checked), for a missed-root check."""
        rng = np.random.default_rng(seed)
        found = []
        n = len(self.states)
        for k in range(starts):
            x0 = np.zeros(n) if k == 0 else rng.normal(0, 2.0, n)
            try:
                with warnings.catch_warnings(), np.errstate(all="ignore"):
                    warnings.simplefilter("ignore")
                    sol = root(lambda x: self.f(x, u), x0, method="hybr")
                if sol.success and np.max(np.abs(self.f(sol.x, u))) < 1e-9:
                    found.append(sol.x)
            except ReferenceError_:
                continue
        return found
