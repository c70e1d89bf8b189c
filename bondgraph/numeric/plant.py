"""Numeric linear plants: symbolic A, B, C, D compiled once, evaluated many times.

:func:`compile_plant` compiles the nonzero entries of the model's
``A, B, C, D`` once into a :class:`NumericModel`: a fixed sparsity pattern
per matrix and one vector of values.  Entries that are monomials in the
parameters (``-b/m``, ``1/C``, ``n*r``: nearly all of a bond-graph plant) or
sums of monomials are evaluated together by numpy gathers and products,
without generating code; only the other entries (each distinct one once) are
lambdified, with common-subexpression elimination (see
:mod:`bondgraph.numeric._monomials`). :meth:`NumericModel.plant` evaluates one parameter set
into a :class:`NumericStateSpace`, :meth:`NumericModel.batch` evaluates
thousands at once into a :class:`BatchStateSpace` (stacked ``(P, n, n)``
arrays with batched eigenvalues and frequency responses).  Numbers are never
substituted into sympy expressions.

Sparse plants.  A model with more than
:data:`~bondgraph.numeric.sparse.SPARSE_THRESHOLD` (500) states gives sparse
plants (``scipy.sparse`` CSR matrices, see :mod:`bondgraph.numeric.sparse`)
and sparse batches (:class:`SparseBatchStateSpace`: the patterns once, a
``(P, nnz)`` array of values); ``compile_plant(model, sparse=True/False)``
or ``plant(values, sparse=...)``/``batch(values, sparse=...)`` choose
otherwise.  Dense plants are filled from the patterns in one vectorised
assignment per matrix.

Input derivatives.  A model whose equations hold input derivatives
(``x' = A x + B0 u + B1 u'``, ``y = C x + D0 u + D1 u'``: a flow source
driving an inertia) is compiled too.  Its plant uses the states
``z = x - B1 u`` (in general ``z = x - sum_j S_j u^(j)``, kept in
:attr:`NumericStateSpace.state_shift`), which removes ``u'`` from the state
equations: ``z' = A z + (B0 + A B1) u``, ``y = C z + (D0 + C B1) u + D1 u'``
(products formed on the sparse symbolic matrices, once, at compile time).
The coefficient matrices of ``s, s^2, ...`` in the feedthrough are
:attr:`NumericStateSpace.D_derivatives`; :meth:`~NumericStateSpace.frequency_response`
includes them.  When one is nonzero the plant is improper (``is_proper``
False) and ``to_control``/``to_tf``/``to_scipy`` raise
:class:`~bondgraph.ImproperPlantError` (python-control and scipy
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

from typing import Optional, Sequence, Union

import numpy as np
import scipy.sparse as sp
import sympy

from .._support.gcpause import with_paused_gc
from .._support.labels import control_labels
from ..equations import StateEquations
from ..linear import derivative_form
from .._support.sympify import parameter_symbols
from ._compile import CompiledFunction, placeholders, user_functions
from ._monomials import compile_entries
from ._schur import implicit_blocks, reduce, reduce_batch
from ..elements.fields.algebra import check_definite
from ..elements.rules import check_model_values
from ._linalg import freeze
from .batch import BatchStateSpace, SparseBatchStateSpace
from ..errors import NonlinearModelError
from .errors import NotPicklableError, NumericError, ParameterValueError
from .resolve import ParameterValues, resolve_batch, resolve_parameters
from .sparse import SPARSE_THRESHOLD, Pattern
from .statespace import NumericStateSpace

__all__ = ["NumericStateSpace", "BatchStateSpace", "SparseBatchStateSpace", "NumericModel",
           "compile_plant", "numeric_plant", "control_labels", "SPARSE_THRESHOLD"]


class _CompiledModel:
    """A derived :class:`Model` and its signal and parameter names (base of the compiled forms)."""

    def __init__(self, model: StateEquations) -> None:
        if not isinstance(model, StateEquations):
            raise NumericError("expected a bondgraph Model (from bondgraph.derive); "
                               f"got {type(model).__name__}")
        from ._compile import _check_evaluable
        try:
            _check_evaluable((*model.rhs, *model.output_exprs))
        except NumericError as exc:
            raise NumericError(f"model {model.name!r}: {exc}") from None
        self._model = model
        self._params: tuple[sympy.Symbol, ...] = model.parameters

    @property
    def model(self) -> StateEquations:
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

    Only the nonzero entries are compiled: each matrix is a fixed
    :class:`~bondgraph.numeric.sparse.Pattern` and all their values come at
    once from numpy products for the monomial entries and one lambdified
    function for the others (constant entries are stored, not compiled).

    Parameters
    ----------
    model : StateEquations
        A linear derived model.
    sparse : bool, optional
        Whether :meth:`plant` and :meth:`batch` give sparse plants; by default
        (None) sparse when the model has more than
        :data:`~bondgraph.numeric.sparse.SPARSE_THRESHOLD` states.

    Raises
    ------
    NonlinearModelError
        If the model is not linear (input derivatives are fine: see
        :mod:`bondgraph.numeric.plant`).

    Notes
    -----
    A linear model that keeps algebraic unknowns ``z`` (a loop too large to
    solve symbolically) is compiled as its blocks ``f = F_x x + F_z z + F_u
    u``, ``0 = G_x x + G_z z + G_u u``; each plant eliminates ``z``
    numerically (:mod:`bondgraph.numeric._schur`), and its batches are dense.

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
    >>> nm.nnz, nm.plant({"R": 1e3, "C": 1e-6}, sparse=True).A.toarray()
    (3, array([[-1000.]]))
    """

    @with_paused_gc      # no cycles among the entries; full passes over a big model's heap cost
    def __init__(self, model: StateEquations, *, sparse: Optional[bool] = None) -> None:
        super().__init__(model)
        if sparse not in (None, True, False):
            raise NumericError(f"sparse must be True, False or None (by size); got {sparse!r}")
        self._sparse = sparse
        #: a linear implicit model: its algebraic unknowns are eliminated after evaluation
        self._implicit = bool(model.algebraic)
        #: constant sources: the constant columns c, d of x' = A x + B u + c, y = C x + D u + d
        #: are compiled after the other matrices, for the operating point of each plant
        self._affine = False
        try:
            mats, self._labels = implicit_blocks(model) if self._implicit else _reduced_form(model)
        except NonlinearModelError as exc:
            if self._implicit:
                raise
            mats, self._labels = _offset_form(model, exc)
            self._affine = True
        #: number of D_derivatives (and state_shift) matrices: 0 for an ordinary plant
        self._order = (len(mats) - 4 - 2 * self._affine) // 2
        patterns, var_pos, exprs, const_pos, const_val = [], [], [], [], []
        pos = 0
        for k, M in enumerate(mats):
            items = sorted(_entries(M).items())
            patterns.append(Pattern.from_coordinates(M.shape, [i for (i, _), _ in items],
                                                     [j for (_, j), _ in items]))
            for (i, j), ex in items:
                if not ex.is_Number and (_has_symbol_factor(ex) or ex.free_symbols):
                    var_pos.append(pos)
                    exprs.append(ex)
                else:
                    const_pos.append(pos)
                    const_val.append(_real_constant(ex, self._labels[k], i, j, model.name))
                pos += 1
        self._patterns: tuple[Pattern, ...] = tuple(patterns)
        self._offsets = np.concatenate([[0], np.cumsum([p.nnz for p in patterns])])
        self._var_pos = np.array(var_pos, dtype=np.int64)
        self._const_pos = np.array(const_pos, dtype=np.int64)
        self._const_val = np.array(const_val, dtype=float)
        #: the symbolic entries: monomials and sums of them by numpy, the rest lambdified
        self._fn = compile_entries(self._params, exprs) if exprs else None
        #: fields whose matrix has symbolic entries: checked definite at every evaluation
        self._definite = _definite_checks(model, self._params)
        self._known: Optional[tuple[str, ...]] = None

    def __repr__(self) -> str:
        return (f"NumericModel({self._model.name!r}: {len(self.state_names)} states, "
                f"{len(self._params)} parameters, {self.nnz} nonzeros)")

    @property
    def parameters(self) -> tuple[sympy.Symbol, ...]:
        """Parameter symbols in the order of :attr:`parameter_names`."""
        return self._params

    def _known_parameters(self) -> tuple[str, ...]:
        # Model.known_parameters walks every equation: once per compiled model, not per plant
        if self._known is None:
            self._known = self._model.known_parameters
        return self._known

    @property
    def patterns(self) -> tuple[Pattern, ...]:
        """Sparsity patterns of ``A, B, C, D`` (then of the ``D_derivatives`` and
        ``state_shift`` matrices of a model with input derivatives)."""
        return self._patterns

    @property
    def nnz(self) -> int:
        """Number of stored entries of all the matrices (the length of a value vector)."""
        return int(self._offsets[-1])

    def _is_sparse(self, sparse: Optional[bool]) -> bool:
        if sparse not in (None, True, False):
            raise NumericError(f"sparse must be True, False or None (by size); got {sparse!r}")
        choice = self._sparse if sparse is None else sparse
        return len(self.state_names) > SPARSE_THRESHOLD if choice is None else choice

    def _evaluate(self, columns: list, size: Optional[int]) -> np.ndarray:
        """The value vector ``(nnz,)``, or ``(size, nnz)`` for a batch."""
        lead = () if size is None else (size,)
        vals = np.empty(lead + (self.nnz,))
        vals[..., self._const_pos] = self._const_val
        if self._fn is not None:
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                vals[..., self._var_pos] = self._fn.evaluate(columns, size)
        return vals

    def _check_finite(self, vals: np.ndarray, values: np.ndarray, batch: bool) -> None:
        bad = ~np.isfinite(vals)
        if not bad.any():
            return
        first = np.argwhere(bad)[0]
        row_index, pos = (int(first[0]), int(first[1])) if batch else (0, int(first[0]))
        k = int(np.searchsorted(self._offsets, pos, side="right") - 1)
        local = pos - int(self._offsets[k])
        entry = (int(self._patterns[k].rows[local]), int(self._patterns[k].indices[local]))
        where = f"parameter set {row_index}: " if batch else ""
        row = values[row_index] if batch else values
        vals_text = ", ".join(f"{n}={v:g}" for n, v in zip(self.parameter_names, row))
        zeros = [n for n, v in zip(self.parameter_names, row) if v == 0]
        culprits = _elements_using(self._model, zeros)
        hint = (f"; {culprits} divides by a parameter that is zero" if culprits else
                "; a parameter that divides (mass, inductance, ...) is zero?")
        value = vals[row_index, pos] if batch else vals[pos]
        raise ParameterValueError(
            f"model {self._model.name!r}: {where}matrix {self._labels[k]} entry {entry} is "
            f"{value} for {vals_text}{hint}")

    def _check_definite(self, columns: list, size: Optional[int]) -> None:
        """Each field's matrix positive (semi-)definite at the values (a
        :class:`~bondgraph.FieldError` naming the field and the first
        failing parameter set)."""
        for el, fn, n in self._definite:
            stack = np.empty(((size or 1), n * n))
            for k, v in enumerate(fn(*columns)):
                stack[:, k] = v
            check_definite(stack.reshape(-1, n, n) if size is not None else stack.reshape(n, n),
                           owner=el.label(), what=getattr(el, "matrix_name", "matrix"),
                           definite=el.definite)

    def _split(self, mats: list) -> tuple:
        if self._affine:
            mats = mats[:-2]
        d = self._order
        return tuple(mats[:4]) + (tuple(mats[4:4 + d]), tuple(mats[4 + d:]))

    def plant(self, values: ParameterValues, *, sparse: Optional[bool] = None) -> NumericStateSpace:
        """Evaluate ``A, B, C, D`` at one parameter set.

        Parameters
        ----------
        values : mapping of Symbol or str to float
            Exactly the model's parameters, finite real numbers.
        sparse : bool, optional
            ``scipy.sparse`` CSR matrices (True) or dense arrays (False); by
            default as chosen at :func:`compile_plant`, else by size
            (:data:`~bondgraph.numeric.sparse.SPARSE_THRESHOLD`).

        Raises
        ------
        ParameterValueError
            Missing or unknown names (listed together), non-finite or
            non-real values, or a non-finite matrix entry.
        """
        as_sparse = self._is_sparse(sparse)
        vec = resolve_parameters(self._params, values, model=self._model.name,
                                 known=self._known_parameters(),
                                 inputs=[s.name for s in self._model.inputs])
        check_model_values(self._model, dict(zip(self.parameter_names, vec)),
                           where=f"model {self._model.name!r}: ")
        vals = self._evaluate([np.float64(v) for v in vec], None)
        self._check_definite([np.float64(v) for v in vec], None)
        self._check_finite(vals, vec, False)
        off = self._offsets
        mats = [p.to_sparse(vals[off[k]:off[k + 1]]) if as_sparse
                else freeze(p.to_dense(vals[off[k]:off[k + 1]]))
                for k, p in enumerate(self._patterns)]
        A, B, C, D, Dd, S = self._split(mats)
        if self._implicit:
            A, B, C, D = reduce(self._model, A, B, C, D, as_sparse)
            A, B, C, D = ((sp.csr_array(M) for M in (A, B, C, D)) if as_sparse
                          else (freeze(np.ascontiguousarray(M)) for M in (A, B, C, D)))
        params = dict(zip(self.parameter_names, vec.tolist()))
        point = self._operating_point(A, C, mats[-2:], params) if self._affine else None
        return NumericStateSpace(A, B, C, D, self.state_names, self.input_names, self.output_names,
                                 params, self._model.name, Dd, S, operating_point=point)

    def _operating_point(self, A, C, offsets, params):
        """``x0 = -A^-1 c`` and ``y0 = C x0 + d`` at ``u0 = 0`` (the constant sources alone)."""
        from ..linear import OperatingPoint

        c, d = (np.asarray(M.toarray() if sp.issparse(M) else M, dtype=float).reshape(-1)
                for M in offsets)
        with np.errstate(all="ignore"):
            try:
                x0 = (sp.linalg.spsolve(sp.csc_array(A), -c) if sp.issparse(A)
                      else _scaled_solve(np.asarray(A), -c)) if c.size else c
            except (np.linalg.LinAlgError, RuntimeError):
                x0 = np.full(c.shape, np.nan)
            x0 = np.atleast_1d(np.asarray(x0, dtype=float))
            y0 = np.asarray(C @ x0, dtype=float).reshape(-1) + d
        if not (np.all(np.isfinite(x0)) and np.all(np.isfinite(y0))):
            vals = ", ".join(f"{n}={v:g}" for n, v in params.items())
            raise ParameterValueError(
                f"model {self._model.name!r}: its constant sources have no isolated "
                f"equilibrium at {vals} (A is singular: a conserved quantity, or a state no "
                "equation holds, such as a free mass's position); the plant in deviations "
                "needs one: give the totals with model.operating_point(values=..., "
                "totals=...) and take model.linearize(...) there")
        return OperatingPoint(dict(zip(self.state_names, x0.tolist())),
                              dict.fromkeys(self.input_names, 0.0),
                              dict(zip(self.output_names, y0.tolist())),
                              how="exact: x0 = -A^-1 c at u0 = 0 (the constant sources alone)")

    def batch(self, values: Union[ParameterValues, np.ndarray], *,
              sparse: Optional[bool] = None) -> Union[BatchStateSpace, SparseBatchStateSpace]:
        """Evaluate ``A, B, C, D`` for ``P`` parameter sets at once.

        Parameters
        ----------
        values : mapping or array
            A mapping of name (or Symbol) to a 1-D array of length ``P`` or a
            scalar (shared by every set), or a ``(P, k)`` array with columns
            in the order of :attr:`parameter_names`.
        sparse : bool, optional
            A :class:`SparseBatchStateSpace` (the patterns once and a
            ``(P, nnz)`` array of values) or a :class:`BatchStateSpace`
            (dense ``(P, n, n)`` stacks); chosen as in :meth:`plant`.

        Returns
        -------
        BatchStateSpace or SparseBatchStateSpace

        Raises
        ------
        ParameterValueError
            As :meth:`plant`, naming the first bad parameter set.
        """
        as_sparse = self._is_sparse(sparse)
        arr = resolve_batch(self._params, values, model=self._model.name,
                            known=self._known_parameters(), inputs=self.input_names)
        size = arr.shape[0]
        check_model_values(self._model, {n: arr[:, j] for j, n in enumerate(self.parameter_names)},
                           where=f"model {self._model.name!r}: ")
        vals = self._evaluate([arr[:, j] for j in range(arr.shape[1])], size)
        self._check_definite([arr[:, j] for j in range(arr.shape[1])], size)
        self._check_finite(vals, arr, True)
        freeze(arr)
        names = (self.state_names, self.input_names, self.output_names, self.parameter_names)
        if self._implicit:          # eliminated per parameter set: dense stacks
            off = self._offsets
            A, B, C, D = (p.to_dense(vals[:, off[k]:off[k + 1]])
                          for k, p in enumerate(self._patterns[:4]))
            A, B, C, D = (freeze(np.ascontiguousarray(M))
                          for M in reduce_batch(self._model, A, B, C, D))
            return BatchStateSpace(A, B, C, D, *names, arr, self._model.name, (), ())
        patterns = self._patterns[:len(self._patterns) - 2 * self._affine]
        if self._affine:        # the matrices only: a batch holds no operating point
            vals = vals[:, :self._offsets[-3]]
        if as_sparse:
            return SparseBatchStateSpace(patterns, freeze(vals), *names, arr, self._model.name,
                                         self._order)
        off = self._offsets
        mats = [freeze(p.to_dense(vals[:, off[k]:off[k + 1]])) for k, p in enumerate(patterns)]
        A, B, C, D, Dd, S = self._split(mats + [None, None] * self._affine)
        return BatchStateSpace(A, B, C, D, *names, arr, self._model.name, Dd, S)


def _reduced_form(model: StateEquations) -> tuple[list, list[str]]:
    """Sparse symbolic ``A, B, C, D, D_derivatives..., state_shift...`` and their labels.

    ``x' = A x + sum_k B_k u^(k)``, ``y = C x + sum_k D_k u^(k)`` (``K`` the
    highest order): ``S_{K-1} = B_K``, ``S_j = B_{j+1} + A S_{j+1}``;
    ``B = B0 + A S_0``, ``D_j' = D_j + C S_j`` (see the module docstring).
    """
    A, Bs, C, Ds = derivative_form(model)
    K = len(Bs) - 1
    if K == 0:
        return [A, Bs[0], C, Ds[0]], ["A", "B", "C", "D"]
    S: list = [None] * K
    S[K - 1] = Bs[K]
    for j in range(K - 2, -1, -1):
        S[j] = Bs[j + 1] + A * S[j + 1]
    B = Bs[0] + A * S[0]
    D = [Ds[j] + C * S[j] for j in range(K)] + [Ds[K]]
    mats = [A, B, C, D[0]] + D[1:] + S
    labels = (["A", "B", "C", "D"] + [f"D_derivatives[{k}]" for k in range(K)]
              + [f"state_shift[{k}]" for k in range(K)])
    return [sympy.ImmutableSparseMatrix(M) for M in mats], labels


def _scaled_solve(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``A^-1 b`` with ``A`` equilibrated by rows and columns first (units of 1e-14 and 1e7
    side by side, and no rounding residue where the answer is 0)."""
    from ..linear.trim import equilibrate

    r, c = equilibrate(A)
    return c * np.linalg.solve(A * r[:, None] * c[None, :], r * b)


def _offset_form(model: StateEquations, exc: NonlinearModelError) -> tuple[list, list[str]]:
    """``A, B, C, D, c, d`` of a model linear but for constant terms (constant sources),
    else ``exc`` with the way to its plant about an operating point."""
    from ..linear.forms import linear_form

    try:
        if model.input_derivatives:
            raise exc
        A, B, c = linear_form(model.rhs, model.states, model.inputs, model, "state equation",
                              "x'", offsets=True)
        C, D, d = linear_form(model.output_exprs, model.states, model.inputs, model, "output",
                              "y", offsets=True)
    except NonlinearModelError:
        raise NonlinearModelError(
            f"{exc}; its plant about an operating point is model.linearize(values=..., "
            "u0={...}) (the equilibrium is found there)") from None
    return [A, B, C, D, c, d], ["A", "B", "C", "D", "c (constant terms of x')",
                                "d (constant terms of y)"]


def _definite_checks(model: StateEquations, params: Sequence[sympy.Symbol]) -> tuple:
    """``(element, compiled entries, n)`` of every element with a symbolic matrix that must
    be positive (semi-)definite (the multiport fields: ``matrix`` and ``definite``)."""
    found = []
    swap = dummies = None
    for el in (model.augmented.flat.elements if model.augmented is not None else ()):
        M = getattr(el, "matrix", None)
        if M is None or not hasattr(el, "definite") or not M.free_symbols:
            continue
        if dummies is None:
            dummies = placeholders("p", len(params))
            swap = dict(zip(params, dummies))
        found.append((el, CompiledFunction(dummies, [e.xreplace(swap) for e in M]), M.rows))
    return tuple(found)


def _entries(M: sympy.ImmutableSparseMatrix) -> dict:
    """``{(i, j): entry}`` of the nonzero entries (``M.todok()``, read straight from the
    sparse domain matrix when its domain holds plain expressions: 10x faster)."""
    rep = getattr(M, "_rep", None)
    if rep is not None and str(rep.domain) == "EXRAW" and isinstance(getattr(rep, "rep", None), dict):
        return {(i, j): v for i, row in rep.rep.items() for j, v in row.items()}   # no zeros
    return M.todok()


def _has_symbol_factor(ex: sympy.Expr) -> bool:
    """A cheap sufficient test that ``ex`` is not constant: a symbol, or a product or sum
    with a symbol (or a power of one) among its arguments."""
    if ex.is_Symbol:
        return True
    if ex.is_Mul or ex.is_Add:
        return any(a.is_Symbol or (a.is_Pow and a.base.is_Symbol) for a in ex.args)
    return False


def _elements_using(model: StateEquations, names: Sequence[str]) -> str:
    """``"I:La (La = 0)"`` for the elements whose parameters use one of ``names``."""
    found = []
    for el in (model.augmented.flat.elements if model.augmented is not None else ()):
        hit = sorted({sym.name for sym in parameter_symbols(el)} & set(names))
        if hit:
            found.append(f"{el.label()} ({', '.join(f'{h} = 0' for h in hit)})")
    return ", ".join(found)


def zero_parameters(model: StateEquations, names: Sequence[str], values) -> str:
    """``"; I:J (J = 0) has a parameter that is zero"`` for a failure message, or ``""``."""
    zeros = [n for n, v in zip(names, values) if v == 0]
    culprits = _elements_using(model, zeros) if zeros else ""
    return f"; {culprits} has a parameter that is zero" if culprits else ""


def _real_constant(ex: sympy.Expr, label: str, i: int, j: int, name: str) -> float:
    value = complex(ex)
    if value.imag != 0:
        raise NumericError(f"model {name!r}: matrix {label} entry ({i}, {j}) = {ex} is not real")
    return value.real


def compile_plant(model: StateEquations, *, sparse: Optional[bool] = None) -> NumericModel:
    """Compile a linear model's ``A, B, C, D`` once; see :class:`NumericModel`.

    Parameters
    ----------
    model : StateEquations
        A linear model (from :func:`bondgraph.derive`).
    sparse : bool, optional
        Whether its plants are sparse by default (None: when the model has
        more than :data:`~bondgraph.numeric.sparse.SPARSE_THRESHOLD` states).

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
    return NumericModel(model, sparse=sparse)


def numeric_plant(model: StateEquations, values: ParameterValues) -> NumericStateSpace:
    """One-off numeric plant: ``compile_plant(model).plant(values)``.

    Parameters
    ----------
    model : StateEquations
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
