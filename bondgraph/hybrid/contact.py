"""Contact laws as switches: the unilateral (normal) contact and Karnopp (tangential) friction.

Both are switch elements (:class:`~bondgraph.hybrid.elements.SwitchElement`):
one-ports that are an effort source when on and the zero-flow source
``Sf:0`` when off, answering the hybrid machinery's questions (their guards,
:attr:`self_switched`) like a :class:`~bondgraph.hybrid.Diode`, so that
simulation, code generation and FMUs take them as they take a diode.  Their
state follows complementarity conditions on their own variables; the bond
points into the element, its flow positive into it:

:class:`Contact`, a unilateral contact between two bodies
    The effort is the contact force (compression positive), the flow the
    closing velocity, its time integral ``displacement(name)`` the closing
    travel, so the gap is ``clearance - displacement(name)``.  **Open** (on,
    zero force) while the gap is ``>= 0``; **closed** (off, zero closing
    velocity, the gap frozen at zero) while the force is ``>= 0``.  It closes
    when the gap falls through zero and opens when its force falls through
    zero: a spring and damper behind it push and never pull.
:class:`Slip`, one direction of slip of a Karnopp friction contact
    The effort is the friction force or torque, the flow the slip velocity.
    **Slipping** (on) it is the kinetic friction ``direction*kinetic``, while
    ``direction*flow >= 0``; **stuck** (off, zero slip) while the force it
    holds stays below the static friction, ``static - direction*effort >= 0``.
    Two of them on the slip junction, ``direction=+1`` and ``-1``, are a
    friction contact with its stick and both slip modes (both slipping is no
    consistent mode: two effort sources on one 0-junction).

Examples
--------
>>> import bondgraph as bg
>>> k = Contact("K", clearance=0.25)
>>> k.label(), k.on, k.guard(True)
('Ct:K', True, 0.25 - displacement[K])
>>> k.guard(False)
effort[K]
>>> s = Slip("Kf", kinetic="Tk", static="Ts")
>>> s.guard(True), s.guard(False)
(flow[Kf], -effort[Kf] + Ts)
>>> Slip("Kr", kinetic="Tk", static="Ts", direction=-1).guard(False)
effort[Kr] + Ts
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, ClassVar, Optional, Sequence, cast

import sympy

from ..errors import ParameterError
from ..elements.protocol import LocalVariables
from .._support.sympify import ParameterLike, to_expr
from ..signals import Signal, displacement, effort, flow
from ..signals import t as T_SYM
from .elements import SwitchElement

if TYPE_CHECKING:  # pragma: no cover
    from ..elements.bond import Bond

__all__ = ["Contact", "Slip"]


def _constant(el: SwitchElement, value: ParameterLike, what: str, *, time: bool = False) -> sympy.Expr:
    """``value`` as an expression of parameters (and time if ``time``), finite and real."""
    expr = to_expr(value, owner=el.label(), what=what)
    if expr is None:
        raise ParameterError(f"{el.label()}: give {what}= (a number, a parameter name or a sympy "
                             "expression of parameters)")
    if any(isinstance(s, Signal) for s in expr.free_symbols) or (expr.has(T_SYM) and not time):
        raise ParameterError(f"{el.label()}: {what} {expr} must be an expression of parameters "
                             f"({'and time, ' if time else ''}no signals)")
    if expr.is_number and not expr.is_real:
        raise ParameterError(f"{el.label()}: {what} must be real, got {expr}")
    return expr


class _ContactSwitch:
    """A warning when the element's bond points out of it (its laws hold for the bond into it)."""

    if TYPE_CHECKING:
        name: str
        meaning: ClassVar[str]

        def label(self) -> str: ...

    def bond_warnings(self, bonds: Sequence["Bond"]) -> tuple[str, ...]:
        (b,) = bonds
        if b.tail != self.name:
            return ()
        return (f"bond {b.number} points out of {self.label()} ({b.tail} -> {b.head}): "
                f"{self.meaning} are those of the bond pointing into it, so with this bond they "
                f"have the opposite sign; connect(..., {self.name!r}) is the usual direction. "
                "Silence with warnings.simplefilter('ignore', bondgraph.BondGraphWarning)",)


@dataclass(frozen=True, eq=False)
class Contact(_ContactSwitch, SwitchElement):
    """A unilateral contact: open (on) while its gap is >= 0, closed (off) while it pushes.

    Put it on the 0-junction of the contact force between the two bodies, in
    series with the spring (and damper) of the contact, the bond pointing
    into it: its flow is then the closing velocity and its effort the contact
    force.  Open, it carries no force and the spring and damper behind it
    relax; closed, it carries no closing velocity and the force is the
    spring's and the damper's.  It closes when the gap
    ``clearance - displacement(name)`` falls through zero and opens when the
    force falls through zero (not when the spring's deflection does): a
    damped contact releases the body while the spring is still compressed,
    and the spring then relaxes through the damper.

    Parameters
    ----------
    name : str
    clearance : number, parameter name or expression, keyword-only
        The gap at ``t = 0`` (default 0: touching).  The gap is the
        clearance minus the closing travel ``displacement(name)``, an
        integrated signal whose start value is 0 unless ``x0`` gives it.
    on : bool, keyword-only
        Built open (default) or closed; the simulation chooses the state
        consistent with the initial gap and force.

    Examples
    --------
    >>> Contact("stop", clearance="gap").guard(True)
    -displacement[stop] + gap
    >>> Contact("stop").state_text(False)
    'closed (no closing velocity)'
    """

    clearance: ParameterLike = field(default=0, kw_only=True)
    on: bool = field(default=True, kw_only=True)
    kind: ClassVar[str] = "Ct"
    self_switched: ClassVar[bool] = True
    meaning: ClassVar[str] = "its force (compression positive) and closing velocity"

    def __post_init__(self) -> None:
        super().__post_init__()
        clearance = _constant(self, self.clearance, "clearance")
        if clearance.is_number and clearance < 0:
            raise ParameterError(f"{self.label()}: clearance must be >= 0 (the gap at t = 0), got "
                                 f"{clearance}")
        if not self.on and clearance.is_number and clearance > 0:
            # closed, the gap stays where it was when the contact closed: that must be zero
            raise ParameterError(f"{self.label()}: built closed (on=False) with a clearance of "
                                 f"{clearance}: a contact closes at zero gap; build it open "
                                 "(on=True) or with clearance=0")
        object.__setattr__(self, "clearance", clearance)

    def gap(self) -> sympy.Expr:
        """The gap, ``clearance - displacement(name)`` (>= 0 while open)."""
        return cast(sympy.Expr, self.clearance) - displacement(self.name)

    def guard(self, on: bool) -> Optional[sympy.Expr]:
        return self.gap() if on else effort(self.name)

    def state_text(self, on: bool) -> str:
        return "open (no force)" if on else "closed (no closing velocity)"

    def drawing_label(self) -> tuple[str, str]:
        return self.label(), "open" if self.on else "closed"


@dataclass(frozen=True, eq=False)
class Slip(_ContactSwitch, SwitchElement):
    """One direction of a Karnopp friction contact: slipping (on) or stuck (off).

    Slipping, the element is the effort source ``direction*kinetic`` (the
    kinetic friction opposing the slip) while the slip velocity (its flow)
    has the sign of ``direction``; stuck, it is the zero-flow source while
    the friction it holds, ``direction*effort``, stays at most ``static``.
    Put the pair ``direction=+1`` and ``direction=-1`` on the 0-junction of
    the slip velocity (both bonds pointing into them): their states are
    then stick (both off), slip forwards (+1 on) and slip backwards (-1 on).
    With ``static = kinetic = 0`` and ``direction=+1`` it is a
    :class:`~bondgraph.hybrid.Diode`.

    Parameters
    ----------
    name : str
    kinetic : number, parameter name or expression, keyword-only
        The kinetic (sliding) friction force or torque, ``>= 0``; an
        expression of parameters and time ``bondgraph.t`` (a clutch's
        engagement).
    static : optional, keyword-only
        The static friction (breakaway) force, ``>= kinetic``; default ``kinetic``.
    direction : {+1, -1}, keyword-only
        The slip direction this element stands for.
    on : bool, keyword-only
        Built stuck (default) or slipping.

    Examples
    --------
    >>> s = Slip("fwd", kinetic=2, static=3, on=True)
    >>> s.label(), s.state_text(True), s.guard(True)
    ('Slip:fwd', 'slipping (kinetic friction 2)', flow[fwd])
    >>> Slip("r", kinetic=4, static=3)
    Traceback (most recent call last):
    ...
    bondgraph.errors.ParameterError: Slip:r: static friction 3 is below the kinetic friction 4; expected static >= kinetic
    """

    kinetic: ParameterLike = field(default=None, kw_only=True)
    static: ParameterLike = field(default=None, kw_only=True)
    direction: int = field(default=1, kw_only=True)
    kind: ClassVar[str] = "Slip"
    self_switched: ClassVar[bool] = True
    meaning: ClassVar[str] = "its friction and slip velocity"
    conflict_hint: ClassVar[str] = (
        " A slipping Slip element is an effort source (its kinetic friction) and a stuck one a "
        "zero-flow source: both directions of one friction contact slipping at once (two effort "
        "sources on its 0-junction) is no consistent mode, nor is a stuck contact in series "
        "with a flow source that moves it.")

    def __post_init__(self) -> None:
        super().__post_init__()
        if isinstance(self.direction, bool) or self.direction not in (1, -1):
            raise ParameterError(f"{self.label()}: direction must be +1 or -1; got {self.direction!r}")
        kin = _constant(self, self.kinetic, "kinetic", time=True)
        stat = kin if self.static is None else _constant(self, self.static, "static", time=True)
        for what, val in (("kinetic", kin), ("static", stat)):
            if val.is_number and val < 0:
                raise ParameterError(f"{self.label()}: {what} friction must be >= 0, got {val}")
        diff = sympy.simplify(stat - kin)
        if diff.is_number and diff < 0:
            raise ParameterError(f"{self.label()}: static friction {stat} is below the kinetic "
                                 f"friction {kin}; expected static >= kinetic")
        object.__setattr__(self, "kinetic", kin)
        object.__setattr__(self, "static", stat)

    def guard(self, on: bool) -> Optional[sympy.Expr]:
        d = self.direction
        if on:
            return d * flow(self.name)
        return cast(sympy.Expr, self.static) - d * effort(self.name)

    def state_text(self, on: bool) -> str:
        kinetic = cast(sympy.Expr, self.kinetic)
        return f"slipping (kinetic friction {self.direction * kinetic})" if on else "stuck (no slip)"

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        # slipping: the kinetic friction (an effort source); stuck: no slip (zero flow)
        return self.direction * cast(sympy.Expr, self.kinetic) if self.on else sympy.Integer(0)

    def drawing_label(self) -> tuple[str, str]:
        return self.label(), "slip" if self.on else "stick"
