"""Functional Mock-up Units: a model as an ``.fmu`` archive (FMI 2.0 or 3.0, ME and CS).

:func:`export_fmu` writes the archive (atomically: no partial file is ever
left); :func:`build_fmu` returns its bytes.  Either takes a
:class:`~bondgraph.model.Model` or a model file's
:class:`~bondgraph.modelfile.ModelDefinition` (whose default parameter
values become the parameters' start values; ``values`` overrides them).
The archive holds

* ``modelDescription.xml``: a ``DefaultExperiment`` (start 0, a stop time
  covering the slowest mode's settling, a step resolving the fastest, a
  relative tolerance of 1e-6) and every state's ``nominal`` (its size under
  a unit input step), both read from the linearization at rest with the
  parameters' values (:func:`bondgraph.fmu._defaults.run_defaults`), so
  an importer's default settings fit the model; no units (the model
  declares none); the independent variable ``time``; every state
  (start 0; set it through its name), its derivative ``der(<state>)``, every
  input (start 0), output and parameter (``tunable``, start = its value)
  under the model's names (``motor.Ra``); the model structure (outputs,
  derivatives, initial unknowns) with the dependencies read from the
  equations' free symbols, and their kinds (``constant``, ``tunable`` when
  the coefficient holds parameters, ``dependent`` when it is nonlinear);
* ``sources/``: the model's C from :func:`bondgraph.codegen.generate_c`, the
  FMI function layer (``fmi2Functions.c`` or ``fmi3Functions.c``, over a
  version-independent ``bg_fmu_core.h``), the generated ``bg_fmu_config.h``,
  and the standard's header files, taken from the installed ``fmpy``
  package; FMI 3 adds ``sources/buildDescription.xml``.  Any C99 compiler
  builds them: ``cc -std=c99 -shared -fPIC -I sources sources/*.c -lm``;
* ``binaries/<platform>/<modelIdentifier>.so`` (``linux64`` for FMI 2,
  ``x86_64-linux`` for FMI 3), compiled here with the system C compiler
  (``cc``, or ``$CC``), unless ``binary=False``.

Model Exchange: the importer integrates ``x' = f(t, x, u)`` (no events).
Co-Simulation: each ``doStep`` of length ``H`` is split into ``ceil(H / h)``
equal fixed RK4 steps, inputs held over the communication step; ``h`` is
the tunable parameter ``rk4_step`` (default: ``step=``, else 0.05 over the
largest eigenvalue magnitude of the Jacobian at rest with the default
values, 1-2-5 rounded, within [1e-7, 1e-3] s, see :func:`default_step`).

Switched models (:class:`bondgraph.hybrid.SwitchedModel`): the FMU carries the
table of reachable modes; Model Exchange exposes one event indicator per
switch with a guard and changes the mode and re-initialises the state in
event mode; Co-Simulation steps through the events (see
:mod:`bondgraph.fmu._hybrid`).

Implicit models (algebraic unknowns ``z``, ``0 = g(x, z, u)``): the
generated C solves ``g = 0`` by Newton's method at every evaluation; the
instance keeps the last ``z`` as the warm start (part of the FMU state),
the model structure lists the dependencies through ``z``, and a failed
solve returns an error status with a logged message naming the unknowns.

Names: states, inputs and parameters keep the model's names; an output
named like one of them is the same variable when it is that state
(``theta`` of the SRV-02), else gets ``_2``; names with characters FMI or
XML forbid (line breaks, tabs, control characters) are written with
visible escapes and the description carries the model's name.  Names never
reach the C code (the FMI layer works by value reference).

Requires ``fmpy`` for the header files (``pip install 'bondgraph[fmu]'``);
``import bondgraph`` does not import this module or fmpy.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.fmu import build_fmu
>>> g = bg.BondGraph("rc")
>>> V, n = bg.Se("V"), bg.One("i")
>>> g.add(V, n, bg.R("R"), bg.C("C"))
>>> _ = g.connect(V, n); _ = g.connect(n, "R"); _ = g.connect(n, "C")
>>> model = bg.derive(g, outputs={"vC": bg.effort("C")})
>>> data = build_fmu(model, values={"R": 1e3, "C": 1e-6}, binary=False)
>>> import io, zipfile
>>> sorted(zipfile.ZipFile(io.BytesIO(data)).namelist())[:3]
['modelDescription.xml', 'sources/bg_fmu_config.h', 'sources/bg_fmu_core.h']
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Mapping, Optional, Union

from .._support.files import atomic_write, checked_path
from ..model import Model
from ..modelfile import ModelDefinition
from ..parameters import ParameterValues
from ._build import (FMUError, compile_library, library_suffix, platform_folder, standard_headers,
                     token_for, zip_archive)
from ._c_core import CORE, config_header
from ._defaults import run_defaults
from ._plan import Plan, default_step, identifier_for, make_plan

__all__ = ["FMUError", "export_fmu", "build_fmu", "default_step", "KINDS", "VERSIONS"]

#: values of ``kind``: Model Exchange, Co-Simulation, or both in one archive
KINDS = ("me", "cs", "both")
#: values of ``fmi``
VERSIONS = (2, 3)

Target = Union[Model, ModelDefinition]


def _options(fmi: object, kind: object, step: object) -> tuple[int, bool, bool]:
    if isinstance(fmi, bool) or fmi not in VERSIONS:
        raise FMUError(f"fmi must be 2 or 3 (the FMI version); got {fmi!r}")
    if not isinstance(kind, str) or kind not in KINDS:
        raise FMUError(f"kind must be 'me' (Model Exchange), 'cs' (Co-Simulation) or 'both'; got {kind!r}")
    if step is not None and (isinstance(step, bool) or not isinstance(step, (int, float))
                             or not 0.0 < float(step) < float("inf")):
        raise FMUError(f"step (the Co-Simulation RK4 step) must be a positive finite number; got {step!r}")
    return int(fmi), kind in ("me", "both"), kind in ("cs", "both")  # type: ignore[call-overload]


def _model_and_values(target: object, values: Optional[ParameterValues]) -> tuple[Model, list[float]]:
    from ..numeric.resolve import resolve_parameters

    if isinstance(target, ModelDefinition):
        model = target.derive()
        used = {p.name for p in model.parameters}
        merged: dict = {k: v for k, v in target.parameters.items() if k in used}
    elif isinstance(target, Model):
        model, merged = target, {}
    else:
        raise FMUError(f"expected a bondgraph Model or ModelDefinition; got {type(target).__name__}")
    if model.input_derivatives:
        raise FMUError(
            f"model {model.name!r} cannot be an FMU: its equations use time derivatives of inputs "
            f"({', '.join(s.name for s in model.input_derivatives)}), and FMI inputs carry values only; "
            "drive that storage element through a compliance or resistance instead")
    if values is not None:
        if not isinstance(values, Mapping):
            raise FMUError(f"values must be a mapping of parameter name to number; got {type(values).__name__}")
        merged.update(values)
    resolved = resolve_parameters(model.parameters, merged, model=model.name, known=model.known_parameters)
    from ..elements.rules import check_model_values

    check_model_values(model, {p.name: float(v) for p, v in zip(model.parameters, resolved)},
                       where=f"model {model.name!r}: ")
    return model, [float(v) for v in resolved]


def _c_code(model: Model, prefix: str, parameters: list[float]):
    from ..codegen import CodegenError, generate_c

    defaults = {p: v for p, v in zip(model.parameters, parameters)}
    try:
        return generate_c(model, name=prefix, defaults=defaults, header_file=f"{prefix}.h")
    except CodegenError as exc:
        raise FMUError(f"model {model.name!r} cannot be an FMU: {exc}") from exc


def _plan_bytes(plan: Plan) -> bytes:
    return json.dumps([plan.model_name, plan.identifier, [list(v.__dict__.values()) for v in plan.variables],
                       plan.me, plan.cs, plan.experiment, plan.nominals], default=str).encode("utf-8")


def build_fmu(target: Target, *, fmi: int = 2, kind: str = "both",
              values: Optional[ParameterValues] = None, step: Optional[float] = None,
              binary: bool = True, cc: Optional[str] = None, guard_tol: float = 1e-9) -> bytes:
    """The bytes of an ``.fmu`` archive for ``target`` (see the module docstring).

    Parameters
    ----------
    target : Model, ModelDefinition or SwitchedModel
    fmi : {2, 3}
        FMI version.
    kind : {'me', 'cs', 'both'}
        Model Exchange, Co-Simulation, or both.
    values : mapping of str or Symbol to float, optional
        Parameter values (start values of the FMU's parameters); with a
        ModelDefinition they override its defaults.  Every parameter needs
        one; names are checked as everywhere (:mod:`bondgraph.parameters`).
    step : float, optional
        Default of the Co-Simulation parameter ``rk4_step`` (s); default
        :func:`default_step`.
    binary : bool, default True
        Compile the binary for this platform; False gives a source-only FMU.
    cc : str, optional
        The C compiler command (default ``$CC``, else ``cc``, ``gcc`` or ``clang``).
    guard_tol : float, default 1e-9
        Switched models: a guard is consistent while ``>= -guard_tol`` (as in
        :func:`bondgraph.hybrid.simulate`).

    Returns
    -------
    bytes

    Raises
    ------
    FMUError
        The model cannot be an FMU (input derivatives; a name or function the
        C generator refuses), a bad option, fmpy missing, no compiler, or a
        failed compilation; the message says which.
    ParameterValueError
        Missing, unknown or non-finite parameter values.
    """
    version, me, cs = _options(fmi, kind, step)
    if not isinstance(binary, bool):
        raise FMUError(f"binary must be True or False; got {binary!r}")
    from ..hybrid import ModeSet

    if isinstance(target, ModeSet):
        from ._hybrid import build_switched_fmu

        return build_switched_fmu(target, version=version, me=me, cs=cs, values=values, step=step,
                                  binary=binary, cc=cc, guard_tol=guard_tol)
    model, parameters = _model_and_values(target, values)
    headers = standard_headers(version)
    identifier = identifier_for(model.name)
    prefix = f"{identifier}_model"
    code = _c_code(model, prefix, parameters)
    h = (float(step) if step is not None else default_step(model, parameters)) if cs else None
    plan = make_plan(model, parameters, step=h, me=me, cs=cs, identifier=identifier,
                     defaults=run_defaults(model, parameters))

    from .. import __version__
    from ._c_fmi2 import FMI2_LAYER
    from ._c_fmi3 import FMI3_LAYER
    from ._xml import build_description, model_description

    layer_name = f"fmi{version}Functions.c"
    layer = FMI2_LAYER if version == 2 else FMI3_LAYER
    c_files = [f"{prefix}.c", layer_name]
    token = token_for(str(version).encode(), _plan_bytes(plan), code.source.encode(), layer.encode(),
                      CORE.encode())
    sources: dict[str, bytes] = {
        f"{prefix}.c": code.source.encode("utf-8"), f"{prefix}.h": code.header.encode("utf-8"),
        "bg_fmu_config.h": config_header(plan, prefix, f"{prefix}.h", token).encode("utf-8"),
        "bg_fmu_core.h": CORE.encode("utf-8"), layer_name: layer.encode("utf-8"), **headers}
    if version == 3:
        sources["buildDescription.xml"] = build_description(identifier, c_files)
    files = {"modelDescription.xml": model_description(plan, version, token, f"bondgraph {__version__}",
                                                       c_files)}
    files.update({f"sources/{name}": data for name, data in sorted(sources.items())})
    if binary:
        lib = identifier + library_suffix()
        folder = platform_folder(version)
        c_sources = {k: v for k, v in sources.items() if not k.endswith(".xml")}
        files[f"binaries/{folder}/{lib}"] = compile_library(c_sources, c_files, lib, cc=cc)
    return zip_archive(files)


def export_fmu(target: Target, path: Union[str, "os.PathLike[str]"], *, fmi: int = 2, kind: str = "both",
               values: Optional[ParameterValues] = None, step: Optional[float] = None,
               binary: bool = True, cc: Optional[str] = None, guard_tol: float = 1e-9) -> Path:
    """Write ``target`` as an ``.fmu`` archive at ``path``, all or nothing.

    The arguments are those of :func:`build_fmu`; ``path`` must end in
    ``.fmu``.  The archive is built in memory and written to a temporary
    file renamed over ``path`` (:func:`bondgraph._support.files.atomic_write`), so a
    failure anywhere leaves no file, and an existing file as it was.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    FMUError, ParameterValueError
        As :func:`build_fmu`, and a path that does not end in ``.fmu``.
    ExportError
        The file cannot be written (the message names it).

    Examples
    --------
    >>> import bondgraph as bg, tempfile, pathlib
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
    >>> model = bg.derive(g, outputs={"v": bg.flow("m")})
    >>> with tempfile.TemporaryDirectory() as d:
    ...     export_fmu(model, pathlib.Path(d, "mass.fmu"), values={"m": 2.0}, binary=False).name
    'mass.fmu'
    """
    text = checked_path(path, "FMU", FMUError)
    p = Path(text)
    if p.suffix.lower() != ".fmu":
        raise FMUError(f"FMU output '{text}' must end in .fmu")
    data = build_fmu(target, fmi=fmi, kind=kind, values=values, step=step, binary=binary, cc=cc,
                     guard_tol=guard_tol)
    atomic_write(p, lambda fh: fh.write(data), binary=True)
    return p
