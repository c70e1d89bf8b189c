"""Grey-box identification: physical parameters of a bond-graph model fitted to data.

The model's ``A, B, C, D`` are compiled once (:func:`~bondgraph.numeric.compile_plant`)
and evaluated at each trial parameter vector; :func:`scipy.optimize.least_squares`
minimises

* time data (:class:`TimeData`): ``sum_k ||y_k - ŷ_k(p)||^2``, where ``ŷ`` is
  the model's response to the measured input on the sample grid, exact for a
  zero-order-hold (or first-order-hold) input (:func:`simulate_sampled`);
* frequency data (:class:`FrequencyData`, or an
  :class:`~bondgraph.identification.FRFResult`): ``sum_k w_k |H_k - Ĥ(j omega_k; p)|^2``
  with real and imaginary parts as separate residuals.

Free parameters are optimised in the scaled variables ``p / |p_0|`` so that
parameters of very different magnitude (``Jm ~ 1e-7``, ``Rm ~ 1``) are equally
well conditioned.  At the optimum the residual Jacobian ``J`` (with respect to
the physical parameters) gives the usual asymptotic covariance

.. math::

    \\operatorname{cov}(\\hat p) = \\hat\\sigma^2 (J^T J)^{-1}, \\qquad
    \\hat\\sigma^2 = \\frac{\\|r\\|^2}{N_r - n_p},

standard errors (square roots of its diagonal) and 95 % confidence intervals
``p ± t_{0.975, N_r - n_p} se`` (Ljung, *System Identification*, Sec. 9.3).
The intervals are meaningful when the model structure is right and the noise
is white; coloured noise makes them optimistic.

The Jacobian is :func:`scipy.optimize.least_squares`'s own, by central
(``jac="3-point"``, one-sided next to a bound) differences in the scaled
variables, evaluated at the returned optimum.  ``bench/greybox_numerics.py``
compares it with the hand-written central differences it replaced: standard
errors equal within ``1e-5`` relative (the exact OLS one within ``1e-11``),
for 20-60 % more residual evaluations, as the optimiser's own steps now use
central differences too.

The pipeline, one module each: measurements (:mod:`~bondgraph.identification.data`:
:class:`TimeData`, :class:`FrequencyData`) -> model response
(:mod:`~bondgraph.identification.sampled`: exact discretisation and
:func:`simulate_sampled` for time data; the plant's frequency response for
frequency data) -> the fit (this module, :func:`greybox_fit`) -> the result
(:mod:`~bondgraph.identification.greybox_result`: :class:`GreyboxResult`).
This module also gathers those names under their historical import path.
"""

from __future__ import annotations

import math
from types import MappingProxyType
from typing import Mapping, Sequence

import numpy as np
import scipy.optimize
import scipy.stats
from numpy.typing import ArrayLike, NDArray

from ..errors import MissingValueError
from ..model import Model
from ..numeric import NumericModel, NumericStateSpace, compile_plant
from ..numeric.errors import NumericError
from ..parameters import match_values, real_value
from ._validation import IdentificationError, finite_array, readonly_copy
from .data import FrequencyData, TimeData
from .frf import FRFResult
from .greybox_result import GreyboxResult
from .sampled import Channels, _channel_indices, _discretize, _dlsim, simulate_sampled

__all__ = ["TimeData", "FrequencyData", "GreyboxResult", "greybox_fit", "simulate_sampled"]

#: Singular values of the scaled Jacobian below this fraction of the largest one
#: count as zero: the free parameters are then not identifiable from the data.
#: (The central-difference Jacobian is accurate to about 1e-7 relative.)
_RANK_RTOL = 1e-5


def _compiled(model: Model | NumericModel) -> NumericModel:
    if isinstance(model, NumericModel):
        return model
    if isinstance(model, Model):
        return compile_plant(model)
    raise IdentificationError(
        f"model: expected a bondgraph Model or a NumericModel (compile_plant), "
        f"got {type(model).__name__}")


def _name_map(values: Mapping | None, what: str) -> dict[str, float]:
    if values is None:
        return {}
    if not isinstance(values, Mapping):
        raise IdentificationError(f"{what}: expected a mapping of parameter name to value")
    out = {}
    for k, v in values.items():
        name = k if isinstance(k, str) else getattr(k, "name", None)
        if not isinstance(name, str):
            raise IdentificationError(f"{what}: expected parameter names as keys, got {k!r}")
        try:
            val = float(v)
        except (TypeError, ValueError):
            raise IdentificationError(f"{what}: {name!r} must be a real number, got {v!r}") from None
        if not math.isfinite(val):
            raise IdentificationError(f"{what}: {name!r} must be finite, got {val!r}")
        out[name] = val
    return out


def _unknown(names, known: set[str], what: str) -> None:
    bad = sorted(n for n in names if n not in known)
    if bad:
        raise IdentificationError(
            f"{what}: unknown parameter(s) {', '.join(bad)}; the model's parameters are "
            f"{', '.join(sorted(known))}")


def _bounds(free: list[str], bounds: Mapping | None, nm: NumericModel,
            p0: NDArray) -> tuple[NDArray, NDArray]:
    positive = {s.name: bool(s.is_positive) for s in nm.parameters}
    lo = np.array([0.0 if positive[n] else -np.inf for n in free])
    hi = np.full(len(free), np.inf)
    if bounds is not None:
        if not isinstance(bounds, Mapping):
            raise IdentificationError("bounds: expected a mapping of name to (lower, upper)")
        _unknown(bounds, set(free), "bounds (free parameters)")
        for name, pair in bounds.items():
            try:
                a, b = (float(v) for v in pair)
            except (TypeError, ValueError):
                raise IdentificationError(
                    f"bounds: {name!r} expected a pair (lower, upper), got {pair!r}") from None
            if not a < b:
                raise IdentificationError(f"bounds: {name!r} expected lower < upper, got {pair!r}")
            i = free.index(name)
            lo[i], hi[i] = a, b
    outside = [n for n, v, a, b in zip(free, p0, lo, hi) if not a < v < b]
    if outside:
        raise IdentificationError(
            f"initial: {', '.join(outside)} not strictly inside the bounds "
            f"(positive parameters are bounded below by 0)")
    return lo, hi


def greybox_fit(model: Model | NumericModel, data: TimeData | FrequencyData | FRFResult, *,
                free: Sequence[str], values: Mapping[str, float] | None = None,
                initial: Mapping[str, float] | None = None,
                bounds: Mapping[str, tuple[float, float]] | None = None,
                kind: str | None = None, input: Channels = None, output: Channels = None,
                method: str = "zoh", x0: ArrayLike | None = None,
                ftol: float = 1e-10, xtol: float = 1e-10, max_nfev: int | None = None
                ) -> GreyboxResult:
    """Fit free physical parameters of a linear model to time or frequency data.

    Parameters
    ----------
    model : Model or NumericModel
        A linear derived model (:func:`bondgraph.derive`), or its compiled
        form (:func:`~bondgraph.numeric.compile_plant`) to reuse across fits.
    data : TimeData, FrequencyData or FRFResult
        Measurements.  An :class:`FRFResult` is used through
        :meth:`FrequencyData.from_frf` (``H1``, coherence weights).
    free : sequence of str
        Names of the parameters to estimate.
    values : mapping of str to float, optional
        Values of the other parameters, matched by the package-wide policy
        (:mod:`bondgraph.parameters`): every model parameter must be free or
        given a value; names of the model definition that the derived form
        does not use are accepted.  An entry for a free parameter is its
        starting value unless ``initial`` gives one.
    initial : mapping of str to float, optional
        Starting values of free parameters.
    bounds : mapping of str to (float, float), optional
        Bounds of free parameters.  Default ``(0, inf)`` for parameters
        declared positive in the model, unbounded otherwise.
    kind : {"time", "frequency"}, optional
        Checked against the type of ``data`` when given.
    input : str or sequence of str, optional
        Model input(s) driven by the data (time data: one per column of
        ``u``; frequency data: exactly one).  Required when the model has
        several inputs.
    output : str or sequence of str, optional
        Model output(s) measured (time data: one per column of ``y``;
        frequency data: exactly one).  Required when the model has several
        outputs.
    method : {"zoh", "foh"}
        Input hold between samples for time data.
    x0 : array_like, optional
        Known initial state for time data (default zero).
    ftol, xtol : float
        Tolerances of :func:`scipy.optimize.least_squares`.
    max_nfev : int, optional
        Budget of residual evaluations.

    Returns
    -------
    GreyboxResult

    Raises
    ------
    ParameterValueError
        Unknown parameter names (listing the valid ones), parameters neither
        free nor given a value, values that are not finite real numbers.
    IdentificationError
        Unknown channel names, a free parameter without starting value, NaN/inf data, a
        record with no more residuals than free parameters, channel counts
        that do not match the data, or an evaluation of the model that fails.

    Examples
    --------
    A mass-spring-damper, ``1/(m s^2 + b s + k)``, with ``m`` and ``b`` fitted
    to its exact frequency response:

    >>> import numpy as np, bondgraph as bg
    >>> g = bg.BondGraph("msd")
    >>> F, v = bg.Se("F"), bg.One("v")
    >>> g.add(F, v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
    >>> for a, b in [(F, v), (v, "m"), (v, "b"), (v, "k")]: _ = g.connect(a, b)
    >>> model = bg.derive(g, outputs={"x": bg.displacement("k")})
    >>> w = np.linspace(0.5, 5.0, 40)
    >>> H = 1.0 / (2.0 * (1j * w) ** 2 + 0.3 * (1j * w) + 8.0)
    >>> r = greybox_fit(model, FrequencyData(w, H), free=["m", "b"],
    ...                 values={"k": 8.0}, initial={"m": 1.0, "b": 1.0})
    >>> round(r.estimates["m"], 8), round(r.estimates["b"], 8)
    (2.0, 0.3)
    """
    nm = _compiled(model)
    known = set(nm.parameter_names)
    if isinstance(free, str):
        free = [free]
    free = list(free)
    if not free:
        raise IdentificationError("free: expected at least one parameter to estimate")
    if len(set(free)) != len(free):
        raise IdentificationError(f"free: a parameter is listed twice in {free!r}")
    _unknown(free, known, "free")
    where = f"model {nm.model.name!r}: "
    given = match_values(nm.parameters, values, known=nm.model.known_parameters, partial=True,
                         where=where)
    fixed_v = {p.name: real_value(v, p.name, where) for p, v in given.items()}
    initial_v = _name_map(initial, "initial")
    _unknown(initial_v, set(free), "initial (free parameters)")
    missing = [n for n in nm.parameter_names if n not in fixed_v and n not in free]
    if missing:
        raise MissingValueError(
            f"{where}values: missing {', '.join(missing)} (every parameter must be free or "
            f"given a value). Valid names: {', '.join(sorted(nm.model.known_parameters))}",
            missing=tuple(missing))
    no_start = [n for n in free if n not in initial_v and n not in fixed_v]
    if no_start:
        raise IdentificationError(f"initial: no starting value for {', '.join(no_start)}")
    p0 = np.array([initial_v.get(n, fixed_v.get(n, 0.0)) for n in free])
    lo, hi = _bounds(free, bounds, nm, p0)
    base = {n: v for n, v in fixed_v.items() if n not in free}

    if isinstance(data, FRFResult):
        data = FrequencyData.from_frf(data)
    tdata: TimeData | None = None
    fdata: FrequencyData | None = None
    if isinstance(data, TimeData):
        data_kind, tdata = "time", data
    elif isinstance(data, FrequencyData):
        data_kind, fdata = "frequency", data
    else:
        raise IdentificationError(
            f"data: expected TimeData, FrequencyData or FRFResult, got {type(data).__name__}")
    if kind is not None and kind != data_kind:
        raise IdentificationError(
            f"kind: expected {data_kind!r} for {type(data).__name__} data, got {kind!r}")

    ins, _ = _channel_indices(input, nm.input_names, "input")
    outs, _ = _channel_indices(output, nm.output_names, "output")
    if len(ins) == 1 and len(outs) == 1:      # structural identifiability (issue 26)
        from ..structure.identifiable import warn_unidentifiable

        warn_unidentifiable(nm.model, free, nm.input_names[ins[0]], nm.output_names[outs[0]])
    x0_arr: NDArray | None = None
    sqrt_w: NDArray | None = None
    if tdata is not None:
        n_u, n_y = tdata.u.shape[1], tdata.y.shape[1]
        if input is None and len(ins) != n_u:
            raise IdentificationError(
                f"input: the model has inputs {', '.join(nm.input_names)}; name the "
                f"{n_u} driven by u")
        if output is None and len(outs) != n_y:
            raise IdentificationError(
                f"output: the model has outputs {', '.join(nm.output_names)}; name the "
                f"{n_y} measured in y")
        if len(ins) != n_u:
            raise IdentificationError(
                f"u: expected {len(ins)} column(s) for input(s) "
                f"{', '.join(nm.input_names[i] for i in ins)}, got {n_u}")
        if len(outs) != n_y:
            raise IdentificationError(
                f"y: expected {len(outs)} column(s) for output(s) "
                f"{', '.join(nm.output_names[i] for i in outs)}, got {n_y}")
        if method not in ("zoh", "foh"):
            raise IdentificationError(f"method: expected 'zoh' or 'foh', got {method!r}")
        if x0 is not None:
            x0_arr = finite_array(x0, "x0", ndim=(1,))
            if x0_arr.size != len(nm.state_names):
                raise IdentificationError(
                    f"x0: expected {len(nm.state_names)} initial states, got {x0_arr.size}")
            if method != "zoh":
                raise IdentificationError("x0: only supported with method='zoh'")
        target = np.asarray(tdata.y)
        n_res = target.size
    else:
        assert fdata is not None
        if len(ins) != 1 or len(outs) != 1:
            raise IdentificationError(
                f"{'input' if len(ins) != 1 else 'output'}: frequency data is one channel; "
                f"name one input and one output (model inputs: {', '.join(nm.input_names)}; "
                f"outputs: {', '.join(nm.output_names)})")
        weights = np.asarray(fdata.weights)
        target = np.asarray(fdata.response)
        sqrt_w = np.sqrt(weights)
        n_res = 2 * int(np.count_nonzero(weights > 0))
    _check_excited(tdata, fdata, ins, x0_arr if tdata is not None else None, target)
    if max_nfev is not None and (isinstance(max_nfev, bool) or not isinstance(max_nfev, int)
                                 or max_nfev < 1):
        raise IdentificationError(f"max_nfev: expected None or an integer >= 1, got {max_nfev!r}")
    if n_res <= len(free):
        raise IdentificationError(
            f"data: record too short: {n_res} residuals for {len(free)} free parameters "
            f"(need more residuals than parameters)")

    scale = np.where(p0 != 0, np.abs(p0), 1.0)

    def plant_at(p: NDArray) -> NumericStateSpace:
        vals = dict(base)
        vals.update(zip(free, p.tolist()))
        try:
            return nm.plant(vals)
        except NumericError as exc:
            raise IdentificationError(f"model evaluation failed at {vals}: {exc}") from exc

    def predict(p: NDArray) -> NDArray:
        ss = plant_at(p)
        if tdata is not None:
            B, C, D = ss.B[:, ins], ss.C[outs], ss.D[np.ix_(outs, ins)]
            Ad, Bd, Cd, Dd = _discretize(ss.A, B, C, D, tdata.dt, method)
            return _dlsim(Ad, Bd, Cd, Dd, np.asarray(tdata.u), x0_arr)
        assert fdata is not None
        return ss.frequency_response(fdata.omega)[:, outs[0], ins[0]]

    def weighted(diff: NDArray) -> NDArray:
        if sqrt_w is None:
            return diff.ravel()
        d = diff * sqrt_w
        return np.concatenate((d.real, d.imag))

    def fun(x: NDArray) -> NDArray:
        with np.errstate(over="ignore", invalid="ignore"):
            r = weighted(predict(x * scale) - target)
        if not np.all(np.isfinite(r)):
            return np.full(r.shape, 1e150)
        return r

    sol = scipy.optimize.least_squares(fun, p0 / scale, jac="3-point",
                                       bounds=(lo / scale, hi / scale), method="trf",
                                       ftol=ftol, xtol=xtol, gtol=1e-12, max_nfev=max_nfev,
                                       x_scale=1.0)
    p_hat = sol.x * scale
    model_out = predict(p_hat)
    resid_w = weighted(model_out - target)
    dof = n_res - len(free)
    sigma2 = float(resid_w @ resid_w) / dof
    # Jacobian in the scaled variables x = p / scale (comparable columns): the optimiser's
    # central differences, evaluated at the point it returns
    _, sv, vt = np.linalg.svd(sol.jac, full_matrices=False)
    rank = int(np.count_nonzero(sv > _RANK_RTOL * sv.max())) if sv.size and sv.max() > 0 else 0
    if rank == len(free):
        cov_x = sigma2 * (vt.T / sv**2) @ vt
        cov = cov_x * np.outer(scale, scale)           # physical units
    else:
        cov = np.full((len(free), len(free)), np.nan)
        import warnings

        from ..errors import BondGraphWarning
        warnings.warn(f"greybox_fit: the data do not determine every free parameter (the "
                      f"Jacobian has rank {rank} for {len(free)} free parameters "
                      f"{', '.join(free)}): the standard errors and confidence intervals are "
                      "NaN; excite the model more, or fix some parameters", BondGraphWarning,
                      stacklevel=2)
    se = np.sqrt(np.diag(cov))
    tq = float(scipy.stats.t.ppf(0.975, dof))
    residuals = target - model_out
    if data_kind == "time":
        fits = [_nrmse_fit(target[:, j], model_out[:, j]) for j in range(target.shape[1])]
        in_names = tuple(nm.input_names[i] for i in ins)
    else:
        fits = [_nrmse_fit(target, model_out)]
        in_names = (nm.input_names[ins[0]],)
    all_params = dict(base)
    all_params.update(zip(free, p_hat.tolist()))
    ordered = {n: all_params[n] for n in nm.parameter_names}
    return GreyboxResult(
        names=tuple(free),
        estimates=MappingProxyType(dict(zip(free, p_hat.tolist()))),
        std_errors=MappingProxyType(dict(zip(free, se.tolist()))),
        confidence_intervals=MappingProxyType(
            {n: (float(v - tq * s), float(v + tq * s)) for n, v, s in zip(free, p_hat, se)}),
        covariance=readonly_copy(cov),
        parameters=MappingProxyType(ordered),
        initial=MappingProxyType(dict(zip(free, p0.tolist()))),
        residuals=readonly_copy(residuals, residuals.dtype),
        fit_percent=readonly_copy(fits),
        noise_variance=sigma2, dof=int(dof), rank=rank, kind=data_kind,
        input_names=in_names, output_names=tuple(nm.output_names[i] for i in outs),
        plant=plant_at(p_hat), success=bool(sol.success), message=str(sol.message),
        nfev=int(sol.nfev), cost=float(0.5 * resid_w @ resid_w))


def _check_excited(tdata, fdata, ins, x0, target) -> None:
    """Refuse data that hold no information: a zero input (and zero initial state), a zero response."""
    if tdata is not None:
        u = np.asarray(tdata.u)
        u = u[:, ins] if u.ndim == 2 else u
        if not np.any(u) and (x0 is None or not np.any(x0)):
            raise IdentificationError(
                "data: the input is zero at every sample (and the initial state is zero): the "
                "record does not excite the model, so no parameter can be identified")
    elif not np.any(target):
        raise IdentificationError(
            "data: the frequency response is zero at every frequency: it holds no information "
            "about the parameters")


def _nrmse_fit(y: NDArray, yhat: NDArray) -> float:
    denom = np.linalg.norm(y - y.mean())
    if denom == 0:
        return float("nan")
    return float(100.0 * (1.0 - np.linalg.norm(y - yhat) / denom))
