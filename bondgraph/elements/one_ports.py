"""One-port elements: sources (Se, Sf), storage (I, C) and resistors (R).

The conventions are in :mod:`bondgraph.elements`.  Nonlinear laws are sympy
expressions in the element's own variable (:data:`bondgraph.p`,
:data:`~bondgraph.q`, :data:`~bondgraph.e`, :data:`~bondgraph.f`) or
callables taking it.

Examples
--------
>>> import bondgraph as bg
>>> bg.I("La").parameter is None        # resolved to Symbol('La') on derivation
True
>>> spring = bg.C("k1", law=3*bg.q + bg.q**3)
>>> spring.law
q**3 + 3*q
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, ClassVar, Optional, Sequence, Union, cast

import numpy as np
import sympy

from ..errors import LawError, ParameterError
from .inverse import closed_form_inverse
from .rules import check_numbers, rule
from .protocol import (ARBITRARY, DERIVATIVE, INTEGRAL, RESISTIVE, STORAGE, CausalPorts, Choice,
                       Decision, Element, LocalVariables, prefix_signals, rename, signals_of)
from .._support.sympify import ParameterLike, nonzero, to_expr
from ..signals import LawVariable, Signal, e as E_VAR, f as F_VAR, p as P_VAR, q as Q_VAR, t as T_SYM
from ..signals import (displacement as displacement_signal, effort as effort_signal,
                      flow as flow_signal, momentum as momentum_signal)

__all__ = ["OnePort", "Se", "Sf", "I", "C", "R"]

LawLike = Union[None, sympy.Expr, Callable[[sympy.Symbol], sympy.Expr]]

if TYPE_CHECKING:  # pragma: no cover
    from .bond import Bond


def _call_law(fn: Callable, own: LawVariable, *, owner: str, what: str) -> sympy.Expr:
    """Call a callable law once with the sympy symbol ``own``; failures become :class:`LawError`.

    An exception from the callable is chained (``raise ... from exc``); a
    result that is not a sympy expression or a real number is refused.
    """
    name = getattr(fn, "__name__", type(fn).__name__)
    hint = (f"a callable law is called once with the sympy symbol bondgraph.{own} and must return "
            f"a sympy expression in it (use sympy functions such as sympy.log, not math.log)")
    try:
        value = fn(own)
    except Exception as exc:
        raise LawError(f"{owner}: the {what} law callable {name} raised {type(exc).__name__}: "
                       f"{exc}; {hint}") from exc
    if isinstance(value, bool) or not isinstance(value, (sympy.Expr, numbers.Real)):
        raise LawError(f"{owner}: the {what} law callable {name} returned {type(value).__name__} "
                       f"{str(value)[:40]!r}; {hint}")
    return value


def _law(value: LawLike, own: LawVariable, *, owner: str, what: str) -> Optional[sympy.Expr]:
    """Validate a constitutive law written in the element's own variable."""
    if value is None:
        return None
    if callable(value) and not isinstance(value, sympy.Basic):
        value = _call_law(value, own, owner=owner, what=what)
    expr = to_expr(value, owner=owner, what=f"{what} law", law=True)
    if expr is None:  # pragma: no cover - value is not None here
        return None
    free = expr.free_symbols
    foreign = sorted(str(s) for s in free if isinstance(s, LawVariable) and s != own)
    if foreign:
        raise LawError(
            f"{owner}: the {what} law {expr} uses {', '.join(foreign)}, but it must be a "
            f"function of the element's own variable {own} (bondgraph.{own})"
        )
    if own not in free:
        raise LawError(
            f"{owner}: the {what} law {expr} is not a function of the element's own "
            f"variable {own}; write it with bondgraph.{own}, e.g. k*bondgraph.{own}"
        )
    return expr


@dataclass(frozen=True, eq=False)
class _OneBond(Element):
    """An element with one bond: its effort and flow are the bond's (the flow signed
    by the bond direction, positive into the element)."""

    drawing_role: ClassVar[str] = "dissipative"

    def signal_port(self, variable: str) -> Optional[tuple[int, bool]]:
        return 0, variable == "flow"


@dataclass(frozen=True, eq=False)
class _Source(_OneBond):
    """A source: its value is an input of the model, or a given expression.

    ``value=`` makes the source prescribed instead of an input: a constant
    (gravity ``m*g``), a function of time :data:`bondgraph.t`, or of signals
    (a modulated source, MSe/MSf: a controller or sensor feedback written
    in the graph, e.g. ``-kp*bg.displacement("m")``).
    """

    value: ParameterLike = field(default=None, kw_only=True)

    def __post_init__(self) -> None:
        super().__post_init__()
        val = to_expr(self.value, owner=f"{self.kind}:{self.name}", what="value")
        if val is not None:
            law_vars = [str(s) for s in val.free_symbols if isinstance(s, LawVariable)]
            if law_vars:
                raise ParameterError(
                    f"{self.kind}:{self.name}: value {val} uses {', '.join(law_vars)}; a source value may "
                    "use parameters, signals (bondgraph.flow('m'), ...) and time bondgraph.t")
        object.__setattr__(self, "value", val)

    @property
    def modulated(self) -> bool:
        """Whether the value depends on signals or time (an MSe / MSf)."""
        v = self.value
        return isinstance(v, sympy.Expr) and any(isinstance(s, Signal) or s == T_SYM
                                                  for s in v.free_symbols)

    def label(self) -> str:
        return f"{'M' if self.modulated else ''}{self.kind}:{self.name}"

    def resolved(self, path: str) -> Element:
        el = rename(self, path)
        object.__setattr__(el, "value", prefix_signals(self.value, path[: len(path) - len(self.name)]))
        return el

    def signals(self) -> frozenset:
        return signals_of(self.value)

    # the protocol: a forced decision, no dependency, the input or the given value
    drawing_role: ClassVar[str] = "source"
    conflict_hint: ClassVar[str] = (
        " Two sources fix the same variable (two Sf on a 1-junction or two "
        "Se on a 0-junction), or a source drives a storage-free node the wrong "
        "way: remove one source or put a storage or R element between them.")
    #: whether the source receives effort on its bond (an Sf; an Se imposes it)
    receives_effort: ClassVar[bool] = False

    def forced_causality(self, ports: CausalPorts) -> Sequence[Decision]:
        return (Decision(0, self.receives_effort, f"source {self.label()}"),)

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        return ((),)

    def input_name(self) -> Optional[str]:
        return self.name if self.value is None else None

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        if self.value is None:
            return None
        why = ("a modulated source (feedback written in the graph) is not a port"
               if self.modulated else
               "a prescribed (constant or time-dependent) value is not a port")
        return (f"{self.label()}: value={self.value}: {why}; the port-Hamiltonian form needs "
                "every source as an input (give the source no value)")

    def collocated_output(self) -> Optional[tuple[str, sympy.Expr]]:
        if self.receives_effort:      # a flow source: the effort on its bond
            return f"e_{self.name}", effort_signal(self.name)
        return f"f_{self.name}", -flow_signal(self.name)    # the flow out of an Se

    def _given(self, local: LocalVariables) -> sympy.Expr:
        """The input symbol, or the given value with its signals resolved."""
        if self.value is None:
            return cast(sympy.Expr, local.input_symbol)
        return local.resolve(cast(sympy.Expr, self.value))


@dataclass(frozen=True, eq=False)
class Se(_Source):
    """Effort source; its effort is the input named after the element.

    With ``value=`` the effort is that expression instead (no input); with a
    value that uses signals it is a modulated source, MSe.

    Examples
    --------
    >>> import bondgraph as bg, sympy
    >>> Se("e_in").label()
    'Se:e_in'
    >>> Se("ctrl", value=-sympy.Symbol("kp") * bg.displacement("m")).label()
    'MSe:ctrl'
    """

    kind: ClassVar[str] = "Se"

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        return self._given(local)


@dataclass(frozen=True, eq=False)
class Sf(_Source):
    """Flow source; its flow is the input named after the element.

    ``value=`` prescribes the flow instead (MSf when it uses signals).

    Examples
    --------
    >>> Sf("Q").kind
    'Sf'
    """

    kind: ClassVar[str] = "Sf"
    receives_effort: ClassVar[bool] = True

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        return -local.sign(0) * self._given(local)   # the flow out of the source


@dataclass(frozen=True, eq=False)
class OnePort(_OneBond):
    """Storage or dissipation: a parameter, or a law in the own variable.

    Base of :class:`I`, :class:`C` and :class:`R`; give either ``parameter``
    or ``law`` and/or ``inverse``, not both.

    Parameters
    ----------
    name : str
    parameter : number, str or sympy expression, optional
        The linear coefficient; defaults to a positive symbol named after the
        element's path.
    law, inverse : sympy expression or callable, optional
        The constitutive law in the own variable, and its inverse.
    active : bool, optional, keyword only
        An element negative on purpose (a negative resistance): the sign of
        its parameter is not checked.  By default an I's or a C's parameter
        must be positive and an R's not negative, at construction for a
        number and at every numeric evaluation for a symbol
        (:mod:`bondgraph.elements.rules`).

    Examples
    --------
    >>> import bondgraph as bg
    >>> b = bg.R("b", 0.5)
    >>> isinstance(b, bg.elements.OnePort), b.forward(), b.backward()
    (True, 0.5*f, 2.0*e)
    """

    parameter: ParameterLike = None
    law: LawLike = None
    inverse: LawLike = None
    #: an element negative on purpose (a negative resistance, an amplifier): its
    #: parameter's sign is not checked (:mod:`bondgraph.elements.rules`)
    active: bool = field(default=False, kw_only=True, repr=False)
    own: ClassVar[LawVariable] = P_VAR
    inverse_own: ClassVar[LawVariable] = F_VAR
    law_name: ClassVar[str] = ""
    inverse_name: ClassVar[str] = ""

    def __post_init__(self) -> None:
        super().__post_init__()
        owner = self.label()
        object.__setattr__(self, "parameter", nonzero(
            to_expr(self.parameter, owner=owner, what="parameter"), owner=owner, what="parameter"))
        object.__setattr__(self, "law", _law(self.law, self.own, owner=owner, what=self.law_name))
        object.__setattr__(self, "inverse", _law(self.inverse, self.inverse_own, owner=owner,
                                                 what=self.inverse_name))
        if self.parameter is not None and (self.law is not None or self.inverse is not None):
            raise LawError(f"{owner}: give either a parameter or a law, not both")
        if not isinstance(self.active, (bool, np.bool_)):
            raise ParameterError(f"{owner}: active must be True or False, got "
                                 f"{type(self.active).__name__} {self.active!r}")
        check_numbers(owner, self.value_rules(), active=bool(self.active))

    #: what the linear parameter is, for messages; its sign rule
    parameter_meaning: ClassVar[str] = "parameter"
    parameter_relation: ClassVar[str] = "positive"

    def value_rules(self) -> tuple:
        """The linear parameter's sign (a mass, a compliance positive; a resistance not
        negative); none for a law.  ``active=True`` lifts it."""
        return rule(self.parameter, self.parameter_meaning, self.parameter_relation)

    def resolved(self, path: str) -> Element:
        el = rename(self, path)
        prefix = path[: len(path) - len(self.name)]
        if self.parameter is None and self.law is None and self.inverse is None:
            object.__setattr__(el, "parameter", sympy.Symbol(path, positive=True))
        object.__setattr__(el, "law", prefix_signals(self.law, prefix))
        object.__setattr__(el, "inverse", prefix_signals(self.inverse, prefix))
        return el

    def signals(self) -> frozenset:
        return signals_of(self.law, self.inverse, self.parameter)

    def bond_warnings(self, bonds: Sequence["Bond"]) -> tuple[str, ...]:
        (b,) = bonds
        if b.tail != self.name:
            return ()
        return (f"bond {b.number} points out of {self.label()} ({b.tail} -> {b.head}): its "
                "law holds for power flowing into it, so its flow (and momentum or "
                f"displacement) has the opposite sign; connect(..., {self.name!r}) is the usual "
                "direction. Silence with warnings.simplefilter('ignore', "
                "bondgraph.BondGraphWarning)",)

    def is_linear(self) -> bool:
        """Whether the law is ``c * own`` (and its inverse ``own / c``)."""
        if self.parameter is not None:
            return True
        for law, var in ((self.law, self.own), (self.inverse, self.inverse_own)):
            if isinstance(law, sympy.Expr):     # laws are expressions once the element is built
                if sympy.simplify(sympy.diff(law, var, 2)) != 0 or \
                        sympy.simplify(law.xreplace({var: 0})) != 0:
                    return False
        return True

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        dyn = sorted({str(s) for s in signals_of(self.law, self.inverse, self.parameter)} |
                     {str(T_SYM) for x in (self.law, self.inverse, self.parameter)
                      if isinstance(x, sympy.Basic) and x.has(T_SYM)})
        if dyn:
            return (f"{self.label()}: its law uses {', '.join(dyn)} (a modulated element); the "
                    "port-Hamiltonian form needs laws of the element's own variable only")
        return None

    def _modulated(self, local: LocalVariables, expr: sympy.Expr) -> sympy.Expr:
        """``expr`` with the signals of a modulated law resolved."""
        return local.resolve(expr) if self.signals() else expr

    def _linear(self, x: sympy.Expr) -> sympy.Expr:
        raise NotImplementedError

    def _linear_inverse(self, x: sympy.Expr) -> sympy.Expr:
        raise NotImplementedError

    def forward(self) -> sympy.Expr:
        """The law as a function of the own variable (``f(p)``, ``e(q)``, ``e(f)``)."""
        if self.law is not None:
            return self.law
        if self.parameter is not None:
            return self._linear(self.own)
        return self._invert(self.inverse, self.inverse_own, self.own, self.inverse_name)

    def _forward_at(self, x: sympy.Expr) -> sympy.Expr:
        """``forward()`` with the own variable replaced by ``x`` (a linear law built at once)."""
        if self.parameter is not None:
            return self._linear(x)
        return self.forward().xreplace({self.own: x})

    def _backward_at(self, x: sympy.Expr) -> sympy.Expr:
        """``backward()`` with the dual variable replaced by ``x``."""
        if self.parameter is not None:
            return self._linear_inverse(x)
        return self.backward().xreplace({self.inverse_own: x})

    def backward(self) -> sympy.Expr:
        """The inverse law, a function of the dual variable (``p(f)``, ``q(e)``, ``f(e)``)."""
        if self.inverse is not None:
            return self.inverse
        if self.parameter is not None:
            return self._linear_inverse(self.inverse_own)
        return self._invert(self.law, self.own, self.inverse_own, self.law_name)

    def _implicit_at(self, local: LocalVariables, sign: int, known: sympy.Expr,
                     unknown: sympy.Symbol) -> Optional[sympy.Expr]:
        """Residual of ``unknown = sign * law_at(known)`` written with the law that is
        given, for a law whose needed direction has no closed form: ``known -
        other_law(sign * unknown)``; None when neither direction is given."""
        if self.parameter is not None:
            return None
        if self.law is not None:          # the inverse was needed: known = law(sign*z)
            law = cast(sympy.Expr, self.law)
            return self._modulated(local, law.xreplace({self.own: sign * unknown})) - known
        if self.inverse is not None:      # the law was needed: known = inverse(sign*z)
            inverse = cast(sympy.Expr, self.inverse)
            return self._modulated(local, inverse.xreplace({self.inverse_own: sign * unknown})) - known
        return None

    def _invert(self, expr, var, new_var, name) -> sympy.Expr:
        """Invert one scalar law ``new_var = expr(var)`` (see :mod:`.inverse`).

        Only this element's own equation is solved, and only when exactly one
        solution exists; otherwise the user is asked for the inverse law.
        """
        try:
            sols = closed_form_inverse(expr, var, new_var)
        except (NotImplementedError, ValueError, TypeError) as exc:
            raise LawError(
                f"{self.label()}: its causality needs the inverse of the {name} law {expr}, "
                f"which sympy cannot solve for {var} ({str(exc).strip()}); pass the inverse law "
                "explicitly (inverse=...)") from exc
        if sols is None:
            raise LawError(
                f"{self.label()}: its causality needs the inverse of the {name} law {expr}, "
                f"for which sympy finds no closed form valid for both signs of {var}; pass "
                "the inverse law explicitly (inverse=...)")
        if len(sols) != 1:
            raise LawError(
                f"{self.label()}: its causality needs the inverse of the {name} law "
                f"{expr}, which has {len(sols)} solutions for {var}; pass the inverse "
                "law explicitly (inverse=...)"
            )
        return sols[0]


@dataclass(frozen=True, eq=False)
class _Storage(OnePort):
    """I or C: one state in integral causality (preferred), or derivative causality.

    The flow on the bond is signed (positive into the element), the effort not.
    """

    drawing_role: ClassVar[str] = "storage"
    #: whether it receives effort in integral causality (an I; a C receives flow)
    integral_effort_in: ClassVar[bool] = True
    state_prefix: ClassVar[str] = "p_"
    #: the signal that is its state: 'momentum' or 'displacement'
    energy_signal: ClassVar[str] = "momentum"

    def causal_choices(self, prefer_derivative: bool) -> Sequence[Choice]:
        if prefer_derivative:
            return (Choice(0, not self.integral_effort_in,
                           f"derivative causality of {self.label()}", STORAGE),)
        return (Choice(0, self.integral_effort_in, f"integral causality of {self.label()}",
                       STORAGE),)

    def causal_class(self, effort_in: Sequence[bool], free: Sequence[bool]) -> Optional[str]:
        return INTEGRAL if effort_in[0] == self.integral_effort_in else DERIVATIVE

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        return ((0,),) if causality == DERIVATIVE else ((),)

    def state_names(self, effort_in: Sequence[bool]) -> tuple[str, ...]:
        return (self.state_prefix + self.name,) if effort_in[0] == self.integral_effort_in else ()

    def derivative_ports(self, effort_in: Sequence[bool]) -> tuple[int, ...]:
        return () if effort_in[0] == self.integral_effort_in else (0,)

    def stored_names(self, effort_in: Sequence[bool]) -> tuple[str, ...]:
        return () if effort_in[0] == self.integral_effort_in else (self.state_prefix + self.name,)

    def energy_variable(self, variable: str) -> Optional[int]:
        return 0 if variable == self.energy_signal else None

    def energy_signals(self) -> tuple:
        return ((momentum_signal if self.energy_signal == "momentum" else
                 displacement_signal)(self.name),)

    def stored_energy(self, quantities: Sequence[sympy.Expr]) -> sympy.Expr:
        """``int_0^x phi(s) ds`` of its law ``phi`` (flow of p, effort of q) at ``x``."""
        (quantity,) = quantities
        if self.parameter is not None:       # linear: the familiar form
            return quantity**2 / (2 * self.parameter)
        try:
            law = self.forward()
        except LawError as exc:    # an inverse-only law that sympy cannot invert
            raise LawError(f"{self.label()}: its stored energy needs the {self.law_name} law as "
                           f"a function of {self.own}: {exc}") from exc
        s = sympy.Dummy("s", real=True)
        H = sympy.integrate(law.xreplace({self.own: s}), (s, 0, quantity))
        if H.has(sympy.Integral):
            raise LawError(f"{self.label()}: sympy cannot integrate its law {law} to the stored "
                           f"energy int_0^{self.own} ({law}) d{self.own}")
        return H

    def energy_hessian_inverse(self) -> Optional[sympy.ImmutableMatrix]:
        # H = x**2/(2*parameter): the Hessian's inverse is the parameter itself
        return sympy.ImmutableMatrix([[self.parameter]]) if self.parameter is not None else None

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        err = super().hamiltonian_error(dependent)
        if err is None and dependent and not self.is_linear():
            return (f"{self.label()} is in derivative causality with the nonlinear law "
                    f"{self.law if self.law is not None else self.inverse}; the reduced form "
                    "needs linear storage there (make it compliant, or linear)")
        return err

    def _signed(self, local: LocalVariables, x: sympy.Expr, is_flow: bool) -> sympy.Expr:
        return local.sign(0) * x if is_flow else x

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        if not local.states:  # pragma: no cover - derivation asks derivative_output
            raise AssertionError(f"{self.label()} is in derivative causality")
        out = self._forward_at(local.states[0])
        return self._modulated(local, self._signed(local, out, local.effort_in(0)))

    def implicit_output(self, local: LocalVariables, port: int,
                        unknown: sympy.Symbol) -> Optional[sympy.Expr]:
        if not local.states:
            return None
        sign = local.sign(0) if local.effort_in(0) else 1   # the flow of an I is signed
        return self._implicit_at(local, sign, local.states[0], unknown)

    def state_derivatives(self, local: LocalVariables) -> tuple[sympy.Expr, ...]:
        # dp/dt = e (an I receives effort), dq/dt = flow into the C
        return (self._signed(local, local.input(0), not local.effort_in(0)),)

    def stored(self, local: LocalVariables) -> tuple[sympy.Expr, ...]:
        dual = self._signed(local, local.input(0), not local.effort_in(0))
        return (self._modulated(local, self._backward_at(dual)),)

    def implicit_stored(self, local: LocalVariables,
                        unknowns: Sequence[sympy.Symbol]) -> Optional[tuple[sympy.Expr, ...]]:
        dual = self._signed(local, local.input(0), not local.effort_in(0))
        residual = self._implicit_at(local, 1, dual, unknowns[0])   # dual = law(unknown)
        return None if residual is None else (residual,)

    def derivative_output(self, local: LocalVariables, port: int,
                          rates: Sequence[sympy.Expr]) -> sympy.Expr:
        return self._signed(local, rates[0], local.effort_in(0))


@dataclass(frozen=True, eq=False)
class I(_Storage):
    """Inertia: stores momentum p.  Linear: ``f = p/I``.

    Parameters
    ----------
    name : str
    parameter : number, str or sympy expression, optional
        The inertance (mass, inertia, inductance).  Defaults to a positive
        symbol named after the element.
    law : expression in :data:`bondgraph.p`, optional
        Nonlinear flow law ``f = law(p)``.
    inverse : expression in :data:`bondgraph.f`, optional
        ``p = inverse(f)``, used in derivative causality.

    Examples
    --------
    >>> import bondgraph as bg
    >>> bg.I("m", 2).forward()
    p/2
    """

    kind: ClassVar[str] = "I"
    parameter_meaning: ClassVar[str] = "mass (inertance)"
    own: ClassVar[LawVariable] = P_VAR
    inverse_own: ClassVar[LawVariable] = F_VAR
    law_name: ClassVar[str] = "flow"
    inverse_name: ClassVar[str] = "momentum"

    def _linear(self, p):
        return p / self.parameter

    def _linear_inverse(self, f):
        return self.parameter * f


@dataclass(frozen=True, eq=False)
class C(_Storage):
    """Capacitance: stores displacement q.  Linear: ``e = q/C``.

    Parameters
    ----------
    name : str
    parameter : number, str or sympy expression, optional
        The compliance C.  Defaults to a positive symbol named after the element.
    law : expression in :data:`bondgraph.q`, optional
        Nonlinear effort law ``e = law(q)``.
    inverse : expression in :data:`bondgraph.e`, optional
        ``q = inverse(e)``, used in derivative causality.
    stiffness : number, str or sympy expression, optional
        Shorthand for the linear law ``e = stiffness*q``.

    Examples
    --------
    >>> import bondgraph as bg
    >>> bg.C("k", stiffness="k").forward()
    q*k
    """

    kind: ClassVar[str] = "C"
    parameter_meaning: ClassVar[str] = "compliance (capacitance)"
    integral_effort_in: ClassVar[bool] = False
    state_prefix: ClassVar[str] = "q_"
    energy_signal: ClassVar[str] = "displacement"
    own: ClassVar[LawVariable] = Q_VAR
    inverse_own: ClassVar[LawVariable] = E_VAR
    law_name: ClassVar[str] = "effort"
    inverse_name: ClassVar[str] = "displacement"
    stiffness: ParameterLike = field(default=None, kw_only=True)

    def __post_init__(self) -> None:
        if self.stiffness is not None:
            if self.parameter is not None or self.law is not None:
                raise LawError(f"C:{self.name}: give one of parameter, stiffness or law")
            k = nonzero(to_expr(self.stiffness, owner=f"C:{self.name}", what="stiffness"),
                        owner=f"C:{self.name}", what="stiffness")
            object.__setattr__(self, "law", k * Q_VAR)
            object.__setattr__(self, "inverse", E_VAR / k)
        super().__post_init__()

    def _linear(self, q):
        return q / self.parameter

    def _linear_inverse(self, e):
        return self.parameter * e

    def value_rules(self) -> tuple:
        if self.stiffness is not None and self.parameter is None:
            return rule(to_expr(self.stiffness, owner=f"C:{self.name}", what="stiffness"),
                        "stiffness")
        return super().value_rules()


@dataclass(frozen=True, eq=False)
class R(OnePort):
    """Resistance: ``e = R*f`` (or ``e = law(f)``, ``f = inverse(e)``).

    Parameters
    ----------
    name : str
    parameter : number, str or sympy expression, optional
    law : expression in :data:`bondgraph.f`, optional
        Effort as a function of flow.
    inverse : expression in :data:`bondgraph.e`, optional
        Flow as a function of effort.

    Examples
    --------
    >>> import bondgraph as bg
    >>> bg.R("d", law=bg.f*abs(bg.f)).forward()
    f*Abs(f)
    """

    kind: ClassVar[str] = "R"
    parameter_meaning: ClassVar[str] = "resistance"
    parameter_relation: ClassVar[str] = "nonnegative"
    own: ClassVar[LawVariable] = F_VAR
    inverse_own: ClassVar[LawVariable] = E_VAR
    law_name: ClassVar[str] = "effort"
    inverse_name: ClassVar[str] = "flow"

    def _linear(self, f):
        return self.parameter * f

    def _linear_inverse(self, e):
        return e / self.parameter

    def causal_choices(self, prefer_derivative: bool) -> Sequence[Choice]:
        return (Choice(0, False, f"arbitrary choice for {self.label()}", RESISTIVE),)

    def causal_class(self, effort_in: Sequence[bool], free: Sequence[bool]) -> Optional[str]:
        return ARBITRARY if free[0] else None

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        return ((0,),)

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        err = super().hamiltonian_error(dependent)
        if err is None and not self.is_linear():
            law = self.law if self.law is not None else self.inverse
            return (f"{self.label()}: the nonlinear law {law} makes the dissipation depend on "
                    "the state; the port-Hamiltonian form needs linear R elements (linearize "
                    "the model first)")
        return err

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        s, x = local.sign(0), local.input(0)
        if local.effort_in(0):   # f = inverse(e)
            out = s * self._backward_at(x)
        else:
            out = self._forward_at(s * x)
        return self._modulated(local, out)

    def implicit_output(self, local: LocalVariables, port: int,
                        unknown: sympy.Symbol) -> Optional[sympy.Expr]:
        s, x = local.sign(0), local.input(0)
        if local.effort_in(0):   # unknown = s*inverse(e): e = law(s*unknown)
            return self._implicit_at(local, s, x, unknown)
        return self._implicit_at(local, 1, s * x, unknown)   # s*f = inverse(unknown)



