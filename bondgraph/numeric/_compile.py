"""One place that calls ``sympy.lambdify`` (private).

A user's Python function inside an expression (``sympy``'s
``implemented_function``) is called by the lambdified code with numbers;
:func:`guard_user_functions` wraps each so that an exception, or a result
that is not a real number, becomes :class:`CallbackFailure` naming it.

Examples
--------
>>> import sympy
>>> x = sympy.Symbol("x")
>>> lambdify_cse([x], [x**2 + 1, 2*x])(3.0)
[10.0, 6.0]
"""

from __future__ import annotations

import inspect
from typing import Any, Callable, Sequence

import numpy as np
import sympy
from sympy.core.function import AppliedUndef
from sympy.utilities.lambdify import implemented_function

__all__ = ["lambdify_cse", "placeholders", "guard_user_functions", "CallbackFailure", "real_array"]


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


class CallbackFailure(Exception):
    """A user function inside an expression raised, or returned a non-number, while running.

    Raised from inside lambdified code, which knows neither the model nor the
    time: the caller turns it into a package error.  The original exception,
    if any, is ``__cause__``.

    Attributes
    ----------
    what : str
        Who failed and how (``"R:Rf: the function sat raised ValueError: ..."``).
    args_given : tuple
        The arguments of the failing call.
    """

    def __init__(self, what: str, args: tuple) -> None:
        super().__init__(what)
        self.what = what
        self.args_given = args


def real_array(value: Any) -> np.ndarray:
    """``value`` as a float array; TypeError or ValueError for anything but real numbers.

    Booleans, complex numbers, None, text and ragged sequences are refused
    (numpy would turn ``True`` into 1.0, None into nan, or drop an imaginary
    part silently).

    Examples
    --------
    >>> real_array([1, 2.5])
    array([1. , 2.5])
    >>> real_array(None)
    Traceback (most recent call last):
    ...
    TypeError: not a real number: NoneType
    """
    raw = np.asarray(value)
    if raw.dtype.kind in "fiu":
        return raw.astype(float)
    if raw.dtype.kind != "O" or any(v is None or isinstance(v, (bool, complex, str, bytes))
                                    for v in raw.ravel()):
        raise TypeError(f"not a real number: {type(value).__name__}")
    return np.array([float(v) for v in raw.ravel()], dtype=float).reshape(raw.shape)


def guard_user_functions(exprs: Sequence[sympy.Expr],
                         describe: Callable[[Any], str]) -> list[sympy.Expr]:
    """``exprs`` with each user function replaced by a stand-in that reports failures.

    Parameters
    ----------
    exprs : sequence of sympy.Expr
    describe : callable
        ``describe(func)`` names the user function ``func`` for messages
        (``"R:Rf: the function sat"``).

    Returns
    -------
    list of sympy.Expr
        Each user function (one with ``_imp_``) ``func`` replaced by a new
        implemented function that calls ``func._imp_`` and raises
        :class:`CallbackFailure` (chained to the original exception) when it
        raises or returns something other than real numbers.

    Examples
    --------
    >>> from sympy.utilities.lambdify import implemented_function
    >>> x = sympy.Symbol("x")
    >>> inv = implemented_function("inv", lambda v: 1 / v)
    >>> (g,) = guard_user_functions([inv(x) + 1], lambda func: f"the function {func}")
    >>> fn = lambdify_cse([x], [g])
    >>> fn(0.5)
    [3.0]
    >>> fn(0)
    Traceback (most recent call last):
    ...
    bondgraph.numeric._compile.CallbackFailure: the function inv raised ZeroDivisionError: division by zero
    """
    out = list(exprs)
    funcs = {a.func for ex in out for a in ex.atoms(AppliedUndef) if hasattr(a.func, "_imp_")}
    for i, func in enumerate(sorted(funcs, key=str)):
        stand_in = implemented_function(sympy.Function(f"__bg_fn{i}"),
                                        _guarded(func._imp_, describe(func)))
        out = [ex.replace(func, stand_in) for ex in out]
    return out


def _guarded(impl: Callable, what: str) -> Callable:
    def call(*args):
        try:
            result = impl(*args)
        except Exception as exc:
            raise CallbackFailure(f"{what} raised {type(exc).__name__}: {exc}", args) from exc
        try:
            arr = real_array(result)
        except (TypeError, ValueError, OverflowError):
            text = repr(result)
            raise CallbackFailure(f"{what} returned {type(result).__name__} {text[:40]}, "
                                  "not a real number", args) from None
        return arr if arr.ndim else float(arr)
    return call
