"""Numeric linear plants: symbolic A, B, C, D compiled once, evaluated many times.

:func:`compile_plant` lambdifies the nonzero entries of the model's
``A, B, C, D`` once (numpy, with common-subexpression elimination) into a
:class:`NumericModel`; :meth:`NumericModel.plant` evaluates one parameter set
into a :class:`NumericStateSpace`, :meth:`NumericModel.batch` evaluates
thousands at once into a :class:`BatchStateSpace` (stacked ``(P, n, n)``
arrays with batched eigenvalues and frequency responses).  Numbers are never
substituted into sympy expressions.

Input derivatives.  A model whose equations hold input derivatives
(``x' = A x + B0 u + B1 u'``, ``y = C x + D0 u + D1 u'``: a flow source
driving an inertia) is compiled too.  Its plant uses the states
``z = x - B1 u`` (in general ``z = x - sum_j S_j u^(j)``, kept in
:attr:`NumericStateSpace.state_shift`), which removes ``u'`` from the state
equations: ``z' = A z + (B0 + A B1) u``, ``y = C z + (D0 + C B1) u + D1 u'``.
The coefficient matrices of ``s, s^2, ...`` in the feedthrough are
:attr:`NumericStateSpace.D_derivatives`; :meth:`~NumericStateSpace.frequency_response`
includes them.  When one is nonzero the plant is improper (``is_proper``
False) and ``to_control``/``to_tf``/``to_scipy`` raise
:class:`~bondgraph.numeric.errors.ImproperPlantError` (python-control and scipy
state-space systems cannot hold ``D1 s``); use
``model.transfer_function(...).to_control(values)`` for a python-control
transfer function of an improper entry.

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("msd")
>>> F, v = bg.Se("F"), bg.One("v")
>>> g.add(F, v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
>>> for tail, head in [(F, v), (v, "m"), (v, "b"), (v, "k")]: _ = g.connect(tail, head)
>>> nm = compile_plant(bg.derive(g, outputs={"x": bg.displacement("k")}))
>>> nm.parameter_names
('b', 'k', 'm')
>>> nm.plant({"m": 1.0, "b": 2.0, "k": 5.0}).eigenvalues()     # s^2 + 2 s + 5
array([-1.-2.j, -1.+2.j])
>>> nm.batch({"m": 1.0, "b": [2.0, 5.0], "k": 4.0}).eigenvalues().real.round(9)
array([[-1., -1.],
       [-4., -1.]])
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping, Optional, Sequence, Union

import numpy as np
import sympy

from .._labels import control_labels
from ..model import Model
from ..parameters import real_value
from ..statespace import SignalCounts, check_matrix_shape, expected_shape
from ..values import parameter_symbols
from ._compile import CompiledFunction, placeholders, user_functions
from ._linalg import freeze, frequency_response, sorted_eigenvalues
from .errors import (
    ImproperPlantError,
    NotPicklableError,
    NumericError,
    ParameterValueError,
)
from .parameters import ParameterValues, resolve_batch, resolve_parameters

if TYPE_CHECKING:  # imported lazily at run time
    import control
    import scipy.signal

__all__ = ["NumericStateSpace", "BatchStateSpace", "NumericModel", "compile_plant",
           "numeric_plant", "control_labels"]


def _matrix(value: Any, label: str) -> np.ndarray:
    arr = np.array(value, dtype=float)
    if arr.ndim != 2:
        raise NumericError(f"state-space matrix {label} must be 2-D; got shape {arr.shape}")
    return freeze(arr)


@dataclass(frozen=True, eq=False)
class NumericStateSpace(SignalCounts):
    """``x' = A x + B u``, ``y = C x + D u`` with numbers and names.

    Parameters
    ----------
    A, B, C, D : array_like
        Stored as read-only float64 arrays.
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

    Raises
    ------
    NumericError
        If a matrix shape does not match the numbers of names.

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

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    parameters: Mapping[str, float] = field(default_factory=dict)
    name: str = ""
    D_derivatives: tuple[np.ndarray, ...] = ()
    state_shift: tuple[np.ndarray, ...] = ()

    def __post_init__(self) -> None:
        names = tuple(tuple(str(s) for s in getattr(self, f)) for f in
                      ("state_names", "input_names", "output_names"))
        n, m, p = (len(x) for x in names)

        def checked(raw, label, shape_of):
            arr = _matrix(np.reshape(raw, expected_shape(shape_of, n, m, p))
                          if np.size(raw) == 0 else raw, label)
            check_matrix_shape(shape_of, arr.shape, n, m, p, NumericError)
            return arr
        for label in "ABCD":
            object.__setattr__(self, label, checked(getattr(self, label), label, label))
        object.__setattr__(self, "D_derivatives", tuple(
            checked(M, f"D_derivatives[{k}]", "D") for k, M in enumerate(self.D_derivatives)))
        object.__setattr__(self, "state_shift", tuple(
            checked(M, f"state_shift[{k}]", "B") for k, M in enumerate(self.state_shift)))
        for f, value in zip(("state_names", "input_names", "output_names"), names):
            object.__setattr__(self, f, value)
        object.__setattr__(self, "parameters",
                           MappingProxyType({str(k): real_value(v, str(k))
                                             for k, v in dict(self.parameters).items()}))

    def __repr__(self) -> str:
        return (f"NumericStateSpace({self.name!r}: {self.nstates} states, {self.ninputs} inputs, "
                f"{self.noutputs} outputs)")

    def __reduce__(self):
        # rebuilt through __init__: read-only copies of the same float64 arrays (bit for bit),
        # the parameter values as a read-only mapping again
        return (NumericStateSpace, (self.A, self.B, self.C, self.D, self.state_names,
                                    self.input_names, self.output_names, dict(self.parameters),
                                    self.name, self.D_derivatives, self.state_shift))

    def eigenvalues(self) -> np.ndarray:
        """Eigenvalues of ``A`` (the poles), sorted by real then imaginary part."""
        return sorted_eigenvalues(self.A)

    @property
    def is_proper(self) -> bool:
        """False when an input derivative reaches an output (``D_derivatives`` nonzero)."""
        return not any(np.any(M != 0.0) for M in self.D_derivatives)

    def frequency_response(self, omega: Union[float, Sequence[float], np.ndarray]) -> np.ndarray:
        """``H(jw) = C (jw I - A)^-1 B + D (+ D_derivatives[k-1] (jw)^k)`` at ``omega`` (rad/s).

        Returns
        -------
        numpy.ndarray
            Complex, shape ``(len(omega), noutputs, ninputs)``; ``nan`` where
            ``jw`` is an eigenvalue of ``A``.
        """
        return _add_derivatives(frequency_response(self.A, self.B, self.C, self.D, omega),
                                self.D_derivatives, omega)

    def _require_proper(self, what: str) -> None:
        if not self.is_proper:
            raise ImproperPlantError(
                f"plant {self.name!r} is improper (an output depends on an input derivative: "
                f"D_derivatives is nonzero); {what} cannot hold it.  Use frequency_response(), "
                "or model.transfer_function(input, output).to_control(values) for a "
                "python-control transfer function")

    def to_control(self) -> control.StateSpace:
        """A python-control ``StateSpace`` with state, input and output labels.

        python-control forbids ``'.'`` in signal names: hierarchical names are
        given with ``'_'`` (see :func:`control_labels`).

        Examples
        --------
        >>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[2.0]], [[0.0]], ("x",), ("motor.V",), ("y",))
        >>> sys = ss.to_control()
        >>> sys.input_labels, float(sys.dcgain())
        (['motor_V'], 2.0)
        """
        import control

        self._require_proper("a python-control StateSpace")
        return control.ss(self.A, self.B, self.C, self.D,
                          states=control_labels(self.state_names),
                          inputs=control_labels(self.input_names),
                          outputs=control_labels(self.output_names),
                          name=self.name or None)

    def to_tf(self, *, input: Optional[str] = None,
              output: Optional[str] = None) -> control.TransferFunction:
        """A python-control ``TransferFunction`` (MIMO, or one channel), keeping names.

        Parameters
        ----------
        input, output : str, optional
            Pick one channel by name; by default all channels.

        Examples
        --------
        >>> ss = NumericStateSpace([[-2.0]], [[1.0]], [[4.0]], [[0.0]], ("x",), ("u",), ("y",))
        >>> G = ss.to_tf(input="u", output="y")
        >>> G.num[0][0], G.den[0][0], G.output_labels
        (array([4.]), array([1., 2.]), ['y'])
        """
        import control

        self._require_proper("to_tf (through a StateSpace)")
        G = control.ss2tf(self.to_control(), name=self.name or None)
        if input is None and output is None:
            return G
        rows = range(self.noutputs) if output is None else [self._index(output, self.output_names, "output")]
        cols = range(self.ninputs) if input is None else [self._index(input, self.input_names, "input")]
        return G[list(rows), list(cols)]

    def minimal(self, *, tol: Optional[float] = None) -> "NumericStateSpace":
        """A minimal realization: uncontrollable and unobservable states removed.

        Uses python-control's ``minreal`` (SLICOT ``TB01PD`` through slycot).  The
        states of the result are combinations of the model's states, named
        ``xm_1, xm_2, ...``; inputs and outputs keep their names.

        Parameters
        ----------
        tol : float, optional
            Rank tolerance (SLICOT's default when None).

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
        red = control.minreal(control.ss(self.A, self.B, self.C, self.D), tol=tol, verbose=False)
        n = red.nstates
        return NumericStateSpace(red.A, red.B, red.C, red.D,
                                 tuple(f"xm_{i + 1}" for i in range(n)), self.input_names,
                                 self.output_names, self.parameters, self.name)

    def to_scipy(self) -> scipy.signal.StateSpace:
        """The ``scipy.signal.StateSpace`` system (continuous time, no names)."""
        import scipy.signal

        self._require_proper("a scipy StateSpace")
        return scipy.signal.StateSpace(self.A, self.B, self.C, self.D)

    @staticmethod
    def _index(name: str, names: tuple[str, ...], what: str) -> int:
        if name in names:
            return names.index(name)
        raise NumericError(f"no {what} named {name!r}; {what}s are {', '.join(names) or '(none)'}")


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
        return _add_derivatives(frequency_response(self.A, self.B, self.C, self.D, omega),
                                self.D_derivatives, omega)


class _CompiledModel:
    """A derived :class:`Model` and its signal and parameter names (base of the compiled forms)."""

    def __init__(self, model: Model) -> None:
        if not isinstance(model, Model):
            raise NumericError("expected a bondgraph Model (from bondgraph.derive); "
                               f"got {type(model).__name__}")
        self._model = model
        self._params: tuple[sympy.Symbol, ...] = model.parameters

    @property
    def model(self) -> Model:
        return self._model

    def __getstate__(self) -> dict:
        # the model's own expressions travel too: a law calling a Python function cannot
        funcs = user_functions((*self._model.rhs, *self._model.output_exprs))
        if funcs:
            raise NotPicklableError(
                f"model {self._model.name!r} cannot be pickled: its laws call the Python "
                f"function(s) {', '.join(map(str, funcs))} (sympy implemented_function), which "
                "pickle cannot carry; compile the model in each process instead")
        return dict(self.__dict__)

    @property
    def parameter_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self._params)

    @property
    def state_names(self) -> tuple[str, ...]:
        return self._model.state_names

    @property
    def input_names(self) -> tuple[str, ...]:
        return self._model.input_names

    @property
    def output_names(self) -> tuple[str, ...]:
        return self._model.output_names


class NumericModel(_CompiledModel):
    """A linear model's ``A, B, C, D`` compiled to numpy once, for repeated evaluation.

    Parameters
    ----------
    model : Model
        A linear derived model.

    Raises
    ------
    NonlinearModelError
        If the model is not linear (input derivatives are fine: see
        :mod:`bondgraph.numeric.plant`).

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("rc")
    >>> V, n = bg.Se("V"), bg.One("i")
    >>> g.add(V, n, bg.R("R"), bg.C("C"))
    >>> _ = g.connect(V, n); _ = g.connect(n, "R"); _ = g.connect(n, "C")
    >>> nm = NumericModel(bg.derive(g, outputs={"vC": bg.effort("C")}))
    >>> nm.plant({"R": 1e3, "C": 1e-6}).A
    array([[-1000.]])
    """

    def __init__(self, model: Model) -> None:
        super().__init__(model)
        A, Bs, C, Ds = model._derivative_form()
        #: highest input derivative order (0: an ordinary plant)
        self._order = len(Bs) - 1
        mats = (A,) + tuple(Bs) + (C,) + tuple(Ds)
        self._labels = ("A",) + tuple("B" + (str(k) if k else "") for k in range(len(Bs))) + \
            ("C",) + tuple("D" + (str(k) if k else "") for k in range(len(Ds)))
        self._shapes = tuple(M.shape for M in mats)
        dummies = placeholders("p", len(self._params))
        swap = dict(zip(self._params, dummies))
        self._var: list[tuple[int, int, int]] = []
        self._const: list[tuple[int, int, int, float]] = []
        exprs = []
        for k, M in enumerate(mats):
            for (i, j), ex in sorted(M.todok().items()):
                if ex.free_symbols:
                    self._var.append((k, i, j))
                    exprs.append(ex.xreplace(swap))
                else:
                    self._const.append((k, i, j,
                                        _real_constant(ex, self._labels[k], i, j, model.name)))
        self._fn = CompiledFunction(dummies, exprs) if exprs else None

    def _reduce(self, mats: list[np.ndarray]):
        """``A, B, C, D, D_derivatives, state_shift`` from ``A, B0..BK, C, D0..DK``.

        ``S_{K-1} = B_K``, ``S_j = B_{j+1} + A S_{j+1}`` (so ``S_j = sum_{k>j}
        A^(k-1-j) B_k``); ``B = B0 + A S_0``, ``D_j' = D_j + C S_j``.
        """
        K = self._order
        A, Bs, C, Ds = mats[0], mats[1:K + 2], mats[K + 2], mats[K + 3:]
        if K == 0:
            return A, Bs[0], C, Ds[0], (), ()
        S: list[np.ndarray] = [np.empty(0)] * K
        S[K - 1] = Bs[K]
        for j in range(K - 2, -1, -1):
            S[j] = Bs[j + 1] + A @ S[j + 1]
        B = Bs[0] + A @ S[0]
        D = [Ds[j] + C @ S[j] for j in range(K)] + [Ds[K]]
        return A, B, C, D[0], tuple(freeze(M) for M in D[1:]), tuple(freeze(M) for M in S)

    def __repr__(self) -> str:
        return (f"NumericModel({self._model.name!r}: {len(self.state_names)} states, "
                f"{len(self._params)} parameters)")

    @property
    def parameters(self) -> tuple[sympy.Symbol, ...]:
        """Parameter symbols in the order of :attr:`parameter_names`."""
        return self._params

    def _evaluate(self, columns: list, size: Optional[int]) -> list[np.ndarray]:
        lead = () if size is None else (size,)
        mats = [np.zeros(lead + shape) for shape in self._shapes]
        for k, i, j, value in self._const:
            mats[k][..., i, j] = value
        if self._fn is not None:
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                values = self._fn(*columns)
            for (k, i, j), value in zip(self._var, values):
                mats[k][..., i, j] = value
        return mats

    def _check_finite(self, mats: list[np.ndarray], values: np.ndarray, batch: bool) -> None:
        for label, M in zip(self._labels, mats):
            bad = ~np.isfinite(M)
            if bad.any():
                idx = tuple(int(v) for v in np.argwhere(bad)[0])
                where = f"parameter set {idx[0]}: " if batch else ""
                row = values[idx[0]] if batch else values
                entry = idx[1:] if batch else idx
                vals = ", ".join(f"{n}={v:g}" for n, v in zip(self.parameter_names, row))
                zeros = [n for n, v in zip(self.parameter_names, row) if v == 0]
                culprits = _elements_using(self._model, zeros)
                hint = (f"; {culprits} divides by a parameter that is zero" if culprits else
                        "; a parameter that divides (mass, inductance, ...) is zero?")
                raise ParameterValueError(
                    f"model {self._model.name!r}: {where}matrix {label} entry {entry} is "
                    f"{M[idx]} for {vals}{hint}")

    def plant(self, values: ParameterValues) -> NumericStateSpace:
        """Evaluate ``A, B, C, D`` at one parameter set.

        Parameters
        ----------
        values : mapping of Symbol or str to float
            Exactly the model's parameters, finite real numbers.

        Raises
        ------
        ParameterValueError
            Missing or unknown names (listed together), non-finite or
            non-real values, or a non-finite matrix entry.
        """
        vec = resolve_parameters(self._params, values, model=self._model.name,
                                 known=self._model.known_parameters)
        mats = self._evaluate([np.float64(v) for v in vec], None)
        self._check_finite(mats, vec, False)
        A, B, C, D, Dd, S = self._reduce(mats)
        return NumericStateSpace(A, B, C, D, self.state_names, self.input_names, self.output_names,
                                 dict(zip(self.parameter_names, vec.tolist())), self._model.name,
                                 Dd, S)

    def batch(self, values: Union[ParameterValues, np.ndarray]) -> BatchStateSpace:
        """Evaluate ``A, B, C, D`` for ``P`` parameter sets at once.

        Parameters
        ----------
        values : mapping or array
            A mapping of name (or Symbol) to a 1-D array of length ``P`` or a
            scalar (shared by every set), or a ``(P, k)`` array with columns
            in the order of :attr:`parameter_names`.

        Returns
        -------
        BatchStateSpace

        Raises
        ------
        ParameterValueError
            As :meth:`plant`, naming the first bad parameter set.
        """
        arr = resolve_batch(self._params, values, model=self._model.name,
                            known=self._model.known_parameters)
        size = arr.shape[0]
        mats = self._evaluate([arr[:, j] for j in range(arr.shape[1])], size)
        self._check_finite(mats, arr, True)
        freeze(arr)
        A, B, C, D, Dd, S = self._reduce(mats)
        A, B, C, D = (freeze(np.ascontiguousarray(M)) for M in (A, B, C, D))
        return BatchStateSpace(A, B, C, D, self.state_names, self.input_names,
                               self.output_names, self.parameter_names, arr, self._model.name,
                               Dd, S)


def _rebuild_batch(fields: dict) -> BatchStateSpace:
    """A unpickled :class:`BatchStateSpace`, its arrays read-only again."""
    for key, value in fields.items():
        if isinstance(value, np.ndarray):
            fields[key] = freeze(value)
        elif key in ("D_derivatives", "state_shift"):
            fields[key] = tuple(freeze(M) for M in value)
    return BatchStateSpace(**fields)


def _elements_using(model: Model, names: Sequence[str]) -> str:
    """``"I:La (La = 0)"`` for the elements whose parameters use one of ``names``."""
    found = []
    for el in (model.augmented.flat.elements if model.augmented is not None else ()):
        hit = sorted({sym.name for sym in parameter_symbols(el)} & set(names))
        if hit:
            found.append(f"{el.label()} ({', '.join(f'{h} = 0' for h in hit)})")
    return ", ".join(found)


def _add_derivatives(H: np.ndarray, Dd: Sequence[np.ndarray], omega) -> np.ndarray:
    """``H + sum_k Dd[k-1] (jw)^k``; ``H`` has shape ``(..., F, p, m)``, ``Dd[k]`` ``(..., p, m)``."""
    if not Dd:
        return H
    jw = 1j * np.atleast_1d(np.asarray(omega, dtype=float))
    for k, M in enumerate(Dd, start=1):
        H = H + M[..., None, :, :] * (jw ** k)[:, None, None]
    return H


def _real_constant(ex: sympy.Expr, label: str, i: int, j: int, name: str) -> float:
    value = complex(ex)
    if value.imag != 0:
        raise NumericError(f"model {name!r}: matrix {label} entry ({i}, {j}) = {ex} is not real")
    return value.real


def compile_plant(model: Model) -> NumericModel:
    """Compile a linear model's ``A, B, C, D`` once; see :class:`NumericModel`.

    Parameters
    ----------
    model : Model
        A linear model (from :func:`bondgraph.derive`).

    Returns
    -------
    NumericModel

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
    >>> compile_plant(bg.derive(g, outputs={"v": bg.flow("m")})).plant({"m": 4.0}).C
    array([[0.25]])
    """
    return NumericModel(model)


def numeric_plant(model: Model, values: ParameterValues) -> NumericStateSpace:
    """One-off numeric plant: ``compile_plant(model).plant(values)``.

    Parameters
    ----------
    model : Model
        A linear model (from :func:`bondgraph.derive`).
    values : mapping of Symbol or str to float
        A value for every parameter of the model.

    Returns
    -------
    NumericStateSpace

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
    >>> numeric_plant(bg.derive(g, outputs={"v": bg.flow("m")}), {"m": 4.0}).eigenvalues()
    array([0.+0.j])
    """
    return NumericModel(model).plant(values)
