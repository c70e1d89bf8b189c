"""Study files for ``bondgraph sweep``: what to vary, fixed values, options (TOML or JSON).

::

    # study.toml
    [sweep]                                   # the varied parameters
    Beq = [1e-3, 1e-2]                        # bounds [lo, hi]: uniform
    "link.b_1" = { bounds = [0.0, 0.05] }     # the same, spelled out
    Kg = { values = [14, 70] }                # explicit values
    Rm = { distribution = "norm", loc = 2.6, scale = 0.1 }   # any scipy.stats distribution

    [values]                                  # fixed values (override the model file's defaults)
    eta_m = 0.69

    [study]                                   # options (the command line overrides them)
    n = 4096
    design = "sobol"                          # sobol | lhs | halton | grid | random
    seed = 1
    metric = ["min_damping", "peak_gain"]

Nested tables give dotted names, as in ``--params`` files (``[sweep.link]
b_1 = [0, 0.05]`` is ``link.b_1``); a table with ``bounds``, ``values`` or
``distribution`` is one parameter's range.  In a file a two-number array is
bounds; explicit values need ``{ values = [...] }``.  Text is never
evaluated: a distribution is looked up by name in ``scipy.stats`` and its
arguments are numbers.

Examples
--------
>>> import tempfile, pathlib
>>> with tempfile.TemporaryDirectory() as d:
...     path = pathlib.Path(d, "study.toml")
...     _ = path.write_text('[sweep]\\nk = [1, 2]\\n[sweep.link]\\nb_1 = { values = [0, 1, 2] }\\n'
...                         '[values]\\nm = 2\\n[study]\\nn = 64\\n')
...     study = load_study(path)
>>> study.parameters, study.values, study.options
({'k': (1.0, 2.0), 'link.b_1': [0.0, 1.0, 2.0]}, {'m': 2.0}, {'n': 64})
"""

from __future__ import annotations

import math
import numbers
import os
from dataclasses import dataclass, field
from typing import Any, Mapping

from ..errors import BondGraphError
from .._support.files import ParamsFileError, flatten_numbers, number_problem, read_table

__all__ = ["StudyFile", "StudyFileError", "load_study", "OPTIONS"]

#: options a ``[study]`` table may give, and their types
OPTIONS = {"n": int, "design": str, "seed": int, "metric": list, "chunk_size": int,
           "input": str, "output": str}
_SPEC_KEYS = {"bounds", "values", "distribution"}


class StudyFileError(BondGraphError, ValueError):
    """A study file is missing, unreadable or malformed; the message names it and the entry."""


@dataclass
class StudyFile:
    """A study file's content: ``parameters`` for :func:`~bondgraph.study.sweep`, fixed
    ``values``, and ``options`` (``n``, ``design``, ``seed``, ``metric``, ...)."""

    parameters: dict[str, Any] = field(default_factory=dict)
    values: dict[str, float] = field(default_factory=dict)
    options: dict[str, Any] = field(default_factory=dict)


def _read(path: "str | os.PathLike[str]") -> tuple[str, str, Mapping]:
    name, data = read_table(path, "study file", StudyFileError)
    what = f"study file '{name}'"
    if not isinstance(data, dict):
        raise StudyFileError(f"{what} must hold a table; got a {type(data).__name__}")
    return name, what, data


def _number(value: Any, where: str) -> float:
    problem = number_problem(value)
    if problem is not None:
        raise StudyFileError(f"{where} {problem}")
    return float(value)


def _range(value: Any, where: str) -> Any:
    if isinstance(value, list):
        if len(value) != 2:
            raise StudyFileError(f"{where}: an array is bounds [lo, hi]; got {len(value)} values "
                                 "(explicit values: { values = [...] })")
        return tuple(_number(v, f"{where}: bound") for v in value)
    keys = set(value) & _SPEC_KEYS
    if len(keys) != 1:
        raise StudyFileError(f"{where}: give exactly one of bounds, values, distribution")
    kind = keys.pop()
    if kind != "distribution":
        extra = sorted(set(value) - {kind})
        if extra:
            raise StudyFileError(f"{where}: unexpected key(s) {', '.join(extra)} beside {kind}")
        items = value[kind]
        if not isinstance(items, list) or not items:
            raise StudyFileError(f"{where}: {kind} must be a non-empty array of numbers")
        if kind == "bounds":
            return _range(items, where)
        return [_number(v, f"{where}: value") for v in items]
    return _distribution(value, where)


def _distribution(value: Mapping, where: str) -> Any:
    import scipy.stats

    name = value["distribution"]
    dist = getattr(scipy.stats, name, None) if isinstance(name, str) and name.isidentifier() else None
    if not isinstance(dist, (scipy.stats.rv_continuous, scipy.stats.rv_discrete)):
        raise StudyFileError(f"{where}: distribution {name!r} is not a scipy.stats distribution "
                             "(norm, uniform, lognorm, truncnorm, ...)")
    kwargs = {k: _number(v, f"{where}: {k}") for k, v in value.items() if k != "distribution"}
    try:
        frozen = dist(**kwargs)
        frozen.ppf(0.5)
    except (TypeError, ValueError) as exc:
        raise StudyFileError(f"{where}: scipy.stats.{name}({', '.join(kwargs)}) cannot be made: "
                             f"{exc}") from None
    if not math.isfinite(float(frozen.ppf(0.5))):
        raise StudyFileError(f"{where}: scipy.stats.{name} with these arguments has no finite median")
    return frozen


def _ranges(table: Any, what: str) -> dict[str, Any]:
    if not isinstance(table, dict):
        raise StudyFileError(f"{what}: [sweep] must be a table of parameter ranges")
    out: dict[str, Any] = {}
    stack = [("", iter(table.items()))]
    while stack:
        prefix, items = stack[-1]
        for key, value in items:
            name = f"{prefix}{key}"
            where = f"{what}: parameter {name!r}"
            if isinstance(value, dict) and not (set(value) & _SPEC_KEYS):
                stack.append((name + ".", iter(value.items())))
                break
            if not isinstance(value, (list, dict)):
                raise StudyFileError(f"{where} must be bounds [lo, hi] or a table with bounds, "
                                     f"values or distribution; got {type(value).__name__}")
            if name in out:
                raise StudyFileError(f"{where} is given twice")
            out[name] = _range(value, where)
        else:
            stack.pop()
    return out


def _options(table: Any, what: str) -> dict[str, Any]:
    if not isinstance(table, dict):
        raise StudyFileError(f"{what}: [study] must be a table of options")
    out = {}
    for key, value in table.items():
        kind = OPTIONS.get(key)
        if kind is None:
            raise StudyFileError(f"{what}: unknown option {key!r} in [study]; options are "
                                 f"{', '.join(OPTIONS)}")
        if kind is int and (isinstance(value, bool) or not isinstance(value, numbers.Integral)):
            raise StudyFileError(f"{what}: option {key} must be an integer; got {value!r}")
        if kind is str and not isinstance(value, str):
            raise StudyFileError(f"{what}: option {key} must be a string; got {value!r}")
        if kind is list:
            value = [value] if isinstance(value, str) else value
            if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                raise StudyFileError(f"{what}: option metric must be a name or an array of names")
        out[key] = value
    return out


def load_study(path: "str | os.PathLike[str]") -> StudyFile:
    """Read a study file (see the module docstring).

    Raises
    ------
    StudyFileError
        Naming the file and the entry at fault.
    """


    name, what, data = _read(path)
    unknown = sorted(set(data) - {"sweep", "values", "study"})
    if unknown:
        raise StudyFileError(f"{what}: unknown table(s) {', '.join(unknown)}; a study file has "
                             "[sweep], [values] and [study]")
    if "sweep" not in data:
        raise StudyFileError(f"{what} has no [sweep] table: name the parameters to vary")
    parameters = _ranges(data["sweep"], what)
    if not parameters:
        raise StudyFileError(f"{what}: [sweep] names no parameter")
    values: dict[str, float] = {}
    if "values" in data:
        if not isinstance(data["values"], dict):
            raise StudyFileError(f"{what}: [values] must be a table of parameter values")
        try:
            values = flatten_numbers(data["values"], name)
        except ParamsFileError as exc:
            raise StudyFileError(str(exc).replace("params file", "study file", 1)) from None
    options = _options(data.get("study", {}), what)
    return StudyFile(parameters, values, options)
