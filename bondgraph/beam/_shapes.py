"""Overflow-free mode-shape machinery shared by the beam modules (internal).

A solution of ``psi'''' = lam**4 psi`` on ``xi = x/L in [0, 1]`` is written in
the bounded basis ::

    psi(xi) = a0 cos(lam xi) + a1 sin(lam xi) + a2 exp(-lam xi) + a3 exp(-lam (1 - xi))

(every basis function is bounded by 1 on ``[0, 1]``, so high modes do not
suffer the cancellation of ``cosh - cos`` differences).  Derivatives are
handled *normalised*: ``D_n = psi^(n)(xi)/lam**n``.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray


def basis(lam: float, xi: ArrayLike, n: int) -> NDArray:
    """Normalised ``n``-th derivative ``d^n/dxi^n / lam**n`` of the 4 basis functions.

    Returns an array of shape ``xi.shape + (4,)``.
    """
    xi = np.asarray(xi, dtype=float)
    arg = lam * xi + n * np.pi / 2
    return np.stack([np.cos(arg), np.sin(arg),
                     (-1.0) ** n * np.exp(-lam * xi),
                     np.exp(-lam * (1.0 - xi))], axis=-1)


def root_rows(kind: str, lam: float, *, rho: float = 0.0, eta: float = 0.0) -> list[NDArray]:
    """Two boundary-condition rows at ``xi = 0``.

    ``clamped``: psi = psi' = 0; ``pinned``: psi = psi'' = 0;
    ``hub``: psi - rho psi' = 0 and psi'' - rho psi''' + eta lam**4 psi' = 0
    (normalised: ``D0 - rho lam D1``, ``D2 - rho lam D3 + eta lam**3 D1``).
    """
    d = [basis(lam, 0.0, n) for n in range(4)]
    if kind == "clamped":
        return [d[0], d[1]]
    if kind == "pinned":
        return [d[0], d[2]]
    return [d[0] - rho * lam * d[1], d[2] - rho * lam * d[3] + eta * lam**3 * d[1]]


def tip_rows(lam: float, *, mu: float = 0.0, j: float = 0.0) -> list[NDArray]:
    """Two rows at ``xi = 1``: ``psi'' = j lam**4 psi'`` and ``psi''' = -mu lam**4 psi``."""
    d = [basis(lam, 1.0, n) for n in range(4)]
    return [d[2] - j * lam**3 * d[1], d[3] + mu * lam * d[0]]


def null_vector(rows: list[NDArray]) -> NDArray:
    """Unit coefficient vector spanning the (numerical) null space of the 4x4 BC matrix."""
    a = np.array(rows, dtype=float)
    a /= np.linalg.norm(a, axis=1, keepdims=True)
    _, _, vt = np.linalg.svd(a)
    return vt[-1]


def evaluate(coef: ArrayLike, lam: float, xi: ArrayLike, n: int = 0) -> NDArray:
    """``sum_k coef_k * basis_k^(n)(xi)`` with the true (un-normalised) xi-derivative."""
    return basis(lam, xi, n) @ np.asarray(coef, dtype=float) * lam**n


@lru_cache(maxsize=64)
def _gauss(npts: int) -> tuple[NDArray, NDArray]:
    x, w = np.polynomial.legendre.leggauss(npts)
    return 0.5 * (x + 1.0), 0.5 * w


def integrate(func, lam: float) -> float:
    """Gauss–Legendre integral over ``xi in [0, 1]`` of a function of the mode ``lam``.

    Uses ``int(1.5 lam) + 48`` nodes: exact to round-off for products of two
    modes of eigenvalue ``<= lam`` with polynomials of low degree.
    """
    x, w = _gauss(int(1.5 * lam) + 48)
    return float(np.dot(w, func(x)))
