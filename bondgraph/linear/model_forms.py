"""Linear forms of derived equations: state space, descriptor form, Laplace systems,
transfer functions, symbolic linearization.

Each function reads a :class:`~bondgraph.equations.StateEquations` record (a
:class:`bondgraph.Model` is one) and is what the model's method of the same
name calls.  Results that are computed once per model (the state space, the
descriptor form) are cached on the record.

Examples
--------
>>> from bondgraph import examples
>>> from bondgraph.equations import derive_equations
>>> from bondgraph.linear import state_space
>>> ss = state_space(derive_equations(examples.rc()))
>>> ss.A, ss.B
(Matrix([[-1/(C*R)]]), Matrix([[1/R]]))
"""

from __future__ import annotations

import contextlib
import dataclasses
from typing import Any, Mapping

import sympy
from sympy.solvers.solveset import NonlinearError

from ..equations import StateEquations
from ..errors import NonlinearModelError
from ..signals import t as T_SYM
from ..tf import transfer_function as tf_transfer_function
from ..tf import transfer_matrix as tf_transfer_matrix
from ..tf import resolve_signal
from ..tf.errors import TermBudgetError
from .forms import derivative_orders, linear_form, point_values, refuse_implicit, residual
from .conserved import unify, where
from .offsets import SYMBOLIC_MAX_STATES, _TooLarge, nominal_inputs, symbolic_operating_point
from .point import OperatingPoint, OperatingPointError
from .statespace import SymbolicStateSpace

__all__ = ["state_space", "is_linear", "descriptor_form", "laplace_system", "derivative_form",
           "transfer_function", "transfer_matrix", "linearize", "deviations"]


def state_space(eqs: StateEquations, *, at=None) -> SymbolicStateSpace:
    """A, B, C, D of linear equations (sympy ImmutableMatrix), with names; cached.

    A model with constant sources, or linear in its states but not in its
    inputs, gives its form in deviations about the operating point (see
    :func:`bondgraph.linear.deviations`; ``at`` chooses the point) and
    says which in ``operating_point``.

    Raises
    ------
    NonlinearModelError
        If an equation is not linear in the states (without ``at``), depends
        on time or on input derivatives.
    """
    if at is not None:
        dev, op = deviations(eqs, at)
        return dataclasses.replace(_strict_state_space(dev), operating_point=op)
    if "state_space" not in eqs._cache:
        try:
            eqs._cache["state_space"] = _strict_state_space(eqs)
        except NonlinearModelError as exc:
            dev, op = _automatic(eqs, exc)
            eqs._cache["state_space"] = dataclasses.replace(_strict_state_space(dev),
                                                            operating_point=op)
    return eqs._cache["state_space"]


def _strict_state_space(eqs: StateEquations) -> SymbolicStateSpace:
    x, u = eqs.states, eqs.inputs
    A, B = linear_form(eqs.rhs, x, u, eqs, "state equation", "x'")
    C, D = linear_form(eqs.output_exprs, x, u, eqs, "output", "y")
    return SymbolicStateSpace(A, B, C, D, eqs.state_names, eqs.input_names, eqs.output_names,
                              known_parameters=eqs.known_parameters,
                              value_checks=_rule_elements(eqs))


def _rule_elements(eqs: StateEquations) -> tuple:
    """The elements whose parameters have rules (:meth:`bondgraph.Element.value_rules`):
    a symbolic form checks them when it is given values."""
    augmented = getattr(eqs, "augmented", None)
    return () if augmented is None else tuple(el for el in augmented.flat.elements
                                              if el.value_rules())


def _automatic(eqs: StateEquations, exc: NonlinearModelError):
    """The deviation record and point of a model whose state equations are linear in the
    states at the nominal inputs (one equilibrium), else ``exc`` re-raised with a hint."""
    if eqs.algebraic or eqs.input_derivatives or any(T_SYM in r.free_symbols
                                                     for r in eqs.rhs + eqs.output_exprs):
        raise exc
    u0 = nominal_inputs(eqs)
    at_u0 = [r.xreplace(u0) for r in eqs.rhs]
    try:
        M, b = sympy.linear_eq_to_matrix(at_u0, list(eqs.states))
        affine = not (M.free_symbols | b.free_symbols) & set(eqs.states)
    except (NonlinearError, ValueError):
        affine = False
    if not affine:
        raise NonlinearModelError(
            f"{exc}; or linearize about an operating point: give it with at={{input: value, "
            "state: value, ...}} (states not given are solved) or take "
            "model.linearize(model.equilibrium(values, inputs))") from None
    try:
        return deviations(eqs, u0)
    except OperatingPointError as err:
        raise NonlinearModelError(f"{exc}; about the operating point instead: {err}") from None


def is_linear(eqs: StateEquations) -> bool:
    """Whether ``rhs`` and outputs are linear in states and inputs (no constant term)."""
    if "state_space" in eqs._cache:
        return eqs._cache["state_space"].operating_point is None
    try:
        eqs._cache["state_space"] = _strict_state_space(eqs)
    except NonlinearModelError:
        return False
    return True


def laplace_system(eqs: StateEquations, descriptor: bool, s: sympy.Symbol, outputs=None):
    """``A, B(s), C, D(s), E`` of the Laplace-transformed equations.

    Input derivatives enter as powers of ``s`` (zero initial conditions):
    ``x' = A x + B0 u + B1 u'`` gives ``B(s) = B0 + s B1``, likewise for
    ``D``.  ``outputs``: indices of the outputs to linearize (default all).
    """
    x, u = eqs.states, eqs.inputs
    ud = eqs.input_derivatives
    orders = derivative_orders(eqs) if ud else {}
    outs = range(len(eqs.output_exprs)) if outputs is None else outputs
    out_exprs = [eqs.output_exprs[i] for i in outs]
    if descriptor and eqs.descriptor is not None:
        E, F = eqs.descriptor
        if E.free_symbols & (set(x) | set(u) | set(ud)):
            raise NonlinearModelError(f"model {eqs.name!r}: E depends on the states")
        A, B, B1 = linear_form(F, x, u, eqs, "state equation", "F", ud)
    else:
        E = None
        A, B, B1 = linear_form(eqs.rhs, x, u, eqs, "state equation", "x'", ud)
    C, D, D1 = linear_form(out_exprs, x, u, eqs, "output", "y", ud)

    def with_s(M0, M1):
        if not ud:
            return M0
        M = sympy.Matrix(M0)
        for (i, k), c in M1.todok().items():
            j, order = orders[ud[k]]
            M[i, j] += c * s**order
        return sympy.ImmutableMatrix(M)
    return A, with_s(B, B1), C, with_s(D, D1), E


def derivative_form(eqs: StateEquations):
    """``A, (B0, B1, ..), C, (D0, D1, ..)`` of the explicit equations
    ``x' = A x + sum_k B_k u^(k)``, ``y = C x + sum_k D_k u^(k)``.

    Without input derivatives the tuples have one matrix (:func:`state_space`).
    """
    x, u, ud = eqs.states, eqs.inputs, eqs.input_derivatives
    if not ud:
        ss = state_space(eqs)
        if ss.operating_point is not None:      # in deviations: not the model's own form
            ss = _strict_state_space(eqs)        # raises, naming the constant term
        return ss.A, (ss.B,), ss.C, (ss.D,)
    orders = derivative_orders(eqs)
    A, B, B1 = linear_form(eqs.rhs, x, u, eqs, "state equation", "x'", ud)
    C, D, D1 = linear_form(eqs.output_exprs, x, u, eqs, "output", "y", ud)
    top = max(k for _, k in orders.values())

    def split(M0, M1):
        mats = [M0] + [sympy.zeros(*M0.shape) for _ in range(top)]
        for (i, c), val in M1.todok().items():
            j, k = orders[ud[c]]
            mats[k][i, j] += val
        return (M0,) + tuple(sympy.ImmutableSparseMatrix(M) for M in mats[1:])
    return A, split(B, B1), C, split(D, D1)


@contextlib.contextmanager
def _memory_named(eqs: StateEquations, states: int):
    """A ``MemoryError`` while expanding a symbolic transfer function becomes a
    :class:`~bondgraph.tf.TermBudgetError` saying what to do."""
    try:
        yield
    except MemoryError:
        raise TermBudgetError(
            f"model {eqs.name!r}: its symbolic transfer function ({states} states, "
            f"{len(eqs.parameters)} symbolic parameters) does not fit in memory; pass "
            "max_terms= to refuse before expanding, give numbers for some parameters, or use "
            "the numeric plant (compile_plant(model).plant(values))") from None


def transfer_function(eqs: StateEquations, input=None, output=None, *,
                      descriptor: bool | None = None, at=None, **options):
    """Symbolic ``G(s)`` from one input to one output (see :meth:`bondgraph.Model.transfer_function`).

    A model with constant sources (or nonlinear in its inputs) gives ``G`` in
    deviations about its operating point, held in ``G.operating_point``.
    """
    if at is not None:
        dev, op = deviations(eqs, at)
        return transfer_function(dev, input, output, descriptor=False,
                                 **options)._with_metadata(operating_point=op)
    use_e = eqs.descriptor is not None if descriptor is None else descriptor
    s = options.pop("s", None) or sympy.Symbol("s")
    i = resolve_signal(output, eqs.output_names, "output")
    try:
        A, B, C, D, E = laplace_system(eqs, use_e, s, [i])
    except NonlinearModelError as exc:
        dev, op = _automatic(eqs, exc)
        return transfer_function(dev, input, output, descriptor=False, s=s,
                                 **options)._with_metadata(operating_point=op)
    with _memory_named(eqs, A.rows):
        G = tf_transfer_function(A, B, C, D, E=E, input=input, output=0,
                                 input_names=eqs.input_names,
                                 output_names=(eqs.output_names[i],), s=s, **options)
    augmented = getattr(eqs, "augmented", None)
    fields = () if augmented is None else tuple(       # fields (definite) and elements' rules
        el for el in augmented.flat.elements
        if (getattr(el, "matrix", None) is not None and hasattr(el, "check_values"))
        or el.value_rules())
    return G._with_metadata(known_parameters=eqs.known_parameters, value_checks=fields)


def transfer_matrix(eqs: StateEquations, *, at=None, **options):
    """All transfer functions over one denominator (see :meth:`bondgraph.Model.transfer_matrix`);
    in deviations about the operating point for a model with constant sources."""
    if at is not None:
        dev, op = deviations(eqs, at)
        return dataclasses.replace(transfer_matrix(dev, **options), operating_point=op)
    s = options.pop("s", None) or sympy.Symbol("s")
    try:
        A, B, C, D, E = laplace_system(eqs, eqs.descriptor is not None, s)
    except NonlinearModelError as exc:
        dev, op = _automatic(eqs, exc)
        return dataclasses.replace(transfer_matrix(dev, s=s, **options), operating_point=op)
    with _memory_named(eqs, A.rows):
        G = tf_transfer_matrix(A, B, C, D, E=E, input_names=eqs.input_names,
                               output_names=eqs.output_names, s=s, **options)
    return dataclasses.replace(G, known_parameters=eqs.known_parameters)


def descriptor_form(eqs: StateEquations) -> SymbolicStateSpace:
    """``E x' = A x + B u`` as derived, before eliminating dependent storage; cached.

    Without derivative causality ``E`` is the identity.
    """
    if "descriptor_form" not in eqs._cache:
        eqs._cache["descriptor_form"] = _descriptor_form(eqs)
    return eqs._cache["descriptor_form"]


def _descriptor_form(eqs: StateEquations) -> SymbolicStateSpace:
    if eqs.descriptor is None:
        ss = state_space(eqs)
        return SymbolicStateSpace(ss.A, ss.B, ss.C, ss.D, ss.state_names,
                                  ss.input_names, ss.output_names,
                                  sympy.ImmutableMatrix(sympy.eye(len(eqs.states))),
                                  known_parameters=eqs.known_parameters,
                                  value_checks=ss.value_checks,
                                  operating_point=ss.operating_point)
    E, F = eqs.descriptor
    x, u = eqs.states, eqs.inputs
    A, B = linear_form(F, x, u, eqs, "state equation", "F")
    C, D = linear_form(eqs.output_exprs, x, u, eqs, "output", "y")
    if E.free_symbols & (set(x) | set(u)):
        raise NonlinearModelError(f"model {eqs.name!r}: E depends on the states")
    return SymbolicStateSpace(A, B, C, D, eqs.state_names, eqs.input_names,
                              eqs.output_names, E, known_parameters=eqs.known_parameters,
                              value_checks=_rule_elements(eqs))


def linearize(eqs: StateEquations, x0=None, u0=None, *, equilibrium: bool = True,
              tol: float = 1e-9) -> SymbolicStateSpace:
    """Symbolic Jacobians about ``(x0, u0)`` (see :meth:`bondgraph.Model.linearize`).

    Without ``x0`` the states are the equilibrium at ``u0`` solved exactly
    (:func:`bondgraph.linear.offsets.symbolic_operating_point`; inputs not in
    ``u0`` are the symbols ``<input>0``).  The result's ``operating_point``
    holds ``x0``, ``u0`` and ``y0``.
    """
    refuse_implicit(eqs, "symbolic linearization")
    x, u = eqs.states, eqs.inputs
    if x0 is None:
        op = symbolic_operating_point(eqs, u0)
        x0, u0 = dict(op.states), dict(op.inputs)
    point = {**point_values(eqs, x0, x, "state"), **point_values(eqs, u0, u, "input")}
    point = {k: unify(v, eqs) for k, v in point.items()}
    bad = set(eqs.input_derivatives) | {T_SYM}
    for ex in eqs.rhs + tuple(o.xreplace(dict.fromkeys(eqs.input_derivatives, 0))
                              for o in eqs.output_exprs):
        if ex.free_symbols & bad:
            raise NonlinearModelError(
                f"model {eqs.name!r} depends on {', '.join(map(str, ex.free_symbols & bad))}; "
                "it cannot be linearized to a constant (A, B)")
    if equilibrium:
        if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not tol >= 0:
            raise NonlinearModelError(f"tol: expected a number >= 0, got {tol!r}")
        for s_, r in zip(x, eqs.rhs):
            val = residual(r, point, tol)
            if val is not None:
                raise NonlinearModelError(
                    f"model {eqs.name!r}: the operating point is not an equilibrium: "
                    f"d{s_.name}/dt = {val} there (tol={tol:g}); pass equilibrium=False "
                    "to linearize about a non-equilibrium point")

    from .operating import output_derivative_feedthrough

    point.update(dict.fromkeys(eqs.input_derivatives, sympy.S.Zero))   # u constant there

    def d(ex, v):
        # sign(g)' stays an unevaluated Derivative when sympy cannot tell g is real; it is
        # 2 DiracDelta(g) g', 0 away from the jump (a Derivative cannot take a number)
        return sympy.diff(ex, v).replace(
            lambda a: isinstance(a, sympy.Derivative) and isinstance(a.expr, sympy.sign),
            lambda a: sympy.S.Zero)

    def jac(exprs, wrt):
        return sympy.ImmutableMatrix(len(exprs), len(wrt), lambda i, j: sympy.simplify(
            d(exprs[i], wrt[j]).xreplace(point)))
    y0 = {n: sympy.simplify(y.xreplace(point)) for n, y in zip(eqs.output_names, eqs.output_exprs)}
    op = OperatingPoint({s_.name: point[s_] for s_ in x}, {v.name: point[v] for v in u}, y0,
                        how="given" if equilibrium else "given (not checked as an "
                        "equilibrium)")
    return SymbolicStateSpace(jac(eqs.rhs, x), jac(eqs.rhs, u), jac(eqs.output_exprs, x),
                              jac(eqs.output_exprs, u), eqs.state_names, eqs.input_names,
                              eqs.output_names, known_parameters=eqs.known_parameters,
                              D_derivatives=output_derivative_feedthrough(eqs, jac),
                              value_checks=_rule_elements(eqs),
                              operating_point=op)


def deviations(eqs: "StateEquations", at: Any = None) -> tuple["StateEquations", OperatingPoint]:
    """The record in deviation variables about an operating point, and the point.

    Parameters
    ----------
    eqs : StateEquations
    at : OperatingPoint, mapping or None
        The point: an :class:`OperatingPoint`; a mapping of input values and,
        optionally, state values (``{"d": d0, "Vg": Vg0}``; states not given are
        solved, see :func:`symbolic_operating_point`); None for the symbolic point
        at the nominal inputs ``<input>0``.

    Returns
    -------
    (StateEquations, OperatingPoint)
        A record with the same names whose ``rhs`` and outputs are linear:
        ``A dx + B du`` with ``A = df/dx`` and ``B = df/du`` at the point (its
        symbols stand for the deviations).

    Raises
    ------
    OperatingPointError
        See :func:`symbolic_operating_point`; also a given point that is not an
        equilibrium.
    """
    given_states = True          # a point given (not solved here) is checked
    if isinstance(at, OperatingPoint):
        op = at
    elif hasattr(at, "states") and hasattr(at, "values") and hasattr(at, "stability"):
        raise OperatingPointError(
            f"{where(eqs)}a numeric Equilibrium holds parameter values: take the plant there "
            "with model.linearize(eq) (numeric), or give the symbolic point as a mapping")
    else:
        if at is not None and not isinstance(at, Mapping):
            raise OperatingPointError(
                f"{where(eqs)}at: expected an OperatingPoint or a mapping of input (and state) "
                f"names to values, got {type(at).__name__}")
        given = dict(at or {})
        names = {s.name for s in eqs.states}
        keyname = (lambda k: k.name if isinstance(k, sympy.Symbol) else k)   # noqa: E731
        xs = {k: v for k, v in given.items() if keyname(k) in names}
        us = {k: v for k, v in given.items() if keyname(k) not in names}
        given_states = bool(xs)
        try:
            op = symbolic_operating_point(eqs, us, states=xs or None)
        except _TooLarge:
            op = None       # a constant-source model keeps its matrices about any point
    if op is None:
        try:
            linear_form(eqs.rhs, eqs.states, eqs.inputs, eqs, "state equation", "x'",
                        offsets=True)
        except NonlinearModelError:
            raise _TooLarge(f"{where(eqs)}{len(eqs.states)} states: the symbolic operating "
                            f"point is not solved above {SYMBOLIC_MAX_STATES} states; give "
                            "parameter values for a numeric one, or the point's states "
                            "(at={state: value, ...})") from None
        u0 = nominal_inputs(eqs, us)
        return _linear_part(eqs), OperatingPoint(
            {}, {u.name: v for u, v in u0.items()}, {},
            how=f"x0 not solved symbolically ({len(eqs.states)} states > "
                f"{SYMBOLIC_MAX_STATES}): the matrices are the same about every equilibrium; "
                "model.operating_point(inputs, values=...) gives the numeric point")
    by_name = {s.name: s for s in eqs.states + eqs.inputs}
    point = {by_name[k]: sympy.sympify(v, strict=True) for k, v in {**op.states, **op.inputs}.items()
             if k in by_name}
    point.update(dict.fromkeys(eqs.input_derivatives, sympy.S.Zero))
    for s, r in zip(eqs.states, eqs.rhs if given_states else ()):
        val = residual(r, point, 1e-9)
        if val is not None:
            raise OperatingPointError(
                f"{where(eqs)}the operating point is not an equilibrium: d{s.name}/dt = {val} "
                "there")
    affine = True
    try:
        A, B, _c = linear_form(eqs.rhs, eqs.states, eqs.inputs, eqs, "state equation", "x'",
                               offsets=True)
        C, D, _d = linear_form(eqs.output_exprs, eqs.states, eqs.inputs, eqs, "output", "y",
                               offsets=True)
    except NonlinearModelError:
        affine = False
    if not affine:
        lin = linearize(eqs, {s.name: point[s] for s in eqs.states},
                        {u.name: point[u] for u in eqs.inputs}, equilibrium=False)
        A, B, C, D = lin.A, lin.B, lin.C, lin.D
    x = sympy.Matrix(len(eqs.states), 1, list(eqs.states))
    u = sympy.Matrix(len(eqs.inputs), 1, list(eqs.inputs))

    def lin_rows(M, N):
        return tuple(sympy.expand(e) if not affine else e for e in (M * x + N * u))
    dev = dataclasses.replace(eqs, rhs=lin_rows(A, B), output_exprs=lin_rows(C, D),
                              input_derivatives=(), descriptor=None)
    return dev, op


def _linear_part(eqs: "StateEquations") -> "StateEquations":
    """The record of ``A x + B u`` of a model linear but for its constant terms."""
    A, B, _ = linear_form(eqs.rhs, eqs.states, eqs.inputs, eqs, "state equation", "x'",
                          offsets=True)
    C, D, _ = linear_form(eqs.output_exprs, eqs.states, eqs.inputs, eqs, "output", "y",
                          offsets=True)
    x = sympy.Matrix(len(eqs.states), 1, list(eqs.states))
    u = sympy.Matrix(len(eqs.inputs), 1, list(eqs.inputs))
    return dataclasses.replace(eqs, rhs=tuple(A * x + B * u), output_exprs=tuple(C * x + D * u),
                               input_derivatives=(), descriptor=None)
