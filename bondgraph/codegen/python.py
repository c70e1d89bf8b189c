"""A plain Python module for a model, importing only :mod:`math`.

The generated module exposes::

    NAME, STATE_NAMES, INPUT_NAMES, OUTPUT_NAMES, PARAMETER_NAMES   # str, tuples of str
    DEFAULT_PARAMETERS        # dict name -> value, or None
    derivatives(t, x, u, p)   # -> list of len(STATE_NAMES) floats
    outputs(t, x, u, p)       # -> list of len(OUTPUT_NAMES) floats

``x`` and ``u`` are sequences in the order of ``STATE_NAMES`` and
``INPUT_NAMES``; ``p`` is a sequence in the order of ``PARAMETER_NAMES`` or a
mapping from those names.  ``derivatives`` fits
``scipy.integrate.solve_ivp(lambda t, x: derivatives(t, x, u, p), ...)``.

The module is printable ASCII.  Names are never pasted raw: string literals
are their :func:`ascii` form (a str literal that evaluates to the name), and
the module docstring shows a name that is not a plain (dotted) identifier
escaped and quoted, in a literal that no quotes in that text can close
(:func:`py_docstring`).

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("rc")
>>> V, n = bg.Se("V"), bg.One("i")
>>> g.add(V, n, bg.R("R"), bg.C("C"))
>>> _ = g.connect(V, n); _ = g.connect(n, "R"); _ = g.connect(n, "C")
>>> src = generate_python(bg.derive(g, outputs={"vC": bg.effort("C")}))
>>> ns = {}
>>> exec(src, ns)
>>> ns["derivatives"](0.0, [2.0], [3.0], {"R": 0.5, "C": 4.0}), ns["outputs"](0.0, [2.0], [0.0], [4.0, 0.5])
([5.0], [0.5])
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Mapping, Optional, Sequence, Union

import sympy
from sympy.printing.pycode import PythonCodePrinter

from ..model import Model
from ._common import (PY_RESERVED, PreparedModel, TargetPrinter, header_lines, prepare, shown,
                      split_cse, write_text)

__all__ = ["generate_python", "write_python", "py_docstring"]


class _Printer(TargetPrinter, PythonCodePrinter):
    """Python printer using :mod:`math`; floats printed exactly; unknown functions refused."""

    missing = "no Python math function"

    def __init__(self) -> None:
        super().__init__({"strict": True, "error_on_reserved": True, "fully_qualified_modules": True})


def _unpack(ids: Sequence[str], source: str) -> list[str]:
    if not ids:
        return []
    target = ", ".join(ids) + ("," if len(ids) == 1 else "")
    return [f"    {target} = {source}"]


def _function(pm: PreparedModel, fname: str, exprs: Sequence[sympy.Expr], doc: str,
              args: str = "t, x, u, p") -> list[str]:
    printer = _Printer()
    where = f"model {pm.name!r}, {fname}"
    reps, reduced = split_cse(exprs, pm.taken)
    lines = [f"def {fname}({args}):", f'    """{doc}"""']
    if pm.algebraic_ids and "z" not in args:       # an implicit model: z solved first
        lines.append("    z = solve_algebraic(t, x, u, p)")
    lines += _unpack(pm.state_ids, "x")
    lines += _unpack(pm.input_ids, "u")
    lines += _unpack(pm.parameter_ids, "_params(p)")
    lines += _unpack(pm.algebraic_ids, "z")
    for sym, ex in reps:
        lines.append(f"    {sym.name} = {printer.code(ex, where)}")
    items = ", ".join(_as_float(printer.code(ex, where)) for ex in reduced)
    lines.append(f"    return [{items}]")
    return lines


def _as_float(text: str) -> str:
    return f"float({text})"


def _str_tuple(names: Sequence[str]) -> str:
    items = [ascii(n) for n in names]
    return "(" + ", ".join(items) + ("," if len(items) == 1 else "") + ")"


def py_docstring(lines: Sequence[str]) -> str:
    r"""A triple-quoted literal whose value is ``lines`` joined by newlines.

    Every backslash is escaped, and so is every double quote followed by
    another or ending the text: no two unescaped quotes ever stand together,
    so three can never close the literal early, and no escape sequence
    changes the text.  Anything but printable ASCII and the line breaks is
    escaped too (``\r``, ``\xe9``), so the literal is ASCII and its value is
    exactly the text.

    Parameters
    ----------
    lines : sequence of str

    Returns
    -------
    str

    Examples
    --------
    >>> payload = 'x' + '"' * 3 + '; import os; ' + '"' * 3 + ' \\'
    >>> text = py_docstring([payload, "second line"])
    >>> '"' * 3 in text[3:-3], eval(text) == payload + "\n" + "second line"
    (False, True)
    >>> print(py_docstring(['say "hi"', '""'])[3:-3])
    say "hi"
    \"\"
    >>> print(py_docstring(["caf\u00e9\r"])[3:-3])
    caf\xe9\r
    """
    body = "\n".join(lines).replace("\\", "\\\\")
    body = re.sub(r'"(?=")|"\Z', r'\\"', body)   # \Z: the very end ($ would allow a newline)
    body = re.sub(r"[^\x20-\x7e\n]", lambda ch: ascii(ch.group())[1:-1], body)
    return '"""' + body + '"""'


def generate_python(model: Model, *, defaults: Optional[Mapping[str, float]] = None) -> str:
    """Source of a standalone Python module for ``model`` (see the module docstring).

    Parameters
    ----------
    model : Model
    defaults : mapping of str to float, optional
        Values for every parameter, emitted as ``DEFAULT_PARAMETERS``.

    Raises
    ------
    CodegenError
        A function with no :mod:`math` equivalent, input derivatives, or a
        name no escape can carry (NUL, lone surrogate).
    ParameterValueError
        ``defaults`` missing or naming unknown parameters.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> _ = g.connect("F", "m")
    >>> model = bg.derive(g, outputs={"v": bg.flow("m")})
    >>> ns = {}
    >>> exec(generate_python(model, defaults={"m": 2.0}), ns)
    >>> ns["STATE_NAMES"], ns["DEFAULT_PARAMETERS"], ns["outputs"](0.0, [3.0], [1.0], [2.0])
    (('p_m',), {'m': 2.0}, [1.5])
    """
    from . import _newton_py

    pm = prepare(model, reserved=PY_RESERVED, defaults=defaults,
                 implicit_reserved=_newton_py.RESERVED)
    doc = [f"Model {shown(pm.name)} -- generated by bondgraph; do not edit.", "",
           "x' = derivatives(t, x, u, p), y = outputs(t, x, u, p); arrays in this order:", ""]
    doc += header_lines(pm, index_base=0)
    doc += ["", "p may also be a mapping from PARAMETER_NAMES to values.", ""]
    if pm.algebraic_ids:
        doc[-1:-1] = ["", "Implicit model: derivatives and outputs first solve 0 = g(t, x, z, u, p)",
                      "for the algebraic unknowns z (ALGEBRAIC_NAMES) by Newton's method, warm-",
                      "started from the last solution (solve_algebraic); AlgebraicSolveError",
                      "names the unknowns when it fails:"]
        doc[-1:-1] = [f"    z[{k}]  {shown(n)}: {shown(o)}"
                      for k, (n, o) in enumerate(zip(pm.algebraic_names, pm.algebraic_origin))]
    defaults_text = "None"
    if pm.defaults is not None:
        pairs = zip(pm.parameter_names, pm.defaults)
        defaults_text = "{" + ", ".join(f"{ascii(n)}: {float(v)!r}" for n, v in pairs) + "}"
    out = [py_docstring(doc), "", "import math", "",
           f"NAME = {ascii(pm.name)}",
           f"STATE_NAMES = {_str_tuple(pm.state_names)}",
           f"INPUT_NAMES = {_str_tuple(pm.input_names)}",
           f"OUTPUT_NAMES = {_str_tuple(pm.output_names)}",
           f"PARAMETER_NAMES = {_str_tuple(pm.parameter_names)}",
           f"DEFAULT_PARAMETERS = {defaults_text}", "", "",
           "def _params(p):",
           '    """Parameter values in the order of PARAMETER_NAMES (p: sequence or mapping)."""',
           '    if hasattr(p, "keys"):',
           "        return [p[name] for name in PARAMETER_NAMES]",
           "    return p", "", ""]
    if pm.algebraic_ids:
        out += _newton_py.solver_lines(pm, lambda *a: _function(pm, *a)) + ["", ""]
    out += _function(pm, "derivatives", pm.rhs, "State derivatives x' in the order of STATE_NAMES.")
    out += ["", ""]
    out += _function(pm, "outputs", pm.outputs, "Outputs y in the order of OUTPUT_NAMES.")
    text = "\n".join(out) + "\n"
    compile(text, "<bondgraph generated module>", "exec")  # a printer bug surfaces here, not on import
    return text


def write_python(model: Model, path: Union[str, "os.PathLike[str]"], *,
                 defaults: Optional[Mapping[str, float]] = None) -> Path:
    """Write the module to ``path`` (a ``.py`` file) atomically; returns the path.

    Parameters
    ----------
    model : Model
    path : str or path-like
        The ``.py`` file to write.
    defaults : mapping of str to float, optional
        Values for every parameter, emitted as ``DEFAULT_PARAMETERS``.

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
    ...     path = write_python(model, pathlib.Path(d, "mass_model.py"))
    ...     path.name, "def derivatives(t, x, u, p):" in path.read_text()
    ('mass_model.py', True)
    """
    return write_text(path, ".py", "Python", lambda p: generate_python(model, defaults=defaults))
