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

__all__ = ["frequency_response", "channel_response", "ChannelResponse", "sorted_eigenvalues",
           "freeze"]

#: eigenvector condition number above which a plant's response is solved, not taken modally
MODAL_COND = 1e6

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
    for sl, fs in _blocks(count, F, n):
        M = _shifted(A2[sl], jw[fs])                                # (c, f, n, n)
        rhs = np.broadcast_to(B2[sl, None], M.shape[:-1] + (m,))
        out[sl, fs] += C2[sl, None] @ _solve(M, rhs)                # (c, f, p, m)
    return out.reshape(lead + (F, p, m))


def channel_response(A: np.ndarray, B: np.ndarray, C: np.ndarray, D: np.ndarray,
                     D_derivatives, omega: np.ndarray, output: int, input: int) -> np.ndarray:
    """One channel's ``H(jw)`` for a stack of plants, each at its own frequencies.

    Parameters
    ----------
    A, B, C, D : numpy.ndarray
        Stacks ``(P, n, n)``, ``(P, n, m)``, ``(P, p, n)``, ``(P, p, m)``.
    D_derivatives : sequence of numpy.ndarray
        Stacks ``(P, p, m)`` of the coefficients of ``s, s^2, ...`` (may be empty).
    omega : numpy.ndarray
        ``(P, F)``: the frequencies (rad/s) of each plant, or ``(F,)`` for all.
    output, input : int
        The channel.

    Returns
    -------
    numpy.ndarray
        Complex ``(P, F)``; ``nan`` where ``jw I - A`` is singular.

    Examples
    --------
    >>> A = np.array([[[-1.0]], [[-2.0]]]); B = np.ones((2, 1, 1)); C = np.ones((2, 1, 1))
    >>> channel_response(A, B, C, np.zeros((2, 1, 1)), (), np.array([[0.0], [2.0]]), 0, 0)
    array([[1.  +0.j  ],
           [0.25-0.25j]])
    """
    P, n = A.shape[0], A.shape[-1]
    w = np.asarray(omega, dtype=float)
    w = np.broadcast_to(w, (P,) + w.shape[-1:]) if w.ndim == 1 else w
    F = w.shape[1]
    jw = 1j * w
    out = np.empty((P, F), dtype=complex)
    out[...] = D[:, output, input][:, None]
    for k, M in enumerate(D_derivatives, start=1):
        out += M[:, output, input][:, None] * jw ** k
    if n == 0 or F == 0 or P == 0:
        return out
    b = B[:, :, input].astype(complex)                                # (P, n)
    c = C[:, output, :]                                               # (P, n)
    for sl, fs in _blocks(P, F, n):
        M = _shifted(A[sl], jw[sl, fs])                               # (c, f, n, n)
        rhs = np.broadcast_to(b[sl, None, :, None], M.shape[:-1] + (1,))
        X = _solve(M, rhs)[..., 0]                                    # (c, f, n)
        out[sl, fs] += np.einsum("pfn,pn->pf", X, c[sl])
    return out


class ChannelResponse:
    """One channel's ``H(jw)`` of a stack of plants, evaluated many times (searches, grids).

    The plants are diagonalised once, ``H(s) = d + sum_k r_k / (s - p_k)``
    (plus the input-derivative terms), so each frequency costs ``O(n)``
    instead of a solve; a plant whose eigenvectors are ill-conditioned
    (condition number above :data:`MODAL_COND`, a defective ``A``) is
    solved with :func:`channel_response` instead.

    Examples
    --------
    >>> A = np.array([[[0.0, 1.0], [-4.0, -0.4]]]); B = np.array([[[0.0], [1.0]]])
    >>> C = np.array([[[1.0, 0.0]]]); D = np.zeros((1, 1, 1))
    >>> H = ChannelResponse(A, B, C, D, (), 0, 0)
    >>> np.allclose(H(np.array([[0.0, 2.0]])), channel_response(A, B, C, D, (), np.array([[0.0, 2.0]]), 0, 0))
    True
    """

    def __init__(self, A: np.ndarray, B: np.ndarray, C: np.ndarray, D: np.ndarray,
                 D_derivatives, output: int, input: int) -> None:
        self._mats = (A, B, C, D, tuple(D_derivatives))
        self._channel = (output, input)
        P, n = A.shape[0], A.shape[-1]
        self._d = D[:, output, input]
        self._dd = [M[:, output, input] for M in D_derivatives]
        if n == 0 or P == 0:
            self._poles = np.zeros((P, 0), dtype=complex)
            self._res = np.zeros((P, 0), dtype=complex)
            self._solved = np.zeros(P, dtype=bool)
            return
        with np.errstate(all="ignore"):
            lam, V = np.linalg.eig(A)
            cond = np.linalg.cond(V)
        solved = ~(np.isfinite(cond) & (cond < MODAL_COND))
        V = np.where(solved[:, None, None], np.eye(n), V)
        right = np.linalg.solve(V, B[:, :, input].astype(complex)[..., None])[..., 0]   # V^-1 b
        left = np.einsum("pn,pnk->pk", C[:, output, :], V)                              # c V
        self._poles, self._res, self._solved = lam, left * right, solved

    def __call__(self, omega: np.ndarray) -> np.ndarray:
        """``H(jw)`` for ``omega`` of shape ``(P, F)`` (or ``(F,)`` for all): complex ``(P, F)``."""
        w = np.asarray(omega, dtype=float)
        P = self._d.shape[0]
        w = np.broadcast_to(w, (P,) + w.shape[-1:]) if w.ndim == 1 else w
        jw = 1j * w
        with np.errstate(all="ignore"):
            out = self._d[:, None] + np.einsum("pk,pfk->pf", self._res,
                                               1.0 / (jw[:, :, None] - self._poles[:, None, :]))
            for k, M in enumerate(self._dd, start=1):
                out = out + M[:, None] * jw ** k
        out[~np.isfinite(out)] = np.nan + 0j
        if self._solved.any():
            idx = np.flatnonzero(self._solved)
            A, B, C, D, Dd = self._mats
            out[idx] = channel_response(A[idx], B[idx], C[idx], D[idx], tuple(M[idx] for M in Dd),
                                        w[idx], *self._channel)
        return out


def _blocks(count: int, F: int, n: int):
    """``(plants, frequencies)`` slices whose ``(jw I - A)`` stack holds at most about
    :data:`_CHUNK_ENTRIES` complex entries (a 999-state plant: a few frequencies at a time)."""
    per_plant = max(1, F * n * n)
    if per_plant <= _CHUNK_ENTRIES:
        step = _CHUNK_ENTRIES // per_plant
        for start in range(0, count, step):
            yield slice(start, min(count, start + step)), slice(0, F)
        return
    fstep = max(1, _CHUNK_ENTRIES // max(1, n * n))
    for i in range(count):
        for f0 in range(0, F, fstep):
            yield slice(i, i + 1), slice(f0, min(F, f0 + fstep))


def _shifted(A: np.ndarray, jw: np.ndarray) -> np.ndarray:
    """``jw I - A`` for plants ``A (c, n, n)`` and frequencies ``jw (f,)`` or ``(c, f)``:
    one complex ``(c, f, n, n)`` array, the diagonal added in place (no identity stack)."""
    c, n = A.shape[0], A.shape[-1]
    f = jw.shape[-1]
    M = np.empty((c, f, n, n), dtype=complex)
    np.negative(A[:, None], out=M)
    M.reshape(c, f, n * n)[:, :, ::n + 1] += np.broadcast_to(jw, (c, f))[:, :, None]
    return M


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
