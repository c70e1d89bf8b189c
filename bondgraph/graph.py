"""The mutable bond-graph builder and its bonds.

A :class:`BondGraph` holds elements, sub-models and bonds.  It checks each
call as it is made (names, and each element's port rules: bond counts,
direction of two-port bonds) so that errors surface at the wrong call, not
at derivation.  Algorithms (causality,
equations) are free functions that read a graph; they never change it.

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("rc")
>>> V, n = bg.Se("V"), bg.Zero("n")
>>> g.add(V, n, bg.R("R"), bg.C("C"))
>>> _ = g.connect(V, n); _ = g.connect(n, "R"); _ = g.connect(n, "C")
>>> [str(b) for b in g.bonds]
['1: V -> n', '2: n -> R', '3: n -> C']
"""

from __future__ import annotations

import copy
from typing import Iterable, Iterator, Union

from .elements import Bond, Element, Port, check_name
from .errors import DuplicateNameError, ModelStructureError, PortError, UnknownElementError

__all__ = ["BondGraph", "Bond", "Endpoint"]


Endpoint = Union[Element, str, "BondGraph"]


class BondGraph:
    """A bond graph under construction.

    Parameters
    ----------
    name : str
        The graph's name; it prefixes the names of its elements when the
        graph is used as a sub-model of another (``motor.Ra``).

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("dc_motor")
    >>> V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    >>> g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
    >>> for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
    ...     _ = g.connect(tail, head)
    >>> len(g.bonds), len(g.elements)
    (7, 8)
    """

    def __init__(self, name: str) -> None:
        self.name = check_name(name, "graph")
        self._elements: dict[str, Element] = {}
        self._subgraphs: dict[str, BondGraph] = {}
        self._bonds: list[Bond] = []
        self._order: list[Union[Bond, str]] = []  # bonds and sub-model names, in order
        self._degree: dict[str, list[Bond]] = {}

    # ------------------------------------------------------------------ building
    def add(self, *items: Union[Element, "BondGraph"]) -> None:
        """Add elements and sub-models (other graphs, used through their ports).

        Raises
        ------
        DuplicateNameError
            If a name is already used in this graph.
        """
        for item in items:
            if isinstance(item, BondGraph):
                if item is self:
                    raise ModelStructureError(f"graph {self.name!r} cannot contain itself")
                name = item.name
            elif isinstance(item, Element):
                name = item.name
            else:
                raise ModelStructureError(
                    f"graph {self.name!r}: add() takes elements or BondGraphs, got "
                    f"{type(item).__name__} {item!r}"
                )
            if name in self._elements or name in self._subgraphs:
                raise DuplicateNameError(
                    f"graph {self.name!r}: the name {name!r} is already used by "
                    f"{self._describe(name)}; every element and sub-model needs its own name"
                )
            if isinstance(item, BondGraph):
                if not item.ports:
                    raise PortError(
                        f"graph {self.name!r}: sub-model {name!r} exposes no Port elements, "
                        "so nothing can connect to it"
                    )
                try:
                    self._subgraphs[name] = item.copy()
                except RecursionError:
                    raise ModelStructureError(
                        f"graph {self.name!r}: sub-model {name!r} is nested too deeply to be "
                        "copied (sub-models inside sub-models beyond Python's recursion limit); "
                        "flatten some levels of the hierarchy") from None
                self._order.append(name)
            else:
                self._elements[name] = item
            self._degree[name] = []

    def connect(self, tail: Endpoint, head: Endpoint) -> Bond:
        """Add a bond from ``tail`` to ``head`` (power positive from tail to head).

        Endpoints are elements of this graph, their names, or sub-model
        ports written ``"sub.port"``.

        Returns
        -------
        Bond
            The new bond, numbered in creation order.
        """
        t, h = self._endpoint(tail), self._endpoint(head)
        if t == h:
            raise ModelStructureError(
                f"graph {self.name!r}: a bond from {t!r} to itself is not allowed"
            )
        bond = Bond(len(self._bonds) + 1, t, h)
        for end in (t, h):
            self._check_capacity(end, bond)
        self._bonds.append(bond)
        self._order.append(bond)
        self._degree[t].append(bond)
        self._degree[h].append(bond)
        return bond

    def copy(self, name: str | None = None) -> "BondGraph":
        """A deep copy, optionally renamed (to use one sub-model twice).

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("a"); g.copy("b").name
        'b'
        """
        new = copy.copy(self)
        new.name = self.name if name is None else check_name(name, "graph")
        new._elements = dict(self._elements)
        new._subgraphs = {k: v.copy() for k, v in self._subgraphs.items()}
        new._bonds = list(self._bonds)
        new._order = list(self._order)
        new._degree = {k: list(v) for k, v in self._degree.items()}
        return new

    # ------------------------------------------------------------------ queries
    @property
    def elements(self) -> tuple[Element, ...]:
        """The elements of this graph (not those inside sub-models)."""
        return tuple(self._elements.values())

    @property
    def submodels(self) -> tuple["BondGraph", ...]:
        """The sub-models used in this graph."""
        return tuple(self._subgraphs.values())

    @property
    def bonds(self) -> tuple[Bond, ...]:
        """The bonds of this graph in creation order."""
        return tuple(self._bonds)

    @property
    def ports(self) -> tuple[str, ...]:
        """Names of the Port elements this graph exposes."""
        return tuple(n for n, el in self._elements.items() if isinstance(el, Port))

    def __getitem__(self, name: str) -> Element:
        if name in self._elements:
            return self._elements[name]
        if "." in name:
            sub, _, rest = name.partition(".")
            if sub in self._subgraphs:
                return self._subgraphs[sub][rest]
        raise UnknownElementError(f"graph {self.name!r} has no element {name!r}{self._hint(name)}")

    def __contains__(self, name: object) -> bool:
        return isinstance(name, str) and (name in self._elements or name in self._subgraphs)

    def __iter__(self) -> Iterator[Element]:
        return iter(self._elements.values())

    def __repr__(self) -> str:
        return (f"BondGraph({self.name!r}: {len(self._elements)} elements, "
                f"{len(self._subgraphs)} sub-models, {len(self._bonds)} bonds)")

    def bonds_of(self, name: str) -> tuple[Bond, ...]:
        """Bonds attached to an element (or sub-model port path) of this graph."""
        return tuple(self._degree.get(name, ()))

    # ------------------------------------------------------------------ helpers
    def _describe(self, name: str) -> str:
        if name in self._elements:
            return f"element {self._elements[name].label()}"
        return f"sub-model {name!r}"

    def _hint(self, name: str) -> str:
        names = list(self._elements) + list(self._subgraphs)
        if not names:
            return " (the graph is empty)"
        shown = ", ".join(names[:12]) + (", ..." if len(names) > 12 else "")
        return f"; add() it first (known: {shown})"

    def _endpoint(self, obj: Endpoint) -> str:
        if isinstance(obj, Element):
            if self._elements.get(obj.name) is not obj:
                raise UnknownElementError(
                    f"graph {self.name!r}: element {obj.label()} is not in this graph"
                    f"{self._hint(obj.name)}"
                )
            return obj.name
        if isinstance(obj, BondGraph):
            raise PortError(
                f"graph {self.name!r}: connect to a port of sub-model {obj.name!r} as "
                f"'{obj.name}.<port>' (its ports: {', '.join(obj.ports) or 'none'})"
            )
        if not isinstance(obj, str):
            raise ModelStructureError(
                f"graph {self.name!r}: a bond end must be an element, its name or "
                f"'sub.port'; got {type(obj).__name__} {obj!r}"
            )
        if obj in self._elements:
            return obj
        sub, dot, port = obj.partition(".")
        if dot and sub in self._subgraphs:
            sg = self._subgraphs[sub]
            if port not in sg.ports:
                raise PortError(
                    f"graph {self.name!r}: {obj!r} is not a port of sub-model {sub!r}; "
                    f"its ports are: {', '.join(sg.ports)}"
                )
            self._degree.setdefault(obj, [])
            return obj
        if obj in self._subgraphs:
            raise PortError(
                f"graph {self.name!r}: connect to a port of sub-model {obj!r} as "
                f"'{obj}.<port>' (its ports: {', '.join(self._subgraphs[obj].ports)})"
            )
        raise UnknownElementError(f"graph {self.name!r} has no element {obj!r}{self._hint(obj)}")

    def _check_capacity(self, end: str, bond: Bond) -> None:
        existing = self._degree[end]
        if end not in self._elements:  # a sub-model port, seen from outside
            if existing:
                raise PortError(
                    f"graph {self.name!r}: port {end!r} already has bond {existing[0].number}; "
                    "a port takes exactly one bond (add a 0- or 1-junction to branch)"
                )
            return
        err = self._elements[end].bond_error(existing, bond)   # the element's port rules
        if err is not None:
            raise ModelStructureError(f"graph {self.name!r}: {err}")


def walk(graph: BondGraph, prefix: str = "") -> Iterable[tuple[str, BondGraph]]:
    """Yield ``(prefix, graph)`` for a graph and all nested sub-models."""
    yield prefix, graph
    for name, sub in graph._subgraphs.items():
        yield from walk(sub, prefix + name + ".")
