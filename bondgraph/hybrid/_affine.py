"""The exact flow of a mode whose equations are ``x' = A x + b`` with constant ``A``, ``b`` (private).

Most modes of switched circuits are linear and time-invariant between events
(a buck converter's three).  Their solution from ``x0`` is, with the
eigendecomposition ``A = V diag(lam) V^-1``::

    x(s) = x_p + V diag(exp(lam s)) V^-1 (x0 - x_p),   A x_p = -b,

exact at every instant and vectorized over many instants, so that the
segment integration (:mod:`bondgraph.hybrid._segment`) needs no solver
there: it samples the guards on the exact solution in steps no longer than
a fifth of the fastest time constant and locates their falls by brentq on it.
A mode with a singular or badly conditioned ``A`` (an integrator, a
defective matrix) has no :class:`AffineFlow` and is integrated numerically.

Examples
--------
>>> import numpy as np
>>> flow = AffineFlow.of(np.array([[-1.0]]), np.array([2.0]))
>>> [round(float(v), 12) for v in flow.at(np.array([0.0, np.log(2.0)]), 0.0, np.array([0.0]))[0]]
[0.0, 1.0]
"""

from __future__ import annotations

from typing import Optional

import numpy as np

__all__ = ["AffineFlow"]


class AffineFlow:
    """``x' = A x + b`` solved exactly (see the module docstring)."""

    def __init__(self, lam: np.ndarray, V: np.ndarray, Vinv: np.ndarray, xp: np.ndarray) -> None:
        self.lam, self.V, self.Vinv, self.xp = lam, V, Vinv, xp
        rate = float(np.max(np.abs(lam))) if lam.size else 0.0
        #: longest step between guard samples: a fifth of the fastest time constant (an
        #: oscillation sampled every 0.04 rad)
        self.step = 0.2 / rate if rate > 0 else np.inf
        self.real = bool(np.all(lam.imag == 0))
        self._steps: dict = {}

    @classmethod
    def of(cls, A: np.ndarray, b: np.ndarray) -> Optional["AffineFlow"]:
        """The flow of ``x' = A x + b``, or None when ``A`` is singular, defective or badly
        conditioned (then a solver integrates the mode)."""
        n = A.shape[0]
        if n == 0 or not np.all(np.isfinite(A)) or not np.all(np.isfinite(b)):
            return None
        try:
            if np.linalg.cond(A) > 1e10:
                return None
            lam, V = np.linalg.eig(A)
            if np.linalg.cond(V) > 1e6:
                return None
            Vinv = np.linalg.inv(V)
            xp = -np.linalg.solve(A, b)
        except np.linalg.LinAlgError:
            return None
        return cls(lam, V, Vinv, xp)

    def at(self, s: np.ndarray, t0: float, x0: np.ndarray) -> np.ndarray:
        """The states at times ``s`` (an array) from ``x0`` at ``t0``: shape ``(n, len(s))``."""
        return self.from_coefficients(s, t0, self.coefficients(x0))

    def coefficients(self, x0: np.ndarray) -> np.ndarray:
        """The modal coefficients ``V^-1 (x0 - x_p)`` of a start ``x0``."""
        return self.Vinv @ (np.asarray(x0, dtype=float) - self.xp)

    def samples(self, fractions: np.ndarray, offset: float, h: float, c: np.ndarray) -> np.ndarray:
        """The states at ``offset + h*fractions`` after the start (modal coefficients ``c``):
        the exponentials of a step length are kept (a periodic switching repeats them)."""
        key = float(f"{h:.13g}")
        E = self._steps.get(key)
        if E is None:
            if len(self._steps) > 64:
                self._steps.clear()
            E = self._steps[key] = np.exp(self.lam[:, None] * (key * fractions)[None, :])
        w = c if offset == 0 else c * np.exp(self.lam * offset)
        out = self.V @ (E * w[:, None])
        return (out.real if not self.real else out.real) + self.xp[:, None]

    def from_coefficients(self, s: np.ndarray, t0: float, c: np.ndarray) -> np.ndarray:
        """The states at times ``s`` from the modal coefficients ``c`` at ``t0``."""
        e = np.exp(self.lam[:, None] * (np.asarray(s, dtype=float) - t0)[None, :]) * c[:, None]
        out = self.V @ e
        return (out.real if np.iscomplexobj(out) else out) + self.xp[:, None]
