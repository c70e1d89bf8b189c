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

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np
import sympy

from ..model import Model
from ..signals import t as T_SYM
from ._compile import lambdify_cse, placeholders
from ._linalg import freeze
from .errors import NumericError, SimulationError
from .parameters import ParameterValues, resolve_parameters
from .plant import _CompiledModel, control_labels

if TYPE_CHECKING:  # imported lazily at run time
    import control

__all__ = ["NumericDynamics", "compile_dynamics", "SimulationResult", "simulate",
           "to_nonlinear_iosys", "InputSpec"]

#: ``u`` for :func:`simulate`: None, constants, a callable of t, or ``(t_samples, u_samples)``
InputSpec = Union[None, float, Sequence[float], np.ndarray, Callable[[float], Any],
                  tuple[np.ndarray, np.ndarray]]


class NumericDynamics(_CompiledModel):
    """``f(t, x, u, p)`` and ``g(t, x, u, p)`` of a model compiled to numpy once.

    Works for nonlinear and time-varying models.  ``p`` is the vector of
    parameter values in the order of :attr:`parameter_names` (see
    :meth:`parameter_vector`).

    Parameters
    ----------
    model : Model

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

    def __init__(self, model: Model) -> None:
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
        ps = placeholders("p", len(self._params))
        swap = {T_SYM: tt, **dict(zip(model.states, xs)), **dict(zip(model.inputs, us)),
                **dict(zip(self._params, ps))}
        args = [tt, xs, us, ps]
        self._f = lambdify_cse(args, [ex.xreplace(swap) for ex in model.rhs])
        self._g = lambdify_cse(args, [ex.xreplace(swap) for ex in model.output_exprs])

    def __repr__(self) -> str:
        return f"NumericDynamics({self._model.name!r}: {len(self.state_names)} states)"

    @property
    def name(self) -> str:
        return self._model.name

    def parameter_vector(self, values: ParameterValues) -> np.ndarray:
        """Checked parameter values in order (see :func:`~bondgraph.numeric.resolve_parameters`)."""
        return resolve_parameters(self._params, values, model=self._model.name)

    def derivatives(self, t: float, x, u, p) -> np.ndarray:
        """``x'`` at time ``t``, state ``x`` (n,), input ``u`` (m,) and parameters ``p`` (k,)."""
        return np.array(self._f(t, x, u, p), dtype=float).reshape(len(self.state_names))

    def outputs(self, t, x, u, p) -> np.ndarray:
        """``y`` (p,); with ``t`` of shape (N,), ``x`` (n, N) and ``u`` (m, N): shape (p, N)."""
        values = self._g(t, x, u, p)
        size = np.shape(t)
        return np.array([np.broadcast_to(np.asarray(v, dtype=float), size) for v in values],
                        dtype=float).reshape((len(self.output_names),) + size)


def compile_dynamics(model: Model) -> NumericDynamics:
    """Compile a model's equations once for simulation; see :class:`NumericDynamics`.

    Parameters
    ----------
    model : Model
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

    def __getitem__(self, name: str) -> np.ndarray:
        """The history of the output, state or input called ``name`` (searched in that order)."""
        for names, data in ((self.output_names, self.y), (self.state_names, self.x),
                            (self.input_names, self.u)):
            if name in names:
                return data[:, names.index(name)]
        raise KeyError(f"no output, state or input named {name!r}; outputs: "
                       f"{', '.join(self.output_names) or '-'}; states: {', '.join(self.state_names)}; "
                       f"inputs: {', '.join(self.input_names) or '-'}")


def _input_function(u: InputSpec, m: int, names: tuple[str, ...]) -> tuple[Callable, Optional[float]]:
    """(t -> u(t) of shape (m,), smallest sample spacing or None)."""
    def shaped(value, what: str) -> np.ndarray:
        arr = np.asarray(value, dtype=float)
        if arr.shape == () and m == 1:
            arr = arr.reshape(1)
        if arr.shape != (m,):
            raise NumericError(
                f"{what} must have shape ({m},) for the inputs {', '.join(names) or '(none)'}; "
                f"got shape {arr.shape}")
        return arr

    if u is None:
        zero = np.zeros(m)
        return (lambda t: zero), None
    if callable(u):
        def call(t: float) -> np.ndarray:
            return shaped(u(t), "u(t)")
        return call, None
    if isinstance(u, tuple) and len(u) == 2 and np.ndim(u[0]) == 1:
        ts = np.asarray(u[0], dtype=float)
        us = np.asarray(u[1], dtype=float)
        if us.ndim == 1 and m == 1:
            us = us[:, None]
        if ts.size < 2 or not np.all(np.diff(ts) > 0) or not np.all(np.isfinite(ts)):
            raise NumericError("input sample times must be finite, strictly increasing, at least two")
        if us.shape != (ts.size, m):
            raise NumericError(
                f"input samples must have shape ({ts.size}, {m}) for the inputs "
                f"{', '.join(names) or '(none)'}; got shape {us.shape}")
        cols = [us[:, j].copy() for j in range(m)]

        def interp(t: float) -> np.ndarray:
            return np.array([np.interp(t, ts, c) for c in cols])
        return interp, float(np.min(np.diff(ts)))
    const = shaped(u, "constant input u")
    return (lambda t: const), None


def _initial_state(x0: Any, names: tuple[str, ...]) -> np.ndarray:
    n = len(names)
    if x0 is None:
        return np.zeros(n)
    if isinstance(x0, Mapping):
        unknown = sorted(str(k) for k in x0 if k not in names)
        if unknown:
            raise NumericError(f"x0 names unknown states {', '.join(unknown)}; states are {', '.join(names)}")
        return np.array([float(x0.get(s, 0.0)) for s in names])
    arr = np.asarray(x0, dtype=float)
    if arr.shape != (n,):
        raise NumericError(f"x0 must have shape ({n},) for the states {', '.join(names)}; "
                           f"got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise NumericError("x0 must be finite")
    return arr


def simulate(model: Union[Model, NumericDynamics], params: ParameterValues,
             t_span: tuple[float, float],
             x0: Union[None, Sequence[float], np.ndarray, Mapping[str, float]] = None,
             *, u: InputSpec = None, t_eval: Optional[Sequence[float]] = None, method: str = "RK45",
             rtol: float = 1e-6, atol: float = 1e-9, max_step: Optional[float] = None) -> SimulationResult:
    """Integrate a (possibly nonlinear) model with :func:`scipy.integrate.solve_ivp`.

    Parameters
    ----------
    model : Model or NumericDynamics
        Pass a :class:`NumericDynamics` to reuse its compiled functions.
    params : mapping of Symbol or str to float
        Exactly the model's parameters.
    t_span : (float, float)
        Start and end time.
    x0 : array_like or mapping of str to float, optional
        Initial state in the order of ``state_names``, or by name (states not
        named start at 0).  Default: zeros.
    u : optional
        The inputs: None (all zero); a constant vector of length ``m`` (a
        number if ``m == 1``); a callable ``u(t)`` returning such a vector; or
        a pair ``(t_samples, u_samples)`` with ``u_samples`` of shape
        ``(N, m)`` (or ``(N,)`` if ``m == 1``), linearly interpolated and held
        constant outside the samples.
    t_eval : array_like, optional
        Times at which to report; default: the solver's steps.
    method : str, optional
        A ``solve_ivp`` method: ``"RK45"``, ``"LSODA"``, ``"BDF"``, ...
    rtol, atol : float, optional
        Solver tolerances.
    max_step : float, optional
        Largest step; with sampled inputs the default is the smallest sample
        spacing, otherwise unbounded.

    Returns
    -------
    SimulationResult

    Raises
    ------
    ParameterValueError
        Bad parameter values.
    NumericError
        Bad ``x0`` or ``u`` shapes.
    SimulationError
        The solver failed.

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
    """
    from scipy.integrate import solve_ivp

    dyn = model if isinstance(model, NumericDynamics) else NumericDynamics(model)
    p = dyn.parameter_vector(params)
    m = len(dyn.input_names)
    ufun, spacing = _input_function(u, m, dyn.input_names)
    x_init = _initial_state(x0, dyn.state_names)
    t0, t1 = (float(v) for v in t_span)
    if max_step is None:
        max_step = spacing if spacing is not None else np.inf
    ufun(t0)  # check the input's shape before integrating

    def rhs(t: float, x: np.ndarray) -> np.ndarray:
        return dyn.derivatives(t, x, ufun(t), p)

    with np.errstate(all="ignore"):
        sol = solve_ivp(rhs, (t0, t1), x_init, method=method, t_eval=t_eval, rtol=rtol, atol=atol,
                        max_step=max_step)
    if sol.status < 0:
        raise SimulationError(f"model {dyn.name!r}: the {method} solver failed at t = "
                              f"{sol.t[-1] if sol.t.size else t0:g}: {sol.message}")
    t = np.asarray(sol.t, dtype=float)
    x = np.asarray(sol.y, dtype=float).reshape(len(dyn.state_names), t.size)
    uu = np.array([ufun(ti) for ti in t], dtype=float).reshape(t.size, m)
    y = dyn.outputs(t, x, uu.T, p)
    return SimulationResult(freeze(t), freeze(x.T.copy()), freeze(y.T.copy()), freeze(uu),
                            dyn.state_names, dyn.input_names, dyn.output_names,
                            MappingProxyType(dict(zip(dyn.parameter_names, p.tolist()))), dyn.name)


def to_nonlinear_iosys(model: Union[Model, NumericDynamics], params: ParameterValues, *,
                       name: Optional[str] = None) -> control.NonlinearIOSystem:
    """A python-control ``NonlinearIOSystem`` with the model's equations and labels.

    Parameter values are fixed here; python-control's own ``params`` are
    ignored.  Signal names with ``'.'`` are given with ``'_'`` (python-control
    forbids dots; see :func:`~bondgraph.numeric.control_labels`).

    Parameters
    ----------
    model : Model or NumericDynamics
        Pass a :class:`NumericDynamics` to reuse its compiled functions.
    params : mapping of Symbol or str to float
        Exactly the model's parameters.
    name : str, optional
        The system's name; default: the model's name.

    Returns
    -------
    control.NonlinearIOSystem

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
    p = dyn.parameter_vector(params)

    def updfcn(t, x, u, params=None):
        return dyn.derivatives(t, x, np.atleast_1d(u), p)

    def outfcn(t, x, u, params=None):
        return dyn.outputs(t, x, np.atleast_1d(u), p)

    return control.nlsys(updfcn, outfcn, states=control_labels(dyn.state_names),
                         inputs=control_labels(dyn.input_names),
                         outputs=control_labels(dyn.output_names), name=name or dyn.name)

