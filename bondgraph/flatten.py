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

Flattening also infers the physical domain of every bond (:func:`infer_domains`)
and refuses a bond given two, naming both elements and both domains:

>>> from bondgraph.library.thermal import HeatCapacity, RS
>>> g = bg.BondGraph("heater")
>>> g.add(bg.Se("V"), bg.One("i"), RS("Rh", 10), HeatCapacity("body", capacity=2))
>>> for t, h in [("V", "i"), ("i", "Rh"), ("Rh", "body.p")]:
...     _ = g.connect(t, h)
>>> bg.derive(g)
Traceback (most recent call last):
...
bondgraph.flatten.DomainError: graph 'heater': the bond Rh -> body.C would be thermal (heat flow, from port body.p of component HeatCapacity) and thermal (entropy) (entropy flow, from RS:Rh); a TF, GY or RS must separate two domains (in a true thermal graph use EntropyStore, in a pseudo one a resistor into HeatCapacity)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping, Optional, Sequence, Union

from .elements import Element, Port, Zero
from .errors import ModelStructureError, PortError, UnknownElementError
from .graph import Bond, BondGraph, walk

__all__ = ["FlatGraph", "flatten", "DOMAIN_NAMES", "DomainError", "infer_domains", "check_domains"]


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


# --- the physical domain of every bond -------------------------------------------------
# The physical domain of every bond, inferred and checked whether or not units are given.
# 
# An element may fix the domain of its ports (:meth:`~bondgraph.Element.fixed_domains`:
# a chemical species, a thermal ``RS`` whose heat enters a body as an *entropy*
# flow) and a library component declares the domain of each port
# (``port_domains``; a port that serves several, a temperature source in a
# pseudo or a true thermal graph, lists them in ``port_domain_choices``).  The
# domain spreads over every bond of a junction and through every element but a
# ``TF``, ``GY`` or ``RS`` (:meth:`~bondgraph.Element.domain_groups`).  Two
# seeds that give one bond different domains are refused when the graph is
# flattened, naming both elements and both domains: a Joule heater ``RS``
# (entropy flow) bonded to a pseudo-thermal ``HeatCapacity`` (heat flow) would
# otherwise run and give a wrong temperature.

#: the domains a bond can be in (their units: :data:`bondgraph.library.units.DOMAINS`)
DOMAIN_NAMES = ("electrical", "translation", "rotation", "hydraulic", "thermal",
                "thermal (entropy)", "chemical", "magnetic")

#: what the flow of a domain is, where two share an effort (messages)
_FLOW = {"thermal": "heat flow", "thermal (entropy)": "entropy flow"}


class DomainError(ModelStructureError):
    """One bond given two physical domains (naming both elements and both domains),
    or an unknown domain name."""


Seed = tuple[int, Union[str, tuple[str, ...]], str]   # (flat bond index, domain(s), who)


def _name(dom: object, where: str) -> str:
    if not isinstance(dom, str) or dom not in DOMAIN_NAMES:
        raise DomainError(f"{where}: unknown domain {dom!r}; expected one of "
                          f"{', '.join(DOMAIN_NAMES)}")
    return dom


def _component_seeds(graph: "BondGraph", flat: "FlatGraph") -> list[Seed]:
    """(flat bond index, domain or choices, who) for every port of a library component."""

    seeds: list[Seed] = []
    for prefix, sub in walk(graph):
        port_domains = getattr(sub, "port_domains", None)
        if not port_domains or not prefix:
            continue
        choices = getattr(sub, "port_domain_choices", {}) or {}
        for b in sub.bonds:
            for port, other, port_is_tail in ((b.tail, b.head, True), (b.head, b.tail, False)):
                if port not in sub.ports or port not in port_domains:
                    continue
                who = f"port {prefix}{port} of component {type(sub).__name__}"
                path = prefix + port
                if path in flat.index:       # the port became a 0-junction
                    ks = list(flat.incidence[path])
                else:
                    ks = [k for k in flat.incidence.get(prefix + other, ())
                          if (flat.bonds[k].head == prefix + other) == port_is_tail
                          and not (flat.bonds[k].tail if port_is_tail else
                                   flat.bonds[k].head).startswith(prefix)]
                dom = tuple(choices[port]) if port in choices else port_domains[port]
                seeds += [(k, dom, who) for k in ks]
    return seeds


def _shown(dom: str, who: str) -> str:
    flow = _FLOW.get(dom)
    return f"{dom} ({flow + ', ' if flow else ''}from {who})"


def infer_domains(flat: "FlatGraph", graph: Optional["BondGraph"] = None,
                  extra: Sequence[Seed] = ()) -> dict[int, str]:
    """The domain of each bond (flat bond number -> domain name) that can be inferred.

    Parameters
    ----------
    flat : FlatGraph
    graph : BondGraph, optional
        The hierarchical graph ``flat`` came from (its components' port domains).
    extra : sequence of (bond index, domain, who)
        Further seeds (the domains a user names for the units check).

    Raises
    ------
    DomainError
        Two seeds give one bond different domains (naming both).
    """
    parent = list(range(len(flat.bonds)))

    def find(k: int) -> int:
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    for el in flat.elements:
        inc = flat.incidence[el.name]
        for group in el.domain_groups(len(inc)):
            for p in group[1:]:
                parent[find(inc[p])] = find(inc[group[0]])
    seeds: list[Seed] = []
    for el in flat.elements:
        inc = flat.incidence[el.name]
        into = [flat.bonds[k].head == el.name for k in inc]
        for p, dom in el.fixed_domains(into).items():
            seeds.append((inc[p], _name(dom, el.label()), el.label()))
    if graph is not None:
        seeds += _component_seeds(graph, flat)
    seeds += list(extra)
    found: dict[int, tuple[str, str]] = {}
    where = f"graph {flat.name!r}: "
    for k, dom_s, who in (s for s in seeds if isinstance(s[1], str)):
        dom = str(dom_s)
        root = find(k)
        if root in found and found[root][0] != dom:
            a, b = found[root], (_name(dom, who), who)
            bond = flat.bonds[k]
            raise DomainError(f"{where}the bond {bond.tail} -> {bond.head} would be "
                              f"{_shown(b[0], b[1])} and "
                              f"{_shown(a[0], a[1])}; a TF, GY or RS must separate two domains"
                              f"{_hint(a[0], b[0])}")
        found.setdefault(root, (_name(dom, who), who))
    for k, doms, who in (s for s in seeds if not isinstance(s[1], str)):
        root = find(k)
        if root in found and found[root][0] not in doms:
            bond = flat.bonds[k]
            raise DomainError(f"{where}the bond {bond.tail} -> {bond.head} is "
                              f"{_shown(*found[root])}, but {who} "
                              f"serves {' or '.join(doms)} only")
    return {k + 1: found[find(k)][0] for k in range(len(flat.bonds)) if find(k) in found}


def _hint(a: str, b: str) -> str:
    if {a, b} == {"thermal", "thermal (entropy)"}:
        return (" (in a true thermal graph use EntropyStore, in a pseudo one a resistor into "
                "HeatCapacity)")
    return ""


def check_domains(flat: "FlatGraph", graph: Optional["BondGraph"] = None) -> None:
    """Refuse a graph whose bonds' domains conflict (see :func:`infer_domains`)."""
    infer_domains(flat, graph)


def given_seeds(flat: "FlatGraph", domains: Optional[Mapping[Union[str, int], str]]) -> list[Seed]:
    """Seeds from the ``domains`` a user names (element path or flat bond number -> domain)."""
    seeds: list[Seed] = []
    for key, dom in (domains or {}).items():
        if isinstance(key, int) and not isinstance(key, bool):
            flat.bond(key)
            seeds.append((key - 1, _name(dom, f"bond {key}"), f"bond {key} (given)"))
            continue
        el = flat.element(str(key))
        inc = flat.incidence[el.name]
        group = el.domain_groups(len(inc))[0]
        seeds.append((inc[group[0]], _name(dom, el.label()), f"{el.label()} (given)"))
    return seeds
