"""Thermal components: pseudo bond graphs (T, Q) and true thermal ones (T, entropy flow).

Pseudo bond graph (effort temperature K, flow heat flow W; Karnopp,
Margolis and Rosenberg, *System Dynamics*, 5th ed., Sec. 12.4): nodes are
0-junctions of temperature; :class:`HeatCapacity` is a ``C`` of capacitance
``m c`` (its state is the heat stored, ``T = q/(m c)``), conduction and
convection are linear ``R`` (``L/(k A)``, ``1/(h A)``), radiation the
nonlinear two-port :class:`Radiation`.

True thermal bond graph (effort ``T``, flow entropy flow W/K; Cellier,
*Continuous System Modeling*, 1991, Ch. 8): :class:`EntropyCapacity`,
:class:`HeatConduction` and the element :class:`RS`, which lets an
electrical resistor or a damper heat a body.

Examples
--------
Two bodies exchanging heat through a conductor:

>>> import bondgraph as bg
>>> g = bg.BondGraph("two_bodies")
>>> g.add(HeatCapacity("b1", capacity=2), HeatCapacity("b2", capacity=3),
...       Conduction("rod", resistance=5), bg.Zero("T1"), bg.Zero("T2"))
>>> for t, h in [("T1", "b1.p"), ("T2", "b2.p"), ("T1", "rod.a"), ("rod.b", "T2")]:
...     _ = g.connect(t, h)
>>> bg.derive(g).state_space().A
Matrix([
[-1/10,  1/15],
[ 1/10, -1/15]])
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ..elements import C, One, Port, R, Se, Sf
from .._support.sympify import ParameterLike
from ..elements.rules import check_numbers, rule
from ..errors import ParameterError
from ._component import Component, SourceComponent
from ._thermal_elements import (RS, SIGMA_SB, STEFAN_BOLTZMANN, EntropyCapacity, HeatConduction,
                                Radiation)

__all__ = ["HeatCapacity", "Conduction", "Convection", "RadiationExchange", "HeatFlowSource",
           "TemperatureSource", "EntropyStore", "TrueConduction", "Radiation", "EntropyCapacity",
           "HeatConduction", "RS", "STEFAN_BOLTZMANN", "SIGMA_SB"]

_KMR = "Karnopp, Margolis and Rosenberg, System Dynamics, 5th ed., Sec. 12.4"
_INC = "Incropera et al., Fundamentals of Heat and Mass Transfer, 6th ed., Ch. 1 and 3"
_CEL = "Cellier, Continuous System Modeling, 1991, Ch. 8"


class _TwoTerminal(Component):
    """A resistance on a 1-junction between ports ``a`` (heat in) and ``b`` (heat out)."""

    port_names: tuple[str, ...] = ("a", "b")
    port_domains = {"a": "thermal", "b": "thermal"}
    domain: ClassVar[str] = "thermal"

    def _series(self, element) -> None:
        self.add(Port("a"), Port("b"), One("Q"), element)
        self.connect("a", "Q")
        self.connect("Q", "b")
        self.connect("Q", element.name)


class HeatCapacity(Component):
    """A body of heat capacity ``C = m c_p`` (J/K): ``T = q/C``, ``dq/dt = Q`` (pseudo).

    Its state ``q_<name>.C`` is the heat stored (J); start it at ``C*T0``
    for a body at ``T0``.  One port ``p`` (heat flow in).

    Parameters
    ----------
    name : str
    capacity : optional, keyword only
        ``m c_p``; default symbol ``<name>_capacity``.

    Examples
    --------
    >>> HeatCapacity("body", capacity=4).ports
    ('p',)
    """

    domain = "thermal"
    port_names = ("p",)
    port_domains = {"p": "thermal"}
    law = "T = q / C,  dq/dt = Q"
    reference = _KMR
    symbol = "C"

    def __init__(self, name: str, *, capacity: ParameterLike = None) -> None:
        self._capacity = capacity
        super().__init__(name)

    def build(self) -> None:
        self.add(Port("p"), C("C", self.param(self._capacity, "capacity")))
        self.connect("p", "C")


class Conduction(_TwoTerminal):
    """Conduction through a slab, ``T_a - T_b = R Q`` with ``R = L/(k A)`` (pseudo).

    Give ``resistance`` (K/W), or ``length``, ``conductivity`` and ``area``
    (Fourier's law, Incropera Eq. 3.6).

    Examples
    --------
    >>> g = Conduction("wall", length=0.2, conductivity=0.5, area=4)
    >>> g["R"].parameter
    0.100000000000000
    """

    law = "T_a - T_b = R Q,  R = L / (k A)"
    reference = _INC + " (Fourier's law, Eq. 3.6)"
    symbol = "R"

    def __init__(self, name: str, *, resistance: ParameterLike = None,
                 length: ParameterLike = None, conductivity: ParameterLike = None,
                 area: ParameterLike = None) -> None:
        if resistance is not None and (length, conductivity, area) != (None, None, None):
            raise ParameterError(f"Conduction {name!r}: give resistance or the geometry (length, "
                                 "conductivity, area), not both: one of them would be ignored")
        self._given = (resistance, length, conductivity, area)
        super().__init__(name)

    def build(self) -> None:
        resistance, length, conductivity, area = self._given
        if resistance is None and (length, conductivity, area) != (None, None, None):
            value = (self.param(length, "length") /
                     (self.param(conductivity, "conductivity") * self.param(area, "area")))
        else:
            value = self.param(resistance, "resistance")
        self._series(R("R", value))


class Convection(_TwoTerminal):
    """Convection at a surface, ``T_a - T_b = Q/(h A)`` (Newton's law of cooling; pseudo).

    Examples
    --------
    >>> Convection("air", h=10, area=2)["R"].parameter
    1/20
    """

    law = "T_a - T_b = Q / (h A)"
    reference = _INC + " (Newton's law of cooling, Eq. 1.3a)"
    symbol = "R"

    def __init__(self, name: str, *, h: ParameterLike = None, area: ParameterLike = None) -> None:
        self._given = (h, area)
        super().__init__(name)

    def build(self) -> None:
        h, area = self._given
        self._series(R("R", 1 / (self.param(h, "h") * self.param(area, "area"))))


class RadiationExchange(Component):
    """Radiation from surface ``a`` to ``b``: ``Q = eps sigma A (T_a**4 - T_b**4)`` (pseudo).

    A nonlinear resistance of both temperatures (the :class:`Radiation`
    two-port).  ``sigma`` defaults to the symbol ``sigma_SB``
    (:data:`STEFAN_BOLTZMANN`).

    Examples
    --------
    >>> RadiationExchange("sky", area=1, emissivity=0.9).ports
    ('a', 'b')
    """

    domain = "thermal"
    port_names = ("a", "b")
    port_domains = {"a": "thermal", "b": "thermal"}
    law = "Q = eps sigma A (T_a^4 - T_b^4)"
    reference = _INC + " (Stefan-Boltzmann law, Eq. 1.7)"
    symbol = "Rrad"

    def __init__(self, name: str, *, area: ParameterLike = None,
                 emissivity: ParameterLike = None, sigma: ParameterLike = None) -> None:
        self._given = (area, emissivity, sigma)
        super().__init__(name)

    def build(self) -> None:
        area, emissivity, sigma = self._given
        self.add(Port("a"), Port("b"),
                 Radiation("rad", area=self.param(area, "area"),
                           emissivity=self.param(emissivity, "emissivity"), sigma=sigma))
        self.connect("a", "rad")
        self.connect("rad", "b")


class HeatFlowSource(SourceComponent):
    """A prescribed heat flow ``Q`` (W) out of port ``p``: the input ``<name>.Q``, or ``value``.

    Examples
    --------
    >>> HeatFlowSource("heater", value=100)["Q"].value
    100
    """

    domain = "thermal"
    port_domains = {"p": "thermal"}
    law = "Q = Q_s (a flow source)"
    reference = _KMR
    symbol = "Sf"
    source = Sf
    inner = "Q"


@dataclass(frozen=True, eq=False)
class _Temperature(Se):
    """The effort source of :class:`TemperatureSource`: an absolute temperature, not negative
    (0 K: the sky of a radiation closed form)."""

    def value_rules(self) -> tuple:
        return rule(self.value, "absolute temperature (K)", "nonnegative", opt_out=False)


class TemperatureSource(SourceComponent):
    """A prescribed temperature ``T`` (K) at port ``p`` (an ambient, a thermostat).

    The input ``<name>.T``, or ``value``.  Serves pseudo and true thermal graphs.

    Examples
    --------
    >>> TemperatureSource("ambient", value=293.15)["T"].value
    293.150000000000
    """

    domain = "thermal"
    port_domains = {"p": "thermal"}
    #: a temperature is the effort of both thermal graphs: the port takes the domain of
    #: what it is bonded to (:mod:`bondgraph.flatten`)
    port_domain_choices = {"p": ("thermal", "thermal (entropy)")}
    law = "T = T_s (an effort source)"
    reference = _KMR
    symbol = "Se"
    source = _Temperature
    inner = "T"

    def __init__(self, name: str, *, value: ParameterLike = None) -> None:
        check_numbers(f"TemperatureSource {name!r}", _Temperature("T", value=value).value_rules())
        super().__init__(name, value=value)


class EntropyStore(Component):
    """A body in a true thermal graph: ``T = T0 exp(S/c)``, state the entropy ``S`` (J/K).

    One port ``p`` (entropy flow in); the :class:`EntropyCapacity` element.

    Examples
    --------
    >>> EntropyStore("mass", heat_capacity=450, reference_temperature=300)["S"].forward()
    300*exp(q/450)
    """

    domain = "thermal (entropy)"
    port_names = ("p",)
    port_domains = {"p": "thermal (entropy)"}
    law = "T = T0 exp(S / c),  dS/dt = S'"
    reference = _CEL + ", Sec. 8.3"
    symbol = "C"

    def __init__(self, name: str, *, heat_capacity: ParameterLike = None,
                 reference_temperature: ParameterLike = None) -> None:
        self._given = (heat_capacity, reference_temperature)
        super().__init__(name)

    def build(self) -> None:
        c, T0 = self._given
        self.add(Port("p"), EntropyCapacity("S", heat_capacity=self.param(c, "heat_capacity"),
                                            reference_temperature=self.param(T0, "T0")))
        self.connect("p", "S")


class TrueConduction(Component):
    """Conduction in a true thermal graph: ``Q = (T_a - T_b)/R``, entropy flows ``Q/T``.

    The :class:`HeatConduction` element between ports ``a`` and ``b``; it
    produces the entropy ``Q (1/T_b - 1/T_a)``.

    Examples
    --------
    >>> TrueConduction("k", resistance=2).ports
    ('a', 'b')
    """

    domain = "thermal (entropy)"
    port_names = ("a", "b")
    port_domains = {"a": "thermal (entropy)", "b": "thermal (entropy)"}
    law = "Q = (T_a - T_b) / R,  S'_a = Q / T_a,  S'_b = Q / T_b"
    reference = _CEL + ", Sec. 8.4"
    symbol = "RS"

    def __init__(self, name: str, *, resistance: ParameterLike = None) -> None:
        self._resistance = resistance
        super().__init__(name)

    def build(self) -> None:
        self.add(Port("a"), Port("b"),
                 HeatConduction("k", resistance=self.param(self._resistance, "resistance")))
        self.connect("a", "k")
        self.connect("k", "b")
