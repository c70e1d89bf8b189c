"""Shared preparation for the code generators (private).

A model's symbols (``p_La``, ``motor.V``, ``motor.Ra``, time ``t``) are
renamed to identifiers valid in the target language, distinct from its
reserved words and from each other; the equations are rewritten in those
identifiers and split into common subexpressions with :func:`sympy.cse`.

Examples
--------
>>> sanitize(["Ra", "motor.Ra", "motor_Ra", "for"], reserved={"for"})
('Ra', 'motor_Ra_2', 'motor_Ra', 'for_2')
"""

from __future__ import annotations

import itertools
import keyword
import math
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable, Mapping, Optional, Sequence, Union

import sympy
from sympy.printing.codeprinter import PrintMethodNotImplementedError

from ..errors import BondGraphError
from ..model import Model
from ..signals import t as T_SYM

__all__ = ["CodegenError", "PreparedModel", "prepare", "sanitize", "split_cse", "C_RESERVED",
           "PY_RESERVED", "M_RESERVED", "check_identifier", "header_lines", "TargetPrinter",
           "write_text"]


class CodegenError(BondGraphError, ValueError):
    """Code cannot be generated: a bad name, an unsupported function, input derivatives."""


_C_KEYWORDS = """auto break case char const continue default do double else enum extern float for goto
if inline int long register restrict return short signed sizeof static struct switch typedef union
unsigned void volatile while _Bool _Complex _Imaginary bool true false NULL""".split()
_C_MATH = """acos acosh asin asinh atan atan2 atanh cbrt ceil copysign cos cosh erf erfc exp exp2 expm1
fabs fdim floor fma fmax fmin fmod frexp hypot ilogb ldexp lgamma llrint llround log log10 log1p log2
logb lrint lround modf nan nearbyint nextafter pow remainder remquo rint round scalbn sin sinh sqrt tan
tanh tgamma trunc j0 j1 jn y0 y1 yn gamma signbit isnan isinf isfinite HUGE_VAL INFINITY NAN""".split()
_COMMON_ARGS = ["t", "x", "u", "p", "xdot", "y"]   # arguments of the generated functions

#: identifiers generated C code must not use for model symbols
C_RESERVED = frozenset(_C_KEYWORDS + _C_MATH + _COMMON_ARGS + ["main", "printf", "size_t"])
#: ... generated Python code
PY_RESERVED = frozenset(list(keyword.kwlist) + list(getattr(keyword, "softkwlist", [])) + _COMMON_ARGS + [
    "math", "abs", "min", "max", "float", "int", "len", "list", "tuple", "dict", "range", "round",
    "derivatives", "outputs", "NAME", "STATE_NAMES", "INPUT_NAMES", "OUTPUT_NAMES",
    "PARAMETER_NAMES", "DEFAULT_PARAMETERS", "_params", "hasattr", "print", "self", "cls"])
#: ... generated MATLAB / Octave code
M_RESERVED = frozenset("""break case catch classdef continue else elseif end for function global if
otherwise parfor persistent return spmd switch try unwind_protect unwind_protect_cleanup while
end_try_catch endfunction endif endfor endwhile endswitch do until
pi e i j Inf inf NaN nan eps abs sign sqrt exp log log10 log2 sin cos tan asin acos atan atan2 sinh cosh
tanh asinh acosh atanh floor ceil mod rem max min heaviside gamma erf besselj zeros ones struct isstruct
nargin nargout numel isfield error real imag""".split() + _COMMON_ARGS)

_C_IDENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_M_IDENT = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,62}$")


def check_identifier(name: str, *, what: str, matlab: bool = False,
                     reserved: Iterable[str] = ()) -> str:
    """Check that ``name`` is usable as a generated function or file name."""
    pattern = _M_IDENT if matlab else _C_IDENT
    if not isinstance(name, str) or not pattern.match(name) or name in set(reserved):
        rule = ("a letter followed by letters, digits or underscores (at most 63 characters)"
                if matlab else "letters, digits and underscores, not starting with a digit")
        raise CodegenError(f"{what} {name!r} is not usable: expected {rule}, and not a reserved word")
    return name


def sanitize(names: Sequence[str], *, reserved: Iterable[str] = (), matlab: bool = False,
             taken: Iterable[str] = ()) -> tuple[str, ...]:
    """Distinct identifiers for ``names``; names already valid keep their spelling.

    Invalid characters become ``_``; a name not starting with a letter gets a
    ``v`` prefix (MATLAB) or ``v_`` (C, Python, only when it starts with a
    digit); a clash with a reserved word or another name adds ``_2``, ``_3``...
    """
    reserved = set(reserved)
    pattern = _M_IDENT if matlab else _C_IDENT
    used = set(taken) | reserved
    out: list[Optional[str]] = [None] * len(names)
    # pass 1: valid, unreserved names keep their spelling
    for i, name in enumerate(names):
        if pattern.match(name) and name not in used:
            out[i] = name
            used.add(name)
    # pass 2: everything else is rewritten
    for i, name in enumerate(names):
        if out[i] is not None:
            continue
        base = re.sub(r"[^A-Za-z0-9_]", "_", name) or "v"
        if matlab and not base[0].isalpha():
            base = "v" + base
        elif not matlab and base[0].isdigit():
            base = "v_" + base
        base = base[:58] if matlab else base
        cand = base
        for k in itertools.count(2):
            if cand not in used and pattern.match(cand):
                break
            cand = f"{base}_{k}"
        out[i] = cand
        used.add(cand)
    return tuple(out)  # type: ignore[arg-type]


@dataclass(frozen=True)
class PreparedModel:
    """A model's equations in target-language identifiers.

    ``*_ids`` are the identifiers standing for the names in ``*_names``;
    ``rhs`` and ``outputs`` use plain symbols named by those identifiers and
    ``Symbol('t')`` for time.
    """

    name: str
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    parameter_names: tuple[str, ...]
    state_ids: tuple[str, ...]
    input_ids: tuple[str, ...]
    output_ids: tuple[str, ...]
    parameter_ids: tuple[str, ...]
    rhs: tuple[sympy.Expr, ...]
    outputs: tuple[sympy.Expr, ...]
    defaults: Optional[tuple[float, ...]]

    @property
    def taken(self) -> set[str]:
        return set(self.state_ids) | set(self.input_ids) | set(self.parameter_ids) | {"t"}


def prepare(model: Model, *, reserved: Iterable[str], matlab: bool = False,
            defaults: Optional[Mapping[str, float]] = None) -> PreparedModel:
    """Rename a model's symbols to identifiers and check it can be generated."""
    if not isinstance(model, Model):
        raise CodegenError(f"expected a bondgraph Model (from bondgraph.derive); got {type(model).__name__}")
    if model.input_derivatives:
        raise CodegenError(
            f"model {model.name!r}: the equations use time derivatives of inputs "
            f"({', '.join(s.name for s in model.input_derivatives)}); no code can be generated "
            "from input values alone")
    params = model.parameters
    reserved = set(reserved)
    names = list(model.state_names) + list(model.input_names) + [p.name for p in params]
    ids = sanitize(names, reserved=reserved, matlab=matlab)
    n, m = len(model.states), len(model.inputs)
    state_ids, input_ids, param_ids = ids[:n], ids[n:n + m], ids[n + m:]
    output_ids = sanitize(model.output_names, reserved=reserved, matlab=matlab)
    swap = {T_SYM: sympy.Symbol("t", real=True)}
    for sym, ident in zip(list(model.states) + list(model.inputs) + list(params), ids):
        swap[sym] = sympy.Symbol(ident, real=True)
    rhs = tuple(_rename(ex, swap, model) for ex in model.rhs)
    outs = tuple(_rename(ex, swap, model) for ex in model.output_exprs)
    default_values = None
    if defaults is not None:
        from ..numeric.parameters import resolve_parameters

        default_values = tuple(resolve_parameters(params, defaults, model=model.name).tolist())
    return PreparedModel(model.name, model.state_names, model.input_names, model.output_names,
                         tuple(p.name for p in params), state_ids, input_ids, output_ids,
                         param_ids, rhs, outs, default_values)


def _rename(ex: sympy.Expr, swap: dict, model: Model) -> sympy.Expr:
    stray = ex.free_symbols - set(swap)
    if stray:  # pragma: no cover - Model guarantees states, inputs, parameters and t only
        raise CodegenError(f"model {model.name!r}: unexpected symbols {stray} in the equations")
    return ex.xreplace(swap)


def split_cse(exprs: Sequence[sympy.Expr], taken: Iterable[str],
              prefix: str = "tmp") -> tuple[list[tuple[sympy.Symbol, sympy.Expr]], list[sympy.Expr]]:
    """``sympy.cse`` with temporaries named ``tmp0, tmp1, ...`` that avoid ``taken``."""
    taken = set(taken)
    gen = (sympy.Symbol(f"{prefix}{k}", real=True) for k in itertools.count()
           if f"{prefix}{k}" not in taken)
    if not exprs:
        return [], []
    reps, reduced = sympy.cse(list(exprs), symbols=gen, order="canonical")
    return list(reps), list(reduced)


def header_lines(pm: PreparedModel, *, index_base: int, xname: str = "x", uname: str = "u",
                 yname: str = "y", pname: str = "p") -> list[str]:
    """Human-readable order of the arrays, one line per signal, for header comments."""
    def rows(title: str, arr: str, names: Sequence[str], ids: Sequence[str],
             values: Optional[Sequence[float]] = None) -> list[str]:
        out = [f"{title} ({len(names)}):"]
        if not names:
            out.append("    (none)")
        for k, (nm, ident) in enumerate(zip(names, ids)):
            open_, close = ("(", ")") if index_base == 1 else ("[", "]")
            alias = "" if nm == ident else f"  [as {ident}]"
            default = "" if values is None else f"  default {_num(values[k])}"
            out.append(f"    {arr}{open_}{k + index_base}{close}  {nm}{alias}{default}")
        return out

    return (rows("states", xname, pm.state_names, pm.state_ids)
            + rows("inputs", uname, pm.input_names, pm.input_ids)
            + rows("outputs", yname, pm.output_names, pm.output_names)
            + rows("parameters", pname, pm.parameter_names, pm.parameter_ids, pm.defaults))


def _num(value: float) -> str:
    return repr(float(value)) if math.isfinite(value) else str(value)


class TargetPrinter:
    """Code-printer mixin: doubles printed exactly; a function the target lacks is an error.

    Subclasses set ``missing``, how the error words the lack (``"C has no function"``).
    """

    missing = "no function"

    def _print_Float(self, expr) -> str:
        return repr(float(expr))

    def code(self, expr: sympy.Expr, where: str) -> str:
        """``doprint(expr)``; a missing function is a :class:`CodegenError` naming ``where``."""
        try:
            return self.doprint(expr)  # type: ignore[attr-defined]
        except PrintMethodNotImplementedError as exc:
            first = str(exc).split("\n")[0]
            raise CodegenError(f"{where}: {self.missing} for part of {expr}: {first}") from exc


def write_text(path: Union[str, "os.PathLike[str]"], suffix: str, language: str,
               text_for: Callable[[Path], str]) -> Path:
    """Write ``text_for(path)`` to ``path`` (which must end in ``suffix``) atomically."""
    from ..export import atomic_write

    p = Path(os.fspath(path))
    if p.suffix != suffix:
        raise CodegenError(f"{language} output '{p}' must end in {suffix}")
    text = text_for(p)
    atomic_write(p, lambda fh: fh.write(text), binary=False)
    return p
