"""Conserved quantities of a model and the totals that fix an equilibrium they leave free.

A chemical moiety (free plus bound enzyme) or a floating charge is a
combination ``l . x`` of the states with ``l . f = 0`` identically: the
equilibrium equations ``f(x, u) = 0`` then leave its total free.
:func:`conserved_combinations` finds such combinations;
:func:`totals_equations` replaces the equations they make dependent by
``l . x = total`` (the ``totals=`` of :meth:`bondgraph.Model.equilibrium` and
:meth:`bondgraph.Model.operating_point`).

A floating capacitor pair (two capacitors joined through a resistor, nothing
to the ground) keeps ``q_C1 + q_C2``: the example of :func:`conserved_combinations`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping, Optional

import sympy

from ..signals import t as T_SYM
from .._support.sympify import as_expr
from .point import OperatingPointError

if TYPE_CHECKING:
    from ..equations import StateEquations

__all__ = ["conserved_combinations", "conservation_hint", "totals_equations", "unify"]

#: largest number of states for which an error message looks for conserved combinations
HINT_MAX_STATES = 120


def where(eqs: "StateEquations") -> str:
    """``"model 'name': "``, the prefix of messages."""
    return f"model {eqs.name!r}: "


_where = where


def _named_symbols(eqs: "StateEquations") -> dict[str, sympy.Symbol]:
    out = {p.name: p for p in eqs.parameters}
    out.update({s.name: s for s in eqs.states + eqs.inputs})
    return out


def unify(expr: sympy.Expr, eqs: "StateEquations") -> sympy.Expr:
    """``expr`` with every symbol named like a symbol of the model replaced by the model's
    one: ``Symbol('C')`` typed by a user is the model's ``C`` (positive), so
    ``-C + C`` cancels."""
    known = _named_symbols(eqs)
    swap = {s: known[s.name] for s in expr.free_symbols
            if s.name in known and s != known[s.name]}
    return expr.xreplace(swap) if swap else expr


def _law(key: Any, eqs: "StateEquations") -> sympy.Matrix:
    """The row ``l`` of a total's key: a state name, a tuple of state names (their sum),
    or a sympy expression linear in the states (matched by name)."""
    by_name = {s.name: s for s in eqs.states}
    if isinstance(key, str):
        key = (key,)
    if isinstance(key, (tuple, list, frozenset)):
        missing = [k for k in key if not isinstance(k, str) or k not in by_name]
        if missing or not key:
            raise OperatingPointError(
                f"{_where(eqs)}totals: {missing or key!r} names no state; a total's key is a "
                f"state name, a tuple of them or an expression linear in the states "
                f"({', '.join(by_name)})")
        expr = sympy.Add(*[by_name[k] for k in key])
    elif isinstance(key, sympy.Expr):
        expr = key.xreplace({s: by_name[s.name] for s in key.free_symbols if s.name in by_name})
    else:
        raise OperatingPointError(f"{_where(eqs)}totals: a key must be a state name, a tuple of "
                                  f"state names or a sympy expression; got {key!r}")
    row = sympy.Matrix([[sympy.diff(expr, x) for x in eqs.states]])
    if row.free_symbols & set(eqs.states) or expr.free_symbols & (set(eqs.inputs) | {T_SYM}) \
            or sympy.expand(expr - (row * sympy.Matrix(eqs.states))[0]) != 0 or row.is_zero_matrix:
        raise OperatingPointError(f"{_where(eqs)}totals: {key} is not a linear combination of the "
                                  "states without a constant")
    return row


def totals_equations(eqs: "StateEquations", exprs: list, totals: Optional[Mapping],
                     u0: Optional[Mapping] = None) -> tuple[list, list[int]]:
    """``exprs`` (``f``) with the equations that conserved totals make dependent replaced by
    ``l . x - total``; also the indices replaced.

    Each key's combination ``l . x`` must be conserved (``l . f`` is identically 0 at
    the inputs ``u0``).  With ``k`` totals, the equations of the rows' pivots (reduced
    row echelon form) are replaced: ``l . f = 0`` makes each of them a combination
    of the others.

    Examples
    --------
    Two capacitors exchanging charge through a resistor: ``q1 + q2`` is conserved.

    >>> import bondgraph as bg
    >>> g = bg.BondGraph("float")
    >>> g.add(bg.Zero("a"), bg.Zero("b"), bg.One("i"), bg.C("C1"), bg.C("C2"), bg.R("R"))
    >>> for t, h in [("a", "C1"), ("a", "i"), ("i", "R"), ("i", "b"), ("b", "C2")]:
    ...     _ = g.connect(t, h)
    >>> eqs = bg.derive(g)
    >>> Q = sympy.Symbol("Q")
    >>> totals_equations(eqs, list(eqs.rhs), {("q_C1", "q_C2"): Q})
    ([-Q + q_C1 + q_C2, (-q_C2/C2 + q_C1/C1)/R], [0])
    """
    if not totals:
        return list(exprs), []
    if not isinstance(totals, Mapping):
        raise OperatingPointError(f"{_where(eqs)}totals: expected a mapping of a state name (or "
                                  f"a tuple of them) to the total, got {type(totals).__name__}")
    rows, values = [], []
    for key, value in totals.items():
        row = _law(key, eqs)
        drift = sympy.expand(sum((row[j] * e for j, e in enumerate(eqs.rhs)), sympy.S.Zero)
                             .xreplace(dict(u0 or {})))
        if drift != 0 and sympy.simplify(drift) != 0:
            raise OperatingPointError(
                f"{_where(eqs)}totals: {key} is not conserved: its rate is {sympy.simplify(drift)}"
                "; a total fixes a quantity the model keeps constant (a moiety, a floating "
                "charge)")
        rows.append(row)
        values.append(unify(as_expr(value, what=f"the total of {key}", error=OperatingPointError),
                            eqs))
    L = sympy.Matrix.vstack(*rows)
    pivots = L.rref()[1]
    if len(pivots) < L.rows:
        raise OperatingPointError(f"{_where(eqs)}totals: the {L.rows} totals are not independent "
                                  "(one is a combination of the others)")
    out = list(exprs)
    x = sympy.Matrix(eqs.states)
    for k, i in enumerate(pivots):
        out[i] = (L.row(k) * x)[0] - values[k]
    return out, list(pivots)


def conserved_combinations(eqs: "StateEquations") -> list[sympy.Expr]:
    """Combinations ``l . x`` of the states with ``l . f = 0`` identically (for every state,
    input and parameter value): chemical moieties, a floating charge.

    ``f`` is written ``M m(x, u)`` over its distinct state- and input-dependent factors
    ``m`` (a constant term is one more); the laws are the left null space of ``M``.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("float")
    >>> g.add(bg.Zero("a"), bg.Zero("b"), bg.One("i"), bg.C("C1"), bg.C("C2"), bg.R("R"))
    >>> for t, h in [("a", "C1"), ("a", "i"), ("i", "R"), ("i", "b"), ("b", "C2")]:
    ...     _ = g.connect(t, h)
    >>> conserved_combinations(bg.derive(g))
    [q_C1 + q_C2]
    """
    variables = tuple(eqs.states) + tuple(eqs.inputs) + tuple(eqs.input_derivatives)
    columns: dict = {}
    entries: dict = {}
    for i, f in enumerate(eqs.rhs):
        for term in sympy.Add.make_args(sympy.expand(f)):
            coeff, dep = term.as_independent(*variables, as_Add=False)
            j = columns.setdefault(dep, len(columns))
            entries[(i, j)] = entries.get((i, j), 0) + coeff
    if not columns:
        return [s for s in eqs.states]
    M = sympy.Matrix(len(eqs.rhs), len(columns), lambda i, j: entries.get((i, j), 0))
    laws = []
    for vec in M.T.nullspace(simplify=True):
        scale = sympy.lcm([sympy.fraction(sympy.nsimplify(c))[1] for c in vec]) \
            if all(c.is_Rational for c in vec) else 1
        laws.append(sympy.Add(*[sympy.simplify(c * scale) * x for c, x in zip(vec, eqs.states)]))
    return laws


def conservation_hint(eqs: "StateEquations") -> str:
    """The totals to give when conserved quantities leave an equilibrium free, or ''."""
    try:
        laws = conserved_combinations(eqs) if len(eqs.states) <= HINT_MAX_STATES else []
    except Exception:       # noqa: BLE001 -- a hint only: never hide the real error
        laws = []
    if not laws:
        return ""
    def key(law):
        terms = sympy.Add.make_args(law)
        if all(t.is_Symbol for t in terms):
            return repr(tuple(sorted(t.name for t in terms)))
        return str(law)
    example = ", ".join(f"{key(law)}: ..." for law in laws)
    return (f"; conserved: {', '.join(map(str, laws))}, whose total"
            f"{'s' if len(laws) > 1 else ''} the equilibrium needs: totals={{{example}}} "
            "(a key is a state name, a tuple of state names summed, or a sympy expression)")
