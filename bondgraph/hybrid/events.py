"""Simulation of a switched bond graph with events and state re-initialisation.

Each mode is integrated by :func:`scipy.integrate.solve_ivp` with one
terminal event per switch that has a guard (a diode's forward flow while on,
minus its effort while off; a controlled switch's gate): the event is the
guard falling through zero (through ``-guard_tol`` when the mode was
entered with the guard already within ``guard_tol`` below zero).  At an event the triggering switch
flips; the diodes may take any state, and the new mode is the consistent
one (every diode's guard >= ``-guard_tol`` after the re-initialisation) that
loses no energy if there is one, then the one with fewest flips (a buck
converter's switch opening: the diode turns on and the inductor current
continues; a clutch engaging: no alternative, so the velocities jump and the
energy loss is reported).  The re-initialisation is described in
:mod:`bondgraph.hybrid._numeric`.

Chattering -- one switch flipping ``chatter_count`` times within
``chatter_time``, or no consistent state for it at an instant (a sliding
mode) -- raises :class:`~bondgraph.hybrid.ChatteringError` naming the switch
and the time; ``max_events`` and ``time_budget`` (wall seconds) bound a run
(:class:`~bondgraph.hybrid.EventBudgetError`, with the partial result).

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

import itertools
import math
import time as _time
from collections import defaultdict, deque
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Optional, Sequence

import numpy as np
import sympy
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from ..parameters import match_values, real_value
from ..signals import Signal
from ..signals import t as T_SYM
from ._numeric import CompiledMode, EnergyMetric, integrated
from ._result import SwitchedResponse
from .errors import ChatteringError, EventBudgetError, HybridError, ModeError
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
    x0 : mapping of str to float, optional
        Initial stored quantities by state name (``p_J1``, ``q_C``) and
        initial integrator states by name, or by the name of an output that
        is one displacement or momentum signal (``x`` for
        ``outputs={"x": bg.displacement("m")}``); missing ones are 0.  The initial
        mode is the built one if it is consistent with ``x0``, else the
        consistent one with fewest flips (re-initialised if it must be).
    values : mapping
        Parameter values (the policy of :mod:`bondgraph.parameters`).
    inputs : mapping of str to number or callable ``u(t)``, optional
        The model's inputs (sources without a value).
    t_eval : sequence of float, optional
        Sample times; by default the solver's steps.  The start and every
        event (before and after the change) are always sampled too.
    method, rtol, atol, max_step
        Passed to :func:`scipy.integrate.solve_ivp`.  Gates of time only (a
        PWM) are scanned ahead on a grid of ``period/1000`` (their switch's
        ``period``), else ``(t1 - t0)/1e5``, and their zero crossings refined
        to machine precision: no step limit is needed for them.
    guard_tol : float
        A guard is consistent while >= ``-guard_tol``.
    max_events : int
        Event budget; ``time_budget`` a wall-time budget in seconds.
    chatter_count, chatter_time
        Chattering: one switch firing ``chatter_count`` times within
        ``chatter_time`` (default ``1e-6*(t1 - t0)``).

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
        No consistent mode, an input derivative needed, bad ``x0`` names.
    """
    t0, t1 = (real_value(v, "t_span") for v in t_span)
    if not t1 > t0:
        raise HybridError(f"t_span must be increasing; got {tuple(t_span)!r}")
    run = _Run(sm, values, inputs, guard_tol=guard_tol)
    if max_step is None:
        max_step = math.inf
    resolution = run.scan_resolution(t0, t1)
    chatter_time = 1e-6 * (t1 - t0) if chatter_time is None else chatter_time
    q, integ = run.initial_state(x0)
    # the initial mode: every switch with a guard may be chosen freely
    free = tuple(n for n in sm.switches if sm.element(n).guard(True) is not None)
    mode, cm, x, q_new, loss = run.select(t0, sm.initial, free, free, q, integ, trigger=None)
    rec = _Recorder(run)
    rec.add_point(cm, t0, x)
    events: list[SwitchEvent] = []
    if loss or mode != sm.initial:
        events.append(run.event(t0, (), sm.initial, mode, q, q_new, loss))
    t = t0
    recent: dict[str, deque] = defaultdict(lambda: deque(maxlen=chatter_count))
    started = _time.monotonic()
    evals = None if t_eval is None else np.asarray(t_eval, dtype=float)
    while True:
        if time_budget is not None and _time.monotonic() - started > time_budget:
            raise EventBudgetError(f"model {sm.name!r}: time budget of {time_budget} s used up "
                                   f"at t = {t:.6g}", result=rec.result(events))
        seg_eval = None
        if evals is not None:
            seg_eval = evals[(evals >= t) & (evals <= t1)]
        sol, names, te, xe = run.segment(cm, t, t1, x, seg_eval, method, rtol, atol, max_step,
                                         resolution)
        if len(sol.t):
            rec.add(cm, sol.t, np.asarray(sol.y)[:-1])
        if sol.status < 0:
            raise HybridError(f"model {sm.name!r}, mode ({mode}): the integrator failed at "
                              f"t = {sol.t[-1]:.6g}: {sol.message}")
        if not names:
            break
        if len(events) >= max_events:
            raise EventBudgetError(f"model {sm.name!r}: event budget of {max_events} used up at "
                                   f"t = {te:.6g}", result=rec.result(events))
        for name in names:
            recent[name].append(te)
            if len(recent[name]) == chatter_count and te - recent[name][0] <= chatter_time:
                raise ChatteringError(
                    f"model {sm.name!r}: switch {name!r} chatters: {chatter_count} events within "
                    f"{te - recent[name][0]:.3g} s up to t = {te:.9g} (a sliding mode: its guard is "
                    "driven to zero from both sides); add the dynamics that decide it (a "
                    "resistance, an inductance) or a hysteresis in its gate", time=te, element=name)
        u = run.u(te)
        if not rec.t or rec.t[-1] != te:
            rec.add_point(cm, te, xe)
        q_old = cm.stored(te, xe, u)
        integ = integrated(sm, cm, te, xe, u)
        proposed = mode.flipped(*names)
        diodes = tuple(n for n in sm.switches if sm.element(n).self_switched)
        check = tuple(dict.fromkeys(diodes + tuple(n for n in names if n in diodes)))
        new_mode, cm_new, x, q_new, loss = run.select(te, proposed, diodes, check, q_old, integ,
                                                      trigger=names)
        events.append(run.event(te, names, mode, new_mode, q_old, q_new, loss))
        mode, cm, t = new_mode, cm_new, te
        rec.add_point(cm, te, x)
    return rec.result(events)


class _Run:
    """The numbers of one simulation: parameters, inputs, compiled modes."""

    def __init__(self, sm: ModeSet, values, inputs, *, guard_tol: float) -> None:
        self.sm = sm
        self.guard_tol = guard_tol
        modes = sm.modes
        if not modes:
            raise ModeError(f"model {sm.name!r} has no consistent mode")
        fulls = [sm.derived(m).full for m in modes]
        params: dict[str, sympy.Symbol] = {}
        for m in fulls:
            for p in m.parameters:
                params.setdefault(p.name, p)
        guard_syms: list = []
        for n in sm.switches:
            for on in (True, False):
                g = sm.element(n).guard(on)
                if g is not None:
                    guard_syms += [s for s in g.free_symbols
                                   if not isinstance(s, Signal) and s != T_SYM]
        for s in sorted(guard_syms, key=str):
            params.setdefault(s.name, s)
        known = tuple(m.known_parameters for m in fulls)
        given = match_values(tuple(params.values()), values, known=tuple(itertools.chain(*known)),
                             where=f"model {sm.name!r}: ")
        num = {p.name: real_value(v, p.name) for p, v in given.items()}
        self.values = num
        self.subs = {}
        for m in fulls:
            for s in m.parameters:
                self.subs[s] = num[s.name]
        for s in guard_syms:
            self.subs[s] = num[s.name]
        # inputs, in order of first appearance
        names: list = []
        for m in fulls:
            names += [s for s in m.inputs if s not in names]
        self.input_syms = tuple(names)
        inputs = dict(inputs or {})
        unknown = sorted(set(inputs) - {s.name for s in names})
        if unknown:
            raise HybridError(f"model {sm.name!r} has no input {unknown[0]!r}; its inputs are "
                              f"{', '.join(s.name for s in names) or '(none)'}")
        self._u: list[Callable] = []
        for s in names:
            if s.name not in inputs:
                raise HybridError(f"model {sm.name!r}: no value for input {s.name!r} (give "
                                  "inputs={name: number or function of t})")
            v = inputs[s.name]
            if callable(v):
                self._u.append(v)
            else:
                c = real_value(v, s.name)
                self._u.append(lambda t, c=c: c)
        self.metric = EnergyMetric(sm, self.subs)
        self._compiled: dict = {}
        # names of the stored quantities: the state name where the element is integral
        labels = [str(s) for s in sm.energy_signals]
        for m in fulls:
            for k in range(len(labels)):
                ex = m.output_exprs[m.output_names.index(f"hyb_E{k}")]
                if ex in m.states[: m.storage_states]:
                    labels[k] = ex.name
        self.labels = tuple(labels)

    def u(self, t: float) -> np.ndarray:
        return np.array([float(f(t)) for f in self._u])

    def compiled(self, mode: Mode) -> CompiledMode:
        cm = self._compiled.get(mode)
        if cm is None:
            cm = self._compiled[mode] = CompiledMode(self.sm, self.sm.derived(mode), self.subs,
                                                     self.input_syms)
        return cm

    def scan_resolution(self, t0: float, t1: float) -> float:
        """Grid step of the scan of time-only gates: period/1000, else (t1 - t0)/1e5."""
        periods = [getattr(self.sm.element(n), "period", None) for n in self.sm.switches]
        steps = [float(p.xreplace(self.subs)) / 1000 for p in periods if p is not None]
        return min(steps + [(t1 - t0) / 1e5])

    def initial_state(self, x0) -> tuple[np.ndarray, dict]:
        x0 = dict(x0 or {})
        q = np.zeros(len(self.labels))
        integ: dict = {}
        valid = set(self.labels)
        integ_names: dict = {}
        for mode in self.sm.modes:
            for name, sig in self.sm.derived(mode).full.integrators:
                integ_names.setdefault(name, sig)
                integ.setdefault(sig, 0.0)
        for s in self.sm.guard_signals:
            integ.setdefault(str(s), 0.0)
        for name, expr in self.sm.user_outputs.items():     # x0={"x": ...} for x = displacement
            if isinstance(expr, Signal) and str(expr) in integ:
                integ_names.setdefault(name, str(expr))
        for key, v in x0.items():
            if key in valid:
                q[self.labels.index(key)] = real_value(v, key)
            elif key in integ_names:
                integ[integ_names[key]] = real_value(v, key)
            else:
                raise HybridError(f"model {self.sm.name!r}: x0 names {key!r}, which is no state "
                                  f"of any mode; expected one of "
                                  f"{', '.join(sorted(valid | set(integ_names)))}")
        return q, integ

    def select(self, t, proposed: Mode, free: tuple, check: tuple, q_old, integ, *, trigger):
        """The new mode: candidates flip any subset of ``free``; see the module docstring."""
        u = self.u(t)
        h_old = self.metric.energy(q_old)
        tiny = 1e-9 * max(abs(h_old), 1e-300)
        cands = []
        tried = []
        for k in range(len(free) + 1):
            for flip in itertools.combinations(free, k):
                mode = proposed.flipped(*flip)
                try:
                    cm = self.compiled(mode)
                except ModeError:
                    continue
                x, q_new, loss = cm.enter(t, q_old, integ, u, self.metric, self.sm)
                g = cm.guard_values(t, x, u)
                bad = [n for n in check if n in g and g[n] < -self.guard_tol]
                tried.append((mode, bad))
                if not bad:
                    cands.append(((abs(loss) > tiny, k, abs(loss)), mode, cm, x, q_new, loss))
        if not cands:
            where = f"at t = {t:.9g}"
            if trigger:
                raise ChatteringError(
                    f"model {self.sm.name!r}: switch {trigger[0]!r} has no consistent state {where}: "
                    + "; ".join(f"mode ({m}) violates the guard of {', '.join(b)}" for m, b in tried)
                    + " (a sliding mode: it would flip at every step)", time=t, element=trigger[0])
            raise ModeError(f"model {self.sm.name!r}: no consistent mode {where}: "
                            + "; ".join(f"mode ({m}) violates the guard of {', '.join(b)}"
                                        for m, b in tried))
        best = min(cands, key=lambda c: c[0])
        _, mode, cm, x, q_new, loss = best
        return mode, cm, x, q_new, loss if abs(loss) > tiny else 0.0

    def segment(self, cm: CompiledMode, t: float, t1: float, x, seg_eval, method, rtol, atol,
                max_step, resolution: float):
        """Integrate mode ``cm`` from ``t`` to the first event or ``t1``.

        Returns ``(sol, fired, te, xe)``: ``fired`` the switches whose guards fell
        through zero at ``te`` with the state ``xe`` (empty when ``t1`` was reached).
        State guards are ``solve_ivp`` events; guards of time only are found by
        scanning them at ``resolution`` and refining with :func:`scipy.optimize.brentq`,
        so that no pulse is stepped over and their instants are exact.
        """
        u = self.u
        tol = self.guard_tol

        def f(tt, y):
            return np.append(cm.f(tt, y[:-1], u(tt)), 0.0)

        events: list = []
        names: list[str] = []
        start = cm.guard_values(t, np.asarray(x, dtype=float), u(t))
        t_stop = t1
        timed: list[str] = []       # the time-only switches that fire at t_stop
        for name, g in cm.guards:
            # a guard accepted slightly below zero (within guard_tol) fires at -guard_tol
            off = tol if start[name] < 0 else 0.0
            if name in cm.time_guards:
                hit = _first_crossing(cm.time_guards[name], off, t, t1, resolution)
                if hit is not None and hit <= t_stop:
                    timed = (timed if hit == t_stop else []) + [name]
                    t_stop = hit
                continue

            def ev(tt, y, g=g, off=off):
                return float(np.asarray(g(tt, *y[:-1], *u(tt))).reshape(-1)[0]) + off
            ev.terminal = True      # type: ignore[attr-defined]
            ev.direction = -1       # type: ignore[attr-defined]
            events.append(ev)
            names.append(name)
        if seg_eval is not None:
            seg_eval = seg_eval[seg_eval <= t_stop]
        y0 = np.append(np.asarray(x, dtype=float), 0.0)
        sol = solve_ivp(f, (t, t_stop), y0, method=method, t_eval=seg_eval, events=events or None,
                        rtol=rtol, atol=atol, max_step=max_step,
                        dense_output=seg_eval is not None and t_stop < t1)
        if sol.status == 1:
            fired = [k for k, te in enumerate(sol.t_events) if len(te)]
            te = float(sol.t_events[fired[0]][0])
            xe = np.asarray(sol.y_events[fired[0]][0], dtype=float)[:-1]
            return sol, tuple(names[k] for k in fired), te, xe
        if sol.status == 0 and t_stop < t1:
            end = sol.sol(t_stop) if sol.sol is not None else sol.y[:, -1]
            return sol, tuple(timed), t_stop, np.asarray(end, dtype=float)[:-1]
        return sol, (), None, None

    def event(self, t, names, before, after, q_old, q_new, loss) -> SwitchEvent:
        jumps = {}
        for k, lab in enumerate(self.labels):
            a, b = float(q_old[k]), float(q_new[k])
            if abs(a - b) > 1e-9 * max(1.0, abs(a)):
                jumps[lab] = (a, b)
        return SwitchEvent(float(t), tuple(names), before, after, float(loss), jumps)


def _first_crossing(g: Callable, off: float, t: float, t1: float, h: float) -> Optional[float]:
    """The first time in ``(t, t1]`` at which ``g + off`` falls from >= 0 below zero, or None.

    A gate located just before its jump (a PWM edge found from the left) is
    still negative at ``t``: the scan then waits until it is >= 0 (past the
    jump) before it looks for the next fall.
    """
    a = t
    armed = float(g(t)) + off >= 0
    while a < t1:
        b = min(t1, a + 2000 * h)
        ts = np.linspace(a, b, 2001)
        v = np.broadcast_to(np.asarray(g(ts), dtype=float), ts.shape) + off
        ok = v >= 0
        if not armed:
            up = np.nonzero(ok)[0]
            if not up.size:
                a = b
                continue
            armed = True
            ts, v, ok = ts[up[0]:], v[up[0]:], ok[up[0]:]
        neg = np.nonzero(~ok[1:])[0]
        if neg.size:
            i = int(neg[0]) + 1
            lo, hi = float(ts[i - 1]), float(ts[i])
            return float(brentq(lambda s: float(g(s)) + off, lo, hi, xtol=4e-16 * max(1.0, abs(hi)),
                                rtol=8.9e-16))
        a = b
    return None


class _Recorder:
    def __init__(self, run: _Run) -> None:
        self.run = run
        self.t: list = []
        self.out: list = []
        self.q: list = []
        self.idx: list = []
        self.modes: list = []

    def _index(self, cm: CompiledMode) -> int:
        if cm.mode not in self.modes:
            self.modes.append(cm.mode)
        return self.modes.index(cm.mode)

    def add(self, cm: CompiledMode, ts, ys) -> None:
        k = self._index(cm)
        for j, tt in enumerate(ts):
            if j == 0 and self.t and self.t[-1] == tt and self.idx[-1] == k:
                continue          # the segment's start, recorded already
            self.add_point(cm, float(tt), ys[:, j], k)

    def add_point(self, cm: CompiledMode, t: float, x, k: Optional[int] = None) -> None:
        u = self.run.u(t)
        self.t.append(t)
        self.out.append(cm.outputs(t, x, u))
        self.q.append(cm.stored(t, x, u))
        self.idx.append(self._index(cm) if k is None else k)

    def result(self, events) -> SwitchedResult:
        names = self.run.sm.user_outputs.keys()
        out = np.array(self.out).reshape(len(self.t), -1)
        q = np.array(self.q).reshape(len(self.t), -1)
        return SwitchedResult(
            t=np.array(self.t), outputs={n: out[:, j] for j, n in enumerate(names)},
            stored={lab: q[:, j] for j, lab in enumerate(self.run.labels)},
            mode_index=np.array(self.idx, dtype=int), modes=tuple(self.modes), events=tuple(events))
