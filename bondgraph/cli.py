"""Command line: ``bondgraph equations | tf | export | draw | sweep MODEL ...``.

``MODEL`` is a model file (see :mod:`bondgraph.modelfile`): a Python file
whose ``model()`` returns a :class:`~bondgraph.modelfile.ModelDefinition`.
Numeric values are the definition's defaults, overridden by ``--params FILE``
(JSON or TOML: a mapping of parameter names to finite numbers; nested
tables/objects give dotted names, ``[motor] Ra = 1.2`` is ``motor.Ra``).

Exit status: 0 on success, 1 when the command fails (the reason is printed
as ``error: ...`` on stderr, never a traceback, naming the file at fault),
2 for bad command-line usage, 130 when interrupted (Ctrl-C).  Files are
written all or nothing: a failed command leaves no partial or temporary
file, and the ``.c``/``.h`` pair of ``export --format c`` is replaced
together or not at all.

Examples
--------
>>> main(["--version"])   # doctest: +ELLIPSIS
bondgraph ...
0
>>> main(["equations", "no/such/model.py"])
1
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from pathlib import Path
from typing import Literal, Mapping, Optional, Sequence, overload

from ._labels import latex_dot, latex_name, tex
from .errors import BondGraphError, ParameterValueError
from .export import EXPORT_FORMATS
from .parameters import match_values

__all__ = ["main", "build_parser", "load_params", "ParamsFileError", "CLIError"]

_EXPORT_FORMATS = EXPORT_FORMATS   # one table with bondgraph.export


class CLIError(BondGraphError, ValueError):
    """A command cannot do what was asked (unknown signal, missing values, ...)."""


class ParamsFileError(CLIError):
    """A ``--params`` file is missing, unreadable, or not a mapping of names to numbers."""


# --------------------------------------------------------------------------- params files
def load_params(path: "str | os.PathLike[str]") -> dict[str, float]:
    """Read a JSON or TOML parameter file into ``{name: value}``.

    Nested mappings give dotted names (``{"motor": {"Ra": 1}}`` is
    ``motor.Ra``).  Every value must be a finite real number (not a bool, not
    a string).

    Parameters
    ----------
    path : str or path-like
        A ``.json`` or ``.toml`` file.

    Returns
    -------
    dict of str to float

    Raises
    ------
    ParamsFileError
        Naming the file and, for a bad value, the parameter.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d, "p.toml")
    ...     _ = p.write_text('J = 0.01\\n[motor]\\nRa = 1.5\\n')
    ...     load_params(p)
    {'J': 0.01, 'motor.Ra': 1.5}
    """
    from .files import read_table

    name, data = read_table(path, "params file", ParamsFileError)
    what = f"params file '{name}'"
    if not isinstance(data, dict):
        raise ParamsFileError(
            f"{what} must hold a mapping of parameter names to numbers; "
            f"got a {type(data).__name__}")
    return _flatten(data, name)


def _flatten(data: Mapping, path: str) -> dict[str, float]:
    """Nested mappings to dotted names, depth first in file order (no recursion: any depth)."""
    from .export import number_problem

    out: dict[str, float] = {}
    stack = [("", iter(data.items()))]
    while stack:
        prefix, items = stack[-1]
        for key, value in items:
            name = f"{prefix}{key}"
            if isinstance(value, dict):
                stack.append((name + ".", iter(value.items())))
                break
            problem = number_problem(value)
            if problem is not None:
                raise ParamsFileError(f"params file '{path}': parameter {name!r} {problem}")
            if name in out:
                raise ParamsFileError(f"params file '{path}': parameter {name!r} is given twice")
            out[name] = float(value)
        else:
            stack.pop()
    return out


# --------------------------------------------------------------------------- helpers
def _load(path: str):
    from .modelfile import load_model

    defn = load_model(path)
    return defn, defn.derive()


def _given(args) -> Optional[dict[str, float]]:
    """The ``--params`` file's values, read before the model (a bad file fails fast)."""
    return None if args.params is None else load_params(args.params)


@overload
def _values(defn, model, params_file: Optional[str], given: Optional[Mapping[str, float]], *,
            complete: Literal[True]) -> dict[str, float]: ...


@overload
def _values(defn, model, params_file: Optional[str], given: Optional[Mapping[str, float]], *,
            complete: bool) -> Optional[dict[str, float]]: ...


def _values(defn, model, params_file: Optional[str], given: Optional[Mapping[str, float]], *,
            complete: bool) -> Optional[dict[str, float]]:
    """Defaults overridden by the params file's values ``given``; checked against the model's parameters."""
    expected = [p.name for p in model.parameters]
    known = set(expected)
    # a model file may give defaults for parameters that only some of its variants use
    values = {n: v for n, v in defn.parameters.items() if n in known}
    if given is not None:
        # the package-wide policy: unknown names listed with the valid ones, names the
        # model definition knows but this variant does not use accepted
        try:
            picked = match_values(model.parameters, given, known=model.known_parameters,
                                  partial=True, where=f"params file '{params_file}': ")
        except ParameterValueError as exc:
            raise CLIError(str(exc)) from None
        values.update({p.name: v for p, v in picked.items()})
    missing = [n for n in expected if n not in values]
    if missing:
        if complete:
            raise CLIError(f"no value for parameters {', '.join(missing)} (the model file has no "
                           "default for them); give them in a --params FILE (JSON or TOML)")
        return None
    return {n: values[n] for n in expected}


def _check_signal(name: str, names: Sequence[str], what: str) -> None:
    if name not in names:
        raise CLIError(f"the model has no {what} named {name!r}; "
                       f"valid {what}s: {', '.join(names) or '(none)'}")


def _transfer_module():
    for modname in ("bondgraph.transfer", "bondgraph.tf"):
        try:
            module = importlib.import_module(modname)
        except ModuleNotFoundError as exc:
            if exc.name not in (modname, "bondgraph.tf"):
                raise
            continue
        if hasattr(module, "transfer_function"):
            return module
    raise CLIError("symbolic transfer functions need bondgraph.transfer (not available in this "
                   "installation)")


# --------------------------------------------------------------------------- commands
def _cmd_equations(args) -> None:

    defn, model = _load(args.model)
    out = [f"model {model.name!r}" + (f": {defn.description}" if defn.description else "")]
    for title, names in (("states", model.state_names), ("inputs", model.input_names),
                         ("outputs", model.output_names)):
        out.append(f"{title} ({len(names)}): {', '.join(names) or '-'}")
    params = [f"{p.name} = {defn.parameters[p.name]:g}" if p.name in defn.parameters else p.name
              for p in model.parameters]
    out.append(f"parameters ({len(params)}): {', '.join(params) or '-'}")
    out.append("")
    if args.latex:
        # the one LaTeX naming helper of the package (bondgraph._labels): \dot{p}_{La}
        lines = [f"{latex_dot(s.name)} &= {tex(r)}" for s, r in zip(model.states, model.rhs)]
        lines += [f"{latex_name(n)} &= {tex(g)}" for n, g in zip(model.output_names, model.output_exprs)]
        out += ["\\begin{aligned}", " \\\\\n".join(lines), "\\end{aligned}"]
    else:
        out += [f"d{s.name}/dt = {r}" for s, r in zip(model.states, model.rhs)]
        out += [f"{n} = {g}" for n, g in zip(model.output_names, model.output_exprs)]
    print("\n".join(out))


def _cmd_tf(args) -> None:
    given = _given(args)
    defn, model = _load(args.model)
    ss = model.state_space()
    inp = args.input if args.input is not None else _only(ss.input_names, "input")
    outp = args.output if args.output is not None else _only(ss.output_names, "output")
    _check_signal(inp, ss.input_names, "input")
    _check_signal(outp, ss.output_names, "output")
    values = _values(defn, model, args.params, given, complete=True) if args.numeric else None
    tfmod = _transfer_module()
    G = tfmod.transfer_function(ss.A, ss.B, ss.C, ss.D, input=inp, output=outp,
                                input_names=list(ss.input_names), output_names=list(ss.output_names))
    if values is None:
        print(G.to_latex() if args.latex else str(G))
        return
    N = G.subs(values)
    print(N.to_latex() if args.latex else str(N))
    table = N.table()
    if table.rows:
        print()
        print(table.to_latex() if args.latex else str(table))


def _only(names: Sequence[str], what: str) -> str:
    if len(names) == 1:
        return names[0]
    raise CLIError(f"the model has {len(names)} {what}s; "
                   f"choose one with --{what}: {', '.join(names) or '(none)'}")


def _export_format(args) -> str:
    """The export format, and the output's suffix checked against it (before any work)."""
    out = Path(args.output)
    fmt = args.format
    if fmt is None:
        fmt = _EXPORT_FORMATS.get(out.suffix.lower())
        if fmt is None:
            raise CLIError(f"cannot tell the export format from '{args.output}'; give --format "
                           f"{'|'.join(sorted(set(_EXPORT_FORMATS.values())))}")
    if fmt == "c" and out.suffix not in ("", ".c"):
        raise CLIError(f"C output '{args.output}' must end in .c (the header is written beside it as .h)")
    if fmt == "fmu" and out.suffix.lower() != ".fmu":
        raise CLIError(f"FMU output '{args.output}' must end in .fmu")
    if fmt in ("m", "py") and out.suffix != f".{fmt}":
        language = "MATLAB" if fmt == "m" else "Python"
        raise CLIError(f"{language} output '{args.output}' must end in .{fmt}")
    return fmt


def _cmd_export(args) -> None:
    fmt = _export_format(args)
    out = Path(args.output)
    _refuse_overwriting_inputs([out.with_suffix(".c"), out.with_suffix(".h")] if fmt == "c" else [out],
                               args)
    given = _given(args)
    defn, model = _load(args.model)
    if fmt in ("mat", "npz", "json"):
        from .export import export
        from .numeric import compile_plant

        full = _values(defn, model, args.params, given, complete=True)
        plant = compile_plant(model).plant(full)
        export(plant, out, format=fmt)
        print(f"wrote {out}")
        return
    if fmt == "fmu":
        from .fmu import export_fmu

        full = _values(defn, model, args.params, given, complete=True)
        export_fmu(defn, out, fmi=args.fmi or 2, kind=args.kind or "both", values=full)
        print(f"wrote {out}")
        return
    values = _values(defn, model, args.params, given, complete=False)
    if values is None:
        print("note: not every parameter has a value; the generated code has no defaults",
              file=sys.stderr)
    if fmt == "c":
        from .codegen import write_c

        src, hdr = write_c(model, out, name=args.name, defaults=values)
        print(f"wrote {src}\nwrote {hdr}")
    elif fmt == "m":
        from .codegen import write_matlab

        print(f"wrote {write_matlab(model, out, defaults=values)}")
    else:
        from .codegen import write_python

        print(f"wrote {write_python(model, out, defaults=values)}")


def _refuse_overwriting_inputs(outputs: Sequence[Path], args) -> None:
    """An output must not replace the model file or the params file it is made from."""
    inputs = [("model file", getattr(args, "model", None)), ("params file", getattr(args, "params", None))]
    for out in outputs:
        for what, source in inputs:
            if source and _same_file(out, source):
                raise CLIError(f"output '{out}' is the {what} '{source}' itself; choose another output")


def _same_file(a: "str | os.PathLike[str]", b: "str | os.PathLike[str]") -> bool:
    try:
        return os.path.samefile(a, b)
    except (OSError, ValueError):       # one does not exist (yet), or a NUL in a name
        try:
            return os.path.realpath(a) == os.path.realpath(b)
        except (OSError, ValueError):
            return False


_DRAW_FORMATS = ("svg", "png")


def _cmd_draw(args) -> None:
    out = Path(args.output)
    kind = args.format or out.suffix.lower().lstrip(".")
    if kind not in _DRAW_FORMATS:
        raise CLIError(f"cannot tell the drawing format from '{args.output}'; use a .svg or .png "
                       "file name, or give --format svg|png")
    _refuse_overwriting_inputs([out], args)
    from .export import atomic_write
    from .modelfile import load_model

    defn = load_model(args.model)
    try:
        drawing = importlib.import_module("bondgraph.drawing")
    except ModuleNotFoundError as exc:
        if exc.name not in ("bondgraph.drawing",):
            raise
        raise CLIError("drawing needs bondgraph.drawing (not available in this installation)") from None
    # drawn here and written through atomic_write, so that a failure names the target file
    scene = drawing.build_scene(drawing.diagram(defn.graph, causality=not args.no_causality))
    if kind == "svg":
        data = drawing.scene_to_svg(scene).encode("utf-8")
        atomic_write(out, lambda fh: fh.write(data))
    else:
        atomic_write(out, lambda fh: drawing.write_png(scene, fh))
    print(f"wrote {args.output}")


_SWEEP_FORMATS = {".csv": "csv", ".parquet": "parquet"}


def _cmd_sweep(args) -> None:
    """``bondgraph sweep``: a parameter study (bondgraph.study) written as CSV or parquet."""
    import warnings

    from .files import atomic_write
    from .study import StudyWarning, sweep
    from .study._deps import require
    from .study.config import load_study

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
        from .study.metrics import BUILTIN

        raise CLIError(f"no metric: give --metric NAME ({', '.join(BUILTIN)}) or metric = [...] "
                       f"in the [study] table of '{args.params}'")
    from .modelfile import load_model

    defn = load_model(args.model)
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
        from .study._deps import require

        distributed = require("distributed", "--scheduler (Dask)")
        try:
            client = distributed.Client(args.scheduler, timeout="10s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise CLIError(f"cannot reach the Dask scheduler at {args.scheduler!r}: {exc}") from None
        return client, client.close
    return None, lambda: None


# --------------------------------------------------------------------------- parser
def build_parser() -> argparse.ArgumentParser:
    """The argument parser (exposed for documentation tools and tests).

    Returns
    -------
    argparse.ArgumentParser
        With sub-commands ``equations``, ``tf``, ``export``, ``draw`` and ``sweep``.

    Examples
    --------
    >>> args = build_parser().parse_args(["export", "motor.py", "-o", "motor.json"])
    >>> args.command, args.model, args.output, args.format
    ('export', 'motor.py', 'motor.json', None)
    """
    from . import __version__

    parser = argparse.ArgumentParser(
        prog="bondgraph",
        description="Bond graphs to state equations, transfer functions, numeric plants and code.",
        epilog="MODEL is a Python file defining model() -> bondgraph.modelfile.ModelDefinition. "
               "Model files are executed: run only files you trust.")
    parser.add_argument("--version", action="version", version=f"bondgraph {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    p = sub.add_parser("equations", help="print the state equations and outputs",
                       description="Print the model's states, inputs, outputs, parameters "
                                   "(with default values) and equations x' = f(x, u), y = g(x, u).")
    p.add_argument("model", metavar="MODEL", help="model file (.py)")
    p.add_argument("--latex", action="store_true", help="print the equations as LaTeX (aligned)")
    p.set_defaults(func=_cmd_equations)

    p = sub.add_parser("tf", help="print a transfer function",
                       description="Print the transfer function from one input to one output, "
                                   "symbolic or (--numeric) with parameter values.")
    p.add_argument("model", metavar="MODEL", help="model file (.py)")
    p.add_argument("--input", "-u", metavar="U", help="input name (optional if there is one input)")
    p.add_argument("--output", "-y", metavar="Y", help="output name (optional if there is one output)")
    p.add_argument("--latex", action="store_true", help="print LaTeX")
    p.add_argument("--numeric", action="store_true",
                   help="substitute parameter values (defaults, overridden by --params) and "
                        "print poles and zeros")
    p.add_argument("--params", metavar="FILE", help="parameter values, JSON or TOML")
    p.set_defaults(func=_cmd_tf)

    p = sub.add_parser("export", help="export a numeric plant or generate code",
                       description="Write the numeric plant (mat, npz, json; every parameter needs a "
                                   "value), code for the equations (c: .c and .h; m: MATLAB/Octave "
                                   "function; py: plain Python module) or an FMU (fmu: FMI 2.0 or 3.0, "
                                   "Model Exchange and/or Co-Simulation, compiled with cc; every "
                                   "parameter needs a value). Files are written atomically.")
    p.add_argument("model", metavar="MODEL", help="model file (.py)")
    p.add_argument("--format", "-f", choices=list(dict.fromkeys(EXPORT_FORMATS.values())),
                   help="output format (default: from the output file's suffix)")
    p.add_argument("--params", metavar="FILE", help="parameter values, JSON or TOML")
    p.add_argument("--name", metavar="NAME", help="C symbol prefix (default: the model's name)")
    p.add_argument("--fmi", type=int, choices=[2, 3], help="FMU: FMI version (default 2)")
    p.add_argument("--kind", choices=["me", "cs", "both"],
                   help="FMU: Model Exchange, Co-Simulation (fixed-step RK4) or both (default)")
    p.add_argument("-o", "--output", metavar="OUT", required=True, help="output file")
    p.set_defaults(func=_cmd_export)

    p = sub.add_parser("draw", help="draw the bond graph (SVG or PNG)",
                       description="Draw the bond graph with causal strokes to an SVG or PNG file.")
    p.add_argument("model", metavar="MODEL", help="model file (.py)")
    p.add_argument("-o", "--output", metavar="FILE", required=True, help="output file, .svg or .png")
    p.add_argument("--format", "-f", choices=["svg", "png"], help="default: from the file's suffix")
    p.add_argument("--no-causality", action="store_true", help="omit causal strokes")
    p.set_defaults(func=_cmd_draw)

    from .study.design import DESIGNS
    from .study.metrics import BUILTIN

    p = sub.add_parser("sweep", help="parameter study: sample parameters, tabulate plant metrics",
                       description="Vary the parameters of the study file's [sweep] table (bounds, "
                                   "value lists or scipy.stats distributions; the others take the "
                                   "model file's defaults and the [values] table), evaluate the "
                                   "metrics of every sample's numeric plant and write one row per "
                                   "sample (CSV or parquet, written atomically). Needs the study "
                                   "extra: pip install \"bondgraph[study]\".")
    p.add_argument("model", metavar="MODEL", help="model file (.py)")
    p.add_argument("--params", metavar="FILE", required=True,
                   help="study file, TOML or JSON: [sweep] ranges, [values], [study] options")
    p.add_argument("--n", type=int, metavar="N", help="number of samples (default 1024)")
    p.add_argument("--design", choices=DESIGNS, help="sampling design (default sobol)")
    p.add_argument("--seed", type=int, metavar="S", help="design seed (default: a fresh one, "
                                                         "printed)")
    p.add_argument("--metric", action="append", choices=list(BUILTIN), metavar="NAME",
                   help=f"metric, repeatable: {', '.join(BUILTIN)}")
    p.add_argument("--input", "-u", metavar="U", help="input of channel metrics (gains, step)")
    p.add_argument("--output-signal", "-y", metavar="Y", help="output of channel metrics")
    p.add_argument("--workers", type=int, metavar="K", help="run on K local worker processes")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on a running Dask scheduler (tcp://host:8786)")
    p.add_argument("--chunk-size", type=int, metavar="C", help="samples per task")
    p.add_argument("--no-progress", action="store_true",
                   help="no progress bar (shown only when stderr is a terminal)")
    p.add_argument("-o", "--output", metavar="OUT", required=True, help="output table, .csv or .parquet")
    p.set_defaults(func=_cmd_sweep)
    return parser


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Run the command line; returns the exit status (0 success, 1 failure, 2 usage, 130 interrupted).

    Never raises and never prints a traceback: every failure is one line
    ``error: <message>`` on stderr naming the file at fault (the model file
    when the message names no path of its own).

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments without the program name; default ``sys.argv[1:]``.

    Returns
    -------
    int
        The exit status.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> src = ('import bondgraph as bg\\n'
    ...        'from bondgraph.modelfile import ModelDefinition\\n'
    ...        'def model():\\n'
    ...        '    g = bg.BondGraph("mass"); g.add(bg.Se("F"), bg.I("m")); g.connect("F", "m")\\n'
    ...        '    return ModelDefinition(g, {"v": bg.flow("m")}, {"m": 2.0})\\n')
    >>> with tempfile.TemporaryDirectory() as d:
    ...     path = pathlib.Path(d, "mass.py")
    ...     _ = path.write_text(src)
    ...     main(["equations", str(path)])
    model 'mass'
    states (1): p_m
    inputs (1): F
    outputs (1): v
    parameters (1): m = 2
    <BLANKLINE>
    dp_m/dt = F
    v = p_m/m
    0
    """
    parser = build_parser()
    try:
        args = parser.parse_args(list(argv) if argv is not None else None)
        if args.command == "export" and args.name is not None and \
                (args.format or _EXPORT_FORMATS.get(Path(args.output).suffix.lower(), "c")) != "c":
            parser.error("--name only applies to --format c (a MATLAB function is named after its file)")
        if args.command == "export" and (args.fmi is not None or args.kind is not None) and \
                (args.format or _EXPORT_FORMATS.get(Path(args.output).suffix.lower())) != "fmu":
            parser.error("--fmi and --kind only apply to --format fmu")
        if args.command == "tf" and args.params is not None and not args.numeric:
            parser.error("tf: --params is used only with --numeric")
    except SystemExit as exc:  # --help, --version, usage errors
        return int(exc.code or 0) if not isinstance(exc.code, str) else 2
    try:
        args.func(args)
    except KeyboardInterrupt as exc:
        _report(str(exc) or "interrupted")
        return 130
    except BrokenPipeError:
        _stdout_to_devnull()
        _report("standard output was closed before everything was printed")
        return 1
    except BondGraphError as exc:
        _report(_naming_path(_text(exc), args))
        return 1
    except Exception as exc:  # anything else is reported the same way: never a traceback
        _report(_naming_path(_message(exc), args))
        return 1
    return 0


def _report(message: str) -> None:
    try:
        print(f"error: {message}", file=sys.stderr)
    except (OSError, ValueError):      # stderr closed: the exit status still tells
        pass


def _stdout_to_devnull() -> None:
    """After a broken pipe: no second error when Python flushes stdout at exit."""
    try:
        fd = os.open(os.devnull, os.O_WRONLY)
        os.dup2(fd, sys.stdout.fileno())
        os.close(fd)
    except (OSError, ValueError, AttributeError):   # stdout has no file descriptor (captured)
        pass


def _text(exc: BaseException) -> str:
    try:
        return str(exc) or type(exc).__name__
    except Exception:
        return type(exc).__name__


def _message(exc: BaseException) -> str:
    """An unexpected exception's message: its type (it says what went wrong) and text."""
    if isinstance(exc, OSError) and exc.filename:
        return f"{exc.strerror or _text(exc)}: '{exc.filename}'"
    return f"{type(exc).__name__}: {_text(exc)}"


def _naming_path(message: str, args) -> str:
    """``message``, prefixed with the model file when it names none of the user's paths."""
    with_output = args.command in ("export", "draw", "sweep")
    keys = ("model", "params", "output") if with_output else ("model", "params")
    paths = [getattr(args, key, None) for key in keys]      # tf's --output is a signal, not a file
    spellings = set()
    for path in filter(None, paths):
        spellings |= {path, os.path.normpath(path), str(Path(path))}
    if any(f"'{spelling}'" in message for spelling in spellings) or not getattr(args, "model", None):
        return message
    return f"model file '{args.model}': {message}"


if __name__ == "__main__":  # python -m bondgraph.cli
    sys.exit(main())
