"""The options of a switched simulation, checked at the door (private).

Every option of :func:`bondgraph.hybrid.simulate` is checked here before any
work starts, and an input function's value is checked at every call: a
:class:`~bondgraph.hybrid.HybridError` names the argument and what was expected.

Examples
--------
>>> opts = check_options((0, 1), t_eval=None, method="RK45", rtol=1e-9, atol=1e-12, max_step=None,
...                      guard_tol=1e-9, max_events=10, time_budget=None, chatter_count=20,
...                      chatter_time=None)
>>> opts.t0, opts.t1, opts.max_step
(0.0, 1.0, inf)
>>> check_options((0, 1, 2), t_eval=None, method="RK45", rtol=1e-9, atol=1e-12, max_step=None,
...               guard_tol=1e-9, max_events=10, time_budget=None, chatter_count=20,
...               chatter_time=None)
Traceback (most recent call last):
...
bondgraph.hybrid.errors.HybridError: t_span must be two numbers (t0, t1); got (0, 1, 2)
"""

from __future__ import annotations

import math
import numbers
import time
from dataclasses import dataclass
from typing import Any, Callable, Optional

import numpy as np
import sympy

from .errors import EventBudgetError, HybridError

__all__ = ["Options", "check_options", "number", "checked_input", "Clock", "METHODS"]

#: the integrators of :func:`scipy.integrate.solve_ivp` a switched simulation accepts
METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")


@dataclass(frozen=True)
class Options:
    """The checked options of one switched simulation."""

    t0: float
    t1: float
    t_eval: Optional[np.ndarray]
    method: str
    rtol: float
    atol: float
    max_step: float
    guard_tol: float
    max_events: int
    time_budget: Optional[float]
    chatter_count: int
    #: None: ``1e-6*(t1 - t0)``, and below a thousandth of every gate's period
    chatter_time: Optional[float]


def number(value: Any, what: str, *, low: Optional[float] = None, strict: bool = False,
           allow_inf: bool = False) -> float:
    """``value`` as a real float (finite unless ``allow_inf``), at least ``low`` (above it if
    ``strict``), or a :class:`HybridError` naming ``what``."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, sympy.Basic) and value.is_number and value.is_extended_real:
        value = float(value)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise HybridError(f"{what} must be a real number; got {type(value).__name__} {value!r}")
    out = float(value)
    if math.isnan(out) or (math.isinf(out) and not allow_inf):
        raise HybridError(f"{what} must be a finite number; got {value!r}")
    if low is not None and (out < low or (strict and out == low)):
        raise HybridError(f"{what} must be {'>' if strict else '>='} {low:g}; got {value!r}")
    return out


def _integer(value: Any, what: str, low: int) -> int:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise HybridError(f"{what} must be an integer >= {low}; got {type(value).__name__} {value!r}")
    if value < low:
        raise HybridError(f"{what} must be an integer >= {low}; got {value!r}")
    return int(value)


def check_options(t_span, *, t_eval, method, rtol, atol, max_step, guard_tol, max_events,
                  time_budget, chatter_count, chatter_time) -> Options:
    """Every option of :func:`bondgraph.hybrid.simulate` checked (see the module docstring)."""
    if isinstance(t_span, (str, bytes)) or not hasattr(t_span, "__len__") or len(t_span) != 2:
        raise HybridError(f"t_span must be two numbers (t0, t1); got {t_span!r}")
    t0, t1 = (number(v, "t_span") for v in t_span)
    if not t1 > t0:
        raise HybridError(f"t_span must be increasing (t0 < t1); got {tuple(t_span)!r}")
    evals = None
    if t_eval is not None:
        try:
            evals = np.asarray(t_eval, dtype=float)
        except (TypeError, ValueError):
            raise HybridError(f"t_eval must be a sequence of times; got {t_eval!r}") from None
        if evals.ndim != 1 or not np.all(np.isfinite(evals)):
            raise HybridError("t_eval must be a one-dimensional sequence of finite times")
        if evals.size and (evals[0] < t0 or evals[-1] > t1 or np.any(np.diff(evals) < 0)):
            raise HybridError(f"t_eval must be increasing and within t_span ({t0:g}, {t1:g})")
    if not isinstance(method, str) or method not in METHODS:
        raise HybridError(f"method must be one of {', '.join(METHODS)}; got {method!r}")
    rtol_ = number(rtol, "rtol", low=0.0, strict=True)
    atol_ = number(atol, "atol", low=0.0, strict=True)
    step = math.inf if max_step is None else number(max_step, "max_step", low=0.0, strict=True,
                                                     allow_inf=True)
    tol = number(guard_tol, "guard_tol", low=0.0)
    budget = None if time_budget is None else number(time_budget, "time_budget", low=0.0, strict=True)
    span = None if chatter_time is None else number(chatter_time, "chatter_time", low=0.0)
    return Options(t0, t1, evals, method, rtol_, atol_, step, tol, _integer(max_events, "max_events", 0),
                   budget, _integer(chatter_count, "chatter_count", 1), span)


def checked_input(name: str, fn: Callable) -> Callable[[float], float]:
    """Input function ``fn`` whose every value is checked to be a finite real number."""

    def value(t: float) -> float:
        v = fn(t)
        if type(v) is float or type(v) is int:
            if math.isfinite(v):
                return v
        elif not isinstance(v, (str, bytes, bool, np.bool_)) and isinstance(v, numbers.Real):
            v = float(v)
            if math.isfinite(v):
                return v
        elif isinstance(v, np.ndarray) and v.shape in ((), (1,)) and np.isrealobj(v):
            v = float(v.reshape(-1)[0])
            if math.isfinite(v):
                return v
        raise HybridError(f"input {name!r} at t = {t:.9g} must be a finite real number; its "
                          f"function returned {type(v).__name__} {v!r}")
    return value


class Clock:
    """The wall-time budget of a run, checked inside integration and scanning."""

    def __init__(self, budget: Optional[float], name: str) -> None:
        self.budget = budget
        self.name = name
        self.start = time.monotonic()

    def check(self, t: float, partial: Callable[[], Any]) -> None:
        if self.budget is not None and time.monotonic() - self.start > self.budget:
            raise EventBudgetError(f"model {self.name!r}: time budget of {self.budget:g} s used up "
                                   f"at t = {t:.6g}", result=partial())
