"""Linear forms about the operating point: constant sources and inputs that enter nonlinearly.

A constant source (``Se("gravity", value=m*g)``, an ambient temperature, a
bias voltage) puts a constant term ``c`` in ``x' = A x + B u + c``; a duty
cycle times a source voltage (an averaged converter) makes ``f`` nonlinear in
the inputs.  Such a model has no linear form in its own variables, but it has
one in deviations ``dx = x - x0``, ``du = u - u0``, ``dy = y - y0`` about an
equilibrium ``f(x0, u0) = 0``.  This module finds that point and the linear
point :func:`bondgraph.linear.deviations` takes the linear record about, which
:func:`bondgraph.linear.state_space`, :func:`~bondgraph.linear.transfer_function`
and the numeric plants use.

* :func:`nominal_inputs` -- ``u0``: the values given, and for the others a
  symbol ``<input>0`` (``F0``, ``d0``, ``Vg0``): a symbolic operating point
  holds for every value of the nominal inputs;
* :func:`symbolic_operating_point` -- ``x0`` solved exactly: a linear solve
  when ``f`` is linear in the states at ``u0`` (constant sources, averaged
  converters), sympy's solver for small polynomial systems otherwise, with
  the totals of conserved quantities (``totals=``,
  :mod:`bondgraph.linear.conserved`) replacing the equations they make
  dependent;
* :func:`numeric_operating_point` -- the point of a numeric equilibrium.

Examples
--------
A mass ``m`` on a spring ``k`` and a damper ``b``, pushed by ``F`` and
loaded by its weight ``W`` (``W`` acts along ``F``, so the spring settles
at ``x0 = (F0 + W)/k`` in the direction of both):

>>> import sympy, bondgraph as bg
>>> g = bg.BondGraph("msd")
>>> v = bg.One("v")
>>> W = sympy.Symbol("W", positive=True)
>>> g.add(bg.Se("F"), bg.Se("weight", value=W), v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
>>> for t, h in [("F", v), ("weight", v), (v, "m"), (v, "b"), (v, "k")]: _ = g.connect(t, h)
>>> model = bg.derive(g, outputs={"x": bg.displacement("k")})
>>> op = symbolic_operating_point(model)
>>> dict(op.states), dict(op.inputs)
({'p_m': 0, 'q_k': (F0 + W)/k}, {'F': F0})
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping, Optional

import sympy
from sympy.solvers.solveset import NonlinearError

from ..signals import t as T_SYM
from .._support.sympify import as_expr
from .conserved import _named_symbols, conservation_hint, totals_equations, unify
from .conserved import where as _where
from .point import OperatingPoint, OperatingPointError

if TYPE_CHECKING:
    from ..equations import StateEquations

__all__ = ["OperatingPointError", "nominal_inputs", "symbolic_operating_point",
           "numeric_operating_point", "SYMBOLIC_MAX_STATES"]

#: largest number of states whose operating point is solved symbolically (an exact linear
#: solve grows like n^3 in expression size); larger models give their point numerically
SYMBOLIC_MAX_STATES = 40
#: largest expression (node count; at most 10 symbols) cancelled and factored for display
TIDY_MAX_OPS = 80


class _TooLarge(OperatingPointError):
    """More states than :data:`SYMBOLIC_MAX_STATES` for a symbolic point."""


def nominal_inputs(eqs: "StateEquations", given: Optional[Mapping] = None) -> dict:
    """``u0``: the values ``given`` (by input name or symbol), a symbol ``<name>0`` for the rest.

    The symbol keeps the input's assumptions; a name taken by a parameter, state
    or input gets an underscore (``F_0``) instead.

    Examples
    --------
    >>> from bondgraph import examples
    >>> from bondgraph.equations import derive_equations
    >>> nominal_inputs(derive_equations(examples.rc()))
    {V: V0}
    """
    if given is not None and not isinstance(given, Mapping):
        raise OperatingPointError(f"{_where(eqs)}the operating point's inputs: expected a mapping "
                                  f"of input names to values, got {type(given).__name__}")
    by_name = {u.name: u for u in eqs.inputs}
    out: dict = {}
    for key, value in dict(given or {}).items():
        name = key.name if isinstance(key, sympy.Symbol) else key
        if name not in by_name:
            raise OperatingPointError(
                f"{_where(eqs)}the operating point names the input {name!r}, which is not one "
                f"of {', '.join(by_name) or '(none)'}")
        out[by_name[name]] = unify(as_expr(value, what=f"input {name!r} of the operating point",
                                           error=OperatingPointError), eqs)
    taken = set(_named_symbols(eqs)) | set(eqs.known_parameters)
    for u in eqs.inputs:
        if u in out:
            continue
        name = f"{u.name}0"
        while name in taken:
            name = name[:-1] + "_0"
        taken.add(name)
        out[u] = sympy.Symbol(name, **u.assumptions0)
    return out


# ------------------------------------------------------------------ the point
def _refuse_time(eqs: "StateEquations") -> None:
    for ex in eqs.rhs:
        if T_SYM in ex.free_symbols:
            raise OperatingPointError(f"{_where(eqs)}the state equations depend on time; a "
                                      "linear form about an equilibrium needs a time-invariant "
                                      "model")


def symbolic_operating_point(eqs: "StateEquations", inputs: Optional[Mapping] = None, *,
                             states: Optional[Mapping] = None,
                             totals: Optional[Mapping] = None) -> OperatingPoint:
    """The equilibrium ``f(x0, u0) = 0`` solved exactly, with ``y0 = g(x0, u0)``.

    Parameters
    ----------
    eqs : StateEquations
    inputs : mapping of input name to value, optional
        ``u0``; inputs not given are symbols ``<name>0`` (:func:`nominal_inputs`).
    states : mapping of state name to value, optional
        States given rather than solved (all of them: the point is then only checked
        by the callers that need an equilibrium).
    totals : mapping, optional
        Totals of conserved quantities (a key is a state name, a tuple of state
        names summed, or an expression linear in the states): ``{("q_E", "q_C"): E_T}``.

    Raises
    ------
    OperatingPointError
        No isolated equilibrium (a singular linear system: the message says
        whether totals are missing), several, or equations sympy cannot
        solve (use :meth:`bondgraph.Model.equilibrium` with numbers).

    Examples
    --------
    A capacitor ``C`` charged through ``R`` from ``V``: ``q0 = C V0``.

    >>> from bondgraph import examples
    >>> from bondgraph.equations import derive_equations
    >>> op = symbolic_operating_point(derive_equations(examples.rc()))
    >>> dict(op.states), dict(op.inputs)
    ({'q_C': C*V0}, {'V': V0})
    """
    where = _where(eqs)
    if eqs.algebraic:
        raise OperatingPointError(
            f"{where}the model is implicit (algebraic unknowns "
            f"{', '.join(eqs.algebraic_names)}); its operating point is numeric: "
            "model.equilibrium(values, inputs)")
    _refuse_time(eqs)
    u0 = nominal_inputs(eqs, inputs)
    at = {**u0, **dict.fromkeys(eqs.input_derivatives, sympy.S.Zero)}
    how = ""
    if states is not None:
        from .forms import point_values
        x0 = {s: unify(v, eqs) for s, v in point_values(eqs, states, eqs.states, "state").items()}
        how = "the states given"
    else:
        exprs, replaced = totals_equations(eqs, [r.xreplace(at) for r in eqs.rhs], totals, at)
        x0 = _solve(eqs, exprs, bool(replaced))
        how = ("exact: " + ("the linear equations f(x0, u0) = 0" if x0.pop(None, True)
                            else "sympy.solve, the one solution")
               + (f" with {len(replaced)} conserved total{'s' * (len(replaced) > 1)}"
                  if replaced else ""))
    point = {**x0, **at}
    y0 = [_tidy(y.xreplace(point)) for y in eqs.output_exprs]
    return OperatingPoint({s.name: x0[s] for s in eqs.states},
                          {u.name: v for u, v in u0.items()},
                          dict(zip(eqs.output_names, y0)), how=how)


def _tidy(e: sympy.Expr) -> sympy.Expr:
    """``e`` cancelled, and factored when that is shorter (small expressions only: factoring
    a long sum costs seconds)."""
    from sympy.core.sorting import _node_count

    if _node_count(e) > TIDY_MAX_OPS or len(e.free_symbols) > 10:
        return e
    e = sympy.cancel(sympy.together(e))
    f = sympy.factor(e)
    return f if _node_count(f) <= _node_count(e) else e


def _linear_solve(M: sympy.Matrix, b: sympy.Matrix) -> Optional[list]:
    """``M^-1 b`` over the field of rational functions of the parameters (sympy's
    ``DomainMatrix``: exact cancellation, fast on sparse systems), or None when ``M`` is
    singular."""
    from sympy.polys.matrices import DomainMatrix
    from sympy.polys.matrices.exceptions import DMNonInvertibleMatrixError

    dM, db = DomainMatrix.from_Matrix(M).unify(DomainMatrix.from_Matrix(b))
    K = dM.domain.get_field() if dM.domain.has_assoc_Field else dM.domain
    try:
        sol = dM.convert_to(K).lu_solve(db.convert_to(K))
    except (DMNonInvertibleMatrixError, ZeroDivisionError):
        return None
    return list(sol.to_Matrix())


def _solve(eqs: "StateEquations", exprs: list, with_totals: bool) -> dict:
    """``{state: x0}`` with ``exprs = 0``; the key ``None`` says whether it was linear."""
    where, x = _where(eqs), list(eqs.states)
    if len(x) > SYMBOLIC_MAX_STATES:
        raise _TooLarge(
            f"{where}{len(x)} states: the symbolic operating point is not solved above "
            f"{SYMBOLIC_MAX_STATES} states (its expressions grow like n^3); give parameter "
            "values for a numeric one (model.operating_point(inputs, values=...))")
    if not x:
        return {None: True}
    try:
        M, b = sympy.linear_eq_to_matrix(exprs, x)
        linear = not (M.free_symbols | b.free_symbols) & set(x)
    except (NonlinearError, ValueError):
        linear = False
    if linear:
        sol = _linear_solve(M, b)
        if sol is None:
            raise OperatingPointError(_singular_text(eqs, M, with_totals))
        out: dict = {s: _tidy(v) for s, v in zip(x, sol)}
        out[None] = True
        return out
    from .trim import exact_budget

    nums = [sympy.together(e).as_numer_denom()[0] for e in exprs]
    if not all(n.is_polynomial(*x) for n in nums) or not exact_budget(nums, x):
        raise OperatingPointError(
            f"{where}the equilibrium equations are not polynomial in the states (or too large "
            "for sympy's exact solver); give the states of the point (at={state: value, ...}) "
            "or parameter values for a numeric search (model.equilibrium(values, inputs))")
    try:
        sols = sympy.solve(nums, x, dict=True)
    except (NotImplementedError, ValueError, TypeError):
        sols = None
    if not sols:
        raise OperatingPointError(f"{where}sympy finds no equilibrium; give parameter values "
                                  "for a numeric search (model.equilibrium(values, inputs))")
    full = [s for s in sols if set(s) == set(x)]
    if len(full) != 1:
        listed = "; ".join(", ".join(f"{k} = {v}" for k, v in s.items()) for s in sols[:4])
        raise OperatingPointError(
            f"{where}{len(sols)} equilibria ({listed}{'; ...' if len(sols) > 4 else ''}); "
            "choose one: give its states (at={state: value, ...}) or use "
            "model.equilibrium(values, inputs, guess=...)")
    out = {s: _tidy(v) for s, v in full[0].items()}
    out[None] = False
    return out


def _singular_text(eqs: "StateEquations", M: sympy.Matrix, with_totals: bool) -> str:
    loose = []
    for vec in M.nullspace(simplify=True):
        loose += [s.name for s, c in zip(eqs.states, vec) if c != 0 and s.name not in loose]
    hint = conservation_hint(eqs) if not with_totals else ""
    if not hint and not with_totals:
        hint = ("; a state no equation holds (a free mass's position) has no equilibrium to "
                "linearize about")
    return (f"{_where(eqs)}the equilibrium is not isolated: f(x0, u0) = 0 does not determine "
            f"{', '.join(loose) or 'every state'} (the Jacobian df/dx is singular){hint}")


def numeric_operating_point(eqs: "StateEquations", eq: Any, units: Optional[Mapping] = None
                            ) -> OperatingPoint:
    """The :class:`OperatingPoint` of a numeric :class:`~bondgraph.linear.Equilibrium`:
    its ``x0`` and ``u0`` and the outputs there (``y0``), as floats.

    Examples
    --------
    >>> from bondgraph import examples
    >>> from bondgraph.equations import derive_equations
    >>> from bondgraph.linear import equilibrium
    >>> import bondgraph as bg
    >>> eqs = derive_equations(examples.rc(), {"vC": bg.effort("C")})
    >>> op = numeric_operating_point(eqs, equilibrium(eqs, {"R": 1.0, "C": 2.0}, {"V": 3.0}))
    >>> dict(op.states), dict(op.outputs)
    ({'q_C': 6.0}, {'vC': 3.0})
    """
    by_name = {p.name: p for p in eqs.parameters}
    at = {by_name[k]: sympy.Float(v, 17) for k, v in eq.values.items() if k in by_name}
    at.update({s: sympy.Float(eq.states[s.name], 17) for s in eqs.states})
    at.update({u: sympy.Float(eq.inputs.get(u.name, 0.0), 17) for u in eqs.inputs})
    at.update({z: sympy.Float(eq.algebraic[z.name], 17) for z in eqs.algebraic
               if z.name in eq.algebraic})
    at.update(dict.fromkeys(eqs.input_derivatives, sympy.S.Zero))
    y0 = {}
    for n, y in zip(eqs.output_names, eqs.output_exprs):
        try:
            y0[n] = float(y.xreplace(at))
        except TypeError:
            raise OperatingPointError(f"{_where(eqs)}output {n} is not a number at the operating "
                                      f"point ({y.xreplace(at)})") from None
    return OperatingPoint(dict(eq.states), {u.name: float(eq.inputs.get(u.name, 0.0))
                                            for u in eqs.inputs}, y0,
                          {k: v for k, v in dict(units or {}).items()},
                          how=f"{eq.method}: {eq.how}" if eq.how else eq.method, equilibrium=eq)
