"""A MATLAB / Octave function file for a model.

The generated ``NAME.m`` defines::

    [xdot, y] = NAME(t, x, u, p)   % column vectors x' = f(t, x, u, p), y = g(t, x, u, p)
    info = NAME()                  % struct: name, states, inputs, outputs, parameters
                                   % (cell arrays of names) and defaults (vector or [])

``x`` and ``u`` are vectors in the order listed in the help text (the model's
``state_names`` and ``input_names``); ``p`` is either a vector in the order
of the parameters (sorted by name) or a struct whose fields are the
parameters' identifiers (``motor.Ra`` becomes the field ``motor_Ra``; the
help text lists every alias).  It runs unchanged in Octave and fits
``ode45(@(t, x) NAME(t, x, u, p), tspan, x0)``.

The file is printable ASCII.  Names are never pasted raw: a name of
printable ASCII is a char array with ``'`` doubled, any other name is
``native2unicode(uint8([...]), 'UTF-8')`` of its UTF-8 bytes
(:func:`m_string`); the help text shows a name that is not a plain (dotted)
identifier escaped and quoted, on one line (:func:`m_comment`).

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("rc")
>>> V, n = bg.Se("V"), bg.One("i")
>>> g.add(V, n, bg.R("R"), bg.C("C"))
>>> _ = g.connect(V, n); _ = g.connect(n, "R"); _ = g.connect(n, "C")
>>> text = generate_matlab(bg.derive(g, outputs={"vC": bg.effort("C")}), name="rc_model")
>>> print(text.splitlines()[0])
function [xdot, y] = rc_model(t, x, u, p)
>>> print("\\n".join(l for l in text.splitlines() if l.startswith("xdot(")))
xdot(1) = (V - q_C./C)./R;
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Mapping, Optional, Sequence, Union

import sympy
from sympy.printing.octave import OctaveCodePrinter

from ..model import Model
from ._common import (M_RESERVED, PreparedModel, TargetPrinter, check_identifier, header_lines,
                      prepare, shown, split_cse, write_text)

__all__ = ["generate_matlab", "write_matlab", "m_string", "m_comment"]


class _Printer(TargetPrinter, OctaveCodePrinter):
    """Octave printer: doubles printed exactly; unknown functions refused."""

    missing = "no MATLAB function"

    def __init__(self) -> None:
        super().__init__({"strict": True, "error_on_reserved": True, "inline": True})


def m_string(text: str) -> str:
    r"""A MATLAB / Octave expression whose value is the char array ``text``.

    Printable ASCII becomes a quoted char array with ``'`` doubled; text
    with anything else (a newline, a non-ASCII letter) is converted from
    its UTF-8 bytes, which keeps the file ASCII and works in both MATLAB
    (UTF-16 chars) and Octave (UTF-8 chars).  Long text is continued over
    lines with ``...`` (at most 60 characters or 24 bytes a line).

    Parameters
    ----------
    text : str

    Returns
    -------
    str

    Examples
    --------
    >>> print(m_string("it's"), m_string("\u00e9\n"))
    'it''s' native2unicode(uint8([195 169 10]), 'UTF-8')
    >>> print(m_string("x" * 70))
    ['xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx', ...
        'xxxxxxxxxx']
    """
    if all(0x20 <= ord(ch) < 0x7F for ch in text):
        parts = ["'" + text[i:i + 60].replace("'", "''") + "'" for i in range(0, len(text), 60)] or ["''"]
        return parts[0] if len(parts) == 1 else "[" + _CONTINUE.join(parts) + "]"
    data = [str(b) for b in text.encode("utf-8")]
    codes = _CONTINUE.join(" ".join(data[i:i + 24]) for i in range(0, len(data), 24))
    return f"native2unicode(uint8([{codes}]), 'UTF-8')"


_CONTINUE = ", ...\n    "


def m_comment(text: str) -> str:
    r"""``text`` as a ``%`` comment may show it: printable ASCII on one line.

    Examples
    --------
    >>> print(m_comment("motor.Ra"), m_comment("a\n%{"))
    motor.Ra "a\n%{"
    """
    return shown(text)


def _cell(names: Sequence[str]) -> str:
    """A cell array of the names: one line, or one name a line once that passes 80 characters."""
    items = [m_string(n) for n in names]
    one_line = "{" + ", ".join(items) + "}"
    return one_line if len(one_line) <= 80 and "\n" not in one_line else "{" + _CONTINUE.join(items) + "}"


def _assignments(pm: PreparedModel, exprs: Sequence[sympy.Expr], out: str, where: str) -> list[str]:
    printer = _Printer()
    reps, reduced = split_cse(exprs, pm.taken)
    lines = [f"{out} = zeros({len(reduced)}, 1);"]
    for sym, ex in reps:
        lines.append(f"{sym.name} = {printer.code(ex, where)};")
    for k, ex in enumerate(reduced):
        lines.append(f"{out}({k + 1}) = {printer.code(ex, where)};")
    return lines


def _unpack(pm: PreparedModel, with_z: bool) -> list[str]:
    arrays = [("x", pm.state_ids), ("u", pm.input_ids), ("p", pm.parameter_ids)]
    arrays += [("z", pm.algebraic_ids)] if with_z else []
    return [f"{ident} = {arr}({k + 1});" for arr, ids in arrays for k, ident in enumerate(ids)]


def generate_matlab(model: Model, *, name: Optional[str] = None,
                    defaults: Optional[Mapping[str, float]] = None) -> str:
    """Text of the function file ``<name>.m`` (see the module docstring).

    Parameters
    ----------
    model : Model
    name : str, optional
        Function name (and file stem); default: the model's name.
    defaults : mapping of str to float, optional
        Values for every parameter, returned by ``info = NAME()``.

    Raises
    ------
    CodegenError
        A function name that is not a MATLAB identifier, an unsupported
        function, input derivatives, or a name no escape can carry (NUL,
        lone surrogate).

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> _ = g.connect("F", "m")
    >>> model = bg.derive(g, outputs={"v": bg.flow("m")})
    >>> text = generate_matlab(model, defaults={"m": 2.0})
    >>> [line for line in text.splitlines() if line.startswith(("function", "xdot(", "y("))]
    ['function [xdot, y] = mass(t, x, u, p)', 'xdot(1) = F;', 'y(1) = p_m./m;']
    """
    fname = check_identifier(name if name is not None else model.name, what="MATLAB function name",
                             matlab=True, reserved=M_RESERVED)
    from . import _newton_m

    pm = prepare(model, reserved=M_RESERVED | {fname}, matlab=True, defaults=defaults,
                 implicit_reserved=_newton_m.RESERVED)
    implicit = bool(pm.algebraic_ids)
    outs = "[xdot, y, z]" if implicit else "[xdot, y]"
    upper = fname.upper()
    help_ = [f"{upper}  State equations of bond-graph model {m_comment(pm.name)}",
             "  (generated by bondgraph; do not edit).",
             f"  [XDOT, Y] = {upper}(T, X, U, P) returns x' = f(t, x, u, p) and y = g(t, x, u, p)",
             "  as column vectors. X and U are vectors; P is a vector or a struct with the",
             "  field names given in brackets (or the names themselves when they are identifiers).",
             f"  INFO = {upper}() returns the names and the default parameter values.", "",
             "  Order of the vectors:"]
    help_ += ["  " + ln for ln in header_lines(pm, index_base=1, show=m_comment)]
    if implicit:
        help_ += ["", f"  Implicit model: [XDOT, Y, Z] = {upper}(T, X, U, P) first solves",
                  "  0 = g(t, x, z, u, p) for the algebraic unknowns z by Newton's method,",
                  "  warm-started from the last solution; error('bondgraph:newton', ...) names",
                  "  the unknowns when it fails.  Algebraic unknowns:"]
        help_ += [f"    z({k + 1})  {m_comment(n)}: {m_comment(o)}"
                  for k, (n, o) in enumerate(zip(pm.algebraic_names, pm.algebraic_origin))]
    lines = [f"function {outs} = {fname}(t, x, u, p)"] + [f"%{h}".rstrip() for h in help_]
    defaults_text = ("[]" if pm.defaults is None
                     else "[" + "; ".join(repr(float(v)) for v in pm.defaults) + "]")
    lines += ["if nargin == 0",
              f"  xdot = struct('name', {m_string(pm.name)});",
              f"  xdot.states = {_cell(pm.state_names)};",
              f"  xdot.inputs = {_cell(pm.input_names)};",
              f"  xdot.outputs = {_cell(pm.output_names)};",
              f"  xdot.parameters = {_cell(pm.parameter_names)};",
              f"  xdot.defaults = {defaults_text};"]
    if implicit:
        lines += [f"  xdot.algebraic = {_cell(pm.algebraic_names)};",
                  f"  xdot.algebraic_origins = {_cell(pm.algebraic_origin)};",
                  "  z = [];"]
    lines += ["  y = [];",
              "  return;",
              "end",
              "if nargin ~= 4",
              f"  error('{fname}: expected 4 arguments (t, x, u, p), got %d', nargin);",
              "end"]
    if pm.parameter_ids:
        fields = "; ".join(f"p.{ident}" for ident in pm.parameter_ids)
        lines += ["if isstruct(p)", f"  p = [{fields}];", "end"]
    if implicit:
        lines += _newton_m.main_lines(pm, m_string)
    lines += _unpack(pm, implicit)
    lines += _assignments(pm, pm.rhs, "xdot", f"model {pm.name!r}, state equations")
    lines += _assignments(pm, pm.outputs, "y", f"model {pm.name!r}, outputs")
    lines += ["end", ""]
    if implicit:
        lines += _newton_m.local_functions(
            pm, lambda with_z: _unpack(pm, with_z),
            lambda ex, out, where: _assignments(pm, ex, out, where), m_string)
    return "\n".join(lines)


def write_matlab(model: Model, path: Union[str, "os.PathLike[str]"], *,
                 defaults: Optional[Mapping[str, float]] = None) -> Path:
    """Write ``path`` (``NAME.m``) atomically; the function is named after the file.

    Parameters
    ----------
    model : Model
    path : str or path-like
        The ``.m`` file to write; its stem names the function.
    defaults : mapping of str to float, optional
        Values for every parameter, returned by ``info = NAME()``.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    CodegenError
        If the file stem is not a valid MATLAB function name.
    ExportError
        If the file cannot be written.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> _ = g.connect("F", "m")
    >>> model = bg.derive(g, outputs={"v": bg.flow("m")})
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     path = write_matlab(model, pathlib.Path(d, "mass_ode.m"))
    ...     path.name, path.read_text().splitlines()[0]
    ('mass_ode.m', 'function [xdot, y] = mass_ode(t, x, u, p)')
    """
    return write_text(path, ".m", "MATLAB",
                      lambda p: generate_matlab(model, name=p.stem, defaults=defaults))
