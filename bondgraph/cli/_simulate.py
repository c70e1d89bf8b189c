"""``bondgraph simulate``: a model in time, to a CSV or Parquet table and optionally a plot.

Any model file: smooth, implicit or switched (with events; a ``mode``
column tells each sample's mode).  The table has the column ``t`` then one
named column per output, state and input (``--signals`` picks some); the
simulation is :func:`bondgraph.simulate`, so the numbers are the API's.

Examples
--------
>>> parse_assignments(["p_L=1e-3", "q_C = 2"], "--x0")
{'p_L': 0.001, 'q_C': 2.0}
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path
from typing import Optional, Sequence

from ._common import CLIError, UsageError, _given, _refuse_overwriting_inputs, _values

__all__ = ["cmd_simulate", "add_parser", "parse_assignments", "TABLE_FORMATS"]

#: table formats of ``bondgraph simulate`` by suffix
TABLE_FORMATS = {".csv": "csv", ".parquet": "parquet"}


def add_parser(sub) -> None:
    """The ``simulate`` sub-command's options."""
    from . import _switched

    p = sub.add_parser("simulate", help="simulate the model, write a CSV/Parquet table (and a plot)",
                       description="Simulate the model from --t-start to --t-end (default 0) and write "
                                   "one row per sample: t, then the outputs, states and inputs by "
                                   "name (CSV, or Parquet when pyarrow is installed; written "
                                   "atomically). A switched model runs with its events (a 'mode' "
                                   "column gives each sample's mode), or in one --mode, or "
                                   "averaged (--average). Inputs are constants (--input NAME=VALUE, "
                                   "others 0); states start at 0 unless --x0 NAME=VALUE.")
    p.add_argument("model", metavar="MODEL", help="model file (.py)")
    p.add_argument("-o", "--output", metavar="OUT", required=True, help="table, .csv or .parquet")
    p.add_argument("--t-end", type=float, required=True, metavar="T", help="end time (s)")
    p.add_argument("--t-start", type=float, default=0.0, metavar="T", help="start time (s), default 0")
    p.add_argument("--points", type=int, default=501, metavar="N",
                   help="samples, evenly spaced (default 501; a switched run adds each event "
                        "before and after the change)")
    p.add_argument("--input", "-u", action="append", default=[], metavar="NAME=VALUE",
                   help="a constant input value (repeatable)")
    p.add_argument("--x0", action="append", default=[], metavar="NAME=VALUE",
                   help="an initial state (repeatable)")
    p.add_argument("--params", metavar="FILE", help="parameter values, JSON or TOML")
    p.add_argument("--signals", metavar="NAMES", help="columns to write, comma-separated "
                                                      "(default: every output, state and input)")
    p.add_argument("--plot", metavar="PNG", help="also plot the signals against time to this .png")
    p.add_argument("--method", default="RK45",
                   help="solve_ivp method: RK45, RK23, DOP853, Radau, BDF, LSODA (default RK45)")
    p.add_argument("--rtol", type=float, default=None, metavar="R",
                   help="relative tolerance (default 1e-6; switched 1e-9)")
    p.add_argument("--atol", type=float, default=None, metavar="A",
                   help="absolute tolerance (default 1e-9; switched 1e-12)")
    p.add_argument("--max-step", type=float, default=None, metavar="H", help="largest step (s)")
    _switched.add_arguments(p)
    p.set_defaults(func=cmd_simulate)


def parse_assignments(items: Sequence[str], option: str) -> dict[str, float]:
    """``NAME=VALUE`` texts to a mapping; a value is a finite number (never evaluated)."""
    out: dict[str, float] = {}
    for item in items:
        name, eq, value = item.partition("=")
        name = name.strip()
        if not eq or not name:
            raise UsageError(f"{option} {item!r}: expected NAME=VALUE")
        try:
            number = float(value.strip())
        except ValueError:
            raise UsageError(f"{option} {item!r}: {value.strip()!r} is not a number") from None
        if not math.isfinite(number):
            raise UsageError(f"{option} {item!r}: the value must be finite")
        if name in out:
            raise UsageError(f"{option}: {name!r} is given twice")
        out[name] = number
    return out


def _table_format(path: str) -> str:
    fmt = TABLE_FORMATS.get(Path(path).suffix.lower())
    if fmt is None:
        raise CLIError(f"cannot tell the table format from '{path}': use a .csv or .parquet file name")
    return fmt


def cmd_simulate(args) -> None:
    """``bondgraph simulate``: :func:`bondgraph.simulate` of the model file, as a table."""
    import numpy as np

    from . import _switched

    fmt = _table_format(args.output)
    if args.plot is not None and Path(args.plot).suffix.lower() != ".png":
        raise CLIError(f"plot '{args.plot}' must end in .png")
    if not (args.t_end > args.t_start) or not all(map(math.isfinite, (args.t_start, args.t_end))):
        raise UsageError(f"--t-end must be finite and after --t-start; got {args.t_start:g} .. "
                         f"{args.t_end:g}")
    if args.points < 2:
        raise UsageError(f"--points must be at least 2; got {args.points}")
    outputs = [Path(args.output)] + ([Path(args.plot)] if args.plot else [])
    _refuse_overwriting_inputs(outputs, args)
    inputs = parse_assignments(args.input, "--input")
    x0 = parse_assignments(args.x0, "--x0")
    given = _given(args)
    from ..modelfile import load_model
    from ..numeric import simulate

    defn = load_model(args.model)
    sm = _switched.switched_of(defn)
    if sm is not None and args.mode is None and args.average is None:
        target = sm
        values = {n: v for n, v in defn.parameters.items()}
        values.update(given or {})
        names = _switched_inputs(sm)
    else:
        target = _switched.chosen_model(args, defn, "simulate")
        values = _values(defn, target, args.params, given, complete=True)
        names = list(target.input_names)
    unknown = sorted(set(inputs) - set(names))
    if unknown:
        raise UsageError(f"--input {unknown[0]!r}: model {defn.name!r} has no input named so; its "
                         f"inputs are {', '.join(names) or '(none)'}")
    grid = np.linspace(args.t_start, args.t_end, args.points).tolist()
    res = simulate(target, values, (args.t_start, args.t_end), x0 or None,
                   u={n: inputs.get(n, 0.0) for n in names}, t_eval=grid, method=args.method,
                   max_step=args.max_step, rtol=args.rtol, atol=args.atol)
    signals = None
    if args.signals is not None:
        signals = [s.strip() for s in args.signals.split(",") if s.strip()]
        missing = [s for s in signals if s not in res]
        if missing:
            raise UsageError(f"--signals {missing[0]!r}: no output, state or input of model "
                             f"{defn.name!r} is named so; valid names: {', '.join(res.names)}")
    columns = _columns(res, signals)
    from .._support.files import atomic_write

    if fmt == "csv":
        text = _csv_text(columns)
        atomic_write(args.output, lambda fh: fh.write(text.encode("utf-8")))
    else:
        data = _parquet_bytes(columns)
        atomic_write(args.output, lambda fh: fh.write(data))
    print(f"wrote {args.output} ({len(res.t)} samples" +
          (f", {len(res.events)} events)" if sm is not None and target is sm else ")"))
    if args.plot:
        _write_plot(res, signals, args.plot, defn.name)
        print(f"wrote {args.plot}")


def _switched_inputs(sm) -> list[str]:
    names: dict = {}
    for mode in sm.modes:
        names.update(dict.fromkeys(s.name for s in sm.derived(mode).user.inputs))
    return list(names)


def _columns(res, signals: Optional[list[str]]) -> dict[str, list]:
    """``t``, the chosen signals, and a switched run's ``mode``: name -> column."""
    chosen = list(res.names) if signals is None else signals
    out: dict[str, list] = {"t": [float(v) for v in res.t]}
    for name in chosen:
        out[name] = [float(v) for v in res[name]]
    out.update({k: list(v) for k, v in res._extra_columns().items()})
    return out


def _csv_text(columns: dict[str, list]) -> str:
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(list(columns))
    for row in zip(*columns.values()):
        writer.writerow([repr(v) if isinstance(v, float) else v for v in row])
    return buf.getvalue()


def _parquet_bytes(columns: dict[str, list]) -> bytes:
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ModuleNotFoundError:
        raise CLIError("a .parquet table needs pyarrow (pip install pyarrow, or the study extra: "
                       "pip install \"bondgraph[study]\"); or write a .csv") from None
    sink = pa.BufferOutputStream()
    pq.write_table(pa.table(columns), sink)
    return sink.getvalue().to_pybytes()


def _write_plot(res, signals, path: str, name: str) -> None:
    import matplotlib

    matplotlib.use("Agg")           # a file, never a window
    import matplotlib.pyplot as plt

    from .._support.files import atomic_write

    ax = res.plot(signals, title=name)
    fig = ax.figure
    try:
        atomic_write(path, lambda fh: fig.savefig(fh, format="png", dpi=120, bbox_inches="tight"))
    finally:
        plt.close(fig)
