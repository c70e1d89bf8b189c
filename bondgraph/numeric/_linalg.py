"""Stacked linear algebra for plants and batches of plants (private).

Examples
--------
>>> import numpy as np
>>> A = np.array([[-1.0]]); B = np.array([[1.0]]); C = np.array([[1.0]]); D = np.zeros((1, 1))
>>> frequency_response(A, B, C, D, [0.0, 1.0])[:, 0, 0]
array([1. +0.j , 0.5-0.5j])
"""

from __future__ import annotations

import numpy as np

__all__ = ["frequency_response", "sorted_eigenvalues", "freeze"]

#: complex entries per chunk of (jw I - A) matrices solved at once (~64 MB)
_CHUNK_ENTRIES = 1 << 22


def freeze(arr: np.ndarray) -> np.ndarray:
    """``arr`` made read-only (in place) and returned."""
    arr.setflags(write=False)
    return arr


def sorted_eigenvalues(A: np.ndarray) -> np.ndarray:
    """Eigenvalues of ``A`` (or of each matrix of a stack), sorted by real then imaginary part."""
    if A.shape[-1] == 0:
        return np.zeros(A.shape[:-1], dtype=complex)
    ev = np.linalg.eigvals(A).astype(complex, copy=False)
    return np.sort_complex(ev) if ev.ndim == 1 else np.sort(ev, axis=-1)


def frequency_response(A: np.ndarray, B: np.ndarray, C: np.ndarray, D: np.ndarray,
                       omega) -> np.ndarray:
    """``C (jw I - A)^-1 B + D`` for each ``w`` of ``omega`` (and each plant of a stack).

    ``A`` has shape ``(..., n, n)``; the result has shape ``(..., F, p, m)``
    with ``F = len(omega)``.  Frequencies at which ``jw I - A`` is singular
    (``jw`` an eigenvalue) give ``nan``.
    """
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    if w.ndim != 1:
        raise ValueError(f"omega must be a number or a 1-D array; got shape {w.shape}")
    lead = A.shape[:-2]
    n, m, p = A.shape[-1], B.shape[-1], C.shape[-2]
    F = w.size
    count = int(np.prod(lead, dtype=int))
    A2 = A.reshape((count, n, n))
    B2, C2, D2 = B.reshape((count, n, m)), C.reshape((count, p, n)), D.reshape((count, p, m))
    out = np.empty((count, F, p, m), dtype=complex)
    out[...] = D2[:, None]
    if n == 0 or F == 0 or count == 0:
        return out.reshape(lead + (F, p, m))
    jw = 1j * w
    eye = np.eye(n)
    chunk = max(1, _CHUNK_ENTRIES // max(1, F * n * n))
    for start in range(0, count, chunk):
        sl = slice(start, min(count, start + chunk))
        M = jw[None, :, None, None] * eye - A2[sl, None]          # (c, F, n, n)
        rhs = np.broadcast_to(B2[sl, None].astype(complex), M.shape[:-1] + (m,))
        X = _solve(M, rhs)                                        # (c, F, n, m)
        out[sl] += C2[sl, None] @ X
    return out.reshape(lead + (F, p, m))


def _solve(M: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    try:
        return np.linalg.solve(M, rhs)
    except np.linalg.LinAlgError:
        flatM = M.reshape(-1, *M.shape[-2:])
        flatR = rhs.reshape(-1, *rhs.shape[-2:])
        X = np.empty(flatR.shape, dtype=complex)
        for i in range(flatM.shape[0]):
            try:
                X[i] = np.linalg.solve(flatM[i], flatR[i])
            except np.linalg.LinAlgError:
                X[i] = np.nan
        return X.reshape(rhs.shape)
