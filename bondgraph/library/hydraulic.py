"""Hydraulic components: effort pressure (Pa), flow volume flow (m^3/s).

Pressures are common at 0-junctions: the parent graph's nodes are
0-junctions (one per volume of fluid).  Two-terminal components
(:class:`Orifice`, :class:`Pipe`, :class:`ProportionalValve`) put their
elements on a 1-junction between ports ``a`` (flow in) and ``b`` (flow out);
a :class:`Tank` is the return at a fixed pressure.  Laws: Merritt,
*Hydraulic Control Systems*, 1967 (orifice Eq. 3-7, valve Ch. 5, accumulator
and cylinder Ch. 6), Manring, *Hydraulic Control Systems*, 2005, and White,
*Fluid Mechanics*, Eq. 6.12 (Hagen--Poiseuille).

Examples
--------
A pressure source filling an accumulator through an orifice:

>>> import bondgraph as bg
>>> g = bg.BondGraph("charge")
>>> g.add(PressureSource("pump"), Orifice("o"), Accumulator("acc"), bg.Zero("p1"))
>>> for t, h in [("pump.p", "o.a"), ("o.b", "p1"), ("p1", "acc.p")]:
...     _ = g.connect(t, h)
>>> bg.derive(g).state_names
('q_acc.gas',)
"""

from __future__ import annotations

from typing import ClassVar

import sympy

from ..elements import C, I, One, Port, R, Se, Sf, TF, Zero
from ..signals import displacement, e as E_VAR, f as F_VAR, q as Q_VAR
from .._support.sympify import ParameterLike
from ._component import Component, SourceComponent

__all__ = ["Orifice", "Pipe", "LaminarRestriction", "Accumulator", "GravityTank", "Cylinder", "ProportionalValve",
           "PressureSource", "FlowSource", "Tank", "orifice_flow", "orifice_drop"]

_MER = "Merritt, Hydraulic Control Systems, 1967"


def orifice_flow(dp: sympy.Expr, coefficient: sympy.Expr) -> sympy.Expr:
    """``Q = c sign(dp) sqrt(|dp|)``: the square-root law (turbulent orifice, Merritt Eq. 3-7).

    ``c = Cd A sqrt(2/rho)``.

    Examples
    --------
    >>> orifice_flow(sympy.Integer(4), 3)
    6
    """
    return coefficient * sympy.sign(dp) * sympy.sqrt(sympy.Abs(dp))


def orifice_drop(Q: sympy.Expr, coefficient: sympy.Expr) -> sympy.Expr:
    """``dp = Q |Q| / c**2``: the inverse of :func:`orifice_flow`.

    Examples
    --------
    >>> orifice_drop(sympy.Integer(6), 3)
    4
    """
    return Q * sympy.Abs(Q) / coefficient**2


class _Restriction(Component):
    domain: ClassVar[str] = "hydraulic"
    port_names: tuple[str, ...] = ("a", "b")
    port_domains = {"a": "hydraulic", "b": "hydraulic"}

    def _series(self, *elements) -> None:
        self.add(Port("a"), Port("b"), One("Q"), *elements)
        self.connect("a", "Q")
        self.connect("Q", "b")
        for el in elements:
            self.connect("Q", el.name)


class Orifice(_Restriction):
    """A sharp-edged orifice: ``Q = Cd A sqrt(2 |dp|/rho) sign(dp)``, ``dp = p_a - p_b``.

    A nonlinear ``R`` carrying both the square-root law (flow from the
    pressure drop, the usual causality) and its inverse
    ``dp = rho Q |Q| / (2 Cd**2 A**2)`` (pressure drop from flow, when a flow
    source or an inertance drives it).  Merritt Eq. 3-7.

    Parameters
    ----------
    name : str
    area, discharge, density : optional, keyword only
        ``A`` (m^2), ``Cd`` (about 0.61 for a sharp edge), ``rho`` (kg/m^3);
        default symbols ``<name>_area``, ``<name>_Cd``, ``<name>_rho``.

    Examples
    --------
    >>> o = Orifice("o", area=1e-6, discharge=0.6, density=850)
    >>> import bondgraph as bg
    >>> o["R"].backward().subs(bg.e, 2.0e5).evalf(4)
    1.302e-5
    """

    law = "Q = Cd A sqrt(2 |p_a - p_b| / rho) sign(p_a - p_b)"
    reference = _MER + ", Eq. 3-7"
    symbol = "R"

    def __init__(self, name: str, *, area: ParameterLike = None, discharge: ParameterLike = None,
                 density: ParameterLike = None) -> None:
        self._given = (area, discharge, density)
        super().__init__(name)

    def coefficient(self) -> sympy.Expr:
        """``Cd A sqrt(2/rho)``."""
        area, cd, rho = self._given
        return (self.param(cd, "Cd") * self.param(area, "area") *
                sympy.sqrt(2 / self.param(rho, "rho")))

    def build(self) -> None:
        c = self.coefficient()
        self._series(R("R", law=orifice_drop(F_VAR, c), inverse=orifice_flow(E_VAR, c)))


class Pipe(_Restriction):
    """A laminar pipe: Hagen--Poiseuille resistance and the fluid's inertance in series.

    ``p_a - p_b = R Q + I dQ/dt`` with ``R = 128 mu L/(pi d**4)`` and
    ``I = rho L/A``, ``A = pi d**2/4`` (White Eq. 6.12; Merritt Sec. 4.2).
    Its state is the pressure momentum ``p_<name>.I`` (``Q = p/I``).

    Examples
    --------
    >>> p = Pipe("line", length=2, diameter=0.01, viscosity=0.03, density=850)
    >>> f"{float(p['R'].parameter):.4e} {float(p['I'].parameter):.4e}"
    '2.4446e+08 2.1645e+07'

    """

    law = "p_a - p_b = R Q + I dQ/dt,  R = 128 mu L / (pi d^4),  I = rho L / A"
    reference = "White, Fluid Mechanics, Eq. 6.12; " + _MER + ", Sec. 4.2"
    symbol = "R, I"

    def __init__(self, name: str, *, length: ParameterLike = None, diameter: ParameterLike = None,
                 viscosity: ParameterLike = None, density: ParameterLike = None) -> None:
        self._given = (length, diameter, viscosity, density)
        super().__init__(name)

    def build(self) -> None:
        L, d, mu, rho = (self.param(v, w) for v, w in
                         zip(self._given, ("length", "diameter", "viscosity", "rho")))
        self._series(R("R", 128 * mu * L / (sympy.pi * d**4)),
                     I("I", rho * L / (sympy.pi * d**2 / 4)))


class LaminarRestriction(_Restriction):
    """A linear (laminar) restriction: ``p_a - p_b = R Q``.

    A capillary, a porous plug, or an outlet linearized about its operating
    point (the liquid-level resistance ``R = dH/dQ`` of Ogata, *Modern
    Control Engineering*, 5th ed., Sec. 4-2, here in pressure units,
    ``R = rho g dH/dQ``; MTT's linear outlet ``R lin``).  A linear ``R`` of
    resistance ``resistance`` (Pa s/m^3) on a 1-junction between ``a`` and ``b``.

    Examples
    --------
    >>> r = LaminarRestriction("out", resistance=4e8)
    >>> r["R"].parameter, r.ports
    (400000000.000000, ('a', 'b'))
    """

    law = "p_a - p_b = R Q"
    reference = "Ogata, Modern Control Engineering, 5th ed., Sec. 4-2 (liquid-level resistance)"
    symbol = "R"

    def __init__(self, name: str, *, resistance: ParameterLike = None) -> None:
        self._resistance = resistance
        super().__init__(name)

    def build(self) -> None:
        self._series(R("R", self.param(self._resistance, "R")))


class Accumulator(Component):
    """A gas-charged accumulator: ``p = p0 (V0/(V0 - q))**n`` for ``q >= 0``.

    ``q`` is the volume of fluid in it (state ``q_<name>.gas``), ``V0`` the
    gas volume at the precharge pressure ``p0`` and ``n`` the polytropic
    exponent (1 isothermal, 1.4 adiabatic nitrogen): the gas law
    ``p V**n = p0 V0**n`` (Merritt Sec. 6.2).  Below ``p0`` the accumulator
    is empty; the law is meant for ``p >= p0``.  Its inverse
    ``q = V0 (1 - (p0/p)**(1/n))`` is used in derivative causality.

    Examples
    --------
    >>> acc = Accumulator("acc", volume=1e-3, precharge=5e6, exponent=1)
    >>> acc["gas"].forward()
    5000.0/(0.001 - q)
    """

    domain = "hydraulic"
    port_names = ("p",)
    port_domains = {"p": "hydraulic"}
    law = "p = p0 (V0 / (V0 - q))^n"
    reference = _MER + ", Sec. 6.2 (gas law p V^n = const)"
    symbol = "C"

    def __init__(self, name: str, *, volume: ParameterLike = None,
                 precharge: ParameterLike = None, exponent: ParameterLike = None) -> None:
        self._given = (volume, precharge, exponent)
        super().__init__(name)

    def build(self) -> None:
        V0, p0, n = (self.param(v, w) for v, w in
                     zip(self._given, ("volume", "precharge", "exponent")))
        law = p0 * (V0 / (V0 - Q_VAR)) ** n
        inverse = V0 * (1 - (p0 / E_VAR) ** (1 / n))
        self.add(Port("p"), C("gas", law=law, inverse=inverse))
        self.connect("p", "gas")


class GravityTank(Component):
    """An open tank of cross-section ``A``: the pressure at its bottom is ``p = rho g q/A``.

    ``q`` is the volume of liquid (state ``q_<name>.C``; the level is
    ``h = q/A``): a linear ``C`` of capacitance ``A/(rho g)`` (hydrostatics;
    Karnopp, Margolis and Rosenberg, *System Dynamics*, 5th ed., Sec. 4.4).

    Examples
    --------
    >>> GravityTank("t1", area=2, density=1000, gravity=10)["C"].parameter
    1/5000
    """

    domain = "hydraulic"
    port_names = ("p",)
    port_domains = {"p": "hydraulic"}
    law = "p = rho g q / A  (C = A / (rho g))"
    reference = "Karnopp, Margolis and Rosenberg, System Dynamics, 5th ed., Sec. 4.4"
    symbol = "C"

    def __init__(self, name: str, *, area: ParameterLike = None, density: ParameterLike = None,
                 gravity: ParameterLike = None) -> None:
        self._given = (area, density, gravity)
        super().__init__(name)

    def build(self) -> None:
        A, rho, g = (self.param(v, w) for v, w in zip(self._given, ("area", "rho", "g")))
        self.add(Port("p"), C("C", A / (rho * g)))
        self.connect("p", "C")


class Cylinder(Component):
    """A single-acting cylinder of piston area ``A``: ``F = A p``, ``v = Q/A``.

    Port ``a`` is the chamber (hydraulic), ``rod`` the piston rod
    (translation): a ``TF`` of modulus ``1/A``.  With ``volume`` and
    ``bulk_modulus`` the chamber's oil compressibility ``C = V/beta`` is
    added on the chamber's 0-junction (Merritt Sec. 6.3).

    Examples
    --------
    >>> Cylinder("cyl", area=2e-3).ports
    ('a', 'rod')
    """

    domain = "hydraulic -> translation"
    port_names = ("a", "rod")
    port_domains = {"a": "hydraulic", "rod": "translation"}
    law = "F = A p,  v = Q / A  (+ chamber: dp/dt = (beta/V) (Q - A v))"
    reference = _MER + ", Sec. 6.3"
    symbol = "TF"

    def __init__(self, name: str, *, area: ParameterLike = None, volume: ParameterLike = None,
                 bulk_modulus: ParameterLike = None) -> None:
        self._given = (area, volume, bulk_modulus)
        super().__init__(name)

    def build(self) -> None:
        area, volume, beta = self._given
        A = self.param(area, "area")
        self.add(Port("a"), Port("rod"), Zero("p"), TF("A", 1 / A))
        self.connect("a", "p")
        if volume is not None or beta is not None:
            self.add(C("oil", self.param(volume, "volume") / self.param(beta, "bulk_modulus")))
            self.connect("p", "oil")
        self.connect("p", "A")
        self.connect("A", "rod")


class ProportionalValve(_Restriction):
    """A proportional valve metering ``a -> b``: ``Q = Cd w x sqrt(2 |dp|/rho) sign(dp)``.

    The opening ``x`` is the displacement of the spool port ``spool``
    (translation; the valve exerts no flow force on the spool): drive it with
    a velocity source, or a spool mass pushed by a solenoid force.  Valid for
    ``x >= 0`` (an opening); ``w`` is the area gradient (m).  Merritt Sec. 5.2.

    Examples
    --------
    >>> ProportionalValve("v1").ports
    ('a', 'b', 'spool')
    """

    port_names = ("a", "b", "spool")
    port_domains = {"a": "hydraulic", "b": "hydraulic", "spool": "translation"}
    law = "Q = Cd w x sqrt(2 |p_a - p_b| / rho) sign(p_a - p_b),  x = spool displacement"
    reference = _MER + ", Sec. 5.2"
    symbol = "MR"
    domain = "hydraulic"

    def __init__(self, name: str, *, gradient: ParameterLike = None,
                 discharge: ParameterLike = None, density: ParameterLike = None) -> None:
        self._given = (gradient, discharge, density)
        super().__init__(name)

    def build(self) -> None:
        w, cd, rho = self._given
        c = (self.param(cd, "Cd") * self.param(w, "gradient") * sympy.sqrt(2 / self.param(rho, "rho"))
             * displacement("x"))
        self._series(R("R", inverse=orifice_flow(E_VAR, c)))
        self.add(Port("spool"), One("x"), Se("no_force", value=0))
        self.connect("spool", "x")
        self.connect("x", "no_force")


class PressureSource(SourceComponent):
    """A pump or supply at a prescribed pressure at port ``p``: the input ``P``, or ``value``.

    Examples
    --------
    >>> PressureSource("supply", value=2e7)["P"].value
    20000000.0000000
    """

    domain = "hydraulic"
    port_domains = {"p": "hydraulic"}
    law = "p = P_s (an effort source)"
    reference = _MER
    symbol = "Se"
    source = Se
    inner = "P"


class FlowSource(SourceComponent):
    """A fixed-displacement pump: a prescribed flow out of port ``p`` (input ``Q`` or ``value``).

    Examples
    --------
    >>> FlowSource("pump").ports
    ('p',)
    """

    domain = "hydraulic"
    port_domains = {"p": "hydraulic"}
    law = "Q = Q_s (a flow source)"
    reference = _MER
    symbol = "Sf"
    source = Sf
    inner = "Q"


class Tank(Component):
    """The return line: a reservoir at the pressure ``value`` (default 0, gauge) at port ``p``.

    Connect the flow *into* the tank: ``connect(..., "tank.p")``.

    Examples
    --------
    >>> Tank("tank")["p0"].value
    0
    """

    domain = "hydraulic"
    port_names = ("p",)
    port_domains = {"p": "hydraulic"}
    law = "p = p_tank"
    reference = _MER
    symbol = "Se"

    def __init__(self, name: str, *, value: ParameterLike = 0) -> None:
        self._value = value
        super().__init__(name)

    def build(self) -> None:
        self.add(Se("p0", value=self._value), Port("p"))
        self.connect("p", "p0")
