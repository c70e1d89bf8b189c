"""Conformance checks for elements of the protocol (scikit-learn's ``check_estimator`` habit).

Whoever writes a new element (a class derived from :class:`bondgraph.Element`)
gets the guarantees the built-in elements have by calling
:func:`check_element` with a factory that makes one, named as asked:

>>> import bondgraph as bg
>>> from bondgraph.testing import check_element
>>> report = check_element(lambda name: bg.R(name))
>>> print(report)
R:x conforms: 7 checks; causal patterns derived: effort-in on port 1; flow-in on port 1
>>> report.causalities          # a source fixes the R's causality: not an arbitrary choice
(((True,), None), ((False,), None))
>>> dict(check_element(bg.I).causalities)
{(True,): 'integral', (False,): 'derivative'}

The checks (each a function of this module, runnable alone):

* :func:`check_identity` -- a frozen element with a kind, a label
  ``KIND:name``, a bond range, a drawing label and role, that pickles;
* :func:`check_port_rules` -- too few bonds refused when the graph is
  flattened, one bond too many refused by ``connect``, both naming the
  element;
* :func:`check_causalities` -- the element's ports driven by effort and flow
  sources in every combination: each either derives (every bond's causality
  decided, the element's causal class one of the protocol's, its states in
  the model, every bond's effort and flow an expression of the model's
  symbols) or is refused with a :class:`~bondgraph.BondGraphError`; at least
  one combination derives;
* :func:`check_algebraic_loop` -- an element with a free (resistive) choice,
  put in a resistive loop, derives or is refused with an
  :class:`~bondgraph.AlgebraicLoopError`;
* :func:`check_submodel` -- the element inside a sub-model gives the same
  equations as at the top, with its names prefixed;
* :func:`check_energy` -- the energy answers have the protocol's types, and a
  stored energy is non-negative at random states;
* :func:`check_drawing` -- the element is drawn, with its label.

A failed check raises :class:`ElementCheckError` naming the element, the
check and what was expected.
"""

from __future__ import annotations

import dataclasses
import itertools
import pickle
import random
import sys
import warnings
from dataclasses import dataclass
from typing import Callable, Optional, Sequence

import sympy

from .causality import assign_causality
from .drawing import draw
from .elements import Element, Port, R, Se, Sf, One, Zero
from .elements.protocol import ARBITRARY, DERIVATIVE, INTEGRAL, RESISTIVE
from .errors import AlgebraicLoopError, BondGraphError, BondGraphWarning, ModelStructureError
from .flatten import flatten
from .graph import BondGraph
from .model import Model, derive
from .signals import effort, flow

__all__ = ["ElementCheckError", "ConformanceReport", "check_element", "check_identity",
           "check_port_rules", "check_causalities", "check_algebraic_loop", "check_submodel",
           "check_energy", "check_drawing"]

Factory = Callable[[str], Element]

#: drawing roles the drawings know
ROLES = ("source", "storage", "dissipative", "junction", "backbone")
#: most ports tried in every source combination (2**n patterns); more ports are sampled
MAX_EXHAUSTIVE_PORTS = 4


class ElementCheckError(AssertionError):
    """An element does not conform to the protocol; the message names it and the check."""


@dataclass(frozen=True)
class ConformanceReport:
    """What :func:`check_element` found.

    Attributes
    ----------
    label : str
    checks : tuple of str
        The checks run (all passed).
    causalities : tuple of ((bool, ...), str or None)
        For each source combination that derived: ``effort_in`` of the
        element's ports and its causal class.
    """

    label: str
    checks: tuple[str, ...]
    causalities: tuple[tuple[tuple[bool, ...], Optional[str]], ...]

    def __str__(self) -> str:
        seen = []
        for effort_in, _ in self.causalities:
            seen.append(", ".join(f"{'effort' if e else 'flow'}-in on port {p + 1}"
                                  for p, e in enumerate(effort_in)))
        return (f"{self.label} conforms: {len(self.checks)} checks; causal patterns derived: "
                + ("; ".join(seen) or "none"))


def _fail(el: Element, check: str, message: str) -> ElementCheckError:
    return ElementCheckError(f"{el.label()}: {check}: {message}")


def _ports(el: Element) -> int:
    least, most = el.bonds
    return max(least, 1) if most is None or most >= least else least


def _connect(g: BondGraph, source: str, el: Element, port: int) -> None:
    """Bond ``source -> el`` (power into the element), or ``el -> source`` where the
    element's port rules want the power out (port 2 of a two-port)."""
    try:
        g.connect(source, el.name)
    except ModelStructureError:
        g.connect(el.name, source)
        return
    if port and el.bond_warnings(g.bonds[-1:]):       # pragma: no cover - direction hint
        pass


def _pattern_graph(factory: Factory, pattern: Sequence[bool], name: str = "x"
                   ) -> tuple[BondGraph, Element]:
    """The element with an effort source (True) or a flow source (False) on each port."""
    el = factory(name)
    g = BondGraph("check")
    sources = [Se(f"u{p + 1}") if e else Sf(f"u{p + 1}") for p, e in enumerate(pattern)]
    g.add(el, *sources)
    for p, src in enumerate(sources):
        _connect(g, src.name, el, p)
    return g, el


def _quiet_derive(g, outputs=None) -> Model:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BondGraphWarning)
        return derive(g, outputs)


# ------------------------------------------------------------------ the checks
def check_identity(factory: Factory) -> None:
    """A frozen element with a kind, a ``KIND:name`` label, a bond range, drawing answers, pickling."""
    el = factory("x")
    if not isinstance(el, Element):
        raise ElementCheckError(f"factory('x') returned {type(el).__name__}, not an Element")
    if not isinstance(el.kind, str) or not el.kind or el.kind == "?":
        raise _fail(el, "identity", f"kind must be a non-empty string; got {el.kind!r}")
    if el.label() != f"{el.kind}:x" or el.name != "x":
        raise _fail(el, "identity", f"label() must be '{el.kind}:x' for factory('x'); "
                                    f"got {el.label()!r}")
    least, most = el.bonds
    if not (isinstance(least, int) and least >= 1 and (most is None or
                                                        (isinstance(most, int) and most >= least))):
        raise _fail(el, "identity", f"bonds must be (least >= 1, most >= least or None); "
                                    f"got {el.bonds!r}")
    if dataclasses.is_dataclass(el):
        field = dataclasses.fields(el)[0].name
        try:
            object.__getattribute__(el, "__setattr__")(field, None)
        except dataclasses.FrozenInstanceError:
            pass
        else:
            raise _fail(el, "identity", "elements must be frozen dataclasses (an attribute was set)")
    text, note = el.drawing_label()
    if not (isinstance(text, str) and isinstance(note, str) and text):
        raise _fail(el, "identity", f"drawing_label() must be two strings; got {(text, note)!r}")
    if el.drawing_role not in ROLES:
        raise _fail(el, "identity", f"drawing_role must be one of {ROLES}; got {el.drawing_role!r}")
    cls = type(el)
    if getattr(sys.modules.get(cls.__module__), cls.__qualname__, None) is cls:
        # (a class defined inside a function or an exec'd string cannot be pickled by anyone)
        back = pickle.loads(pickle.dumps(el))
        if type(back) is not cls or back.label() != el.label():
            raise _fail(el, "identity", "a pickle round trip changed the element")


def check_port_rules(factory: Factory) -> None:
    """Too few bonds refused at flattening, one too many refused by ``connect``; both name it."""
    el = factory("x")
    least, most = el.bonds
    g = BondGraph("ports")
    g.add(el)
    try:
        flatten(g)
    except ModelStructureError as exc:
        if el.label() not in str(exc):
            raise _fail(el, "port rules", f"the unconnected element's error does not name it: "
                                          f"{exc}") from None
    else:
        raise _fail(el, "port rules", "an element with no bond was accepted by flatten")
    if most is None:
        return
    g = BondGraph("ports")
    g.add(el)
    for k in range(most + 1):
        j = Zero(f"j{k}")
        g.add(j)
        try:
            g.connect(j, el.name)
        except ModelStructureError as exc:
            try:
                g.connect(el.name, j)
            except ModelStructureError as exc2:
                if k < most:
                    raise _fail(el, "port rules", f"bond {k + 1} of {most} was refused: "
                                                  f"{exc}; {exc2}") from None
                if el.label() not in str(exc2) and el.label() not in str(exc):
                    raise _fail(el, "port rules", f"the refusal does not name the element: "
                                                  f"{exc2}") from None
                return
    raise _fail(el, "port rules", f"bond {most + 1} was accepted although bonds = {el.bonds}")


def _patterns(n: int) -> list[tuple[bool, ...]]:
    every = list(itertools.product((True, False), repeat=n))
    if n <= MAX_EXHAUSTIVE_PORTS:
        return every
    return random.Random(n).sample(every, 2 ** MAX_EXHAUSTIVE_PORTS)


def check_causalities(factory: Factory) -> tuple[tuple[tuple[bool, ...], Optional[str]], ...]:
    """Every combination of effort and flow sources on the ports derives or is refused well.

    Returns
    -------
    tuple of ((bool, ...), str or None)
        ``effort_in`` of the element's ports and its causal class, per derived combination.
    """
    probe = factory("x")
    n = _ports(probe)
    derived = []
    for pattern in _patterns(n):
        g, el = _pattern_graph(factory, pattern)
        outputs = {}
        for b in g.bonds:
            outputs[f"e{b.number}"] = effort(b.number)
            outputs[f"f{b.number}"] = flow(b.number)
        try:
            model = _quiet_derive(g, outputs)
        except BondGraphError:
            continue                               # refused, and refused well
        except Exception as exc:                   # noqa: BLE001 - the check reports it
            raise _fail(el, "causalities", f"sources {pattern} raised {type(exc).__name__}: "
                                           f"{exc} (expected a derivation or a BondGraphError)"
                        ) from exc
        aug = model.augmented
        bonds = [b for b in aug.bonds if el.name in (b.tail, b.head)]
        effort_in = tuple(b.stroke == el.name for b in bonds)
        klass = None
        if el.name in aug.integral:
            klass = INTEGRAL
        elif el.name in aug.derivative:
            klass = DERIVATIVE
        elif el.name in aug.arbitrary:
            klass = ARBITRARY
        own = set(el.state_names(effort_in))
        missing = own - set(model.state_names)
        if missing:
            raise _fail(el, "causalities", f"sources {pattern}: states {sorted(missing)} it "
                                           f"names are not states of the model {model.state_names}")
        allowed = set(model.states) | set(model.inputs) | set(model.input_derivatives) \
            | set(model.parameters) | set(getattr(model, "algebraic", ())) \
            | {sympy.Symbol("t", real=True)}
        for name, ex in zip(model.output_names, model.output_exprs):
            if not isinstance(ex, sympy.Expr) or ex.free_symbols - allowed:
                raise _fail(el, "causalities", f"sources {pattern}: output {name} = {ex} is not "
                                               "an expression of the model's symbols")
        derived.append((effort_in, klass))
    if not derived:
        raise _fail(probe, "causalities", f"no combination of sources on its {n} port(s) derives")
    return tuple(derived)


def check_algebraic_loop(factory: Factory) -> None:
    """An element with a free (resistive) choice, in a resistive loop, derives or says why.

    The loop: ``Se:U -> 1 [R:R1] -> 0 [R:R2, element]``; the element's other
    ports (if any) get effort sources.
    """
    el = factory("x")
    if not any(c.priority == RESISTIVE for c in el.causal_choices(False)):
        return
    g = BondGraph("loop")
    s, n = One("s"), Zero("n")
    g.add(Se("U"), s, R("R1"), n, R("R2"), el)
    bonds: list[tuple[Element | str, Element | str]] = [("U", s), (s, "R1"), (s, n), (n, "R2")]
    for tail, head in bonds:
        g.connect(tail, head)
    g.connect(n, el.name)
    for p in range(1, _ports(el)):
        src = Se(f"u{p + 1}")
        g.add(src)
        _connect(g, src.name, el, p)
    try:
        _quiet_derive(g, {"i": flow(1)})
    except AlgebraicLoopError as exc:
        if el.label() not in str(exc) and el.name not in str(exc):
            raise _fail(el, "algebraic loop", f"the loop error does not name it: {exc}") from None
    except BondGraphError:
        pass
    except Exception as exc:  # noqa: BLE001
        raise _fail(el, "algebraic loop", f"raised {type(exc).__name__}: {exc}") from exc


def _unprefixed(expr: sympy.Expr, prefix: str) -> sympy.Expr:
    swap = {}
    for s in expr.free_symbols:
        if prefix in s.name:
            swap[s] = sympy.Symbol(s.name.replace(prefix, ""), **s.assumptions0)
    return expr.xreplace(swap)


def check_submodel(factory: Factory) -> None:
    """Inside a sub-model the element derives the same equations, its names prefixed ``sub.``.

    Skipped for an element whose laws read signals of other elements (a
    modulated element): inside a sub-model those names are the sub-model's.
    """
    probe = factory("x")
    if probe.signals():
        return
    n = _ports(probe)
    for pattern in _patterns(n):
        flat_graph, _ = _pattern_graph(factory, pattern)
        try:
            want = _quiet_derive(flat_graph)
        except BondGraphError:
            continue
        inner = BondGraph("sub")
        el = factory("x")
        ports = [Port(f"p{p + 1}") for p in range(n)]
        inner.add(el, *ports)
        for p, port in enumerate(ports):
            _connect(inner, port.name, el, p)
        top = BondGraph("check")
        sources = [Se(f"u{p + 1}") if e else Sf(f"u{p + 1}") for p, e in enumerate(pattern)]
        top.add(inner, *sources)
        for p, (src, port) in enumerate(zip(sources, ports)):
            into = any(b.tail == port.name for b in inner.bonds)
            if into:
                top.connect(src.name, f"sub.{port.name}")
            else:
                top.connect(f"sub.{port.name}", src.name)
        try:
            got = _quiet_derive(top)
        except BondGraphError as exc:
            raise _fail(el, "sub-model", f"derives at the top with sources {pattern} but not "
                                         f"inside a sub-model: {exc}") from None
        names = tuple(s.replace("sub.", "") for s in got.state_names)
        if names != want.state_names:
            raise _fail(el, "sub-model", f"states {got.state_names} inside a sub-model, "
                                         f"{want.state_names} at the top")
        for a, b in zip(got.rhs, want.rhs):
            if sympy.simplify(_unprefixed(a, "sub.") - b) != 0:
                raise _fail(el, "sub-model", f"inside a sub-model {a}, at the top {b}")
        return


def _resolved(factory: Factory) -> Optional[Element]:
    """The element as derivation sees it (default parameters resolved), from the first
    source combination that derives; None if none does."""
    for pattern in _patterns(_ports(factory("x"))):
        g, _ = _pattern_graph(factory, pattern)
        try:
            return _quiet_derive(g).augmented.flat.element("x")
        except BondGraphError:
            continue
    return None


def check_energy(factory: Factory) -> None:
    """Energy answers of the protocol's types; a stored energy is non-negative at random
    states and at random parameter values the element accepts (``check_values``, where it
    has one)."""
    el = _resolved(factory) or factory("x")
    signals = el.energy_signals()
    if not isinstance(signals, tuple):
        raise _fail(el, "energy", f"energy_signals() must be a tuple; got {signals!r}")
    if not isinstance(el.conserves_power(), bool):
        raise _fail(el, "energy", "conserves_power() must be a bool")
    for dependent in (False, True):
        why = el.hamiltonian_error(dependent)
        if why is not None and not isinstance(why, str):
            raise _fail(el, "energy", f"hamiltonian_error() must be None or a string; got {why!r}")
    if not signals:
        return
    qs = sympy.symbols(f"z0:{len(signals)}", real=True)
    H = el.stored_energy(qs)
    if not isinstance(H, sympy.Expr):
        raise _fail(el, "energy", f"stored_energy() must be a sympy expression; got {H!r}")
    params = sorted(H.free_symbols - set(qs), key=lambda s: s.name)
    accepts = getattr(el, "check_values", None)
    rng = random.Random(0)
    tried = 0
    for _ in range(50):
        values = {p: rng.uniform(0.5, 2) for p in params}
        if accepts is not None:
            try:
                accepts({p.name: v for p, v in values.items()})
            except BondGraphError:
                continue                       # parameter values the element refuses
        point = {**values, **{q: rng.uniform(-2, 2) for q in qs}}
        value = complex(H.evalf(subs=point))
        if abs(value.imag) > 1e-12 or value.real < -1e-12:
            at = ", ".join(f"{k} = {v:.4g}" for k, v in point.items())
            raise _fail(el, "energy", f"stored energy {H} is {value.real:.4g} < 0 at {at}")
        tried += 1
        if tried == 5:
            break


def check_drawing(factory: Factory) -> None:
    """The element is drawn (SVG) with its label."""
    probe = factory("x")
    for pattern in _patterns(_ports(probe)):
        g, el = _pattern_graph(factory, pattern)
        try:
            assign_causality(g)
        except BondGraphError:
            continue
        svg = draw(g, causality=True)
        text = el.drawing_label()[0]
        if text.replace("&", "&amp;").replace("<", "&lt;") not in svg:
            raise _fail(el, "drawing", f"the drawing does not show its label {text!r}")
        return


CHECKS = (check_identity, check_port_rules, check_causalities, check_algebraic_loop,
          check_submodel, check_energy, check_drawing)


def check_element(factory: Factory) -> ConformanceReport:
    """Run every conformance check on the element ``factory(name)`` makes.

    Parameters
    ----------
    factory : callable
        ``factory(name)`` returns a new element named ``name`` (give every
        parameter it needs; symbols are fine).

    Returns
    -------
    ConformanceReport

    Raises
    ------
    ElementCheckError
        The first check that fails, naming the element and what was expected.
    """
    causalities: tuple = ()
    for check in CHECKS:
        result = check(factory)
        if check is check_causalities and result is not None:
            causalities = result
    return ConformanceReport(factory("x").label(), tuple(c.__name__ for c in CHECKS), causalities)
