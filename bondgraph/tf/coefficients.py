"""Coefficient tables of a transfer function: power, value, unit, a printed reference, the symbolic form.

A paper prints a transfer function as ``(a_n s^n + ... + a_0)/(b_m s^m +
... + b_0)`` with a list of numbers (seed 000, Eq. 13); a console needs the
same thing in lines a reader can follow.  :func:`coefficient_table` gives
one row per coefficient, ``a`` for the numerator and ``b`` for the
denominator, every power of the requested form present (a coefficient that
vanishes is a row with value 0), and :meth:`CoefficientTable.format` writes
it wrapped to a width: the fixed columns on one line, the symbolic
coefficient under it, broken at ``+``, ``-``, ``*`` and ``/``.

Units: a denominator whose leading coefficient is 1 makes ``b_k`` a
``1/time^(m-k)``, and ``a_k`` carries ``[output]/[input]`` on top of that;
they are shown when the units are given (``output_unit``, ``input_unit``)
and the denominator is monic, else left blank.

Examples
--------
>>> import sympy as sp
>>> from bondgraph.tf import SymbolicTF
>>> m, b, k, s = sp.symbols("m b k s", positive=True)
>>> G = SymbolicTF(sp.Poly(1 / m, s), sp.Poly(s**2 + b / m * s + k / m, s), "F", "x")
>>> t = coefficient_table(G, {"m": 2.0, "b": 0.4, "k": 50.0}, output_unit="m", input_unit="N",
...                       printed_num=[0.5], printed_den=[1.0, 0.25, 25.0])
>>> print(t.format(width=60))
coef  power  value  unit       printed  ratio
----  -----  -----  ---------  -------  -----
a0    1      0.5    m/(N s^2)  0.5      1
        = 1/m
b2    s^2    1      1          1        1
b1    s      0.2    1/s        0.25     0.8
        = b/m
b0    1      25     1/s^2      25       1
        = k/m
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping, Optional, Sequence

import sympy as sp

from .errors import InvalidOptionError
from .tables import format_number

__all__ = ["CoefficientRow", "CoefficientTable", "coefficient_table", "wrap_expression"]


@dataclass(frozen=True)
class CoefficientRow:
    """One coefficient: ``name`` (``a4``), its ``power`` of ``s``, symbolic form, value, unit, printed value."""

    name: str
    power: int
    symbolic: sp.Expr
    value: Optional[float] = None
    unit: Optional[str] = None
    printed: Optional[float] = None

    @property
    def ratio(self) -> Optional[float]:
        """``value / printed`` (None without both, or for a printed 0)."""
        if self.value is None or self.printed is None or self.printed == 0.0:
            return None
        return self.value / self.printed


def _cuts(text: str) -> list[str]:
    """``text`` cut after each ``*`` or ``/`` that is not part of ``**``."""
    pieces, start = [], 0
    for i, ch in enumerate(text):
        if ch in "*/" and not (ch == "*" and (text[i - 1:i] == "*" or text[i + 1:i + 2] == "*")):
            pieces.append(text[start:i + 1])
            start = i + 1
    if start < len(text):
        pieces.append(text[start:])
    return pieces


def wrap_expression(text: str, width: int) -> list[str]:
    """``text`` in lines of at most ``width`` characters.

    Lines break at spaces (between the terms of a sum) where a term fits; a
    term longer than the room left is broken after a ``*`` or ``/`` (never
    inside ``**``); a run with no such break longer than ``width`` is cut.

    Examples
    --------
    >>> wrap_expression("a*b*c + d**2*e/f - g", 7)
    ['a*b*c +', 'd**2*e/', 'f - g']
    """
    if isinstance(width, bool) or not isinstance(width, int) or width < 1:
        raise InvalidOptionError(f"width: expected a positive number of characters, got {width!r}")
    words = text.split(" ")
    lines: list[str] = []
    line = ""
    for word in words:
        joined = f"{line} {word}" if line else word
        if len(joined) <= width:
            line = joined
            continue
        if len(word) <= width:
            lines.append(line)
            line = word
            continue
        # a long term: fill the current line, then whole lines, at the cuts
        for piece in _cuts(word):
            sep = " " if line and not line.endswith(("*", "/")) else ""
            if len(line) + len(sep) + len(piece) <= width:
                line += sep + piece
                continue
            if line:
                lines.append(line)
            while len(piece) > width:
                lines.append(piece[:width])
                piece = piece[width:]
            line = piece
    if line:
        lines.append(line)
    return lines


def _power_text(k: int) -> str:
    return "1" if k == 0 else ("s" if k == 1 else f"s^{k}")


def _time_unit(k: int, time: str) -> str:
    return "1" if k == 0 else (f"1/{time}" if k == 1 else f"1/{time}^{k}")


def _ratio_unit(top: str, bottom: str, k: int, time: str) -> str:
    """``top/bottom`` times ``time^-k``: ``m/V``, ``m/(V s)``, ``m/(V s^2)``; ``1/s`` when
    ``top`` and ``bottom`` are the same unit."""
    if top == bottom:
        return _time_unit(k, time)
    if k == 0:
        return f"{top}/{bottom}"
    t = time if k == 1 else f"{time}^{k}"
    return f"{top}/({bottom} {t})"


@dataclass(frozen=True)
class CoefficientTable:
    """Rows of :class:`CoefficientRow`, numerator first, highest power first; see :func:`coefficient_table`."""

    rows: tuple[CoefficientRow, ...]
    printed_label: str = "printed"
    digits: int = 4

    def format(self, width: int = 100) -> str:
        """The table in lines of at most ``width`` characters (at least 40).

        Columns ``coef``, ``power``, ``value``, ``unit`` and, when a printed
        reference was given, the printed value and ``ratio``; the symbolic
        coefficient follows its row on lines indented by 8, ``= ...``,
        unless it is a plain number (then the value says it all).
        """
        if isinstance(width, bool) or not isinstance(width, int) or width < 40:
            raise InvalidOptionError(f"width: expected an integer >= 40, got {width!r}")
        d = self.digits
        printed = any(r.printed is not None for r in self.rows)
        head = ["coef", "power", "value", "unit"] + ([self.printed_label, "ratio"] if printed else [])

        def num(x: Optional[float]) -> str:
            return "" if x is None else format_number(x, d)

        cells = []
        for r in self.rows:
            row = [r.name, _power_text(r.power), num(r.value), r.unit or ""]
            if printed:
                row += [num(r.printed), num(r.ratio)]
            cells.append(row)
        widths = [max(len(h), *(len(c[k]) for c in cells)) for k, h in enumerate(head)]
        lines = ["  ".join(h.ljust(w) for h, w in zip(head, widths)).rstrip(),
                 "  ".join("-" * w for w in widths)]
        indent = " " * 8
        for r, c in zip(self.rows, cells):
            lines.append("  ".join(x.ljust(w) for x, w in zip(c, widths)).rstrip()[:width])
            if r.symbolic.is_number:
                continue
            text = "= " + str(r.symbolic)
            for piece in wrap_expression(text, width - len(indent)):
                lines.append((indent + piece).rstrip())
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.format()


def _padded(coeffs: Sequence, degree: int, what: str) -> list:
    """``coeffs`` (highest power first) as a list of ``degree + 1`` entries, zeros in front."""
    coeffs = list(coeffs)
    # leading zeros beyond the form are allowed; anything else does not fit it
    while len(coeffs) > degree + 1 and coeffs[0] == 0:
        coeffs.pop(0)
    if len(coeffs) > degree + 1:
        raise InvalidOptionError(f"{what}: the form has degree {degree} but the polynomial has degree "
                                 f"{len(coeffs) - 1}")
    return [sp.Integer(0)] * (degree + 1 - len(coeffs)) + coeffs


def coefficient_table(G, values: Optional[Mapping] = None, *,
                      printed_num: Optional[Sequence[float]] = None,
                      printed_den: Optional[Sequence[float]] = None,
                      printed_label: str = "printed",
                      num_degree: Optional[int] = None, den_degree: Optional[int] = None,
                      output_unit: Optional[str] = None, input_unit: Optional[str] = None,
                      time_unit: str = "s", digits: int = 4) -> CoefficientTable:
    """The coefficient table of a :class:`~bondgraph.tf.SymbolicTF`.

    Parameters
    ----------
    G : SymbolicTF
    values : mapping of parameter name (or Symbol) to number, optional
        Parameter values (every parameter of ``G``); the ``value`` column.
    printed_num, printed_den : sequence of float, optional
        Published coefficients, highest power first (the ``printed`` and
        ``ratio`` columns); their lengths set the form's degrees unless
        ``num_degree``/``den_degree`` are given.
    printed_label : str
        Heading of the printed column (``"paper (Eq. 13)"``).
    num_degree, den_degree : int, optional
        Degrees of the form to show (every power down to 0 gets a row);
        default the larger of the polynomial's degree and the printed list's.
    output_unit, input_unit : str, optional
        Units of the output and input signals (``"m"``, ``"V"``).
    time_unit : str
        Unit of time (the unit of ``1/s``).
    digits : int
        Significant digits of the numbers.

    Returns
    -------
    CoefficientTable

    Raises
    ------
    InvalidOptionError
        A degree smaller than the polynomial's, or a printed list longer
        than the form.
    ParameterValueError
        ``values`` misses a parameter or names an unknown one.

    Examples
    --------
    >>> import sympy as sp
    >>> from bondgraph.tf import SymbolicTF
    >>> a, s = sp.symbols("a s", positive=True)
    >>> G = SymbolicTF(sp.Poly(a, s), sp.Poly(s**2 + a*s, s), "u", "y")
    >>> [(r.name, r.power, r.symbolic, r.value) for r in coefficient_table(G, {"a": 3.0}, num_degree=1).rows]
    [('a1', 1, 0, 0.0), ('a0', 0, a, 3.0), ('b2', 2, 1, 1.0), ('b1', 1, a, 3.0), ('b0', 0, 0, 0.0)]
    """
    num, den = list(G.num_coeffs), list(G.den_coeffs)
    if num_degree is None:
        num_degree = max(len(num), len(printed_num or ())) - 1
    if den_degree is None:
        den_degree = max(len(den), len(printed_den or ())) - 1
    num, den = _padded(num, num_degree, "numerator"), _padded(den, den_degree, "denominator")
    for given, degree, what in ((printed_num, num_degree, "printed_num"), (printed_den, den_degree, "printed_den")):
        if given is not None and len(given) > degree + 1:
            raise InvalidOptionError(f"{what}: {len(given)} coefficients for a form of degree {degree}")
    pnum = [None] * (num_degree + 1 - len(printed_num or ())) + [float(c) for c in printed_num or ()]
    pden = [None] * (den_degree + 1 - len(printed_den or ())) + [float(c) for c in printed_den or ()]
    vnum: list = [None] * len(num)
    vden: list = [None] * len(den)
    if values is not None:
        N = G.subs(values)
        vnum = [0.0] * (len(num) - len(N.num)) + list(N.num)
        vden = [0.0] * (len(den) - len(N.den)) + list(N.den)
    monic = sp.simplify(den[0] - 1) == 0
    rows = []
    for k, c in enumerate(num):
        power = num_degree - k
        unit = None
        if monic and output_unit and input_unit:
            unit = _ratio_unit(output_unit, input_unit, den_degree - power, time_unit)
        rows.append(CoefficientRow(f"a{power}", power, sp.sympify(c, strict=True), vnum[k], unit, pnum[k]))
    for k, c in enumerate(den):
        power = den_degree - k
        unit = _time_unit(den_degree - power, time_unit) if monic else None
        rows.append(CoefficientRow(f"b{power}", power, sp.sympify(c, strict=True), vden[k], unit, pden[k]))
    if not (isinstance(digits, int) and digits >= 1) or isinstance(digits, bool):
        raise InvalidOptionError(f"digits: expected an integer >= 1, got {digits!r}")
    for r in rows:
        if r.value is not None and not math.isfinite(r.value):
            raise InvalidOptionError(f"coefficient {r.name} is not finite at these values ({r.value})")
    return CoefficientTable(tuple(rows), printed_label, digits)
