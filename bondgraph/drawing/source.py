"""What to draw: the nodes and bonds of a bond graph, with causality marks.

:func:`diagram` turns a :class:`~bondgraph.BondGraph`, an
:class:`~bondgraph.AugmentedBondGraph`, a :class:`~bondgraph.FlatGraph` or a
derived :class:`~bondgraph.Model` into a :class:`Diagram`: a plain, immutable
list of nodes and edges that the layout and the renderers read.  Nothing here
knows about coordinates.

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("rl")
>>> V, j = bg.Se("V"), bg.One("j")
>>> g.add(V, j, bg.R("R"), bg.I("L"))
>>> for t, h in [(V, j), (j, "R"), (j, "L")]: _ = g.connect(t, h)
>>> d = diagram(g)
>>> [n.text for n in d.nodes]
['Se:V', '1', 'R:R', 'I:L']
>>> d.edges[0].stroke_end     # Se imposes effort: the stroke is at the junction
'j'
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Optional, Union

from ..causality import AugmentedBondGraph, assign_causality
from ..errors import BondGraphError
from ..flatten import FlatGraph, flatten
from ..graph import BondGraph
from ..model import Model
from ..elements.protocol import Element

__all__ = ["DrawingError", "Node", "Edge", "Diagram", "diagram", "Drawable"]

Drawable = Union[BondGraph, AugmentedBondGraph, FlatGraph, Model]

#: drawing roles (:attr:`bondgraph.elements.protocol.Element.drawing_role`) that the layout may
#: draw as leaves of the junction structure; those drawn above it (and right of a
#: branch); those drawn in line with the main path
LEAF_ROLES = ("source", "storage", "dissipative")
UP_ROLES = ("source", "storage")
SOURCE_ROLES = ("source",)


class DrawingError(BondGraphError, ValueError):
    """A drawing was asked for with options that do not fit the object or file."""


@dataclass(frozen=True)
class Node:
    """One label of the drawing.

    Attributes
    ----------
    name : str
        Unique name: the element's path (``motor.Ra``) or the sub-model's name.
    kind : str
        Element kind (``'Se'``, ``'I'``, ``'0'``, ...), or ``'sub'`` for a
        sub-model drawn as one box (written to the SVG, not interpreted).
    text : str
        The main text: ``'I:La'``, ``'1'``, ``'motor'`` (the element's
        :meth:`~bondgraph.elements.protocol.Element.drawing_label`).
    note : str
        Small text next to the main one: a junction's name ('' otherwise).
    derivative : bool
        A storage element in derivative causality (for a sub-model box: one
        inside it).
    arbitrary : bool
        An R element whose causality was chosen arbitrarily (algebraic loop).
    role : str
        Where the layout puts it: the element's
        :attr:`~bondgraph.elements.protocol.Element.drawing_role`, or ``'sub'``.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("rl")
    >>> g.add(bg.Se("V"), bg.One("j"), bg.R("R"), bg.I("L"))
    >>> for tail, head in [("V", "j"), ("j", "R"), ("j", "L")]: _ = g.connect(tail, head)
    >>> diagram(g).node("j")
    Node(name='j', kind='1', text='1', note='j', derivative=False, arbitrary=False, role='junction')
    """

    name: str
    kind: str
    text: str
    note: str = ""
    derivative: bool = False
    arbitrary: bool = False
    role: str = "backbone"


@dataclass(frozen=True)
class Edge:
    """One bond of the drawing.

    Attributes
    ----------
    number : int
        The bond number shown (flattened numbering, or the builder's own
        numbering when sub-models are drawn as boxes).
    tail, head : str
        Names of the nodes at the two ends (the head carries the half-arrow).
    tail_port, head_port : str
        Port name where an end is a sub-model box ('' otherwise).
    stroke_end : str or None
        The endpoint name at the causal stroke end (an element path, or
        ``sub.port`` for a sub-model box); None without causality.
    loop : bool
        The bond belongs to an algebraic loop.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("rl")
    >>> g.add(bg.Se("V"), bg.One("j"), bg.R("R"), bg.I("L"))
    >>> for tail, head in [("V", "j"), ("j", "R"), ("j", "L")]: _ = g.connect(tail, head)
    >>> edge = diagram(g).edges[0]
    >>> edge
    Edge(number=1, tail='V', head='j', tail_port='', head_port='', stroke_end='j', loop=False)
    >>> edge.stroke_at_head
    True
    """

    number: int
    tail: str
    head: str
    tail_port: str = ""
    head_port: str = ""
    stroke_end: Optional[str] = None
    loop: bool = False

    @property
    def stroke_at_head(self) -> Optional[bool]:
        """True / False for a stroke at the head / tail end, None without causality."""
        if self.stroke_end is None:
            return None
        return self.stroke_end == _end_name(self.head, self.head_port)


def _end_name(node: str, port: str) -> str:
    return f"{node}.{port}" if port else node


@dataclass(frozen=True)
class Diagram:
    """Nodes and edges to lay out and draw (immutable).

    Attributes
    ----------
    name : str
    nodes : tuple of Node
        In the order of the graph's elements.
    edges : tuple of Edge
        In bond-number order.
    causal : bool
        Whether the edges carry causal strokes.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("rl")
    >>> g.add(bg.Se("V"), bg.One("j"), bg.R("R"), bg.I("L"))
    >>> for tail, head in [("V", "j"), ("j", "R"), ("j", "L")]: _ = g.connect(tail, head)
    >>> d = diagram(g)
    >>> d.name, d.causal, [n.name for n in d.nodes], len(d.edges)
    ('rl', True, ['V', 'j', 'R', 'L'], 3)
    """

    name: str
    nodes: tuple[Node, ...]
    edges: tuple[Edge, ...]
    causal: bool = False

    def node(self, name: str) -> Node:
        """The node called ``name``."""
        for n in self.nodes:
            if n.name == name:
                return n
        raise KeyError(name)


def diagram(obj: Drawable, *, causality: bool = True, expand: bool = True,
            mode: Any = None) -> Diagram:
    """The nodes and bonds to draw for a bond graph or a derived model.

    Parameters
    ----------
    obj : BondGraph, AugmentedBondGraph, FlatGraph, Model or SwitchedModel
        A builder graph (causality is assigned if asked), a causal graph, a
        flattened graph, or a derived model (its ``augmented`` graph is drawn).
        A switched model (anything answering ``drawing_mode(mode)``, such as
        :class:`bondgraph.hybrid.SwitchedModel`) is drawn in one mode: the
        strokes of that mode, each switch's state (``on``/``off``) beside it,
        the mode in the title.
    causality : bool
        Show causal strokes (assigning causality when ``obj`` has none).
    expand : bool
        Draw sub-models expanded (hierarchical names); with False, each
        sub-model of a :class:`BondGraph` is one box and its ports are bond ends.
    mode : Mode or mapping with keys ``'on'`` and ``'off'``, optional
        Switched models only: the mode to draw (default: the initial one).

    Returns
    -------
    Diagram

    Raises
    ------
    DrawingError
        For ``expand=False`` on an object that is already flattened.
    TypeError
        For an object that is not a bond graph or a model.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("r"); g.add(bg.Se("V"), bg.R("R")); _ = g.connect("V", "R")
    >>> d = diagram(g, causality=False)
    >>> d.causal, d.edges[0].stroke_end is None
    (False, True)
    >>> from bondgraph.hybrid import SwitchedModel, library
    >>> d = diagram(SwitchedModel(library.buck()), mode={"on": {"D"}, "off": {"S"}})
    >>> d.name, d.node("S").note, d.node("D").note
    ('buck (D on, S off)', 'off', 'on')
    """
    as_mode = getattr(obj, "drawing_mode", None)
    if callable(as_mode) and not isinstance(obj, (Model, BondGraph, AugmentedBondGraph, FlatGraph)):
        if not expand:
            raise DrawingError("expand=False: a switched model is drawn flattened, one mode at a time")
        chosen, aug, states = as_mode(mode)
        d = _from_flat(aug.flat, aug if causality else None)
        nodes = tuple(replace(n, note="on" if states[n.name] else "off") if n.name in states else n
                      for n in d.nodes)
        return replace(d, name=f"{d.name} ({chosen})", nodes=nodes)
    if mode is not None:
        raise DrawingError(f"mode= applies to switched models; got a {type(obj).__name__}")
    if isinstance(obj, Model):
        obj = obj.augmented
    if isinstance(obj, BondGraph):
        if not expand:
            return _boxed(obj, causality)
        flat = flatten(obj)
        return _from_flat(flat, assign_causality(flat) if causality else None)
    if isinstance(obj, (AugmentedBondGraph, FlatGraph)):
        if not expand:
            raise DrawingError(
                f"expand=False needs the BondGraph builder: a {type(obj).__name__} is "
                "already flattened, so its sub-models cannot be drawn as boxes; pass the "
                "BondGraph instead, or use expand=True"
            )
        if isinstance(obj, FlatGraph):
            return _from_flat(obj, assign_causality(obj) if causality else None)
        return _from_flat(obj.flat, obj if causality else None)
    raise TypeError(
        "draw() takes a BondGraph, AugmentedBondGraph, FlatGraph, Model or SwitchedModel; got "
        f"{type(obj).__name__} {obj!r}"
    )


def _node(el: Element, aug: Optional[AugmentedBondGraph]) -> Node:
    text, note = el.drawing_label()
    return Node(
        name=el.name, kind=el.kind, text=text, note=note,
        derivative=aug is not None and el.name in aug.derivative,
        arbitrary=aug is not None and el.name in aug.arbitrary,
        role=el.drawing_role,
    )


def _from_flat(flat: FlatGraph, aug: Optional[AugmentedBondGraph]) -> Diagram:
    nodes = tuple(_node(el, aug) for el in flat.elements)
    in_loop: set[int] = set()
    if aug is not None:
        for lp in aug.loops:
            in_loop.update(lp)
    edges = tuple(
        Edge(b.number, b.tail, b.head,
             stroke_end=aug.bond(b.number).stroke if aug is not None else None,
             loop=b.number in in_loop)
        for b in flat.bonds
    )
    return Diagram(flat.name, nodes, edges, causal=aug is not None)


# ---------------------------------------------------------------- sub-model boxes
def _boxed(graph: BondGraph, causality: bool) -> Diagram:
    """Top-level elements plus one box per sub-model; builder bond numbers."""
    aug = None
    flat_number: dict[int, int] = {}
    if causality:
        aug = assign_causality(graph)
        flat_number = dict(aug.flat.top_bonds)
    subs = {s.name for s in graph.submodels}
    nodes = []
    for what, item in _element_then_sub_order(graph):
        if what == "sub":
            inside = aug is not None and any(n.startswith(item + ".") for n in aug.derivative)
            nodes.append(Node(item, "sub", item, derivative=inside, role="sub"))
        else:
            nodes.append(_node(graph[item], aug))
    in_loop: set[int] = set()
    if aug is not None:
        for lp in aug.loops:
            in_loop.update(lp)
    edges = []
    for b in graph.bonds:
        tail, tport = _split(b.tail, subs)
        head, hport = _split(b.head, subs)
        stroke, loop = None, False
        if aug is not None and b.number in flat_number:
            fb = aug.bond(flat_number[b.number])
            loop = fb.number in in_loop
            stroke = _stroke_on_top_bond(b.tail, b.head, fb)
        edges.append(Edge(b.number, tail, head, tport, hport, stroke, loop))
    return Diagram(graph.name, tuple(nodes), tuple(edges), causal=aug is not None)


def _element_then_sub_order(graph: BondGraph):
    for el in graph.elements:
        yield "el", el.name
    for item in graph._order:
        if isinstance(item, str):
            yield "sub", item


def _split(end: str, subs: set) -> tuple[str, str]:
    sub, dot, port = end.partition(".")
    if dot and sub in subs:
        return sub, port
    return end, ""


def _stroke_on_top_bond(tail: str, head: str, fb) -> str:
    """The end of a top-level bond that carries the stroke of its flattened bond.

    Joining a port keeps the power direction, so the flattened bond's tail
    lies on the builder bond's tail side and its head on the head side.
    """
    return tail if fb.stroke == fb.tail else head
