"""The physical domain of every bond, inferred and checked whether or not units are given.

An element may fix the domain of its ports (:meth:`~bondgraph.Element.fixed_domains`:
a chemical species, a thermal ``RS`` whose heat enters a body as an *entropy*
flow) and a library component declares the domain of each port
(``port_domains``; a port that serves several, a temperature source in a
pseudo or a true thermal graph, lists them in ``port_domain_choices``).  The
domain spreads over every bond of a junction and through every element but a
``TF``, ``GY`` or ``RS`` (:meth:`~bondgraph.Element.domain_groups`).  Two
seeds that give one bond different domains are refused when the graph is
flattened, naming both elements and both domains: a Joule heater ``RS``
(entropy flow) bonded to a pseudo-thermal ``HeatCapacity`` (heat flow) would
otherwise run and give a wrong temperature.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.library.thermal import HeatCapacity, RS
>>> g = bg.BondGraph("heater")
>>> g.add(bg.Se("V"), bg.One("i"), RS("Rh", 10), HeatCapacity("body", capacity=2))
>>> for t, h in [("V", "i"), ("i", "Rh"), ("Rh", "body.p")]:
...     _ = g.connect(t, h)
>>> bg.derive(g)
Traceback (most recent call last):
...
bondgraph.domains.DomainError: graph 'heater': the bond Rh -> body.C would be thermal (heat flow, from port body.p of component HeatCapacity) and thermal (entropy) (entropy flow, from RS:Rh); a TF, GY or RS must separate two domains (in a true thermal graph use EntropyStore, in a pseudo one a resistor into HeatCapacity)
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Mapping, Optional, Sequence, Union

from .errors import ModelStructureError

if TYPE_CHECKING:  # pragma: no cover
    from .flatten import FlatGraph
    from .graph import BondGraph

__all__ = ["DOMAIN_NAMES", "DomainError", "infer_domains", "check_domains"]

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
    from .graph import walk

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
    for k, dom, who in (s for s in seeds if isinstance(s[1], str)):
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
