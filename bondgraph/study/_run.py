"""Running a study: the model and its fixed values, chunks, executors, progress (private).

A study's samples are cut into chunks (the same chunks whatever runs
them, so results do not depend on the executor); each chunk is one task:
its plants are evaluated at once with :meth:`NumericModel.batch` and the
vectorised metrics run on the whole batch; a plant or metric that fails
falls back to plant-by-plant evaluation, where a failing sample is
recorded with its error and the others go on.
"""

from __future__ import annotations

import concurrent.futures as cf
import math
import sys
from typing import Any, Iterator, Mapping, Optional, Sequence

import numpy as np

from ..errors import MissingValueError
from ..model import Model
from ..numeric import NumericModel, compile_plant
from ..parameters import match_values, real_value
from .deps import StudyError, require
from .design import ParameterSpec
from .metrics import Metric

__all__ = ["Prepared", "prepare", "evaluate_chunk", "run_chunks", "default_chunk_size"]

#: most samples in one chunk by default
MAX_CHUNK = 1000
#: chunks a study is cut into by default (when samples allow), for progress and load balance
CHUNKS = 32


class Prepared:
    """A compiled model, the varied parameters and the fixed values of the others."""

    def __init__(self, nm: NumericModel, specs: Sequence[ParameterSpec],
                 fixed: dict[str, float]) -> None:
        self.nm = nm
        self.specs = list(specs)
        self.fixed = fixed
        names = nm.parameter_names
        self.columns = [names.index(s.name) if s.name in names else -1 for s in self.specs]

    def full(self, X: np.ndarray) -> np.ndarray:
        """``(N, k)`` parameter sets in the model's order from the varied values ``X`` ``(N, d)``."""
        names = self.nm.parameter_names
        out = np.empty((X.shape[0], len(names)))
        for j, name in enumerate(names):
            if name in self.fixed:
                out[:, j] = self.fixed[name]
        for col, j in enumerate(self.columns):
            if j >= 0:
                out[:, j] = X[:, col]
        return out


def prepare(model: Any, specs: Sequence[ParameterSpec], values: Optional[Mapping]) -> Prepared:
    """Compile ``model`` and check the varied names and the fixed ``values`` by the package policy.

    ``model`` is a :class:`Model`, a :class:`NumericModel` (reused) or a
    :class:`~bondgraph.modelfile.ModelDefinition` (derived; its default
    values are the fixed values ``values`` overrides).  A varied parameter
    may also have a value in ``values`` (the nominal one): the study's value
    wins.

    Raises
    ------
    ParameterValueError
        An unknown name (varied or fixed; the valid ones listed), a bad value.
    MissingValueError
        A parameter neither varied nor given a value.
    """
    from ..modelfile import ModelDefinition

    defaults: dict[str, Any] = {}
    if isinstance(model, ModelDefinition):
        defaults = dict(model.parameters)
        model = model.derive()
    if isinstance(model, NumericModel):
        nm = model
    elif isinstance(model, Model):
        nm = compile_plant(model)
    else:
        raise StudyError("model must be a bondgraph Model, NumericModel or ModelDefinition; "
                         f"got {type(model).__name__}")
    mdl = nm.model
    where = f"model {mdl.name!r}: "
    known = mdl.known_parameters
    # varied names: the same policy (unknown names listed, definition-only names accepted)
    match_values(nm.parameters, {s.name: 0.0 for s in specs}, known=known, partial=True,
                 where=where + "study parameters: ")
    used = set(nm.parameter_names)
    fixed = {n: real_value(v, n, where) for n, v in defaults.items() if n in used}
    given = match_values(nm.parameters, values, known=known, partial=True, where=where)
    fixed.update({p.name: real_value(v, p.name, where) for p, v in given.items()})
    varied = {s.name for s in specs}
    missing = [n for n in nm.parameter_names if n not in fixed and n not in varied]
    if missing:
        raise MissingValueError(
            f"{where}no value for {', '.join(missing)}: vary them or give them in values=",
            missing=tuple(missing))
    return Prepared(nm, specs, {n: v for n, v in fixed.items() if n not in varied})


def _describe(exc: BaseException) -> str:
    text = str(exc).strip() or "(no message)"
    return f"{type(exc).__name__}: {text}"


def evaluate_chunk(nm: NumericModel, metrics: Sequence[Metric],
                   block: np.ndarray) -> tuple[np.ndarray, list[Optional[str]]]:
    """Metric values ``(P, columns)`` and an error (or None) per sample of ``block`` ``(P, k)``.

    Runs in a worker: everything it needs travels in its arguments.
    """
    P = block.shape[0]
    ncols = sum(len(m.columns) for m in metrics)
    out = np.full((P, ncols), np.nan)
    errors: list[Optional[str]] = [None] * P
    names = nm.parameter_names
    try:
        batch: Any = nm.batch(block)
        plants: list = []
    except Exception:                       # one bad sample: evaluate them one by one
        batch = None
        plants = []
        for r in range(P):
            try:
                plants.append(nm.plant(dict(zip(names, block[r].tolist()))))
            except Exception as exc:
                plants.append(None)
                errors[r] = _describe(exc)
    col = 0
    for metric in metrics:
        cols = slice(col, col + len(metric.columns))
        col += len(metric.columns)
        if batch is not None and metric.vectorised:
            try:
                with np.errstate(all="ignore"):
                    out[:, cols] = np.column_stack(metric.stack(batch))
                continue
            except Exception:               # find the sample(s) at fault plant by plant
                pass
        for r in range(P):
            plant = batch[r] if batch is not None else plants[r]
            if plant is None:
                continue
            try:
                with np.errstate(all="ignore"):
                    out[r, cols] = metric.plant(plant)
            except Exception as exc:
                message = f"metric {metric.name}: {_describe(exc)}"
                errors[r] = message if errors[r] is None else f"{errors[r]}; {message}"
    return out, errors


def default_chunk_size(n: int) -> int:
    """``ceil(n / 32)`` samples, at most 1000: the same whatever the executor."""
    return max(1, min(MAX_CHUNK, math.ceil(n / CHUNKS)))


def _is_dask_client(executor: Any) -> bool:
    distributed = sys.modules.get("distributed")
    return distributed is not None and isinstance(executor, distributed.Client)


def _progress(total: int, progress: bool, desc: str):
    if not progress:
        return _NoBar()
    tqdm = require("tqdm", "a study's progress bar (progress=True)")
    return tqdm.tqdm(total=total, desc=desc, unit="sample", dynamic_ncols=True)


class _NoBar:
    def update(self, n: int) -> None:
        pass

    def close(self) -> None:
        pass


def run_chunks(nm: NumericModel, metrics: Sequence[Metric], full: np.ndarray, *,
               executor: Any = None, chunk_size: Optional[int] = None, progress: bool = True,
               desc: str = "study", timeout: Optional[float] = None
               ) -> tuple[np.ndarray, list[Optional[str]]]:
    """Evaluate every row of ``full`` (``(N, k)``) in chunks on ``executor``; results in order.

    ``executor``: None (in this process), a :class:`concurrent.futures.Executor`
    (the compiled model and metrics are pickled to its workers with each
    chunk) or a ``dask.distributed.Client`` (the compiled model is scattered
    to every worker once; the progress bar follows completed futures).

    ``timeout`` (seconds, on an executor): the samples of chunks not finished
    by then get the error "not finished within ..." and the study returns
    (a metric that never returns cannot hang it).  On a Dask client, a chunk
    whose worker died (``KilledWorker``) marks its samples failed instead of
    losing the study.

    Raises
    ------
    StudyError
        A bad ``chunk_size``, ``executor`` or ``timeout``, or a task that could
        not run (a metric the executor cannot send).
    """
    if timeout is not None and (isinstance(timeout, bool) or not isinstance(timeout, (int, float))
                                or not math.isfinite(timeout) or timeout <= 0):
        raise StudyError(f"timeout must be a positive number of seconds or None; got {timeout!r}")
    N = full.shape[0]
    if chunk_size is None:
        size = default_chunk_size(N)
    elif isinstance(chunk_size, (bool, np.bool_)) or not isinstance(chunk_size, (int, np.integer)) \
            or chunk_size < 1:
        raise StudyError(f"chunk_size must be a positive integer; got {chunk_size!r}")
    else:
        size = int(chunk_size)
    starts = list(range(0, N, size))
    blocks = [full[s:s + size] for s in starts]
    ncols = sum(len(m.columns) for m in metrics)
    out = np.full((N, ncols), np.nan)
    errors: list[Optional[str]] = [None] * N
    bar = _progress(N, progress, desc)

    def store(index: int, result: Any) -> None:
        s = starts[index]
        if isinstance(result, str):         # the whole chunk failed or timed out
            n = len(blocks[index])
            errors[s:s + n] = [result] * n
            bar.update(n)
            return
        values, errs = result
        out[s:s + len(errs)] = values
        errors[s:s + len(errs)] = errs
        bar.update(len(errs))

    try:
        if executor is None:
            for index, block in enumerate(blocks):
                store(index, evaluate_chunk(nm, metrics, block))
        elif _is_dask_client(executor):
            for index, result in _dask(executor, nm, metrics, blocks, timeout):
                store(index, result)
        elif isinstance(executor, cf.Executor):
            for index, result in _pool(executor, nm, metrics, blocks, timeout):
                store(index, result)
        else:
            raise StudyError("executor must be None, a concurrent.futures.Executor or a "
                             f"dask.distributed.Client; got {type(executor).__name__}")
    finally:
        bar.close()
    return out, errors


def _task_failed(exc: BaseException) -> StudyError:
    return StudyError(f"a study task could not run on the executor ({_describe(exc)}); the "
                      "metrics and the compiled model must be picklable (a metric function "
                      "defined at module level) and the workers must have bondgraph installed")


def _late(timeout: Optional[float]) -> str:
    return (f"not finished within the study's timeout of {timeout:g} s (a metric that does not "
            "return?); its samples were abandoned")


def _pool(executor: cf.Executor, nm: NumericModel, metrics: Sequence[Metric],
          blocks: Sequence[np.ndarray], timeout: Optional[float]) -> Iterator[tuple[int, Any]]:
    futures = {}
    finished: set = set()
    try:
        for index, block in enumerate(blocks):
            futures[executor.submit(evaluate_chunk, nm, metrics, block)] = index
        try:
            for fut in cf.as_completed(futures, timeout=timeout):
                finished.add(fut)
                try:
                    result = fut.result()
                except Exception as exc:
                    raise _task_failed(exc) from exc
                yield futures[fut], result
        except cf.TimeoutError:
            for fut, index in futures.items():
                if fut not in finished:
                    yield index, _late(timeout)
    finally:
        for fut in futures:
            fut.cancel()


def _dask(client: Any, nm: NumericModel, metrics: Sequence[Metric],
          blocks: Sequence[np.ndarray], timeout: Optional[float]) -> Iterator[tuple[int, Any]]:
    distributed = sys.modules["distributed"]
    # a worker that died: KilledWorker, or the task "cancelled for reason: already forgotten"
    lost = tuple(c for c in (getattr(sys.modules.get("distributed.scheduler"), "KilledWorker", None),
                             getattr(sys.modules.get("distributed.client"), "FutureCancelledError",
                                     None)) if c is not None)
    futures: dict = {}
    finished: set = set()
    try:
        try:
            model_future = client.scatter(nm, broadcast=True, hash=False)
        except Exception as exc:
            raise _task_failed(exc) from exc
        for index, block in enumerate(blocks):
            fut = client.submit(evaluate_chunk, model_future, metrics, block, pure=False)
            futures[fut] = index
        done = distributed.as_completed(list(futures), with_results=True, raise_errors=False,
                                        timeout=timeout)
        try:
            for fut, result in done:
                finished.add(fut)
                if fut.status != "finished":
                    try:
                        fut.result()
                    except lost as exc:         # the worker died on these samples
                        yield futures[fut], (f"the worker running these samples died "
                                             f"({_describe(exc)}); a metric crashed it?")
                        continue
                    except Exception as exc:
                        raise _task_failed(exc) from exc
                    raise _task_failed(RuntimeError(f"task {fut.status}"))
                yield futures[fut], result
        except (TimeoutError, distributed.TimeoutError):
            for fut, index in futures.items():
                if fut not in finished:
                    yield index, _late(timeout)
    finally:
        client.cancel(list(futures))
