"""The arguments of :func:`~bondgraph.numeric.simulate.simulate`, checked and shaped.

Every value a user passes (times, tolerances, the initial state, the inputs
in any of their forms) is checked here and refused with a
:class:`~bondgraph.numeric.errors.NumericError` naming the argument, the
state or input, and what was expected.
"""

from __future__ import annotations

import math
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np
import sympy

from ._compile import real_array
from .errors import NumericError, SimulationError

__all__ = ["METHODS", "InputSpec", "floats", "scalar", "vector", "time_span", "eval_times", "solver",
           "tolerances", "step_limit", "input_function", "initial_state", "short",
           "by_name", "named_inputs"]

#: ``u`` for :func:`~bondgraph.numeric.simulate.simulate`: None, constants, a mapping of input
#: names to numbers or functions of t, a callable of t, or ``(t_samples, u_samples)``
InputSpec = Union[None, float, Sequence[float], np.ndarray, Callable[[float], Any],
                  Mapping[str, Any], tuple[np.ndarray, np.ndarray]]

#: the ``method`` names :func:`scipy.integrate.solve_ivp` accepts
METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")


def short(value: Any) -> str:
    """``value`` for a message: numbers with ``%g``, anything else by a short repr."""
    if isinstance(value, (float, np.floating)) or (isinstance(value, (int, np.integer))
                                                   and not isinstance(value, bool)):
        return f"{value:g}"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def floats(value: Any, what: str, expected: str) -> np.ndarray:
    """:func:`~._compile.real_array`, or :class:`NumericError` naming ``what`` and ``expected``."""
    try:
        return real_array(value)
    except (TypeError, ValueError, OverflowError):
        raise NumericError(f"{what} must be {expected}; got {short(value)}") from None


def scalar(value: Any, what: str, expected: str) -> float:
    arr = floats(value, what, expected)
    if arr.shape != ():
        raise NumericError(f"{what} must be {expected}; got an array of shape {arr.shape}")
    return float(arr)


def nonfinite(arr: np.ndarray) -> int:
    """Index of the first non-finite entry of a 1-D array, or -1."""
    bad = np.flatnonzero(~np.isfinite(arr))
    return int(bad[0]) if bad.size else -1


def vector(value: Any, what: str, names: tuple[str, ...], kind: str, when: str = "") -> np.ndarray:
    """``value`` as finite floats of shape ``(len(names),)``, one per ``kind`` (a number if one).

    ``when`` (``" (at t = 0.5)"``) ends each message.
    """
    n, listed = len(names), ", ".join(names) or "(none)"
    arr = floats(value, what, f"{n} finite number(s), one per {kind} {listed}{when}")
    if arr.shape == () and n == 1:
        arr = arr.reshape(1)
    if arr.shape != (n,):
        raise NumericError(f"{what} must have shape ({n},) for the {kind}s {listed}; "
                           f"got shape {arr.shape}{when}")
    k = nonfinite(arr)
    if k >= 0:
        raise NumericError(f"{what} must be finite; {kind} {names[k]} is {arr[k]:g}{when}")
    return arr


def time_span(t_span: Any) -> tuple[float, float]:
    """``(t0, t1)``: two finite numbers with ``t0 < t1``."""
    expected = "two finite numbers (t0, t1) with t0 < t1"
    if isinstance(t_span, Mapping):
        raise NumericError(f"t_span must be {expected}; got a {type(t_span).__name__}")
    arr = floats(t_span, "t_span", expected)
    if arr.shape != (2,):
        raise NumericError(f"t_span must be {expected}; got {arr.size} value(s), shape {arr.shape}")
    t0, t1 = float(arr[0]), float(arr[1])
    if not (math.isfinite(t0) and math.isfinite(t1)):
        raise NumericError(f"t_span must be {expected}; got ({t0:g}, {t1:g}), which is not finite")
    if not t0 < t1:
        raise NumericError(f"t_span must be {expected} (simulate integrates forward in time); "
                           f"got ({t0:g}, {t1:g})")
    return t0, t1


#: the largest result a simulation may build: times x (states + outputs + inputs + 1)
#: doubles, counted twice for the solver's own copy (a budget: 1 GiB)
MAX_RESULT_BYTES = 2**30


def eval_times(t_eval: Any, t0: float, t1: float, width: int = 1) -> Optional[np.ndarray]:
    """``t_eval`` checked: finite, strictly increasing, within ``[t0, t1]``, and its
    result (``width`` numbers per time) within :data:`MAX_RESULT_BYTES`."""
    if t_eval is None:
        return None
    expected = f"an increasing sequence of finite times within t_span ({t0:g}, {t1:g})"
    size = getattr(t_eval, "size", None) if isinstance(t_eval, np.ndarray) else (
        len(t_eval) if hasattr(t_eval, "__len__") else None)
    if size is not None and 16 * size * (width + 1) > MAX_RESULT_BYTES:
        raise NumericError(
            f"t_eval has {size:,} times: the result ({width} values per time) would need "
            f"{16 * size * (width + 1) / 2**30:.1f} GiB, more than the "
            f"{MAX_RESULT_BYTES / 2**30:.0f} GiB budget (bondgraph.numeric.arguments."
            "MAX_RESULT_BYTES); simulate in pieces (each run's last state is the next x0) or "
            "ask for fewer times")
    arr = floats(t_eval, "t_eval", expected)
    if arr.ndim == 0:
        arr = arr.reshape(1)
    if arr.ndim != 1 or arr.size == 0:
        raise NumericError(f"t_eval must be {expected}; got shape {arr.shape}")
    k = nonfinite(arr)
    if k >= 0:
        raise NumericError(f"t_eval must be {expected}; t_eval[{k}] is {arr[k]:g}")
    outside = np.flatnonzero((arr < t0) | (arr > t1))
    if outside.size:
        k = int(outside[0])
        raise NumericError(f"t_eval must be {expected}; t_eval[{k}] = {float(arr[k])!r} is outside "
                           f"({outside.size} of the {arr.size} times are)")
    steps = np.flatnonzero(np.diff(arr) <= 0)
    if steps.size:
        k = int(steps[0])
        raise NumericError(f"t_eval must be {expected} (sorted, no repeats); t_eval[{k + 1}] = "
                           f"{arr[k + 1]:g} follows t_eval[{k}] = {arr[k]:g}")
    return arr


def solver(method: Any) -> Any:
    """A ``solve_ivp`` method name from :data:`METHODS`, or an ``OdeSolver`` subclass."""
    from scipy.integrate import OdeSolver

    if isinstance(method, type) and issubclass(method, OdeSolver):
        return method
    if isinstance(method, str) and method in METHODS:
        return method
    hint = ""
    if isinstance(method, str):
        close = [m for m in METHODS if m.lower() == method.lower()]
        hint = f" (did you mean {close[0]!r}?)" if close else ""
    raise NumericError(f"method must be one of {', '.join(METHODS)}, or a scipy.integrate.OdeSolver "
                       f"subclass; got {short(method)}{hint}")


def tolerances(rtol: Any, atol: Any, n: int) -> tuple[float, Union[float, np.ndarray]]:
    """``rtol`` in (0, 1); ``atol`` > 0, a number or one per state; all finite.

    ``atol = 0`` is refused: a state that stays at 0 then has an error scale
    of 0, and scipy's step-size control loops forever (RK45) or fails.
    """
    r = scalar(rtol, "rtol", "a finite number with 0 < rtol < 1")
    if not (math.isfinite(r) and 0.0 < r < 1.0):
        raise NumericError(f"rtol must be a finite number with 0 < rtol < 1; got {r:g}")
    expected = f"a finite number > 0, or {n} of them (one per state)"
    a = floats(atol, "atol", expected)
    if a.shape not in ((), (n,)):
        raise NumericError(f"atol must be {expected}; got shape {a.shape}")
    if not (np.all(np.isfinite(a)) and np.all(a > 0)):
        raise NumericError(f"atol must be {expected}; got {short(atol)}")
    return r, (float(a) if a.shape == () else a)


def step_limit(max_step: Any, spacing: Optional[float]) -> float:
    """``max_step`` > 0 (``inf`` allowed); None: the input sample spacing, or ``inf``."""
    if max_step is None:
        return spacing if spacing is not None else np.inf
    value = scalar(max_step, "max_step", "a number > 0 (or None)")
    if not value > 0:
        raise NumericError(f"max_step must be a number > 0 (or None); got {value:g}")
    return value


def input_function(u: InputSpec, m: int, names: tuple[str, ...]) -> tuple[Callable, Optional[float]]:
    """(t -> u(t) of shape (m,), smallest sample spacing or None).

    Every input value is checked: shape ``(m,)`` and finite.  A callable
    ``u`` that raises is reported as :class:`SimulationError` with the time.
    """
    listed = ", ".join(names) or "(none)"

    def shaped(value: Any, what: str, when: str = "") -> np.ndarray:
        return vector(value, what, names, "input", when)

    if u is None:
        zero = np.zeros(m)
        return (lambda t: zero), None
    if isinstance(u, Mapping):
        return named_inputs(u, names, shaped), None
    if callable(u):
        def call(t: float) -> np.ndarray:
            try:
                value = u(t)
            except Exception as exc:
                raise SimulationError(f"the input function u(t) raised {type(exc).__name__} at "
                                      f"t = {t:g}: {exc}") from exc
            return shaped(value, "u(t)", f" (at t = {t:g})")
        return call, None
    if isinstance(u, tuple) and len(u) == 2 and np.ndim(u[0]) == 1:
        ts = floats(u[0], "input sample times", "a sequence of finite times")
        us = floats(u[1], "input samples", f"finite numbers, one column per input {listed}")
        if us.ndim == 1 and m == 1:
            us = us[:, None]
        if ts.size < 2 or not np.all(np.isfinite(ts)) or not np.all(np.diff(ts) > 0):
            raise NumericError("input sample times must be finite, strictly increasing, at least two")
        if us.shape != (ts.size, m):
            raise NumericError(
                f"input samples must have shape ({ts.size}, {m}) for the inputs {listed}; "
                f"got shape {us.shape}")
        if not np.all(np.isfinite(us)):
            row, col = np.argwhere(~np.isfinite(us))[0]
            raise NumericError(f"input samples must be finite; input {names[col]} is "
                               f"{us[row, col]:g} at t = {ts[row]:g}")
        cols = [us[:, j].copy() for j in range(m)]

        def interp(t: float) -> np.ndarray:
            return np.array([np.interp(t, ts, c) for c in cols])
        return interp, float(np.min(np.diff(ts)))
    const = shaped(u, "constant input u")
    return (lambda t: const), None


def by_name(values: Mapping, names: tuple[str, ...], what: str, kind: str) -> dict:
    """``values`` keyed by name (str or Symbol), every key one of ``names``."""
    keys = [k.name if isinstance(k, sympy.Symbol) else k for k in values]
    unknown = sorted(str(k) for k in keys if k not in names)
    if unknown:
        raise NumericError(f"{what} names unknown {kind}s {', '.join(unknown)}; "
                           f"the {kind}s are {', '.join(names) or '(none)'}")
    if len(set(keys)) != len(keys):
        raise NumericError(f"{what} gives a {kind} twice (as a name and as a Symbol)")
    return dict(zip(keys, values.values()))


def named_inputs(u: Mapping, names: tuple[str, ...], shaped: Callable) -> Callable:
    """``{name: number or callable of t}`` as ``t -> u(t)`` (inputs not named are 0)."""
    given = by_name(u, names, "u", "input")
    parts = [given.get(n, 0.0) for n in names]
    for n, part in zip(names, parts):
        if not callable(part):
            scalar(part, f"u[{n!r}]", "a finite number or a function of time")

    def call(t: float) -> np.ndarray:
        values = []
        for n, part in zip(names, parts):
            if callable(part):
                try:
                    values.append(part(t))
                except Exception as exc:
                    raise SimulationError(f"the input function u[{n!r}] raised "
                                          f"{type(exc).__name__} at t = {t:g}: {exc}") from exc
            else:
                values.append(part)
        return shaped(values, "u(t)", f" (at t = {t:g})")
    return call


def initial_state(x0: Any, names: tuple[str, ...]) -> np.ndarray:
    """``x0`` as a finite array in the order of ``names`` (by name: the rest start at 0)."""
    if x0 is None:
        return np.zeros(len(names))
    if isinstance(x0, Mapping):
        given = by_name(x0, names, "x0", "state")
        x0 = [scalar(given.get(s, 0.0), f"x0[{s!r}]", "a finite number") for s in names]
    return vector(x0, "x0", names, "state")
