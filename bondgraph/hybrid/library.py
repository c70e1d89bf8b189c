"""Switched bond graphs of the model library: rectifier, buck converter, clutches, end stops, bouncing ball.

Each function returns a fresh :class:`~bondgraph.BondGraph` with its switches
in their initial state; ``models/buck.py`` and ``models/clutch.py`` wrap two
of them for the ``bondgraph`` command line.

Examples
--------
>>> from bondgraph.hybrid import SwitchedModel, library
>>> [str(m) for m in SwitchedModel(library.buck()).modes]
['D off, S off', 'D on, S off', 'D off, S on']
"""

from __future__ import annotations

import sympy

from ..elements import C, I, One, R, Se, Zero
from ..graph import BondGraph
from ..signals import displacement
from ..signals import t as T_SYM
from .contact import Contact, Slip
from .elements import ControlledSwitch, Diode, pwm

__all__ = ["rectifier", "buck", "clutch", "friction_clutch", "end_stop", "contact_stop", "bounce"]


def _connect(g: BondGraph, pairs) -> BondGraph:
    for tail, head in pairs:
        g.connect(tail, head)
    return g


def rectifier(name: str = "rectifier") -> BondGraph:
    """Half-wave rectifier: ``Vm sin(w t)`` source, ideal diode ``D``, RC load.

    With the diode on, the capacitor is driven by the source directly
    (derivative causality: no state); off, it discharges through ``R``.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.hybrid import SwitchedModel
    >>> sm = SwitchedModel(rectifier(), outputs={"v": bg.effort("C")})
    >>> sm.mode(on={"D"}).output_exprs, sm.mode(off={"D"}).rhs
    ((Vm*sin(t*w),), (-q_C/(C*R),))
    """
    Vm, w = sympy.symbols("Vm w", positive=True)
    g = BondGraph(name)
    g.add(Se("Vs", value=Vm * sympy.sin(w * T_SYM)), One("i"), Diode("D", on=True), Zero("v"),
          R("R"), C("C"))
    return _connect(g, [("Vs", "i"), ("i", "D"), ("i", "v"), ("v", "R"), ("v", "C")])


def buck(name: str = "buck") -> BondGraph:
    """Buck converter: ``Vin``, PWM switch ``S`` (duty ``duty``, period ``T``), freewheeling
    diode ``D``, inductor ``L``, capacitor ``C``, load ``R``.

    The switch connects the source to node A; the diode conducts from ground
    to node A (the 1-junction ``d`` sums its voltage and node A's to zero);
    ``L`` runs from A to the output node B with ``C`` and ``R``.

    Examples
    --------
    >>> from bondgraph.hybrid import SwitchedModel
    >>> SwitchedModel(buck()).mode(on={"S"}, off={"D"}).rhs
    (Vin - q_C/C, p_L/L - q_C/(C*R))
    """
    Vin, duty, T = sympy.symbols("Vin duty T", positive=True)
    g = BondGraph(name)
    g.add(Se("Vin", value=Vin), One("s"), ControlledSwitch("S", gate=pwm(duty, T), period=T, on=True),
          Zero("A"), One("d"), Diode("D"), One("iL"), I("L"), Zero("B"), C("C"), R("R"))
    return _connect(g, [("Vin", "s"), ("s", "S"), ("s", "A"), ("d", "D"), ("d", "A"),
                        ("A", "iL"), ("iL", "L"), ("iL", "B"), ("B", "C"), ("B", "R")])


def clutch(name: str = "clutch") -> BondGraph:
    """Two inertias ``J1`` (driven by the torque input ``tau``) and ``J2``, joined by a clutch
    ``K`` that engages at ``t = t_lock``.

    The clutch is a switch on the 0-junction ``c`` of the slip velocity
    ``w1 - w2``: disengaged = on (zero torque), engaged = off (zero slip).
    Engaged, ``J2`` is in derivative causality.

    Examples
    --------
    >>> from bondgraph.hybrid import SwitchedModel
    >>> sm = SwitchedModel(clutch())
    >>> sm.mode(on={"K"}).rhs, sm.mode(off={"K"}).rhs
    ((tau, 0), (J1*tau/(J1 + J2),))
    """
    t_lock = sympy.Symbol("t_lock", positive=True)
    g = BondGraph(name)
    g.add(Se("tau"), One("w1"), I("J1"), Zero("c"), ControlledSwitch("K", gate=t_lock - T_SYM, on=True),
          One("w2"), I("J2"))
    return _connect(g, [("tau", "w1"), ("w1", "J1"), ("w1", "c"), ("c", "K"), ("c", "w2"),
                        ("w2", "J2")])


def friction_clutch(name: str = "friction_clutch", *, torque=None) -> BondGraph:
    """Two inertias ``J1`` (driven by the torque ``tau``) and ``J2`` joined by a Karnopp friction
    clutch: stuck while the torque it must transmit stays within ``Ts``, slipping with the
    kinetic torque ``Tk sign(w1 - w2)`` otherwise.

    The clutch is the pair of :class:`~bondgraph.hybrid.Slip` switches ``Kf``
    (slip forwards, ``w1 > w2``) and ``Kr`` (backwards) on the 0-junction
    ``c`` of the slip speed; both stuck, ``J2`` is in derivative causality
    and the clutch torque is ``effort(c)``.  ``torque``: the source's
    value (an expression of time ``bondgraph.t`` and parameters); default
    the input ``tau``.  Both clutches start stuck; the simulation picks the
    slip direction the initial speeds need.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.hybrid import SwitchedModel
    >>> sm = SwitchedModel(friction_clutch(), outputs={"torque": bg.effort("c")})
    >>> [str(m) for m in sm.modes]
    ['Kf off, Kr off', 'Kf off, Kr on', 'Kf on, Kr off']
    >>> sm.mode().rhs, sm.mode().output_exprs          # stuck: J2 tau/(J1 + J2) transmitted
    ((J1*tau/(J1 + J2),), (J2*tau/(J1 + J2),))
    >>> sm.mode(on={"Kf"}).rhs                          # slipping forwards
    (-Tk + tau, Tk)
    """
    Tk, Ts = sympy.symbols("Tk Ts", positive=True)
    g = BondGraph(name)
    g.add(Se("tau", value=torque), One("w1"), I("J1"), Zero("c"), Slip("Kf", kinetic=Tk, static=Ts),
          Slip("Kr", kinetic=Tk, static=Ts, direction=-1), One("w2"), I("J2"))
    return _connect(g, [("tau", "w1"), ("w1", "J1"), ("w1", "c"), ("c", "Kf"), ("c", "Kr"),
                        ("c", "w2"), ("w2", "J2")])


def end_stop(name: str = "end_stop") -> BondGraph:
    """A mass ``m`` moving freely onto a spring end stop ``k`` at ``x = 0``; the contact ``K``
    closes when ``x`` reaches 0 and opens when it returns (``x`` = displacement of ``m``).

    Free: ``K`` on (no contact force, the spring in derivative causality at
    zero deflection); in contact: ``K`` off (the mass and the spring move together).

    Examples
    --------
    >>> from bondgraph.hybrid import SwitchedModel
    >>> SwitchedModel(end_stop()).mode(off={"K"}).rhs
    (-k*q_k, p_m/m)
    """
    g = BondGraph(name)
    g.add(One("v"), I("m"), Zero("c"), C("k", stiffness="k"),
          ControlledSwitch("K", gate=-displacement("m"), on=True))
    return _connect(g, [("v", "m"), ("v", "c"), ("c", "k"), ("c", "K")])


def contact_stop(name: str = "contact_stop", *, damper: bool = True, gravity: bool = False) -> BondGraph:
    """A mass ``m`` moving onto a unilateral contact ``K``: a spring ``k`` and damper ``b`` that
    push and never pull, at the distance ``gap`` ahead of the mass at ``t = 0``.

    The contact :class:`~bondgraph.hybrid.Contact` closes when the gap
    ``gap - displacement(K)`` reaches zero and opens when the contact force
    ``k x + b v`` falls through zero -- while the spring is still compressed
    (compare the position gate :func:`end_stop`, which opens at ``x = 0``
    and pulls on the mass before).  The spring and damper sit on the
    1-junction ``s`` of the contact surface: open, the spring relaxes
    through the damper.  The mass's displacement is measured from where
    it starts; so the stop is at ``displacement(m) = gap``, and with
    ``x0={"x": -gap}`` (an output ``x = displacement(m)``) at ``x = 0``.

    ``damper=False``: an elastic contact (no ``b``); ``gravity=True``: the
    force ``m g`` pushes the mass towards the stop (a drop from the height ``gap``).

    Examples
    --------
    >>> from bondgraph.hybrid import SwitchedModel
    >>> sm = SwitchedModel(contact_stop())
    >>> sm.mode(off={"K"}).rhs          # closed: the mass on the spring and damper
    (-b*p_m/m - k*q_k, p_m/m, 0)
    >>> sm.mode(on={"K"}).rhs           # open: free flight, the spring relaxes through b
    (0, -k*q_k/b, p_m/m + k*q_k/b)
    """
    m, grav = sympy.symbols("m g", positive=True)
    g = BondGraph(name)
    g.add(One("v"), I("m"), Zero("c"), Contact("K", clearance=sympy.Symbol("gap", positive=True)),
          One("s"), C("k", stiffness="k"))
    pairs = [("v", "m"), ("v", "c"), ("c", "K"), ("c", "s"), ("s", "k")]
    if damper:
        g.add(R("b"))
        pairs.append(("s", "b"))
    if gravity:
        g.add(Se("gravity", value=m * grav))
        pairs.append(("gravity", "v"))
    return _connect(g, pairs)


def bounce(name: str = "bounce") -> BondGraph:
    """MTT's ``Hybrid/Bounce``: a ball (mass ``m``, linear air resistance ``r``) under gravity
    ``g`` falling onto ground of stiffness ``k_g``, in contact while its height ``h < 0``.

    The height is the displacement of ``ball`` (up positive); the ground is
    a spring switched in by ``ground`` (MTT's switched C, ``CSW``).

    Examples
    --------
    >>> from bondgraph.hybrid import SwitchedModel
    >>> SwitchedModel(bounce()).mode(off={"ground"}).rhs
    (-g*m - k_g*q_k_g - p_ball*r/m, p_ball/m)
    """
    m, grav = sympy.symbols("m g", positive=True)
    g = BondGraph(name)
    g.add(Se("gravity", value=-m * grav), One("v"), I("ball", "m"), R("air", "r"), Zero("c"),
          C("k_g", stiffness="k_g"), ControlledSwitch("ground", gate=displacement("ball"), on=True))
    return _connect(g, [("gravity", "v"), ("v", "ball"), ("v", "air"), ("v", "c"), ("c", "k_g"),
                        ("c", "ground")])
