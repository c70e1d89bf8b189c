r"""C99 and Python code for a switched model: a mode table, the guards, the re-initialisations.

The generated code keeps one mode-independent state ``x`` (the stored quantity
of every storage element, then every integrated signal; see
:mod:`bondgraph.codegen._hybrid`) and evaluates, for the current mode (an
index into the table of reachable modes):

* ``derivatives`` -- ``x'`` of that mode;
* ``outputs`` -- the user's outputs;
* ``guards`` -- one value per switch with a guard, ``>= 0`` while the mode is
  consistent; a guard falling through zero is the event that flips its switch;
* ``enter`` -- the state after entering the mode (the momentum-conserving
  lock, the shorted capacitor emptied; the identity where nothing jumps);
* ``energy`` -- the total stored energy;
* ``select`` -- the mode change of :func:`bondgraph.hybrid.simulate`: from a
  proposed combination of switch states, the candidates flip any subset of
  the ``free`` switches (the diodes at an event); a candidate is consistent
  when every guard of the ``check`` switches is ``>= -guard_tol`` after its
  re-initialisation; the chosen one needs no jump of a state if one can
  (a state moving by more than ``1e-9`` of its size plus ``1e-12``), then flips
  fewest switches.  It re-initialises ``x`` and returns the new mode, or -1.

C: :func:`generate_switched_c` gives a ``.c``/``.h`` pair with
``NAME_derivatives(mode, t, x, u, p, xdot)``, ``NAME_outputs``,
``NAME_guards``, ``NAME_enter``, ``NAME_energy``, ``NAME_select``,
``NAME_mode_index``, ``NAME_step_rk4(mode, ...)`` and the tables
``NAME_mode_on[]`` (bit ``i``: switch ``i`` on) and ``NAME_guard_switch[]``.
Python: :func:`generate_switched_python` gives a module of the same
functions using only :mod:`math`.  Names reach the text only escaped, as in
:mod:`bondgraph.codegen.c`.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.hybrid import SwitchedModel, library
>>> sm = SwitchedModel(library.clutch(), outputs={"w2": bg.flow("J2")})
>>> code = generate_switched_c(sm)
>>> "#define CLUTCH_NMODES 2" in code.header, "int clutch_select(" in code.source
(True, True)
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Mapping, Optional, Sequence, cast

import sympy
from sympy.printing.pycode import PythonCodePrinter

from ._common import (C_RESERVED, PY_RESERVED, CodegenError, TargetPrinter, check_identifier,
                      split_cse)
from ._hybrid import SwitchedExportError, SwitchedPrepared, prepare_switched
from .c import _HEADER_FILE, _MACRO_VALUES, _function_body, _names_array, _Printer, c_comment

__all__ = ["SwitchedCCode", "generate_switched_c", "generate_switched_python", "SwitchedExportError"]

_ARGS = "double t, const double *x, const double *u, const double *p"
_FUNCS = ("derivatives", "outputs", "guards", "enter")


@dataclass(frozen=True)
class SwitchedCCode:
    """Generated C of a switched model: ``source``, ``header`` and the prepared modes.

    Attributes
    ----------
    name, header_file, header, source : str
    identifiers : mapping of str to str
        Model name -> C identifier of every state, input and parameter.
    prepared : SwitchedPrepared
        The modes' equations the code was generated from (names, orders, masks).
    """

    name: str
    header_file: str
    header: str
    source: str
    identifiers: Mapping[str, str]
    prepared: SwitchedPrepared


def _mask_doc(sp: SwitchedPrepared) -> list[str]:
    out = ["switches (bit i of a mode's mask: switch i on):"]
    out += [f"    {i}  {c_comment(n)}" for i, n in enumerate(sp.switches)]
    out += ["reachable modes (index: mask, state):"]
    out += [f"    {k}: {sp.mode_on[k]}  {c_comment(sp.mode_label(k))}" for k in range(len(sp.modes))]
    return out


def _rows(title: str, arr: str, names: Sequence[str], ids: Sequence[str]) -> list[str]:
    out = [f"{title} ({len(names)}):"] + (["    (none)"] if not names else [])
    for k, (nm, ident) in enumerate(zip(names, ids)):
        out.append(f"    {arr}[{k}]  {c_comment(nm)}" + ("" if nm == ident else f"  [as {ident}]"))
    return out


def generate_switched_c(sm: Any, *, name: Optional[str] = None,
                        defaults: Optional[Mapping[str, float]] = None,
                        header_file: Optional[str] = None) -> SwitchedCCode:
    """Generate C99 source and header for switched model ``sm`` (see the module docstring).

    Parameters
    ----------
    sm : bondgraph.hybrid.SwitchedModel
    name : str, optional
        Prefix of the C symbols; default: the model's name.
    defaults : mapping of str to float, optional
        Values for every parameter (guards' included), emitted as ``NAME_default_parameters``.
    header_file : str, optional
        File name the source includes; default ``"<name>.h"``.

    Returns
    -------
    SwitchedCCode

    Raises
    ------
    SwitchedExportError
        A mode whose re-initialisation is not a linear map, input derivatives (naming the mode).
    CodegenError
        A bad prefix or header name, a function C lacks, a name no escape can carry.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.hybrid import SwitchedModel, library
    >>> code = generate_switched_c(SwitchedModel(library.rectifier(), outputs={"v": bg.effort("C")}),
    ...                            name="rect")
    >>> [ln for ln in code.header.splitlines() if ln.startswith("#define RECT_N")]
    ['#define RECT_NX 1', '#define RECT_NU 0', '#define RECT_NY 1', '#define RECT_NP 4', '#define RECT_NG 1', '#define RECT_NSW 1', '#define RECT_NMODES 2']
    """
    prefix = check_identifier(name if name is not None else getattr(sm, "name", ""), what="C name prefix",
                              reserved=C_RESERVED | set(_MACRO_VALUES))
    up = prefix.upper()
    macros = {f"{up}_{tail}" for tail in ("H", "NX", "NU", "NY", "NP", "NG", "NSW", "NMODES", "ALLOC",
                                          "HAS_DEFAULT_PARAMETERS", "SELF_SWITCHED", "INITIAL_ON")}
    sp = prepare_switched(sm, reserved=C_RESERVED | set(_MACRO_VALUES) | macros | {prefix, "mode", "g",
                                                                                   "xn", "h"},
                          defaults=defaults)
    header_file = header_file or f"{prefix}.h"
    if not isinstance(header_file, str) or not _HEADER_FILE.fullmatch(header_file):
        raise CodegenError(f"header file name {header_file!r} cannot be #included safely: expected "
                           "letters, digits and _ . + - only (no directory, spaces or quotes)")
    n, m, ny, npar = len(sp.state_ids), len(sp.input_ids), len(sp.output_ids), len(sp.parameter_ids)
    ng, nsw, nm = len(sp.guard_switch), len(sp.switches), len(sp.modes)
    sigs = {
        "derivatives": f"void {prefix}_derivatives(int mode, {_ARGS}, double *xdot)",
        "outputs": f"void {prefix}_outputs(int mode, {_ARGS}, double *y)",
        "guards": f"void {prefix}_guards(int mode, {_ARGS}, double *g)",
        "enter": f"void {prefix}_enter(int mode, {_ARGS}, double *xn)",
    }
    sig_h = f"double {prefix}_energy(const double *x, const double *p)"
    sig_i = f"int {prefix}_mode_index(unsigned long on)"
    sig_s = (f"int {prefix}_select(unsigned long proposed, unsigned long free_mask, unsigned long "
             f"check_mask, double guard_tol, double t, double *x, const double *u, const double *p, "
             f"double *loss)")
    sig_r = f"void {prefix}_step_rk4(int mode, double t, double h, double *x, const double *u, const double *p)"
    comment = [(f"{header_file} -- generated by bondgraph from switched model {c_comment(sp.name)}; "
                "do not edit."), "",
               "One state x for every mode: stored quantities, then integrated signals.",
               "For mode k (an index of the table below): x' = NAME_derivatives(k, ...),".replace(
                   "NAME", prefix),
               "y = outputs, g = guards (>= 0 while mode k is consistent), enter = the state",
               "after entering mode k (re-initialisation), select = the mode change.", ""]
    comment += (_rows("states", "x", sp.state_names, sp.state_ids)
                + _rows("inputs", "u", sp.input_names, sp.input_ids)
                + _rows("outputs", "y", sp.output_names, sp.output_names)
                + _rows("parameters", "p", sp.parameter_names, sp.parameter_ids))
    comment += [f"guards ({ng}): g[j] is the guard of switch {prefix}_guard_switch[j]"] + _mask_doc(sp)
    guard = f"{up}_H"
    h = ["/*"] + [f" * {c}".rstrip() for c in comment] + [" */", f"#ifndef {guard}", f"#define {guard}", "",
                                                          "#ifdef __cplusplus", 'extern "C" {', "#endif", ""]
    h += [f"#define {up}_NX {n}", f"#define {up}_NU {m}", f"#define {up}_NY {ny}", f"#define {up}_NP {npar}",
          f"#define {up}_NG {ng}", f"#define {up}_NSW {nsw}", f"#define {up}_NMODES {nm}",
          f"#define {up}_SELF_SWITCHED {sp.self_switched}UL", f"#define {up}_INITIAL_ON {sp.initial_on}UL"]
    if sp.defaults is not None:
        h.append(f"#define {up}_HAS_DEFAULT_PARAMETERS 1")
    h += [""] + [f"extern const char *const {prefix}_{w}_names[];"
                 for w in ("state", "input", "output", "parameter", "switch", "mode")]
    h += [f"extern const unsigned long {prefix}_mode_on[];", f"extern const int {prefix}_guard_switch[];"]
    if sp.defaults is not None:
        h.append(f"extern const double {prefix}_default_parameters[];")
    h += [""] + [s + ";" for s in sigs.values()] + [sig_h + ";", sig_i + ";", sig_s + ";", sig_r + ";", "",
                                                    "#ifdef __cplusplus", "}", "#endif", "",
                                                    f"#endif /* {guard} */", ""]

    pm = cast(Any, sp)
    bodies: list[str] = []
    for k in range(nm):
        where = f"model {sp.name!r}, mode ({sp.mode_label(k)})"
        parts = {"derivatives": (sp.rhs[k], "xdot"), "outputs": (sp.outputs[k], "y"),
                 "guards": (sp.guards[k], "g")}
        ent = sp.enter[k]
        parts["enter"] = (ent if ent is not None else tuple(sympy.Symbol(i, real=True) for i in sp.state_ids),
                          "xn")
        for fn, (exprs, out) in parts.items():
            bodies += [f"static void {prefix}_m{k}_{fn}({_ARGS}, double *{out})", "{"]
            bodies += _function_body(pm, exprs, out, f"{where}, {fn}") + ["}", ""]
    bodies += [f"static void {prefix}_energy_({_ARGS}, double *h)", "{"]
    bodies += _function_body(pm, [sp.energy], "h", f"model {sp.name!r}, stored energy") + ["}", ""]
    body_text = "\n".join(bodies)
    alloc = f"{up}_ALLOC"
    src = [f"/* {prefix}.c -- generated by bondgraph from switched model {c_comment(sp.name)}; do not edit.",
           f" * See {header_file} for the order of the arrays and the mode table. */",
           f'#include "{header_file}"', "", "#include <math.h>", "#include <stddef.h>", ""]
    for mac in sorted(set(re.findall(r"\bM_[A-Z0-9_]+\b", body_text)) & set(_MACRO_VALUES)):
        src += [f"#ifndef {mac}", f"#define {mac} {_MACRO_VALUES[mac]!r}", "#endif", ""]
    src += ["/* work arrays (C has no zero-length arrays) */",
            f"#define {alloc} ({up}_NX > 0 ? {up}_NX : 1)", f"#define {up}_GALLOC ({up}_NG > 0 ? {up}_NG : 1)", ""]
    src += [_names_array(prefix, "state", sp.state_names), _names_array(prefix, "input", sp.input_names),
            _names_array(prefix, "output", sp.output_names),
            _names_array(prefix, "parameter", sp.parameter_names),
            _names_array(prefix, "switch", sp.switches),
            _names_array(prefix, "mode", [sp.mode_label(k) for k in range(nm)]),
            f"const unsigned long {prefix}_mode_on[] = {{{', '.join(f'{v}UL' for v in sp.mode_on)}}};",
            f"const int {prefix}_guard_switch[] = {{{', '.join(str(v) for v in sp.guard_switch) or '-1'}}};"]
    if sp.defaults is not None:
        vals = ", ".join(_Printer()._print_Float(sympy.Float(v)) for v in sp.defaults) or "0.0"
        src.append(f"const double {prefix}_default_parameters[] = {{{vals}}};")
    src += ["", body_text]
    fn_type = f"{prefix}_fn"
    src += [f"typedef void (*{fn_type})({_ARGS}, double *);"]
    for fn in _FUNCS:
        src.append(f"static const {fn_type} {prefix}_{fn}_table[{up}_NMODES] = "
                   f"{{{', '.join(f'{prefix}_m{k}_{fn}' for k in range(nm))}}};")
    src.append("")
    for fn in _FUNCS:
        out = sigs[fn].rsplit("*", 1)[1].rstrip(")")
        src += [sigs[fn], "{", f"    {prefix}_{fn}_table[mode](t, x, u, p, {out});", "}", ""]
    src += _c_runtime(prefix, up, sig_h, sig_i, sig_s, sig_r, alloc)
    idents = dict(zip(sp.state_names + sp.input_names + sp.parameter_names,
                      sp.state_ids + sp.input_ids + sp.parameter_ids))
    return SwitchedCCode(prefix, header_file, "\n".join(h), "\n".join(src), MappingProxyType(idents), sp)


def _c_runtime(P: str, up: str, sig_h: str, sig_i: str, sig_s: str, sig_r: str, alloc: str) -> list[str]:
    """The model-independent functions: energy, mode lookup, selection, RK4."""
    text = f"""{sig_h}
{{
    double h[1];
    {P}_energy_(0.0, x, NULL, p, h);
    return h[0];
}}

{sig_i}
{{
    int k;
    for (k = 0; k < {up}_NMODES; ++k)
        if ({P}_mode_on[k] == on) return k;
    return -1;
}}

static int {P}_bits(unsigned long v)
{{
    int n = 0;
    for (; v; v >>= 1) n += (int)(v & 1UL);
    return n;
}}

{sig_s}
{{
    double xn[{alloc}], best_x[{alloc}], g[{up}_GALLOC];
    double h_old = {P}_energy(x, p), best_loss = 0.0;
    int k, j, i, best = -1, best_flips = 0, best_lossy = 0;
    for (k = 0; k < {up}_NMODES; ++k) {{
        unsigned long diff = {P}_mode_on[k] ^ proposed;
        int ok = 1, flips, lossy;
        double loss;
        if (diff & ~free_mask) continue;
        {P}_enter(k, t, x, u, p, xn);
        {P}_guards(k, t, xn, u, p, g);
        for (j = 0; j < {up}_NG; ++j)
            if (((check_mask >> {P}_guard_switch[j]) & 1UL) && g[j] < -guard_tol) ok = 0;
        if (!ok) continue;
        loss = h_old - {P}_energy(xn, p);
        flips = {P}_bits(diff);
        /* a jump: a state moved beyond the rounding of the event (energy alone cannot tell at 0) */
        lossy = 0;
        for (i = 0; i < {up}_NX; ++i)
            if (fabs(xn[i] - x[i]) > 1e-9 * (fabs(x[i]) > fabs(xn[i]) ? fabs(x[i]) : fabs(xn[i])) + 1e-12)
                lossy = 1;
        if (best < 0 || lossy < best_lossy || (lossy == best_lossy && (flips < best_flips
                || (flips == best_flips && fabs(loss) < fabs(best_loss))))) {{
            best = k; best_flips = flips; best_lossy = lossy; best_loss = loss;
            for (i = 0; i < {up}_NX; ++i) best_x[i] = xn[i];
        }}
    }}
    if (best >= 0) {{
        for (i = 0; i < {up}_NX; ++i) x[i] = best_x[i];
        *loss = best_lossy ? best_loss : 0.0;
    }}
    return best;
}}

{sig_r}
{{
    double k1[{alloc}], k2[{alloc}], k3[{alloc}], k4[{alloc}], xt[{alloc}];
    int i;
    {P}_derivatives(mode, t, x, u, p, k1);
    for (i = 0; i < {up}_NX; ++i) xt[i] = x[i] + 0.5 * h * k1[i];
    {P}_derivatives(mode, t + 0.5 * h, xt, u, p, k2);
    for (i = 0; i < {up}_NX; ++i) xt[i] = x[i] + 0.5 * h * k2[i];
    {P}_derivatives(mode, t + 0.5 * h, xt, u, p, k3);
    for (i = 0; i < {up}_NX; ++i) xt[i] = x[i] + h * k3[i];
    {P}_derivatives(mode, t + h, xt, u, p, k4);
    for (i = 0; i < {up}_NX; ++i)
        x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
}}
"""
    return text.split("\n")


# ----------------------------------------------------------------------------- Python
class _PyPrinter(TargetPrinter, PythonCodePrinter):
    missing = "Python's math module has no function"

    def __init__(self) -> None:
        super().__init__({"fully_qualified_modules": True, "strict": True})


def _py_function(sp: SwitchedPrepared, fname: str, exprs: Sequence[sympy.Expr], where: str) -> list[str]:
    printer = _PyPrinter()
    reps, reduced = split_cse(exprs, sp.taken)
    used: set = set()
    for ex in list(reduced) + [r for _, r in reps]:
        used |= {s.name for s in ex.free_symbols}
    lines = [f"def {fname}(t, x, u, p):"]
    for arr, ids in (("x", sp.state_ids), ("u", sp.input_ids), ("p", sp.parameter_ids)):
        for k, ident in enumerate(ids):
            if ident in used:
                lines.append(f"    {ident} = {arr}[{k}]")
    for sym, ex in reps:
        lines.append(f"    {sym.name} = {printer.code(ex, where)}")
    items = ", ".join(printer.code(ex, where) for ex in reduced)
    lines.append(f"    return [{items}]")
    return lines + ["", ""]


def generate_switched_python(sm: Any, *, defaults: Optional[Mapping[str, float]] = None) -> str:
    """A Python module (using only :mod:`math`) with the mode table of switched model ``sm``.

    The module defines ``STATE_NAMES``, ``INPUT_NAMES``, ``OUTPUT_NAMES``,
    ``PARAMETER_NAMES``, ``SWITCHES``, ``MODES`` (labels), ``MODE_ON`` (masks),
    ``GUARD_SWITCH``, ``SELF_SWITCHED``, ``INITIAL_ON``, ``DEFAULT_PARAMETERS``
    (or None) and the functions ``derivatives(mode, t, x, u, p)``,
    ``outputs``, ``guards``, ``enter`` (lists), ``energy(x, p)`` and
    ``select(proposed, free_mask, check_mask, guard_tol, t, x, u, p)`` returning
    ``(mode, x_new, loss)`` or ``(-1, x, 0.0)`` (see the module docstring).

    Raises
    ------
    SwitchedExportError, CodegenError
        As :func:`generate_switched_c`.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.hybrid import SwitchedModel, library
    >>> src = generate_switched_python(SwitchedModel(library.clutch(), outputs={"w2": bg.flow("J2")}))
    >>> ns = {}; exec(compile(src, "clutch_gen", "exec"), ns)
    >>> ns["MODES"], ns["enter"](0, 1.0, [1.0, 6.0], [0.0], [1.0, 2.0, 1.0])
    (('K off', 'K on'), [2.3333333333333335, 4.666666666666667])
    """
    sp = prepare_switched(sm, reserved=PY_RESERVED | {"mode", "select", "energy", "enter", "guards",
                                                      "SWITCHES", "MODES", "MODE_ON", "GUARD_SWITCH"},
                          defaults=defaults)
    nm = len(sp.modes)
    lines = [f"# generated by bondgraph from switched model {ascii(sp.name)}; do not edit.",
             "# One state x for every mode (stored quantities, then integrated signals);",
             "# see bondgraph.codegen.switched for the meaning of the functions.",
             "import math", "",
             f"NAME = {ascii(sp.name)}", f"STATE_NAMES = {ascii(tuple(sp.state_names))}",
             f"INPUT_NAMES = {ascii(tuple(sp.input_names))}", f"OUTPUT_NAMES = {ascii(tuple(sp.output_names))}",
             f"PARAMETER_NAMES = {ascii(tuple(sp.parameter_names))}",
             f"SWITCHES = {ascii(tuple(sp.switches))}",
             f"MODES = {ascii(tuple(sp.mode_label(k) for k in range(nm)))}",
             f"MODE_ON = {sp.mode_on!r}", f"GUARD_SWITCH = {sp.guard_switch!r}",
             f"SELF_SWITCHED = {sp.self_switched}", f"INITIAL_ON = {sp.initial_on}",
             f"DEFAULT_PARAMETERS = {None if sp.defaults is None else tuple(float(v) for v in sp.defaults)!r}",
             "", ""]
    for k in range(nm):
        where = f"model {sp.name!r}, mode ({sp.mode_label(k)})"
        ent = sp.enter[k]
        parts = {"derivatives": sp.rhs[k], "outputs": sp.outputs[k], "guards": sp.guards[k],
                 "enter": ent if ent is not None else tuple(sympy.Symbol(i, real=True) for i in sp.state_ids)}
        for fn, exprs in parts.items():
            lines += _py_function(sp, f"_m{k}_{fn}", exprs, f"{where}, {fn}")
    lines += _py_function(sp, "_energy", [sp.energy], f"model {sp.name!r}, stored energy")
    for fn in _FUNCS:
        lines += [f"_{fn.upper()} = ({', '.join(f'_m{k}_{fn}' for k in range(nm))},)", "",
                  f"def {fn}(mode, t, x, u, p):", f"    return _{fn.upper()}[mode](t, x, u, p)", "", ""]
    lines += ['''def energy(x, p):
    return _energy(0.0, x, (), p)[0]


def select(proposed, free_mask, check_mask, guard_tol, t, x, u, p):
    h_old = energy(x, p)
    best = None
    for k, on in enumerate(MODE_ON):
        diff = on ^ proposed
        if diff & ~free_mask:
            continue
        xn = enter(k, t, x, u, p)
        g = guards(k, t, xn, u, p)
        if any((check_mask >> s) & 1 and gj < -guard_tol for s, gj in zip(GUARD_SWITCH, g)):
            continue
        loss = h_old - energy(xn, p)
        # a jump: a state moved beyond the rounding of the event (energy alone cannot tell at 0)
        jumped = any(abs(b - a) > 1e-9 * max(abs(a), abs(b)) + 1e-12 for a, b in zip(x, xn))
        key = (jumped, bin(diff).count("1"), abs(loss))
        if best is None or key < best[0]:
            best = (key, k, xn, loss if jumped else 0.0)
    if best is None:
        return -1, list(x), 0.0
    return best[1], best[2], best[3]
''']
    return "\n".join(lines)
