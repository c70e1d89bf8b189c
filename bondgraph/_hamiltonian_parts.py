"""The pieces of :mod:`bondgraph.hamiltonian`: element checks, stored energy,
collocated outputs, the coefficient matrices and the final symbolic check."""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Optional, Sequence

import sympy

from .elements import OnePort, TwoPort
from .errors import BondGraphWarning, LawError, NonlinearModelError
from .model import Model
from .signals import Signal, displacement, effort, flow, momentum
from .signals import t as T_SYM

if TYPE_CHECKING:
    from .hamiltonian import PortHamiltonian

__all__ = ["PortHamiltonianError"]

Matrix = sympy.ImmutableMatrix   # constructor shorthand; annotations spell it out


class PortHamiltonianError(NonlinearModelError):
    """A model has no port-Hamiltonian form (or no energy) that bondgraph can give.

    The message names the element at fault and says why.
    """



def _col(entries: Sequence) -> sympy.ImmutableMatrix:
    """A column (``n x 1`` also for ``n = 0``)."""
    return Matrix(len(entries), 1, list(entries))


# ===================================================================== checks
def _check_elements(model: Model) -> None:
    """Refuse, naming the element, what has no constant (J, R, G) form."""
    aug = model.augmented
    for el in aug.flat.elements:
        label = el.label()
        if isinstance(el, TwoPort) and el.modulated:
            raise PortHamiltonianError(
                f"{label}: a modulated {el.kind[1:]} (modulus {el.modulus}) makes J depend on "
                "the state or time; the port-Hamiltonian form needs constant-modulus TF and GY")
        if el.kind in ("Se", "Sf") and getattr(el, "value", None) is not None:
            value = getattr(el, "value")
            why = ("a modulated source (feedback written in the graph) is not a port"
                   if getattr(el, "modulated", False) else
                   "a prescribed (constant or time-dependent) value is not a port")
            raise PortHamiltonianError(
                f"{label}: value={value}: {why}; the port-Hamiltonian form needs every "
                "source as an input (give the source no value)")
        if isinstance(el, OnePort):
            _check_law(el, el.name in aug.derivative)


def _check_law(el: OnePort, dependent: bool) -> None:
    label = el.label()
    dyn = sorted(str(s) for s in _dynamic(el.law, el.inverse, el.parameter))
    if dyn:
        raise PortHamiltonianError(
            f"{label}: its law uses {', '.join(dyn)} (a modulated element); the "
            "port-Hamiltonian form needs laws of the element's own variable only")
    if el.kind == "R" and not _linear_law(el):
        law = el.law if el.law is not None else el.inverse
        raise PortHamiltonianError(
            f"{label}: the nonlinear law {law} makes the dissipation depend on the state; "
            "the port-Hamiltonian form needs linear R elements (linearize the model first)")
    if el.kind in ("I", "C") and dependent and not _linear_law(el):
        raise PortHamiltonianError(
            f"{label} is in derivative causality with the nonlinear law "
            f"{el.law if el.law is not None else el.inverse}; the reduced form needs linear "
            "storage there (make it compliant, or linear)")


def _dynamic(*exprs) -> set:
    out: set = set()
    for ex in exprs:
        if isinstance(ex, sympy.Basic):
            out |= {s for s in ex.free_symbols if isinstance(s, Signal) or s == T_SYM}
    return out


def _linear_law(el: OnePort) -> bool:
    """Whether the element's law is ``c * own`` (and its inverse ``own / c``)."""
    if el.parameter is not None:
        return True
    for law, var in ((el.law, el.own), (el.inverse, el.inverse_own)):
        if isinstance(law, sympy.Expr):     # laws are expressions once the element is built
            if sympy.simplify(sympy.diff(law, var, 2)) != 0 or \
                    sympy.simplify(law.xreplace({var: 0})) != 0:
                return False
    return True


def _nonconservative(model: Model) -> tuple[str, ...]:
    return tuple(el.label() for el in model.augmented.flat.elements
                 if isinstance(el, TwoPort) and el.efficiency != 1)


def _input_derivative_error(model: Model, derived: Model) -> None:
    names = {f"d{u.name}/dt": u.name for u in derived.inputs}
    srcs = [names.get(s.name, s.name) for s in derived.input_derivatives]
    labels = [model.augmented.flat.element(n).label() for n in srcs
              if n in model.augmented.flat.index]
    raise PortHamiltonianError(
        f"{', '.join(labels or srcs)}: the derivative of this input enters the equations "
        "(the source drives a storage element in derivative causality, so the stored "
        "energy depends on the input); such a source is not a port of a port-Hamiltonian "
        "system")


# ===================================================================== energy
def _storage(model: Model, *, linear_dependent: bool
             ) -> tuple[list[tuple[sympy.Symbol, OnePort]], list[OnePort]]:
    """``([(state, element)] in integral causality, [element] in derivative causality)``."""
    aug = model.augmented
    by_name = {s.name: s for s in model.states[:model.storage_states]}
    storage: list[tuple[sympy.Symbol, OnePort]] = []
    dependent: list[OnePort] = []
    for el in aug.flat.elements:
        if not isinstance(el, OnePort) or el.kind not in ("I", "C"):
            continue
        dyn = sorted(str(s) for s in _dynamic(el.law, el.inverse, el.parameter))
        if dyn:
            raise PortHamiltonianError(
                f"{el.label()}: its law uses {', '.join(dyn)}; the stored energy of a "
                "modulated storage element is not a function of the state alone")
        if el.name in aug.derivative:
            if linear_dependent:
                _check_law(el, True)
            dependent.append(el)
            continue
        name = ("p_" if el.kind == "I" else "q_") + el.name
        if name not in by_name:
            raise PortHamiltonianError(
                f"{el.label()}: model {model.name!r} has no state {name!r} for it "
                f"(states: {', '.join(model.state_names)})")
        storage.append((by_name[name], el))
    if len(storage) != model.storage_states:
        raise PortHamiltonianError(
            f"model {model.name!r}: {model.storage_states} storage states but "
            f"{len(storage)} storage elements in integral causality")
    return storage, dependent


def _stored_signals(dependent: Sequence[OnePort]) -> dict[str, sympy.Expr]:
    """Output signals for the momentum / displacement of each dependent element."""
    return {f"s{i}": (momentum if el.kind == "I" else displacement)(el.name)
            for i, el in enumerate(dependent)}


def _stored(storage, dependent, aux: Optional[Model]) -> list[tuple[sympy.Expr, OnePort]]:
    """``[(stored quantity, element)]``: the state, or (derivative causality) the
    momentum or displacement in the states, read from the outputs of ``aux``."""
    stored: list[tuple[sympy.Expr, OnePort]] = [(sym, el) for sym, el in storage]
    if not dependent:
        return stored
    assert aux is not None
    out = dict(zip(aux.output_names, aux.output_exprs))
    bad = set(aux.inputs) | set(aux.input_derivatives) | {T_SYM}
    for name, el in zip(_stored_signals(dependent), dependent):
        expr = out[name]
        if expr.free_symbols & bad:
            which = ", ".join(sorted(str(s) for s in expr.free_symbols & bad))
            raise PortHamiltonianError(
                f"{el.label()} is in derivative causality and its "
                f"{'momentum' if el.kind == 'I' else 'displacement'} {expr} depends on "
                f"{which}: a source fixes its {'flow' if el.kind == 'I' else 'effort'}, so its "
                "stored energy is not a function of the state and the source's power "
                "needs the input's derivative; such a source is not a port of a "
                "port-Hamiltonian system")
        stored.append((expr, el))
    return stored


def _energy(stored: Sequence[tuple[sympy.Expr, OnePort]]) -> sympy.Expr:
    total = sympy.Integer(0)
    for quantity, el in stored:
        total += _element_energy(el, quantity)
    return total


def _element_energy(el: OnePort, quantity: sympy.Expr) -> sympy.Expr:
    """``int_0^quantity phi(s) ds`` of the element's law ``phi`` (flow of p, effort of q)."""
    try:
        law = el.forward()
    except LawError as exc:    # an inverse-only law that sympy cannot invert
        raise PortHamiltonianError(
            f"{el.label()}: its stored energy needs the {el.law_name} law as a function of "
            f"{el.own}: {exc}") from exc
    s = sympy.Dummy("s", real=True)
    phi = law.xreplace({el.own: s})
    if el.parameter is not None:       # linear: phi = s/parameter, the familiar form
        return quantity**2 / (2 * el.parameter)
    H = sympy.integrate(phi, (s, 0, quantity))
    if H.has(sympy.Integral):
        raise PortHamiltonianError(
            f"{el.label()}: sympy cannot integrate its law {law} to the stored energy "
            f"int_0^{el.own} ({law}) d{el.own}")
    return H


# ===================================================================== coefficients
def _collocated(model: Model) -> tuple[dict[str, sympy.Expr], tuple[str, ...]]:
    """Output signals power-conjugate to each input, and their names."""
    flat = model.augmented.flat
    ports: dict[str, sympy.Expr] = {}
    names: list[str] = []
    for i, u in enumerate(model.inputs):
        el = flat.element(u.name)
        if el.kind == "Se":          # flow out of the source: -(flow into it)
            ports[f"y{i}"] = -flow(el.name)
            names.append(f"f_{el.name}")
        else:                        # the effort at a flow source
            ports[f"y{i}"] = effort(el.name)
            names.append(f"e_{el.name}")
    return ports, tuple(names)


def _rederive(model: Model, outputs: dict[str, sympy.Expr]) -> Model:
    """``derive`` on the model's own augmented graph (same causality, same states)."""
    from .equations import derive

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BondGraphWarning)   # the model warned already
        return derive(model.augmented, outputs=outputs or None)


def _inverse(Q: sympy.ImmutableMatrix, model: Model) -> sympy.ImmutableMatrix:
    if Q.is_diagonal():
        if any(Q[i, i] == 0 for i in range(Q.rows)):
            k = next(i for i in range(Q.rows) if Q[i, i] == 0)
            raise PortHamiltonianError(
                f"model {model.name!r}: the stored energy does not depend on the state "
                f"{model.state_names[k]}")
        return Matrix.diag(*[1 / Q[i, i] for i in range(Q.rows)]) if Q.rows else Q
    if sympy.simplify(Q.det()) == 0:
        raise PortHamiltonianError(
            f"model {model.name!r}: the stored energy is a singular quadratic form of the states")
    return Matrix(Q.inv(method="LU"))


def _cancel(M) -> sympy.ImmutableMatrix:
    """Entries as one reduced fraction, factored when small (big ones: common factors only)."""
    def tidy(expr: sympy.Expr) -> sympy.Expr:
        expr = sympy.cancel(sympy.together(expr))
        return sympy.factor(expr) if sympy.count_ops(expr) <= 80 else sympy.factor_terms(expr)
    return Matrix(M.rows, M.cols, lambda i, j: tidy(M[i, j]))


def _input_matrix(exprs, u, x, model: Model, what: str) -> sympy.ImmutableMatrix:
    M = Matrix(len(exprs), len(u), lambda i, j: sympy.cancel(sympy.diff(exprs[i], u[j])))
    _constant(M, set(x) | set(u), model, what, "inputs")
    return M


def _coefficients(exprs, x, hess, model: Model, what: str) -> sympy.ImmutableMatrix:
    """``(d exprs / dx) diag(1/phi'(x))`` for nonlinear storage in integral causality."""
    if not hess.is_diagonal():
        raise PortHamiltonianError(
            f"model {model.name!r}: nonlinear storage with coupled energy "
            "(derivative causality) is not supported")
    M = Matrix(len(exprs), len(x), lambda i, j: sympy.cancel(
        sympy.diff(exprs[i], x[j]) / hess[j, j]))
    _constant(M, set(x), model, what, "co-energy variables grad H")
    return M


def _constant(M: sympy.ImmutableMatrix, variables: set, model: Model, what: str, wrt: str) -> None:
    for (i, j), val in M.todok().items():
        if val.free_symbols & (variables | {T_SYM}):
            raise PortHamiltonianError(
                f"model {model.name!r}: {what} {i + 1} is not linear in the {wrt} "
                f"(coefficient {val}); the port-Hamiltonian form needs linear R elements "
                "and constant moduli")


def _verify(ph: PortHamiltonian, model: Model) -> None:
    """The rebuilt ``x'`` must equal the model's storage ``rhs`` exactly."""
    n = len(ph.states)
    for i, (got, want) in enumerate(zip(ph.rhs(), model.rhs[:n])):
        extra = want.free_symbols & set(model.states[n:])
        if extra:
            raise PortHamiltonianError(
                f"model {model.name!r}: d{ph.states[i].name}/dt depends on the integrator "
                f"state(s) {', '.join(sorted(s.name for s in extra))}, which store no energy")
        diff = sympy.cancel(sympy.together(got - want))
        if diff != 0 and sympy.simplify(diff) != 0:
            raise PortHamiltonianError(
                f"model {model.name!r}: the port-Hamiltonian form does not reproduce "
                f"d{ph.states[i].name}/dt (difference {diff}); please report this model")

