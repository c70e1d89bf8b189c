"""The pieces of :mod:`bondgraph.hamiltonian.form`: element checks, stored energy,
collocated outputs, the coefficient matrices and the final symbolic check."""

from __future__ import annotations

import warnings
from typing import Optional, Sequence

import sympy

from ..elements.fields.algebra import inverse as matrix_inverse
from ..errors import BondGraphWarning, LawError, NonlinearModelError
from ..equations import StateEquations, derive_equations
from ..elements.protocol import Element
from ..signals import t as T_SYM

__all__ = ["PortHamiltonianError"]

Matrix = sympy.ImmutableMatrix   # constructor shorthand; annotations spell it out


class PortHamiltonianError(NonlinearModelError):
    """A model has no port-Hamiltonian form (or no energy) that bondgraph can give.

    The message names the element at fault and says why.
    """



def column_of(entries: Sequence) -> sympy.ImmutableMatrix:
    """A column (``n x 1`` also for ``n = 0``)."""
    return Matrix(len(entries), 1, list(entries))


# ===================================================================== checks
def check_elements(model: StateEquations) -> None:
    """Refuse, naming the element, what has no constant (J, R, G) form (each element
    says why: :meth:`~bondgraph.elements.protocol.Element.hamiltonian_error`)."""
    aug = model.augmented
    for el in aug.flat.elements:
        why = el.hamiltonian_error(el.name in aug.derivative)
        if why:
            raise PortHamiltonianError(why)


def nonconservative_elements(model: StateEquations) -> tuple[str, ...]:
    return tuple(el.label() for el in model.augmented.flat.elements if not el.conserves_power())


def input_derivative_error(model: StateEquations, derived: StateEquations) -> None:
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
def _effort_in(model: StateEquations, el: Element) -> list[bool]:
    aug, bonds = model.augmented, model.augmented.flat.bonds
    return [aug.stroke_at_head[k] if bonds[k].head == el.name else not aug.stroke_at_head[k]
            for k in aug.flat.incidence[el.name]]


def storage_elements(model: StateEquations, *, linear_dependent: bool
             ) -> tuple[list[tuple[tuple[sympy.Symbol, ...], Element]], list[Element]]:
    """``([(states, element)] in integral causality, [element] with ports in derivative
    causality)``; every element that :meth:`~bondgraph.elements.protocol.Element.energy_signals`."""
    aug = model.augmented
    by_name = {s.name: s for s in model.states[:model.storage_states]}
    storage: list[tuple[tuple[sympy.Symbol, ...], Element]] = []
    dependent: list[Element] = []
    count = 0
    for el in aug.flat.elements:
        if not el.energy_signals():
            continue
        is_dependent = el.name in aug.derivative
        why = el.hamiltonian_error(linear_dependent and is_dependent)
        if why:
            if not linear_dependent:       # energy(): only a modulated law matters
                why = why.split(" (a modulated element)")[0] + \
                    "; the stored energy of a modulated storage element is not a function " \
                    "of the state alone"
            raise PortHamiltonianError(why)
        names = el.state_names(_effort_in(model, el))
        missing = [n for n in names if n not in by_name]
        if missing:
            raise PortHamiltonianError(
                f"{el.label()}: model {model.name!r} has no state {missing[0]!r} for it "
                f"(states: {', '.join(model.state_names)})")
        count += len(names)
        if is_dependent:
            dependent.append(el)
        else:
            storage.append((tuple(by_name[n] for n in names), el))
    if count != model.storage_states:
        raise PortHamiltonianError(
            f"model {model.name!r}: {model.storage_states} storage states but "
            f"{count} storage ports in integral causality")
    return storage, dependent


def stored_signals(dependent: Sequence[Element]) -> dict[str, sympy.Expr]:
    """Output signals for the stored quantities of each element in derivative causality."""
    return {f"s{i}_{j}": sig for i, el in enumerate(dependent)
            for j, sig in enumerate(el.energy_signals())}


def stored_quantities(storage, dependent, aux: Optional[StateEquations]) -> list[tuple[tuple, Element]]:
    """``[(stored quantities, element)]``: the states, or (derivative causality) the
    momenta or displacements in the states, read from the outputs of ``aux``."""
    stored: list[tuple[tuple, Element]] = [(syms, el) for syms, el in storage]
    if not dependent:
        return stored
    assert aux is not None
    out = dict(zip(aux.output_names, aux.output_exprs))
    bad = set(aux.inputs) | set(aux.input_derivatives) | {T_SYM}
    signals = stored_signals(dependent)
    for i, el in enumerate(dependent):
        values = []
        for j, sig in enumerate(el.energy_signals()):
            expr = out[f"s{i}_{j}"]
            if expr.free_symbols & bad:
                which = ", ".join(sorted(str(s) for s in expr.free_symbols & bad))
                raise PortHamiltonianError(
                    f"{el.label()} is in derivative causality and its {sig.variable} {expr} "
                    f"depends on {which}: a source fixes its "
                    f"{'flow' if sig.variable == 'momentum' else 'effort'}, so its stored "
                    "energy is not a function of the state and the source's power needs the "
                    "input's derivative; such a source is not a port of a port-Hamiltonian "
                    "system")
            values.append(expr)
        stored.append((tuple(values), el))
    assert len(signals) == sum(len(v) for v, _ in stored[len(storage):])
    return stored


def sum_energy(stored: Sequence[tuple[tuple, Element]]) -> sympy.Expr:
    total = sympy.Integer(0)
    for quantities, el in stored:
        try:
            total += el.stored_energy(quantities)
        except LawError as exc:
            raise PortHamiltonianError(str(exc)) from exc
    return total


# ===================================================================== coefficients
def collocated_outputs(model: StateEquations) -> tuple[dict[str, sympy.Expr], tuple[str, ...]]:
    """Output signals power-conjugate to each input, and their names (each source's
    :meth:`~bondgraph.elements.protocol.Element.collocated_output`)."""
    flat = model.augmented.flat
    ports: dict[str, sympy.Expr] = {}
    names: list[str] = []
    for i, u in enumerate(model.inputs):
        el = flat.element(u.name)
        pair = el.collocated_output()
        if pair is None:
            raise PortHamiltonianError(f"{el.label()}: it introduces the input {u.name} but "
                                       "names no power-conjugate output")
        names.append(pair[0])
        ports[f"y{i}"] = pair[1]
    return ports, tuple(names)


def rederive(model: StateEquations, outputs: dict[str, sympy.Expr]) -> StateEquations:
    """``derive`` on the model's own augmented graph (same causality, same states)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BondGraphWarning)   # the model warned already
        return derive_equations(model.augmented, outputs=outputs or None)


def hessian_inverse(Q: sympy.ImmutableMatrix, model: StateEquations) -> sympy.ImmutableMatrix:
    if Q.is_diagonal():
        if any(Q[i, i] == 0 for i in range(Q.rows)):
            k = next(i for i in range(Q.rows) if Q[i, i] == 0)
            raise PortHamiltonianError(
                f"model {model.name!r}: the stored energy does not depend on the state "
                f"{model.state_names[k]}")
        return Matrix.diag(*[1 / Q[i, i] for i in range(Q.rows)]) if Q.rows else Q
    try:
        return matrix_inverse(Matrix(Q))
    except ValueError:
        raise PortHamiltonianError(
            f"model {model.name!r}: the stored energy is a singular quadratic form of the "
            "states") from None


def block_hessian_inverse(storage, x: Sequence[sympy.Symbol], hess, model: StateEquations
                   ) -> sympy.ImmutableMatrix:
    """The inverse Hessian of ``H`` element by element (every state in integral causality:
    ``H`` is a sum of the elements' energies, so the Hessian is block diagonal), each block
    the element's own :meth:`~bondgraph.elements.protocol.Element.energy_hessian_inverse` (a mass or
    compliance matrix needs no inversion) or its Hessian block inverted."""
    index = {sym: i for i, sym in enumerate(x)}
    out = sympy.zeros(len(x), len(x))
    for syms, el in storage:
        rows = [index[s] for s in syms]
        block = el.energy_hessian_inverse()
        if block is None or block.shape != (len(syms), len(syms)):
            block = hessian_inverse(Matrix(hess.extract(rows, rows)), model)
        for a, i in enumerate(rows):
            for b, j in enumerate(rows):
                out[i, j] = block[a, b]
    return Matrix(out)


def cancel_entries(M) -> sympy.ImmutableMatrix:
    """Entries as one reduced fraction, factored when small (big ones: common factors only)."""
    def tidy(expr: sympy.Expr) -> sympy.Expr:
        expr = sympy.cancel(sympy.together(expr))
        return sympy.factor(expr) if sympy.count_ops(expr) <= 80 else sympy.factor_terms(expr)
    return Matrix(M.rows, M.cols, lambda i, j: tidy(M[i, j]))


def input_matrix(exprs, u, x, model: StateEquations, what: str) -> sympy.ImmutableMatrix:
    M = Matrix(len(exprs), len(u), lambda i, j: sympy.cancel(sympy.diff(exprs[i], u[j])))
    _constant(M, set(x) | set(u), model, what, "inputs")
    return M


def coefficient_matrix(exprs, x, hess, model: StateEquations, what: str) -> sympy.ImmutableMatrix:
    """``(d exprs / dx) (d^2 H / dx^2)^-1`` for nonlinear storage in integral causality
    (a diagonal Hessian ``phi_i'(x_i)``, or a coupled one: a nonlinear field)."""
    jac = Matrix(len(exprs), len(x), lambda i, j: sympy.diff(exprs[i], x[j]))
    if hess.is_diagonal():
        M = Matrix(len(exprs), len(x), lambda i, j: sympy.cancel(jac[i, j] / hess[j, j]))
    else:
        M = Matrix((jac * hessian_inverse(Matrix(hess), model)).applyfunc(
            lambda v: sympy.simplify(sympy.cancel(sympy.together(v)))))
    _constant(M, set(x), model, what, "co-energy variables grad H")
    return M


def _constant(M: sympy.ImmutableMatrix, variables: set, model: StateEquations, what: str, wrt: str) -> None:
    for (i, j), val in M.todok().items():
        if val.free_symbols & (variables | {T_SYM}):
            raise PortHamiltonianError(
                f"model {model.name!r}: {what} {i + 1} is not linear in the {wrt} "
                f"(coefficient {val}); the port-Hamiltonian form needs linear R elements "
                "and constant moduli")
