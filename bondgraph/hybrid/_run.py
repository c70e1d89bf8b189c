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

_NO_INPUTS = np.zeros(0)
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
        qs, H = sm.energy()      # a storage parameter in no mode's equations (a mass held still)
        guard_syms += [s for s in H.free_symbols if s not in qs]
        for s in sorted(guard_syms, key=str):
            params.setdefault(s.name, s)
        known = tuple(m.known_parameters for m in fulls)
        given = match_values(tuple(params.values()), values, known=tuple(itertools.chain(*known)),
                             where=f"model {sm.name!r}: ")
        num = {p.name: real_value(v, p.name) for p, v in given.items()}
        self.values = num
        # sympy numbers, so that an expression that is one parameter stays a sympy expression
        self.subs = {p: sympy.Float(num[p.name]) for p in params.values() if p.name in num}
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
        # compiled modes are kept on the model for the same numbers (a second run compiles nothing)
        key = (tuple(sorted((p.name, float(v)) for p, v in self.subs.items())), self.input_syms)
        store = sm.__dict__.setdefault("_numeric", {})
        if key not in store:
            if len(store) > 8:
                store.clear()
            store[key] = ({}, EnergyMetric(sm, self.subs), {})
        self._compiled, self.metric, self._falls = store[key]
        self._cands: dict = {}
        # names of the stored quantities: the state name where the element is integral
        labels = [str(s) for s in sm.energy_signals]
        for m in fulls:
            for k in range(len(labels)):
                ex = m.output_exprs[m.output_names.index(f"hyb_E{k}")]
                if ex in m.states[: m.storage_states]:
                    labels[k] = ex.name
        self.labels = tuple(labels)
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
        if not self._u:
            return _NO_INPUTS
        return np.array([f(t) for f in self._u], dtype=float)

    def compiled(self, mode: Mode) -> Optional[CompiledMode]:
        """The compiled mode, None for an inconsistent combination of switch states."""
        try:
            return self._compiled[mode]
        except KeyError:
            pass
        try:
            mm = self.sm.derived(mode)
        except ModeError:
            self._compiled[mode] = None
            return None
        cm = self._compiled[mode] = CompiledMode(self.sm, mm, self.subs, self.input_syms, self.periods)
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

    def _time_event(self, cm: CompiledMode, t: float) -> Optional[tuple]:
        """The next fall of the periodic guards of ``cm`` after ``t``, moved to the first
        instant at which they are negative (a fall shifted by whole periods lands a few
        roundings before a jump)."""
        hit = next_time_event(self.falls(cm, t), t, self.opts.t1)
        if hit is None:
            return None
        tp, names = hit
        step = math.ulp(tp)
        for _ in range(60):
            if all(float(cm.time_guards[n](tp)) < 0 for n in names):
                break
            tp += step
            step *= 2
        return (tp, names) if tp < self.opts.t1 else None

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
        watch = tuple(dict.fromkeys(tuple(check) + tuple(trigger or ())))
        for k, mode in self._candidates(proposed, free):
            if cands and min(c[0] for c in cands)[:2] == (False, False) and k > min(
                    c[0] for c in cands)[3]:
                break       # a candidate that holds without a jump, with fewer flips: the best
            cm = self.compiled(mode)
            if cm is None:
                continue
            x, q_new, loss = cm.enter(t, q_old, integ, u, self.metric, self.sm)
            q_ref = q_old
            if given:
                x, q_new, q_ref, why = self._honour(cm, t, x, u, q_old, given)
                if why:
                    tried.append((mode, why))
                    continue
                loss = self.metric.energy(q_ref) - self.metric.energy(q_new)
            g = cm.guard_array(t, x, u)
            idx = cm.index_of(watch)
            bad = [n for n, j in idx if n in check and not g[j] >= -self.guard_tol]
            if bad:
                tried.append((mode, f"violates the guard of {', '.join(bad)}"))
                continue
            near = [n for n, j in idx if g[j] <= self.guard_tol]
            leaving = self._leaving(cm, t, x, u, near) if near else ()
            jumped = self._jumped(q_ref, q_new)
            # a jump that cannot be avoided: the smallest in the energy metric (the projection
            # of the state before onto what the mode allows), then the fewest flips
            size = 0.0
            if jumped:
                d = q_new - q_ref
                size = float(d @ self.metric.hessian(q_ref) @ d)
            cands.append(((bool(leaving), jumped, size, k, abs(loss)), mode, cm, x, q_new, loss,
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

    def _leaving(self, cm: CompiledMode, t, x, u, near) -> tuple:
        """The guards among ``near`` (at zero within ``guard_tol``) that fall below zero at
        the next instant (their first nonzero time derivative negative)."""
        u_dot = self.u_rate(t) if len(u) else u
        rel = max(1e-10, 100 * self.opts.rtol)
        return tuple(n for n in near if cm.trend(n, t, x, u, u_dot, rel) < 0)

    def _candidates(self, proposed: Mode, free: tuple) -> list:
        """``(flips, mode)`` for every subset of ``free`` flipped in ``proposed`` (cached)."""
        key = (proposed, free)
        out = self._cands.get(key)
        if out is None:
            out = self._cands[key] = [(k, proposed.flipped(*flip)) for k in range(len(free) + 1)
                                      for flip in itertools.combinations(free, k)]
        return out

    def u_rate(self, t: float) -> np.ndarray:
        """The inputs' rates at ``t`` (a one-sided difference forward: the next instant)."""
        h = 1e-7 * max(1.0, abs(t))
        return (self.u(t + h) - self.u(t)) / h

    def _jumped(self, q_old, q_new) -> bool:
        """Whether a stored quantity moved beyond ten times the solver's tolerance on it."""
        atol, rtol = self.opts.atol, self.opts.rtol
        for a, b in zip(q_old.tolist(), q_new.tolist()):
            if abs(b - a) > 10 * (atol + rtol * max(abs(a), abs(b))):
                return True
        return False

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
        t = o.t0
        armed: dict[str, bool] = {}
        level: dict[str, float] = {}
        steps: dict = {}
        wheres: dict = {}
        same_t, same_n = None, 0
        while True:
            check_clock(t)
            where = wheres.get(mode)
            if where is None:
                where = wheres[mode] = f"model {sm.name!r}, mode ({mode})"
            seg = integrate(cm, t, x, o.t1, u=self.u, method=o.method, rtol=o.rtol, atol=o.atol,
                            max_step=o.max_step, guard_tol=o.guard_tol, armed=armed,
                            arm_level=level, time_event=self._time_event(cm, t),
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
        sizes = [t.size for _, t, _ in self.chunks]
        total = sum(sizes)
        t_all = np.concatenate([t for _, t, _ in self.chunks]) if self.chunks else np.zeros(0)
        out = np.zeros((len(names), total))
        q = np.zeros((len(run.labels), total))
        idx = np.zeros(total, dtype=int)
        groups: dict = {}
        pos = 0
        for (cm, t, xs), size in zip(self.chunks, sizes):
            idx[pos:pos + size] = self._index(cm)
            groups.setdefault(id(cm), (cm, []))[1].append((pos, t, xs))
            pos += size
        for cm, parts in groups.values():
            sel = np.concatenate([np.arange(p, p + t.size) for p, t, _ in parts])
            tt = np.concatenate([t for _, t, _ in parts])
            xx = np.hstack([xs for _, _, xs in parts])
            us = np.array([[f(float(s)) for s in tt] for f in run._u]).reshape(len(run._u), tt.size)
            out[:, sel] = _many(cm._outs, tt, xx, us)
            q[:, sel] = _many(cm._q, tt, xx, us)
        return SwitchedResult(
            t=t_all, outputs={n: out[j] for j, n in enumerate(names)},
            stored={lab: q[j] for j, lab in enumerate(run.labels)},
            mode_index=idx, modes=tuple(self.modes), events=tuple(events))
