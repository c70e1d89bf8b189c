"""Thermal elements: radiation, entropy-form capacity, true-thermal conduction, ``RS``.

Two thermal bond graphs are in use (Karnopp, Margolis and Rosenberg, *System
Dynamics*, 5th ed., Sec. 12.4; Cellier, *Continuous System Modeling*, 1991,
Ch. 8):

* the *pseudo* bond graph: effort temperature ``T`` (K), flow heat flow ``Q``
  (W); ``T*Q`` is not a power, but heat capacities and thermal resistances
  are the ordinary linear ``C`` and ``R``;
* the *true* thermal bond graph: effort ``T``, flow entropy flow ``S'`` (W/K),
  so ``T*S'`` is the heat flow (a power).  A body of constant heat capacity
  ``c`` stores entropy with ``T = T0 exp(S/c)`` (:class:`EntropyCapacity`);
  conduction produces entropy (:class:`HeatConduction`); the resistive source
  :class:`RS` turns the power an electrical or mechanical resistance
  dissipates into the entropy flow ``P/T`` entering a thermal port.

Examples
--------
>>> import sympy
>>> from bondgraph.library.thermal import HeatConduction
>>> T1, T2 = sympy.symbols("T1 T2", positive=True)
>>> [sympy.simplify(x) for x in HeatConduction("k", resistance=2).flows(T1, T2)]
[(T1 - T2)/(2*T1), (T1 - T2)/(2*T2)]
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar, Optional, Sequence, cast

import sympy

from ..elements import C
from ..errors import ParameterError
from ..elements.protocol import (ARBITRARY, RESISTIVE, CausalPorts, Choice, Decision, Element,
                        LocalVariables, rename)
from ..signals import e as E_VAR, q as Q_VAR
from .._support.sympify import ParameterLike
from ._twoport import ConductanceTwoPort, DirectedTwoPort, positive_parameter
from ..elements.rules import rule

__all__ = ["Radiation", "EntropyCapacity", "HeatConduction", "RS", "STEFAN_BOLTZMANN",
           "SIGMA_SB"]

#: the Stefan--Boltzmann constant, W/(m^2 K^4) (CODATA 2018, exact)
STEFAN_BOLTZMANN = 5.670374419e-8
#: its default symbol in :class:`Radiation` (give its value with the others)
SIGMA_SB = sympy.Symbol("sigma_SB", positive=True)


def _param(el: Element, value: ParameterLike, what: str) -> sympy.Expr:
    return positive_parameter(value, sympy.Symbol(f"{what}_{el.name}", positive=True),
                              owner=el.label(), what=what)


@dataclass(frozen=True, eq=False)
class Radiation(ConductanceTwoPort):
    """Radiative heat exchange between two surfaces (pseudo bond graph): a nonlinear R.

    ``Q = eps sigma A (T1**4 - T2**4)`` from the surface on the bond into it
    to the one on the bond out of it (Stefan--Boltzmann law between a grey
    body and large surroundings, Incropera et al., *Fundamentals of Heat and
    Mass Transfer*, 6th ed., Eq. 1.7).  Not a function of ``T1 - T2`` alone,
    so it takes both temperatures.

    Parameters
    ----------
    name : str
    area, emissivity : optional, keyword only
        Default symbols ``area_<name>`` and ``emissivity_<name>``.
    sigma : optional, keyword only
        Default symbol ``sigma_SB`` (:data:`STEFAN_BOLTZMANN` is its value).

    Examples
    --------
    >>> Radiation("rad").label()
    'Rrad:rad'
    """

    area: ParameterLike = field(default=None, kw_only=True)
    emissivity: ParameterLike = field(default=None, kw_only=True)
    sigma: ParameterLike = field(default=None, kw_only=True)
    kind: ClassVar[str] = "Rrad"
    sides: ClassVar[str] = "the hotter surface's bond in, the other's out, by convention"

    def __post_init__(self) -> None:
        super().__post_init__()
        self.coefficient()

    def coefficient(self) -> sympy.Expr:
        """``eps sigma A``."""
        return (_param(self, self.emissivity, "emissivity") * _param(self, self.area, "area") *
                positive_parameter(self.sigma, SIGMA_SB, owner=self.label(), what="sigma"))

    def value_rules(self) -> tuple:
        """Area and ``sigma`` positive, the emissivity in (0, 1]."""
        return (rule(_param(self, self.emissivity, "emissivity"), "emissivity", "fraction") +
                rule(_param(self, self.area, "area"), "area", opt_out=False) +
                rule(positive_parameter(self.sigma, SIGMA_SB, owner=self.label(), what="sigma"),
                     "Stefan-Boltzmann constant sigma", opt_out=False))

    def flows(self, effort_in: sympy.Expr, effort_out: sympy.Expr) -> tuple[sympy.Expr, sympy.Expr]:
        Q = self.coefficient() * (effort_in**4 - effort_out**4)
        return Q, Q

    def fixed_domains(self, into) -> dict[int, str]:
        return {0: "thermal", 1: "thermal"}

    def drawing_label(self) -> tuple[str, str]:
        return self.label(), "radiation"


@dataclass(frozen=True, eq=False)
class HeatConduction(ConductanceTwoPort):
    """Conduction in a true thermal bond graph: ``Q = (T1 - T2)/R``, entropy flows ``Q/T``.

    The heat ``Q`` leaves the body at ``T1`` as the entropy flow ``Q/T1`` and
    enters the one at ``T2`` as ``Q/T2``; the difference is the entropy
    produced (Cellier 1991, Sec. 8.4: the ``RS`` of conduction).  Both ports
    are thermal.

    Parameters
    ----------
    name : str
    resistance : optional, keyword only
        Thermal resistance ``R`` (K/W); default symbol ``resistance_<name>``.

    Examples
    --------
    >>> HeatConduction("wall").label()
    'RS:wall'
    """

    resistance: ParameterLike = field(default=None, kw_only=True)
    kind: ClassVar[str] = "RS"

    def __post_init__(self) -> None:
        super().__post_init__()
        _param(self, self.resistance, "resistance")

    def value_rules(self) -> tuple:
        """The thermal resistance positive."""
        return rule(_param(self, self.resistance, "resistance"), "thermal resistance",
                    opt_out=False)

    def flows(self, effort_in: sympy.Expr, effort_out: sympy.Expr) -> tuple[sympy.Expr, sympy.Expr]:
        Q = (effort_in - effort_out) / _param(self, self.resistance, "resistance")
        return Q / effort_in, Q / effort_out

    def fixed_domains(self, into) -> dict[int, str]:
        return {0: "thermal (entropy)", 1: "thermal (entropy)"}

    def drawing_label(self) -> tuple[str, str]:
        return self.label(), "conduction"


@dataclass(frozen=True, eq=False)
class EntropyCapacity(C):
    """A body of constant heat capacity in a true thermal bond graph: ``T = T0 exp(S/c)``.

    Its state ``q_<name>`` is the entropy ``S`` (J/K) gained since it was at
    ``T0``: ``dU = T dS = c dT`` integrates to ``S = c ln(T/T0)`` (Cellier
    1991, Sec. 8.3).  Its stored heat is ``c (T - T0)``.

    Parameters
    ----------
    name : str
    heat_capacity : optional, keyword only
        ``c = m c_p`` (J/K); default symbol ``heat_capacity_<name>``.
    reference_temperature : optional, keyword only
        ``T0`` (K), the temperature at ``S = 0``; default symbol ``T0_<name>``.

    Examples
    --------
    >>> EntropyCapacity("mass", heat_capacity=2, reference_temperature=300).forward()
    300*exp(q/2)
    """

    heat_capacity: ParameterLike = field(default=None, kw_only=True)
    reference_temperature: ParameterLike = field(default=None, kw_only=True)
    kind: ClassVar[str] = "CS"

    def __post_init__(self) -> None:
        if (self.parameter, self.law, self.inverse, self.stiffness) != (None,) * 4:
            raise ParameterError(f"CS:{self.name}: an entropy capacity's law is T = T0 exp(S/c); "
                                 "give heat_capacity= and reference_temperature=, not a law")
        self._set_law()
        super().__post_init__()

    def _constants(self) -> tuple[sympy.Expr, sympy.Expr]:
        c = _param(self, self.heat_capacity, "heat_capacity")
        T0 = positive_parameter(self.reference_temperature,
                                sympy.Symbol(f"T0_{self.name}", positive=True),
                                owner=f"CS:{self.name}", what="reference_temperature")
        return c, T0

    def _set_law(self) -> None:
        c, T0 = self._constants()
        object.__setattr__(self, "law", T0 * sympy.exp(Q_VAR / c))
        object.__setattr__(self, "inverse", c * sympy.log(E_VAR / T0))

    def value_rules(self) -> tuple:
        """The heat capacity and the (absolute) reference temperature positive."""
        c, T0 = self._constants()
        return (rule(c, "heat capacity", opt_out=False) +
                rule(T0, "reference temperature T0", opt_out=False))

    def resolved(self, path: str) -> Element:
        el = cast(EntropyCapacity, rename(self, path))
        el._set_law()
        return el

    def fixed_domains(self, into) -> dict[int, str]:
        return {0: "thermal (entropy)"}

    def energy_signals(self) -> tuple:
        return ()        # U = c T0 (exp(S/c) - 1) is not a storage of the port-Hamiltonian form

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        return (f"{self.label()}: a thermal capacity in entropy form (T = T0 exp(S/c)) is "
                "not a port-Hamiltonian storage here")

    def drawing_label(self) -> tuple[str, str]:
        return self.label(), "entropy"


@dataclass(frozen=True, eq=False)
class RS(DirectedTwoPort):
    """A resistor whose dissipated power enters a thermal port as the entropy flow ``P/T``.

    Port 1 (the bond into it) is the resistance of any domain, ``e = R f``
    (an electrical resistor, a damper); port 2 (the bond out of it) is a true
    thermal port: it receives the temperature ``T`` and delivers the entropy
    flow ``R f**2 / T`` (Karnopp et al., Sec. 12.4; Cellier 1991, Sec. 8.5).
    The power is conserved: what port 1 absorbs, port 2 delivers as heat.

    Parameters
    ----------
    name : str
    resistance : optional
        ``R``; default symbol ``<name>`` (like an ``R``'s parameter).

    Examples
    --------
    >>> RS("heater", 10).label(), RS("heater").bonds
    ('RS:heater', (2, 2))
    """

    resistance: ParameterLike = None
    kind: ClassVar[str] = "RS"
    conflict_hint: ClassVar[str] = (" An RS receives the temperature on its thermal bond (the "
                                    "bond out of it): connect it to a thermal capacity's junction.")

    def __post_init__(self) -> None:
        super().__post_init__()
        self._R()

    def _R(self) -> sympy.Expr:
        return positive_parameter(self.resistance, sympy.Symbol(self.name, positive=True),
                                  owner=self.label(), what="resistance")

    def value_rules(self) -> tuple:
        """The resistance positive (it heats the body it is bonded to)."""
        return rule(self._R(), "resistance", opt_out=False)

    def resolved(self, path: str) -> Element:
        el = rename(self, path)
        if self.resistance is None:
            object.__setattr__(el, "resistance", sympy.Symbol(path, positive=True))
        return el

    sides: ClassVar[str] = "port 1, the resistance, is the bond into an RS; the thermal port the bond out"

    def forced_causality(self, ports: CausalPorts) -> Sequence[Decision]:
        thermal = 1 if ports.into(0) else 0
        return (Decision(thermal, True, f"{self.label()} takes the temperature"),)

    def causal_choices(self, prefer_derivative: bool) -> Sequence[Choice]:
        # the resistive port is free; asked with the thermal port already forced
        return (Choice(0, False, f"arbitrary choice for {self.label()}", RESISTIVE),
                Choice(1, False, f"arbitrary choice for {self.label()}", RESISTIVE))

    def causal_class(self, effort_in: Sequence[bool], free: Sequence[bool]) -> Optional[str]:
        return ARBITRARY if any(free) else None

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        if all(effort_in):          # resistive port in conductance form: order unknown here
            return ((0, 1), (0, 1))
        res = 0 if not effort_in[0] else 1     # the thermal port always receives effort
        return tuple((p,) if p == res else (0, 1) for p in range(2))

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        return (f"{self.label()}: its entropy flow R f**2/T is nonlinear; the port-Hamiltonian "
                "form needs linear R elements")

    def _resistive(self, local: LocalVariables, port: int) -> sympy.Expr:
        s, x = local.sign(port), local.input(port)
        R = self._R()
        return s * x / R if local.effort_in(port) else R * s * x

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        res = 0 if local.into(0) else 1
        if port == res:
            return self._resistive(local, port)
        out = self._resistive(local, res)
        e, f = ((local.input(res), out) if local.effort_in(res) else (out, local.input(res)))
        power = e * f * local.sign(res)                 # power into the resistive port
        return -local.sign(port) * power / local.input(port)   # entropy flow out of the thermal port

    def domain_groups(self, count: int) -> tuple[tuple[int, ...], ...]:
        return ((0,), (1,))      # any resistive domain -> thermal

    def fixed_domains(self, into) -> dict[int, str]:
        return {1 if into[0] else 0: "thermal (entropy)"}   # the bond out of it

    def drawing_label(self) -> tuple[str, str]:
        return self.label(), "heat"
