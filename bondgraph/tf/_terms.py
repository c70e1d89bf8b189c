"""Signed sums ``c1 m1 + c2 m2 + ...`` as text, shared by the printers (private).

Examples
--------
>>> symbolic_sum(poly_terms([1, -2, 3], "s", power="{}**{}"), text=str, group="({})*{}",
...              product="{}*{}")
's**2 - 2*s + 3'
>>> numeric_sum(poly_terms([1.0, 0.0, -0.5], "s", power="{}^{}"), lambda x: f"{x:.4g}")
's^2 - 0.5'
"""

from __future__ import annotations

from typing import Callable, Iterable, Sequence, SupportsFloat, cast

import sympy as sp

from .._support.labels import tex

__all__ = ["monomial", "poly_terms", "numeric_sum", "symbolic_sum"]

LATEX_POWER = "{}^{{{}}}"


def monomial(s: str, k: int, power: str = LATEX_POWER) -> str:
    """``s**k`` as text: ``""`` for ``k = 0``, ``s`` for ``k = 1``, else ``power.format(s, k)``."""
    if k == 0:
        return ""
    if k == 1:
        return s
    return power.format(s, k)


def poly_terms(coeffs: Sequence[object], s: str,
               power: str = LATEX_POWER) -> list[tuple[object, str]]:
    """``(coefficient, monomial)`` pairs of a polynomial, highest power first."""
    n = len(coeffs) - 1
    return [(c, monomial(s, n - k, power)) for k, c in enumerate(coeffs)]


def _join(parts: Sequence[tuple[bool, str]]) -> str:
    """``a - b + c`` from ``(negative, magnitude text)`` pairs; ``"0"`` when there are none."""
    if not parts:
        return "0"
    out = ("-" if parts[0][0] else "") + parts[0][1]
    for neg, body in parts[1:]:
        out += f" {'-' if neg else '+'} {body}"
    return out


def numeric_sum(terms: Iterable[tuple[object, str]], number: Callable[[float], str]) -> str:
    """Sum with float coefficients printed by ``number`` (zeros skipped, a unit factor dropped)."""
    parts = []
    for c, mono in terms:
        x = float(cast(SupportsFloat, c))
        if x == 0:
            continue
        txt = number(abs(x))
        parts.append((x < 0, mono if (mono and txt == "1") else f"{txt} {mono}".rstrip()))
    return _join(parts)


def symbolic_sum(terms: Iterable[tuple[object, str]], *, text: Callable[[sp.Expr], str] = tex,
                 group: str = "\\left({}\\right) {}", product: str = "{} {}") -> str:
    """Sum with sympy coefficients: signs folded out, a unit factor dropped, and a
    coefficient that is itself a sum written ``group.format(text(c), monomial)``."""
    parts = []
    for c, mono in terms:
        c = sp.sympify(c, strict=True)
        if c == 0:
            continue
        neg = bool(c.could_extract_minus_sign())
        mag = -c if neg else c
        if mono and mag == 1:
            body = mono
        elif mono and mag.is_Add:
            body = group.format(text(mag), mono)
        elif mono:
            body = product.format(text(mag), mono)
        else:
            body = text(mag)
        parts.append((neg, body))
    return _join(parts)
