"""Simulation of a switched bond graph with events and state re-initialisation.

Each mode is integrated step by step (a :mod:`scipy.integrate` solver) and
after every accepted step every guard (a diode's forward flow while on,
minus its effort while off; a controlled switch's gate) is looked at on the
step's dense output and its first fall below zero located there, whatever
the step (:mod:`bondgraph.hybrid._segment`).  At an event the triggering
switch flips and the new mode is chosen by complementarity
(:meth:`bondgraph.hybrid._run.Run.select`): the diodes may take any state;
candidates are the modes whose guards hold after the re-initialisation,
then those whose guards do not fall below zero at the next instant, then
those that need no jump of a stored quantity (a buck converter's switch
opening: the diode turns on and the inductor current continues), then the
fewest flips (a clutch engaging: no alternative, so the velocities jump and
the energy loss is reported).  The re-initialisation is described in
:mod:`bondgraph.hybrid._numeric`.

Chattering -- one switch changing state ``chatter_count`` times within
``chatter_time``, or no state of it that holds at the next instant (a
sliding mode) -- raises :class:`~bondgraph.hybrid.ChatteringError` naming
the switch and the time; ``max_events`` and ``time_budget`` (wall seconds,
checked at every step) bound a run (:class:`~bondgraph.hybrid.EventBudgetError`,
with the partial result).

Examples
--------
An RL circuit whose switch opens at ``t = 1``: the inductor current drops to
zero and its energy ``L i^2/2`` is lost in the (ideal) switch.

>>> import bondgraph as bg
>>> from bondgraph import hybrid
>>> g = bg.BondGraph("rl")
>>> g.add(bg.Se("E", value=1), bg.One("i"), bg.R("R"), bg.I("L"),
...       hybrid.ControlledSwitch("S", gate=1 - bg.t, on=True))
>>> for a, b in [("E", "i"), ("i", "R"), ("i", "L"), ("i", "S")]: _ = g.connect(a, b)
>>> sm = hybrid.SwitchedModel(g, outputs={"i": bg.flow("L")})
>>> res = hybrid.simulate(sm, (0, 2), values={"R": 1, "L": 1})
>>> ev = res.events[0]
>>> round(ev.time, 9), str(ev.after), round(ev.energy_loss, 6)     # (1 - exp(-1))**2/2
(1.0, 'S off', 0.199788)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping, Optional, Sequence

import numpy as np

from ._options import check_options
from .modes import Mode, ModeSet

__all__ = ["simulate", "SwitchedResult", "SwitchEvent"]


@dataclass(frozen=True)
class SwitchEvent:
    """One mode change.

    Attributes
    ----------
    time : float
    elements : tuple of str
        The switches whose guards fired (empty for the initial mode choice).
    before, after : Mode
    energy_loss : float
        Stored energy lost in the re-initialisation (0 when no state jumps; negative
        if a jump driven by a source added energy).
    jumps : dict
        Stored quantity name -> (before, after), for those that jumped.
    """

    time: float
    elements: tuple
    before: Mode
    after: Mode
    energy_loss: float
    jumps: dict = field(default_factory=dict)


@dataclass(frozen=True)
class SwitchedResult:
    """A switched simulation: samples, modes and events.

    Attributes
    ----------
    t : ndarray
        Sample times (an event time appears twice: before and after the change).
    outputs : dict of str to ndarray
        The model's outputs.
    stored : dict of str to ndarray
        The stored quantity of every storage element (``p_J1``, ``q_C``), also
        while it is in derivative causality.
    mode_index : ndarray of int
        Per sample, the index in ``modes``.
    modes : tuple of Mode
        The modes visited, in order of first visit.
    events : tuple of SwitchEvent
    """

    t: np.ndarray
    outputs: dict
    stored: dict
    mode_index: np.ndarray
    modes: tuple
    events: tuple

    @property
    def energy_loss(self) -> float:
        """Total energy lost in re-initialisations."""
        return float(sum(e.energy_loss for e in self.events))

    def event_times(self, element: str) -> np.ndarray:
        """Times at which switch ``element`` fired."""
        return np.array([e.time for e in self.events if element in e.elements])


def simulate(sm: ModeSet, t_span: Sequence[float], x0: Optional[Mapping[str, float]] = None, *,
             values: Optional[Mapping] = None, inputs: Optional[Mapping[str, Any]] = None,
             t_eval: Optional[Sequence[float]] = None, method: str = "RK45",
             rtol: float = 1e-9, atol: float = 1e-12, max_step: Optional[float] = None,
             guard_tol: float = 1e-9, max_events: int = 10_000,
             time_budget: Optional[float] = None, chatter_count: int = 20,
             chatter_time: Optional[float] = None) -> SwitchedResult:
    """Simulate a switched model from ``t_span[0]`` to ``t_span[1]`` with events.

    Parameters
    ----------
    sm : SwitchedModel
    t_span : (t0, t1)
        Finite, ``t0 < t1``.
    x0 : mapping of str to float, optional
        Initial stored quantities by state name (``p_J1``, ``q_C``) and
        initial integrator states by name, or by the name of an output that
        is one displacement or momentum signal (``x`` for
        ``outputs={"x": bg.displacement("m")}``); missing ones are 0.  A given
        signal is honoured in the initial mode (where the mode computes it from a
        stored quantity, that quantity is set from it) or refused naming it.
    values : mapping
        Parameter values (the policy of :mod:`bondgraph.parameters`); a value
        that makes an equation or a guard non-finite (``C = 0``, a PWM period 0)
        is refused naming the element and the parameter.
    inputs : mapping of str to number or callable ``u(t)``, optional
        The model's inputs (sources without a value); a function must return
        finite real numbers (text is never parsed).
    t_eval : sequence of float, optional
        Increasing sample times within ``t_span``; by default the solver's
        steps.  The start and every event (before and after the change) are
        always sampled too.
    method : {"RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA"}
    rtol, atol, max_step : float
        Solver tolerances (positive) and largest step (positive, default none).
    guard_tol : float
        ``>= 0``: a guard is consistent while ``>= -guard_tol``.
    max_events : int
        ``>= 0``: event budget (real mode changes).
    time_budget : float, optional
        Wall-time budget in seconds, checked at every step.
    chatter_count, chatter_time
        Chattering: one switch changing state ``chatter_count`` (``>= 1``) times within
        ``chatter_time`` (default ``1e-6*(t1 - t0)``, and at most a thousandth of
        every switch's ``period``).

    Returns
    -------
    SwitchedResult

    Raises
    ------
    ChatteringError
        Naming the switch and the time.
    EventBudgetError
        The event or time budget was used up (``err.result`` holds the run so far).
    ModeError, HybridError
        No consistent mode, an input derivative needed, bad options or ``x0`` names,
        a non-finite guard (naming the switch and the time).

    Notes
    -----
    The mode at ``t0`` and after every event is chosen by complementarity:
    among the combinations of the free switches (every switch with a guard at
    ``t0``; the diodes at an event), those whose guards hold after the
    re-initialisation, then those whose guards do not fall below zero at the
    next instant (a tie at zero resolved by the derivatives), then those that
    need no jump of a stored quantity, then the fewest flips.  Events are
    located on the dense output of every accepted step (see
    :mod:`bondgraph.hybrid._segment`).
    """
    opts = check_options(t_span, t_eval=t_eval, method=method, rtol=rtol, atol=atol,
                         max_step=max_step, guard_tol=guard_tol, max_events=max_events,
                         time_budget=time_budget, chatter_count=chatter_count,
                         chatter_time=chatter_time)
    from ._run import Run

    return Run(sm, values, inputs, opts).simulate(x0)
