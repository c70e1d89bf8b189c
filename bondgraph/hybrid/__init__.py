"""Switched (hybrid) bond graphs: ideal switches, diodes, controlled switches and their modes.

A switch (:class:`Switch`, :class:`Diode`, :class:`ControlledSwitch`, the
contact laws :class:`Contact` and :class:`Slip`) is an element of the
protocol: on, it is an effort source (zero but for a slipping friction);
off, a zero-flow source.  A :class:`SwitchedModel` derives one ordinary
:class:`~bondgraph.Model` per mode (lazily, cached); :func:`simulate` runs
it with events (guards from diode flows and efforts and from gates) and
re-initialises the state when a mode change removes states; :func:`average`
gives the state-space average of a PWM-switched model in the duty cycle.

Nothing here is imported by ``import bondgraph``: ``import bondgraph.hybrid``.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph import hybrid
>>> g = bg.BondGraph("rl")
>>> g.add(bg.Se("E"), bg.One("i"), bg.R("R"), bg.I("L"), hybrid.Switch("S", on=True))
>>> for a, b in [("E", "i"), ("i", "R"), ("i", "L"), ("i", "S")]: _ = g.connect(a, b)
>>> sm = hybrid.SwitchedModel(g)
>>> sm.mode(on={"S"}).rhs, sm.mode(off={"S"}).state_names
((E - R*p_L/L,), ())
"""

from .elements import ControlledSwitch, Diode, Switch, SwitchElement, pwm
from .contact import Contact, Slip
from .junctions import SwitchedOne, SwitchedZero
from .errors import ChatteringError, EventBudgetError, HybridError, ModeError
from .modes import Mode, ModeModel, ModeSet
from .switched import SwitchedModel, derive_switched, simulate
from .events import SwitchEvent, SwitchedResult
from .averaging import average

__all__ = [
    "SwitchElement", "Switch", "Diode", "ControlledSwitch", "pwm", "Contact", "Slip",
    "SwitchedZero", "SwitchedOne",
    "Mode", "ModeModel", "ModeSet", "SwitchedModel", "derive_switched",
    "simulate", "SwitchedResult", "SwitchEvent", "average",
    "HybridError", "ModeError", "ChatteringError", "EventBudgetError",
]

