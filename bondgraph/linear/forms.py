"""Linear forms of derived equations: the Jacobian pieces behind
:mod:`bondgraph.linear.model_forms` (operating-point values, equilibrium
residuals with a tolerance for floats, linear coefficients with the error naming
the equation that is not linear, sparse matrices built at C speed)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import sympy
from sympy.core.basic import Basic
from sympy.core.containers import Dict, Tuple
from sympy.core.sorting import _node_count

from .._support.gcpause import with_paused_gc
from ..errors import NonlinearModelError
from ..signals import t as T_SYM
from .._support.sympify import as_expr
from .._support.zero import is_zero, reduced

if TYPE_CHECKING:
    from ..equations import StateEquations


def residual(expr: sympy.Expr, point: dict, tol: float):
    """``expr`` at ``point`` when it is not zero within ``tol``, else None.

    See :func:`bondgraph.linear.linearize`: terms are grouped by their symbolic factor;
    a group holding a float passes when ``|sum| <= tol * max(1, sum |parts|)``,
    exact groups must simplify to zero.
    """
    total = expr.xreplace(point)
    if total == 0:
        return None
    if not total.has(sympy.Float):
        total = sympy.simplify(total)
        return None if total == 0 else total
    groups: dict[sympy.Expr, list] = {}
    for term in sympy.Add.make_args(expr):
        for part in sympy.Add.make_args(sympy.expand(term.xreplace(point))):
            c, rest = part.as_coeff_Mul()
            groups.setdefault(rest, []).append(c)
    exact = []
    for rest, coeffs in groups.items():
        c = sympy.Add(*coeffs)
        if c == 0:
            continue
        if any(isinstance(k, sympy.Float) for k in coeffs) and c.is_number:
            scale = max(1.0, sum(abs(float(k)) for k in coeffs))
            if abs(complex(c)) <= tol * scale:
                continue
        exact.append(c * rest)
    if not exact:
        return None
    rem = sympy.simplify(sympy.Add(*exact))
    return None if rem == 0 else total


def point_values(model: StateEquations, values, symbols, what: str) -> dict:
    """Map names or symbols of states/inputs to sympy values; all must be given."""
    values = dict(values or {})
    by_name = {s.name: s for s in symbols}
    out = {}
    for key, val in values.items():
        name = key.name if isinstance(key, sympy.Symbol) else key
        if name not in by_name:
            raise NonlinearModelError(
                f"model {model.name!r}: {what} {name!r} is not one of {', '.join(by_name)}")
        out[by_name[name]] = as_expr(val, what=f"{what} {name!r}", error=NonlinearModelError)
    missing = [n for n, sym in by_name.items() if sym not in out]
    if missing:
        raise NonlinearModelError(
            f"model {model.name!r}: the operating point needs a value for {what}s "
            f"{', '.join(missing)}")
    return out


def derivative_orders(model: StateEquations) -> dict[sympy.Symbol, tuple[int, int]]:
    """``{input derivative symbol: (input index, order)}``.

    ``dV/dt`` is the first derivative of input ``V``; ``d2V/dt2`` (or
    ``d^2V/dt^2``) the second, and so on.
    """
    names = {}
    for j, u in enumerate(model.inputs):
        names[f"d{u.name}/dt"] = (j, 1)
        for k in range(2, 10):
            names[f"d{k}{u.name}/dt{k}"] = (j, k)
            names[f"d^{k}{u.name}/dt^{k}"] = (j, k)
    out = {}
    for sym in model.input_derivatives:
        if sym.name not in names:
            raise NonlinearModelError(
                f"model {model.name!r}: input derivative {sym.name} names no input "
                f"({', '.join(model.input_names)})")
        out[sym] = names[sym.name]
    return out


def refuse_implicit(model: StateEquations, what: str) -> None:
    """:class:`NonlinearModelError` for an implicit model (algebraic unknowns ``z``), naming them."""
    if model.algebraic:
        raise NonlinearModelError(
            f"model {model.name!r} is implicit: x' = f(x, z, u), 0 = g(x, z, u) with the "
            f"algebraic unknowns {', '.join(model.algebraic_names)} "
            f"({'; '.join(model.algebraic_origin)}); it has no {what}.  Linearize it at a "
            "numeric operating point instead: model.linearize(model.equilibrium(values, "
            "inputs)) (the implicit-function theorem, A = f_x - f_z g_z^-1 g_x); when "
            "f and g are linear, bondgraph.compile_plant(model).plant(values) gives its "
            "plant at any parameter values")


@with_paused_gc
def linear_form(exprs, x, u, model: StateEquations, what: str, lhs: str, ud=None, *,
                implicit_ok: bool = False, offsets: bool = False):
    """Sparse ``(M_x, M_u)`` with ``exprs = M_x x + M_u u``; checks linearity.

    With ``ud`` (input-derivative symbols) also ``M_ud``, the coefficients
    of those symbols, which are otherwise refused.  An implicit model is
    refused unless ``implicit_ok`` (then ``x`` lists its algebraic unknowns
    after the states).  With ``offsets`` the constant terms (a constant
    source: gravity, an ambient temperature) are returned as one more column
    matrix ``k`` (``exprs = M_x x + M_u u + k``) instead of being refused.

    One pass over the terms of each expression: a term that is a product
    containing exactly one state or input (to the first power) gives its
    coefficient directly; any other term is differentiated.  Cost is
    proportional to the size of the expressions, not to ``len(x)**2``.
    """
    if not implicit_ok:         # with it, ``x`` holds the algebraic unknowns too
        refuse_implicit(model, "a constant linear form")
    x, u = tuple(x), tuple(u)
    ud_cols = tuple(ud) if ud is not None else ()
    col = {s: (0, j) for j, s in enumerate(x)}
    col.update({s: (1, j) for j, s in enumerate(u)})
    col.update({s: (2, j) for j, s in enumerate(ud_cols)})
    variables = set(col)
    bad = (set(model.input_derivatives) - set(ud_cols)) | {T_SYM}
    entries: tuple[dict, dict, dict] = ({}, {}, {})
    constant: dict = {}

    def refuse_constant(i, c):
        if offsets:
            constant[(i, 0)] = constant.get((i, 0), 0) + c
            return
        raise NonlinearModelError(
            f"model {model.name!r}: {what} {i + 1} ({lhs}) has the constant term {c}; "
            "its linear forms are taken about the operating point (see "
            "bondgraph.linear.offsets)")
    for i, ex in enumerate(exprs):
        terms = sympy.Add.make_args(ex)
        term_free = [_free_symbols(term) for term in terms]
        free = set().union(*term_free)
        if free & bad:
            hint = ""
            if free & set(model.input_derivatives):
                hint = ("; transfer_function() and transfer_matrix() handle input "
                        "derivatives (G(s) = C (sI - A)^-1 (B + s B1) + D + s D1), and "
                        "compile_plant() gives the numeric plant and its frequency response")
            raise NonlinearModelError(
                f"model {model.name!r}: {what} {i + 1} depends on "
                f"{', '.join(sorted(str(s) for s in free & bad))}; it has no constant (A, B) "
                f"form{hint}"
            )
        if not free & variables:
            if ex != 0 and not is_zero(ex):
                refuse_constant(i, ex)
            continue
        coeffs: dict[sympy.Symbol, list] = {}
        constants = [term for term, tfree in zip(terms, term_free) if not tfree & variables]
        if constants and not is_zero(sympy.Add(*constants)):
            refuse_constant(i, sympy.Add(*constants))
        for term, tfree in zip(terms, term_free):
            vs = tfree & variables
            if not vs:
                continue
            if len(vs) == 1:
                (v,) = vs
                if term == v:
                    coeffs.setdefault(v, []).append(sympy.Integer(1))
                    continue
                if term.is_Mul and term.args.count(v) == 1:
                    rest = [a for a in term.args if a != v]
                    if not any(_free_symbols(a) & variables for a in rest):
                        coeffs.setdefault(v, []).append(_mul_rest(rest))
                        continue
            for v in vs:  # general term: differentiate, then check linearity
                d = sympy.diff(term, v)
                if d.free_symbols & variables:
                    d = reduced(d)          # a coefficient that vanishes identically goes
                if d.free_symbols & variables:
                    raise NonlinearModelError(
                        f"model {model.name!r}: {what} {i + 1} ({lhs}) is nonlinear in {v}: "
                        f"d/d{v} = {d}; use a linearization about an operating point")
                coeffs.setdefault(v, []).append(d)
            rest_term = term.xreplace({v: 0 for v in vs})
            if rest_term != 0 and not is_zero(rest_term):
                refuse_constant(i, rest_term)
        for v, parts in coeffs.items():
            c = parts[0] if len(parts) == 1 else sympy.Add(*parts)
            if c != 0:
                k, j = col[v]
                entries[k][(i, j)] = c
    mats: tuple = (sparse_matrix(len(exprs), len(x), entries[0]),
                   sparse_matrix(len(exprs), len(u), entries[1]))
    if ud is not None:
        mats += (sparse_matrix(len(exprs), len(ud_cols), entries[2]),)
    if offsets:
        mats += (sparse_matrix(len(exprs), 1, {k: v for k, v in constant.items() if v != 0}),)
    return mats


def _free_symbols(e: sympy.Basic) -> set:
    """``e.free_symbols`` without the recursion for symbols, numbers and ``x**n``."""
    if e.is_Symbol:
        return {e}
    if e.is_Number:
        return set()
    if e.is_Mul:
        out = set()
        for a in e.args:
            if a.is_Symbol:
                out.add(a)
            elif a.is_Number:
                continue
            elif a.is_Pow and a.base.is_Symbol and a.exp.is_Number:
                out.add(a.base)
            else:
                out |= a.free_symbols
        return out
    return e.free_symbols


def _mul_rest(rest: list) -> sympy.Expr:
    """``Mul(*rest)`` for the factors left of a canonical product less one factor.

    They are already combined and sorted, so the product is rebuilt without
    ``Mul.flatten``, except for a number times a sum, which sympy distributes.
    """
    if len(rest) == 1:
        return rest[0]
    if len(rest) == 2 and rest[0].is_Number and rest[1].is_Add:
        return sympy.Mul(*rest)
    return sympy.Mul._from_args(rest)


def sparse_matrix(rows: int, cols: int, entries: dict) -> sympy.ImmutableSparseMatrix:
    """``ImmutableSparseMatrix(rows, cols, entries)`` without its sort by printed form.

    sympy orders the entries of the matrix's ``Dict`` argument with
    ``ordered``: by node count, ties broken by ``default_sort_key``, which
    for the unique ``(i, j)`` keys is the row-major position (the entries
    are never compared).  On a 10,000-cell chain that key (it prints every
    entry) was half the time of ``state_space()``.  This builds the same
    object (same ``args``, hash, representation) with the key
    ``(node count, i, j)``; any other sympy layout falls back to the
    constructor.

    Examples
    --------
    >>> import sympy
    >>> a = sympy.Symbol("a")
    >>> M = sparse_matrix(2, 2, {(0, 1): a + 1, (1, 0): sympy.Integer(-2)})
    >>> M == sympy.ImmutableSparseMatrix(2, 2, {(0, 1): a + 1, (1, 0): -2})
    True
    >>> M.args == sympy.ImmutableSparseMatrix(2, 2, {(0, 1): a + 1, (1, 0): -2}).args
    True
    """
    cls = sympy.ImmutableSparseMatrix
    try:
        entries = {k: sympy.sympify(v, strict=True) for k, v in entries.items()}
        rep = cls._smat_to_DomainMatrix(rows, cols, entries)
        smat = rep.to_sympy().to_dok()
        keyed = sorted(((_node_count(v), i, j, v) for (i, j), v in smat.items()),
                       key=_first3)
        new, integer = Basic.__new__, sympy.Integer
        items = [new(Tuple, new(Tuple, integer(i), integer(j)), v) for _, i, j, v in keyed]
        d = Basic.__new__(Dict, *items)
        d.elements = frozenset(items)
        d._dict = dict(items)
        obj = Basic.__new__(cls, sympy.Integer(rows), sympy.Integer(cols), d)
        obj._rows, obj._cols, obj._rep = rows, cols, rep
    except (AttributeError, TypeError):  # pragma: no cover - a sympy without these internals
        return cls(rows, cols, entries)
    return obj


def _first3(t: tuple) -> tuple:
    return t[:3]
