"""Command line: ``bondgraph equations | tf | export | draw | simulate | sweep MODEL ...``.

``MODEL`` is a model file (see :mod:`bondgraph.modelfile`): a Python file
whose ``model()`` returns a :class:`~bondgraph.modelfile.ModelDefinition`.
Numeric values are the definition's defaults, overridden by ``--params FILE``
(JSON or TOML: a mapping of parameter names to finite numbers; nested
tables/objects give dotted names, ``[motor] Ra = 1.2`` is ``motor.Ra``).
``tf`` and ``export`` linearize a nonlinear model about an operating point
given by ``--operating-point FILE`` or found by ``--trim`` (see
:mod:`bondgraph.cli._operating`).

Exit status: 0 on success, 1 when the command fails (the reason is printed
as ``error: ...`` on stderr, never a traceback, naming the file at fault),
2 for bad command-line usage (including an operating point whose names or
values do not fit the model), 130 when interrupted (Ctrl-C), 143 on SIGTERM
and 129 on SIGHUP (cleaned up as for Ctrl-C).  Files are
written all or nothing: a failed command leaves no partial or temporary
file, and the ``.c``/``.h`` pair of ``export --format c`` is replaced
together or not at all.

A switched model file (its graph holds switches, :mod:`bondgraph.hybrid`) is
switched in every command: ``equations`` prints every mode, ``simulate``
runs it with its events, ``export -f fmu`` writes every mode with event
indicators, ``draw`` draws the initial mode; ``tf`` and the other exports
take one mode (``--mode on=S``) or the state-space average (``--average d
on=S on=D``) and refuse without one, listing the modes
(:mod:`bondgraph.cli._switched`).

Start-up: this package imports only what ``--help`` needs (no sympy, numpy
or engine); each command imports its modules when it runs
(``bench/bench_cli_startup.py`` measures it).

The package: :mod:`._common` (errors, params files, values),
:mod:`._commands` (equations, tf, export, draw), :mod:`._simulate`,
:mod:`._switched` (modes and averages), :mod:`._operating` (operating
points), :mod:`._sweep`, :mod:`._parser`; :func:`main` here.

Examples
--------
>>> main(["--version"])   # doctest: +ELLIPSIS
bondgraph ...
0
>>> main(["equations", "no/such/model.py"])
1
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Optional, Sequence

from ..errors import BondGraphError
from .._support.formats import EXPORT_FORMATS
from . import _operating
from ._common import CLIError, ParamsFileError, UsageError, load_params
from ._operating import OperatingPointError
from ._parser import build_parser

__all__ = ["main", "build_parser", "load_params", "ParamsFileError", "CLIError", "UsageError",
           "OperatingPointError"]

_EXPORT_FORMATS = EXPORT_FORMATS   # one table with bondgraph.export (tests look for "fmu" in it)


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
                (args.format or EXPORT_FORMATS.get(Path(args.output).suffix.lower(), "c")) != "c":
            parser.error("--name only applies to --format c (a MATLAB function is named after its file)")
        if args.command == "export" and (args.fmi is not None or args.kind is not None) and \
                (args.format or EXPORT_FORMATS.get(Path(args.output).suffix.lower())) != "fmu":
            parser.error("--fmi and --kind only apply to --format fmu")
        if args.command == "tf" and args.params is not None and not args.numeric:
            parser.error("tf: --params is used only with --numeric")
        if args.command in ("tf", "export"):
            problem = _operating.usage_problem(args)
            if problem is not None:
                parser.error(problem)
        if args.command == "tf" and args.trim and not args.numeric:
            parser.error("tf: --trim solves at parameter values: add --numeric")
    except SystemExit as exc:  # --help, --version, usage errors
        return int(exc.code or 0) if not isinstance(exc.code, str) else 2
    from ._signals import ClosedStream, exit_status, signals_as_interrupts

    closed = sys.stdout is None             # started with stdout closed (>&-): Python drops prints
    try:
        if closed:
            sys.stdout = ClosedStream()     # a print is then a failure, not silently lost
        with signals_as_interrupts():       # SIGTERM, SIGHUP: cleaned up as Ctrl-C is
            args.func(args)
    except KeyboardInterrupt as exc:
        _report(str(exc) or "interrupted")
        return exit_status(exc)
    except BrokenPipeError:
        _stdout_to_devnull()
        _report("standard output was closed before everything was printed")
        return 1
    except BondGraphError as exc:     # an option's error names the option, not the model file
        _report(_text(exc) if getattr(exc, "culprit_named", False) else _naming_path(_text(exc), args))
        return getattr(exc, "exit_status", 1)
    except MemoryError:       # a size, not the model file's fault: say what to do
        _report(f"out of memory in 'bondgraph {args.command}': the computation is too large for "
                "this machine (a symbolic result over many parameters?); give numeric values "
                "(--params, and --numeric for tf) or reduce the model")
        return 1
    except Exception as exc:  # anything else is reported the same way: never a traceback
        _report(_naming_path(_message(exc), args))
        return 1
    finally:
        if closed:
            sys.stdout = None  # type: ignore[assignment]
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
    with_output = args.command in ("export", "draw", "sweep", "simulate")
    keys = ("model", "params", "operating_point") + (("output",) if with_output else ())
    paths = [getattr(args, key, None) for key in keys]      # tf's --output is a signal, not a file
    spellings = set()
    for path in filter(None, paths):
        spellings |= {path, os.path.normpath(path), str(Path(path))}
    if any(f"'{spelling}'" in message for spelling in spellings) or not getattr(args, "model", None):
        return message
    return f"model file '{args.model}': {message}"


