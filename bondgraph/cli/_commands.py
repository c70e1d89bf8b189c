"""The commands ``equations``, ``tf``, ``export`` and ``draw`` of the command line.

Examples
--------
>>> sorted(NUMERIC_EXPORTS)
['json', 'mat', 'npz']
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

from .._support.labels import latex_dot, latex_name, tex
from ..errors import NonlinearModelError
from .._support.formats import EXPORT_FORMATS
from . import _common
from . import _operating as _op
from . import _switched as _sw
from ._common import CLIError, UsageError, _check_signal, _given, _only, _refuse_overwriting_inputs, _values

__all__ = ["cmd_equations", "cmd_tf", "cmd_export", "cmd_draw", "NUMERIC_EXPORTS",
           "DRAW_FORMATS"]

#: export formats that write a numeric plant (the ones an operating point applies to)
NUMERIC_EXPORTS = ("mat", "npz", "json")

#: drawing formats of ``bondgraph draw`` (``tex``: TikZ)
DRAW_FORMATS = ("svg", "png", "tex")


def _needs_point(exc: NonlinearModelError) -> CLIError:
    """A nonlinear model's error, with the options that give an operating point."""
    return CLIError(f"{exc}; {_op.HINT}")


def _linear(args) -> bool:
    return bool(getattr(args, "trim", False) or getattr(args, "operating_point", None))


def _load(args, command: str):
    """The model file's definition and the one model the command works on (a switched
    model's mode or average, refused without a choice)."""
    defn = _common._load_definition(args.model)
    return defn, _sw.chosen_model(args, defn, command)


def _point_file(args):
    """The operating-point file read before the model (a bad file fails fast), or None."""
    path = getattr(args, "operating_point", None)
    return None if path is None else _op.read_operating_point(path)


# --------------------------------------------------------------------------- equations
def cmd_equations(args) -> None:
    """``bondgraph equations``: states, inputs, outputs, parameters and equations.

    A switched model prints every mode (or the one ``--mode``, or the average
    ``--average``)."""
    defn = _common._load_definition(args.model)
    sm = _sw.switched_of(defn)
    if sm is None or args.mode is not None or args.average is not None:
        model = _sw.chosen_model(args, defn, "equations")
        what = ("" if sm is None else f" (mode {args.mode})" if args.mode is not None
                else f" (state-space average, duty {args.average[0]})")
        print("\n".join(_equations_text(defn, model, args.latex, what)))
        return
    from ..hybrid import ModeError

    out = [f"model {sm.name!r}" + (f": {defn.description}" if defn.description else ""),
           f"switched: switches {', '.join(sm.switches)}; initial mode {_sw.mode_text(sm, sm.initial)} "
           f"({sm.initial}); choose one with --mode, or --average DUTY ACTIVE PASSIVE"]
    for mode in sm.all_modes:
        out.append("")
        try:
            model = sm.derived(mode).user
        except ModeError:
            out.append(f"mode {_sw.mode_text(sm, mode)} ({mode}): not consistent (the switch states "
                       "contradict each other)")
            continue
        out.append(f"mode {_sw.mode_text(sm, mode)} ({mode}):")
        out += ["  " + line if line else "" for line in _equations_text(defn, model, args.latex, "")[1:]]
    print("\n".join(out))


def _equations_text(defn, model, latex: bool, what: str) -> list[str]:
    out = [f"model {model.name!r}{what}" + (f": {defn.description}" if defn.description else "")]
    units = defn.units

    def unit(name: str) -> str:
        return f" [{units[name]}]" if name in units else ""

    for title, names in (("states", model.state_names), ("inputs", model.input_names),
                         ("outputs", model.output_names),
                         ("algebraic unknowns", model.algebraic_names)):
        if title == "algebraic unknowns" and not names:
            continue
        out.append(f"{title} ({len(names)}): {', '.join(n + unit(n) for n in names) or '-'}")
    params = [f"{p.name} = {defn.parameters[p.name]:g}{unit(p.name)}" if p.name in defn.parameters
              else p.name for p in model.parameters]
    out.append(f"parameters ({len(params)}): {', '.join(params) or '-'}")
    out.append("")
    if latex:
        # the one LaTeX naming helper of the package (bondgraph._support.labels): \dot{p}_{La}
        lines = [f"{latex_dot(s.name)} &= {tex(r)}" for s, r in zip(model.states, model.rhs)]
        lines += [f"0 &= {tex(g)}" for g in model.residuals]
        lines += [f"{latex_name(n)} &= {tex(g)}" for n, g in zip(model.output_names, model.output_exprs)]
        out += ["\\begin{aligned}", " \\\\\n".join(lines), "\\end{aligned}"]
    else:
        out += [f"d{s.name}/dt = {r}" for s, r in zip(model.states, model.rhs)]
        out += [f"0 = {g}" for g in model.residuals]
        out += [f"{n} = {g}" for n, g in zip(model.output_names, model.output_exprs)]
    return out


# --------------------------------------------------------------------------- tf
def cmd_tf(args) -> None:
    """``bondgraph tf``: one transfer function, symbolic or numeric, at an operating point if asked."""
    import sympy

    point = _point_file(args)
    given = _given(args)
    defn, model = _load(args, "tf")
    values = _values(defn, model, args.params, given, complete=True) if args.numeric else None
    if _linear(args) and values is not None:
        ss = _op.linear_plant(args, model, values, point)       # numeric plant at the point
        matrices = [sympy.Matrix(M.tolist()) if M.size else sympy.zeros(*M.shape)
                    for M in (ss.A, ss.B, ss.C, ss.D)]
        matrices[3] = _with_derivatives(matrices[3], [sympy.Matrix(M.tolist()) if M.size else
                                                      sympy.zeros(*M.shape)
                                                      for M in ss.D_derivatives])
        values = {}
    elif _linear(args):                                      # symbolic, at the file's point
        x0, u0 = _op.file_point(args, model, point)
        try:
            ss = model.linearize(x0, u0)
        except NonlinearModelError as exc:
            message = str(exc).split("; pass equilibrium=False")[0]
            raise CLIError(f"{message}; an operating point that holds only at some parameter "
                           "values is checked there with --numeric") from None
        matrices = [ss.A, ss.B, ss.C, _with_derivatives(ss.D, ss.D_derivatives)]
    else:
        try:
            ss = model.state_space()
        except NonlinearModelError as exc:
            raise _needs_point(exc) from None
        _op.announce(ss)            # constant sources: deviations about the equilibrium
        matrices = [ss.A, ss.B, ss.C, ss.D]
    inp = args.input if args.input is not None else _only(ss.input_names, "input")
    outp = args.output if args.output is not None else _only(ss.output_names, "output")
    _check_signal(inp, ss.input_names, "input")
    _check_signal(outp, ss.output_names, "output")
    tfmod = _common._transfer_module()
    G = tfmod.transfer_function(*matrices, input=inp, output=outp,
                                input_names=list(ss.input_names), output_names=list(ss.output_names))
    if values:
        # the model file's values were checked against the whole model; this function uses some
        used = {p.name for p in G.parameters}
        values = {k: v for k, v in values.items() if getattr(k, "name", k) in used}
    if args.latex:
        if values is None:
            print(G.to_latex())
            return
        N = G.subs(values)
        print(N.to_latex())
        if N.table().rows:
            print()
            print(N.table().to_latex())
        return
    _print_tf(G, values, _units_line(defn, inp, outp), defn.units.get(outp), defn.units.get(inp))


def _units_line(defn, inp: str, outp: str) -> str:
    """``units: input F [newton], output v [meter/second], v/F [(meter/second)/newton]``, or ''."""
    units = defn.units
    if inp not in units and outp not in units:
        return ""
    parts = [f"{what} {n} [{units[n]}]" for what, n in (("input", inp), ("output", outp))
             if n in units]
    if inp in units and outp in units:
        from ..library.units.signals import ratio_text

        dims = defn.unit_dimensions
        parts.append(f"{outp}/{inp} [{ratio_text(dims[outp], dims[inp])}]")
    return "units: " + ", ".join(parts)


#: width of the command line's text output (characters)
WIDTH = 100


def _print_tf(G, values, units: str = "", output_unit=None, input_unit=None) -> None:
    """``tf`` as text: the function (when it fits the width), the units of its input, output
    and gain (when the model declares them), its coefficient table (with each coefficient's
    unit when both units are known), poles and zeros."""
    from ..tf.coefficients import coefficient_table

    whole = str(G)
    if len(whole) <= WIDTH:
        print(whole)
    else:
        print(f"{G.output_name}/{G.input_name} = (a_n s^n + ... + a_0)/(b_m s^m + ... + b_0), "
              "coefficients below")
    if units:
        print(units)
    if values is not None:
        N = G.subs(values)
        text = str(N)
        if max(len(line) for line in text.splitlines()) <= WIDTH:
            print()
            print(text)
    print()
    grouped = [u if u is None or u.isidentifier() else f"({u})" for u in (output_unit, input_unit)]
    print(coefficient_table(G, values, output_unit=grouped[0], input_unit=grouped[1]).format(WIDTH))
    if values is None:
        return
    table = N.table()
    if table.rows:
        print()
        print(table)


def _with_derivatives(D, D_derivatives):
    """``D + D_1 s + D_2 s^2 + ...``: a linearized output that needs input derivatives keeps
    them in its transfer function (``s`` is the transfer functions' default symbol)."""
    import sympy

    s = sympy.Symbol("s")
    total = sympy.Matrix(D)
    for k, M in enumerate(D_derivatives, start=1):
        total += sympy.Matrix(M) * s ** k
    return total


# --------------------------------------------------------------------------- export
def export_format(args) -> str:
    """The export format, and the output's suffix checked against it (before any work)."""
    out = Path(args.output)
    fmt = args.format
    if fmt is None:
        fmt = EXPORT_FORMATS.get(out.suffix.lower())
        if fmt is None:
            raise CLIError(f"cannot tell the export format from '{args.output}'; give --format "
                           f"{'|'.join(sorted(set(EXPORT_FORMATS.values())))}")
    if fmt == "c" and out.suffix not in ("", ".c"):
        raise CLIError(f"C output '{args.output}' must end in .c (the header is written beside it as .h)")
    if fmt == "fmu" and out.suffix.lower() != ".fmu":
        raise CLIError(f"FMU output '{args.output}' must end in .fmu")
    if fmt in ("m", "py") and out.suffix != f".{fmt}":
        language = "MATLAB" if fmt == "m" else "Python"
        raise CLIError(f"{language} output '{args.output}' must end in .{fmt}")
    if _linear(args) and fmt not in NUMERIC_EXPORTS:
        raise _op.OperatingPointError(
            f"--operating-point and --trim apply to the numeric plant formats "
            f"({', '.join(NUMERIC_EXPORTS)}); the {fmt} export writes the nonlinear equations")
    return fmt


def cmd_export(args) -> None:
    """``bondgraph export``: a numeric plant (at an operating point if asked), code or an FMU."""
    fmt = export_format(args)
    out = Path(args.output)
    _refuse_overwriting_inputs([out.with_suffix(".c"), out.with_suffix(".h")] if fmt == "c" else [out],
                               args)
    point = _point_file(args)
    given = _given(args)
    if fmt == "fmu" and args.mode is None and args.average is None:
        defn = _common._load_definition(args.model)
        sm = _sw.switched_of(defn)
        if sm is not None:          # every mode, with event indicators
            from ..fmu import export_fmu

            every = dict(defn.parameters)
            every.update(given or {})
            export_fmu(sm, out, fmi=args.fmi or 2, kind=args.kind or "both", values=every)
            print(f"wrote {out} (switched: {len(sm.modes)} modes, switches {', '.join(sm.switches)})")
            return
    defn, model = _load(args, f"export -f {fmt}")
    if fmt in NUMERIC_EXPORTS:
        from ..export import export
        from ..numeric import compile_plant

        full = _values(defn, model, args.params, given, complete=True)
        if _linear(args):
            plant = _op.linear_plant(args, model, full, point)
        else:
            try:
                plant = compile_plant(model).plant(full)
            except NonlinearModelError as exc:
                raise _needs_point(exc) from None
            _op.announce(plant)     # constant sources: the file stores x0, u0, y0
        if defn.units:         # the model declares units: the file carries its signals'
            signals = {*plant.state_names, *plant.input_names, *plant.output_names}
            plant = plant.with_units({k: v for k, v in defn.units.items() if k in signals})
        export(plant, out, format=fmt)
        print(f"wrote {out}")
        return
    if fmt == "fmu":
        full = _values(defn, model, args.params, given, complete=True)
        if defn.units and _sw.switched_of(defn) is None:         # modelDescription.xml with unit attributes and UnitDefinitions
            from .._support.files import atomic_write
            from ..fmu import build_fmu
            from ..library.units import fmu_with_units

            data = fmu_with_units(build_fmu(defn, values=full, fmi=args.fmi or 2,
                                            kind=args.kind or "both"), defn.unit_dimensions)
            atomic_write(out, lambda fh: fh.write(data), binary=True)
        else:
            from ..fmu import export_fmu

            export_fmu(defn if _sw.switched_of(defn) is None else model, out, fmi=args.fmi or 2,
                       kind=args.kind or "both", values=full)
        print(f"wrote {out}")
        return
    values = _values(defn, model, args.params, given, complete=False)
    if values is None:
        print("note: not every parameter has a value; the generated code has no defaults",
              file=sys.stderr)
    if fmt == "c":
        from ..codegen import write_c

        src, hdr = write_c(model, out, name=args.name, defaults=values)
        print(f"wrote {src}\nwrote {hdr}")
    elif fmt == "m":
        from ..codegen import write_matlab

        print(f"wrote {write_matlab(model, out, defaults=values)}")
    else:
        from ..codegen import write_python

        print(f"wrote {write_python(model, out, defaults=values)}")


# --------------------------------------------------------------------------- draw
def cmd_draw(args) -> None:
    """``bondgraph draw``: the bond graph with causal strokes as SVG, PNG or TikZ."""
    out = Path(args.output)
    kind = args.format or out.suffix.lower().lstrip(".")
    if kind not in DRAW_FORMATS:
        raise CLIError(f"cannot tell the drawing format from '{args.output}'; use a .svg, .png or "
                       ".tex file name, or give --format svg|png|tex")
    if args.tikz_only and kind != "tex":
        raise UsageError(f"--tikz-only applies to TikZ output (.tex or --format tex); "
                       f"'{args.output}' is {kind}")
    _refuse_overwriting_inputs([out], args)
    from .._support.files import atomic_write
    from ..modelfile import load_model

    defn = load_model(args.model)
    try:
        drawing = importlib.import_module("bondgraph.drawing")
    except ModuleNotFoundError as exc:
        if exc.name not in ("bondgraph.drawing",):
            raise
        raise CLIError("drawing needs bondgraph.drawing (not available in this installation)") from None
    # drawn here and written through atomic_write, so that a failure names the target file
    sm = _sw.switched_of(defn)
    if sm is None:
        if args.mode is not None:
            raise UsageError(f"--mode applies to switched models; model {defn.name!r} has no switch")
        diag = drawing.diagram(defn.graph, causality=not args.no_causality)
    else:                   # one mode's strokes, each switch's state beside it
        mode = None if args.mode is None else _sw.to_mode(sm, args.mode)
        from ..hybrid import ModeError

        try:
            diag = drawing.diagram(sm, causality=not args.no_causality, mode=mode)
        except ModeError as exc:
            raise CLIError(f"--mode {args.mode!r}: {str(exc).split('; the consistent')[0]}; the "
                           f"consistent modes are {_sw.modes_listing(sm)}") from None
    if getattr(args, "no_prefixes", False):
        from ..drawing.labels import without_prefixes
        diag = without_prefixes(diag)
    max_width = getattr(args, "max_width", 17.0)
    font_pt = getattr(args, "font_pt", 8.0)
    if not (font_pt > 0 and max_width >= 0):
        raise CLIError(f"--font-pt must be positive and --max-width at least 0; got {font_pt:g} "
                       f"and {max_width:g}")
    scene = drawing.build_scene(diag, max_width=max_width or None, font_pt=font_pt,
                                title=not getattr(args, "no_title", False),
                                numbers=not getattr(args, "no_numbers", False),
                                latex=getattr(args, "latex", False))
    if kind == "svg":
        data = drawing.scene_to_svg(scene).encode("utf-8")
        atomic_write(out, lambda fh: fh.write(data))
    elif kind == "tex":
        data = drawing.scene_to_tikz(scene, standalone=not args.tikz_only, font_pt=font_pt).encode("ascii")
        atomic_write(out, lambda fh: fh.write(data))
    else:
        atomic_write(out, lambda fh: drawing.write_png(scene, fh))
    print(f"wrote {args.output}")
