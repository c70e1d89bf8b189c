"""C99 code for a model: a self-contained ``.c`` / ``.h`` pair.

The header declares, for a model prefix ``NAME`` (the model's name unless
given)::

    #define NAME_NX, NAME_NU, NAME_NY, NAME_NP        /* sizes */
    extern const char *const NAME_state_names[];      /* NX names, then NULL */
    extern const char *const NAME_input_names[];      /* likewise */
    extern const char *const NAME_output_names[];
    extern const char *const NAME_parameter_names[];
    extern const double NAME_default_parameters[];    /* if defaults were given */
    void NAME_derivatives(double t, const double *x, const double *u, const double *p, double *xdot);
    void NAME_outputs(double t, const double *x, const double *u, const double *p, double *y);
    void NAME_step_euler(double t, double h, double *x, const double *u, const double *p);
    void NAME_step_rk4(double t, double h, double *x, const double *u, const double *p);

``x``, ``u``, ``p``, ``xdot`` and ``y`` are arrays in the order listed in the
header comment (the model's ``state_names``, ``input_names``,
``parameter_names`` -- sorted by name -- and ``output_names``).  The step
functions advance ``x`` in place from ``t`` to ``t + h`` with ``u`` held
constant over the step (fixed step, no allocation: fit for real time).  The
code needs only ``<math.h>`` (link with ``-lm``) and compiles warning-free
with ``-std=c99 -Wall -Wextra -pedantic``.

Names are never pasted raw: the name arrays hold C string literals of the
names' UTF-8 bytes (:func:`c_string`: octal escapes, no trigraphs), and the
comments show a name that is not a plain (dotted) identifier as an escaped
literal with no ``*/``, ``/*`` or ``??`` in it (:func:`c_comment`).

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("rc")
>>> V, n = bg.Se("V"), bg.One("i")
>>> g.add(V, n, bg.R("R"), bg.C("C"))
>>> _ = g.connect(V, n); _ = g.connect(n, "R"); _ = g.connect(n, "C")
>>> code = generate_c(bg.derive(g, outputs={"vC": bg.effort("C")}))
>>> print(code.source.split("void rc_derivatives")[1].split("}")[0].strip())
(double t, const double *x, const double *u, const double *p, double *xdot)
{
    const double q_C = x[0];
    const double V = u[0];
    const double C = p[0];
    const double R = p[1];
    (void)t;
    xdot[0] = (V - q_C/C)/R;
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Mapping, Optional, Sequence, Union

import sympy
from sympy.printing.c import C99CodePrinter

from ..model import Model
from ._common import (C_RESERVED, CodegenError, PreparedModel, TargetPrinter, check_identifier,
                      header_lines, prepare, shown, split_cse)

__all__ = ["CCode", "generate_c", "write_c", "c_string", "c_comment"]


class _Printer(TargetPrinter, C99CodePrinter):
    """C99 printer: doubles printed exactly (shortest repr), unknown functions refused."""

    missing = "C has no function"

    def __init__(self) -> None:
        super().__init__({"strict": True, "error_on_reserved": True})

    def _print_Float(self, expr) -> str:
        text = super()._print_Float(expr)
        return text if any(c in text for c in ".en") else text + ".0"


#: values of the POSIX constants sympy's C printer may emit (not in strict C99)
_MACRO_VALUES = {
    "M_E": math.e, "M_LOG2E": 1 / math.log(2), "M_LOG10E": 1 / math.log(10), "M_LN2": math.log(2),
    "M_LN10": math.log(10), "M_PI": math.pi, "M_PI_2": math.pi / 2, "M_PI_4": math.pi / 4,
    "M_1_PI": 1 / math.pi, "M_2_PI": 2 / math.pi, "M_2_SQRTPI": 2 / math.sqrt(math.pi),
    "M_SQRT2": math.sqrt(2), "M_SQRT1_2": math.sqrt(0.5),
}


@dataclass(frozen=True)
class CCode:
    """Generated C: ``source`` (``.c``) and ``header`` (``.h``) text.

    Attributes
    ----------
    name : str
        The C prefix of every symbol.
    header_file : str
        The file name the source ``#include``\\ s.
    identifiers : mapping of str to str
        Model name of each state, input and parameter -> C identifier used
        in the code (they differ when a name is not a C identifier, such as
        ``motor.Ra`` -> ``motor_Ra``).
    header, source : str
        The text of the ``.h`` and ``.c`` files.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> _ = g.connect("F", "m")
    >>> model = bg.derive(g, outputs={"v": bg.flow("m")})
    >>> code = generate_c(model, defaults={"m": 2.0})
    >>> code.name, code.header_file, dict(code.identifiers)
    ('mass', 'mass.h', {'p_m': 'p_m', 'F': 'F', 'm': 'm'})
    >>> [line.strip() for line in code.source.splitlines() if "xdot[0] =" in line or "y[0] =" in line]
    ['xdot[0] = F;', 'y[0] = p_m/m;']
    """

    name: str
    header_file: str
    header: str
    source: str
    identifiers: Mapping[str, str]


def _function_body(pm: PreparedModel, exprs: Sequence[sympy.Expr], out: str, where: str) -> list[str]:
    printer = _Printer()
    reps, reduced = split_cse(exprs, pm.taken)
    used = set()
    for ex in list(reduced) + [r for _, r in reps]:
        used |= {s.name for s in ex.free_symbols}
    lines = []
    arrays = (("x", pm.state_ids), ("u", pm.input_ids), ("p", pm.parameter_ids),
              ("z", pm.algebraic_ids))
    for arr, ids in arrays:
        for k, ident in enumerate(ids):
            if ident in used:
                lines.append(f"    const double {ident} = {arr}[{k}];")
    for sym, ex in reps:
        lines.append(f"    const double {sym.name} = {printer.code(ex, where)};")
    for arr, ids in (("t", ("t",)),) + arrays:
        if arr == "z" and not pm.algebraic_ids:
            continue
        if not (set(ids) & used):
            lines.append(f"    (void){arr};")
    for k, ex in enumerate(reduced):
        lines.append(f"    {out}[{k}] = {printer.code(ex, where)};")
    if not reduced:
        lines.append(f"    (void){out};")
    return lines


def c_string(text: str) -> str:
    r"""A C string literal holding the UTF-8 bytes of ``text``, in printable ASCII.

    ``\``, ``"`` and ``?`` are escaped (so no trigraph such as ``??/`` can
    form); newline, carriage return and tab get their named escapes; every
    other byte outside printable ASCII is a three-digit octal escape (octal
    escapes stop after three digits, unlike ``\x``, which would swallow a
    following hex digit).

    Parameters
    ----------
    text : str
        Text accepted by :func:`bondgraph.codegen._common.check_text`.

    Returns
    -------
    str

    Examples
    --------
    >>> print(c_string('say "hi"??/'), c_string("\u00e9\n"))
    "say \"hi\"\?\?/" "\303\251\n"
    """
    out = []
    for byte in text.encode("utf-8"):
        ch = chr(byte)
        if ch in '\\"?':
            out.append("\\" + ch)
        elif ch in _C_NAMED:
            out.append(_C_NAMED[ch])
        elif 0x20 <= byte < 0x7F:
            out.append(ch)
        else:
            out.append(f"\\{byte:03o}")
    return '"' + "".join(out) + '"'


_C_NAMED = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}


def c_comment(text: str) -> str:
    r"""``text`` as a ``/* ... */`` comment may show it: one line, no ``*/``, ``/*`` or ``??``.

    A plain (dotted) identifier is shown as it is; anything else as
    :func:`~bondgraph.codegen._common.shown` gives it, with ``?``, ``*`` and
    ``/`` also escaped by a backslash.

    Parameters
    ----------
    text : str

    Returns
    -------
    str

    Examples
    --------
    >>> print(c_comment("motor.Ra"), c_comment('a*/ x("y"); /*??/'))
    motor.Ra "a\*\/ x(\"y\"); \/\*\?\?\/"
    """
    view = shown(text)
    return view if view == text else re.sub(r"([?*/])", r"\\\1", view)


#: file names the source may ``#include "..."`` (and its comments may show)
_HEADER_FILE = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.+-]*")


def _names_array(prefix: str, what: str, names: Sequence[str]) -> str:
    items = ", ".join(c_string(n) for n in names)
    return f"const char *const {prefix}_{what}_names[] = {{{items + ', ' if items else ''}NULL}};"


def generate_c(model: Model, *, name: Optional[str] = None,
               defaults: Optional[Mapping[str, float]] = None,
               header_file: Optional[str] = None) -> CCode:
    """Generate C99 source and header for ``model`` (see the module docstring).

    Parameters
    ----------
    model : Model
    name : str, optional
        Prefix of the C symbols; default: the model's name.
    defaults : mapping of str to float, optional
        Values for every parameter, emitted as ``NAME_default_parameters``.
    header_file : str, optional
        File name the source includes; default ``"<name>.h"``.

    Returns
    -------
    CCode

    Raises
    ------
    CodegenError
        A prefix that is not a C identifier (or is reserved), a header file
        name that cannot be ``#include``\\ d safely, a function with no C
        equivalent, input derivatives, or a name no escape can carry (NUL,
        lone surrogate).
    ParameterValueError
        ``defaults`` missing or naming unknown parameters.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> _ = g.connect("F", "m")
    >>> model = bg.derive(g, outputs={"v": bg.flow("m")})
    >>> code = generate_c(model, name="plant")
    >>> [line for line in code.header.splitlines() if line.startswith("#define PLANT_N")]
    ['#define PLANT_NX 1', '#define PLANT_NU 1', '#define PLANT_NY 1', '#define PLANT_NP 1']
    """
    prefix = check_identifier(name if name is not None else model.name, what="C name prefix",
                              reserved=C_RESERVED | set(_MACRO_VALUES))
    up = prefix.upper()
    # the header's macros: a local variable of that name would be rewritten by them
    header_macros = {f"{up}_{tail}" for tail in ("H", "NX", "NU", "NY", "NP", "NX_ALLOC",
                                                 "HAS_DEFAULT_PARAMETERS")}
    from . import _newton_c

    pm = prepare(model, reserved=C_RESERVED | set(_MACRO_VALUES) | header_macros | {prefix},
                 defaults=defaults, implicit_reserved=_newton_c.reserved_names(prefix))
    implicit = bool(pm.algebraic_ids)
    header_file = header_file or f"{prefix}.h"
    if not isinstance(header_file, str) or not _HEADER_FILE.fullmatch(header_file):
        raise CodegenError(f"header file name {header_file!r} cannot be #included safely: expected "
                           "letters, digits and _ . + - only (no directory, spaces or quotes)")
    n, m, p, k = len(pm.state_ids), len(pm.input_ids), len(pm.output_ids), len(pm.parameter_ids)
    args = "double t, const double *x, const double *u, const double *p"
    sig_d = f"void {prefix}_derivatives({args}, double *xdot)"
    sig_o = f"void {prefix}_outputs({args}, double *y)"
    sig_e = f"void {prefix}_step_euler(double t, double h, double *x, const double *u, const double *p)"
    sig_r = f"void {prefix}_step_rk4(double t, double h, double *x, const double *u, const double *p)"
    if implicit:
        sigs = _newton_c.c_signatures(prefix)
        sig_d, sig_o, sig_e, sig_r = (sigs[k] for k in ("derivatives", "outputs", "step_euler",
                                                         "step_rk4"))
    comment = [f"{header_file} -- generated by bondgraph from model {c_comment(pm.name)}; do not edit.",
               "",
               "x' = f(t, x, u, p) (NAME_derivatives), y = g(t, x, u, p) (NAME_outputs).".replace(
                   "NAME", prefix),
               "Arrays are indexed in this order (parameters sorted by name):", ""]
    comment += header_lines(pm, index_base=0, show=c_comment)
    comment += ["", "Name arrays end with NULL. The step functions advance x in place from t",
                "to t + h, holding u constant over the step."]
    if implicit:
        comment += ["", "Implicit model: the algebraic unknowns z (NAME_algebraic_names) solve".replace(
                        "NAME", prefix),
                    "0 = g(t, x, z, u, p) by Newton's method at every call; z is the caller's",
                    "warm start (in: last solution, out: new one; left as it was on failure).",
                    "The int functions return 0, or a status whose text NAME_status_message".replace(
                        "NAME", prefix),
                    "gives (naming the unknowns); on failure xdot and y are NAN and the steps",
                    "leave x unchanged.", "", f"algebraic unknowns ({len(pm.algebraic_ids)}):"]
        comment += [f"    z[{k}]  {c_comment(nm)}" + ("" if nm == ident else f"  [as {ident}]")
                    + f": {c_comment(origin)}" for k, (nm, ident, origin) in
                    enumerate(zip(pm.algebraic_names, pm.algebraic_ids, pm.algebraic_origin))]
    guard = f"{up}_H"
    h = ["/*"] + [f" * {c}".rstrip() for c in comment] + [" */", f"#ifndef {guard}", f"#define {guard}", "",
                                                          "#ifdef __cplusplus", 'extern "C" {', "#endif", "",
                                                          f"#define {up}_NX {n}", f"#define {up}_NU {m}",
                                                          f"#define {up}_NY {p}", f"#define {up}_NP {k}"]
    if pm.defaults is not None:
        h.append(f"#define {up}_HAS_DEFAULT_PARAMETERS 1")
    h += ["",
          f"extern const char *const {prefix}_state_names[];",
          f"extern const char *const {prefix}_input_names[];",
          f"extern const char *const {prefix}_output_names[];",
          f"extern const char *const {prefix}_parameter_names[];"]
    if pm.defaults is not None:
        h.append(f"extern const double {prefix}_default_parameters[];")
    if implicit:
        h += _newton_c.header_lines(pm, prefix)
    h += ["", sig_d + ";", sig_o + ";", sig_e + ";", sig_r + ";", "",
          "#ifdef __cplusplus", "}", "#endif", "", f"#endif /* {guard} */", ""]

    body_d = _function_body(pm, pm.rhs, "xdot", f"model {pm.name!r}, state equations")
    body_o = _function_body(pm, pm.outputs, "y", f"model {pm.name!r}, outputs")
    alloc = f"{up}_NX_ALLOC"
    src = [f"/* {prefix}.c -- generated by bondgraph from model {c_comment(pm.name)}; do not edit.",
           f" * See {header_file} for the order of the arrays. */",
           f'#include "{header_file}"', "", "#include <math.h>", "#include <stddef.h>", ""]
    solver = (_newton_c.source_lines(pm, prefix, lambda ex, out, where: _function_body(
        pm, ex, out, where), c_string, _names_array) if implicit else [])
    body_text = "\n".join(body_d + body_o + solver)
    macros = sorted(set(re.findall(r"\bM_[A-Z0-9_]+\b", body_text)) & set(_MACRO_VALUES))
    for mac in macros:
        src += [f"#ifndef {mac}", f"#define {mac} {_MACRO_VALUES[mac]!r}", "#endif", ""]
    src += ["/* work arrays of the step functions (C has no zero-length arrays) */",
            f"#define {alloc} ({up}_NX > 0 ? {up}_NX : 1)", ""]
    src += [_names_array(prefix, "state", pm.state_names),
            _names_array(prefix, "input", pm.input_names),
            _names_array(prefix, "output", pm.output_names),
            _names_array(prefix, "parameter", pm.parameter_names)]
    if pm.defaults is not None:
        vals = ", ".join(_Printer()._print_Float(sympy.Float(v)) for v in pm.defaults) or "0.0"
        src.append(f"const double {prefix}_default_parameters[] = {{{vals}}};")
    if implicit:
        src += [""] + solver
        src += _newton_c.model_function(pm, prefix, "derivatives", body_d, "xdot", f"{up}_NX")
        src += _newton_c.model_function(pm, prefix, "outputs", body_o, "y", f"{up}_NY")
        src += _newton_c.step_functions(prefix, alloc)
    else:
        src += ["", sig_d, "{"] + body_d + ["}", "", sig_o, "{"] + body_o + ["}", ""]
        src += _explicit_steps(prefix, sig_e, sig_r, alloc)
    idents = dict(zip(pm.state_names + pm.input_names + pm.parameter_names + pm.algebraic_names,
                      pm.state_ids + pm.input_ids + pm.parameter_ids + pm.algebraic_ids))
    return CCode(prefix, header_file, "\n".join(h), "\n".join(src), MappingProxyType(idents))


def _explicit_steps(prefix: str, sig_e: str, sig_r: str, alloc: str) -> list[str]:
    up = prefix.upper()
    return [sig_e, "{",
            f"    double k1[{alloc}];",
            "    int i;",
            f"    {prefix}_derivatives(t, x, u, p, k1);",
            f"    for (i = 0; i < {up}_NX; ++i) x[i] += h * k1[i];",
            "}", "",
            sig_r, "{",
            f"    double k1[{alloc}], k2[{alloc}], k3[{alloc}], k4[{alloc}];",
            f"    double xt[{alloc}];",
            "    int i;",
            f"    {prefix}_derivatives(t, x, u, p, k1);",
            f"    for (i = 0; i < {up}_NX; ++i) xt[i] = x[i] + 0.5 * h * k1[i];",
            f"    {prefix}_derivatives(t + 0.5 * h, xt, u, p, k2);",
            f"    for (i = 0; i < {up}_NX; ++i) xt[i] = x[i] + 0.5 * h * k2[i];",
            f"    {prefix}_derivatives(t + 0.5 * h, xt, u, p, k3);",
            f"    for (i = 0; i < {up}_NX; ++i) xt[i] = x[i] + h * k3[i];",
            f"    {prefix}_derivatives(t + h, xt, u, p, k4);",
            f"    for (i = 0; i < {up}_NX; ++i)",
            "        x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);",
            "}", ""]


def write_c(model: Model, path: Union[str, "os.PathLike[str]"], *, name: Optional[str] = None,
            defaults: Optional[Mapping[str, float]] = None) -> tuple[Path, Path]:
    """Write ``<path>.c`` and the header ``<path>.h`` beside it, all or nothing.

    ``path`` may end in ``.c`` or have no suffix.  The C prefix defaults to
    the model's name.

    Parameters
    ----------
    model : Model
    path : str or path-like
        The ``.c`` file (or its stem); the header gets the suffix ``.h``.
    name : str, optional
        Prefix of the C symbols; default: the model's name.
    defaults : mapping of str to float, optional
        Values for every parameter, emitted as ``NAME_default_parameters``.

    Returns
    -------
    (Path, Path)
        The source and header paths.

    Raises
    ------
    CodegenError, ExportError

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> _ = g.connect("F", "m")
    >>> model = bg.derive(g, outputs={"v": bg.flow("m")})
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     src, hdr = write_c(model, pathlib.Path(d, "mass.c"))
    ...     src.name, hdr.name, '#include "mass.h"' in src.read_text()
    ('mass.c', 'mass.h', True)
    """
    from ..export import atomic_write_many

    p = Path(os.fspath(path))
    if p.suffix not in ("", ".c"):
        raise CodegenError(f"C output '{p}' must end in .c (the header gets .h)")
    src_path, hdr_path = p.with_suffix(".c"), p.with_suffix(".h")
    code = generate_c(model, name=name, defaults=defaults, header_file=hdr_path.name)
    atomic_write_many([(src_path, lambda fh: fh.write(code.source)),
                       (hdr_path, lambda fh: fh.write(code.header))], binary=False)
    return src_path, hdr_path
