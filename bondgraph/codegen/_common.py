r"""Shared preparation for the code generators (private).

A model's symbols (``p_La``, ``motor.V``, ``motor.Ra``, time ``t``) are
renamed to identifiers valid in the target language, distinct from its
reserved words and from each other; the equations are rewritten in those
identifiers and split into common subexpressions with :func:`sympy.cse`.

Names reach generated text only through the escapes of each generator
(string literals, comments, docstrings); :func:`check_text` refuses the few
names no escape can carry (not text, NUL, lone surrogates), and
:func:`shown` gives the form of a name in comments: the name itself when it
is a (dotted) ASCII identifier, else a quoted, escaped, printable-ASCII form.

Examples
--------
>>> sanitize(["Ra", "motor.Ra", "motor_Ra", "for"], reserved={"for"})
('Ra', 'motor_Ra_2', 'motor_Ra', 'for_2')
>>> print(shown("motor.Ra"), shown('a*/ "b"\n'), shown("\u03b1"))
motor.Ra "a*/ \"b\"\n" "\u03b1"
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
from ..linear.trim import dirac_free
from ..model import Model
from ..signals import t as T_SYM

__all__ = ["CodegenError", "PreparedModel", "prepare", "sanitize", "split_cse", "C_RESERVED",
           "PY_RESERVED", "M_RESERVED", "check_identifier", "check_text", "shown", "header_lines",
           "TargetPrinter", "write_text", "residual_jacobian"]


class CodegenError(BondGraphError, ValueError):
    """Code cannot be generated: a bad name, an unsupported function, input derivatives."""


_C_KEYWORDS = """auto break case char const continue default do double else enum extern float for goto
if inline int long register restrict return short signed sizeof static struct switch typedef union
unsigned void volatile while _Bool _Complex _Imaginary bool true false NULL""".split()
_C_MATH = """acos acosh asin asinh atan atan2 atanh cbrt ceil copysign cos cosh erf erfc exp exp2 expm1
fabs fdim floor fma fmax fmin fmod frexp hypot ilogb ldexp lgamma llrint llround log log10 log1p log2
logb lrint lround modf nan nearbyint nextafter pow remainder remquo rint round scalbn sin sinh sqrt tan
tanh tgamma trunc j0 j1 jn y0 y1 yn gamma signbit isnan isinf isfinite HUGE_VAL INFINITY NAN
HUGE_VALF HUGE_VALL FP_NAN FP_INFINITE FP_ZERO FP_SUBNORMAL FP_NORMAL FP_ILOGB0 FP_ILOGBNAN FP_FAST_FMA
FP_FAST_FMAF FP_FAST_FMAL MATH_ERRNO MATH_ERREXCEPT math_errhandling fpclassify isnormal isgreater
isgreaterequal isless islessequal islessgreater isunordered float_t double_t HUGE MAXFLOAT DOMAIN SING
OVERFLOW UNDERFLOW TLOSS PLOSS X_TLOSS offsetof ptrdiff_t wchar_t entry""".split()  # macros of <math.h>,
# <stddef.h> (a local named after a macro would be rewritten by it) and the printer's reserved words
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
nargin nargout numel isfield error real imag native2unicode uint8 char double cell isempty true
false""".split() + _COMMON_ARGS)

# Identifiers are matched whole (fullmatch: ``$`` alone would let a trailing newline through).
# C: not ``_X...`` nor ``__...`` (reserved to the implementation: they may be macros).
_C_IDENT = re.compile(r"(?!_[A-Z_])[A-Za-z_][A-Za-z0-9_]*")
_M_IDENT = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,62}")
#: names shown as they are in comments: (dotted) ASCII identifiers
_PLAIN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*")
_NAMED_ESCAPES = {"\\": "\\\\", '"': '\\"', "\n": "\\n", "\r": "\\r", "\t": "\\t"}


def check_identifier(name: str, *, what: str, matlab: bool = False,
                     reserved: Iterable[str] = ()) -> str:
    r"""Check that ``name`` is usable as a generated function name or symbol prefix.

    Parameters
    ----------
    name : str
        The candidate, matched whole against the identifier rule of the target.
    what : str
        What the name is, for the error message (``"C name prefix"``).
    matlab : bool, default False
        MATLAB rule (a letter first, at most 63 characters) instead of C's.
    reserved : iterable of str
        Words the name must not be.

    Returns
    -------
    str
        ``name``.

    Raises
    ------
    CodegenError
        Naming ``name`` and the rule it breaks.

    Examples
    --------
    >>> check_identifier("plant", what="C name prefix")
    'plant'
    >>> try:
    ...     check_identifier("abc\n", what="C name prefix")
    ... except CodegenError as exc:
    ...     print(str(exc)[:40])
    C name prefix 'abc\n' is not usable: exp
    """
    pattern = _M_IDENT if matlab else _C_IDENT
    if not isinstance(name, str) or not pattern.fullmatch(name) or name in set(reserved):
        rule = ("a letter followed by letters, digits or underscores (at most 63 characters)"
                if matlab else "letters, digits and underscores, not starting with a digit "
                "(nor with _ and a capital or a second _)")
        raise CodegenError(f"{what} {name!r} is not usable: expected {rule}, and not a reserved word")
    return name


def check_text(name: object, *, what: str) -> str:
    r"""Check that ``name`` can be written into generated text (escaped as each place needs).

    Any text can be escaped except a NUL character (it would end a C string)
    and a lone surrogate (not Unicode, so it has no UTF-8 bytes).

    Parameters
    ----------
    name : object
        The name of a model, state, input, output or parameter.
    what : str
        What the name is, for the error message.

    Returns
    -------
    str
        ``name``.

    Raises
    ------
    CodegenError
        Naming ``name`` and what was expected.

    Examples
    --------
    >>> check_text('a*/ "b"', what="parameter")
    'a*/ "b"'
    >>> try:
    ...     check_text("a\x00b", what="parameter")
    ... except CodegenError as exc:
    ...     print(exc)
    parameter 'a\x00b' cannot be written into generated code: expected a str of Unicode text without NUL characters
    """
    if isinstance(name, str) and "\0" not in name:
        try:
            name.encode("utf-8")
        except UnicodeEncodeError:
            pass
        else:
            return name
    raise CodegenError(f"{what} {name!r} cannot be written into generated code: expected a str "
                       "of Unicode text without NUL characters")


def shown(name: str) -> str:
    r"""A name as comments show it: printable ASCII on one line, never ambiguous.

    A (dotted) ASCII identifier is shown as it is; any other name in double
    quotes with C-style escapes (``\\``, ``\"``, ``\n``, ``\r``, ``\t``,
    ``\xNN``, ``\uNNNN``, ``\UNNNNNNNN``).  Each generator adds what its
    comments need on top (C: no ``*/``, ``/*`` or trigraphs).

    Parameters
    ----------
    name : str
        A name accepted by :func:`check_text`.

    Returns
    -------
    str

    Examples
    --------
    >>> print(shown("motor.Ra"), shown("it's"), shown("e\u0301\u200f"), shown("\U0001f600"))
    motor.Ra "it's" "e\u0301\u200f" "\U0001f600"
    """
    if _PLAIN.fullmatch(name):
        return name
    out = []
    for ch in name:
        code = ord(ch)
        if ch in _NAMED_ESCAPES:
            out.append(_NAMED_ESCAPES[ch])
        elif 0x20 <= code < 0x7F:
            out.append(ch)
        elif code < 0x100:
            out.append(f"\\x{code:02x}")
        elif code < 0x10000:
            out.append(f"\\u{code:04x}")
        else:
            out.append(f"\\U{code:08x}")
    return '"' + "".join(out) + '"'


def sanitize(names: Sequence[str], *, reserved: Iterable[str] = (), matlab: bool = False,
             taken: Iterable[str] = ()) -> tuple[str, ...]:
    """Distinct identifiers for ``names``; names already valid keep their spelling.

    Invalid characters become ``_``; a name not starting with a letter gets a
    ``v`` prefix (MATLAB; C and Python: ``v_`` before a digit, ``v`` before
    ``_``); a clash with a reserved word or another name adds ``_2``, ``_3``...
    Identifiers are matched whole, so a name with a trailing newline is
    rewritten, never kept.
    """
    reserved = set(reserved)
    pattern = _M_IDENT if matlab else _C_IDENT
    used = set(taken) | reserved
    out: list[Optional[str]] = [None] * len(names)
    # pass 1: valid, unreserved names keep their spelling
    for i, name in enumerate(names):
        if pattern.fullmatch(name) and name not in used:
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
        elif not matlab and base[0] == "_":   # "_2", "__2" from "_": never _X... or __...
            base = "v" + base
        base = base[:58] if matlab else base
        cand = base
        for k in itertools.count(2):
            if cand not in used and pattern.fullmatch(cand):
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
    #: implicit models: algebraic unknowns z, residuals 0 = g(t, x, z, u, p) and dg/dz
    #: (row-major), in the same identifiers (see :mod:`bondgraph.codegen._newton`)
    algebraic_names: tuple[str, ...] = ()
    algebraic_ids: tuple[str, ...] = ()
    algebraic_origin: tuple[str, ...] = ()
    residuals: tuple[sympy.Expr, ...] = ()
    jacobian: tuple[sympy.Expr, ...] = ()

    @property
    def taken(self) -> set[str]:
        return (set(self.state_ids) | set(self.input_ids) | set(self.parameter_ids)
                | set(self.algebraic_ids) | {"t"})


def prepare(model: Model, *, reserved: Iterable[str], matlab: bool = False,
            defaults: Optional[Mapping[str, float]] = None,
            implicit_reserved: Iterable[str] = ()) -> PreparedModel:
    """Rename a model's symbols to identifiers and check it can be generated.

    ``implicit_reserved`` are further words model symbols must not take when
    the model is implicit (the names of the generated Newton solver's arrays).
    """
    if not isinstance(model, Model):
        raise CodegenError(f"expected a bondgraph Model (from bondgraph.derive); got {type(model).__name__}")
    if model.input_derivatives:
        raise CodegenError(
            f"model {model.name!r}: the equations use time derivatives of inputs "
            f"({', '.join(s.name for s in model.input_derivatives)}); no code can be generated "
            "from input values alone")
    params = model.parameters
    check_text(model.name, what="model name")
    for what, group in (("state", model.state_names), ("input", model.input_names),
                        ("output", model.output_names), ("parameter", [p.name for p in params]),
                        ("algebraic unknown", model.algebraic_names),
                        ("algebraic unknown's origin", model.algebraic_origin)):
        for text in group:
            check_text(text, what=f"model {model.name!r}: {what} name")
    reserved = set(reserved) | (set(implicit_reserved) if model.algebraic else set())
    names = (list(model.state_names) + list(model.input_names) + [p.name for p in params]
             + list(model.algebraic_names))
    ids = sanitize(names, reserved=reserved, matlab=matlab)
    n, m, k = len(model.states), len(model.inputs), len(params)
    state_ids, input_ids, param_ids = ids[:n], ids[n:n + m], ids[n + m:n + m + k]
    output_ids = sanitize(model.output_names, reserved=reserved, matlab=matlab)
    swap = {T_SYM: sympy.Symbol("t", real=True)}
    symbols = list(model.states) + list(model.inputs) + list(params) + list(model.algebraic)
    for sym, ident in zip(symbols, ids):
        swap[sym] = sympy.Symbol(ident, real=True)
    rhs = tuple(_rename(ex, swap, model) for ex in model.rhs)
    outs = tuple(_rename(ex, swap, model) for ex in model.output_exprs)
    implicit: dict = {}
    if model.algebraic:
        res, jac = residual_jacobian(model)
        implicit = dict(algebraic_names=model.algebraic_names, algebraic_ids=ids[n + m + k:],
                        algebraic_origin=model.algebraic_origin,
                        residuals=tuple(_rename(ex, swap, model) for ex in res),
                        jacobian=tuple(_rename(ex, swap, model) for ex in jac))
    default_values = None
    if defaults is not None:
        from ..numeric.resolve import resolve_parameters

        default_values = tuple(resolve_parameters(params, defaults, model=model.name,
                                                  known=model.known_parameters).tolist())
        from ..elements.rules import check_model_values

        check_model_values(model, dict(zip((p.name for p in params), default_values)),
                           where=f"model {model.name!r}: ")
    return PreparedModel(model.name, model.state_names, model.input_names, model.output_names,
                         tuple(p.name for p in params), state_ids, input_ids, output_ids,
                         param_ids, rhs, outs, default_values, **implicit)


def residual_jacobian(model: Model) -> tuple[tuple[sympy.Expr, ...], tuple[sympy.Expr, ...]]:
    """The residuals ``g`` and ``dg/dz`` (row-major) of an implicit model, in its own symbols.

    ``dg/dz`` is differentiated in the model's real symbols (``d|z|/dz =
    sign(z)``); a ``DiracDelta`` (the slope of ``sign`` or ``Heaviside``) is 0
    away from the jump.

    Examples
    --------
    >>> import sympy, bondgraph as bg
    >>> Is, Vt = sympy.symbols("Is Vt", positive=True)
    >>> g = bg.BondGraph("diode")
    >>> g.add(bg.C("C"), bg.One("s"), bg.R("R"), bg.R("D", inverse=Is*(sympy.exp(bg.e/Vt) - 1)))
    >>> for t, h in [("s", "C"), ("s", "R"), ("s", "D")]: _ = g.connect(t, h)
    >>> residual_jacobian(bg.derive(g))[1]
    (1 + Vt/(Is*R*(1 + f_D/Is)),)

    Raises
    ------
    CodegenError
        A residual whose derivative sympy leaves unevaluated (a user
        function with no derivative), naming the unknown.
    """
    z = list(model.algebraic)
    res = tuple(model.residuals)
    jac = dirac_free(sympy.Matrix(res).jacobian(z))
    flat = tuple(jac[i, j] for i in range(len(z)) for j in range(len(z)))
    for k, entry in enumerate(flat):
        if entry.atoms(sympy.Derivative, sympy.Subs):
            i, j = divmod(k, len(z))
            raise CodegenError(
                f"model {model.name!r}: the residual of {model.algebraic_names[i]} has no "
                f"analytic derivative with respect to {model.algebraic_names[j]} ({entry}); "
                "Newton's method in generated code needs dg/dz: give the law's function a "
                "derivative (fdiff) or an explicit inverse")
    return res, flat


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


def header_lines(pm: PreparedModel, *, index_base: int, show: Callable[[str], str] = shown,
                 xname: str = "x", uname: str = "u", yname: str = "y", pname: str = "p") -> list[str]:
    """Human-readable order of the arrays, one line per signal, for header comments.

    Every name goes through ``show``, which must make it safe for the
    comment it lands in (:func:`shown`, plus the target's own escapes).
    """
    def rows(title: str, arr: str, names: Sequence[str], ids: Sequence[str],
             values: Optional[Sequence[float]] = None) -> list[str]:
        out = [f"{title} ({len(names)}):"]
        if not names:
            out.append("    (none)")
        for k, (nm, ident) in enumerate(zip(names, ids)):
            open_, close = ("(", ")") if index_base == 1 else ("[", "]")
            alias = "" if nm == ident else f"  [as {ident}]"
            default = "" if values is None else f"  default {_num(values[k])}"
            out.append(f"    {arr}{open_}{k + index_base}{close}  {show(nm)}{alias}{default}")
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
