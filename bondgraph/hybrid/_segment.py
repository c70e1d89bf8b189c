"""One mode integrated to its first event: step by step, every guard located on the dense output.

:func:`integrate` advances one mode with a :mod:`scipy.integrate` solver,
one accepted step at a time, and after every step looks at every guard on the
step's dense output (its ends and interior points, both signs): the first
fall of a guard is located by :func:`scipy.optimize.brentq` on the dense
output, whatever the step.  Guards that read time or inputs (a diode's
guard behind a sinusoidal source while the capacitor's state rests) are also
integrated as extra components of the state, ``z' = g``, reset after every
step, so the solver's own error control keeps the step short enough to
resolve them, as if they drove a state.  A guard of time only with a period
(a PWM gate) gives exact time events from its falls over one period, found
once and shifted by whole periods; a constant guard never falls.  Nothing
is scanned beyond the current step, so the cost of an event does not grow
with the horizon.

A guard is *armed* while it has been above zero since the segment started
(or above ``guard_tol`` after an event that left the mode unchanged): armed,
it fires when it falls below zero; not armed (entered at zero), below
``-guard_tol``.
"""

from __future__ import annotations

import math
from typing import Callable, Optional

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK23, RK45, Radau
from scipy.optimize import brentq

from ._numeric import CompiledMode
from .errors import HybridError

__all__ = ["integrate", "periodic_falls", "Segment"]

_SOLVERS = {"RK45": RK45, "RK23": RK23, "DOP853": DOP853, "Radau": Radau, "BDF": BDF, "LSODA": LSODA}
_RESETTABLE = ("RK45", "RK23", "DOP853")
#: interior points of a step at which every guard is evaluated on the dense output
_INTERIOR = 4
_FRACTIONS = np.linspace(0.0, 1.0, _INTERIOR + 2)[1:]


class Segment:
    """What :func:`integrate` returns: the event (``fired`` empty at the end of the span)."""

    __slots__ = ("t", "x", "fired", "last_step")

    def __init__(self, t: float, x: np.ndarray, fired: tuple, last_step: float) -> None:
        self.t, self.x, self.fired, self.last_step = t, x, fired, last_step


def periodic_falls(g: Callable, period: float, t_ref: float) -> np.ndarray:
    """The instants in ``[t_ref, t_ref + period)`` at which a periodic guard of time falls
    from >= 0 below zero (scanned at ``period/2000`` and refined by brentq)."""
    ts = t_ref + period * np.linspace(0.0, 1.0, 2001)
    v = np.broadcast_to(np.asarray(g(ts), dtype=float), ts.shape)
    if not np.all(np.isfinite(v)):
        k = int(np.nonzero(~np.isfinite(v))[0][0])
        raise HybridError(f"a periodic gate is {v[k]} at t = {ts[k]:.9g}")
    out = []
    for i in np.nonzero((v[:-1] >= 0) & (v[1:] < 0))[0]:
        lo, hi = float(ts[i]), float(ts[i + 1])
        out.append(_first_negative(lambda s: float(g(s)), lo, hi))
    return np.array([c for c in out if c < t_ref + period])


def _first_negative(h: Callable[[float], float], lo: float, hi: float) -> float:
    """Where ``h`` (>= 0 at ``lo``, < 0 at ``hi``) falls below zero: the first negative
    point of the bracket, to the rounding of the time."""
    xtol = 4e-16 * max(1.0, abs(hi))
    try:
        r = brentq(h, lo, hi, xtol=xtol, rtol=8.9e-16)
    except ValueError:      # h(lo) is 0 exactly and brentq accepts it
        r = lo
    # the event is where the guard is negative: the negative side of the root, by bisection
    # between the root (not negative: rounding) and hi (negative)
    if h(r) < 0:
        return r
    lo2, hi2 = r, hi
    for _ in range(200):
        if hi2 - lo2 <= xtol:
            break
        mid = 0.5 * (lo2 + hi2)
        if h(mid) < 0:
            hi2 = mid
        else:
            lo2 = mid
    return hi2


def integrate(cm: CompiledMode, t: float, x: np.ndarray, t_end: float, *, u: Callable,
              method: str, rtol: float, atol: float, max_step: float, guard_tol: float,
              armed: dict, arm_level: dict, time_event: Optional[tuple], first_step: Optional[float],
              record: Callable, evals: Optional[np.ndarray], clock: Callable, where: str) -> Segment:
    """Integrate mode ``cm`` from ``(t, x)`` to its first event or ``t_end``.

    ``armed``/``arm_level``: each guard's state (see the module docstring),
    updated in place; ``time_event``: ``(t_p, names)``, the next fall of the
    periodic guards; ``record(ts, ys)`` receives the samples (the solver's
    steps, or the ``evals`` within the segment); ``clock(t)`` checks the time
    budget.  Guards that are NaN raise a :class:`HybridError` naming the
    switch and the time.
    """
    n = len(cm.states)
    names = cm.guard_names
    watch = [k for k, nm in enumerate(names) if nm not in cm.periodic and nm not in cm.constant_guards]
    n_x = len(cm.explicit_guards)
    t_stop, timed = (t_end, ()) if time_event is None or time_event[0] >= t_end else time_event
    if not watch and n == 0 and n_x == 0 or t_stop <= t:
        _record_static(cm, t, t_stop, x, record, evals)
        return Segment(t_stop, np.asarray(x, dtype=float), tuple(timed) if t_stop < t_end else (), 0.0)
    if n_x == 0 and cm.affine_flow is not None:
        return _integrate_exact(cm, cm.affine_flow, t, np.asarray(x, dtype=float), t_stop,
                                tuple(timed) if t_stop < t_end else (), u, watch, armed, arm_level,
                                guard_tol, record, evals, clock, where, max_step)
    y0 = np.concatenate([np.asarray(x, dtype=float), np.zeros(n_x)])
    uc = u

    if n_x:
        def f(tt, y):
            xx = y[:n]
            uu = uc(tt)
            gx = cm.explicit_values(tt, xx, uu)
            if not np.all(np.isfinite(gx)):
                k = int(np.nonzero(~np.isfinite(gx))[0][0])
                raise HybridError(f"{where}: the guard of switch {cm.explicit_guards[k]!r} is "
                                  f"{gx[k]} at t = {tt:.9g}; a guard must be a finite real number")
            return np.concatenate([cm.f(tt, xx, uu), gx])
    else:
        def f(tt, y):
            return cm.f(tt, y, uc(tt))

    kw = {} if first_step is None or not first_step > 0 else {"first_step": min(first_step, t_stop - t)}
    solver = _SOLVERS[method](f, t, y0, t_stop, rtol=rtol, atol=atol, max_step=max_step, **kw)
    reset = n_x and method in _RESETTABLE
    g_prev = _guards(cm, t, y0[:n], uc(t), where)
    for k in watch:
        if not armed.get(names[k], False) and g_prev[k] > arm_level.get(names[k], 0.0):
            armed[names[k]] = True
    while True:
        clock(solver.t)
        msg = solver.step()
        if solver.status == "failed":
            raise HybridError(f"{where}: the integrator failed at t = {solver.t:.6g}: {msg}")
        a, b = solver.t_old, solver.t
        dense = solver.dense_output()
        hit, _ = _locate(cm, dense, a, b, n, g_prev, watch, armed, arm_level, guard_tol, uc, where)
        if hit is not None:
            te, fired = hit
            ye = np.asarray(dense(te), dtype=float)
            _record_dense(cm, dense, a, te, n, record, evals, include_end=False)
            return Segment(te, ye[:n], fired, b - a)
        _record_dense(cm, dense, a, b, n, record, evals, include_end=True)
        if reset:
            solver.y[n:] = 0.0
        g_prev = _guards(cm, b, solver.y[:n], uc(b), where)
        if solver.status == "finished":
            fired = tuple(timed) if t_stop < t_end else ()
            return Segment(t_stop, np.array(solver.y[:n], dtype=float), fired, b - a)


class _Exact:
    """The dense output of an exact affine flow from ``(t0, x0)`` (scipy's calling convention)."""

    def __init__(self, flow, t0: float, x0: np.ndarray) -> None:
        self.flow, self.t0 = flow, t0
        self.c = flow.coefficients(x0)

    def __call__(self, s):
        if np.ndim(s) == 0:
            return self.flow.from_coefficients(np.array([s]), self.t0, self.c)[:, 0]
        return self.flow.from_coefficients(s, self.t0, self.c)


def _integrate_exact(cm, flow, t, x, t_stop, timed, u, watch, armed, arm_level, guard_tol, record,
                     evals, clock, where, max_step=math.inf) -> Segment:
    """:func:`integrate` for a mode with an exact affine flow: guards sampled on the exact
    solution in steps of at most a fifth of the fastest time constant (and ``max_step``)."""
    n = len(x)
    dense = _Exact(flow, t, x)
    names = cm.guard_names
    g_prev = _guards(cm, t, x, u(t), where)
    for k in watch:
        if not armed.get(names[k], False) and g_prev[k] > arm_level.get(names[k], 0.0):
            armed[names[k]] = True
    a = t
    while True:
        clock(a)
        b = min(t_stop, a + min(flow.step, max_step))
        ts = a + (b - a) * _FRACTIONS
        ys = flow.samples(_FRACTIONS, a - t, b - a, dense.c)
        hit, G = _locate(cm, dense, a, b, n, g_prev, watch, armed, arm_level, guard_tol, u, where,
                         samples=(ts, ys))
        if hit is not None:
            te, fired = hit
            if evals is None:
                keep = ts < te
                if keep.any():
                    record(ts[keep], ys[:, keep])
            else:
                _record_dense(cm, dense, a, te, n, record, evals, include_end=False)
            return Segment(te, dense(te), fired, 0.0)
        if evals is None:
            record(ts, ys)      # no solver steps to sample at: the guards' sample points
        else:
            _record_dense(cm, dense, a, b, n, record, evals, include_end=True)
        if b >= t_stop:
            return Segment(t_stop, ys[:, -1].copy(), timed, 0.0)
        g_prev = G[:, -1] if G is not None else _guards(cm, b, ys[:, -1], u(b), where)
        a = b


def _guards(cm: CompiledMode, t: float, x, u, where: str) -> np.ndarray:
    g = cm.guard_array(t, x, u)
    if not np.all(np.isfinite(g)):
        k = int(np.nonzero(~np.isfinite(g))[0][0])
        raise HybridError(f"{where}: the guard of switch {cm.guard_names[k]!r} is {g[k]} at "
                          f"t = {t:.9g}; a guard must be a finite real number")
    return g


def _locate(cm, dense, a, b, n, g_prev, watch, armed, arm_level, tol, u, where, samples=None):
    """The first guard fall in ``(a, b]`` on the dense output: ``((te, names) or None, G)``,
    ``G`` the guards at the sample points (None when nothing is watched)."""
    if not watch:
        return None, None
    if samples is None:
        ts = a + (b - a) * _FRACTIONS
        ys = np.asarray(dense(ts), dtype=float)
    else:
        ts, ys = samples
    G = cm.guard_matrix(ts, ys[:n], _inputs(u, ts))
    if not np.all(np.isfinite(G)):
        k, j = (int(v[0]) for v in np.nonzero(~np.isfinite(G)))
        raise HybridError(f"{where}: the guard of switch {cm.guard_names[k]!r} is {G[k, j]} at "
                          f"t = {ts[j]:.9g}; a guard must be a finite real number")
    names = cm.guard_names
    # the common case: every guard stays on its side and none is armed in this step
    quiet = True
    for k in watch:
        nm = names[k]
        row = G[k]
        if armed.get(nm, False):
            if row.min() < 0:
                quiet = False
                break
        elif row.min() < -tol or row.max() > arm_level.get(nm, 0.0):
            quiet = False
            break
    if quiet:
        dip = _dip(cm, dense, a, ts, G, n, g_prev, watch, armed, u, where)
        return (None if dip is None else dip), G
    best = None
    prev_t, prev = a, g_prev
    for j, s in enumerate(ts):
        cur = G[:, j]
        for k in watch:
            nm = names[k]
            level = 0.0 if armed.get(nm, False) else -tol
            if cur[k] < level and prev[k] >= level:
                def h(tt, k=k, level=level):
                    y = np.asarray(dense(tt), dtype=float)[:n]
                    return float(_guards(cm, tt, y, u(tt), where)[k]) - level
                te = _first_negative(h, float(prev_t), float(s))
                if best is None or te < best[0]:
                    best = (te, k)
            elif not armed.get(nm, False) and cur[k] > arm_level.get(nm, 0.0):
                armed[nm] = True
        if best is not None:
            break
        prev_t, prev = s, cur
    if best is None:
        return None, G
    te = best[0]
    y = np.asarray(dense(te), dtype=float)[:n]
    g = _guards(cm, te, y, u(te), where)
    fired = tuple(names[k] for k in watch
                  if g[k] < (0.0 if armed.get(names[k], False) else -tol) or k == best[1])
    return (te, fired), G


def _dip(cm, dense, a, ts, G, n, g_prev, watch, armed, u, where):
    """A fall below zero between two samples of an armed guard that comes back above zero
    before the next sample: looked for at each sampled local minimum that is nearer zero than
    the guard's change around it (the minimum found on the dense output by a bounded search)."""
    from scipy.optimize import minimize_scalar

    t_all = np.concatenate([[a], ts])
    for k in watch:
        if not armed.get(cm.guard_names[k], False):
            continue
        seq = np.concatenate([[g_prev[k]], G[k]])
        for j in range(1, len(seq) - 1):
            lo, mid, hi = seq[j - 1], seq[j], seq[j + 1]
            if not (mid <= lo and mid <= hi and mid < (lo - mid) + (hi - mid)):
                continue

            def h(tt, k=k):
                y = np.asarray(dense(tt), dtype=float)[:n]
                return float(_guards(cm, tt, y, u(tt), where)[k])
            left, right = float(t_all[j - 1]), float(t_all[j + 1])
            found = minimize_scalar(h, bounds=(left, right), method="bounded",
                                    options={"xatol": 1e-12 * max(1.0, abs(right))})
            if found.fun < 0:
                te = _first_negative(h, left, float(found.x))
                y = np.asarray(dense(te), dtype=float)[:n]
                g = _guards(cm, te, y, u(te), where)
                fired = tuple(cm.guard_names[i] for i in watch
                              if armed.get(cm.guard_names[i], False) and g[i] < 0 or i == k)
                return te, fired
    return None


def _inputs(u, ts: np.ndarray) -> np.ndarray:
    """The inputs at the times ``ts``: shape ``(n_inputs, len(ts))``."""
    first = u(float(ts[0]))
    if not len(first):
        return np.zeros((0, ts.size))
    return np.array([u(float(s)) for s in ts]).T


def _record_dense(cm, dense, a, b, n, record, evals, *, include_end: bool) -> None:
    if evals is None:
        if include_end:
            record(np.array([b]), np.asarray(dense(b), dtype=float)[:n].reshape(n, 1))
        return
    sel = evals[(evals > a) & ((evals <= b) if include_end else (evals < b))]
    if sel.size:
        record(sel, np.asarray(dense(sel), dtype=float)[:n].reshape(n, sel.size))


def _record_static(cm, t, t_stop, x, record, evals) -> None:
    """A segment with nothing to integrate: the state stays; outputs may still read time."""
    x = np.asarray(x, dtype=float)
    if evals is None:
        ts = np.array([t_stop])
    else:
        ts = evals[(evals > t) & (evals <= t_stop)]
    if ts.size:
        record(ts, np.repeat(x.reshape(-1, 1), ts.size, axis=1))


def next_time_event(falls: dict, t: float, t_end: float) -> Optional[tuple]:
    """The next fall after ``t`` of the periodic guards: ``(t_p, names)`` or None.

    ``falls`` maps a switch to ``(instants, period)``; an instant within
    ``1e-9`` of a period after ``t`` is the event just handled, not the next.
    """
    best, who = math.inf, []
    for name, (inst, period) in falls.items():
        if not len(inst):
            continue
        cand = min(c + math.ceil((t + 1e-9 * period - c) / period) * period for c in inst)
        if cand < best - 1e-12 * period:
            best, who = cand, [name]
        elif abs(cand - best) <= 1e-12 * period:
            who.append(name)
    if best >= t_end:
        return None
    return best, tuple(who)
