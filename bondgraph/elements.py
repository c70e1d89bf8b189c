"""Bond-graph elements: frozen values describing each node of a graph.

Conventions
-----------
Every bond has a power direction, from its *tail* to its *head* (the
half-arrow end); ``e*f`` is the power flowing that way.

* ``Se``, ``Sf`` -- effort and flow sources; each is an input ``u`` named after
  the element.  A source's bond normally points away from it.
* ``I`` stores momentum ``p``; a linear I has ``f = p/I``.
* ``C`` stores displacement ``q``; a linear C has ``e = q/C`` (C is a
  compliance; pass ``stiffness=k`` for ``e = k*q``).
* ``R`` dissipates; a linear R has ``e = R*f``.
* One-port laws are written for power flowing *into* the element; a bond
  that points away from an I, C or R flips the sign of its flow.
* ``TF`` with modulus ``n``: ``e1 = n*e2`` and ``f2 = n*f1``, where port 1
  is the bond into the TF and port 2 the bond out of it.
* ``GY`` with modulus ``r``: ``e1 = r*f2`` and ``e2 = r*f1``.
* ``MTF`` and ``MGY`` are the same with a modulus that may depend on
  signals (states, efforts, flows, displacements) and on time :data:`t`.
* ``Zero``: common effort, flows sum to zero (signed by bond direction).
  ``One``: common flow, efforts sum to zero.
* ``Port``: an external port of a graph used as a sub-model.

Parameters default to a positive sympy symbol named after the element (with
its hierarchical path, ``motor.Ra``); a number, a symbol, an expression or an
identifier string may be given instead.

Nonlinear laws are sympy expressions in the element's own variable
(:data:`bondgraph.p`, :data:`~bondgraph.q`, :data:`~bondgraph.e`,
:data:`~bondgraph.f`) or callables taking it.

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

import keyword
import numbers
import re
from dataclasses import dataclass, field, replace
from typing import Callable, ClassVar, Optional, Union

import sympy

from .errors import LawError, ModelStructureError, ParameterError
from .values import ParameterLike, nonzero, to_expr
from .signals import LawVariable, Signal, e as E_VAR, f as F_VAR, p as P_VAR, q as Q_VAR, t as T_SYM

__all__ = [
    "Element",
    "OnePort",
    "TwoPort",
    "Se",
    "Sf",
    "I",
    "C",
    "R",
    "TF",
    "GY",
    "MTF",
    "MGY",
    "Zero",
    "One",
    "Port",
    "ParameterLike",
]

LawLike = Union[None, sympy.Expr, Callable[[sympy.Symbol], sympy.Expr]]

_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def check_name(name: object, what: str) -> str:
    """Validate an element or graph name: an identifier without dots."""
    if not isinstance(name, str) or not _NAME.fullmatch(name) or keyword.iskeyword(name):
        raise ModelStructureError(
            f"{what} name {name!r} is not valid: expected an identifier such as "
            "'Ra' or 'motor' (letters, digits, underscores; no dots, which separate "
            "sub-model paths)"
        )
    return name


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
class Element:
    """Base of all elements.  ``name`` is local to the graph holding it.

    Parameters
    ----------
    name : str
        An identifier without dots, unique within its graph.

    Examples
    --------
    >>> import bondgraph as bg
    >>> el = bg.R("b")
    >>> isinstance(el, bg.Element), el.label(), el.bonds
    (True, 'R:b', (1, 1))
    >>> el.resolved("motor.b").name
    'motor.b'
    """

    name: str
    kind: ClassVar[str] = "?"
    #: (minimum, maximum) number of bonds; None for unbounded
    bonds: ClassVar[tuple[int, Optional[int]]] = (1, 1)

    def __post_init__(self) -> None:
        check_name(self.name, self.kind)

    def label(self) -> str:
        """``KIND:name`` as drawn on a bond graph."""
        return f"{self.kind}:{self.name}"

    def resolved(self, path: str) -> "Element":
        """A copy named ``path`` with default parameters filled in."""
        return _rename(self, path)

    def signals(self) -> frozenset:
        """Signals used by this element's laws (modulated elements)."""
        return frozenset()


def _rename(el: Element, path: str) -> Element:
    obj = object.__new__(type(el))
    for fld in el.__dataclass_fields__:
        object.__setattr__(obj, fld, getattr(el, fld))
    object.__setattr__(obj, "name", path)
    return obj


def _prefix_signals(expr: Optional[sympy.Expr], prefix: str) -> Optional[sympy.Expr]:
    if expr is None or not prefix:
        return expr
    sig = {s: s.retarget(prefix + s.target) for s in expr.free_symbols
           if isinstance(s, Signal) and isinstance(s.target, str)}
    return expr.xreplace(sig) if sig else expr


def _signals_of(*exprs) -> frozenset:
    out = set()
    for ex in exprs:
        if ex is not None:
            out |= {s for s in ex.free_symbols if isinstance(s, Signal)}
    return frozenset(out)


@dataclass(frozen=True, eq=False)
class _Source(Element):
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
        el = _rename(self, path)
        object.__setattr__(el, "value", _prefix_signals(self.value, path[: len(path) - len(self.name)]))
        return el

    def signals(self) -> frozenset:
        return _signals_of(self.value)


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


@dataclass(frozen=True, eq=False)
class OnePort(Element):
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

    def resolved(self, path: str) -> Element:
        el = _rename(self, path)
        prefix = path[: len(path) - len(self.name)]
        if self.parameter is None and self.law is None and self.inverse is None:
            object.__setattr__(el, "parameter", sympy.Symbol(path, positive=True))
        object.__setattr__(el, "law", _prefix_signals(self.law, prefix))
        object.__setattr__(el, "inverse", _prefix_signals(self.inverse, prefix))
        return el

    def signals(self) -> frozenset:
        return _signals_of(self.law, self.inverse, self.parameter)

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

    def backward(self) -> sympy.Expr:
        """The inverse law, a function of the dual variable (``p(f)``, ``q(e)``, ``f(e)``)."""
        if self.inverse is not None:
            return self.inverse
        if self.parameter is not None:
            return self._linear_inverse(self.inverse_own)
        return self._invert(self.law, self.own, self.inverse_own, self.law_name)

    def _invert(self, expr, var, new_var, name) -> sympy.Expr:
        """Invert one scalar law ``new_var = expr(var)`` with ``sympy.solve``.

        Only this element's own equation is solved, and only when exactly one
        solution exists; otherwise the user is asked for the inverse law.
        """
        try:
            sols = sympy.solve(sympy.Eq(expr, new_var), var, dict=False)
        except (NotImplementedError, ValueError, TypeError) as exc:
            raise LawError(
                f"{self.label()}: its causality needs the inverse of the {name} law {expr}, "
                f"which sympy cannot solve for {var} ({str(exc).strip()}); pass the inverse law "
                "explicitly (inverse=...)") from exc
        if len(sols) != 1:
            raise LawError(
                f"{self.label()}: its causality needs the inverse of the {name} law "
                f"{expr}, which has {len(sols)} solutions for {var}; pass the inverse "
                "law explicitly (inverse=...)"
            )
        return sols[0]


@dataclass(frozen=True, eq=False)
class I(OnePort):
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
    own: ClassVar[LawVariable] = P_VAR
    inverse_own: ClassVar[LawVariable] = F_VAR
    law_name: ClassVar[str] = "flow"
    inverse_name: ClassVar[str] = "momentum"

    def _linear(self, p):
        return p / self.parameter

    def _linear_inverse(self, f):
        return self.parameter * f


@dataclass(frozen=True, eq=False)
class C(OnePort):
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
    own: ClassVar[LawVariable] = F_VAR
    inverse_own: ClassVar[LawVariable] = E_VAR
    law_name: ClassVar[str] = "effort"
    inverse_name: ClassVar[str] = "flow"

    def _linear(self, f):
        return self.parameter * f

    def _linear_inverse(self, e):
        return e / self.parameter


@dataclass(frozen=True, eq=False)
class TwoPort(Element):
    """Two-port element with a modulus: base of TF, GY, MTF and MGY.

    Parameters
    ----------
    name : str
    modulus : number, str or sympy expression, optional
        Defaults to a positive symbol named after the element's path.
    efficiency : number, str or sympy expression, optional
        Constant power efficiency (keyword only); 1 when not given.

    Examples
    --------
    >>> import bondgraph as bg
    >>> gear = bg.TF("gear", 3, efficiency=0.9)
    >>> isinstance(gear, bg.elements.TwoPort), gear.modulus, gear.bonds
    (True, 3, (2, 2))
    >>> bg.GY("K").resolved("motor.K").modulus
    motor.K
    """

    modulus: ParameterLike = None
    efficiency: ParameterLike = field(default=None, kw_only=True)
    bonds: ClassVar[tuple[int, Optional[int]]] = (2, 2)
    modulated: ClassVar[bool] = False

    def __post_init__(self) -> None:
        super().__post_init__()
        owner = self.label()
        eff = nonzero(to_expr(self.efficiency, owner=owner, what="efficiency"),
                      owner=owner, what="efficiency")
        if eff is not None and (eff.free_symbols & {T_SYM} or
                                any(isinstance(s, (Signal, LawVariable)) for s in eff.free_symbols)):
            raise ParameterError(f"{owner}: efficiency {eff} must be a constant parameter")
        object.__setattr__(self, "efficiency", sympy.Integer(1) if eff is None else eff)
        mod = nonzero(to_expr(self.modulus, owner=owner, what="modulus"), owner=owner,
                      what="modulus")
        if mod is None and self.modulated:
            raise ParameterError(f"{owner}: a modulated element needs modulus=<expression>")
        if mod is not None:
            dyn = [str(s) for s in mod.free_symbols if isinstance(s, (Signal, LawVariable)) or s == T_SYM]
            if dyn and not self.modulated:
                raise ParameterError(
                    f"{owner}: modulus {mod} depends on {', '.join(sorted(dyn))}; "
                    f"use M{self.kind} for a modulated {self.kind}"
                )
            law_vars = [str(s) for s in mod.free_symbols if isinstance(s, LawVariable)]
            if law_vars:
                raise ParameterError(
                    f"{owner}: modulus {mod} uses {', '.join(law_vars)}; a modulus may use "
                    "signals (bondgraph.displacement('J'), ...) and time bondgraph.t"
                )
        object.__setattr__(self, "modulus", mod)

    def resolved(self, path: str) -> Element:
        el = _rename(self, path)
        prefix = path[: len(path) - len(self.name)]
        if self.modulus is None:
            object.__setattr__(el, "modulus", sympy.Symbol(path, positive=True))
        else:
            object.__setattr__(el, "modulus", _prefix_signals(self.modulus, prefix))
        return el

    def signals(self) -> frozenset:
        return _signals_of(self.modulus)


@dataclass(frozen=True, eq=False)
class TF(TwoPort):
    """Transformer: ``e1 = n*e2``, ``f2 = n*f1`` (port 1 = bond in).

    ``efficiency=eta`` makes it lossy the way servo-motor data sheets do
    (Quanser SRV-02 gearbox): ``f2 = n*f1`` still, but ``e2 = eta*e1/n``, so
    the power out of port 2 is ``eta`` times the power into port 1.  This is
    exact in the motoring quadrant (power from port 1 to port 2).

    Examples
    --------
    >>> TF("gear", 14).modulus
    14
    """

    kind: ClassVar[str] = "TF"


@dataclass(frozen=True, eq=False)
class GY(TwoPort):
    """Gyrator: ``e1 = r*f2``, ``e2 = r*f1``.

    ``efficiency=eta`` gives ``e2 = eta*r*f1`` with ``e1 = r*f2`` unchanged
    (a DC motor whose torque is ``eta_m*k*i`` and back-emf ``k*w``).

    Examples
    --------
    >>> GY("K").label()
    'GY:K'
    """

    kind: ClassVar[str] = "GY"


@dataclass(frozen=True, eq=False)
class MTF(TwoPort):
    """Modulated transformer; the modulus may use signals and time.

    Examples
    --------
    >>> import bondgraph as bg, sympy
    >>> yoke = bg.MTF("yoke", modulus=sympy.Symbol("r")*sympy.sin(bg.displacement("crank")))
    >>> sorted(str(s) for s in yoke.signals())
    ['displacement[crank]']
    """

    kind: ClassVar[str] = "MTF"
    modulated: ClassVar[bool] = True


@dataclass(frozen=True, eq=False)
class MGY(TwoPort):
    """Modulated gyrator; the modulus may use signals and time.

    Examples
    --------
    >>> import bondgraph as bg
    >>> MGY("g", modulus=2*bg.t).kind
    'MGY'
    """

    kind: ClassVar[str] = "MGY"
    modulated: ClassVar[bool] = True


@dataclass(frozen=True, eq=False)
class Zero(Element):
    """0-junction: common effort, signed flows sum to zero.

    Examples
    --------
    >>> Zero("node").bonds
    (2, None)
    """

    kind: ClassVar[str] = "0"
    bonds: ClassVar[tuple[int, Optional[int]]] = (2, None)


@dataclass(frozen=True, eq=False)
class One(Element):
    """1-junction: common flow, signed efforts sum to zero.

    Examples
    --------
    >>> One("w").label()
    '1:w'
    """

    kind: ClassVar[str] = "1"
    bonds: ClassVar[tuple[int, Optional[int]]] = (2, None)


@dataclass(frozen=True, eq=False)
class Port(Element):
    """External port of a graph used as a sub-model (exactly one inner bond).

    Examples
    --------
    >>> Port("shaft").label()
    'Port:shaft'
    """

    kind: ClassVar[str] = "Port"
