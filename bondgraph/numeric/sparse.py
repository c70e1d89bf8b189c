"""Sparse numeric plants: fixed sparsity patterns and the linear algebra on them.

A plant with more than :data:`SPARSE_THRESHOLD` states holds its ``A, B, C,
D`` as ``scipy.sparse`` CSR arrays (``compile_plant(model, sparse=...)`` or
``plant(values, sparse=...)`` choose otherwise).  :func:`compile_plant
<bondgraph.numeric.compile_plant>` compiles only the nonzero entries: each
matrix is a :class:`Pattern` (where the entries are, fixed for the model)
and a vector of values (computed together for all of them), so a dense
plant is filled from the pattern and a sparse one is the pattern and the
values, with no dense ``n x n`` intermediate.

On a sparse plant:

* the frequency response factors ``(jw I - A)`` by a sparse LU
  (:func:`scipy.sparse.linalg.splu`) per frequency, with one column ordering
  (COLAMD, computed at the first frequency) reused for every other
  frequency and every plant of a batch; memory is ``O(nnz)``;
* :meth:`~bondgraph.numeric.NumericStateSpace.eigenvalues` with ``k=`` gives
  the ``k`` eigenvalues nearest a target (ARPACK in shift-invert mode,
  :func:`scipy.sparse.linalg.eigs`); all of them need the dense ``A`` and
  warn with its size (:class:`DenseConversionWarning`);
* conversions to python-control or scipy systems take ``dense="warn"``
  (convert, warn with the memory), ``"allow"`` or ``"refuse"``
  (:class:`DenseConversionError`).

Examples
--------
>>> import numpy as np
>>> p = Pattern.from_coordinates((2, 3), [0, 1, 1], [1, 0, 2])
>>> p.nnz, p.indptr.tolist(), p.indices.tolist()
(3, [0, 1, 3], [1, 0, 2])
>>> p.to_dense(np.array([5.0, 7.0, 9.0]))         # values in row-major order
array([[0., 5., 0.],
       [7., 0., 9.]])
>>> p.to_sparse(np.array([5.0, 7.0, 9.0])).toarray().tolist() == p.to_dense(np.array([5.0, 7.0, 9.0])).tolist()
True
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Optional, Sequence

import numpy as np

from .errors import DenseConversionError, DenseConversionWarning, NumericError

if TYPE_CHECKING:  # scipy.sparse is imported when a sparse plant is made, not with bondgraph
    import scipy.sparse

__all__ = ["SPARSE_THRESHOLD", "Pattern", "ShiftedSolver", "sparse_frequency_response",
           "nearest_eigenvalues", "dense_allowed", "describe_bytes", "DENSE_CHOICES"]

#: plants with more states than this are sparse unless ``sparse=False`` is asked for
SPARSE_THRESHOLD = 500

#: the choices of ``dense=`` for conversions of a sparse plant to dense arrays
DENSE_CHOICES = ("warn", "allow", "refuse")


class Pattern:
    """Where the nonzero entries of a matrix are: a CSR structure without values.

    Values of a matrix with this pattern are a vector (or a stack ``(..., nnz)``
    of vectors) in row-major order (the order of :attr:`indices`).

    Parameters
    ----------
    shape : tuple of int
    indptr, indices : array_like of int
        CSR row pointers (``rows + 1``) and column indices, sorted within each
        row, no duplicates.

    Examples
    --------
    >>> p = Pattern.from_coordinates((2, 2), [0, 1], [1, 1])
    >>> p, p.rows.tolist()
    (Pattern((2, 2), nnz=2), [0, 1])
    """

    __slots__ = ("shape", "indptr", "indices", "_rows")

    def __init__(self, shape: tuple[int, int], indptr, indices) -> None:
        self.shape = (int(shape[0]), int(shape[1]))
        self.indptr = _readonly(np.asarray(indptr, dtype=np.int32))
        self.indices = _readonly(np.asarray(indices, dtype=np.int32))
        self._rows: Optional[np.ndarray] = None

    @classmethod
    def from_coordinates(cls, shape: tuple[int, int], rows: Sequence[int],
                         cols: Sequence[int]) -> "Pattern":
        """The pattern of the entries ``(rows[k], cols[k])``, given in row-major order
        (sorted by row, then column; no duplicates)."""
        r = np.asarray(rows, dtype=np.int64)
        c = np.asarray(cols, dtype=np.int64)
        key = r * max(1, shape[1]) + c
        if key.size and np.any(np.diff(key) <= 0):
            raise ValueError("pattern entries must be sorted row-major without duplicates")
        indptr = np.zeros(shape[0] + 1, dtype=np.int64)
        np.cumsum(np.bincount(r, minlength=shape[0]), out=indptr[1:])
        return cls(shape, indptr, c)

    @property
    def nnz(self) -> int:
        """Number of stored entries."""
        return int(self.indices.size)

    @property
    def rows(self) -> np.ndarray:
        """Row index of each entry (the COO rows), computed once."""
        if self._rows is None:
            self._rows = _readonly(np.repeat(np.arange(self.shape[0], dtype=np.int32),
                                             np.diff(self.indptr)))
        return self._rows

    def to_dense(self, values: np.ndarray) -> np.ndarray:
        """A dense ``(..., rows, cols)`` array with ``values`` (``(..., nnz)``) in place."""
        values = np.asarray(values, dtype=float)
        out = np.zeros(values.shape[:-1] + self.shape)
        out[..., self.rows, self.indices] = values
        return out

    def to_sparse(self, values: np.ndarray) -> "scipy.sparse.csr_array":
        """A CSR array with this pattern and ``values`` (``(nnz,)``), sharing the structure."""
        import scipy.sparse

        return scipy.sparse.csr_array((np.asarray(values, dtype=float), self.indices, self.indptr),
                                      shape=self.shape, copy=False)

    def __repr__(self) -> str:
        return f"Pattern({self.shape}, nnz={self.nnz})"

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, Pattern) and self.shape == other.shape
                and np.array_equal(self.indptr, other.indptr)
                and np.array_equal(self.indices, other.indices))

    __hash__ = None  # type: ignore[assignment]

    def __reduce__(self):
        return (Pattern, (self.shape, self.indptr, self.indices))


def _readonly(arr: np.ndarray) -> np.ndarray:
    arr.setflags(write=False)
    return arr


def describe_bytes(nbytes: float) -> str:
    """``"1.9 GB"``: a byte count for a message.

    Examples
    --------
    >>> describe_bytes(8 * 20000 ** 2), describe_bytes(1536)
    ('3.2 GB', '1.5 kB')
    """
    for unit, size in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if nbytes >= size:
            return f"{nbytes / size:.1f} {unit}"
    return f"{int(nbytes)} B"


def dense_allowed(dense: str, n: int, what: str, name: str, *, copies: int = 2) -> None:
    """Check ``dense=`` before a sparse plant of ``n`` states is made dense for ``what``.

    ``"warn"`` warns (:class:`DenseConversionWarning`) with the memory the
    dense ``A`` takes (``copies`` arrays of ``n x n`` doubles), ``"allow"``
    says nothing, ``"refuse"`` raises :class:`DenseConversionError`.
    """
    if dense not in DENSE_CHOICES:
        raise NumericError(f"dense= must be one of {', '.join(map(repr, DENSE_CHOICES))}; "
                                   f"got {dense!r}")
    size = describe_bytes(copies * 8.0 * n * n)
    if dense == "refuse":
        raise DenseConversionError(
            f"plant {name!r} is sparse ({n} states): {what} needs dense n x n arrays "
            f"(about {size}); refused because dense='refuse'.  Pass dense='warn' or "
            "dense='allow' to convert, or stay sparse (frequency_response, "
            "eigenvalues(k=..., sigma=...))")
    if dense == "warn":
        warnings.warn(
            f"plant {name!r} is sparse ({n} states): {what} converts it to dense n x n arrays, "
            f"about {size} of memory (dense='allow' silences this, dense='refuse' refuses)",
            DenseConversionWarning, stacklevel=3)


#: factors with at most this many entries a column (``L`` and ``U``) are refactored without
#: SuperLU's relaxed supernodes: 2x faster on a 40,000-state chain (4.5 a column), 30 %
#: slower on a 22,500-node 2-D grid (78 a column), faster still at 50 a column
THIN_FACTORS = 16


class ShiftedSolver:
    """Solves ``(s I - A) X = R`` for many ``s`` and many ``A`` of one :class:`Pattern`.

    The CSC structure of ``s I - A`` (``A``'s pattern plus the diagonal) is
    built once; the first factorization orders the columns (COLAMD) and every
    later one reuses that ordering on the pre-permuted structure
    (``permc_spec="NATURAL"``), so only the numeric LU is repeated; when the
    first factors are thin (at most :data:`THIN_FACTORS` entries a column)
    the later ones are taken without relaxed supernodes (``relax=1,
    panel_size=1``).

    Examples
    --------
    >>> p = Pattern.from_coordinates((2, 2), [0, 1, 1], [1, 0, 1])
    >>> solver = ShiftedSolver(p)
    >>> a = np.array([1.0, -4.0, -0.4])                 # A = [[0, 1], [-4, -0.4]]
    >>> x = solver.solve(a, 2j, np.array([[0.0], [1.0]]))
    >>> bool(np.allclose((2j * np.eye(2) - p.to_dense(a)) @ x, [[0.0], [1.0]]))
    True
    """

    def __init__(self, pattern: Pattern) -> None:
        n = pattern.shape[0]
        self.n = n
        diag = np.arange(n, dtype=np.int64)
        rows = np.concatenate([pattern.rows.astype(np.int64), diag])
        cols = np.concatenate([pattern.indices.astype(np.int64), diag])
        uniq, inv = np.unique(cols * n + rows, return_inverse=True)     # column-major
        self._indices = (uniq % n).astype(np.int32)
        self._indptr = np.zeros(n + 1, dtype=np.int32)
        np.cumsum(np.bincount(uniq // n, minlength=n), out=self._indptr[1:])
        self._a_pos, self._d_pos = inv[:pattern.nnz], inv[pattern.nnz:]
        self._size = uniq.size
        self._perm: Optional[np.ndarray] = None           # perm_c of the first factorization
        self._take: Optional[np.ndarray] = None           # data order of the permuted structure
        self._pstruct: Optional[tuple[np.ndarray, np.ndarray]] = None
        self._tuning: dict[str, int] = {}                 # SuperLU options after the first LU

    def _data(self, a_values: np.ndarray, s: complex) -> np.ndarray:
        data = np.zeros(self._size, dtype=complex)
        data[self._a_pos] = -a_values
        data[self._d_pos] += s
        return data

    def factor(self, a_values: np.ndarray, s: complex):
        """``(LU, perm)``: the SuperLU factors of ``(s I - A)`` with columns reordered by ``perm``."""
        import scipy.sparse
        import scipy.sparse.linalg

        data = self._data(a_values, s)
        if self._perm is None:
            M = scipy.sparse.csc_array((data, self._indices, self._indptr), shape=(self.n, self.n))
            lu = scipy.sparse.linalg.splu(M, permc_spec="COLAMD")
            self._remember(lu.perm_c)
            # factors this thin (a chain: 4.5 entries a column) have no supernodes worth
            # gathering: SuperLU without relaxed supernodes and panels factors them 2x faster
            if lu.L.nnz + lu.U.nnz <= THIN_FACTORS * max(self.n, 1):
                self._tuning = {"relax": 1, "panel_size": 1}
            return lu, None
        indices, indptr = self._pstruct                   # type: ignore[misc]
        M = scipy.sparse.csc_array((data[self._take], indices, indptr), shape=(self.n, self.n))
        return scipy.sparse.linalg.splu(M, permc_spec="NATURAL", **self._tuning), self._perm

    def _remember(self, perm_c: np.ndarray) -> None:
        # column k of A Pc is column inv[k] of A (SuperLU: Pr A Pc = L U, Pc[i, perm_c[i]] = 1)
        inv = np.argsort(perm_c)
        starts, ends = self._indptr[inv], self._indptr[inv + 1]
        counts = ends - starts
        indptr = np.zeros(self.n + 1, dtype=np.int32)
        np.cumsum(counts, out=indptr[1:])
        take = np.repeat(starts - indptr[:-1], counts) + np.arange(indptr[-1])
        self._take = take
        self._pstruct = (self._indices[take], indptr)
        self._perm = np.asarray(perm_c)

    def solve(self, a_values: np.ndarray, s: complex, rhs: np.ndarray, *,
              trans: bool = False) -> np.ndarray:
        """``X`` with ``(s I - A) X = rhs`` (or ``(s I - A)^T X = rhs`` with ``trans``);
        ``nan`` where ``s I - A`` is singular."""
        try:
            lu, perm = self.factor(a_values, s)
        except RuntimeError:                               # "Factor is exactly singular"
            return np.full(rhs.shape, np.nan, dtype=complex)
        rhs = np.asarray(rhs, dtype=complex)
        if perm is None:
            return lu.solve(rhs, trans="T" if trans else "N")
        if not trans:                                      # (A Pc) y = r, x = Pc y
            return lu.solve(rhs)[perm]
        inv = np.argsort(perm)                             # (A Pc)^T y = Pc^T r, x = y
        return lu.solve(rhs[inv], trans="T")


def sparse_frequency_response(solver: ShiftedSolver, a_values: np.ndarray, B, C, D,
                              omega: np.ndarray) -> np.ndarray:
    """``C (jw I - A)^-1 B + D`` for a sparse plant; complex ``(F, p, m)``.

    ``B``, ``C``, ``D`` are sparse; only the nonzero columns of ``B`` (or
    rows of ``C``, whichever are fewer) are solved for, one sparse LU per
    frequency, memory ``O(nnz)``.
    """
    F, (p, m) = omega.size, D.shape
    out = np.empty((F, p, m), dtype=complex)
    out[...] = D.toarray()
    cols = np.flatnonzero(np.diff(B.tocsc().indptr))              # inputs that reach a state
    rows = np.flatnonzero(np.diff(C.tocsr().indptr))              # outputs that see a state
    if solver.n == 0 or cols.size == 0 or rows.size == 0:
        return out
    # the products with B and C stay sparse (scipy's own loops, O(nnz)): a dense product went
    # to BLAS, whose idle threads then spin beside each LU and doubled the CPU time of a
    # 40,000-state response
    Bs, Cs = B.tocsc()[:, cols], C.tocsr()[rows, :]
    transpose = rows.size < cols.size
    rhs = (Cs.T if transpose else Bs).toarray()
    where = np.ix_(rows, cols)
    for f, w in enumerate(omega):
        if transpose:                       # H^T = B^T (jw I - A)^-T C^T
            Y = solver.solve(a_values, 1j * w, rhs, trans=True)           # (n, r)
            out[f][where] += (Bs.T @ Y).T
        else:
            X = solver.solve(a_values, 1j * w, rhs)                       # (n, c)
            out[f][where] += Cs @ X
    return out


def nearest_eigenvalues(A, k: int, sigma: complex, *, name: str = "") -> np.ndarray:
    """The ``k`` eigenvalues of ``A`` nearest ``sigma``, nearest first.

    ARPACK in shift-invert mode (:func:`scipy.sparse.linalg.eigs`) for a
    sparse or dense ``A`` when ``k < n - 1``; otherwise all eigenvalues of the
    dense ``A``, of which the ``k`` nearest.
    """
    import scipy.sparse
    import scipy.sparse.linalg

    n = A.shape[0]
    if not isinstance(k, (int, np.integer)) or isinstance(k, bool) or not 1 <= k <= n:
        raise NumericError(
            f"plant {name!r}: k must be an integer from 1 to the number of states ({n}); got {k!r}")
    if k < n - 1:
        M = A.astype(complex) if np.iscomplexobj(sigma) and complex(sigma).imag != 0 else A
        ev = scipy.sparse.linalg.eigs(M, k=k, sigma=sigma, which="LM", return_eigenvectors=False)
    else:
        dense = A.toarray() if scipy.sparse.issparse(A) else np.asarray(A)
        ev = np.linalg.eigvals(dense)
    ev = np.asarray(ev, dtype=complex)
    order = np.lexsort((ev.imag, ev.real, np.round(np.abs(ev - sigma), 12)))
    return ev[order][:k]
