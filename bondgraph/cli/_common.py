"""Shared pieces of the command line: errors, ``--params`` files, parameter values, checks.

Examples
--------
>>> _only(["V"], "input")
'V'
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import ClassVar, Literal, Mapping, Optional, Sequence, overload

from ..errors import BondGraphError, ParameterValueError
from .._support.files import ParamsFileError, load_params  # noqa: F401  (the cli's API)

__all__ = ["CLIError", "UsageError", "ParamsFileError", "load_params"]


class CLIError(BondGraphError, ValueError):
    """A command cannot do what was asked (unknown signal, missing values, ...)."""

    #: the command line's exit status for this error
    exit_status: ClassVar[int] = 1


class UsageError(CLIError):
    """The command line's options do not fit the model (exit status 2, as argparse's usage errors)."""

    exit_status: ClassVar[int] = 2




# --------------------------------------------------------------------------- helpers
def _load_definition(path: str):
    """The model file's :class:`~bondgraph.modelfile.ModelDefinition` (every command loads it here)."""
    from ..modelfile import load_model

    return load_model(path)


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
        from ..parameters import match_values

        try:
            picked = match_values(model.parameters, given, known=model.known_parameters,
                                  partial=True, inputs=[s.name for s in model.inputs], where=f"params file '{params_file}': ")
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


def _only(names: Sequence[str], what: str) -> str:
    if len(names) == 1:
        return names[0]
    raise CLIError(f"the model has {len(names)} {what}s; "
                   f"choose one with --{what}: {', '.join(names) or '(none)'}")


def _transfer_module():
    from .. import tf

    return tf


def _refuse_overwriting_inputs(outputs: Sequence[Path], args) -> None:
    """An output must not replace the model file or a file it is made from."""
    inputs = [("model file", getattr(args, "model", None)), ("params file", getattr(args, "params", None)),
              ("operating-point file", getattr(args, "operating_point", None))]
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
