"""Switch elements: ideal switches, diodes and controlled switches.

A switch is a one-port with two states.  The convention is the electrical one,
that of an ideal switch in Mosterman and Biswas' hybrid bond graphs:

* **on** (closed, conducting): zero *effort* across it, any flow -- in that
  mode it is the source ``Se:0``;
* **off** (open, blocking): zero *flow* through it, any effort -- in that
  mode it is the source ``Sf:0``.

So every mode of a switched graph is an ordinary bond graph: SCAP and the
derivation ask the switch for its causality and its output exactly as they
ask a source, and the switch answers from its state.  A clutch between two
shafts is a switch on the 0-junction of the slip velocity: *engaged* means
zero slip (flow), i.e. the switch **off**; *disengaged* means zero torque
(effort), the switch **on**.  A contact (end stop) is the same: in contact =
off (no relative velocity at the contact), free = on (no contact force).

The hybrid machinery (:mod:`bondgraph.hybrid.modes`,
:mod:`bondgraph.hybrid.simulate`) asks each switch three more questions and
tests no kinds:

* :meth:`SwitchElement.in_state` -- a copy in the other state;
* :meth:`SwitchElement.guard` -- an expression that is >= 0 while the present
  state is consistent (a diode that is on: its forward flow; off: minus its
  effort); its zero crossing from above is the event that flips it; None for
  a switch that only the user sets;
* :attr:`SwitchElement.self_switched` -- whether the state follows the
  element's own variables (a diode), so that at an event the new mode may
  pick its state freely among the consistent ones.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.hybrid import Diode, ControlledSwitch, pwm
>>> d = Diode("D1")
>>> d.label(), d.on, d.in_state(True).guard(True)
('D:D1', False, flow[D1])
>>> d.guard(False)
-effort[D1]
>>> s = ControlledSwitch("S", gate=pwm(0.25, 1e-3))
>>> s.label(), s.guard(True) == s.gate
('CSw:S', True)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar, Optional, Sequence, cast

import sympy

from ..errors import ParameterError
from ..elements.protocol import CausalPorts, Decision, Element, LocalVariables, prefix_signals, rename
from ..signals import Signal, effort, flow
from ..signals import t as T_SYM

__all__ = ["SwitchElement", "Switch", "Diode", "ControlledSwitch", "pwm"]


@dataclass(frozen=True, eq=False)
class SwitchElement(Element):
    """Base of the switch elements: a one-port that is ``Se:0`` when on, ``Sf:0`` when off.

    Parameters
    ----------
    name : str
    on : bool, keyword-only
        The state the element is built in (default off, open).
    """

    on: bool = field(default=False, kw_only=True)
    drawing_role: ClassVar[str] = "source"
    #: whether the state follows the element's own effort and flow (a diode)
    self_switched: ClassVar[bool] = False
    conflict_hint: ClassVar[str] = (
        " A switch is a zero-effort source when on and a zero-flow source when off: this "
        "combination of switch states is not a consistent mode (two switches closed across "
        "an effort source, a switch opened in series with a flow source, ...).")

    def __post_init__(self) -> None:
        super().__post_init__()
        if not isinstance(self.on, bool):
            raise ParameterError(f"{self.label()}: on must be True or False; got {self.on!r}")

    # ------------------------------------------------------------ the hybrid questions
    def in_state(self, on: bool) -> "SwitchElement":
        """A copy of the element in state ``on`` (its name kept as it is, a sub-model's
        path ``cell.D`` included)."""
        if on == self.on:
            return self
        el = cast(SwitchElement, rename(self, self.name))
        object.__setattr__(el, "on", bool(on))
        return el

    def guard(self, on: bool) -> Optional[sympy.Expr]:
        """An expression >= 0 while state ``on`` is consistent, or None (set by the user)."""
        return None

    def state_text(self, on: bool) -> str:
        """How the state is named in messages and drawings."""
        return "on (e=0)" if on else "off (f=0)"

    # ------------------------------------------------------------ the element protocol
    def signal_port(self, variable: str) -> Optional[tuple[int, bool]]:
        return 0, variable == "flow"

    def forced_causality(self, ports: CausalPorts) -> Sequence[Decision]:
        # on: imposes its (zero) effort like an Se; off: imposes its (zero) flow like an Sf
        return (Decision(0, not self.on, f"switch {self.label()} {self.state_text(self.on)}"),)

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        return ((),)

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        return sympy.Integer(0)

    def drawing_label(self) -> tuple[str, str]:
        return self.label(), "closed" if self.on else "open"


@dataclass(frozen=True, eq=False)
class Switch(SwitchElement):
    """An ideal switch whose state only the user sets (a mode of the graph).

    Examples
    --------
    >>> Switch("S1", on=True).guard(True) is None
    True
    """

    kind: ClassVar[str] = "Sw"


@dataclass(frozen=True, eq=False)
class Diode(SwitchElement):
    """An ideal diode: on while its forward flow is >= 0, off while its effort is <= 0.

    Forward means along the bond direction into the element (anode at the
    tail side), the way a one-port's laws are written: connect *to* the diode.

    Examples
    --------
    >>> Diode("D", on=True).guard(True)
    flow[D]
    """

    kind: ClassVar[str] = "D"
    self_switched: ClassVar[bool] = True

    def guard(self, on: bool) -> Optional[sympy.Expr]:
        return flow(self.name) if on else -effort(self.name)


@dataclass(frozen=True, eq=False)
class ControlledSwitch(SwitchElement):
    """A switch driven by a gate: on while ``gate > 0``.

    Parameters
    ----------
    name : str
    gate : sympy expression
        Of time :data:`bondgraph.t`, parameters and signals
        (``bg.displacement("m")``); :func:`pwm` builds a PWM gate.
    period : number or expression, optional, keyword-only
        The switching period of a periodic gate (finite, positive).  A gate of
        time only with a period gives exact time events: its falls over one
        period are found once (scanned at ``period/2000``, refined to machine
        precision) and shifted by whole periods.  Any other gate is located on
        the dense output of every integration step, whatever the step.

    Examples
    --------
    >>> import bondgraph as bg
    >>> ControlledSwitch("S", gate=bg.t - 1).guard(False)
    1 - t
    """

    gate: sympy.Expr = field(default=None, kw_only=True)
    period: Optional[sympy.Expr] = field(default=None, kw_only=True)
    kind: ClassVar[str] = "CSw"

    def __post_init__(self) -> None:
        super().__post_init__()
        for what in ("gate", "period"):
            val = getattr(self, what)
            if val is None and what == "period":
                continue
            if isinstance(val, (int, float)) and not isinstance(val, bool):
                val = sympy.Float(val) if isinstance(val, float) else sympy.Integer(val)
            if not isinstance(val, sympy.Expr):
                raise ParameterError(
                    f"{self.label()}: {what} must be a sympy expression of time bondgraph.t, "
                    f"parameters and signals (or a number); got {type(val).__name__} {val!r}")
            if what == "period" and val.is_number and not (val.is_extended_real and val.is_positive
                                                            and val.is_finite):
                raise ParameterError(f"{self.label()}: period must be a finite positive number; "
                                     f"got {val}")
            if what == "gate" and val.has(sympy.I):
                raise ParameterError(f"{self.label()}: gate must be real; got {val}")
            object.__setattr__(self, what, val)

    def resolved(self, path: str) -> Element:
        el = rename(self, path)
        object.__setattr__(el, "gate", prefix_signals(self.gate, path[: len(path) - len(self.name)]))
        return el

    def guard(self, on: bool) -> Optional[sympy.Expr]:
        return self.gate if on else -self.gate


def pwm(duty, period, *, delay=0) -> sympy.Expr:
    """A PWM gate: positive for the first ``duty`` fraction of each ``period``.

    ``duty - frac((t - delay)/period)``; at ``t = delay + k*period`` it jumps
    from ``duty - 1`` to ``duty`` (switch on), and it falls through zero at
    ``t = delay + (k + duty)*period`` (switch off).

    Examples
    --------
    >>> import bondgraph as bg, sympy
    >>> g = pwm(sympy.Rational(1, 4), 2)
    >>> [g.subs(bg.t, x) for x in (0, sympy.Rational(2, 5), 2)]
    [1/4, 1/20, 1/4]
    """
    duty, period, delay = (sympy.sympify(v, strict=True) for v in (duty, period, delay))
    for what, v in (("duty", duty), ("period", period), ("delay", delay)):
        if v.is_number and not (v.is_extended_real and v.is_finite):
            raise ParameterError(f"pwm: {what} must be a finite real number; got {v}")
    if period.is_number and not period.is_positive:
        raise ParameterError(f"pwm: period must be positive; got {period}")
    phase = (T_SYM - delay) / period
    return duty - (phase - sympy.floor(phase))


def gate_signals(expr: Optional[sympy.Expr]) -> frozenset:
    """The signals a guard reads."""
    if expr is None:
        return frozenset()
    return frozenset(s for s in expr.free_symbols if isinstance(s, Signal))
