"""Operating points on the command line: ``--operating-point FILE`` and ``--trim``.

A nonlinear model has a linear plant only about an operating point (see
:mod:`bondgraph.linear.operating`).  ``bondgraph tf`` and ``bondgraph export`` take
one of:

``--operating-point FILE``
    A ``.json`` or ``.toml`` file with a ``states`` table (a value for every
    state) and an ``inputs`` table (a value for every input; may be left out
    when the model has no inputs)::

        [states]
        p_J = 0.0
        q_grav = 3.141592653589793
        [inputs]
        T = 0.0

    The point must be an equilibrium at the parameter values.

``--trim``
    Solve ``f(x, u) = 0`` for the states (:meth:`bondgraph.Model.equilibrium`)
    at the inputs given by ``--input-value U=V`` (repeatable; inputs not
    given are 0), starting from ``--guess X=V`` and holding ``--fix X=V``.

Problems with these options or with the file (unknown or missing names, a
value that is not a number) are usage errors: exit status 2, nothing
written.

Examples
--------
>>> name_value("T=0.5")
('T', 0.5)
"""

from __future__ import annotations

import argparse
import math
import sys
from typing import Mapping, Optional, Sequence

from ._common import UsageError

__all__ = ["OperatingPointError", "name_value", "add_arguments", "usage_problem",
           "read_operating_point", "check_names", "file_point", "linear_plant", "announce", "HINT"]

#: what the error for a nonlinear model without an operating point adds
HINT = ("give an operating point: --operating-point FILE (a .json/.toml file with [states] and "
        "[inputs]) or --trim (with --input-value U=V for nonzero inputs)")


class OperatingPointError(UsageError):
    """An ``--operating-point`` file or a ``--trim`` option that does not fit the model (exit 2)."""


def name_value(text: str) -> tuple[str, float]:
    """``NAME=VALUE`` of ``--input-value``, ``--guess`` and ``--fix`` (argparse ``type=``).

    Parameters
    ----------
    text : str

    Returns
    -------
    (str, float)

    Raises
    ------
    argparse.ArgumentTypeError
        Without ``=``, with an empty name, or a value that is not a finite number.

    Examples
    --------
    >>> name_value("q_grav=3.14")
    ('q_grav', 3.14)
    >>> name_value("T")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: expected NAME=VALUE (such as T=0.5); got 'T'
    """
    name, eq, value = text.partition("=")
    name = name.strip()
    if not eq or not name:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE (such as T=0.5); got {text!r}")
    try:
        number = float(value)
    except ValueError:
        number = math.nan
    if not math.isfinite(number):
        raise argparse.ArgumentTypeError(f"the value of {name!r} must be a finite number; got {value!r}")
    return name, number


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The operating-point options of ``tf`` and ``export``."""
    group = p.add_argument_group(
        "operating point (nonlinear models)",
        "Linearize about an operating point: a file, or a trim (equilibrium) solved at given inputs.")
    group.add_argument("--operating-point", metavar="FILE",
                       help="JSON or TOML file with a [states] table (every state) and an [inputs] "
                            "table (every input): an equilibrium at the parameter values")
    group.add_argument("--trim", action="store_true",
                       help="solve for the equilibrium states at the inputs of --input-value "
                            "(others 0) and linearize there")
    group.add_argument("--input-value", metavar="U=V", action="append", type=name_value,
                       help="--trim: value of input U (repeatable; inputs not given are 0)")
    group.add_argument("--guess", metavar="X=V", action="append", type=name_value,
                       help="--trim: starting value of state X (repeatable; others start at 0; "
                            "picks among several equilibria)")
    group.add_argument("--fix", metavar="X=V", action="append", type=name_value,
                       help="--trim: hold state X at V (a state no equation determines)")


def usage_problem(args) -> Optional[str]:
    """What is wrong with the combination of operating-point options (None if nothing)."""
    point, trim = getattr(args, "operating_point", None), getattr(args, "trim", False)
    if point is not None and trim:
        return "give --operating-point FILE or --trim, not both"
    if not trim:
        for opt in ("input_value", "guess", "fix"):
            if getattr(args, opt, None):
                return f"--{opt.replace('_', '-')} only applies with --trim"
    return None


def _pairs(pairs: Optional[Sequence[tuple[str, float]]], names: Sequence[str], option: str,
           what: str) -> dict[str, float]:
    out: dict[str, float] = {}
    for name, value in pairs or ():
        if name not in names:
            raise OperatingPointError(f"{option} {name}=...: the model has no {what} named "
                                      f"{name!r}; valid {what}s: {', '.join(names) or '(none)'}")
        if name in out:
            raise OperatingPointError(f"{option}: {what} {name!r} is given twice")
        out[name] = value
    return out


def read_operating_point(path: str) -> tuple[dict, dict]:
    """The ``states`` and ``inputs`` tables of an operating-point file (shapes and numbers checked).

    Parameters
    ----------
    path : str
        A ``.json`` or ``.toml`` file.

    Returns
    -------
    (dict, dict)
        ``{state: value}`` and ``{input: value}`` (names not yet checked
        against a model: see :func:`check_names`).

    Raises
    ------
    OperatingPointError
        Naming the file and the table or name at fault.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d, "op.json")
    ...     _ = p.write_text('{"states": {"q": 0.5}, "inputs": {"F": 1}}')
    ...     read_operating_point(str(p))
    ({'q': 0.5}, {'F': 1.0})
    """
    from .._support.files import number_problem, read_table

    name, data = read_table(path, "operating-point file", OperatingPointError)
    where = f"operating-point file '{name}'"
    if not isinstance(data, dict):
        raise OperatingPointError(f"{where} must hold a mapping with the tables states and inputs; "
                                  f"got a {type(data).__name__}")
    extra = sorted(set(data) - {"states", "inputs"})
    if extra:
        raise OperatingPointError(f"{where}: unknown table {extra[0]!r}; expected states and inputs")
    if "states" not in data:
        raise OperatingPointError(f"{where} has no states table (a value for every state)")
    tables = []
    for table in ("states", "inputs"):
        entries = data.get(table, {})
        if not isinstance(entries, dict):
            raise OperatingPointError(f"{where}: {table} must be a table of names to numbers; "
                                      f"got a {type(entries).__name__}")
        out = {}
        for key, value in entries.items():
            problem = number_problem(value)
            if problem is not None:
                raise OperatingPointError(f"{where}: {table[:-1]} {key!r} {problem}")
            out[key] = float(value)
        tables.append(out)
    return tables[0], tables[1]


def check_names(given: Mapping[str, float], names: Sequence[str], what: str, where: str) -> None:
    """Every name of the model given, none other (:class:`OperatingPointError` otherwise)."""
    unknown = [n for n in given if n not in names]
    if unknown:
        raise OperatingPointError(f"{where}: the model has no {what} named {unknown[0]!r}; "
                                  f"valid {what}s: {', '.join(names) or '(none)'}")
    missing = [n for n in names if n not in given]
    if missing:
        raise OperatingPointError(f"{where}: no value for the {what}{'s' if len(missing) > 1 else ''} "
                                  f"{', '.join(missing)}; an operating point gives every {what}")


def linear_plant(args, model, values: Mapping[str, float], point=None):
    """The numeric plant of ``model`` at the operating point the options ask for.

    ``point`` is the file's ``(states, inputs)`` when already read; the trim
    or the file's point is reported on stderr.
    """
    if args.trim:
        states = list(model.state_names)
        inputs = _pairs(args.input_value, list(model.input_names), "--input-value", "input")
        guess = _pairs(args.guess, states, "--guess", "state")
        fixed = _pairs(args.fix, states, "--fix", "state")
        eq = _trim(args, model, values, inputs, guess, fixed)
        _note(f"trim ({eq.method}, {eq.stability}; {eq.how})", eq.states, eq.inputs)
        return model.linearize(eq)
    x0, u0 = file_point(args, model, point)
    return model.linearize(x0, u0, values=values)


def _trim(args, model, values, inputs, guess, fixed):
    """``model.equilibrium`` with its errors naming where the values came from."""
    from ..errors import ParameterValueError
    from ..linear import EquilibriumError

    try:
        return model.equilibrium(values, inputs, guess=guess, fixed=fixed)
    except ParameterValueError as exc:
        source = (f"params file '{args.params}'" if getattr(args, "params", None) else
                  "the model file's parameter values")
        raise ParameterValueError(f"--trim at the values of the {source}: {exc}") from None
    except EquilibriumError as exc:
        raise EquilibriumError(f"--trim: {exc}") from None


def file_point(args, model, point=None) -> tuple[dict, dict]:
    """The ``--operating-point`` file's states and inputs, checked against the model's names."""
    x0, u0 = point if point is not None else read_operating_point(args.operating_point)
    where = f"operating-point file '{args.operating_point}'"
    check_names(x0, list(model.state_names), "state", where)
    check_names(u0, list(model.input_names), "input", where)
    _note("from the file", x0, u0)
    return x0, u0


def announce(result) -> None:
    """Say on stderr which operating point a linear form was taken about, when it has one (a
    model with constant sources: gravity, an ambient temperature)."""
    point = getattr(result, "operating_point", None)
    if point is not None:
        print(f"note: {point.note}", file=sys.stderr)


def _note(how: str, states: Mapping[str, float], inputs: Mapping[str, float]) -> None:
    def listed(d):
        return ", ".join(f"{k} = {float(v)!r}" for k, v in d.items()) or "-"
    print(f"note: operating point {how}: states {listed(states)}; inputs {listed(inputs)}",
          file=sys.stderr)
