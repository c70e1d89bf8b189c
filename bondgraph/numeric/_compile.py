"""One place that calls ``sympy.lambdify`` (private).

Examples
--------
>>> import sympy
>>> x = sympy.Symbol("x")
>>> lambdify_cse([x], [x**2 + 1, 2*x])(3.0)
[10.0, 6.0]
"""

from __future__ import annotations

import inspect
from typing import Callable, Sequence

import sympy

__all__ = ["lambdify_cse", "placeholders"]


def placeholders(prefix: str, n: int) -> list[sympy.Symbol]:
    """``n`` plain symbols with identifier names for lambdify arguments.

    Plain symbols, not ``Dummy``: a single Dummy argument makes lambdify
    re-substitute every argument into every expression, which is quadratic in
    the model size (a 1000-state plant took minutes).

    Examples
    --------
    >>> placeholders("p", 2)
    [__bg_p0, __bg_p1]
    """
    return [sympy.Symbol(f"__bg_{prefix}{i}") for i in range(n)]

_HAS_DOCLIMIT = "docstring_limit" in inspect.signature(sympy.lambdify).parameters


def lambdify_cse(args: Sequence, exprs: Sequence[sympy.Expr]) -> Callable:
    """``sympy.lambdify(args, list(exprs), "numpy", cse=True)``, without the long docstring."""
    extra = {"docstring_limit": 0} if _HAS_DOCLIMIT else {}
    return sympy.lambdify(list(args), list(exprs), modules="numpy", cse=True, **extra)
