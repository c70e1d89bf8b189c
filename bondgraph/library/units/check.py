"""The dimensional check: bond domains, unit-carrying values, every relation's units.

See :mod:`bondgraph.library.units` for the choices (sympy.physics.units) and an example.

Examples
--------
>>> import bondgraph as bg, sympy.physics.units as u
>>> g = bg.BondGraph("rc")
>>> g.add(bg.Se("V"), bg.One("i"), bg.R("R"), bg.C("C"))
>>> for t, h in [("V", "i"), ("i", "R"), ("i", "C")]: _ = g.connect(t, h)
>>> rep = check_units(g, {"R": 10 * u.ohm, "C": 2 * u.farad}, domains={"V": "electrical"})
>>> rep.units["q_C"], rep.unchecked
('coulomb', ())
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping, Optional, Sequence, Union

import sympy
import sympy.physics.units as u

from ...errors import BondGraphError
from ...flatten import FlatGraph, flatten
from ...flatten import DomainError, given_seeds, infer_domains
from ...graph import BondGraph
from ...elements.protocol import Element, LocalVariables
from ...signals import t as T_SYM
from ._dims import BadQuantity, ZERO, Dim, Mismatch, Unknown, dims_of, si_value, text, unit_dims

__all__ = ["Domain", "DOMAINS", "UnitError", "UnitReport", "bond_domains", "check_units",
           "si_values", "signal_units"]


class UnitError(BondGraphError, ValueError):
    """A parameter or relation whose units are inconsistent, or conflicting domains."""


@dataclass(frozen=True)
class Domain:
    """A physical domain: the units of its effort and flow.

    Examples
    --------
    >>> DOMAINS["hydraulic"].effort
    pascal
    """

    name: str
    effort: sympy.Expr
    flow: sympy.Expr

    @property
    def effort_dims(self) -> Dim:
        return unit_dims(self.effort)

    @property
    def flow_dims(self) -> Dim:
        return unit_dims(self.flow)


DOMAINS: dict[str, Domain] = {d.name: d for d in (
    Domain("electrical", u.volt, u.ampere),
    Domain("translation", u.newton, u.meter / u.second),
    Domain("rotation", u.newton * u.meter, u.radian / u.second),
    Domain("hydraulic", u.pascal, u.meter**3 / u.second),
    Domain("thermal", u.kelvin, u.watt),
    Domain("thermal (entropy)", u.kelvin, u.watt / u.kelvin),
    Domain("chemical", u.joule / u.mole, u.mole / u.second),
    Domain("magnetic", u.ampere, u.volt),
)}

_TIME = unit_dims(u.second)


# ---------------------------------------------------------------- values
def _carries_units(value: Any) -> bool:
    return isinstance(value, sympy.Basic) and bool(value.atoms(u.Quantity))


def si_values(values: Mapping[str, Any]) -> dict[str, Any]:
    """The values with every unit-carrying one converted to an SI float (others as given).

    Examples
    --------
    >>> si = si_values({"Jm": 3.87 * u.gram * u.centimeter**2, "Rm": 2.6})
    >>> f"{si['Jm']:g}", si["Rm"]
    ('3.87e-07', 2.6)
    """
    if not isinstance(values, Mapping):
        raise UnitError(f"si_values: values must be a mapping of parameter name to value; got "
                        f"{type(values).__name__}")
    return {k: (_si(v, k)[0] if _carries_units(v) else v) for k, v in values.items()}


def _si(value: Any, name: str) -> tuple:
    """:func:`si_value` of parameter ``name``'s value; a bad quantity is a :class:`UnitError`."""
    try:
        return si_value(value)
    except BadQuantity as exc:
        raise UnitError(f"parameter {name!r}: the value {value} is not a number with a unit: "
                        f"{exc}") from None


# ---------------------------------------------------------------- domains
def _flat(graph: Union[BondGraph, FlatGraph]) -> FlatGraph:
    """``flatten(graph)``; conflicting domains are a :class:`UnitError` here."""
    if isinstance(graph, FlatGraph):
        return graph
    try:
        return flatten(graph)
    except DomainError as exc:
        raise UnitError(str(exc)) from None


def bond_domains(graph: Union[BondGraph, FlatGraph], *,
                 domains: Optional[Mapping[Union[str, int], str]] = None) -> dict[int, str]:
    """The domain of each bond (flat bond number -> domain name) that can be inferred.

    The inference of :mod:`bondgraph.flatten` (which :func:`bondgraph.flatten`
    runs on every graph), with the ``domains`` a user names as further seeds.

    Parameters
    ----------
    graph : BondGraph or FlatGraph
    domains : mapping, optional
        Element path (every port in its first group: a one-port, a junction,
        port 1 of a TF) or flat bond number -> domain name.

    Raises
    ------
    UnitError
        Two seeds give one bond different domains (naming both), or an unknown
        element or domain.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("motor")
    >>> g.add(bg.Se("V"), bg.One("i"), bg.R("R"), bg.GY("k"), bg.One("w"), bg.I("J"))
    >>> for t, h in [("V", "i"), ("i", "R"), ("i", "k"), ("k", "w"), ("w", "J")]:
    ...     _ = g.connect(t, h)
    >>> bond_domains(g, domains={"V": "electrical", "J": "rotation"})
    {1: 'electrical', 2: 'electrical', 3: 'electrical', 4: 'rotation', 5: 'rotation'}
    """
    flat = _flat(graph)
    try:
        return infer_domains(flat, graph if isinstance(graph, BondGraph) else None,
                             given_seeds(flat, domains))
    except DomainError as exc:
        raise UnitError(str(exc)) from None


# ---------------------------------------------------------------- the check
@dataclass(frozen=True)
class UnitReport:
    """What :func:`check_units` checked.

    Attributes
    ----------
    domains : dict of int to str
        Flat bond number -> domain.
    checked : int
        Relations whose dimension was verified.
    unchecked : tuple of str
        Relations that could not be (unknown domain, parameter without units).
    units : dict of str to str
        States and inputs -> their unit (named or SI base), where known.
    dims : dict of str to tuple
        The same as dimension vectors (SI base exponents; see ``_dims``).
    """

    domains: Mapping[int, str]
    checked: int
    unchecked: tuple[str, ...]
    units: Mapping[str, str]
    dims: Mapping[str, Dim] = field(default_factory=dict)


class _DimLocal(LocalVariables):
    """Bond variables, states and the input as placeholder symbols of known dimension."""

    def __init__(self, el: Element, flat: FlatGraph, effort_in: Sequence[bool],
                 port_dims: Sequence[Optional[tuple[Dim, Dim]]], known: dict) -> None:
        self.el, self.flat, self._ein, self.count = el, flat, list(effort_in), len(effort_in)
        self._inc = flat.incidence[el.name]
        self.states = ()
        self.input_symbol = sympy.Dummy(f"u_{el.name}")
        self._inputs = []
        #: the placeholders by the names messages show: the bond variable (``e_3``: the
        #: effort of bond 3), never an internal name
        self.shown: dict = {}
        for p, dims in enumerate(port_dims):
            sym = sympy.Dummy(f"in{p}")
            known[sym] = None if dims is None else dims[0 if effort_in[p] else 1]
            self._inputs.append(sym)
            self.shown[sym] = sympy.Symbol(f"{'e' if effort_in[p] else 'f'}_{self._inc[p] + 1}")
        self.shown[self.input_symbol] = sympy.Symbol(el.name)

    def sign(self, port: int) -> int:
        return 1 if self.into(port) else -1

    def into(self, port: int) -> bool:
        return self.flat.bonds[self._inc[port]].head == self.el.name

    def effort_in(self, port: int) -> bool:
        return self._ein[port]

    def input(self, port: int) -> sympy.Expr:
        return self._inputs[port]

    def resolve(self, expr: sympy.Expr) -> sympy.Expr:
        return expr          # signals stay: a relation using them is not checked


def _parameter_dims(values: Mapping[str, Any]) -> tuple[dict, dict]:
    dims: dict[str, Optional[Dim]] = {}
    shown: dict[str, str] = {}
    for name, v in values.items():
        if _carries_units(v):
            _, d, unit = _si(v, name)
            dims[name], shown[name] = d, unit
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            dims[name] = None     # a bare number: no units declared
    return dims, shown


def _exponent(expr: sympy.Expr, sym: sympy.Symbol, known: dict) -> Optional[sympy.Expr]:
    """The power of ``sym`` in the dimension of ``expr`` (via a probe dimension)."""
    probe = ZERO[:-1] + (sympy.Integer(1),)
    try:
        return dims_of(expr, {**known, sym: probe})[-1]
    except (Unknown, Mismatch):
        return None


def check_units(graph: Union[BondGraph, FlatGraph], values: Mapping[str, Any], *,
                domains: Optional[Mapping[Union[str, int], str]] = None) -> UnitReport:
    """Check every constitutive relation's dimension; refuse the first wrong one.

    Parameters
    ----------
    graph : BondGraph or FlatGraph
    values : mapping of str to value
        Parameter values; those carrying sympy units (``3*u.newton/u.mm``)
        declare the parameter's unit.  Bare numbers are not checked.
    domains : mapping, optional
        Seeds for :func:`bond_domains`.

    Raises
    ------
    UnitError
        Naming the element, the parameter, the unit of its value and the unit
        its bond's domain needs (or the relation and both dimensions).
    """
    from ...causality import assign_causality

    if not isinstance(values, Mapping):
        raise UnitError(f"check_units: values must be a mapping of parameter name to value; got "
                        f"{type(values).__name__}")
    if domains is not None and not isinstance(domains, Mapping):
        raise UnitError(f"check_units: domains must be a mapping of element name or bond number "
                        f"to domain name; got {type(domains).__name__}")
    flat = _flat(graph)
    doms = bond_domains(graph, domains=domains)
    aug = assign_causality(flat)
    pdims, shown = _parameter_dims(values)
    checked, unchecked, units = 0, [], {}
    dims: dict[str, Dim] = {}
    for el in flat.elements:
        inc = flat.incidence[el.name]
        ein = [aug.stroke_at_head[k] if flat.bonds[k].head == el.name else
               not aug.stroke_at_head[k] for k in inc]
        port_dims = [(DOMAINS[doms[k + 1]].effort_dims, DOMAINS[doms[k + 1]].flow_dims)
                     if (k + 1) in doms else None for k in inc]
        known: dict = {T_SYM: _TIME}
        local = _DimLocal(el, flat, ein, port_dims, known)
        rates = el.state_derivatives(local)
        _learn(rates, known, pdims)
        names = el.state_names(ein)
        state_syms = []
        for name, rate in zip(names, rates):
            sym = sympy.Dummy(name)
            local.shown[sym] = sympy.Symbol(name)          # messages show the state's name
            try:
                known[sym] = tuple(a + b for a, b in zip(dims_of(rate, known), _TIME))
                units[name], dims[name] = text(known[sym]), known[sym]
            except (Unknown, Mismatch):
                known[sym] = None
            state_syms.append(sym)
        local.states = tuple(state_syms)
        skip = set(el.derivative_ports(ein))
        for p in range(len(inc)):
            if p in skip:
                continue
            what = f"{el.label()}, {'flow' if ein[p] else 'effort'} on bond {inc[p] + 1}"
            pair = port_dims[p]
            if pair is None:
                unchecked.append(f"{what}: bond of unknown domain")
                continue
            want = pair[1 if ein[p] else 0]
            rel = el.output(local, p)
            if rel == 0:                   # zero has every unit (a Fixed, a Ground)
                checked += 1
                continue
            _learn((rel,), known, pdims)
            if local.input_symbol in rel.free_symbols and el.input_name():
                known[local.input_symbol] = want
                dims[el.input_name() or ""] = want
                units[el.input_name() or ""] = text(want)
            try:
                got = dims_of(rel, known)
            except Unknown as exc:
                unchecked.append(f"{what}: {exc} has no unit")
                continue
            except Mismatch as exc:
                given = ", ".join(f"{s.name} in {shown[s.name]}" for s in
                                  sorted(rel.free_symbols, key=str) if s.name in shown)
                raise UnitError(f"{el.label()}: its relation on bond {inc[p] + 1} adds or "
                                f"transforms quantities of different units "
                                f"({_readable(exc, local)}); its "
                                f"parameters: {given or 'none with units'}") from None
            if got[:-1] != want[:-1]:
                raise UnitError(_culprit(el, rel, known, got, want, inc[p] + 1,
                                         doms[inc[p] + 1], shown, rel.xreplace(local.shown)))
            checked += 1
    return UnitReport(doms, checked, tuple(unchecked), units, dims)


def _readable(exc: Exception, local: _DimLocal) -> str:
    """An exception's text with the placeholders' internal names replaced by bond variables."""
    out = str(exc)
    for dummy, name in local.shown.items():
        out = out.replace(str(dummy), str(name))
    return out


def _learn(exprs, known: dict, pdims: Mapping[str, Optional[Dim]]) -> None:
    """Give the parameters (plain symbols) of some relations the dimensions of their values."""
    for ex in exprs:
        for sym in ex.free_symbols:
            if type(sym) is sympy.Symbol and sym not in known:
                known[sym] = pdims.get(sym.name)


def _culprit(el, rel, known, got, want, bond, dom, shown, printed) -> str:
    d = DOMAINS[dom]
    need = f"(effort {text(d.effort_dims)}, flow {text(d.flow_dims)})"
    params = [s for s in rel.free_symbols if type(s) is sympy.Symbol and known.get(s) is not None
              and s.name in shown]
    if len(params) == 1:
        (p,) = params
        a = _exponent(rel, p, known)
        if a:
            expected = tuple(k + (w - g) / a for k, w, g in zip(known[p], want, got))
            return (f"{el.label()}, parameter {p.name}: its value has the unit {shown[p.name]} "
                    f"({text(known[p])}), but its {dom} bond {bond} needs {text(expected)} {need}")
    return (f"{el.label()}: its relation {printed} on its {dom} bond {bond} has the unit {text(got)}, "
            f"expected {text(want)} {need}")


def signal_units(report: UnitReport, names: Sequence[str]) -> dict[str, str]:
    """The units of some states and inputs (by name) from a report; unknown ones omitted.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("m")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> _ = g.connect("F", "m")
    >>> rep = check_units(g, {}, domains={"F": "translation"})
    >>> signal_units(rep, ["p_m", "F"])
    {'p_m': 'kilogram*meter/second', 'F': 'newton'}
    """
    return {n: report.units[n] for n in names if n in report.units}

