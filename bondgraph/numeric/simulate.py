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

from dataclasses import dataclass, field, fields
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping, Optional, Sequence, Union

import numpy as np
import sympy
from sympy.core.function import AppliedUndef

from ..errors import BondGraphError
from ..equations import StateEquations
from ..signals import t as T_SYM
from ._compile import CallbackFailure, CompiledFunction, guard_user_functions, placeholders
from ._linalg import freeze
from ._field_values import check_fields_at
from ._stiffness import check_stiffness
from .errors import NumericError, SimulationError
from .resolve import ParameterValues, resolve_parameters
from .result import TimeResponse
from . import arguments
from .arguments import METHODS, InputSpec
from .implicit import with_algebraic
from .plant import _CompiledModel, control_labels, zero_parameters

if TYPE_CHECKING:  # imported lazily at run time
    import control

__all__ = ["NumericDynamics", "compile_dynamics", "SimulationResult", "simulate", "METHODS",
           "to_nonlinear_iosys", "InputSpec"]

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
    shown = ", ".join(arguments.short(a) for a in fail.args_given)
    when = f" at t = {arguments.short(t)}" if t is not None else ""
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
                                  inputs=[s.name for s in self._model.inputs],
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
class SimulationResult(TimeResponse):
    """Time histories from :func:`simulate` (time along the first axis).

    A :class:`~bondgraph.numeric.result.TimeResponse`: ``res["v"]`` is the
    history of the output, state or input ``v``; :meth:`to_dataframe` and
    :meth:`plot` give a table and a plot; ``events`` is empty.

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

    def _signals(self):
        return (("output", dict(zip(self.output_names, self.y.T))),
                ("state", dict(zip(self.state_names, self.x.T))),
                ("input", dict(zip(self.input_names, self.u.T))))


def _rebuild_result(values: dict) -> SimulationResult:
    """An unpickled :class:`SimulationResult`: read-only arrays, read-only parameter mapping."""
    for key in ("t", "x", "y", "u"):
        values[key] = freeze(values[key])
    values["parameters"] = MappingProxyType(dict(values["parameters"]))
    return SimulationResult(**values)


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
    k = arguments.nonfinite(dx)
    if k >= 0:
        others = [dyn.state_names[j] for j in np.flatnonzero(~np.isfinite(dx)) if j != k]
        inputs = f" and inputs {_named(dyn.input_names, u)}" if dyn.input_names else ""
        raise SimulationError(
            f"model {dyn.name!r}: {context}the derivative of state {dyn.state_names[k]} is {dx[k]:g} "
            f"(not finite) at t = {t:g}" + (f" (also of {', '.join(others)})" if others else "")
            + f", with {_named(dyn.state_names, x)}{inputs}; a law is evaluated outside its domain "
            "(log or sqrt of a negative value, division by zero) or the state overflowed"
            + zero_parameters(dyn.model, dyn.parameter_names, p))
    return dx


def _check_history(dyn: NumericDynamics, t: np.ndarray, data: np.ndarray, names: tuple[str, ...],
                   what: str) -> None:
    """Refuse a non-finite value in ``data`` (one row per name), naming it and its first time."""
    bad = ~np.isfinite(data)
    if data.size and bad.any():
        row = int(np.flatnonzero(bad.any(axis=1))[0])
        col = int(np.flatnonzero(bad[row])[0])
        shown = ""
        if what == "output":         # the expression: the law evaluated outside its domain
            exprs = getattr(dyn.model, "output_exprs", ())
            text = str(exprs[row]) if row < len(exprs) else ""
            shown = f" = {text if len(text) <= 80 else text[:77] + '...'}" if text else ""
        raise SimulationError(
            f"model {dyn.name!r}: {what} {names[row]}{shown} is {data[row, col]:g} (not finite) at "
            f"t = {t[col]:g} (first of {int(bad[row].sum())} such samples); a law is evaluated "
            "outside its domain (log or sqrt of a negative value, division by zero) or the "
            "state overflowed")


def simulate(model: Union[StateEquations, NumericDynamics, Any], values: ParameterValues,
             t_span: tuple[float, float],
             x0: Union[None, Sequence[float], np.ndarray, Mapping[str, float]] = None,
             *, u: InputSpec = None, t_eval: Optional[Sequence[float]] = None,
             method: Union[str, type] = "RK45", rtol: Optional[float] = None,
             atol: Union[None, float, Sequence[float], np.ndarray] = None,
             max_step: Optional[float] = None, max_events: Optional[int] = None,
             time_budget: Optional[float] = None, chatter_count: Optional[int] = None,
             chatter_time: Optional[float] = None,
             guard_tol: Optional[float] = None) -> TimeResponse:
    """Simulate any model: smooth, implicit (algebraic unknowns) or switched (with events).

    The one form of simulation: ``simulate(model, values, t_span, x0, u=...)``
    for every kind of model, returning a
    :class:`~bondgraph.numeric.result.TimeResponse` (``res.t``, ``res["v"]``
    for any output, state or input, ``res.events``, ``res.to_dataframe()``,
    ``res.plot()``).  A smooth or implicit model is integrated with
    :func:`scipy.integrate.solve_ivp` and gives a :class:`SimulationResult`;
    a switched model (:class:`bondgraph.hybrid.SwitchedModel`) is integrated
    mode by mode with events (:mod:`bondgraph.hybrid.events`) and gives a
    :class:`~bondgraph.hybrid.SwitchedResult`.

    Every argument is checked before integrating; a derivative, state or
    output that is not finite stops the simulation at once with an error
    naming it and the time (scipy's step-size control would otherwise loop
    forever on a NaN).

    Parameters
    ----------
    model : StateEquations, NumericDynamics or SwitchedModel
        Pass a :class:`NumericDynamics` to reuse its compiled functions.  A
        switched model takes its inputs ``u`` as a mapping of input names to
        numbers or functions of time, and its initial state ``x0`` as a
        mapping (stored quantities such as ``p_L``, ``q_C``, or an output
        that is one displacement or momentum).
    values : mapping of Symbol or str to float
        Parameter values: exactly the model's parameters.
    t_span : (float, float)
        Start and end time, finite, with ``t0 < t1``.
    x0 : array_like or mapping of str to float, optional
        Initial state in the order of ``state_names``, or by name (states not
        named start at 0).  Finite.  Default: zeros.
    u : optional
        The inputs: None (all zero); a mapping of input names to numbers or
        functions of time (inputs not named are 0); a constant vector of
        length ``m`` (a number if ``m == 1``); a callable ``u(t)`` returning
        such a vector; or
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
        Relative tolerance, ``0 < rtol < 1``; default 1e-6 (switched models
        1e-9: event times are located to it).
    atol : float or array_like, optional
        Absolute tolerance, ``> 0``: one number, or one per state; default
        1e-9 (switched models 1e-12).
    max_step : float, optional
        Largest step, ``> 0``; with sampled inputs the default is the smallest
        sample spacing, otherwise unbounded.
    max_events, time_budget, chatter_count, chatter_time, guard_tol : optional
        Switched models only (see :func:`bondgraph.hybrid.events.simulate`):
        the event budget, a wall-time budget in seconds, the chattering
        detection (``chatter_count`` events of one switch within
        ``chatter_time``) and the tolerance of a guard.

    Returns
    -------
    TimeResponse
        :class:`SimulationResult` (smooth and implicit models) or
        :class:`~bondgraph.hybrid.SwitchedResult` (switched models, with
        ``events``).

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

    events = {"max_events": max_events, "time_budget": time_budget, "chatter_count": chatter_count,
              "chatter_time": chatter_time, "guard_tol": guard_tol}
    switched = getattr(model, "simulate_with_events", None)
    if switched is not None:       # a switched model (bondgraph.hybrid) runs its own event loop
        return switched(values, t_span, x0, u=u, t_eval=t_eval, method=method,
                        rtol=1e-9 if rtol is None else rtol, atol=1e-12 if atol is None else atol,
                        max_step=max_step, **events)
    given = [k for k, v in events.items() if v is not None]
    if given:
        raise NumericError(f"{', '.join(given)} apply to switched models (with events) only; "
                           f"model {getattr(model, 'name', '?')!r} has no switch")
    dyn = model if isinstance(model, NumericDynamics) else NumericDynamics(model)
    p = dyn.parameter_vector(values)
    check_fields_at(dyn.model, values, dyn.parameter_names, p.tolist())   # as plant() does
    m = len(dyn.input_names)
    t0, t1 = arguments.time_span(t_span)
    x_init = arguments.initial_state(x0, dyn.state_names)
    ufun, spacing = arguments.input_function(u, m, dyn.input_names)
    times = arguments.eval_times(t_eval, t0, t1, len(dyn.state_names) + len(dyn.output_names) + m)
    solver = arguments.solver(method)
    r_tol, a_tol = arguments.tolerances(1e-6 if rtol is None else rtol,
                                        1e-9 if atol is None else atol, len(dyn.state_names))
    step = arguments.step_limit(max_step, spacing)
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
