"""One switched simulation: its numbers, the mode choice by complementarity, the event loop (private).

:class:`Run` holds what :func:`bondgraph.hybrid.simulate` computes once
(parameters, inputs, compiled modes, the periodic gates' falls) and runs the
loop: integrate the mode to its first event (:mod:`._segment`), choose the
new mode (:meth:`Run.select`), re-initialise, repeat.
"""

from __future__ import annotations

import itertools
import math
from collections import defaultdict, deque
from typing import Any, Callable, Mapping, Optional

import numpy as np
import sympy

from ..parameters import match_values, real_value
from ..signals import Signal
from ..signals import t as T_SYM
from ._numeric import CompiledMode, EnergyMetric, integrated, nonfinite, periods
from ._options import Clock, Options, checked_input
from ._segment import integrate, next_time_event, periodic_falls
from .errors import ChatteringError, EventBudgetError, HybridError, ModeError
from .events import SwitchedResult, SwitchEvent
from .modes import Mode, ModeSet

__all__ = ["Run"]

#: most events at one instant that leave the mode as it was
_SAME_INSTANT = 100


class Run:
    """The numbers of one simulation: parameters, inputs, compiled modes; and its loop."""

    def __init__(self, sm: ModeSet, values, inputs, opts: Options) -> None:
        self.sm = sm
        self.opts = opts
        self.guard_tol = opts.guard_tol
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
            el = sm.element(n)
            for expr in (el.guard(True), el.guard(False), getattr(el, "period", None)):
                if expr is not None:
                    guard_syms += [s for s in expr.free_symbols
                                   if not isinstance(s, Signal) and s != T_SYM]
        for s in sorted(guard_syms, key=str):
            params.setdefault(s.name, s)
        known = tuple(m.known_parameters for m in fulls)
        given = match_values(tuple(params.values()), values, known=tuple(itertools.chain(*known)),
                             where=f"model {sm.name!r}: ")
        num = {p.name: real_value(v, p.name) for p, v in given.items()}
        self.values = num
        self.subs = {p: num[p.name] for p in params.values() if p.name in num}
        self._check_finite(modes, fulls)
        self.periods = self._periods()
        # inputs, in order of first appearance
        names: list = []
        for m in fulls:
            names += [s for s in m.inputs if s not in names]
        self.input_syms = tuple(names)
        if inputs is not None and not isinstance(inputs, Mapping):
            raise HybridError(f"model {sm.name!r}: inputs must be a mapping of input name to a "
                              f"number or a function of t; got {type(inputs).__name__}")
        inputs = dict(inputs or {})
        unknown = sorted(set(inputs) - {s.name for s in names}, key=str)
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
                self._u.append(checked_input(s.name, v))
            else:
                try:
                    c = real_value(v, s.name)
                except Exception as exc:
                    raise HybridError(f"model {sm.name!r}: input {s.name!r} must be a finite real "
                                      f"number or a function of t; got {type(v).__name__} {v!r}") from exc
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
        self._falls: dict = {}
        self.chatter_time = opts.chatter_time
        if self.chatter_time is None:
            self.chatter_time = min([1e-6 * (opts.t1 - opts.t0)] + [1e-3 * p for p in self.periods.values()])

    # ------------------------------------------------------------ checks of the numbers
    def _check_finite(self, modes, fulls) -> None:
        """Every mode's equations and guards finite with the values, else the culprit named."""
        why = nonfinite(self.sm, modes, fulls, self.subs)
        if why:
            raise HybridError(why)

    def _periods(self) -> dict:
        out, why = periods(self.sm, self.subs)
        if why:
            raise HybridError(why)
        return out

    # ------------------------------------------------------------ numbers
    def u(self, t: float) -> np.ndarray:
        return np.array([f(t) for f in self._u], dtype=float)

    def compiled(self, mode: Mode) -> CompiledMode:
        cm = self._compiled.get(mode)
        if cm is None:
            cm = self._compiled[mode] = CompiledMode(self.sm, self.sm.derived(mode), self.subs,
                                                     self.input_syms, self.periods)
        return cm

    def falls(self, cm: CompiledMode, t: float) -> dict:
        """The falls over one period of each periodic guard of ``cm`` (found once)."""
        out = {}
        for name, period in cm.periodic.items():
            key = (cm.mode, name)
            if key not in self._falls:
                try:
                    self._falls[key] = (periodic_falls(cm.time_guards[name], period, t), period)
                except HybridError as exc:
                    raise HybridError(f"model {self.sm.name!r}: the guard of switch {name!r}: {exc}") from None
            out[name] = self._falls[key]
        return out

    def initial_state(self, x0) -> tuple[np.ndarray, dict, dict]:
        """``(q_all, integrators, given signals)`` from ``x0``."""
        if x0 is not None and not isinstance(x0, Mapping):
            raise HybridError(f"model {self.sm.name!r}: x0 must be a mapping of state name to "
                              f"number; got {type(x0).__name__}")
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
        given: dict = {}
        for key, v in x0.items():
            if key in valid:
                q[self.labels.index(key)] = real_value(v, key)
            elif key in integ_names:
                integ[integ_names[key]] = given[integ_names[key]] = real_value(v, key)
            else:
                raise HybridError(f"model {self.sm.name!r}: x0 names {key!r}, which is no state "
                                  f"of any mode; expected one of "
                                  f"{', '.join(sorted(valid | set(integ_names)))}")
        self.given_q = {self.labels.index(k) for k in x0 if k in valid}
        self.given_names = {integ_names[k]: k for k in x0 if k in integ_names}
        return q, integ, given

    # ------------------------------------------------------------ the mode choice
    def select(self, t, proposed: Mode, free: tuple, check: tuple, q_old, integ, *, trigger,
               given: Optional[dict] = None):
        """The new mode by complementarity: ``(mode, cm, x, q_new, loss, jumped)``."""
        u = self.u(t)
        cands, tried = [], []
        for k in range(len(free) + 1):
            for flip in itertools.combinations(free, k):
                mode = proposed.flipped(*flip)
                try:
                    cm = self.compiled(mode)
                except ModeError:
                    continue
                x, q_new, loss = cm.enter(t, q_old, integ, u, self.metric, self.sm)
                q_ref = q_old
                if given:
                    x, q_new, q_ref, why = self._honour(cm, t, x, u, q_old, given)
                    if why:
                        tried.append((mode, why))
                        continue
                    loss = self.metric.energy(q_ref) - self.metric.energy(q_new)
                g = cm.guard_values(t, x, u)
                bad = [n for n in check if n in g and not g[n] >= -self.guard_tol]
                if bad:
                    tried.append((mode, f"violates the guard of {', '.join(bad)}"))
                    continue
                leaving = self._leaving(cm, t, x, u, g, tuple(check) + tuple(trigger or ()))
                jumped = self._jumped(q_ref, q_new)
                cands.append(((bool(leaving), jumped, k, abs(loss)), mode, cm, x, q_new, loss,
                              jumped, leaving, q_ref))
        where = f"at t = {t:.9g}"
        if not cands:
            text = "; ".join(f"mode ({m}) {why}" for m, why in tried)
            if trigger:
                raise ChatteringError(
                    f"model {self.sm.name!r}: switch {trigger[0]!r} chatters: it has no consistent "
                    f"state {where}: {text} (a sliding mode: it would flip at every step)",
                    time=t, element=trigger[0])
            raise ModeError(f"model {self.sm.name!r}: no consistent mode {where}: {text}")
        best = min(cands, key=lambda c: c[0])
        _, mode, cm, x, q_new, loss, jumped, leaving, self.q_ref = best
        if leaving:
            name = next((n for n in (trigger or ()) if n in leaving), leaving[0])
            raise ChatteringError(
                f"model {self.sm.name!r}: switch {name!r} chatters {where}: in every consistent "
                f"mode its guard falls below zero at the next instant (a sliding mode: its guard "
                "is driven to zero from both sides); add the dynamics that decide it (a "
                "resistance, an inductance) or a hysteresis in its gate", time=t, element=name)
        return mode, cm, x, q_new, (loss if jumped else 0.0), jumped

    def _leaving(self, cm: CompiledMode, t, x, u, g: dict, names) -> tuple:
        """The guards among ``names`` that are at zero (within ``guard_tol``) and fall below it
        at the next instant (their first nonzero time derivative negative)."""
        near = [n for n in dict.fromkeys(names) if n in g and g[n] <= self.guard_tol]
        if not near:
            return ()
        u_dot = self.u_rate(t) if len(u) else u
        rel = max(1e-10, 100 * self.opts.rtol)
        return tuple(n for n in near if cm.trend(n, t, x, u, u_dot, rel) < 0)

    def u_rate(self, t: float) -> np.ndarray:
        """The inputs' rates at ``t`` (a one-sided difference forward: the next instant)."""
        h = 1e-7 * max(1.0, abs(t))
        return (self.u(t + h) - self.u(t)) / h

    def _jumped(self, q_old, q_new) -> bool:
        o = self.opts
        scale = 10 * (o.atol + o.rtol * np.maximum(np.abs(q_old), np.abs(q_new)))
        return bool(np.any(np.abs(q_new - q_old) > scale))

    def _honour(self, cm: CompiledMode, t, x, u, q_old, given: dict):
        """``x`` adjusted so that the mode's signals take the values given in ``x0``:
        ``(x, q_new, q_ref, why)``, ``why`` the reason when it cannot."""
        own = {sig for _, sig in cm.integrators}
        x = np.array(x, dtype=float)
        q_ref = q_old.copy()
        n = cm.n_storage
        for sig, value in given.items():
            if sig in own:
                continue
            have = integrated(self.sm, cm, t, x, u)[sig]
            if abs(have - value) <= 1e-12 * max(1.0, abs(value)):
                continue
            coef = []
            for j in range(n):
                row = cm.storage_rows[j]
                if row is None or row in self.given_q:
                    continue
                e = np.zeros(len(x))
                e[j] = 1.0
                c1 = integrated(self.sm, cm, t, x + e, u)[sig] - have
                c2 = integrated(self.sm, cm, t, x + 2 * e, u)[sig] - have
                if c1 != 0 and abs(c2 - 2 * c1) <= 1e-9 * abs(c1):
                    coef.append((j, c1))
            if len(coef) != 1:
                name = self.given_names.get(sig, sig)
                return x, None, q_ref, (f"cannot take the given {name} = {value:g}: there it is "
                                        f"{have:g}, fixed by its equations")
            j, c1 = coef[0]
            x[j] += (value - have) / c1
        q_new = cm.stored(t, x, u)
        for j in range(n):
            row = cm.storage_rows[j]
            if row is not None and row not in self.given_q:
                q_ref[row] = q_new[row]
        return x, q_new, q_ref, ""

    # ------------------------------------------------------------ the loop
    def simulate(self, x0) -> SwitchedResult:
        sm, o = self.sm, self.opts
        q, integ, given = self.initial_state(x0)
        free = tuple(n for n in sm.switches if sm.element(n).guard(True) is not None)
        diodes = tuple(n for n in sm.switches if sm.element(n).self_switched)
        mode, cm, x, q_new, loss, jumped = self.select(o.t0, sm.initial, free, free, q, integ,
                                                       trigger=None, given=given)
        rec = _Recorder(self)
        rec.point(cm, o.t0, x)
        events: list[SwitchEvent] = []
        if jumped or mode != sm.initial:
            events.append(self.event(o.t0, (), sm.initial, mode, self.q_ref, q_new, loss))
        clock = Clock(o.time_budget, sm.name)
        check_clock = (lambda tt: clock.check(tt, lambda: rec.result(events))) \
            if o.time_budget is not None else (lambda tt: None)
        recent: dict[str, deque] = defaultdict(lambda: deque(maxlen=o.chatter_count))
        t, armed, level = o.t0, {}, {}
        steps: dict = {}
        same_t, same_n = None, 0
        while True:
            check_clock(t)
            where = f"model {sm.name!r}, mode ({mode})"
            seg = integrate(cm, t, x, o.t1, u=self.u, method=o.method, rtol=o.rtol, atol=o.atol,
                            max_step=o.max_step, guard_tol=o.guard_tol, armed=armed,
                            arm_level=level, time_event=next_time_event(self.falls(cm, t), t, o.t1),
                            first_step=steps.get(mode), record=lambda ts, ys, cm=cm: rec.add(cm, ts, ys),
                            evals=o.t_eval, clock=check_clock, where=where)
            if seg.last_step > 0:
                steps[mode] = seg.last_step
            te, xe, names = seg.t, seg.x, seg.fired
            if not names:
                if o.t_eval is None:
                    rec.point(cm, te, xe, only_new=True)
                break
            rec.point(cm, te, xe, only_new=True)
            u = self.u(te)
            q_old = cm.stored(te, xe, u)
            integ = integrated(sm, cm, te, xe, u)
            check = tuple(dict.fromkeys(diodes + tuple(n for n in names if n in diodes)))
            new_mode, cm_new, x, q_new, loss, jumped = self.select(
                te, mode.flipped(*names), diodes, check, q_old, integ, trigger=names)
            same_n = same_n + 1 if te == same_t else 1
            same_t = te
            if same_n > _SAME_INSTANT:
                raise ChatteringError(f"model {sm.name!r}: switch {names[0]!r} chatters: more than "
                                      f"{_SAME_INSTANT} events at t = {te:.9g}", time=te, element=names[0])
            if new_mode == mode and not jumped:
                # the guard touched zero and the mode holds: continue, that guard re-armed
                # only once it is back above guard_tol
                for n in names:
                    armed[n] = False
                    level[n] = o.guard_tol
                t, x = te, xe
                continue
            if len(events) >= o.max_events:
                raise EventBudgetError(f"model {sm.name!r}: event budget of {o.max_events} used up "
                                       f"at t = {te:.6g}", result=rec.result(events))
            for n in sm.switches:
                if new_mode.is_on(n) != mode.is_on(n):
                    times = recent[n]
                    times.append(te)
                    if len(times) == o.chatter_count and te - times[0] <= self.chatter_time:
                        raise ChatteringError(
                            f"model {sm.name!r}: switch {n!r} chatters: {o.chatter_count} changes "
                            f"within {te - times[0]:.3g} s up to t = {te:.9g} (a sliding mode: its "
                            "guard is driven to zero from both sides); add the dynamics that decide "
                            "it (a resistance, an inductance) or a hysteresis in its gate",
                            time=te, element=n)
            events.append(self.event(te, names, mode, new_mode, q_old, q_new, loss))
            mode, cm, t, armed, level = new_mode, cm_new, te, {}, {}
            rec.point(cm, te, x)
        return rec.result(events)

    def event(self, t, names, before, after, q_old, q_new, loss) -> SwitchEvent:
        jumps = {}
        for k, lab in enumerate(self.labels):
            a, b = float(q_old[k]), float(q_new[k])
            if abs(a - b) > 1e-9 * max(1.0, abs(a)):
                jumps[lab] = (a, b)
        return SwitchEvent(float(t), tuple(names), before, after, float(loss), jumps)


def _many(fn: Callable, ts: np.ndarray, xs: np.ndarray, us: np.ndarray) -> np.ndarray:
    """A lambdified list of expressions at many samples: shape ``(k, len(ts))``."""
    vals = fn(ts, *xs, *us)
    if not len(vals):
        return np.zeros((0, ts.size))
    return np.vstack([np.broadcast_to(np.asarray(v, dtype=float), ts.shape) for v in vals])


class _Recorder:
    """The samples, kept per segment and evaluated together at the end."""

    def __init__(self, run: Run) -> None:
        self.run = run
        self.chunks: list = []        # (cm, ts, xs)
        self.last_t: Optional[float] = None
        self.modes: list = []

    def _index(self, cm: CompiledMode) -> int:
        if cm.mode not in self.modes:
            self.modes.append(cm.mode)
        return self.modes.index(cm.mode)

    def add(self, cm: CompiledMode, ts, ys) -> None:
        ts = np.asarray(ts, dtype=float)
        if ts.size:
            self.chunks.append((cm, ts, np.asarray(ys, dtype=float).reshape(len(cm.states), ts.size)))
            self.last_t = float(ts[-1])

    def point(self, cm: CompiledMode, t: float, x, only_new: bool = False) -> None:
        if only_new and self.last_t == t:
            return
        self.add(cm, np.array([t]), np.asarray(x, dtype=float).reshape(-1, 1))

    def result(self, events) -> SwitchedResult:
        run = self.run
        names = list(run.sm.user_outputs.keys())
        ts, outs, qs, idx = [], [], [], []
        for cm, t, xs in self.chunks:
            us = np.array([[f(float(s)) for s in t] for f in run._u]).reshape(len(run._u), t.size)
            ts.append(t)
            outs.append(_many(cm._outs, t, xs, us))
            qs.append(_many(cm._q, t, xs, us))
            idx.append(np.full(t.size, self._index(cm), dtype=int))
        t_all = np.concatenate(ts) if ts else np.zeros(0)
        out = np.hstack(outs) if outs else np.zeros((len(names), 0))
        q = np.hstack(qs) if qs else np.zeros((len(run.labels), 0))
        return SwitchedResult(
            t=t_all, outputs={n: out[j] for j, n in enumerate(names)},
            stored={lab: q[j] for j, lab in enumerate(run.labels)},
            mode_index=np.concatenate(idx) if idx else np.zeros(0, dtype=int),
            modes=tuple(self.modes), events=tuple(events))
