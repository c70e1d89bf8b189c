"""Nonlinear (and linear) models in time: compiled right-hand sides and simulation.

:func:`compile_dynamics` lambdifies ``x' = f(t, x, u, p)`` and
``y = g(t, x, u, p)`` once (numpy, with common-subexpression elimination);
:func:`simulate` integrates with :func:`scipy.integrate.solve_ivp`;
:func:`to_nonlinear_iosys` wraps the same functions as a python-control
``NonlinearIOSystem``.

Examples
--------
>>> import numpy as np, bondgraph as bg
>>> g = bg.BondGraph("rc")
>>> V, n = bg.Se("V"), bg.One("i")
>>> g.add(V, n, bg.R("R"), bg.C("C"))
>>> _ = g.connect(V, n); _ = g.connect(n, "R"); _ = g.connect(n, "C")
>>> model = bg.derive(g, outputs={"vC": bg.effort("C")})
>>> res = simulate(model, {"R": 1.0, "C": 1.0}, (0.0, 1.0), u=[1.0], t_eval=[1.0], rtol=1e-10, atol=1e-12)
>>> print(f"{res['vC'][-1]:.8f} {1 - np.exp(-1):.8f}")      # step response of 1/(s + 1)
0.63212056 0.63212056
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np
import sympy
from sympy.core.function import AppliedUndef

from ..errors import BondGraphError
from ..equations import StateEquations
from ..signals import t as T_SYM
from ._compile import CallbackFailure, CompiledFunction, guard_user_functions, placeholders, real_array
from ._linalg import freeze
from ._field_values import check_fields_at
from ._stiffness import check_stiffness
from .errors import NumericError, SimulationError
from .resolve import ParameterValues, resolve_parameters
from .implicit import with_algebraic
from .plant import _CompiledModel, control_labels

if TYPE_CHECKING:  # imported lazily at run time
    import control

__all__ = ["NumericDynamics", "compile_dynamics", "SimulationResult", "simulate", "METHODS",
           "to_nonlinear_iosys", "InputSpec"]

#: ``u`` for :func:`simulate`: None, constants, a callable of t, or ``(t_samples, u_samples)``
InputSpec = Union[None, float, Sequence[float], np.ndarray, Callable[[float], Any],
                  tuple[np.ndarray, np.ndarray]]


def _short(value: Any) -> str:
    """``value`` for a message: numbers with ``%g``, anything else by a short repr."""
    if isinstance(value, (float, np.floating)) or (isinstance(value, (int, np.integer))
                                                   and not isinstance(value, bool)):
        return f"{value:g}"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _law_owners(model: StateEquations, func: Any) -> str:
    """``"R:Rf: the function sat"``: the elements whose law (or modulus) uses the user function."""
    owners = []
    flat = getattr(model.augmented, "flat", None)        # None in a hand-built Model
    for el in flat.elements if flat is not None else ():
        for fld in fields(el):
            value = getattr(el, fld.name, None)
            if isinstance(value, sympy.Basic) and any(a.func == func for a in value.atoms(AppliedUndef)):
                owners.append(el.label())
                break
    return f"{' and '.join(owners) or 'a law'}: the function {func} in its law"


def _callback_error(fail: CallbackFailure, model: str, t: Any) -> SimulationError:
    """The package error for a user function that failed (at time ``t``, if known)."""
    shown = ", ".join(_short(a) for a in fail.args_given)
    when = f" at t = {_short(t)}" if t is not None else ""
    return SimulationError(f"model {model!r}: {fail.what}{when} (called with {shown})")


class NumericDynamics(_CompiledModel):
    """``f(t, x, u, p)`` and ``g(t, x, u, p)`` of a model compiled to numpy once.

    Works for nonlinear and time-varying models.  ``p`` is the vector of
    parameter values in the order of :attr:`parameter_names` (see
    :meth:`parameter_vector`).

    Parameters
    ----------
    model : StateEquations

    Raises
    ------
    NumericError
        If the equations use time derivatives of inputs.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("duffing")
    >>> F, v = bg.Se("F"), bg.One("v")
    >>> g.add(F, v, bg.I("m"), bg.C("s", law=bg.q**3))
    >>> for a, b in [(F, v), (v, "m"), (v, "s")]: _ = g.connect(a, b)
    >>> dyn = NumericDynamics(bg.derive(g, outputs={"x": bg.displacement("s")}))
    >>> dyn.state_names, dyn.parameter_names
    (('p_m', 'q_s'), ('m',))
    >>> dyn.derivatives(0.0, [1.0, 2.0], [0.5], [4.0])     # [F - q^3, p/m]
    array([-7.5 ,  0.25])
    """

    def __init__(self, model: StateEquations) -> None:
        super().__init__(model)
        if model.input_derivatives:
            raise NumericError(
                f"model {model.name!r}: the equations use time derivatives of inputs "
                f"({', '.join(s.name for s in model.input_derivatives)}); they cannot be simulated "
                "from input values alone -- drive that storage element through a compliance or "
                "resistance instead")
        (tt,) = placeholders("t", 1)
        xs = placeholders("x", len(model.states))
        us = placeholders("u", len(model.inputs))
        ps = placeholders("p", len(self._params) + len(model.algebraic))
        swap = {T_SYM: tt, **dict(zip(model.states, xs)), **dict(zip(model.inputs, us)),
                **dict(zip((*self._params, *model.algebraic), ps))}
        args = [tt, xs, us, ps]
        exprs = guard_user_functions((*model.rhs, *model.output_exprs),
                                     lambda func: _law_owners(model, func))
        n = len(model.rhs)
        self._f, self._g = with_algebraic(model, self._params, *(CompiledFunction(args, [
            ex.xreplace(swap) for ex in part]) for part in (exprs[:n], exprs[n:])))  # p + z

    def __repr__(self) -> str:
        return f"NumericDynamics({self._model.name!r}: {len(self.state_names)} states)"

    @property
    def name(self) -> str:
        return self._model.name

    def parameter_vector(self, values: ParameterValues) -> np.ndarray:
        """Checked parameter values in order (see :func:`~bondgraph.numeric.resolve_parameters`)."""
        return resolve_parameters(self._params, values, model=self._model.name,
                                  known=self._model.known_parameters)

    def derivatives(self, t: float, x, u, p) -> np.ndarray:
        """``x'`` at time ``t``, state ``x`` (n,), input ``u`` (m,) and parameters ``p`` (k,).

        Raises
        ------
        SimulationError
            A user function inside a law (``sympy`` ``implemented_function``)
            raised or returned something other than a real number.
        """
        try:
            out = self._f(t, x, u, p)
        except CallbackFailure as fail:
            raise _callback_error(fail, self.name, t) from fail.__cause__
        return np.array(out, dtype=float).reshape(len(self.state_names))

    def outputs(self, t, x, u, p) -> np.ndarray:
        """``y`` (p,); with ``t`` of shape (N,), ``x`` (n, N) and ``u`` (m, N): shape (p, N).

        A user function inside a law that does not take arrays is called one
        sample at a time.

        Raises
        ------
        SimulationError
            A user function inside a law raised or returned something other
            than a real number (the message gives the time).
        """
        size = np.shape(t)
        try:
            values = self._g(t, x, u, p)
        except CallbackFailure as fail:
            if not size:
                raise _callback_error(fail, self.name, t) from fail.__cause__
            tt = np.asarray(t, dtype=float)
            if tt.ndim != 1:
                raise _callback_error(fail, self.name, None) from fail.__cause__
            x, u = np.asarray(x, dtype=float), np.asarray(u, dtype=float)
            values = np.array([self.outputs(tt[k], x[:, k], u[:, k], p) for k in range(tt.size)]).T
        return np.array([np.broadcast_to(np.asarray(v, dtype=float), size) for v in values],
                        dtype=float).reshape((len(self.output_names),) + size)


def compile_dynamics(model: StateEquations) -> NumericDynamics:
    """Compile a model's equations once for simulation; see :class:`NumericDynamics`.

    Parameters
    ----------
    model : StateEquations
        The symbolic model (nonlinear and time-varying models allowed).

    Returns
    -------
    NumericDynamics

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
    >>> dyn = compile_dynamics(bg.derive(g, outputs={"v": bg.flow("m")}))
    >>> dyn.parameter_names, dyn.derivatives(0.0, [0.0], [3.0], [2.0]), dyn.outputs(0.0, [4.0], [0.0], [2.0])
    (('m',), array([3.]), array([2.]))
    """
    return NumericDynamics(model)


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """Time histories from :func:`simulate` (time along the first axis).

    Attributes
    ----------
    t : numpy.ndarray
        Shape ``(N,)``.
    x, y, u : numpy.ndarray
        States ``(N, n)``, outputs ``(N, p)`` and inputs ``(N, m)``.
    state_names, input_names, output_names : tuple of str
    parameters : mapping of str to float
    name : str

    Examples
    --------
    >>> import numpy as np, bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
    >>> model = bg.derive(g, outputs={"v": bg.flow("m")})
    >>> res = bg.simulate(model, {"m": 2.0}, (0.0, 1.0), u=[3.0], t_eval=[0.0, 0.5, 1.0])
    >>> res, res.x.shape, res.output_names
    (SimulationResult('mass': 3 samples, t = 0..1), (3, 1), ('v',))
    >>> np.allclose(res["v"], [0.0, 0.75, 1.5]), np.allclose(res["p_m"], 2.0 * res["v"])
    (True, True)
    """

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    u: np.ndarray
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    parameters: Mapping[str, float] = field(default_factory=dict)
    name: str = ""

    def __repr__(self) -> str:
        return (f"SimulationResult({self.name!r}: {self.t.size} samples, t = {self.t[0]:g}..{self.t[-1]:g})"
                if self.t.size else f"SimulationResult({self.name!r}: no samples)")

    def __reduce__(self):
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        values["parameters"] = dict(self.parameters)      # a mappingproxy does not pickle
        return (_rebuild_result, (values,))

    def __getitem__(self, name: str) -> np.ndarray:
        """The history of the output, state or input called ``name`` (searched in that order)."""
        for names, data in ((self.output_names, self.y), (self.state_names, self.x),
                            (self.input_names, self.u)):
            if name in names:
                return data[:, names.index(name)]
        raise KeyError(f"no output, state or input named {name!r}; outputs: "
                       f"{', '.join(self.output_names) or '-'}; states: {', '.join(self.state_names)}; "
                       f"inputs: {', '.join(self.input_names) or '-'}")


def _rebuild_result(values: dict) -> SimulationResult:
    """An unpickled :class:`SimulationResult`: read-only arrays, read-only parameter mapping."""
    for key in ("t", "x", "y", "u"):
        values[key] = freeze(values[key])
    values["parameters"] = MappingProxyType(dict(values["parameters"]))
    return SimulationResult(**values)


#: the ``method`` names :func:`scipy.integrate.solve_ivp` accepts
METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")


def _floats(value: Any, what: str, expected: str) -> np.ndarray:
    """:func:`~._compile.real_array`, or :class:`NumericError` naming ``what`` and ``expected``."""
    try:
        return real_array(value)
    except (TypeError, ValueError, OverflowError):
        raise NumericError(f"{what} must be {expected}; got {_short(value)}") from None


def _scalar(value: Any, what: str, expected: str) -> float:
    arr = _floats(value, what, expected)
    if arr.shape != ():
        raise NumericError(f"{what} must be {expected}; got an array of shape {arr.shape}")
    return float(arr)


def _nonfinite(arr: np.ndarray) -> int:
    """Index of the first non-finite entry of a 1-D array, or -1."""
    bad = np.flatnonzero(~np.isfinite(arr))
    return int(bad[0]) if bad.size else -1


def _vector(value: Any, what: str, names: tuple[str, ...], kind: str, when: str = "") -> np.ndarray:
    """``value`` as finite floats of shape ``(len(names),)``, one per ``kind`` (a number if one).

    ``when`` (``" (at t = 0.5)"``) ends each message.
    """
    n, listed = len(names), ", ".join(names) or "(none)"
    arr = _floats(value, what, f"{n} finite number(s), one per {kind} {listed}{when}")
    if arr.shape == () and n == 1:
        arr = arr.reshape(1)
    if arr.shape != (n,):
        raise NumericError(f"{what} must have shape ({n},) for the {kind}s {listed}; "
                           f"got shape {arr.shape}{when}")
    k = _nonfinite(arr)
    if k >= 0:
        raise NumericError(f"{what} must be finite; {kind} {names[k]} is {arr[k]:g}{when}")
    return arr


def _time_span(t_span: Any) -> tuple[float, float]:
    """``(t0, t1)``: two finite numbers with ``t0 < t1``."""
    expected = "two finite numbers (t0, t1) with t0 < t1"
    if isinstance(t_span, Mapping):
        raise NumericError(f"t_span must be {expected}; got a {type(t_span).__name__}")
    arr = _floats(t_span, "t_span", expected)
    if arr.shape != (2,):
        raise NumericError(f"t_span must be {expected}; got {arr.size} value(s), shape {arr.shape}")
    t0, t1 = float(arr[0]), float(arr[1])
    if not (math.isfinite(t0) and math.isfinite(t1)):
        raise NumericError(f"t_span must be {expected}; got ({t0:g}, {t1:g}), which is not finite")
    if not t0 < t1:
        raise NumericError(f"t_span must be {expected} (simulate integrates forward in time); "
                           f"got ({t0:g}, {t1:g})")
    return t0, t1


def _eval_times(t_eval: Any, t0: float, t1: float) -> Optional[np.ndarray]:
    """``t_eval`` checked: finite, strictly increasing, within ``[t0, t1]``."""
    if t_eval is None:
        return None
    expected = f"an increasing sequence of finite times within t_span ({t0:g}, {t1:g})"
    arr = _floats(t_eval, "t_eval", expected)
    if arr.ndim == 0:
        arr = arr.reshape(1)
    if arr.ndim != 1 or arr.size == 0:
        raise NumericError(f"t_eval must be {expected}; got shape {arr.shape}")
    k = _nonfinite(arr)
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


def _solver(method: Any) -> Any:
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
                       f"subclass; got {_short(method)}{hint}")


def _tolerances(rtol: Any, atol: Any, n: int) -> tuple[float, Union[float, np.ndarray]]:
    """``rtol`` in (0, 1); ``atol`` > 0, a number or one per state; all finite.

    ``atol = 0`` is refused: a state that stays at 0 then has an error scale
    of 0, and scipy's step-size control loops forever (RK45) or fails.
    """
    r = _scalar(rtol, "rtol", "a finite number with 0 < rtol < 1")
    if not (math.isfinite(r) and 0.0 < r < 1.0):
        raise NumericError(f"rtol must be a finite number with 0 < rtol < 1; got {r:g}")
    expected = f"a finite number > 0, or {n} of them (one per state)"
    a = _floats(atol, "atol", expected)
    if a.shape not in ((), (n,)):
        raise NumericError(f"atol must be {expected}; got shape {a.shape}")
    if not (np.all(np.isfinite(a)) and np.all(a > 0)):
        raise NumericError(f"atol must be {expected}; got {_short(atol)}")
    return r, (float(a) if a.shape == () else a)


def _step_limit(max_step: Any, spacing: Optional[float]) -> float:
    """``max_step`` > 0 (``inf`` allowed); None: the input sample spacing, or ``inf``."""
    if max_step is None:
        return spacing if spacing is not None else np.inf
    value = _scalar(max_step, "max_step", "a number > 0 (or None)")
    if not value > 0:
        raise NumericError(f"max_step must be a number > 0 (or None); got {value:g}")
    return value


def _input_function(u: InputSpec, m: int, names: tuple[str, ...]) -> tuple[Callable, Optional[float]]:
    """(t -> u(t) of shape (m,), smallest sample spacing or None).

    Every input value is checked: shape ``(m,)`` and finite.  A callable
    ``u`` that raises is reported as :class:`SimulationError` with the time.
    """
    listed = ", ".join(names) or "(none)"

    def shaped(value: Any, what: str, when: str = "") -> np.ndarray:
        return _vector(value, what, names, "input", when)

    if u is None:
        zero = np.zeros(m)
        return (lambda t: zero), None
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
        ts = _floats(u[0], "input sample times", "a sequence of finite times")
        us = _floats(u[1], "input samples", f"finite numbers, one column per input {listed}")
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


def _initial_state(x0: Any, names: tuple[str, ...]) -> np.ndarray:
    """``x0`` as a finite array in the order of ``names`` (by name: the rest start at 0)."""
    if x0 is None:
        return np.zeros(len(names))
    if isinstance(x0, Mapping):
        keys = [k.name if isinstance(k, sympy.Symbol) else k for k in x0]
        unknown = sorted(str(k) for k in keys if k not in names)
        if unknown:
            raise NumericError(f"x0 names unknown states {', '.join(unknown)}; "
                               f"the states are {', '.join(names) or '(none)'}")
        if len(set(keys)) != len(keys):
            raise NumericError("x0 gives a state twice (as a name and as a Symbol)")
        given = dict(zip(keys, x0.values()))
        x0 = [_scalar(given.get(s, 0.0), f"x0[{s!r}]", "a finite number") for s in names]
    return _vector(x0, "x0", names, "state")


def _named(names: tuple[str, ...], values: np.ndarray) -> str:
    return ", ".join(f"{s} = {v:g}" for s, v in zip(names, values))


def _checked_derivatives(dyn: NumericDynamics, t: float, x: np.ndarray, u: np.ndarray,
                         p: np.ndarray, context: str) -> np.ndarray:
    """``dyn.derivatives``, refusing a non-finite value at once with :class:`SimulationError`.

    A NaN derivative would make the step-size control of ``solve_ivp`` loop
    forever; the message names the state and the time, and gives the states
    and inputs there.
    """
    dx = dyn.derivatives(t, x, u, p)
    k = _nonfinite(dx)
    if k >= 0:
        others = [dyn.state_names[j] for j in np.flatnonzero(~np.isfinite(dx)) if j != k]
        inputs = f" and inputs {_named(dyn.input_names, u)}" if dyn.input_names else ""
        raise SimulationError(
            f"model {dyn.name!r}: {context}the derivative of state {dyn.state_names[k]} is {dx[k]:g} "
            f"(not finite) at t = {t:g}" + (f" (also of {', '.join(others)})" if others else "")
            + f", with {_named(dyn.state_names, x)}{inputs}; a law is evaluated outside its domain "
            "(log or sqrt of a negative value, division by zero) or the state overflowed")
    return dx


def _check_history(dyn: NumericDynamics, t: np.ndarray, data: np.ndarray, names: tuple[str, ...],
                   what: str) -> None:
    """Refuse a non-finite value in ``data`` (one row per name), naming it and its first time."""
    bad = ~np.isfinite(data)
    if data.size and bad.any():
        row = int(np.flatnonzero(bad.any(axis=1))[0])
        col = int(np.flatnonzero(bad[row])[0])
        raise SimulationError(
            f"model {dyn.name!r}: {what} {names[row]} is {data[row, col]:g} (not finite) at "
            f"t = {t[col]:g} (first of {int(bad[row].sum())} such samples)")


def simulate(model: Union[StateEquations, NumericDynamics], values: ParameterValues,
             t_span: tuple[float, float],
             x0: Union[None, Sequence[float], np.ndarray, Mapping[str, float]] = None,
             *, u: InputSpec = None, t_eval: Optional[Sequence[float]] = None,
             method: Union[str, type] = "RK45", rtol: float = 1e-6,
             atol: Union[float, Sequence[float], np.ndarray] = 1e-9,
             max_step: Optional[float] = None) -> SimulationResult:
    """Integrate a (possibly nonlinear) model with :func:`scipy.integrate.solve_ivp`.

    Every argument is checked before integrating; a derivative, state or
    output that is not finite stops the simulation at once with an error
    naming it and the time (scipy's step-size control would otherwise loop
    forever on a NaN).

    Parameters
    ----------
    model : StateEquations or NumericDynamics
        Pass a :class:`NumericDynamics` to reuse its compiled functions.  A
        switched model (:class:`bondgraph.hybrid.SwitchedModel`) is simulated
        with events by :func:`bondgraph.hybrid.simulate` (``u`` then maps
        input names to numbers or functions of time) and returns its
        :class:`~bondgraph.hybrid.SwitchedResult`.
    values : mapping of Symbol or str to float
        Parameter values: exactly the model's parameters.
    t_span : (float, float)
        Start and end time, finite, with ``t0 < t1``.
    x0 : array_like or mapping of str to float, optional
        Initial state in the order of ``state_names``, or by name (states not
        named start at 0).  Finite.  Default: zeros.
    u : optional
        The inputs: None (all zero); a constant vector of length ``m`` (a
        number if ``m == 1``); a callable ``u(t)`` returning such a vector; or
        a pair ``(t_samples, u_samples)`` with ``u_samples`` of shape
        ``(N, m)`` (or ``(N,)`` if ``m == 1``), linearly interpolated and held
        constant outside the samples.  Values must be finite.
    t_eval : array_like, optional
        Times at which to report: strictly increasing, within ``t_span``;
        default: the solver's steps.
    method : str or scipy.integrate.OdeSolver subclass, optional
        A ``solve_ivp`` method, one of :data:`METHODS`: ``"RK45"``,
        ``"RK23"``, ``"DOP853"``, ``"Radau"``, ``"BDF"``, ``"LSODA"``.
    rtol : float, optional
        Relative tolerance, ``0 < rtol < 1``.
    atol : float or array_like, optional
        Absolute tolerance, ``> 0``: one number, or one per state.
    max_step : float, optional
        Largest step, ``> 0``; with sampled inputs the default is the smallest
        sample spacing, otherwise unbounded.

    Returns
    -------
    SimulationResult

    Raises
    ------
    ParameterValueError
        Bad parameter values.
    NumericError
        A bad argument (``t_span``, ``x0``, ``u``, ``t_eval``, ``method``,
        ``rtol``, ``atol``, ``max_step``); the message names it and says
        what was expected.
    SimulationError
        The solver failed; a derivative, state or output became NaN or
        infinite (the message names it and the time); or a user function
        (``u(t)``, or a Python function inside a law) raised.

    Examples
    --------
    >>> import numpy as np, bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
    >>> model = bg.derive(g, outputs={"v": bg.flow("m")})
    >>> res = simulate(model, {"m": 2.0}, (0.0, 2.0), x0={"p_m": 1.0}, u=lambda t: [1.0],
    ...                t_eval=[2.0])
    >>> np.allclose(res["v"], [1.5])            # v(2) = (p0 + F*t)/m
    True
    >>> simulate(model, {"m": 2.0}, (0.0, float("nan")))
    Traceback (most recent call last):
    ...
    bondgraph.numeric.errors.NumericError: t_span must be two finite numbers (t0, t1) with t0 < t1; got (0, nan), which is not finite
    """
    from scipy.integrate import solve_ivp

    switched = getattr(model, "simulate_with_events", None)
    if switched is not None:       # a switched model (bondgraph.hybrid) runs its own event loop
        return switched(values, t_span, x0, u=u, t_eval=t_eval, method=method, rtol=rtol,
                        atol=atol, max_step=max_step)
    dyn = model if isinstance(model, NumericDynamics) else NumericDynamics(model)
    p = dyn.parameter_vector(values)
    check_fields_at(dyn.model, values, dyn.parameter_names, p.tolist())   # as plant() does
    m = len(dyn.input_names)
    t0, t1 = _time_span(t_span)
    x_init = _initial_state(x0, dyn.state_names)
    ufun, spacing = _input_function(u, m, dyn.input_names)
    times = _eval_times(t_eval, t0, t1)
    solver = _solver(method)
    r_tol, a_tol = _tolerances(rtol, atol, len(dyn.state_names))
    step = _step_limit(max_step, spacing)
    ufun(t0)  # check the input's shape before integrating
    label = solver if isinstance(solver, str) else solver.__name__
    context = f"the {label} solver failed: "

    def rhs(t: float, x: np.ndarray) -> np.ndarray:
        return _checked_derivatives(dyn, t, x, ufun(t), p, context)

    check_stiffness(rhs, t0, t1, np.asarray(x_init, dtype=float), solver, dyn.name)
    try:
        with np.errstate(all="ignore"):
            sol = solve_ivp(rhs, (t0, t1), x_init, method=solver, t_eval=times, rtol=r_tol,
                            atol=a_tol, max_step=step)
    except BondGraphError:
        raise
    except (ValueError, TypeError, ArithmeticError, np.linalg.LinAlgError) as exc:
        raise SimulationError(f"model {dyn.name!r}: the {label} solver failed: scipy raised "
                              f"{type(exc).__name__}: {exc}") from exc
    if sol.status < 0:
        reached = np.asarray(sol.t, dtype=float)     # a list when t_eval was given
        raise SimulationError(f"model {dyn.name!r}: the {label} solver failed at t = "
                              f"{reached[-1] if reached.size else t0:g}: {sol.message}")
    t = np.asarray(sol.t, dtype=float)
    x = np.asarray(sol.y, dtype=float).reshape(len(dyn.state_names), t.size)
    _check_history(dyn, t, x, dyn.state_names, "state")
    uu = np.array([ufun(ti) for ti in t], dtype=float).reshape(t.size, m)
    with np.errstate(all="ignore"):
        y = dyn.outputs(t, x, uu.T, p)
    _check_history(dyn, t, y, dyn.output_names, "output")
    return SimulationResult(freeze(t), freeze(x.T.copy()), freeze(y.T.copy()), freeze(uu),
                            dyn.state_names, dyn.input_names, dyn.output_names,
                            MappingProxyType(dict(zip(dyn.parameter_names, p.tolist()))), dyn.name)


def to_nonlinear_iosys(model: Union[StateEquations, NumericDynamics], values: ParameterValues, *,
                       name: Optional[str] = None) -> control.NonlinearIOSystem:
    """A python-control ``NonlinearIOSystem`` with the model's equations and labels.

    Parameter values are fixed here; python-control's own ``params`` are
    ignored.  Signal names with ``'.'`` are given with ``'_'`` (python-control
    forbids dots; see :func:`~bondgraph.numeric.control_labels`).  A
    derivative or output that is not finite raises :class:`SimulationError`
    naming it and the time (python-control's ``input_output_response`` would
    otherwise loop forever on a NaN).

    Parameters
    ----------
    model : StateEquations or NumericDynamics
        Pass a :class:`NumericDynamics` to reuse its compiled functions.
    values : mapping of Symbol or str to float
        Parameter values: exactly the model's parameters.
    name : str, optional
        The system's name; default: the model's name.

    Returns
    -------
    control.NonlinearIOSystem

    Raises
    ------
    ParameterValueError
        Bad parameter values.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
    >>> sys = to_nonlinear_iosys(bg.derive(g, outputs={"v": bg.flow("m")}), {"m": 2.0})
    >>> sys.state_labels, sys.input_labels, sys.output_labels
    (['p_m'], ['F'], ['v'])
    >>> sys.dynamics(0.0, [0.0], [3.0]), sys.output(0.0, [4.0], [0.0])
    (array([3.]), array([2.]))
    """
    import control

    dyn = model if isinstance(model, NumericDynamics) else NumericDynamics(model)
    p = dyn.parameter_vector(values)

    def updfcn(t, x, u, params=None):
        with np.errstate(all="ignore"):
            return _checked_derivatives(dyn, float(t), np.asarray(x, dtype=float),
                                        np.atleast_1d(np.asarray(u, dtype=float)), p, "")

    def outfcn(t, x, u, params=None):
        with np.errstate(all="ignore"):
            y = dyn.outputs(t, x, np.atleast_1d(u), p)
        if np.ndim(t) == 0:
            _check_history(dyn, np.atleast_1d(float(t)), y.reshape(-1, 1), dyn.output_names, "output")
        return y

    return control.nlsys(updfcn, outfcn, states=control_labels(dyn.state_names),
                         inputs=control_labels(dyn.input_names),
                         outputs=control_labels(dyn.output_names), name=name or dyn.name)
