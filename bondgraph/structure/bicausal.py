"""The bicausal bond graph of an inversion: the source-sensor pair and the split strokes.

Gawthrop's bicausal bond graphs give each bond two strokes, one for the
effort and one for the flow.  To invert a pair, the sensor becomes a *double
source* (it imposes the measured variable, and the zero power-conjugate
variable of an ideal detector) and the input source a *double sensor* (both
its variables are computed): the storage elements on the path between them
turn to derivative causality (the trajectory is differentiated), the others
keep integral causality (the zero dynamics), and on the bonds of that path
effort and flow may travel the same way.

An assignment of bicausal strokes is a pair of ordinary causal assignments,
an *effort layer* and a *flow layer*: every junction, TF and GY obeys its
own causal rule in each layer (its rule on the effort strokes and on the
flow strokes is the same), every one-port element has one causality shared
by both layers, and only the source-sensor pair differs between them (an
``SS`` imposing effort and flow, an ``SS`` receiving both).  Here the two
layers are built as one graph (the junction structure twice, each one-port a
two-port :class:`_Pair` holding its causality equal in both) and assigned by
the engine's SCAP (:func:`bondgraph.assign_causality`), integral causality
preferred; a bond whose two layers disagree is bicausal.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.structure import bicausal_graph
>>> g = bg.BondGraph("mass_spring")
>>> v = bg.One("v")
>>> g.add(bg.Se("F"), v, bg.I("m"), bg.C("k"))
>>> for a, b in [("F", v), (v, "m"), (v, "k")]: _ = g.connect(a, b)
>>> bc = bicausal_graph(bg.derive(g, outputs={"vel": bg.flow("m")}))
>>> bc.derivative, bc.zero_dynamics
(('I:m',), ('q_k',))
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Optional, Sequence

from ..causality import assign_causality
from ..elements import One, Zero
from ..elements.bond import Bond
from ..elements.protocol import (DERIVATIVE, INTEGRAL, CausalPorts, Choice, Decision, Element,
                                 rename)
from ..errors import CausalityConflictError
from ..flatten import FlatGraph
from ..model import Model
from ..signals import Signal
from ._generic import StructureError

__all__ = ["Bicausal", "bicausal_graph"]


class _Ports(CausalPorts):
    """The one port of the element a :class:`_Pair` stands for (asked for its forced causality)."""

    count, undecided, efforts_in = 1, 1, 0

    def effort_in(self, port: int) -> Optional[bool]:
        return None

    def open(self) -> list[int]:
        return [0]

    def reason(self, port: int) -> str:
        return ""

    def number(self, port: int) -> int:
        return 0

    def into(self, port: int) -> bool:
        return True


@dataclass(frozen=True, eq=False)
class _Pair(Element):
    """A one-port element in both layers: port 0 in the effort layer, port 1 in the flow layer."""

    original: Any = None
    forced: Optional[tuple[bool, bool]] = None     # (effort layer, flow layer), else shared
    kind: ClassVar[str] = "pair"
    bonds: ClassVar[tuple[int, Optional[int]]] = (2, 2)

    def label(self) -> str:
        return self.original.label() if self.original is not None else super().label()

    def forced_causality(self, ports: CausalPorts) -> Sequence[Decision]:
        if self.forced is not None:
            why = f"source-sensor {self.label()}"
            return (Decision(0, self.forced[0], why), Decision(1, self.forced[1], why))
        got = self.original.forced_causality(_Ports())
        return tuple(d for p in (0, 1) for d in (Decision(p, x.effort_in, x.reason) for x in got))

    def propagate(self, ports: CausalPorts) -> Sequence[Decision]:
        if self.forced is not None:
            return ()
        a, b = ports.effort_in(0), ports.effort_in(1)
        if a is not None and b is None:
            return (Decision(1, a, f"{self.label()} in the effort layer"),)
        if b is not None and a is None:
            return (Decision(0, b, f"{self.label()} in the flow layer"),)
        if a is not None and a != b:
            raise CausalityConflictError(
                f"causality conflict at {self.label()}: a one-port element takes one causality, "
                f"but the effort layer (bond {ports.number(0)}, {ports.reason(0)}) and the flow "
                f"layer (bond {ports.number(1)}, {ports.reason(1)}) differ")
        return ()

    def causal_choices(self, prefer_derivative: bool) -> Sequence[Choice]:
        if self.forced is not None:
            return ()
        return tuple(self.original.causal_choices(False))

    def causal_class(self, effort_in: Sequence[bool], free: Sequence[bool]) -> Optional[str]:
        if self.forced is not None:
            return None
        return self.original.causal_class(effort_in[:1], free[:1])

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        return ((), ())

    def state_names(self, effort_in: Sequence[bool]) -> tuple[str, ...]:
        if self.forced is not None:
            return ()
        return tuple(self.original.state_names(effort_in[:1]))


@dataclass(frozen=True)
class Bicausal:
    """The bicausal bond graph of inverting ``output`` for ``input`` (immutable).

    Attributes
    ----------
    model, input, output : str
    strokes : tuple of (int, str, str, str, str)
        Per bond: number, tail, head, the element the effort goes to, the
        element the flow goes to (the same element on a bicausal bond).
    derivative : tuple of str
        Storage elements in derivative causality (differentiators of the trajectory),
        including those already in derivative causality in the model.
    differentiations : int
        The model's storage states less the zero dynamics: the differentiations
        of the trajectory, the structural relative degree (equal to the generic
        one unless causal-path gains cancel).  Dependent storage elements (in
        derivative causality in the model) may trade places with others, so
        this is not ``len(derivative)``.
    zero_dynamics : tuple of str
        States that stay integral: the zero dynamics.
    sensor : str
        The element whose variable is the output (the source-sensor ``SS``).
    """

    model: str
    input: str
    output: str
    strokes: tuple[tuple[int, str, str, str, str], ...]
    derivative: tuple[str, ...]
    differentiations: int
    zero_dynamics: tuple[str, ...]
    sensor: str

    @property
    def bicausal_bonds(self) -> tuple[int, ...]:
        """Numbers of the bonds whose effort and flow go the same way."""
        return tuple(n for n, _, _, e, f in self.strokes if e == f)

    def __str__(self) -> str:
        lines = [f"bicausal bond graph of {self.model!r}: {self.output} set by {self.input} "
                 f"(SS:{self.input} receives effort and flow, {self.sensor} imposes both)"]
        for n, tail, head, e, f in self.strokes:
            mark = "  bicausal" if e == f else ""
            lines.append(f"  {n}: {tail} -> {head}: effort to {e}, flow to {f}{mark}")
        lines.append(f"  derivative causality (differentiators): "
                     f"{', '.join(self.derivative) or '-'} ({self.differentiations} "
                     "differentiations of the trajectory)")
        lines.append(f"  zero dynamics (integral): {', '.join(self.zero_dynamics) or '-'}")
        return "\n".join(lines)


class _Probe(_Ports):
    """Two ports, the first receiving effort, the second open (asks a two-port's rule)."""

    count, undecided, efforts_in = 2, 1, 1

    def effort_in(self, port: int) -> Optional[bool]:
        return True if port == 0 else None

    def open(self) -> list[int]:
        return [1]


def _gyrating(el: Element) -> bool:
    """Whether a two-port's causal rule has both ports receive effort together (a gyrator:
    ``e1 = r f2``, ``e2 = r f1``, so its effort strokes on one port go with the flow strokes
    on the other)."""
    if el.bonds != (2, 2):
        return False
    try:
        got = el.propagate(_Probe())
    except CausalityConflictError:      # pragma: no cover - one decided port cannot conflict
        return False
    return bool(got) and got[0].port == 1 and got[0].effort_in is True


def _classes(two, combined: FlatGraph) -> dict[str, tuple[str, bool]]:
    """(causal class, effort_in in the effort layer) of every free storage pair."""
    out = {}
    for el in combined.elements:
        if isinstance(el, _Pair) and el.forced is None:
            inc = combined.incidence[el.name]
            ein = [two.effort_into(el.name, combined.bonds[j].number) for j in inc]
            cls = el.causal_class(ein, [False, False])
            if cls in (INTEGRAL, DERIVATIVE):
                out[el.name] = (cls, ein[0])
    return out


def _fewer_differentiators(two, combined: FlatGraph):
    """Turn elements back to integral causality while that lowers their number.

    SCAP's integral preference is greedy (the elements nearest the sources
    first): a differentiator it left may become integral when the path
    between the source-sensor pair runs elsewhere.  Each differentiator is
    tried integral, every other element free; an assignment with fewer
    differentiators replaces the current one."""
    while True:
        cls = _classes(two, combined)
        count = sum(c == DERIVATIVE for c, _ in cls.values())
        better = None
        for n, (c, e) in sorted(cls.items()):
            if c != DERIVATIVE:
                continue
            trial = rename(_Pair("p", original=getattr(combined.element(n), "original", None),
                                 forced=(not e, not e)), n)
            els = tuple(trial if el.name == n else el for el in combined.elements)
            flat = FlatGraph(name=combined.name, elements=els, bonds=combined.bonds,
                             incidence=combined.incidence, index=combined.index)
            try:
                found = assign_causality(flat)
            except CausalityConflictError:
                continue
            # the tried element is forced (not counted): fewer means at most count - 1
            if sum(c2 == DERIVATIVE for c2, _ in _classes(found, combined).values()) < count:
                better = found
                break
        if better is None:
            return two
        two = better


def _output_bond(model: Model, output: str, signal: Any) -> tuple[int, str]:
    flat = model.augmented.flat
    sigs = [x for x in getattr(signal, "free_symbols", ()) if isinstance(x, Signal)]
    if len(sigs) != 1 or sigs[0].variable not in ("effort", "flow") or \
            (signal / sigs[0]).free_symbols & set(sigs):
        raise StructureError(f"bicausal: output {output!r} = {signal} is not proportional to one "
                             "effort or flow (a sensor on one bond)")
    sig = sigs[0]
    if isinstance(sig.target, int):
        return sig.target - 1, sig.variable
    if sig.target not in flat.index:
        raise StructureError(f"bicausal: {sig} names no element of model {model.name!r}")
    el = flat.element(sig.target)
    carried = el.signal_port(sig.variable) if sig.port is None else \
        el.port_signal(sig.variable, sig.port)
    if carried is None:
        raise StructureError(f"bicausal: {sig} is not the variable of one bond")
    return flat.incidence[sig.target][carried[0]], sig.variable


def bicausal_graph(model: Model, input: Optional[str] = None, output: Optional[str] = None, *,
             signal: Any = None) -> Bicausal:
    """The bicausal bond graph that inverts ``output`` for ``input`` (SISO).

    Parameters
    ----------
    model : Model
        A derived model; its augmented bond graph is used.
    input, output : str, optional
        Required when the model has several inputs (outputs).
    signal : expression, optional
        The signal the output was defined by (the value given to
        :func:`bondgraph.derive`, e.g. ``bg.flow("m")``): the sensor sits on its
        bond.  Without it the output is matched to the bond variables, as
        :func:`bondgraph.structure.derivative_causality` does (graphs of at
        most 12 bonds).

    Returns
    -------
    Bicausal

    Raises
    ------
    StructureError
        Unknown channels, an output that is not one effort or flow, a
        multiport element (fields), or no bicausal assignment (the input
        cannot set this output).

    """
    from ._paths import state_elements
    from .derivative import _detector_bonds

    owners = state_elements(model)
    storage = [x for x in model.state_names if owners.get(x)]

    aug = model.augmented
    if aug is None:
        raise StructureError(f"bicausal: model {model.name!r} has no bond graph")
    flat = aug.flat
    ins, outs = model.input_names, model.output_names
    if input is None and len(ins) != 1 or input is not None and input not in ins:
        raise StructureError(f"bicausal: name one input of model {model.name!r} "
                             f"({', '.join(ins) or 'none'})")
    if output is None and len(outs) != 1 or output is not None and output not in outs:
        raise StructureError(f"bicausal: name one output of model {model.name!r} "
                             f"({', '.join(outs) or 'none'})")
    u = input if input is not None else ins[0]
    y = output if output is not None else outs[0]
    if signal is not None:
        k, var = _output_bond(model, y, signal)
    else:
        found, why = _detector_bonds(model, [outs.index(y)])
        if why:
            raise StructureError(f"bicausal: {why}; pass signal=")
        k, var = found[0]
    source = [el for el in flat.elements if el.input_name() == u]
    if len(source) != 1 or len(flat.incidence[source[0].name]) != 1:
        raise StructureError(f"bicausal: input {u!r} is not introduced by a one-port source")
    taken = set(flat.index)
    jname = next(f"{var[0]}_{y}{i or ''}" for i in range(len(taken) + 1)
                 if f"{var[0]}_{y}{i or ''}" not in taken)
    sname = next(f"{y}_sensor{i or ''}" for i in range(len(taken) + 1)
                 if f"{y}_sensor{i or ''}" not in taken | {jname})
    junction = (Zero if var == "effort" else One)(jname)
    # the sensor as a double source: it imposes the measured variable and the zero
    # power-conjugate one of an ideal detector (effort layer: it sends effort; flow layer: flow)
    sensor_ss: Element = rename(_Pair("ss", forced=(False, True)), sname)
    elements = list(flat.elements) + [junction]
    bonds = list(flat.bonds)
    b = bonds[k]
    bonds[k] = Bond(b.number, b.tail, jname)
    bonds.append(Bond(len(bonds) + 1, jname, b.head))
    bonds.append(Bond(len(bonds) + 1, jname, sname))
    one_ports = {el.name for el in elements
                 if sum(el.name in (q.tail, q.head) for q in bonds) == 1}
    multi = [el for el in elements if el.name not in one_ports and el.causal_choices(False)]
    if multi:      # a storage field: its ports would need one causality per layer and port
        raise StructureError(f"bicausal: multiport element {multi[0].label()} is not supported")
    pairs: dict[str, Element] = {}
    for el in elements:
        if el.name in one_ports:
            forced = (True, False) if el.name == source[0].name else None
            pairs[el.name] = rename(_Pair("p", original=el, forced=forced), el.name)
    pairs[sname] = sensor_ss
    copies = {el.name: rename(el, el.name + "__flow") for el in elements
              if el.name not in one_ports}
    ports_of: dict[str, list[int]] = {}
    for i, q in enumerate(bonds):
        ports_of.setdefault(q.tail, []).append(i)
        ports_of.setdefault(q.head, []).append(i)
    crossing = {name for name in copies if _gyrating(next(e for e in elements if e.name == name))}

    def end(name: str, i: int, flow_layer: bool) -> str:
        if name in pairs:
            return name
        if name in crossing:       # a gyrator: port 1 of one copy is port 2 of the other
            second = ports_of[name].index(i) == 1
            return copies[name].name if second != flow_layer else name
        return copies[name].name if flow_layer else name

    nb = len(bonds)
    all_bonds = [Bond(q.number, end(q.tail, i, False), end(q.head, i, False))
                 for i, q in enumerate(bonds)]
    all_bonds += [Bond(q.number + nb, end(q.tail, i, True), end(q.head, i, True))
                  for i, q in enumerate(bonds)]
    els = [pairs.get(el.name, el) for el in elements] + [sensor_ss] + list(copies.values())
    incidence: dict[str, list[int]] = {el.name: [] for el in els}
    for i, q in enumerate(all_bonds):
        incidence[q.tail].append(i)
        incidence[q.head].append(i)
    combined = FlatGraph(name=flat.name, elements=tuple(els), bonds=tuple(all_bonds),
                         incidence={n: tuple(v) for n, v in incidence.items()},
                         index={el.name: i for i, el in enumerate(els)})
    try:
        two = assign_causality(combined)
    except CausalityConflictError as err:
        raise StructureError(f"bicausal: no bicausal assignment sets {y} by {u} in model "
                             f"{model.name!r} ({err})") from err
    two = _fewer_differentiators(two, combined)
    strokes = []
    for i, q in enumerate(bonds):
        effort_to = q.head if two.stroke_at_head[i] else q.tail
        # the flow layer: the end that receives effort there sends the flow
        f_head = two.stroke_at_head[i + nb]
        flow_to = q.tail if f_head else q.head
        strokes.append((q.number, q.tail, q.head, effort_to, flow_to))
    derivative: list[str] = []
    zero: list[str] = []
    for name, el in pairs.items():
        if not isinstance(el, _Pair) or el.forced is not None:
            continue
        inc = combined.incidence[name]
        ein = [two.effort_into(name, combined.bonds[j].number) for j in inc]
        cls = el.causal_class(ein, [False, False])
        if cls == DERIVATIVE:
            derivative.append(el.label())
        elif cls == INTEGRAL:
            zero += el.state_names(ein)
    return Bicausal(model=model.name, input=u, output=y, strokes=tuple(strokes),
                    derivative=tuple(derivative),
                    differentiations=len(storage) - len(zero), zero_dynamics=tuple(zero),
                    sensor=f"SS:{sname}")
