"""The ``sweep`` command: a parameter study (:mod:`bondgraph.study`) written as CSV or parquet.

Examples
--------
>>> sorted(_SWEEP_FORMATS.values())
['csv', 'parquet']
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import ParameterValueError
from ._common import CLIError, _refuse_overwriting_inputs

__all__ = ["cmd_sweep"]

_SWEEP_FORMATS = {".csv": "csv", ".parquet": "parquet"}


#: the most samples a sweep draws (the design alone is 8 bytes per sample and parameter)
MAX_SAMPLES = 10**7


class OptionError(CLIError):
    """A command-line option or a [study] option is wrong; the message names it (no model file)."""

    culprit_named = True


def _check_options(args, opts) -> None:
    """n, seed, chunk size and workers checked before the model is loaded, naming their source."""
    checks = (("n", "--n", 1, MAX_SAMPLES), ("seed", "--seed", 0, None),
              ("chunk_size", "--chunk-size", 1, None), ("workers", "--workers", 1, None))
    for key, flag, low, high in checks:
        given = getattr(args, key, None)
        where = flag if given is not None else f"{key} in the [study] table of '{args.params}'"
        value = given if given is not None else opts.get(key)
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, int):
            raise OptionError(f"{where} must be an integer; got {value!r}")
        if value < low or (high is not None and value > high):
            bound = f"between {low} and {high:,}" if high is not None else f"at least {low}"
            raise OptionError(f"{where} must be {bound}; got {value:,}")


def cmd_sweep(args) -> None:
    """``bondgraph sweep``: a parameter study (bondgraph.study) written as CSV or parquet."""
    import warnings

    from .._support.files import atomic_write
    from ..study import StudyWarning, sweep
    from ..study.deps import require
    from ..study.config import load_study

    out = Path(args.output)
    fmt = _SWEEP_FORMATS.get(out.suffix.lower())
    if fmt is None:
        raise CLIError(f"cannot tell the table format from '{args.output}'; use a .csv or .parquet "
                       "file name")
    if args.workers is not None and args.scheduler is not None:
        raise CLIError("give --workers (a local process pool) or --scheduler (a Dask cluster), not both")
    _refuse_overwriting_inputs([out], args)
    require("pandas", "bondgraph sweep")
    if fmt == "parquet":
        require("pyarrow", f"writing '{args.output}' (parquet)")
    study = load_study(args.params)
    opts = study.options
    metric = args.metric or opts.get("metric")
    if not metric:
        from ..study.metrics import BUILTIN

        raise CLIError(f"no metric: give --metric NAME ({', '.join(BUILTIN)}) or metric = [...] "
                       f"in the [study] table of '{args.params}'")
    _check_options(args, opts)
    from ..modelfile import load_model

    defn = load_model(args.model)
    from ._switched import modes_listing, switched_of

    sm = switched_of(defn)
    if sm is not None:          # never the plant of the mode the graph was built in, silently
        raise CLIError(f"model {sm.name!r} is switched (switches {', '.join(sm.switches)}; modes "
                       f"{modes_listing(sm)}): 'sweep' studies one linear plant; write a model file "
                       "whose model() is one mode or the average (SwitchedModel.mode, .average)")
    executor, close = _sweep_executor(args)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", StudyWarning)
            try:
                df = sweep(defn, study.parameters, metric, values=study.values,
                           n=args.n if args.n is not None else opts.get("n"),
                           design=args.design or opts.get("design", "sobol"),
                           seed=args.seed if args.seed is not None else opts.get("seed"),
                           executor=executor,
                           chunk_size=args.chunk_size or opts.get("chunk_size"),
                           progress=not args.no_progress and sys.stderr.isatty(),
                           input=args.input or opts.get("input"),
                           output=args.output_signal or opts.get("output"))
            except ParameterValueError as exc:      # names or values of the study file
                raise CLIError(f"study file '{args.params}': {exc}") from None
    finally:
        close()
    if fmt == "csv":
        data = df.to_csv(index=False).encode("utf-8")
        atomic_write(out, lambda fh: fh.write(data))
    else:
        atomic_write(out, lambda fh: df.to_parquet(fh, index=False))
    for w in caught:
        if issubclass(w.category, StudyWarning):
            print(f"note: {w.message}", file=sys.stderr)
    print(f"wrote {out} ({len(df)} samples, design {df.attrs['design']}, seed {df.attrs['seed']}, "
          f"{df.attrs['failed']} failed)")


def _sweep_executor(args):
    """(executor, close) for ``--workers`` / ``--scheduler``; (None, no-op) in process."""
    if args.workers is not None:
        if args.workers < 1:
            raise CLIError(f"--workers must be at least 1; got {args.workers}")
        from concurrent.futures import ProcessPoolExecutor

        pool = ProcessPoolExecutor(args.workers)
        return pool, lambda: pool.shutdown(cancel_futures=True)
    if args.scheduler is not None:
        from ..study.deps import require

        distributed = require("distributed", "--scheduler (Dask)")
        try:
            client = distributed.Client(args.scheduler, timeout="10s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise CLIError(f"cannot reach the Dask scheduler at {args.scheduler!r}: {exc}") from None
        return client, client.close
    return None, lambda: None

