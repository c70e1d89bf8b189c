"""One numeric plant: :class:`NumericStateSpace` (dense arrays, or sparse above a size).

See :mod:`bondgraph.numeric.plant` for how plants are made and
:mod:`bondgraph.numeric.sparse` for sparse plants.

Examples
--------
>>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[1.0]], [[0.0]], ("x",), ("u",), ("y",))
>>> ss.is_sparse, ss.to_sparse().is_sparse, complex(ss.to_sparse().frequency_response(1.0)[0, 0, 0])
(False, True, (0.5-0.5j))
"""

from __future__ import annotations

import dataclasses

from collections import Counter
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping, Optional, Sequence, Union

import numpy as np

from .._support.labels import control_labels
from ..parameters import real_value
from ..linear.statespace import SignalCounts, check_matrix_shape, expected_shape
from ._linalg import freeze, frequency_response, sorted_eigenvalues
from .errors import ImproperPlantError, NumericError
from .sparse import Pattern, ShiftedSolver, dense_allowed, nearest_eigenvalues, sparse_frequency_response

if TYPE_CHECKING:  # imported lazily at run time
    import control
    import scipy.signal
    import scipy.sparse

__all__ = ["NumericStateSpace", "issparse", "add_derivatives"]


def issparse(value: Any) -> bool:
    """True for a ``scipy.sparse`` array or matrix (without importing scipy.sparse)."""
    return type(value).__module__.startswith("scipy.sparse")


def _dense(value: Any, label: str) -> np.ndarray:
    if issparse(value):
        value = value.toarray()
    if isinstance(value, np.ndarray) and value.dtype == np.float64 and not value.flags.writeable:
        arr = value                           # already read-only float64 (compile_plant's): no copy
    else:
        from .._support.numeric_input import numeric_array

        arr = np.array(numeric_array(value, f"state-space matrix {label}", NumericError), dtype=float)
    if arr.ndim != 2:
        raise NumericError(f"state-space matrix {label} must be 2-D; got shape {arr.shape}")
    return freeze(arr)


def _sparse(value: Any, label: str) -> "scipy.sparse.csr_array":
    import scipy.sparse

    if not issparse(value):
        from .._support.numeric_input import numeric_array

        value = numeric_array(value, f"state-space matrix {label}", NumericError)
        if value.ndim != 2:
            raise NumericError(f"state-space matrix {label} must be 2-D; got shape {value.shape}")
    elif value.ndim != 2:
        raise NumericError(f"state-space matrix {label} must be 2-D; got shape {value.shape}")
    M = scipy.sparse.csr_array(value, dtype=float)
    M.sum_duplicates()
    for arr in (M.data, M.indices, M.indptr):
        arr.setflags(write=False)
    return M


def _nonzero(M: Any) -> bool:
    return bool(M.count_nonzero()) if issparse(M) else bool(np.any(M != 0.0))


def _array(M: Any) -> np.ndarray:
    return M.toarray() if issparse(M) else M


@dataclass(frozen=True, eq=False)
class NumericStateSpace(SignalCounts):
    """``x' = A x + B u``, ``y = C x + D u`` with numbers and names.

    Parameters
    ----------
    A, B, C, D : array_like or scipy.sparse array
        Stored as read-only float64 arrays, or, when ``A`` is a
        ``scipy.sparse`` array or matrix, all four (and ``D_derivatives``,
        ``state_shift``) as CSR arrays (:attr:`is_sparse`).
    state_names, input_names, output_names : sequence of str
    parameters : mapping of str to float, optional
        The parameter values the matrices were evaluated at.
    name : str, optional
        The model's name.
    D_derivatives : sequence of array_like, optional
        Feedthrough of input derivatives: ``y = C x + D u + D_derivatives[0] u'
        + D_derivatives[1] u'' + ...``, so ``H(s) = C (sI - A)^-1 B + D +
        D_derivatives[0] s + ...``.  Empty (the default) for an ordinary plant.
    state_shift : sequence of array_like, optional
        ``(S_0, S_1, ...)``, each ``(n, m)``: the plant's states are
        ``x - S_0 u - S_1 u' - ...`` where ``x`` are the model's states named
        in ``state_names`` (see :mod:`bondgraph.numeric.plant`).  Empty when
        the states are the model's own.
    units : mapping of str to str, optional
        Signal name (a state, input or output) -> its unit, as text
        (``'newton'``, ``'meter/second'``); given by a model that declares
        units (:class:`bondgraph.modelfile.ModelDefinition` with
        unit-carrying parameters, :func:`bondgraph.library.units.model_units`).
        Empty (the default) when the model declares none.  Kept by
        :meth:`to_control` (as its ``units`` attribute) and written by the
        ``.mat`` and JSON exports.
    operating_point : OperatingPoint, optional
        The point ``x0, u0, y0`` the plant was taken about (its matrices act on
        ``x - x0``, ``u - u0`` and give ``y - y0``): set for a linearization
        and for a model with constant sources (see
        :class:`bondgraph.linear.OperatingPoint`); written by every export.

    Raises
    ------
    NumericError
        If a matrix shape does not match the numbers of names, or a unit
        names no signal of the plant or is not a text.

    Examples
    --------
    >>> ss = NumericStateSpace([[0.0, 1.0], [-4.0, -0.4]], [[0.0], [1.0]], [[1.0, 0.0]], [[0.0]],
    ...                        ("x", "v"), ("F",), ("x",), name="osc")
    >>> ss.eigenvalues()
    array([-0.2-1.98997487j, -0.2+1.98997487j])
    >>> complex(ss.frequency_response([0.0])[0, 0, 0])       # DC gain 1/4
    (0.25+0j)
    >>> ss.A[0, 0] = 1.0
    Traceback (most recent call last):
    ...
    ValueError: assignment destination is read-only
    """

    A: Any
    B: Any
    C: Any
    D: Any
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    parameters: Mapping[str, float] = field(default_factory=dict)
    name: str = ""
    D_derivatives: tuple[Any, ...] = ()
    state_shift: tuple[Any, ...] = ()
    units: Mapping[str, str] = field(default_factory=dict)
    operating_point: Any = None

    def __post_init__(self) -> None:
        names = tuple(tuple(str(s) for s in getattr(self, f)) for f in
                      ("state_names", "input_names", "output_names"))
        n, m, p = (len(x) for x in names)
        convert = _sparse if issparse(self.A) else _dense

        def checked(raw, label, shape_of):
            if not issparse(raw) and np.size(raw) == 0:
                raw = np.reshape(np.asarray(raw, dtype=float), expected_shape(shape_of, n, m, p))
            arr = convert(raw, label)
            check_matrix_shape(shape_of, arr.shape, n, m, p, NumericError)
            return arr
        for label in "ABCD":
            object.__setattr__(self, label, checked(getattr(self, label), label, label))
        object.__setattr__(self, "D_derivatives", tuple(
            checked(M, f"D_derivatives[{k}]", "D") for k, M in enumerate(self.D_derivatives)))
        object.__setattr__(self, "state_shift", tuple(
            checked(M, f"state_shift[{k}]", "B") for k, M in enumerate(self.state_shift)))
        for f, value in zip(("state_names", "input_names", "output_names"), names):
            twice = sorted(v for v, k in Counter(value).items() if k > 1)
            if twice:
                raise NumericError(f"{f}: {', '.join(map(repr, twice))} named more than once; "
                                   "signal names must be distinct")
            object.__setattr__(self, f, value)
        object.__setattr__(self, "parameters",
                           MappingProxyType({str(k): real_value(v, str(k))
                                             for k, v in dict(self.parameters).items()}))
        object.__setattr__(self, "units", MappingProxyType(_checked_units(self.units, names)))

    def __repr__(self) -> str:
        kind = f", sparse, {self.A.nnz} nonzeros in A" if self.is_sparse else ""
        return (f"NumericStateSpace({self.name!r}: {self.nstates} states, {self.ninputs} inputs, "
                f"{self.noutputs} outputs{kind})")

    def __reduce__(self):
        # rebuilt through __init__: read-only copies of the same float64 arrays (bit for bit),
        # the parameter values as a read-only mapping again
        return (NumericStateSpace, (self.A, self.B, self.C, self.D, self.state_names,
                                    self.input_names, self.output_names, dict(self.parameters),
                                    self.name, self.D_derivatives, self.state_shift,
                                    dict(self.units), self.operating_point))

    @property
    def is_sparse(self) -> bool:
        """True when the matrices are ``scipy.sparse`` CSR arrays."""
        return issparse(self.A)

    def to_dense(self) -> "NumericStateSpace":
        """This plant with dense arrays (itself if already dense); takes ``8 n^2`` bytes for ``A``."""
        return self if not self.is_sparse else self._with(_array)

    def to_sparse(self) -> "NumericStateSpace":
        """This plant with ``scipy.sparse`` CSR arrays (itself if already sparse).

        Examples
        --------
        >>> ss = NumericStateSpace([[-1.0, 0.0], [1.0, -2.0]], [[1.0], [0.0]], [[0.0, 1.0]],
        ...                        [[0.0]], ("x1", "x2"), ("u",), ("y",))
        >>> sp = ss.to_sparse()
        >>> sp, sp.A.nnz
        (NumericStateSpace('': 2 states, 1 inputs, 1 outputs, sparse, 3 nonzeros in A), 3)
        """
        if self.is_sparse:
            return self
        import scipy.sparse

        return self._with(scipy.sparse.csr_array)

    def _with(self, conv) -> "NumericStateSpace":
        return NumericStateSpace(conv(self.A), conv(self.B), conv(self.C), conv(self.D),
                                 self.state_names, self.input_names, self.output_names,
                                 dict(self.parameters), self.name,
                                 tuple(conv(M) for M in self.D_derivatives),
                                 tuple(conv(M) for M in self.state_shift), dict(self.units),
                                 self.operating_point)

    def with_operating_point(self, point: Any) -> "NumericStateSpace":
        """This plant with ``operating_point`` set to ``point`` (an
        :class:`~bondgraph.linear.OperatingPoint` or None); its units are the plant's."""
        if point is not None and self.units:
            point = dataclasses.replace(point, units={**self.units, **point.units})
        return NumericStateSpace(self.A, self.B, self.C, self.D, self.state_names,
                                 self.input_names, self.output_names, dict(self.parameters),
                                 self.name, self.D_derivatives, self.state_shift,
                                 dict(self.units), point)

    def eigenvalues(self, k: Optional[int] = None, *, sigma: complex = 0.0,
                    dense: str = "warn") -> np.ndarray:
        """Eigenvalues of ``A`` (the poles): all of them, or the ``k`` nearest ``sigma``.

        Parameters
        ----------
        k : int, optional
            When given, only the ``k`` eigenvalues nearest ``sigma``, nearest
            first, by ARPACK in shift-invert mode (:func:`scipy.sparse.linalg.eigs`;
            all eigenvalues of the dense ``A`` when ``k >= n - 1``).  When None,
            all eigenvalues sorted by real then imaginary part.
        sigma : complex, optional
            The target (default 0: the slowest poles).  Must not be an eigenvalue.
        dense : {'warn', 'allow', 'refuse'}, optional
            For all eigenvalues of a sparse plant, which need the dense ``A``:
            convert with a :class:`~bondgraph.numeric.errors.DenseConversionWarning`
            naming the memory, silently, or raise
            :class:`~bondgraph.numeric.errors.DenseConversionError`.

        Examples
        --------
        >>> ss = NumericStateSpace(np.diag([-1.0, -2.0, -5.0, -9.0]), np.ones((4, 1)),
        ...                        np.ones((1, 4)), [[0.0]], ("a", "b", "c", "d"), ("u",), ("y",))
        >>> ss.eigenvalues(k=2, sigma=-4.5).real
        array([-5., -2.])
        """
        if k is not None:
            return nearest_eigenvalues(self.A, k, sigma, name=self.name)
        if self.is_sparse:
            dense_allowed(dense, self.nstates, "all eigenvalues (LAPACK)", self.name)
            return sorted_eigenvalues(self.A.toarray())
        return sorted_eigenvalues(self.A)

    @property
    def is_proper(self) -> bool:
        """False when an input derivative reaches an output (``D_derivatives`` nonzero)."""
        return not any(_nonzero(M) for M in self.D_derivatives)

    def frequency_response(self, omega: Union[float, Sequence[float], np.ndarray]) -> np.ndarray:
        """``H(jw) = C (jw I - A)^-1 B + D (+ D_derivatives[k-1] (jw)^k)`` at ``omega`` (rad/s).

        A dense plant solves frequencies in chunks of bounded memory (about
        64 MB of ``n x n`` complex matrices at a time); a sparse one factors
        ``jw I - A`` by a sparse LU per frequency (memory ``O(nnz)``).

        Returns
        -------
        numpy.ndarray
            Complex, shape ``(len(omega), noutputs, ninputs)``; ``nan`` where
            ``jw`` is an eigenvalue of ``A``.
        """
        from .._support.numeric_input import numeric_array

        w = np.atleast_1d(numeric_array(omega, "omega", NumericError))
        if w.ndim != 1:
            raise NumericError(f"omega must be a number or a 1-D array; got shape {w.shape}")
        if not np.all(np.isfinite(w)):
            k = int(np.flatnonzero(~np.isfinite(w))[0])
            raise NumericError(f"omega[{k}] is {w[k]}; frequencies must be finite (rad/s)")
        if self.is_sparse:
            H = sparse_frequency_response(self._solver(), self.A.data, self.B, self.C, self.D, w)
        else:
            H = frequency_response(self.A, self.B, self.C, self.D, w)
        return add_derivatives(H, tuple(_array(M) for M in self.D_derivatives), w)

    def _solver(self) -> ShiftedSolver:
        solver = self.__dict__.get("_shifted")
        if solver is None:
            solver = ShiftedSolver(Pattern(self.A.shape, self.A.indptr, self.A.indices))
            object.__setattr__(self, "_shifted", solver)
        return solver

    def _require_proper(self, what: str) -> None:
        if not self.is_proper:
            raise ImproperPlantError(
                f"plant {self.name!r} is improper (an output depends on an input derivative: "
                f"D_derivatives is nonzero); {what} cannot hold it.  Use frequency_response(), "
                "or model.transfer_function(input, output).to_control(values) for a "
                "python-control transfer function")

    def _arrays(self, dense: str, what: str) -> tuple[np.ndarray, ...]:
        """Dense ``A, B, C, D`` for ``what``; a sparse plant asks ``dense=`` first."""
        if self.is_sparse:
            dense_allowed(dense, self.nstates, what, self.name)
        return tuple(_array(M) for M in (self.A, self.B, self.C, self.D))

    def to_control(self, *, dense: str = "warn") -> control.StateSpace:
        """A python-control ``StateSpace`` with state, input and output labels.

        python-control forbids ``'.'`` in signal names: hierarchical names are
        given with ``'_'`` (see :func:`control_labels`).  python-control
        systems have no units of their own: the plant's :attr:`units` are
        set as the system's ``units`` attribute (a dict keyed by those
        labels), which python-control's own operations (``feedback``,
        ``series``, indexing) do not carry over.

        Parameters
        ----------
        dense : {'warn', 'allow', 'refuse'}, optional
            A sparse plant becomes dense arrays (python-control has no sparse
            systems): with a :class:`~bondgraph.numeric.errors.DenseConversionWarning`
            naming the memory (default), silently, or not at all
            (:class:`~bondgraph.numeric.errors.DenseConversionError`).

        Examples
        --------
        >>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[2.0]], [[0.0]], ("x",), ("motor.V",), ("y",))
        >>> sys = ss.to_control()
        >>> sys.input_labels, float(sys.dcgain())
        (['motor_V'], 2.0)
        >>> ss.with_units({"motor.V": "volt", "y": "meter"}).to_control().units
        {'motor_V': 'volt', 'y': 'meter'}
        """
        import control

        self._require_proper("a python-control StateSpace")
        A, B, C, D = self._arrays(dense, "a python-control StateSpace")
        sys = control.ss(A, B, C, D,
                         states=control_labels(self.state_names),
                         inputs=control_labels(self.input_names),
                         outputs=control_labels(self.output_names),
                         name=self.name or None)
        names = (*self.state_names, *self.input_names, *self.output_names)
        labels = (*sys.state_labels, *sys.input_labels, *sys.output_labels)
        sys.units = {label: self.units[n] for n, label in zip(names, labels) if n in self.units}
        return sys

    def with_units(self, units: Mapping[str, str]) -> "NumericStateSpace":
        """This plant with the units of some of its signals (others keep theirs).

        Examples
        --------
        >>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[1.0]], [[0.0]], ("q",), ("V",), ("vC",))
        >>> dict(ss.with_units({"q": "coulomb", "V": "volt"}).units)
        {'q': 'coulomb', 'V': 'volt'}
        >>> ss.with_units({"w": "radian/second"})
        Traceback (most recent call last):
        ...
        bondgraph.numeric.errors.NumericError: unit given for 'w', which is no state, input or output of the plant (states q; inputs V; outputs vC)
        """
        return NumericStateSpace(self.A, self.B, self.C, self.D, self.state_names,
                                 self.input_names, self.output_names, dict(self.parameters),
                                 self.name, self.D_derivatives, self.state_shift,
                                 {**self.units, **dict(units)},
                                 None if self.operating_point is None else dataclasses.replace(
                                     self.operating_point,
                                     units={**self.operating_point.units, **dict(units)}))

    def to_tf(self, *, input: Optional[str] = None, output: Optional[str] = None,
              dense: str = "warn") -> control.TransferFunction:
        """A python-control ``TransferFunction`` (MIMO, or one channel), keeping names.

        Parameters
        ----------
        input, output : str, optional
            Pick one channel by name; by default all channels.
        dense : {'warn', 'allow', 'refuse'}, optional
            As :meth:`to_control`.

        Examples
        --------
        >>> ss = NumericStateSpace([[-2.0]], [[1.0]], [[4.0]], [[0.0]], ("x",), ("u",), ("y",))
        >>> G = ss.to_tf(input="u", output="y")
        >>> G.num[0][0], G.den[0][0], G.output_labels
        (array([4.]), array([1., 2.]), ['y'])
        """
        import control

        self._require_proper("to_tf (through a StateSpace)")
        G = control.ss2tf(self.to_control(dense=dense), name=self.name or None)
        if input is None and output is None:
            return G
        rows = range(self.noutputs) if output is None else [self._index(output, self.output_names, "output")]
        cols = range(self.ninputs) if input is None else [self._index(input, self.input_names, "input")]
        return G[list(rows), list(cols)]

    def minimal(self, *, tol: Optional[float] = None, dense: str = "warn") -> "NumericStateSpace":
        """A minimal realization: uncontrollable and unobservable states removed.

        Uses python-control's ``minreal`` (SLICOT ``TB01PD`` through slycot).  The
        states of the result are combinations of the model's states, named
        ``xm_1, xm_2, ...``; inputs and outputs keep their names.

        Parameters
        ----------
        tol : float, optional
            Rank tolerance (SLICOT's default when None).
        dense : {'warn', 'allow', 'refuse'}, optional
            As :meth:`to_control`.

        Examples
        --------
        >>> # x2 is driven by nothing and seen by nothing: one state remains
        >>> ss = NumericStateSpace([[-1.0, 0.0], [0.0, -3.0]], [[1.0], [0.0]], [[2.0, 0.0]],
        ...                        [[0.0]], ("x1", "x2"), ("u",), ("y",))
        >>> m = ss.minimal()
        >>> m.state_names, round(float(m.to_control().dcgain()), 12)
        (('xm_1',), 2.0)
        """
        import control

        self._require_proper("a minimal state-space realization")
        red = control.minreal(control.ss(*self._arrays(dense, "a minimal realization")), tol=tol,
                              verbose=False)
        n = red.nstates
        kept = {k: v for k, v in self.units.items() if k not in self.state_names}
        return NumericStateSpace(red.A, red.B, red.C, red.D,
                                 tuple(f"xm_{i + 1}" for i in range(n)), self.input_names,
                                 self.output_names, self.parameters, self.name, units=kept)

    def to_scipy(self, *, dense: str = "warn") -> scipy.signal.StateSpace:
        """The ``scipy.signal.StateSpace`` system (continuous time, no names); ``dense`` as
        :meth:`to_control`."""
        import scipy.signal

        self._require_proper("a scipy StateSpace")
        return scipy.signal.StateSpace(*self._arrays(dense, "a scipy StateSpace"))

    @staticmethod
    def _index(name: str, names: tuple[str, ...], what: str) -> int:
        if name in names:
            return names.index(name)
        raise NumericError(f"no {what} named {name!r}; {what}s are {', '.join(names) or '(none)'}")


def _checked_units(units: Any, names: tuple[tuple[str, ...], ...]) -> dict[str, str]:
    """``units`` as a dict of signal name -> unit text, every key a signal of the plant."""
    if not isinstance(units, Mapping):
        raise NumericError(f"units must be a mapping of signal name to unit text; got "
                           f"{type(units).__name__}")
    signals = {n for group in names for n in group}
    out = {}
    for key, value in units.items():
        if key not in signals:
            states, inputs, outputs = (", ".join(g) or "(none)" for g in names)
            raise NumericError(f"unit given for {key!r}, which is no state, input or output of the "
                               f"plant (states {states}; inputs {inputs}; outputs {outputs})")
        if not isinstance(value, str):
            raise NumericError(f"the unit of {key!r} must be a text such as 'newton'; got "
                               f"{type(value).__name__}")
        out[key] = value
    return out


def add_derivatives(H: np.ndarray, Dd: Sequence[np.ndarray], omega) -> np.ndarray:
    """``H + sum_k Dd[k-1] (jw)^k``; ``H`` has shape ``(..., F, p, m)``, ``Dd[k]`` ``(..., p, m)``."""
    if not Dd:
        return H
    jw = 1j * np.atleast_1d(np.asarray(omega, dtype=float))
    for k, M in enumerate(Dd, start=1):
        H = H + M[..., None, :, :] * (jw ** k)[:, None, None]
    return H
