"""Parameter sweeps and Sobol sensitivity indices of a linear model's metrics.

:func:`sweep` samples the varied parameters with a design, evaluates the
metrics of every sample's numeric plant (in chunks, vectorised where the
metric allows, in this process or on an executor) and returns a pandas
``DataFrame``; :func:`sensitivity` does the same on SALib's Saltelli sample
and returns first-order and total Sobol indices.  Both need the ``study``
extra (``pip install "bondgraph[study]"``).

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("msd")
>>> F, v = bg.Se("F"), bg.One("v")
>>> g.add(F, v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
>>> for tail, head in [(F, v), (v, "m"), (v, "b"), (v, "k")]: _ = g.connect(tail, head)
>>> model = bg.derive(g, outputs={"x": bg.displacement("k")})
>>> df = sweep(model, {"b": (0.1, 0.5), "k": [1.0, 4.0]}, "min_damping", values={"m": 1.0},
...            design="grid", n=4, progress=False)
>>> df.round(4)
     b    k  min_damping error
0  0.1  1.0        0.050  <NA>
1  0.1  4.0        0.025  <NA>
2  0.5  1.0        0.250  <NA>
3  0.5  4.0        0.125  <NA>
>>> df.attrs["design"], df.attrs["failed"]
('grid', 0)
"""

from __future__ import annotations

import numbers
import secrets
import warnings
from typing import Any, Mapping, Optional

import numpy as np

from .deps import StudyError, StudyWarning, require
from ._run import prepare, run_chunks
from .design import Design, design_points, parameter_specs
from .metrics import resolve_metrics

__all__ = ["sweep", "sensitivity"]


def _seed(seed: Optional[int]) -> int:
    if seed is None:
        return secrets.randbits(63)
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise StudyError(f"seed must be a non-negative integer (or None for a fresh one); got {seed!r}")
    return int(seed)


def _setup(model, parameters, metric, values, input, output):
    specs = parameter_specs(parameters)
    prepared = prepare(model, specs, values)
    nm = prepared.nm
    metrics = resolve_metrics(metric, nm.input_names, nm.output_names, input=input, output=output)
    names = {s.name for s in specs} | {"error"}
    clash = [c for m in metrics for c in m.columns if c in names]
    if clash:
        raise StudyError(f"metric column {clash[0]!r} has the name of a parameter (or 'error')")
    return prepared, metrics


def _frame(pd, prepared, metrics, X, out, errors):
    data = {s.name: X[:, j] for j, s in enumerate(prepared.specs)}
    col = 0
    for m in metrics:
        for c in m.columns:
            data[c] = out[:, col]
            col += 1
    df = pd.DataFrame(data)
    df["error"] = pd.Series(errors, dtype=object).astype("string")
    return df


def sweep(model: Any, parameters: Mapping[Any, Any], metric: Any, *,
          values: Optional[Mapping[Any, Any]] = None, n: Optional[int] = None,
          design: Design = "sobol", seed: Optional[int] = None, executor: Any = None,
          chunk_size: Optional[int] = None, progress: bool = True,
          input: Optional[str] = None, output: Optional[str] = None,
          timeout: Optional[float] = None):
    """Sample parameters, evaluate metrics of each sample's plant, return a table.

    Parameters
    ----------
    model : Model, NumericModel or ModelDefinition
        A linear model (a ``NumericModel`` is reused; a ``ModelDefinition``
        brings its default values).
    parameters : mapping
        Name (or Symbol) to bounds ``(lo, hi)`` (a tuple), a frozen
        ``scipy.stats`` distribution, or a list of values (see
        :mod:`bondgraph.study.design`).
    metric : str, callable, Metric, or a list or mapping of them
        Built-in names (:data:`bondgraph.study.metrics.BUILTIN`), functions of
        a :class:`~bondgraph.numeric.NumericStateSpace` returning a number,
        or a mapping of column names to functions.
    values : mapping, optional
        Values of the other parameters, by the package's parameter policy
        (names or Symbols; unknown names are refused listing the valid
        ones).  A varied parameter may have one too: the study's value wins.
    n : int, optional
        Number of samples (default 1024); for ``design="grid"`` the largest
        number of grid points wanted.
    design : {"sobol", "lhs", "halton", "grid", "random"} or array
        A scrambled ``scipy.stats.qmc`` sequence, a full factorial, uniform
        random draws, or ``(N, d)`` points of the unit hypercube.
    seed : int, optional
        Seed of the design; a fresh one is drawn (and recorded) when None.
    executor : None, concurrent.futures.Executor or dask.distributed.Client
        Where the chunks run; results do not depend on it.
    chunk_size : int, optional
        Samples per task (default ``ceil(N/32)``, at most 1000).
    progress : bool, optional
        Show a ``tqdm`` progress bar.
    input, output : str, optional
        The channel of channel metrics named by string (``"dc_gain"``).
    timeout : float, optional
        Seconds the study may take on an executor: the samples of chunks not
        finished by then are returned with an ``error`` saying so (a metric
        that never returns cannot hang the study).

    Returns
    -------
    pandas.DataFrame
        One row per sample: the varied parameters, the metric columns and
        ``error`` (the message of a failed sample, else missing).
        ``df.attrs`` holds ``design``, ``seed``, ``n``, ``model``,
        ``parameters`` (the ranges), ``values`` (the fixed values),
        ``metrics`` and ``failed``.

    Raises
    ------
    StudyError
        Bad ranges, design, metric or executor.
    ParameterValueError, MissingValueError
        Unknown names or missing values, by the package policy.
    MissingDependencyError
        pandas (or tqdm, with ``progress``) not installed.

    Warns
    -----
    StudyWarning
        When samples failed (a singular plant, a failing metric): they are
        kept with their message in ``error`` and the study goes on.
    """
    pd = require("pandas", "sweep()")
    prepared, metrics = _setup(model, parameters, metric, values, input, output)
    seed = _seed(seed)
    X, name = design_points(prepared.specs, design, n, seed)
    out, errors = run_chunks(prepared.nm, metrics, prepared.full(X), executor=executor,
                             chunk_size=chunk_size, progress=progress,
                             desc=f"sweep {prepared.nm.model.name}", timeout=timeout)
    df = _frame(pd, prepared, metrics, X, out, errors)
    failed = sum(e is not None for e in errors)
    df.attrs.update({
        "design": name, "seed": seed, "n": int(X.shape[0]), "model": prepared.nm.model.name,
        "parameters": {s.name: s.describe() for s in prepared.specs},
        "values": dict(prepared.fixed), "metrics": [c for m in metrics for c in m.columns],
        "failed": failed,
    })
    if failed:
        first = next(e for e in errors if e is not None)
        warnings.warn(StudyWarning(f"{failed} of {X.shape[0]} samples failed (see the 'error' "
                                   f"column); the first: {first}"), stacklevel=2)
    return df


def sensitivity(model: Any, parameters: Mapping[Any, Any], metric: Any, *,
                values: Optional[Mapping[Any, Any]] = None, n: int = 1024,
                seed: Optional[int] = None, executor: Any = None,
                chunk_size: Optional[int] = None, progress: bool = True,
                input: Optional[str] = None, output: Optional[str] = None,
                num_resamples: int = 100, conf_level: float = 0.95):
    """First-order and total Sobol indices of each metric (SALib, Saltelli's sampling).

    The varied parameters are independent, each drawn from its range as in
    :func:`sweep` (SALib's Saltelli points of the unit hypercube mapped
    through the bounds, distributions or value lists); the model is
    evaluated ``n * (d + 2)`` times on the executor; SALib's
    ``analyze.sobol`` gives the indices and their bootstrap confidence
    intervals.

    Parameters
    ----------
    model, parameters, metric, values, seed, executor, chunk_size, progress, input, output
        As :func:`sweep`.
    n : int, optional
        Saltelli base sample (a power of two).
    num_resamples : int, optional
        Bootstrap resamples of the confidence intervals.
    conf_level : float, optional
        Confidence level of the intervals.

    Returns
    -------
    pandas.DataFrame
        One row per (metric, parameter): ``metric``, ``parameter``, ``S1``,
        ``S1_conf``, ``ST``, ``ST_conf`` (``*_conf``: half-width of the
        interval).  ``df.attrs``: ``design`` ("saltelli"), ``seed``, ``n``,
        ``samples``, ``conf_level``, ``model``, ``parameters``, ``values``.

    Raises
    ------
    StudyError
        As :func:`sweep`; and when a sample fails or a metric is not finite
        (Sobol indices need every sample: the message gives the first error).
    MissingDependencyError
        SALib or pandas not installed.
    """
    pd = require("pandas", "sensitivity()")
    require("SALib", "sensitivity()")
    from SALib.analyze import sobol as analyze
    from SALib.sample import sobol as sample

    prepared, metrics = _setup(model, parameters, metric, values, input, output)
    seed = _seed(seed)
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, numbers.Integral) or n < 2:
        raise StudyError(f"n must be an integer >= 2 (a power of two); got {n!r}")
    d = len(prepared.specs)
    problem = {"num_vars": d, "names": [s.name for s in prepared.specs], "bounds": [[0.0, 1.0]] * d}
    with warnings.catch_warnings():          # n not a power of two: SALib warns, still valid
        warnings.filterwarnings("ignore", message=".*power of 2.*")
        unit = sample.sample(problem, int(n), calc_second_order=False, seed=seed)
    X = np.column_stack([s.from_unit(unit[:, j]) for j, s in enumerate(prepared.specs)])
    out, errors = run_chunks(prepared.nm, metrics, prepared.full(X), executor=executor,
                             chunk_size=chunk_size, progress=progress,
                             desc=f"sensitivity {prepared.nm.model.name}")
    failed = [e for e in errors if e is not None]
    if failed:
        raise StudyError(f"{len(failed)} of {len(errors)} samples failed, and Sobol indices need "
                         f"every sample; the first: {failed[0]}")
    rows = []
    columns = [c for m in metrics for c in m.columns]
    for j, column in enumerate(columns):
        Y = out[:, j]
        if not np.all(np.isfinite(Y)):
            raise StudyError(f"metric {column} is not finite for {int((~np.isfinite(Y)).sum())} "
                             "samples; Sobol indices need a finite value for every sample")
        Si = analyze.analyze(problem, Y, calc_second_order=False, num_resamples=num_resamples,
                             conf_level=conf_level, print_to_console=False, seed=seed)
        for k, spec in enumerate(prepared.specs):
            rows.append({"metric": column, "parameter": spec.name,
                         "S1": float(Si["S1"][k]), "S1_conf": float(Si["S1_conf"][k]),
                         "ST": float(Si["ST"][k]), "ST_conf": float(Si["ST_conf"][k])})
    df = pd.DataFrame(rows, columns=["metric", "parameter", "S1", "S1_conf", "ST", "ST_conf"])
    df.attrs.update({
        "design": "saltelli", "seed": seed, "n": int(n), "samples": int(X.shape[0]),
        "conf_level": float(conf_level), "model": prepared.nm.model.name,
        "parameters": {s.name: s.describe() for s in prepared.specs},
        "values": dict(prepared.fixed),
    })
    return df
