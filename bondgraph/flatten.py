"""Flatten a hierarchical bond graph into one level of elements and bonds.

Sub-model elements get path names (``motor.Ra``) and default parameters named
after those paths.  Each sub-model port joins its inner bond to the outer one:
when the two bonds run the same way through the port they become one bond;
otherwise the port becomes a two-bond 0-junction, which keeps the sign
conventions exact.  Bonds are numbered 1..N in creation order, a sub-model's
bonds taking their place at the moment the sub-model was added.

Examples
--------
>>> import bondgraph as bg
>>> inner = bg.BondGraph("motor")
>>> inner.add(bg.Se("V"), bg.One("i"), bg.R("Ra"), bg.Port("shaft"))
>>> for t, h in [("V", "i"), ("i", "Ra"), ("i", "shaft")]: _ = inner.connect(t, h)
>>> g = bg.BondGraph("top"); g.add(inner, bg.R("load"))
>>> _ = g.connect("motor.shaft", "load")
>>> flat = flatten(g)
>>> [str(b) for b in flat.bonds]
['1: motor.V -> motor.i', '2: motor.i -> motor.Ra', '3: motor.i -> load']
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

from .elements import Element, Port, Zero
from .errors import ModelStructureError, PortError, UnknownElementError
from .graph import Bond, BondGraph
from .domains import check_domains

__all__ = ["FlatGraph", "flatten"]


@dataclass(frozen=True)
class FlatGraph:
    """A one-level bond graph: resolved elements and numbered bonds.

    Returned by :func:`flatten`.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> _ = g.connect("F", "m")
    >>> flat = bg.flatten(g)
    >>> flat.element("m"), str(flat.bond(1)), dict(flat.incidence)
    (I(name='m', parameter=m, law=None, inverse=None), '1: F -> m', {'F': (0,), 'm': (0,)})
    """

    name: str
    elements: tuple[Element, ...]
    bonds: tuple[Bond, ...]
    #: element name -> indices (0-based) of its bonds, in order of creation
    incidence: Mapping[str, tuple[int, ...]] = field(repr=False)
    index: Mapping[str, int] = field(repr=False)
    #: number of each bond of the top-level builder graph -> number of the flat bond it became
    top_bonds: Mapping[int, int] = field(default_factory=dict, repr=False)

    def element(self, name: str) -> Element:
        """The element with this (path) name."""
        try:
            return self.elements[self.index[name]]
        except KeyError:
            raise UnknownElementError(
                f"model {self.name!r} has no element {name!r}"
            ) from None

    def bond(self, number: int) -> Bond:
        """The bond with this number (from 1)."""
        if isinstance(number, bool) or not isinstance(number, int) or not 1 <= number <= len(self.bonds):
            raise UnknownElementError(
                f"model {self.name!r} has bonds 1..{len(self.bonds)}; got bond {number!r}"
            )
        return self.bonds[number - 1]


def flatten(graph: BondGraph) -> FlatGraph:
    """Expand sub-models and join ports; check bond counts.

    Parameters
    ----------
    graph : BondGraph
        The (possibly hierarchical) graph to flatten.

    Returns
    -------
    FlatGraph

    Raises
    ------
    PortError
        For a port left dangling.
    ModelStructureError
        For an element with too few bonds; a :class:`~bondgraph.domains.DomainError`
        for a bond that two elements put in different physical domains.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> _ = g.connect("F", "m")
    >>> [el.label() for el in bg.flatten(g).elements]
    ['Se:F', 'I:m']
    """
    elements: dict[str, Element] = {}
    ports: dict[str, str] = {}  # port path -> graph that owns it
    bonds: list[list] = []      # [tail, head, alive, top-level bond number or None]
    _collect(graph, "", elements, ports, bonds)

    touching: dict[str, list[int]] = {}
    for k, (t, h, _, _) in enumerate(bonds):
        touching.setdefault(t, []).append(k)
        touching.setdefault(h, []).append(k)

    for path, owner in ports.items():
        ks = [k for k in touching.get(path, []) if bonds[k][2]]
        if len(ks) != 2:
            where = "inside" if len(ks) == 0 else "outside"
            raise PortError(
                f"port {path!r} of graph {owner!r} is dangling: it has {len(ks)} bond"
                f"{'' if len(ks) == 1 else 's'} ({'no bond ' + where if len(ks) < 2 else 'too many'}); "
                "a port needs one bond inside its graph and one outside (connect it from the "
                "parent graph, or replace it with a source)"
            )
        a, b = sorted(ks)
        ta, ha, _, na = bonds[a]
        tb, hb, _, nb = bonds[b]
        top = na if na is not None else nb
        if ha == path and tb == path:
            bonds[a] = [ta, hb, True, top]
            bonds[b][2] = False
            touching.setdefault(hb, []).append(a)
        elif ta == path and hb == path:
            bonds[a] = [tb, ha, True, top]
            bonds[b][2] = False
            touching.setdefault(tb, []).append(a)
        else:  # both bonds into, or both out of, the port: a 0-junction keeps the signs
            elements[path] = Zero(path.rsplit(".", 1)[-1]).resolved(path)

    live = [(t, h, top) for t, h, alive, top in bonds if alive]
    flat_bonds = tuple(Bond(n, t, h) for n, (t, h, _) in enumerate(live, start=1))
    top_bonds = {top: n for n, (_, _, top) in enumerate(live, start=1) if top is not None}
    incidence: dict[str, list[int]] = {name: [] for name in elements}
    for k, fb in enumerate(flat_bonds):
        incidence[fb.tail].append(k)
        incidence[fb.head].append(k)
    for name, el in elements.items():        # the elements' port rules
        err = el.structure_error([flat_bonds[k] for k in incidence[name]])
        if err is not None:
            raise ModelStructureError(err)
    names = tuple(elements)
    flat = FlatGraph(
        name=graph.name,
        elements=tuple(elements[n] for n in names),
        bonds=flat_bonds,
        incidence={n: tuple(v) for n, v in incidence.items()},
        index={n: i for i, n in enumerate(names)},
        top_bonds=top_bonds,
    )
    check_domains(flat, graph)        # one physical domain per bond, units or not
    return flat


def _collect(graph: BondGraph, prefix: str, elements, ports, bonds) -> None:
    for name, el in graph._elements.items():
        path = prefix + name
        if isinstance(el, Port):
            ports[path] = graph.name
        else:
            elements[path] = el.resolved(path)
    for item in graph._order:
        if isinstance(item, str):  # a sub-model, at the moment it was added
            _collect(graph._subgraphs[item], prefix + item + ".", elements, ports, bonds)
        else:
            bonds.append([prefix + item.tail, prefix + item.head, True,
                          None if prefix else item.number])
