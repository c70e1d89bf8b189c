"""Pole/zero tables: roots, natural frequencies (rad/s and Hz), damping ratios.

Like Table 2 of Barbosa & Góes (poles, zeros and their frequencies), as a
frozen object with plain-text, booktabs LaTeX and Jupyter renderings.

Examples
--------
>>> from bondgraph.tf.tables import pole_zero_table
>>> t = pole_zero_table([1.0, 2.0], [1.0, 0.2, 4.0])   # (s + 2)/(s^2 + 0.2 s + 4)
>>> [(r.kind, r.pair, round(r.wn, 6), round(r.zeta, 6)) for r in t.rows]
[('pole', True, 2.0, 0.05), ('zero', False, 2.0, 1.0)]
>>> print(t)
kind  root           wn (rad/s)  f (Hz)  zeta
----  -------------  ----------  ------  ----
pole  -0.1 ± 1.997i  2           0.3183  0.05
zero  -2             2           0.3183  1
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable, Sequence

import numpy as np

from .errors import InvalidOptionError

__all__ = ["PoleZeroRow", "PoleZeroTable", "pole_zero_table", "format_number", "snap_roots"]


def format_number(x: float, digits: int = 4) -> str:
    """``x`` with ``digits`` significant digits, no trailing zeros.

    Parameters
    ----------
    x : float
        The number (NaN and infinities are written ``nan``, ``inf``, ``-inf``).
    digits : int
        Significant digits.

    Returns
    -------
    str

    Examples
    --------
    >>> format_number(0.318309886), format_number(2.0), format_number(-1.07e-05)
    ('0.3183', '2', '-1.07e-05')
    """
    if x == 0:
        return "0"
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return f"{x:.{digits}g}"


def latex_number(x: float, digits: int = 4) -> str:
    """``format_number`` with exponents as ``\\cdot 10^{k}``.

    Examples
    --------
    >>> latex_number(-1.07e-05)
    '-1.07 \\\\cdot 10^{-5}'
    """
    txt = format_number(x, digits)
    if "e" in txt:
        mant, exp = txt.split("e")
        return f"{mant} \\cdot 10^{{{int(exp)}}}"
    if txt in ("inf", "-inf"):
        return txt.replace("inf", "\\infty")
    return txt


def snap_roots(roots: Iterable[complex], tol: float = 1e-9) -> list[complex]:
    """Set real or imaginary parts below ``tol * |root|`` to exactly zero.

    Parameters
    ----------
    roots : iterable of complex
        The roots to clean.
    tol : float
        Relative threshold.

    Returns
    -------
    list of complex

    Examples
    --------
    >>> snap_roots([1e-17 + 2j, -3 + 1e-20j])
    [2j, (-3+0j)]
    """
    out = []
    for r in roots:
        r = complex(r)
        mag = abs(r)
        re, im = r.real, r.imag
        if abs(im) <= tol * mag:
            im = 0.0
        if abs(re) <= tol * mag:
            re = 0.0
        out.append(complex(re, im))
    return out


@dataclass(frozen=True)
class PoleZeroRow:
    """One real root or one complex-conjugate pair ``value`` and its conjugate.

    ``wn = |value|`` (rad/s), ``hz = wn / 2 pi``, ``zeta = -Re(value) / wn``
    (``nan`` for a root at the origin).

    Examples
    --------
    >>> row = pole_zero_table([1.0], [1.0, 2.0, 4.0]).rows[0]     # 1/(s^2 + 2 s + 4)
    >>> row.kind, row.pair, round(row.wn, 12), round(row.zeta, 12), row.root_text()
    ('pole', True, 2.0, 0.5, '-1 ± 1.732i')
    """

    kind: str
    value: complex
    pair: bool
    wn: float
    hz: float
    zeta: float

    def root_text(self, digits: int = 4) -> str:
        """``'-0.1 ± 2i'`` for a pair, ``'-2'`` for a real root."""
        re = format_number(self.value.real, digits)
        if not self.pair:
            return re
        return f"{re} ± {format_number(abs(self.value.imag), digits)}i"

    def root_latex(self, digits: int = 4) -> str:
        re = latex_number(self.value.real, digits)
        if not self.pair:
            return re
        return f"{re} \\pm {latex_number(abs(self.value.imag), digits)}i"


def _rows(kind: str, roots: Iterable[complex], tol: float) -> list[PoleZeroRow]:
    roots = snap_roots(roots, tol)
    rows = []
    upper = [r for r in roots if r.imag > 0]
    lower = [r for r in roots if r.imag < 0]
    real = [r for r in roots if r.imag == 0]
    # each upper root is one pair; unmatched lower roots (complex polynomials) too
    for r in upper:
        rows.append(_row(kind, r, True))
    for r in lower[len(upper):]:
        rows.append(_row(kind, r.conjugate(), True))
    for r in real:
        rows.append(_row(kind, complex(r.real, 0.0), False))
    rows.sort(key=lambda row: (row.wn, row.value.real, row.value.imag))
    return rows


def _row(kind: str, r: complex, pair: bool) -> PoleZeroRow:
    wn = abs(r)
    zeta = (-r.real / wn + 0.0) if wn > 0 else float("nan")
    return PoleZeroRow(kind, r, pair, wn, wn / (2 * math.pi), zeta)


@dataclass(frozen=True)
class PoleZeroTable:
    """Poles and zeros with natural frequency (rad/s, Hz) and damping ratio.

    Rows are the poles sorted by natural frequency, then the zeros.  Complex
    conjugate pairs take one row (``value`` is the root with positive
    imaginary part).  Made by :func:`pole_zero_table`.

    Examples
    --------
    >>> t = pole_zero_table([1.0, 0.0], [1.0, 3.0, 2.0])    # s/((s + 1)(s + 2))
    >>> len(t.poles), len(t.zeros), [r.root_text() for r in t.rows]
    (2, 1, ['-1', '-2', '0'])
    >>> print(t)
    kind  root  wn (rad/s)  f (Hz)  zeta
    ----  ----  ----------  ------  ----
    pole  -1    1           0.1592  1
    pole  -2    2           0.3183  1
    zero  0     0           0       —
    """

    rows: tuple[PoleZeroRow, ...]
    digits: int = 4

    @property
    def poles(self) -> tuple[PoleZeroRow, ...]:
        return tuple(r for r in self.rows if r.kind == "pole")

    @property
    def zeros(self) -> tuple[PoleZeroRow, ...]:
        return tuple(r for r in self.rows if r.kind == "zero")

    def _cells(self) -> list[list[str]]:
        d = self.digits
        return [[r.kind, r.root_text(d), format_number(r.wn, d), format_number(r.hz, d),
                 "—" if math.isnan(r.zeta) else format_number(r.zeta, d)] for r in self.rows]

    def __str__(self) -> str:
        head = ["kind", "root", "wn (rad/s)", "f (Hz)", "zeta"]
        cells = self._cells()
        widths = [max([len(head[k])] + [len(c[k]) for c in cells]) for k in range(5)]
        lines = ["  ".join(h.ljust(w) for h, w in zip(head, widths)).rstrip(),
                 "  ".join("-" * w for w in widths)]
        for c in cells:
            lines.append("  ".join(x.ljust(w) for x, w in zip(c, widths)).rstrip())
        return "\n".join(lines)

    def to_latex(self, *, caption: str | None = None, label: str | None = None) -> str:
        """A booktabs ``tabular`` (inside a ``table`` when caption/label given).

        Examples
        --------
        >>> print(pole_zero_table([1.0], [1.0, 2.0]).to_latex())
        \\begin{tabular}{llrrr}
        \\toprule
         & Root & $\\omega_n$ (rad/s) & $f_n$ (Hz) & $\\zeta$ \\\\
        \\midrule
        Pole & $-2$ & 2 & 0.3183 & 1 \\\\
        \\bottomrule
        \\end{tabular}
        """
        d = self.digits
        lines = ["\\begin{tabular}{llrrr}", "\\toprule",
                 " & Root & $\\omega_n$ (rad/s) & $f_n$ (Hz) & $\\zeta$ \\\\", "\\midrule"]
        for r in self.rows:
            zeta = "---" if math.isnan(r.zeta) else latex_number(r.zeta, d)
            lines.append(f"{r.kind.capitalize()} & ${r.root_latex(d)}$ & "
                         f"{latex_number(r.wn, d)} & {latex_number(r.hz, d)} & {zeta} \\\\")
        lines += ["\\bottomrule", "\\end{tabular}"]
        body = "\n".join(lines)
        if caption is None and label is None:
            return body
        out = ["\\begin{table}", "\\centering"]
        if caption is not None:
            out.append(f"\\caption{{{caption}}}")
        if label is not None:
            out.append(f"\\label{{{label}}}")
        out += [body, "\\end{table}"]
        return "\n".join(out)

    def _repr_html_(self) -> str:
        """An HTML table for notebooks and the documentation site (text escaped).

        Examples
        --------
        >>> "<td>pole</td><td>-2</td>" in pole_zero_table([1.0], [1.0, 2.0])._repr_html_()
        True
        """
        from html import escape

        head = ["kind", "root", "&omega;<sub>n</sub> (rad/s)", "f (Hz)", "&zeta;"]
        rows = ["<tr>" + "".join(f"<th>{h}</th>" for h in head) + "</tr>"]
        rows += ["<tr>" + "".join(f"<td>{escape(c)}</td>" for c in cells) + "</tr>"
                 for cells in self._cells()]
        return "<table>\n" + "\n".join(rows) + "\n</table>"

    def _repr_latex_(self) -> str:
        """MathJax-friendly ``array`` (Jupyter does not render ``tabular``)."""
        d = self.digits
        lines = ["\\begin{array}{llrrr}",
                 "& \\text{root} & \\omega_n\\ (\\mathrm{rad/s}) & f_n\\ (\\mathrm{Hz}) "
                 "& \\zeta \\\\ \\hline"]
        for r in self.rows:
            zeta = "\\text{--}" if math.isnan(r.zeta) else latex_number(r.zeta, d)
            lines.append(f"\\text{{{r.kind}}} & {r.root_latex(d)} & {latex_number(r.wn, d)} & "
                         f"{latex_number(r.hz, d)} & {zeta} \\\\")
        lines.append("\\end{array}")
        return "$" + "\n".join(lines) + "$"


def pole_zero_table(num: Sequence[float], den: Sequence[float], *, tol: float = 1e-9,
                    digits: int = 4) -> PoleZeroTable:
    """Pole/zero table of ``num(s)/den(s)`` (coefficients highest power first).

    Roots are ``numpy.roots`` of the coefficients; parts smaller than
    ``tol * |root|`` are set to zero (so an undamped pair shows ``0 ± w i``).

    Parameters
    ----------
    num, den : sequence of float
        Polynomial coefficients, highest power first.
    tol : float
        Relative threshold of :func:`snap_roots`.
    digits : int
        Significant digits shown (>= 1).

    Returns
    -------
    PoleZeroTable

    Raises
    ------
    InvalidOptionError
        For ``digits < 1`` or an all-zero denominator.

    Examples
    --------
    >>> t = pole_zero_table([1.0], [1.0, 0.0, 4.0])
    >>> t.poles[0].root_text(), t.poles[0].zeta
    ('0 ± 2i', 0.0)
    """
    if digits < 1:
        raise InvalidOptionError(f"digits: expected an integer >= 1, got {digits!r}")
    n_arr = np.trim_zeros(np.asarray(num, dtype=float), "f")
    d_arr = np.trim_zeros(np.asarray(den, dtype=float), "f")
    if d_arr.size == 0:
        raise InvalidOptionError("den: expected a nonzero polynomial, got all zeros")
    poles: Iterable[complex] = np.roots(d_arr) if d_arr.size > 1 else []
    zeros: Iterable[complex] = np.roots(n_arr) if n_arr.size > 1 else []
    rows = _rows("pole", poles, tol) + _rows("zero", zeros, tol)
    return PoleZeroTable(tuple(rows), digits)
