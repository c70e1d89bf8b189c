"""Chemical reaction networks as bond graphs: species, reactions, stoichiometry.

A :class:`ReactionNetwork` is a builder: its species are objects, a
reaction is given by species and *integer* stoichiometric coefficients
(``A + 2*B``; no text is parsed), and :meth:`ReactionNetwork.graph` returns
the bond graph of Gawthrop and Crampin (*Proc. R. Soc. A* 470, 2014), the
form BondGraphTools and BondGraphs.jl build:

* each species ``X`` is a ``Ce:X`` (or a :class:`Chemostat` / :class:`Flowstat`)
  on a 0-junction ``mu_X`` (common chemical potential);
* each reaction ``r`` is an ``Re:r`` between a 1-junction ``r_f`` gathering
  its substrates and a 1-junction ``r_r`` gathering its products;
* a coefficient ``n > 1`` is a ``TF`` between the species and the reaction
  (``n_<r>_<X>``): the reaction side sees ``n mu_X`` and the species
  ``n v``.

:func:`stoichiometric_matrix` reads the matrix back from *any* graph holding
``Ce`` and ``Re`` elements (built by hand or by the builder), by deriving the
graph with each reaction's flow made an input; :func:`conservation_laws`
gives its left null space (the conserved moieties) as integer vectors.

Examples
--------
>>> import bondgraph as bg
>>> net = ReactionNetwork("abc")
>>> A, B, C = net.species("A", K=1), net.species("B", K=1), net.species("C", K=1)
>>> _ = net.reaction("r1", A + B, C, r=1)
>>> model = bg.derive(net.graph())
>>> model.rhs[0]
-q_A*q_B + q_C
>>> stoichiometric_matrix(net.graph()).matrix
Matrix([
[-1],
[-1],
[ 1]])
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass, field, replace
from typing import Any, Optional, Union

import sympy

from ..elements import TF, One, Zero
from ..errors import ModelStructureError
from ..flatten import FlatGraph, flatten
from ..graph import BondGraph
from ..elements.protocol import Decision, Element, LocalVariables, check_name
from .._support.sympify import ParameterLike
from ._chem_elements import (FARADAY, GAS_CONSTANT, R_GAS, TEMPERATURE, Ce, Chemostat, Flowstat,
                             Re)

__all__ = ["Ce", "Re", "Chemostat", "Flowstat", "Species", "Term", "Side", "ReactionNetwork",
           "Reaction", "Stoichiometry", "stoichiometric_matrix", "conservation_laws",
           "equilibrium_constant", "GAS_CONSTANT", "FARADAY", "R_GAS", "TEMPERATURE"]


class ReactionError(ModelStructureError):
    """A reaction or species given to a :class:`ReactionNetwork` is not valid."""


def _coefficient(n: object, what: str) -> int:
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or int(n) < 1:
        raise ReactionError(f"{what}: a stoichiometric coefficient must be a positive integer, "
                            f"got {n!r}")
    return int(n)


@dataclass(frozen=True)
class Species:
    """A species of a :class:`ReactionNetwork` (returned by :meth:`ReactionNetwork.species`).

    ``2*A`` is the term ``(A, 2)``; ``A + B`` a side of a reaction.

    Examples
    --------
    >>> net = ReactionNetwork("n")
    >>> A, B = net.species("A"), net.species("B")
    >>> A + 2*B
    Side(terms=(Term(species='A', n=1), Term(species='B', n=2)))
    """

    name: str
    network: str = field(repr=False)

    def __mul__(self, n: object) -> "Term":
        return Term(self.name, _coefficient(n, f"species {self.name}"), self.network)

    __rmul__ = __mul__

    def __add__(self, other: object) -> "Side":
        return Side.of(self) + other


@dataclass(frozen=True)
class Term:
    """``n`` molecules of a species in a reaction."""

    species: str
    n: int
    #: the network the species belongs to ('' for a term built by hand)
    network: str = field(default="", repr=False, compare=False)

    def __add__(self, other: object) -> "Side":
        return Side.of(self) + other


@dataclass(frozen=True)
class Side:
    """One side of a reaction: terms in order (a species at most once)."""

    terms: tuple[Term, ...]

    @staticmethod
    def of(item: object) -> "Side":
        if isinstance(item, Side):
            return item
        if isinstance(item, Term):
            return Side((item,))
        if isinstance(item, Species):
            return Side((Term(item.name, 1, item.network),))
        raise ReactionError(f"a reaction side is made of species (A, 2*B, A + B), got "
                            f"{type(item).__name__} {item!r} (text is never parsed)")

    def __add__(self, other: object) -> "Side":
        terms = self.terms + Side.of(other).terms
        names = [t.species for t in terms]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ReactionError(f"species {', '.join(dup)} appears twice on one side of a "
                                "reaction; write its coefficient once (2*A, not A + A)")
        return Side(terms)

    __radd__ = __add__


@dataclass(frozen=True)
class Reaction:
    """A reaction of a :class:`ReactionNetwork`: its name, sides and rate constant."""

    name: str
    substrates: Side
    products: Side
    r: ParameterLike
    kf: ParameterLike = None
    kr: ParameterLike = None


class ReactionNetwork:
    """A builder of chemical reaction networks; :meth:`graph` returns the bond graph.

    Parameters
    ----------
    name : str
        The graph's name.
    temperature, gas_constant : optional, keyword only
        Passed to every species and reaction (default symbols ``T``, ``R_gas``).

    Examples
    --------
    Reversible Michaelis--Menten with chemostats ``S`` and ``P``
    (``E + S = C``, ``C = E + P``):

    >>> import bondgraph as bg
    >>> net = ReactionNetwork("mm")
    >>> E, C = net.species("E", K=1), net.species("C", K=1)
    >>> S, P = net.chemostat("S", K=1, amount=2), net.chemostat("P", K=1, amount=1)
    >>> _ = net.reaction("r1", E + S, C, r=1); _ = net.reaction("r2", C, E + P, r=1)
    >>> [sympy.expand(x) for x in bg.derive(net.graph()).rhs]
    [2*q_C - 3*q_E, -2*q_C + 3*q_E]
    """

    def __init__(self, name: str, *, temperature: ParameterLike = None,
                 gas_constant: ParameterLike = None) -> None:
        self.name = check_name(name, "reaction network")
        self._thermo: dict[str, Any] = {"temperature": temperature, "gas_constant": gas_constant}
        self._species: dict[str, Element] = {}
        self._reactions: dict[str, Reaction] = {}

    # ------------------------------------------------------------ species
    def _add_species(self, el: Element) -> Species:
        if el.name in self._species or el.name in self._reactions:
            raise ReactionError(f"reaction network {self.name!r}: the name {el.name!r} is "
                                "already used")
        self._species[el.name] = el
        return Species(el.name, self.name)

    def species(self, name: str, *, K: ParameterLike = None) -> Species:
        """A species ``Ce:name`` (its amount ``q_name`` is a state)."""
        return self._add_species(Ce(name, K=K, **self._thermo))

    def chemostat(self, name: str, *, K: ParameterLike = None,
                  amount: ParameterLike = None) -> Species:
        """A species held at ``amount`` (default symbol ``x_name``)."""
        return self._add_species(Chemostat(name, K=K, amount=amount, **self._thermo))

    def flowstat(self, name: str, *, flow: ParameterLike = None) -> Species:
        """A species whose net molar flow is ``flow`` (default: a model input)."""
        return self._add_species(Flowstat(name, value=flow))

    # ------------------------------------------------------------ reactions
    def reaction(self, name: str, substrates: Union[Species, Term, Side],
                 products: Union[Species, Term, Side], *, r: ParameterLike = None,
                 kf: ParameterLike = None, kr: ParameterLike = None) -> Reaction:
        """Add the reaction ``substrates = products`` with rate constant ``r``.

        ``kf`` and ``kr`` instead of ``r`` give the mass-action form (see :class:`Re`).

        Raises
        ------
        ReactionError
            For a species of another network or not yet added, a name in use,
            a coefficient that is not a positive integer.
        """
        check_name(name, "reaction")
        if name in self._reactions or name in self._species:
            raise ReactionError(f"reaction network {self.name!r}: the name {name!r} is "
                                "already used")
        sides = []
        for what, side in (("substrates", substrates), ("products", products)):
            s = Side.of(side)
            for term in s.terms:
                if term.network and term.network != self.name:      # in any form: A, 2*A, A + B
                    raise ReactionError(f"reaction {name}: {what} species {term.species} belongs "
                                        f"to network {term.network!r}, not {self.name!r}; use "
                                        f"the species returned by network {self.name!r}")
                if term.species not in self._species:
                    raise ReactionError(f"reaction {name}: {what} species {term.species!r} is "
                                        f"not in network {self.name!r}; add it with "
                                        "species() first")
            sides.append(s)
        Re(name, r=r, kf=kf, kr=kr, **self._thermo)            # validate now
        rx = Reaction(name, sides[0], sides[1], r, kf, kr)
        self._reactions[name] = rx
        return rx

    # ------------------------------------------------------------ graph
    def graph(self) -> BondGraph:
        """The bond graph (a new builder on each call).

        Raises
        ------
        ReactionError
            A species that takes part in no reaction (its node would be bonded to it alone).
        """
        used = {t.species for rx in self._reactions.values()
                for t in rx.substrates.terms + rx.products.terms}
        idle = [n for n in self._species if n not in used]
        if idle:
            raise ReactionError(f"reaction network {self.name!r}: species {', '.join(idle)} "
                                f"take{'s' if len(idle) == 1 else ''} part in no reaction; add a "
                                "reaction with it or leave it out")
        g = BondGraph(self.name)
        for sp_name, el in self._species.items():
            g.add(el, Zero(f"mu_{sp_name}"))
            g.connect(f"mu_{sp_name}", sp_name) if isinstance(el, Ce) else g.connect(sp_name, f"mu_{sp_name}")
        for rx in self._reactions.values():
            fwd, rev = f"{rx.name}_f", f"{rx.name}_r"
            g.add(Re(rx.name, r=rx.r, kf=rx.kf, kr=rx.kr, **self._thermo), One(fwd), One(rev))
            g.connect(fwd, rx.name)
            g.connect(rx.name, rev)
            for term in rx.substrates.terms:
                self._link(g, f"mu_{term.species}", fwd, term.n, f"n_{rx.name}_{term.species}",
                           substrate=True)
            for term in rx.products.terms:
                self._link(g, rev, f"mu_{term.species}", term.n, f"n_{rx.name}_{term.species}",
                           substrate=False)
        return g

    @staticmethod
    def _link(g: BondGraph, tail: str, head: str, n: int, tf: str, *, substrate: bool) -> None:
        if n == 1:
            g.connect(tail, head)
            return
        # TF port 1 is the bond into it: e1 = m e2, f2 = m f1
        g.add(TF(tf, sympy.Rational(1, n) if substrate else sympy.Integer(n)))
        g.connect(tail, tf)
        g.connect(tf, head)


# ---------------------------------------------------------------- stoichiometry
@dataclass(frozen=True, eq=False)
class _RateProbe(Element):
    """A reaction with its molar flow made an input ``v_<name>`` (for the stoichiometry)."""

    kind = "Re"
    bonds = (2, 2)

    def forced_causality(self, ports):
        return (Decision(0, True, "probe"), Decision(1, True, "probe"))

    def output_dependencies(self, effort_in, causality):
        return ((), ())

    def input_name(self) -> Optional[str]:
        return f"v_{self.name}"

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        return local.input_symbol


@dataclass(frozen=True)
class Stoichiometry:
    """The stoichiometric matrix of a graph: ``dq/dt = N v`` (species by reactions).

    Attributes
    ----------
    species : tuple of str
        The ``Ce`` species (rows), in graph order.
    reactions : tuple of str
        The ``Re`` reactions (columns).
    matrix : sympy.ImmutableMatrix
        ``N``; integer for integer coefficients.
    """

    species: tuple[str, ...]
    reactions: tuple[str, ...]
    matrix: sympy.ImmutableMatrix


def stoichiometric_matrix(graph: Union[BondGraph, FlatGraph]) -> Stoichiometry:
    """The stoichiometric matrix ``N`` of the ``Ce`` species and ``Re`` reactions of a graph.

    Read from the junction structure: each reaction's flow is made an input
    ``v_r`` and ``N[i, j] = d(dq_i/dt)/d(v_j)``.  Chemostats and flowstats are
    not rows (their amounts are not states).

    Raises
    ------
    ModelStructureError
        When the graph has no reaction, or a species' rate is not linear in
        the reaction flows (the graph is not a reaction network).

    Examples
    --------
    >>> net = ReactionNetwork("a2b")
    >>> A, B = net.species("A"), net.species("B")
    >>> _ = net.reaction("r", A, 2*B)
    >>> stoichiometric_matrix(net.graph()).matrix.T
    Matrix([[-1, 2]])
    """
    from ..causality import assign_causality
    from ..model import derive

    flat = graph if isinstance(graph, FlatGraph) else flatten(graph)
    reactions = tuple(el.name for el in flat.elements if isinstance(el, Re))
    if not reactions:
        raise ModelStructureError(f"model {flat.name!r} has no Re reaction; the stoichiometric "
                                  "matrix needs one")
    probed = replace(flat, elements=tuple(_RateProbe(el.name) if isinstance(el, Re) else el
                                          for el in flat.elements))
    model = derive(assign_causality(probed))
    species = tuple(el.name for el in flat.elements if isinstance(el, Ce))
    rows = {name: i for i, name in enumerate(model.state_names)}
    v = [sympy.Symbol(f"v_{r}", real=True) for r in reactions]
    N = sympy.zeros(len(species), len(reactions))
    for i, name in enumerate(species):
        key = f"q_{name}"
        if key not in rows:
            raise ModelStructureError(f"model {flat.name!r}: species Ce:{name} is in derivative "
                                      "causality, so its amount is not a state")
        terms = sympy.expand(model.rhs[rows[key]]).as_coefficients_dict()
        for j, vj in enumerate(v):
            N[i, j] = terms.pop(vj, 0)
        rest = sympy.Add(*[c * t for t, c in terms.items()])
        if rest != 0:
            raise ModelStructureError(f"model {flat.name!r}: the rate of species Ce:{name} has "
                                      f"the term {rest} that is not a reaction flow")
    return Stoichiometry(species, reactions, sympy.ImmutableMatrix(N))


def conservation_laws(graph: Union[BondGraph, FlatGraph]) -> tuple[dict[str, int], ...]:
    """The conserved moieties: a basis of the left null space of ``N`` (integer vectors).

    Each law is a mapping species -> coefficient with ``sum c_i q_i`` constant
    in time, with the smallest integer coefficients.  The basis is the
    reduced row echelon form of sympy's null space of ``N^T`` (pivots on the
    species in graph order): the familiar moieties for small networks (free
    enzyme ``E + C``), but not in general the non-negative extreme rays of
    the conservation cone, which are not computed.

    Examples
    --------
    >>> net = ReactionNetwork("mm")
    >>> E, C = net.species("E"), net.species("C")
    >>> S, P = net.chemostat("S"), net.chemostat("P")
    >>> _ = net.reaction("r1", E + S, C); _ = net.reaction("r2", C, E + P)
    >>> conservation_laws(net.graph())
    ({'E': 1, 'C': 1},)
    """
    st = stoichiometric_matrix(graph)
    basis = st.matrix.T.nullspace()
    if not basis:
        return ()
    rows = sympy.Matrix.vstack(*[v.T for v in basis]).rref()[0]
    laws = []
    for i in range(rows.rows):
        row = rows.row(i)
        scale = sympy.ilcm(*[sympy.fraction(x)[1] for x in row])
        ints = [int(x * scale) for x in row]
        g = sympy.igcd(*ints) if len(ints) > 1 else abs(ints[0])
        laws.append({s: c // g for s, c in zip(st.species, ints) if c})
    return tuple(laws)


def equilibrium_constant(network: ReactionNetwork, reaction: str) -> sympy.Expr:
    """``K_eq = prod K_s^n_s / prod K_p^n_p`` of a reaction (detailed balance).

    At equilibrium the forward and reverse affinities are equal, so
    ``prod q_p^n_p / prod q_s^n_s = K_eq``; a chemostat's ``K`` counts like a
    species'.

    Examples
    --------
    >>> net = ReactionNetwork("n")
    >>> A, B = net.species("A", K=2), net.species("B", K=3)
    >>> _ = net.reaction("r", A, 2*B)
    >>> equilibrium_constant(net, "r")
    2/9
    """
    try:
        rx = network._reactions[reaction]
    except KeyError:
        raise ReactionError(f"reaction network {network.name!r} has no reaction "
                            f"{reaction!r}") from None

    def k_of(name: str) -> sympy.Expr:
        el = network._species[name]
        if not isinstance(el, (Ce, Chemostat)):
            raise ReactionError(f"reaction {reaction}: species {name} is a flowstat, which has "
                                "no thermodynamic constant K")
        return el.K_value

    num = sympy.Mul(*[k_of(t.species) ** t.n for t in rx.substrates.terms])
    den = sympy.Mul(*[k_of(t.species) ** t.n for t in rx.products.terms])
    return num / den
