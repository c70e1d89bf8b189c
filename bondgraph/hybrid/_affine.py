"""The exact flow of a mode whose equations are ``x' = A x + b`` with constant ``A``, ``b`` (private).

Most modes of switched circuits are linear and time-invariant between events
(a buck converter's three).  Their solution from ``x0`` is, with the
eigendecomposition ``A = V diag(lam) V^-1``::

    x(s) = x_p + V diag(exp(lam s)) V^-1 (x0 - x_p),   A x_p = -b,

exact at every instant and vectorized over many instants, so that the
segment integration (:mod:`bondgraph.hybrid._segment`) needs no solver
there: it samples the guards on the exact solution in steps no longer than
a fifth of the fastest time constant and locates their falls by brentq on it.
A singular ``A`` is fine (a capacitor cut off keeps its charge); a
defective or badly conditioned augmented matrix (a mass under a constant
force: ``x = x0 + v t + a t^2/2``) has no :class:`AffineFlow` and the mode is
integrated numerically.

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

    def __init__(self, lam: np.ndarray, V: np.ndarray, Vinv: np.ndarray, n: int) -> None:
        self.lam, self.V, self.Vinv, self.n = lam, V, Vinv, n
        rate = float(np.max(np.abs(lam))) if lam.size else 0.0
        #: longest step between guard samples: a fifth of the fastest time constant (an
        #: oscillation sampled every 0.04 rad)
        self.step = 0.2 / rate if rate > 0 else np.inf
        self._steps: dict = {}

    @classmethod
    def of(cls, A: np.ndarray, b: np.ndarray) -> Optional["AffineFlow"]:
        """The flow of ``x' = A x + b``, or None when the augmented matrix
        ``[[A, b], [0, 0]]`` is defective or badly conditioned (then a solver
        integrates the mode)."""
        n = A.shape[0]
        if n == 0 or not np.all(np.isfinite(A)) or not np.all(np.isfinite(b)):
            return None
        M = np.zeros((n + 1, n + 1))
        M[:n, :n], M[:n, n] = A, b
        try:
            lam, V = np.linalg.eig(M)
            if np.linalg.cond(V) > 1e6:
                return None
            Vinv = np.linalg.inv(V)
        except np.linalg.LinAlgError:
            return None
        return cls(lam, V, Vinv, n)

    def at(self, s: np.ndarray, t0: float, x0: np.ndarray) -> np.ndarray:
        """The states at times ``s`` (an array) from ``x0`` at ``t0``: shape ``(n, len(s))``."""
        return self.from_coefficients(s, t0, self.coefficients(x0))

    def coefficients(self, x0: np.ndarray) -> np.ndarray:
        """The modal coefficients ``V^-1 [x0; 1]`` of a start ``x0``."""
        return self.Vinv @ np.append(np.asarray(x0, dtype=float), 1.0)

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
        return (self.V[: self.n] @ (E * w[:, None])).real

    def from_coefficients(self, s: np.ndarray, t0: float, c: np.ndarray) -> np.ndarray:
        """The states at times ``s`` from the modal coefficients ``c`` at ``t0``."""
        e = np.exp(self.lam[:, None] * (np.asarray(s, dtype=float) - t0)[None, :]) * c[:, None]
        return (self.V[: self.n] @ e).real
