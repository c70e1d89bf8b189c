"""The records of a switched simulation: :class:`SwitchEvent` (one mode change) and
:class:`SwitchedResult` (the samples, modes and events of a run).

:func:`bondgraph.hybrid.simulate` returns them; they live apart from it so that
the run (:mod:`bondgraph.hybrid._run`) builds them without importing the
function that starts it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._result import SwitchedResponse
from .modes import Mode

__all__ = ["SwitchEvent", "SwitchedResult"]


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
class SwitchedResult(SwitchedResponse):
    """A switched simulation: samples, modes and events; indexed by signal name
    (``res["v"]``), with ``to_dataframe()`` and ``plot()`` (see
    :class:`~bondgraph.numeric.result.TimeResponse`).

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
    inputs : dict of str to ndarray
        The inputs at the samples (filled by :func:`bondgraph.simulate`).
    """

    t: np.ndarray
    outputs: dict
    stored: dict
    mode_index: np.ndarray
    modes: tuple
    events: tuple
    inputs: dict = field(default_factory=dict)

    @property
    def energy_loss(self) -> float:
        """Total energy lost in re-initialisations."""
        return float(sum(e.energy_loss for e in self.events))

    def event_times(self, element: str) -> np.ndarray:
        """Times at which switch ``element`` fired."""
        return np.array([e.time for e in self.events if element in e.elements])
