"""Many plants of one model: :class:`BatchStateSpace` (dense stacks) and
:class:`SparseBatchStateSpace` (one sparsity pattern, a ``(P, nnz)`` array of values).

Both come from :meth:`NumericModel.batch <bondgraph.numeric.NumericModel.batch>`;
indexing either gives a :class:`~bondgraph.numeric.NumericStateSpace`.

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("rc")
>>> g.add(bg.Se("V"), bg.One("i"), bg.R("R"), bg.C("C"))
>>> for tail, head in [("V", "i"), ("i", "R"), ("i", "C")]: _ = g.connect(tail, head)
>>> nm = bg.compile_plant(bg.derive(g, outputs={"vC": bg.effort("C")}))
>>> sp = nm.batch({"R": [1.0, 2.0], "C": 1.0}, sparse=True)
>>> sp, sp.values.shape, sp[1].A.toarray()
(SparseBatchStateSpace('rc': 2 plants, 1 states, 1 inputs, 1 outputs, 3 values per plant), (2, 3), array([[-0.5]]))
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Optional, Sequence, Union

import numpy as np

from ._linalg import freeze, frequency_response, sorted_eigenvalues
from .errors import NumericError
from .sparse import Pattern, ShiftedSolver, dense_allowed, nearest_eigenvalues, sparse_frequency_response
from .statespace import NumericStateSpace, add_derivatives

__all__ = ["BatchStateSpace", "SparseBatchStateSpace", "dense_stacks"]


@dataclass(frozen=True, eq=False)
class BatchStateSpace:
    """``P`` plants of one model: stacked ``A (P, n, n)``, ``B (P, n, m)``, ``C``, ``D``.

    Attributes
    ----------
    A, B, C, D : numpy.ndarray
        Read-only stacks.
    state_names, input_names, output_names, parameter_names : tuple of str
    parameter_values : numpy.ndarray
        Shape ``(P, k)``, one row per parameter set, columns as ``parameter_names``.
    name : str
    D_derivatives, state_shift : tuple of numpy.ndarray
        Stacks of the matrices of :class:`NumericStateSpace` of the same names
        (input derivatives); empty for ordinary plants.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("rc")
    >>> g.add(bg.Se("V"), bg.One("i"), bg.R("R"), bg.C("C"))
    >>> for tail, head in [("V", "i"), ("i", "R"), ("i", "C")]: _ = g.connect(tail, head)
    >>> model = bg.derive(g, outputs={"vC": bg.effort("C")})
    >>> plants = bg.compile_plant(model).batch({"R": [1.0, 2.0, 4.0], "C": 1.0})
    >>> plants, plants.A.shape, plants.eigenvalues().real.ravel()
    (BatchStateSpace('rc': 3 plants, 1 states, 1 inputs, 1 outputs), (3, 1, 1), array([-1.  , -0.5 , -0.25]))
    >>> plants[1].parameters["R"]
    2.0
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    parameter_names: tuple[str, ...]
    parameter_values: np.ndarray
    name: str = ""
    D_derivatives: tuple[np.ndarray, ...] = ()
    state_shift: tuple[np.ndarray, ...] = ()

    def __repr__(self) -> str:
        return (f"BatchStateSpace({self.name!r}: {len(self)} plants, {len(self.state_names)} states, "
                f"{len(self.input_names)} inputs, {len(self.output_names)} outputs)")

    def __len__(self) -> int:
        return self.A.shape[0]

    #: stacked dense arrays (see :class:`SparseBatchStateSpace` for the sparse form)
    is_sparse = False

    def __reduce__(self):
        return (_rebuild_batch, ({f.name: getattr(self, f.name) for f in dataclasses.fields(self)},))

    def __getitem__(self, i: int) -> NumericStateSpace:
        """Plant number ``i`` as a :class:`NumericStateSpace`."""
        i = range(len(self))[i]
        return NumericStateSpace(self.A[i], self.B[i], self.C[i], self.D[i], self.state_names,
                                 self.input_names, self.output_names,
                                 dict(zip(self.parameter_names, self.parameter_values[i].tolist())),
                                 self.name, tuple(M[i] for M in self.D_derivatives),
                                 tuple(M[i] for M in self.state_shift))

    def eigenvalues(self) -> np.ndarray:
        """Eigenvalues of every ``A`` at once, shape ``(P, n)``, each row sorted."""
        return sorted_eigenvalues(self.A)

    def frequency_response(self, omega: Union[float, Sequence[float], np.ndarray]) -> np.ndarray:
        """Batched ``H(jw)``, complex array of shape ``(P, len(omega), noutputs, ninputs)``."""
        from .._support.numeric_input import numeric_array

        omega = numeric_array(omega, "omega", NumericError)
        return add_derivatives(frequency_response(self.A, self.B, self.C, self.D, omega),
                               self.D_derivatives, omega)


def _rebuild_batch(fields: dict) -> BatchStateSpace:
    """A unpickled :class:`BatchStateSpace`, its arrays read-only again."""
    for key, value in fields.items():
        if isinstance(value, np.ndarray):
            fields[key] = freeze(value)
        elif key in ("D_derivatives", "state_shift"):
            fields[key] = tuple(freeze(M) for M in value)
    return BatchStateSpace(**fields)


@dataclass(frozen=True, eq=False)
class SparseBatchStateSpace:
    """``P`` sparse plants of one model: the sparsity patterns once, the values per plant.

    Attributes
    ----------
    patterns : tuple of Pattern
        The patterns of ``A, B, C, D``, then of each ``D_derivatives[k]``,
        then of each ``state_shift[k]`` (``n_derivatives`` of each).
    values : numpy.ndarray
        Read-only ``(P, nnz)``: row ``i`` holds the values of plant ``i``,
        matrix after matrix in the order of ``patterns``, each in row-major
        order.
    state_names, input_names, output_names, parameter_names : tuple of str
    parameter_values : numpy.ndarray
        ``(P, k)``, one row per parameter set.
    name : str
    n_derivatives : int
        Number of ``D_derivatives`` (and of ``state_shift``) matrices.
    """

    patterns: tuple[Pattern, ...]
    values: np.ndarray
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    parameter_names: tuple[str, ...]
    parameter_values: np.ndarray
    name: str = ""
    n_derivatives: int = 0

    #: a pattern and values, not stacked arrays
    is_sparse = True

    def __post_init__(self) -> None:
        sizes = [p.nnz for p in self.patterns]
        if len(self.patterns) != 4 + 2 * self.n_derivatives:
            raise NumericError(f"expected {4 + 2 * self.n_derivatives} patterns (A, B, C, D and "
                               f"the derivative terms); got {len(self.patterns)}")
        if self.values.ndim != 2 or self.values.shape[1] != sum(sizes):
            raise NumericError(f"values must have shape (P, {sum(sizes)}); got {self.values.shape}")
        object.__setattr__(self, "_offsets", np.concatenate([[0], np.cumsum(sizes)]))

    def __repr__(self) -> str:
        return (f"SparseBatchStateSpace({self.name!r}: {len(self)} plants, {len(self.state_names)} "
                f"states, {len(self.input_names)} inputs, {len(self.output_names)} outputs, "
                f"{self.values.shape[1]} values per plant)")

    def __len__(self) -> int:
        return self.values.shape[0]

    def __reduce__(self):
        return (_rebuild_sparse_batch, ({f.name: getattr(self, f.name)
                                         for f in dataclasses.fields(self)},))

    def _part(self, k: int, i) -> np.ndarray:
        off = self._offsets                                 # type: ignore[attr-defined]
        return self.values[i, off[k]:off[k + 1]]

    def _matrices(self, i: int, convert) -> tuple:
        mats = tuple(convert(p, self._part(k, i)) for k, p in enumerate(self.patterns))
        d = self.n_derivatives
        return mats[:4] + (mats[4:4 + d], mats[4 + d:])

    def __getitem__(self, i: int) -> NumericStateSpace:
        """Plant number ``i`` as a sparse :class:`NumericStateSpace`."""
        i = range(len(self))[i]
        A, B, C, D, Dd, S = self._matrices(i, Pattern.to_sparse)
        return NumericStateSpace(A, B, C, D, self.state_names, self.input_names,
                                 self.output_names,
                                 dict(zip(self.parameter_names, self.parameter_values[i].tolist())),
                                 self.name, Dd, S)

    def to_dense(self) -> BatchStateSpace:
        """The same plants as dense stacks (``8 P n^2`` bytes for ``A``)."""
        stacks = [p.to_dense(self._part(k, slice(None))) for k, p in enumerate(self.patterns)]
        d = self.n_derivatives
        A, B, C, D = (freeze(M) for M in stacks[:4])
        return BatchStateSpace(A, B, C, D, self.state_names,
                               self.input_names, self.output_names, self.parameter_names,
                               self.parameter_values, self.name,
                               tuple(freeze(M) for M in stacks[4:4 + d]),
                               tuple(freeze(M) for M in stacks[4 + d:]))

    def eigenvalues(self, k: Optional[int] = None, *, sigma: complex = 0.0,
                    dense: str = "warn") -> np.ndarray:
        """Eigenvalues of each ``A``: ``(P, k)`` nearest ``sigma`` (nearest first), or all
        ``(P, n)`` (sorted; dense, with ``dense=`` as
        :meth:`NumericStateSpace.eigenvalues`)."""
        if k is None:
            dense_allowed(dense, len(self.state_names), "all eigenvalues (LAPACK)", self.name)
            pattern = self.patterns[0]
            return np.array([sorted_eigenvalues(pattern.to_dense(self._part(0, i)))
                             for i in range(len(self))]).reshape(len(self), -1)
        return np.array([nearest_eigenvalues(self.patterns[0].to_sparse(self._part(0, i)), k,
                                             sigma, name=self.name)
                         for i in range(len(self))]).reshape(len(self), -1)

    def frequency_response(self, omega: Union[float, Sequence[float], np.ndarray]) -> np.ndarray:
        """``H(jw)`` of every plant, complex ``(P, len(omega), noutputs, ninputs)``: a sparse
        LU per plant and frequency, one column ordering for all."""
        from .._support.numeric_input import numeric_array

        w = np.atleast_1d(numeric_array(omega, "omega", NumericError))
        if w.ndim != 1:
            raise NumericError(f"omega must be a number or a 1-D array; got shape {w.shape}")
        solver = ShiftedSolver(self.patterns[0])
        out = np.empty((len(self), w.size, len(self.output_names), len(self.input_names)),
                       dtype=complex)
        for i in range(len(self)):
            A, B, C, D, Dd, _ = self._matrices(i, Pattern.to_sparse)
            out[i] = add_derivatives(sparse_frequency_response(solver, A.data, B, C, D, w),
                                     tuple(M.toarray() for M in Dd), w)
        return out


def _rebuild_sparse_batch(fields: dict) -> SparseBatchStateSpace:
    """A unpickled :class:`SparseBatchStateSpace`, its arrays read-only again."""
    fields["values"] = freeze(fields["values"])
    fields["parameter_values"] = freeze(fields["parameter_values"])
    return SparseBatchStateSpace(**fields)


def dense_stacks(plants, *, what: str, dense: str = "warn"):
    """``plants`` (a batch or one plant) with dense arrays, for code that needs them.

    Dense batches and plants are returned as they are; a sparse one is
    converted after ``dense=`` is asked (see
    :func:`~bondgraph.numeric.sparse.dense_allowed`: ``"warn"`` names the
    memory of the ``(P, n, n)`` stack, ``"refuse"`` raises).

    Examples
    --------
    >>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[1.0]], [[0.0]], ("x",), ("u",), ("y",))
    >>> dense_stacks(ss.to_sparse(), what="a test", dense="allow").A
    array([[-1.]])
    """
    if not getattr(plants, "is_sparse", False):
        return plants
    count = len(plants) if isinstance(plants, SparseBatchStateSpace) else 1
    dense_allowed(dense, len(plants.state_names), what, plants.name, copies=count)
    return plants.to_dense()
