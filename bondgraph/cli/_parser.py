"""The argument parser of the command line.

Examples
--------
>>> args = build_parser().parse_args(["tf", "pendulum.py", "--numeric", "--trim",
...                                   "--guess", "q_grav=3"])
>>> args.trim, args.guess
(True, [('q_grav', 3.0)])
"""

from __future__ import annotations

import argparse

from .._support.formats import EXPORT_FORMATS
from . import _operating, _simulate, _switched
from ._commands import cmd_draw, cmd_equations, cmd_export, cmd_tf
from ._sweep import cmd_sweep

__all__ = ["build_parser", "SWEEP_DESIGNS", "SWEEP_METRICS"]

#: the designs and metrics of :mod:`bondgraph.study` (written here so that ``--help`` does not
#: import the study package; tests/cli/test_switched_cli.py checks they are the same)
SWEEP_DESIGNS = ("sobol", "lhs", "halton", "grid", "random")
SWEEP_METRICS = ("max_real", "min_damping", "dc_gain", "peak_gain", "bandwidth", "overshoot",
                 "settling_time", "step")


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
    from .. import __version__

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
    _switched.add_arguments(p)
    p.set_defaults(func=cmd_equations)

    p = sub.add_parser("tf", help="print a transfer function",
                       description="Print the transfer function from one input to one output, "
                                   "symbolic or (--numeric) with parameter values. A nonlinear "
                                   "model is linearized about an operating point: a file "
                                   "(--operating-point; symbolic parameters allowed when the point "
                                   "is an equilibrium for all of them) or a trim (--trim, needs "
                                   "--numeric). The operating point found is printed on stderr.")
    p.add_argument("model", metavar="MODEL", help="model file (.py)")
    p.add_argument("--input", "-u", metavar="U", help="input name (optional if there is one input)")
    p.add_argument("--output", "-y", metavar="Y", help="output name (optional if there is one output)")
    p.add_argument("--latex", action="store_true", help="print LaTeX")
    p.add_argument("--numeric", action="store_true",
                   help="substitute parameter values (defaults, overridden by --params) and "
                        "print poles and zeros")
    p.add_argument("--params", metavar="FILE", help="parameter values, JSON or TOML")
    _operating.add_arguments(p)
    _switched.add_arguments(p)
    p.set_defaults(func=cmd_tf)

    p = sub.add_parser("export", help="export a numeric plant or generate code",
                       description="Write the numeric plant (mat, npz, json; every parameter needs a "
                                   "value), code for the equations (c: .c and .h; m: MATLAB/Octave "
                                   "function; py: plain Python module) or an FMU (fmu: FMI 2.0 or 3.0, "
                                   "Model Exchange and/or Co-Simulation, compiled with cc; every "
                                   "parameter needs a value). Files are written atomically. A "
                                   "nonlinear model's plant (mat, npz, json) is its linearization "
                                   "about an operating point: --operating-point FILE or --trim "
                                   "(deviation variables x - x0, u - u0; the point is printed on "
                                   "stderr).")
    p.add_argument("model", metavar="MODEL", help="model file (.py)")
    p.add_argument("--format", "-f", choices=list(dict.fromkeys(EXPORT_FORMATS.values())),
                   help="output format (default: from the output file's suffix)")
    p.add_argument("--params", metavar="FILE", help="parameter values, JSON or TOML")
    p.add_argument("--name", metavar="NAME", help="C symbol prefix (default: the model's name)")
    p.add_argument("--fmi", type=int, choices=[2, 3], help="FMU: FMI version (default 2)")
    p.add_argument("--kind", choices=["me", "cs", "both"],
                   help="FMU: Model Exchange, Co-Simulation (fixed-step RK4) or both (default)")
    p.add_argument("-o", "--output", metavar="OUT", required=True, help="output file")
    _operating.add_arguments(p)
    _switched.add_arguments(p)
    p.set_defaults(func=cmd_export)

    p = sub.add_parser("draw", help="draw the bond graph (SVG, PNG or TikZ)",
                       description="Draw the bond graph with causal strokes to an SVG, PNG or "
                                   "TikZ (.tex) file. The .tex file is a LaTeX document that "
                                   "pdflatex compiles on its own (article + tikz), or with "
                                   "--tikz-only the tikzpicture alone, for \\input into a "
                                   "document that loads tikz.")
    p.add_argument("model", metavar="MODEL", help="model file (.py)")
    p.add_argument("-o", "--output", metavar="FILE", required=True,
                   help="output file, .svg, .png or .tex")
    p.add_argument("--format", "-f", choices=["svg", "png", "tex"],
                   help="default: from the file's suffix")
    p.add_argument("--no-causality", action="store_true", help="omit causal strokes")
    p.add_argument("--tikz-only", action="store_true",
                   help="TikZ: write only the tikzpicture environment (for \\input)")
    p.add_argument("--max-width", type=float, default=17.0, metavar="CM",
                   help="wrap the layout to fit this width in cm with labels at --font-pt "
                        "(default 17, a two-column page; 0: no limit)")
    p.add_argument("--font-pt", type=float, default=8.0, metavar="PT",
                   help="label size in points for --max-width and the TikZ picture (default 8)")
    p.add_argument("--no-title", action="store_true", help="omit the model's name")
    p.add_argument("--no-prefixes", action="store_true",
                   help="labels without sub-model prefixes (I:m_1 for I:link.m_1)")
    p.add_argument("--no-numbers", action="store_true", help="omit the bond numbers")
    p.add_argument("--latex", action="store_true", help="TikZ: element names as LaTeX math")
    _switched.add_arguments(p, average=False)
    p.set_defaults(func=cmd_draw)
    _simulate.add_parser(sub)

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
    p.add_argument("--design", choices=SWEEP_DESIGNS, help="sampling design (default sobol)")
    p.add_argument("--seed", type=int, metavar="S", help="design seed (default: a fresh one, "
                                                         "printed)")
    p.add_argument("--metric", action="append", choices=SWEEP_METRICS, metavar="NAME",
                   help=f"metric, repeatable: {', '.join(SWEEP_METRICS)}")
    p.add_argument("--input", "-u", metavar="U", help="input of channel metrics (gains, step)")
    p.add_argument("--output-signal", "-y", metavar="Y", help="output of channel metrics")
    p.add_argument("--workers", type=int, metavar="K", help="run on K local worker processes")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on a running Dask scheduler (tcp://host:8786)")
    p.add_argument("--chunk-size", type=int, metavar="C", help="samples per task")
    p.add_argument("--no-progress", action="store_true",
                   help="no progress bar (shown only when stderr is a terminal)")
    p.add_argument("-o", "--output", metavar="OUT", required=True, help="output table, .csv or .parquet")
    p.set_defaults(func=cmd_sweep)
    return parser
