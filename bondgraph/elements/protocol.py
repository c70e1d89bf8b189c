"""The element protocol: what an element kind does, supplied by the element class.

Causality (:mod:`bondgraph.causality`), derivation (:mod:`bondgraph.equations`),
the builder's checks (:mod:`bondgraph.graph`, :mod:`bondgraph.flatten`) and the
drawings (:mod:`bondgraph.drawing`) never test what kind an element is: they
ask the element.  Every element class derives from :class:`Element` and answers
four groups of questions, always about its own *ports*: port ``p`` is its
``p``-th bond in creation order (``flat.incidence[name][p]``).

Port rules
    :attr:`Element.bonds` (how many bonds), :meth:`Element.bond_error` (may this
    bond be added, asked by ``BondGraph.connect``),
    :meth:`Element.structure_error` (are the final bonds right, asked when a
    graph is flattened for causality), :meth:`Element.bond_warnings` (legal but
    suspicious directions, warned by ``derive``).
Causal behaviour (SCAP)
    Stated with ``effort_in[p]``: does the element *receive* the effort of port
    ``p`` (the causal stroke is at its end of the bond)?  SCAP passes a
    :class:`CausalPorts` view of the partly decided ports.

    * :meth:`Element.forced_causality` -- decisions at the start (sources);
      elements that force decisions are the origins from which SCAP measures
      distances;
    * :meth:`Element.propagate` -- given the ports decided so far, the
      :class:`Decision` s that follow (junction: exactly one strong bond; TF:
      effort passes through; GY: both or neither), or a
      :class:`~bondgraph.errors.CausalityConflictError` naming the element and
      its bonds;
    * :meth:`Element.causal_choices` -- :class:`Choice` points, each with a
      preferred value and a priority (storage: integral preferred, derivative
      when asked; R: arbitrary); SCAP orders them by priority, then distance
      from the origins, then name, and backtracks over them;
    * :meth:`Element.causal_class` -- after causality, ``'integral'``,
      ``'derivative'`` or ``'arbitrary'`` (or None);
    * :meth:`Element.output_dependencies` -- which ports' input variables each
      port's output variable is computed from (causal order, algebraic loops).
Variables and constitutive relations (derivation)
    On each port the element computes one *output* variable (the flow where it
    receives effort, the effort where it receives flow) from its *input*
    variables, its states and its input symbol.  Derivation passes a
    :class:`LocalVariables` view.

    * :meth:`Element.state_names` -- the states it contributes, given its
      causality (``p_m`` for an I in integral causality, ``q_k``);
    * :meth:`Element.derivative_ports` and :meth:`Element.stored_names` -- the
      ports in derivative causality and the stored quantities their outputs
      are the time derivatives of (an I in derivative causality: port 0, ``p_m``);
    * :meth:`Element.input_name` -- the model input it introduces (an unvalued
      source), or None;
    * :meth:`Element.output` -- the constitutive relation: the output variable
      on a port (every port but the derivative ones);
    * :meth:`Element.state_derivatives` -- ``dx/dt`` of its states;
    * :meth:`Element.stored` and :meth:`Element.derivative_output` -- its stored
      quantities from its inputs and states, and the outputs of its derivative
      ports from their time derivatives;
    * :meth:`Element.signal_port` and :meth:`Element.energy_variable` -- which
      bond variable or state ``bg.effort(name)``, ``bg.flow(name)``,
      ``bg.momentum(name)``, ``bg.displacement(name)`` mean;
      :meth:`Element.port_signal` and :meth:`Element.port_energy_variable` the
      same for one port of a multiport, ``bg.flow(name, port=k)``.
Energy (the port-Hamiltonian form, :mod:`bondgraph.hamiltonian`)
    * :meth:`Element.energy_signals` -- the signals of its stored quantities
      (``bg.momentum(name)`` of an I), in the order of :meth:`state_names` in
      integral causality; empty for an element that stores no energy;
    * :meth:`Element.stored_energy` -- its energy from those quantities
      (``p**2/(2 m)``, ``q^T K q / 2``);
    * :meth:`Element.energy_hessian_inverse` -- the inverse of its energy's
      Hessian when known without inverting (a mass or compliance matrix);
    * :meth:`Element.hamiltonian_error` -- why it has no constant
      port-Hamiltonian form (a modulated two-port, a nonlinear R, a valued
      source), or None;
    * :meth:`Element.conserves_power` -- False for a lossy two-port;
    * :meth:`Element.collocated_output` -- for an input, the name and signal
      of its power-conjugate output (``f_V``, the flow out of an ``Se``).
Values
    :meth:`Element.value_rules` -- what its parameters must be (a mass positive,
    a resistance not negative; :mod:`bondgraph.elements.rules`), checked at
    construction for numbers and at every numeric evaluation for symbols;
    :meth:`Element.check_values` checks them at given values.
Drawing
    :meth:`Element.drawing_label` (text and note) and
    :attr:`Element.drawing_role` (where the layout puts it).

Every relation is written in *bond variables*: the effort of a bond and its
flow in the bond's power direction; ``local.sign(p)`` is +1 when port ``p``'s
bond points into the element, -1 otherwise (a one-port's flow *into* it is
``sign*f``).

A multiport field (n ports, a matrix or an energy function;
:mod:`bondgraph.elements.fields`) is a class like any other: ``bonds = (n, n)``;
``causal_choices`` with one :class:`Choice` per port; ``causal_class`` from
all its ports; ``state_names`` for its integral ports and
``derivative_ports`` / ``stored_names`` for the others (mixed causality
included: the outputs of its integral ports may read the inputs of its
derivative ports); ``output`` / ``state_derivatives`` / ``stored`` /
``derivative_output`` over its ports; ``port_signal`` and
``port_energy_variable`` for ``bg.flow(name, port=k)``; ``energy_signals``
and ``stored_energy`` for its energy.

Examples
--------
A user-defined element: a magnetorheological damper, ``e = (c0 + c1*i)*f``
with ``i`` a signal of the model (its coil current).

>>> from dataclasses import dataclass
>>> from typing import ClassVar
>>> import sympy
>>> import bondgraph as bg
>>> from bondgraph.elements.protocol import Choice, RESISTIVE, ARBITRARY
>>> @dataclass(frozen=True, eq=False)
... class MRDamper(bg.Element):
...     c0: sympy.Expr = sympy.Symbol("c0", positive=True)
...     c1: sympy.Expr = sympy.Symbol("c1", positive=True)
...     current: sympy.Expr = None
...     kind: ClassVar[str] = "MR"
...     drawing_role: ClassVar[str] = "dissipative"
...     def signals(self):
...         return frozenset({self.current})
...     def causal_choices(self, prefer_derivative):
...         return (Choice(0, False, f"arbitrary choice for {self.label()}", RESISTIVE),)
...     def causal_class(self, effort_in, free):
...         return ARBITRARY if free[0] else None
...     def output_dependencies(self, effort_in, causality):
...         return ((0,),)
...     def signal_port(self, variable):
...         return (0, variable == "flow")
...     def output(self, local, port):
...         c = local.resolve(self.c0 + self.c1 * self.current)
...         x, s = local.input(0), local.sign(0)
...         return s * x / c if local.effort_in(0) else c * s * x
>>> g = bg.BondGraph("car")
>>> g.add(bg.Se("F"), bg.One("v"), bg.I("m"), MRDamper("d", current=bg.flow("coil")))
>>> g.add(bg.Se("V"), bg.One("i"), bg.R("Rc"), bg.I("coil"))
>>> for t, h in [("F", "v"), ("v", "m"), ("v", "d"), ("V", "i"), ("i", "Rc"), ("i", "coil")]:
...     _ = g.connect(t, h)
>>> bg.derive(g).rhs[0]
F - p_m*(c0 + c1*p_coil/coil)/m
"""

from __future__ import annotations

import dataclasses
import keyword
import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, NamedTuple, Optional, Sequence

import sympy

from ..errors import ModelStructureError, OutputError
from ..signals import Signal

if TYPE_CHECKING:  # pragma: no cover
    from .bond import Bond

__all__ = [
    "Element", "Decision", "Choice", "CausalPorts", "LocalVariables",
    "STORAGE", "RESISTIVE", "INTEGRAL", "DERIVATIVE", "ARBITRARY",
    "check_name", "drawing_role", "prefix_signals", "signals_of",
]

#: choice priority of storage elements (decided first)
STORAGE = 0
#: choice priority of resistive elements whose causality is free (algebraic loops)
RESISTIVE = 1

#: causal classes returned by :meth:`Element.causal_class`
INTEGRAL = "integral"
DERIVATIVE = "derivative"
ARBITRARY = "arbitrary"

#: element class of each kind string (the drawing asks for roles by kind)
_BY_KIND: dict[str, "type[Element]"] = {}

_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def check_name(name: object, what: str) -> str:
    """Validate an element or graph name: an identifier without dots.

    Examples
    --------
    >>> check_name("Ra", "R")
    'Ra'
    """
    if not isinstance(name, str) or not _NAME.fullmatch(name) or keyword.iskeyword(name):
        raise ModelStructureError(
            f"{what} name {name!r} is not valid: expected an identifier such as "
            "'Ra' or 'motor' (letters, digits, underscores; no dots, which separate "
            "sub-model paths)"
        )
    return name


class Decision(NamedTuple):
    """A causal decision on one port: the element receives effort there iff ``effort_in``.

    ``reason`` is kept with the bond and quoted by later conflict messages.

    Examples
    --------
    >>> Decision(0, True, "source Sf:Q")
    Decision(port=0, effort_in=True, reason='source Sf:Q')
    """

    port: int
    effort_in: bool
    reason: str


class Choice(NamedTuple):
    """A choice point of SCAP on one port: the value tried first, and its priority.

    SCAP makes the choices of lower ``priority`` first (:data:`STORAGE`
    before :data:`RESISTIVE`), then those nearest an origin, then by element
    name; on a conflict it backtracks and tries ``not effort_in``.

    Examples
    --------
    >>> Choice(0, True, "integral causality of I:m", STORAGE).priority
    0
    """

    port: int
    effort_in: bool
    reason: str
    priority: int


class CausalPorts:
    """The view of an element's ports that SCAP gives the causal rules.

    Attributes
    ----------
    count : int
        Number of ports.
    undecided : int
        Ports whose causality is still open.
    efforts_in : int
        Decided ports on which the element receives effort (counters, so a
        rule can be constant time on a junction with many bonds).
    """

    count: int
    undecided: int
    efforts_in: int

    def effort_in(self, port: int) -> Optional[bool]:
        """Whether the element receives effort on ``port``; None while undecided."""
        raise NotImplementedError

    def open(self) -> list[int]:
        """The undecided ports, in order."""
        raise NotImplementedError

    def reason(self, port: int) -> str:
        """What decided ``port`` (for conflict messages)."""
        raise NotImplementedError

    def number(self, port: int) -> int:
        """The bond number of ``port``."""
        raise NotImplementedError

    def into(self, port: int) -> bool:
        """Whether ``port``'s bond points into the element."""
        raise NotImplementedError


class LocalVariables:
    """The view of an element's variables that derivation gives the constitutive relations.

    Attributes
    ----------
    count : int
        Number of ports.
    states : tuple of sympy.Symbol
        The element's states (integral causality), in the order of
        :meth:`Element.state_names`; empty otherwise.
    input_symbol : sympy.Symbol or None
        The model input named by :meth:`Element.input_name`.
    """

    count: int
    states: tuple
    input_symbol: Optional[sympy.Symbol]

    def sign(self, port: int) -> int:
        """+1 when ``port``'s bond points into the element, -1 otherwise."""
        raise NotImplementedError

    def into(self, port: int) -> bool:
        """Whether ``port``'s bond points into the element."""
        raise NotImplementedError

    def effort_in(self, port: int) -> bool:
        """Whether the element receives effort on ``port``."""
        raise NotImplementedError

    def input(self, port: int) -> sympy.Expr:
        """The input variable of ``port`` (its effort where the element receives effort,
        else its flow), as a bond variable."""
        raise NotImplementedError

    def resolve(self, expr: sympy.Expr) -> sympy.Expr:
        """``expr`` with its signals (``bg.flow('m')``, ...) replaced by model variables."""
        raise NotImplementedError


@dataclass(frozen=True, eq=False)
class Element:
    """Base of all elements: a name, and the element protocol (see :mod:`bondgraph.elements.protocol`).

    Subclasses are frozen dataclasses (``@dataclass(frozen=True, eq=False)``)
    that set the class variable ``kind`` (``'R'``, ``'TF'``, ``'0'``, ...:
    drawn in labels, and the key of :func:`drawing_role`) and override the
    protocol methods their behaviour needs.  The defaults describe an element
    with no causal constraint, no choices, no states and no input.

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
    #: where the drawing puts it: 'source', 'storage' (leaves drawn above),
    #: 'dissipative' (leaves drawn below), 'junction' or 'backbone'
    drawing_role: ClassVar[str] = "backbone"
    #: appended to a conflict message on one of its bonds
    conflict_hint: ClassVar[str] = ""

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        if "kind" in cls.__dict__:
            _BY_KIND.setdefault(cls.kind, cls)

    def __post_init__(self) -> None:
        check_name(self.name, self.kind)

    def label(self) -> str:
        """``KIND:name`` as drawn on a bond graph."""
        return f"{self.kind}:{self.name}"

    def resolved(self, path: str) -> "Element":
        """A copy named ``path`` with default parameters filled in."""
        return rename(self, path)

    def signals(self) -> frozenset:
        """Signals used by this element's laws (modulated elements)."""
        return frozenset()

    # ------------------------------------------------------------ port rules
    def bond_error(self, existing: Sequence["Bond"], bond: "Bond") -> Optional[str]:
        """Why ``bond`` may not be added to the element's ``existing`` bonds, or None.

        Asked by :meth:`bondgraph.BondGraph.connect` before the bond is added;
        the message names the element and is prefixed with the graph.
        """
        _, most = self.bonds
        if most is not None and len(existing) >= most:
            nums = ", ".join(str(b.number) for b in existing)
            return (f"element {self.label()} takes {most} bond{'s' if most > 1 else ''} and "
                    f"already has bond {nums}; cannot add bond {bond.tail} -> {bond.head}")
        return None

    def structure_error(self, bonds: Sequence["Bond"]) -> Optional[str]:
        """What is wrong with the element's final ``bonds`` (flattened graph), or None."""
        least, most = self.bonds
        n = len(bonds)
        if n < least or (most is not None and n > most):
            want = f"{least}" if least == most else f"at least {least}"
            return (f"element {self.label()} has {n} bond{'s' if n != 1 else ''}; expected "
                    f"{want}" + ("" if n else " (connect it, or remove it from the graph)"))
        return None

    def bond_warnings(self, bonds: Sequence["Bond"]) -> tuple[str, ...]:
        """Warnings about legal but suspicious bond directions (``derive`` warns them)."""
        return ()

    # ------------------------------------------------------------ causality
    def forced_causality(self, ports: CausalPorts) -> Sequence[Decision]:
        """Decisions SCAP makes at the start (a source's), before any choice."""
        return ()

    def propagate(self, ports: CausalPorts) -> Sequence[Decision]:
        """Decisions that follow from the ports decided so far.

        Raises
        ------
        CausalityConflictError
            When the decided ports break the element's rule; the message names
            the element, the bonds and what decided them.
        """
        return ()

    def causal_choices(self, prefer_derivative: bool) -> Sequence[Choice]:
        """SCAP's choice points on this element; ``prefer_derivative`` asks storage to try
        derivative causality first."""
        return ()

    def causal_class(self, effort_in: Sequence[bool], free: Sequence[bool]) -> Optional[str]:
        """:data:`INTEGRAL`, :data:`DERIVATIVE`, :data:`ARBITRARY` or None, once every
        port is decided; ``free[p]``: port ``p``'s choice point was free when reached."""
        return None

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        """Per port, the ports whose input variables its output variable is computed from.

        ``causality`` is the element's :meth:`causal_class`.  The order is the
        order of evaluation (it decides where a junction-structure cycle is torn).
        """
        raise NotImplementedError(f"{self.label()}: {type(self).__name__} does not define "
                                  "output_dependencies (see bondgraph.elements.protocol)")

    # ------------------------------------------------------------ derivation
    def state_names(self, effort_in: Sequence[bool]) -> tuple[str, ...]:
        """Names of the states the element contributes in this causality."""
        return ()

    def derivative_ports(self, effort_in: Sequence[bool]) -> tuple[int, ...]:
        """The ports in derivative causality: their outputs are time derivatives of
        the :meth:`stored_names` quantities (see :meth:`derivative_output`)."""
        return ()

    def stored_names(self, effort_in: Sequence[bool]) -> tuple[str, ...]:
        """Names of the stored quantities behind the :meth:`derivative_ports` (algebraic
        functions of the inputs, never states)."""
        return ()

    def input_name(self) -> Optional[str]:
        """Name of the model input the element introduces, or None."""
        return None

    def signal_port(self, variable: str) -> Optional[tuple[int, bool]]:
        """The port whose bond carries the element's ``'effort'`` or ``'flow'``, and
        whether the value is signed by the bond direction (``sign*f``); None when
        the element has no single such variable."""
        return None

    def energy_variable(self, variable: str) -> Optional[int]:
        """Index of the state (or, in derivative causality, of the stored quantity)
        that ``bg.momentum(name)`` / ``bg.displacement(name)`` (``variable``) means,
        or None (then an integrator state is added)."""
        return None

    def port_signal(self, variable: str, port: int) -> Optional[tuple[int, bool]]:
        """:meth:`signal_port` for ``bg.effort(name, port=k)`` / ``bg.flow(name, port=k)``
        (``port`` 1-based); only multiport fields have numbered ports."""
        raise OutputError(f"signal {variable}[{self.name}][{port}]: {self.label()} is not a "
                          f"multiport field; write bg.{variable}({self.name!r}) without port=, "
                          "or name a bond number")

    def port_energy_variable(self, variable: str, port: int,
                             effort_in: Sequence[bool]) -> Optional[int]:
        """:meth:`energy_variable` for ``bg.momentum(name, port=k)``: the index in the
        element's states followed by its stored quantities, or None."""
        return self.port_signal(variable, port) and None

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        """The constitutive relation: the output variable of ``port``.

        Asked for every port except the :meth:`derivative_ports` (see
        :meth:`derivative_output`).
        """
        raise NotImplementedError(f"{self.label()}: {type(self).__name__} does not define "
                                  "output (see bondgraph.elements.protocol)")

    def implicit_output(self, local: LocalVariables, port: int,
                        unknown: sympy.Symbol) -> Optional[sympy.Expr]:
        """When :meth:`output` has no closed form (a law with no symbolic inverse), the
        residual ``r`` with ``r = 0`` defining the output ``unknown``; None otherwise.

        Asked only after :meth:`output` raised :class:`~bondgraph.errors.LawError`;
        the derivation then keeps ``unknown`` as an algebraic variable of an
        implicit model ``x' = f(x, z, u)``, ``0 = g(x, z, u)``.
        """
        return None

    def state_derivatives(self, local: LocalVariables) -> tuple[sympy.Expr, ...]:
        """``dx/dt`` of each state (:meth:`state_names`) from the input variables."""
        return ()

    def stored(self, local: LocalVariables) -> tuple[sympy.Expr, ...]:
        """The stored quantities (:meth:`stored_names`) from the input variables and
        the states."""
        return ()

    def implicit_stored(self, local: LocalVariables,
                        unknowns: Sequence[sympy.Symbol]) -> Optional[tuple[sympy.Expr, ...]]:
        """When :meth:`stored` has no closed form (a law with no symbolic inverse), the
        residuals ``r`` with ``r = 0`` defining the stored quantities ``unknowns``; None
        otherwise.

        Asked only after :meth:`stored` raised :class:`~bondgraph.errors.LawError`;
        the derivation then keeps ``unknowns`` as algebraic variables and
        differentiates the residuals for their rates
        (:mod:`bondgraph.equations.dependent`).
        """
        return None

    def derivative_output(self, local: LocalVariables, port: int,
                          rates: Sequence[sympy.Expr]) -> sympy.Expr:
        """The output variable of a derivative ``port`` from the time derivatives of
        :meth:`stored`."""
        raise NotImplementedError(f"{self.label()}: {type(self).__name__} is in derivative "
                                  "causality but does not define derivative_output")

    # ------------------------------------------------------------ energy
    def energy_signals(self) -> tuple:
        """Signals of the quantities it stores (``bg.momentum(name)`` of an I), in the
        order of :meth:`state_names` in integral causality; () if it stores nothing."""
        return ()

    def stored_energy(self, quantities: Sequence[sympy.Expr]) -> sympy.Expr:
        """Its stored energy, given the values of :meth:`energy_signals`."""
        return sympy.Integer(0)

    def energy_hessian_inverse(self) -> Optional[sympy.ImmutableMatrix]:
        """The inverse of the Hessian of :meth:`stored_energy` when it is constant and known
        without inverting (``[[m]]`` of a linear I, the mass matrix of an ``IField``), or None."""
        return None

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        """Why the element prevents a constant port-Hamiltonian form (naming it), or None;
        ``dependent``: it is in derivative causality."""
        return None

    def conserves_power(self) -> bool:
        """False for a two-port whose efficiency is not 1."""
        return True

    def collocated_output(self) -> Optional[tuple[str, sympy.Expr]]:
        """For an element that introduces an input: the name and signal of the output
        power-conjugate to it (``('f_V', -bg.flow('V'))`` for an ``Se``)."""
        return None

    # ------------------------------------------------------------ values
    def value_rules(self) -> tuple:
        """What its parameters must be: :class:`~bondgraph.elements.rules.ValueRule` s
        (a mass positive, a resistance not negative), checked at construction for
        numbers and at every numeric evaluation for symbols; empty by default."""
        return ()

    def check_values(self, values) -> None:
        """Check :meth:`value_rules` at parameter ``values`` (name or Symbol -> number);
        a :class:`~bondgraph.errors.ParameterValueError` names the element and the parameter."""
        from .rules import check_values
        check_values((self,), values)

    # ------------------------------------------------------------ units
    def domain_groups(self, count: int) -> tuple[tuple[int, ...], ...]:
        """Groups of ports whose bonds share one physical domain (:mod:`bondgraph.library.units`):
        all ``count`` ports by default; a TF or GY may join two domains."""
        return (tuple(range(count)),)

    def fixed_domains(self, into: Sequence[bool]) -> dict[int, str]:
        """Ports whose domain the element itself fixes (a chemical species: ``'chemical'``),
        given whether each port's bond points into it; empty by default."""
        return {}

    # ------------------------------------------------------------ drawing
    def drawing_label(self) -> tuple[str, str]:
        """The drawn text and the small note beside it."""
        return self.label(), ""


def drawing_role(kind: str) -> str:
    """The drawing role of an element kind; any other string (a role, ``'sub'``) as is.

    Examples
    --------
    >>> import bondgraph as bg
    >>> role = bg.elements.drawing_role
    >>> role("I"), role("1"), role("TF"), role("sub")
    ('storage', 'junction', 'backbone', 'sub')
    """
    cls = _BY_KIND.get(kind)
    return cls.drawing_role if cls is not None else kind


def rename(el: Element, path: str) -> Element:
    """A copy of ``el`` named ``path`` (every other field shared)."""
    cls = type(el)
    names = _FIELDS.get(cls)
    if names is None:
        names = _FIELDS[cls] = tuple(f.name for f in dataclasses.fields(cls))
    obj = object.__new__(cls)
    for name in names:
        object.__setattr__(obj, name, getattr(el, name))
    object.__setattr__(obj, "name", path)
    return obj


_FIELDS: dict[type, tuple[str, ...]] = {}   # dataclass field names (no ClassVar) per class


def prefix_signals(expr: Optional[sympy.Expr], prefix: str) -> Optional[sympy.Expr]:
    """``expr`` with each signal's element name prefixed (a sub-model's path)."""
    if expr is None or not prefix:
        return expr
    sig = {s: s.retarget(prefix + s.target) for s in expr.free_symbols
           if isinstance(s, Signal) and isinstance(s.target, str)}
    return expr.xreplace(sig) if sig else expr


def signals_of(*exprs) -> frozenset:
    """The signals in some expressions (None ignored)."""
    out = set()
    for ex in exprs:
        if ex is not None:
            out |= {s for s in ex.free_symbols if isinstance(s, Signal)}
    return frozenset(out)
