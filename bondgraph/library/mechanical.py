"""Mechanical components: translation (N, m/s) and rotation (N m, rad/s).

Velocities are common at 1-junctions, so the parent graph's nodes are
1-junctions (one per body or shaft).  A body (:class:`Mass`,
:class:`Inertia`) has one port ``p``.  Two-terminal components
(:class:`Spring`, :class:`Damper`, their rotary forms) put their element on a
0-junction between ports ``a`` and ``b``: the force is common, the velocity
across is ``v_a - v_b`` (connect ``b`` to a :class:`Fixed` for a spring to
the ground, or use the one-port ``grounded=True`` form).  Transmissions
(:class:`Gear`, :class:`Lever`, :class:`RackPinion`, :class:`Belt`) are
``TF`` two-ports from the driving port ``a`` to the driven port ``b``.
Laws: Karnopp, Margolis and Rosenberg, *System Dynamics*, 5th ed., Ch. 3
and 4 (and Modelica's ``Mechanics.Translational``/``Rotational``).

Examples
--------
A mass on a spring to the ground, ``x/F = 1/(m s^2 + k)``:

>>> import bondgraph as bg
>>> g = bg.BondGraph("msd")
>>> g.add(ForceSource("F"), Mass("m", mass="m"), Spring("k", stiffness="k", grounded=True),
...       bg.One("v"))
>>> for t, h in [("F.p", "v"), ("v", "m.p"), ("v", "k.a")]:
...     _ = g.connect(t, h)
>>> model = bg.derive(g, outputs={"x": bg.displacement("v")})
>>> import sympy
>>> sympy.cancel(model.transfer_function().expr)
1/(k + m*s**2)
"""

from __future__ import annotations

from typing import ClassVar

import sympy

from ..elements import C, I, Port, R, Se, Sf, TF, Zero
from ..errors import ParameterError
from .._support.sympify import ParameterLike
from ._component import Component, SourceComponent

__all__ = ["Mass", "Spring", "Damper", "ForceSource", "VelocitySource", "Fixed", "Inertia",
           "TorsionSpring", "RotaryDamper", "TorqueSource", "Gear", "Lever", "RackPinion", "Belt",
           "UnilateralContact", "Friction", "FrictionClutch"]

_KMR = "Karnopp, Margolis and Rosenberg, System Dynamics, 5th ed., Ch. 3 and 4"


class _Body(Component):
    port_names: tuple[str, ...] = ("p",)
    reference: ClassVar[str] = _KMR
    symbol: ClassVar[str] = "I"
    what: ClassVar[str] = "mass"

    def __init__(self, name: str, value: ParameterLike) -> None:
        self._value = value
        super().__init__(name)

    def build(self) -> None:
        self.add(Port("p"), I("I", self.param(self._value, self.what)))
        self.connect("p", "I")


class Mass(_Body):
    """A rigid body in translation, ``v = p/m``, ``dp/dt = F``; state the momentum ``p_<name>.I``.

    Examples
    --------
    >>> Mass("cart", mass=2)["I"].parameter
    2
    """

    domain = "translation"
    port_domains = {"p": "translation"}
    law = "v = p / m,  dp/dt = F"

    def __init__(self, name: str, *, mass: ParameterLike = None) -> None:
        super().__init__(name, mass)


class Inertia(_Body):
    """A rigid body in rotation, ``omega = h/J``, ``dh/dt = tau``.

    Examples
    --------
    >>> Inertia("rotor", inertia=0.1)["I"].parameter
    0.100000000000000
    """

    domain = "rotation"
    port_domains = {"p": "rotation"}
    law = "omega = h / J,  dh/dt = tau"
    what = "inertia"

    def __init__(self, name: str, *, inertia: ParameterLike = None) -> None:
        super().__init__(name, inertia)


class _Coupling(Component):
    """An element on a 0-junction between ``a`` and ``b``, or on ``a`` alone if grounded."""

    reference: ClassVar[str] = _KMR
    what: ClassVar[str] = ""

    def __init__(self, name: str, value: ParameterLike, grounded: bool) -> None:
        self._value, self._grounded = value, grounded
        super().__init__(name)

    def element(self, value):
        raise NotImplementedError

    def build(self) -> None:
        el = self.element(self.param(self._value, self.what))
        if self._grounded:
            self.add(Port("a"), el)
            self.connect("a", el.name)
            self.port_names = ("a",)          # an instance's own (one-port) form
            return
        self.add(Port("a"), Port("b"), Zero("F"), el)
        self.connect("a", "F")
        self.connect("F", "b")
        self.connect("F", el.name)


class Spring(_Coupling):
    """A linear spring, ``F = k (x_a - x_b)``; state its deflection ``q_<name>.C``.

    ``grounded=True`` ties ``b`` to the ground: one port ``a``.

    Examples
    --------
    >>> Spring("k1", stiffness=100).ports, Spring("k2", grounded=True).ports
    (('a', 'b'), ('a',))
    """

    domain = "translation"
    port_names = ("a", "b")
    port_domains = {"a": "translation", "b": "translation"}
    law = "F = k x,  dx/dt = v_a - v_b"
    symbol = "C"
    what = "stiffness"

    def __init__(self, name: str, *, stiffness: ParameterLike = None, grounded: bool = False) -> None:
        super().__init__(name, stiffness, grounded)

    def element(self, value):
        return C("C", stiffness=value)


class Damper(_Coupling):
    """A viscous damper, ``F = b (v_a - v_b)``.

    Examples
    --------
    >>> Damper("b1", damping=3)["R"].parameter
    3
    """

    domain = "translation"
    port_names = ("a", "b")
    port_domains = {"a": "translation", "b": "translation"}
    law = "F = b (v_a - v_b)"
    symbol = "R"
    what = "damping"

    def __init__(self, name: str, *, damping: ParameterLike = None, grounded: bool = False) -> None:
        super().__init__(name, damping, grounded)

    def element(self, value):
        return R("R", value)


class TorsionSpring(Spring):
    """A torsion spring, ``tau = k (theta_a - theta_b)``.

    Examples
    --------
    >>> TorsionSpring("shaft", stiffness=50).domain
    'rotation'
    """

    domain = "rotation"
    port_domains = {"a": "rotation", "b": "rotation"}
    law = "tau = k theta,  dtheta/dt = omega_a - omega_b"


class RotaryDamper(Damper):
    """Viscous rotary friction, ``tau = b (omega_a - omega_b)``.

    Examples
    --------
    >>> RotaryDamper("bearing", damping=1e-4, grounded=True).ports
    ('a',)
    """

    domain = "rotation"
    port_domains = {"a": "rotation", "b": "rotation"}
    law = "tau = b (omega_a - omega_b)"


class _Source(SourceComponent):
    reference: ClassVar[str] = _KMR
    source: ClassVar[type] = Se
    inner: ClassVar[str] = "F"


class ForceSource(_Source):
    """A force applied at port ``p``: the input ``F``, or ``value`` (gravity ``m g``, a
    function of time).

    Examples
    --------
    >>> ForceSource("push").ports
    ('p',)
    """

    domain = "translation"
    port_domains = {"p": "translation"}
    law = "F = F_s (an effort source)"
    symbol = "Se"


class TorqueSource(_Source):
    """A torque applied at port ``p``: the input ``tau``, or ``value``.

    Examples
    --------
    >>> TorqueSource("motor", value=0.5)["tau"].value
    0.500000000000000
    """

    domain = "rotation"
    port_domains = {"p": "rotation"}
    law = "tau = tau_s (an effort source)"
    symbol = "Se"
    inner = "tau"


class VelocitySource(_Source):
    """A prescribed velocity at port ``p``: the input ``v``, or ``value``.

    Examples
    --------
    >>> VelocitySource("shaker").ports
    ('p',)
    """

    domain = "translation"
    port_domains = {"p": "translation"}
    law = "v = v_s (a flow source)"
    symbol = "Sf"
    source = Sf
    inner = "v"


class Fixed(Component):
    """The ground: zero velocity at port ``p`` (an ``Sf`` of value 0).

    Examples
    --------
    >>> Fixed("wall")["v0"].value
    0
    """

    domain = "translation"
    port_names = ("p",)
    port_domains = {"p": "translation"}
    law = "v = 0"
    reference = _KMR
    symbol = "Sf:0"

    def build(self) -> None:
        self.add(Sf("v0", value=0), Port("p"))
        self.connect("p", "v0")


class _Transmission(Component):
    port_names: tuple[str, ...] = ("a", "b")
    reference: ClassVar[str] = _KMR + " (Sec. 4.2, transformers)"
    symbol: ClassVar[str] = "TF"

    def __init__(self, name: str, modulus, efficiency: ParameterLike) -> None:
        self._modulus, self._efficiency = modulus, efficiency
        if isinstance(efficiency, (int, float, sympy.Number)) and not isinstance(efficiency, bool):
            eta = float(efficiency)
            if eta == eta and not 0 < eta <= 1:       # nan and zero: refused by the TF itself
                if eta != 0:
                    raise ParameterError(f"{type(self).__name__} {name!r}: efficiency must be in "
                                         f"(0, 1] (above 1 it would create energy), got "
                                         f"{efficiency}")
        super().__init__(name)

    def build(self) -> None:
        self.add(Port("a"), Port("b"), TF("n", self._modulus, efficiency=self._efficiency))
        self.connect("a", "n")
        self.connect("n", "b")


class Gear(_Transmission):
    """A gear pair of reduction ratio ``N:1``: the driven shaft ``b`` turns ``N`` times
    slower than the driving shaft ``a``, with ``N`` times its torque.

    ``omega_b = omega_a / N`` and ``tau_b = eta N tau_a``: a ``TF`` of modulus
    ``1/N`` from ``a`` to ``b`` (``TF(n)`` has ``f2 = n f1``, so a raw
    ``TF(N)`` would be an ``N``-fold *speed-up*).  ``N < 1`` is an
    overdrive.  ``efficiency`` ``eta`` (default 1) scales the torque
    delivered, as on gearbox data sheets.

    Parameters
    ----------
    name : str
    ratio : keyword only
        ``N`` (teeth of the driven gear over teeth of the driving one).
    efficiency : optional, keyword only

    Examples
    --------
    >>> gb = Gear("gearbox", ratio=14)
    >>> gb["n"].modulus
    1/14
    """

    domain = "rotation"
    port_domains = {"a": "rotation", "b": "rotation"}
    law = "omega_b = omega_a / N,  tau_b = eta N tau_a  (N:1 reduction)"

    def __init__(self, name: str, *, ratio: ParameterLike = None,
                 efficiency: ParameterLike = None) -> None:
        self._ratio = ratio
        super().__init__(name, None, efficiency)

    def build(self) -> None:
        self._modulus = 1 / self.param(self._ratio, "ratio")
        super().build()


class Lever(_Transmission):
    """A rigid lever on a fixed pivot: arm ``l_a`` at port ``a``, ``l_b`` at port ``b``.

    ``v_b = (l_b/l_a) v_a``, ``F_b = (l_a/l_b) F_a`` (small rotations; the
    ends move in opposite directions, the sign kept in the arms' convention).

    Examples
    --------
    >>> Lever("pedal", arm_a=0.3, arm_b=0.05)["n"].modulus
    0.166666666666667
    """

    domain = "translation"
    port_domains = {"a": "translation", "b": "translation"}
    law = "v_b = (l_b / l_a) v_a,  F_b = (l_a / l_b) F_a"

    def __init__(self, name: str, *, arm_a: ParameterLike = None,
                 arm_b: ParameterLike = None) -> None:
        self._arms = (arm_a, arm_b)
        super().__init__(name, None, None)

    def build(self) -> None:
        self._modulus = self.param(self._arms[1], "arm_b") / self.param(self._arms[0], "arm_a")
        super().build()


class RackPinion(_Transmission):
    """A pinion of radius ``r`` on shaft ``a`` driving a rack ``b``: ``v = r omega``, ``tau = r F``.

    Examples
    --------
    >>> rp = RackPinion("steering", radius=0.01)
    >>> rp.port_domains["a"], rp.port_domains["b"], rp["n"].modulus
    ('rotation', 'translation', 0.0100000000000000)
    """

    domain = "rotation -> translation"
    port_domains = {"a": "rotation", "b": "translation"}
    law = "v_b = r omega_a,  tau_a = r F_b"

    def __init__(self, name: str, *, radius: ParameterLike = None,
                 efficiency: ParameterLike = None) -> None:
        self._radius = radius
        super().__init__(name, None, efficiency)

    def build(self) -> None:
        self._modulus = self.param(self._radius, "radius")
        super().build()


class Belt(_Transmission):
    """A rigid belt (or chain) from pulley ``a`` (radius ``r_a``) to pulley ``b`` (``r_b``).

    No slip: ``r_a omega_a = r_b omega_b``, so ``omega_b = (r_a/r_b) omega_a``
    and ``tau_b = (r_b/r_a) tau_a``.

    Examples
    --------
    >>> Belt("drive", radius_a=0.05, radius_b=0.2)["n"].modulus
    0.250000000000000
    """

    domain = "rotation"
    port_domains = {"a": "rotation", "b": "rotation"}
    law = "omega_b = (r_a / r_b) omega_a,  tau_b = (r_b / r_a) tau_a"

    def __init__(self, name: str, *, radius_a: ParameterLike = None,
                 radius_b: ParameterLike = None, efficiency: ParameterLike = None) -> None:
        self._radii = (radius_a, radius_b)
        super().__init__(name, None, efficiency)

    def build(self) -> None:
        self._modulus = (self.param(self._radii[0], "radius_a") /
                         self.param(self._radii[1], "radius_b"))
        super().build()


# ----------------------------------------------------------------------------- switched contacts
_HYBRID = ("Mosterman and Biswas, hybrid bond graphs (ideal switches); Karnopp, 'Computer "
           "simulation of stick-slip friction in mechanical dynamic systems', ASME J. Dyn. Sys. "
           "Meas. Control 107 (1985)")


class UnilateralContact(Component):
    """A spring and damper that push and never pull: a unilateral contact between ``a`` and ``b``.

    Closed, the force is ``F = k x + b v`` (``x`` the compression of the
    contact spring, ``v = v_a - v_b``); the contact opens when that force
    falls through zero -- while a damped spring is still compressed -- and
    closes again when the gap ``clearance - (x_a - x_b) + x`` falls to zero
    (the spring relaxes through the damper meanwhile, ``k x + b x' = 0``).
    Built from the switch :class:`bondgraph.hybrid.Contact` (named
    ``<name>.K``) in series with the spring ``<name>.C`` and damper
    ``<name>.R``, so the component makes a switched model
    (:class:`bondgraph.hybrid.SwitchedModel`); compare the position gate
    :func:`bondgraph.hybrid.library.end_stop`, which pulls while the body
    leaves.

    Parameters
    ----------
    name : str
    stiffness, damping : keyword-only
        ``k`` and ``b``; ``damping=0``: an elastic contact (no damper).
    clearance : keyword-only
        The gap at ``t = 0`` (default 0, touching).
    grounded : bool, keyword-only
        ``b`` is the ground: one port ``a``.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.hybrid import SwitchedModel
    >>> g = bg.BondGraph("drop")
    >>> g.add(Mass("m", mass="m"), bg.One("v"),
    ...       UnilateralContact("stop", stiffness="k", damping="b", clearance="h", grounded=True))
    >>> _ = g.connect("v", "m.p"); _ = g.connect("v", "stop.a")
    >>> sm = SwitchedModel(g)
    >>> closed, opened = sm.mode(off={"stop.K"}), sm.mode(on={"stop.K"})
    >>> closed.rhs[:2]                         # the mass on the spring and damper
    (-b*p_m.I/m - k*q_stop.C, p_m.I/m)
    >>> opened.rhs[:2]                         # the spring relaxes through the damper
    (0, -k*q_stop.C/b)
    """

    domain = "translation"
    port_names: tuple[str, ...] = ("a", "b")
    port_domains = {"a": "translation", "b": "translation"}
    law = "closed: F = k x + b v >= 0, gap = 0;  open: F = 0, gap >= 0"
    reference = _HYBRID
    symbol = "Ct"

    def __init__(self, name: str, *, stiffness: ParameterLike = None, damping: ParameterLike = None,
                 clearance: ParameterLike = 0, grounded: bool = False) -> None:
        self._values = (stiffness, damping, clearance)
        self._grounded = grounded
        super().__init__(name)

    def build(self) -> None:
        from ..elements import One
        from ..hybrid.contact import Contact

        stiffness, damping, clearance = self._values
        elastic = isinstance(damping, (int, float)) and not isinstance(damping, bool) and damping == 0
        parts = [Port("a"), Zero("F"), Contact("K", clearance=clearance), One("x"),
                 C("C", stiffness=self.param(stiffness, "stiffness"))]
        if not elastic:
            parts.append(R("R", self.param(damping, "damping")))
        if not self._grounded:
            parts.append(Port("b"))
        self.add(*parts)
        for tail, head in [("a", "F"), ("F", "K"), ("F", "x"), ("x", "C")] + \
                ([] if elastic else [("x", "R")]) + ([] if self._grounded else [("F", "b")]):
            self.connect(tail, head)
        if self._grounded:
            self.port_names = ("a",)


class _FrictionContact(Component):
    """Karnopp friction on the 0-junction of the slip velocity ``v_a - v_b`` (see subclasses)."""

    reference: ClassVar[str] = _HYBRID
    symbol: ClassVar[str] = "Slip"

    def __init__(self, name: str, kinetic: ParameterLike, static: ParameterLike,
                 grounded: bool) -> None:
        self._values = (kinetic, static)
        self._grounded = grounded
        super().__init__(name)

    def build(self) -> None:
        from ..hybrid.contact import Slip

        kinetic = self.param(self._values[0], "kinetic")
        static = self.param(self._values[1], "static")
        parts = [Port("a"), Zero("F"), Slip("fwd", kinetic=kinetic, static=static),
                 Slip("rev", kinetic=kinetic, static=static, direction=-1)]
        self.add(*parts, *([] if self._grounded else [Port("b")]))
        for tail, head in [("a", "F"), ("F", "fwd"), ("F", "rev")] + \
                ([] if self._grounded else [("F", "b")]):
            self.connect(tail, head)
        if self._grounded:
            self.port_names = ("a",)


class Friction(_FrictionContact):
    """Karnopp stick-slip friction between ``a`` and ``b`` (a slideway, a body on a table).

    It sticks while the force it must hold stays within the static friction
    ``Fs`` and slips with ``Fk sign(v_a - v_b)`` otherwise.  Two :class:`bondgraph.hybrid.Slip` switches (``<name>.fwd``, ``<name>.rev``)
    on the 0-junction of the slip velocity; the component makes a switched
    model with the modes stick (both off), slip forwards (``fwd`` on) and
    slip backwards (``rev`` on).  ``grounded=True``: a body sliding on the
    ground (one port ``a``).

    Parameters
    ----------
    name : str
    kinetic, static : keyword-only
        The kinetic and static (breakaway) friction forces, ``static >= kinetic``.
    grounded : bool, keyword-only

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.hybrid import SwitchedModel
    >>> g = bg.BondGraph("block")
    >>> g.add(ForceSource("push"), Mass("m", mass="m"), bg.One("v"),
    ...       Friction("table", kinetic="Fk", static="Fs", grounded=True))
    >>> for t, h in [("push.p", "v"), ("v", "m.p"), ("v", "table.a")]: _ = g.connect(t, h)
    >>> sm = SwitchedModel(g)
    >>> sm.mode(on={"table.fwd"}).rhs, sm.mode().state_names
    ((-Fk + push.F,), ())
    """

    domain = "translation"
    port_names: tuple[str, ...] = ("a", "b")
    port_domains = {"a": "translation", "b": "translation"}
    law = "stick: v_a = v_b while |F| <= Fs;  slip: F = Fk sign(v_a - v_b)"

    def __init__(self, name: str, *, kinetic: ParameterLike = None, static: ParameterLike = None,
                 grounded: bool = False) -> None:
        super().__init__(name, kinetic, static, grounded)


class FrictionClutch(_FrictionContact):
    """A friction clutch between shafts ``a`` and ``b`` (Karnopp stick-slip).

    Locked while the torque it must transmit stays within ``Ts``, slipping
    with ``Tk sign(omega_a - omega_b)`` otherwise.  The rotary :class:`Friction`: two :class:`bondgraph.hybrid.Slip` switches
    (``<name>.fwd``, ``<name>.rev``) on the 0-junction of the slip speed.

    Parameters
    ----------
    name : str
    kinetic, static : keyword-only
        The kinetic and static friction torques, ``static >= kinetic``.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.hybrid import SwitchedModel
    >>> g = bg.BondGraph("drive")
    >>> g.add(TorqueSource("motor"), Inertia("J1", inertia="J1"), Inertia("J2", inertia="J2"),
    ...       FrictionClutch("K", kinetic="Tk", static="Ts"), bg.One("w1"), bg.One("w2"))
    >>> for t, h in [("motor.p", "w1"), ("w1", "J1.p"), ("w1", "K.a"), ("K.b", "w2"),
    ...              ("w2", "J2.p")]: _ = g.connect(t, h)
    >>> SwitchedModel(g).mode().rhs       # locked: both shafts turn together
    (J1*motor.tau/(J1 + J2),)
    """

    domain = "rotation"
    port_names: tuple[str, ...] = ("a", "b")
    port_domains = {"a": "rotation", "b": "rotation"}
    law = "stick: omega_a = omega_b while |tau| <= Ts;  slip: tau = Tk sign(omega_a - omega_b)"

    def __init__(self, name: str, *, kinetic: ParameterLike = None,
                 static: ParameterLike = None) -> None:
        super().__init__(name, kinetic, static, False)
