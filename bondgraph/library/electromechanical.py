"""Electromechanical components: the permanent-magnet DC motor.

Examples
--------
A motor spinning a free flywheel from a voltage ``V``:

>>> import bondgraph as bg, sympy
>>> g = bg.BondGraph("drive")
>>> g.add(bg.Se("V"), DCMotor("m", inertia=False, damping=False, inductance=False),
...       bg.One("w"), bg.I("J"))
>>> for t, h in [("V", "m.elec"), ("m.shaft", "w"), ("w", "J")]:
...     _ = g.connect(t, h)
>>> sympy.factor(bg.derive(g).rhs[0])
m_back_emf*(J*V - m_back_emf*p_J)/(J*m_resistance)
"""

from __future__ import annotations

from typing import Union

import sympy

from ..elements import GY, I, One, Port, R
from .._support.sympify import ParameterLike
from ._component import Component

__all__ = ["DCMotor"]

Optional_ = Union[ParameterLike, bool]


class DCMotor(Component):
    """A permanent-magnet DC motor: armature ``R``, ``L``; gyrator ``k``; rotor ``J``, ``b``.

    ``v = R i + L di/dt + k_e omega`` and ``J domega/dt = eta k_t i - b omega - tau_load``
    (Karnopp, Margolis and Rosenberg, *System Dynamics*, 5th ed., Sec. 8.2;
    Quanser SRV-02 user manual).  The electromechanical coupling is a ``GY``
    of modulus ``k_e`` (the back-emf constant) whose torque side is scaled by
    ``eta k_t/k_e``, so the torque is ``eta k_t i`` (with ``eta = 1`` and
    ``k_t = k_e`` in SI units it is lossless).

    Ports: ``elec`` (the armature terminals: voltage, current in) and
    ``shaft`` (rotation: torque and speed out).

    Parameters
    ----------
    name : str
    resistance, back_emf : optional, keyword only
        ``R`` (ohm), ``k_e`` (V s/rad).
    torque_constant, efficiency : optional, keyword only
        ``k_t`` (N m/A; default ``k_e``) and ``eta`` (default 1).
    inductance, inertia, damping : optional, keyword only
        ``L`` (H), ``J`` (kg m^2), ``b`` (N m s/rad); ``False`` leaves the
        element out (a motor whose inertia is lumped elsewhere).

    Examples
    --------
    >>> m = DCMotor("m", resistance=2.6, back_emf=0.00767, damping=False)
    >>> sorted(el.name for el in m.elements)
    ['J', 'L', 'R', 'elec', 'i', 'k', 'shaft', 'w']
    """

    domain = "electrical -> rotation"
    port_names = ("elec", "shaft")
    port_domains = {"elec": "electrical", "shaft": "rotation"}
    law = "v = R i + L di/dt + k_e omega,  J domega/dt = eta k_t i - b omega - tau"
    reference = "Karnopp, Margolis and Rosenberg, System Dynamics, 5th ed., Sec. 8.2"
    symbol = "GY"

    def __init__(self, name: str, *, resistance: ParameterLike = None,
                 inductance: Optional_ = None, back_emf: ParameterLike = None,
                 torque_constant: ParameterLike = None, efficiency: ParameterLike = None,
                 inertia: Optional_ = None, damping: Optional_ = None) -> None:
        self._given = dict(resistance=resistance, inductance=inductance, back_emf=back_emf,
                           torque_constant=torque_constant, efficiency=efficiency,
                           inertia=inertia, damping=damping)
        super().__init__(name)

    def build(self) -> None:
        p = self._given
        ke = self.param(p["back_emf"], "back_emf")
        kt = ke if p["torque_constant"] is None else self.param(p["torque_constant"],
                                                                "torque_constant")
        eta = sympy.Integer(1) if p["efficiency"] is None else self.param(p["efficiency"],
                                                                          "efficiency")
        scale = sympy.cancel(eta * kt / ke)
        self.add(Port("elec"), Port("shaft"), One("i"), One("w"),
                 R("R", self.param(p["resistance"], "resistance")),
                 GY("k", ke, efficiency=None if scale == 1 else scale))
        self.connect("elec", "i")
        self.connect("i", "R")
        if p["inductance"] is not False:
            self.add(I("L", self.param(p["inductance"], "inductance")))
            self.connect("i", "L")
        self.connect("i", "k")
        self.connect("k", "w")
        if p["inertia"] is not False:
            self.add(I("J", self.param(p["inertia"], "inertia")))
            self.connect("w", "J")
        if p["damping"] is not False:
            self.add(R("b", self.param(p["damping"], "damping")))
            self.connect("w", "b")
        self.connect("w", "shaft")
