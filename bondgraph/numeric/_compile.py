"""One place that calls ``sympy.lambdify`` (private).

A user's Python function inside an expression (``sympy``'s
``implemented_function``) is called by the lambdified code with numbers;
:func:`guard_user_functions` wraps each so that an exception, or a result
that is not a real number, becomes :class:`CallbackFailure` naming it.

:class:`CompiledFunction` is the picklable form of a lambdified function: it
pickles as its expressions (themselves pickled once, and keyed by the SHA-256
of those bytes) and is lambdified again on first use after loading, through
a per-process cache, so that a worker receiving the same compiled model for
every chunk of a parameter study compiles it once.

Examples
--------
>>> import sympy
>>> x = sympy.Symbol("x")
>>> lambdify_cse([x], [x**2 + 1, 2*x])(3.0)
[10.0, 6.0]
"""

from __future__ import annotations

import hashlib
import inspect
import pickle
import threading
from collections import OrderedDict
from typing import Any, Callable, Optional, Sequence

import numpy as np
import sympy
from sympy.core.function import AppliedUndef
from sympy.utilities.lambdify import implemented_function

__all__ = ["lambdify_cse", "placeholders", "guard_user_functions", "CallbackFailure", "real_array",
           "CompiledFunction", "user_functions"]


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


def _check_evaluable(exprs: Sequence[sympy.Expr]) -> None:
    """Refuse what numpy code cannot evaluate (audit P09, S19) before it is generated.

    An undefined ``sympy.Function("g")(k)`` became a ``NameError`` from the
    generated code at the first call; a ``Derivative`` a ``ValueError`` from
    sympy's printer.
    """
    from .errors import NumericError

    clean: set = set()           # subexpressions already walked (and found evaluable)
    for ex in exprs:
        if not isinstance(ex, sympy.Basic):
            continue
        found = _calls(ex, clean)
        undefined = sorted({str(a) for a in found
                            if isinstance(a, AppliedUndef) and not hasattr(a.func, "_imp_")})
        if undefined:
            raise NumericError(
                f"{', '.join(undefined)} calls an undefined sympy Function, which has no numeric "
                "value: define it with sympy.implemented_function(name, python_function) or write "
                "the expression it stands for")
        derivatives = sorted({str(a) for a in found if isinstance(a, sympy.Derivative)})
        if derivatives:
            raise NumericError(
                f"{', '.join(derivatives)} is a symbolic derivative, which numeric code cannot "
                "evaluate: take it by hand (or use an output the model has, e.g. an effort or "
                "flow instead of the derivative of a displacement)")


def _calls(ex: sympy.Basic, clean: set) -> list[sympy.Basic]:
    """The function calls and derivatives in ``ex`` (``ex.atoms(AppliedUndef, Derivative)``),
    skipping the subexpressions in ``clean`` and adding those walked to it.

    One walk for both kinds, and each shared subexpression (``1/m`` in every
    row of a chain) once per model: a third of the time of two ``atoms``
    calls per expression on a 20,000-cell chain.

    Examples
    --------
    >>> x = sympy.Symbol("x")
    >>> g = sympy.Function("g")
    >>> clean: set = set()
    >>> _calls(g(x) / (x + 1) + sympy.Derivative(g(x), x), clean)
    [Derivative(g(x), x), g(x)]
    >>> _calls(1 / (x + 1), clean)         # x + 1 was walked: nothing new
    []
    """
    found = []
    stack = [ex]
    while stack:
        node = stack.pop()
        if node.is_Atom or node in clean:
            continue
        clean.add(node)
        if isinstance(node, (AppliedUndef, sympy.Derivative)):
            found.append(node)
        stack.extend(a for a in node.args if isinstance(a, sympy.Basic))
    return found


def lambdify_cse(args: Sequence, exprs: Sequence[sympy.Expr]) -> Callable:
    """``sympy.lambdify(args, list(exprs), "numpy", cse=True)``, without the long docstring."""
    _check_evaluable(exprs)
    extra = {"docstring_limit": 0} if _HAS_DOCLIMIT else {}
    return sympy.lambdify(list(args), list(exprs), modules="numpy", cse=True, **extra)


#: lambdified functions by the SHA-256 of their pickled (args, exprs); least recently used last out
_CACHE: "OrderedDict[str, Callable]" = OrderedDict()
_CACHE_SIZE = 64
_CACHE_LOCK = threading.Lock()


def _cached(key: str) -> Optional[Callable]:
    with _CACHE_LOCK:
        fn = _CACHE.get(key)
        if fn is not None:
            _CACHE.move_to_end(key)
        return fn


def _remember(key: str, fn: Callable) -> None:
    with _CACHE_LOCK:
        _CACHE[key] = fn
        _CACHE.move_to_end(key)
        while len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)


def user_functions(exprs: Sequence[sympy.Expr]) -> list[Any]:
    """The user functions (``implemented_function``, with ``_imp_``) called in ``exprs``, by name.

    Examples
    --------
    >>> x = sympy.Symbol("x")
    >>> user_functions([implemented_function("sat", abs)(x) + 1, x])
    [sat]
    """
    funcs = {a.func for ex in exprs if isinstance(ex, sympy.Basic)
             for a in ex.atoms(AppliedUndef) if hasattr(a.func, "_imp_")}
    return sorted(funcs, key=str)


class CompiledFunction:
    """``lambdify_cse(args, exprs)`` that pickles as its expressions and recompiles lazily.

    Calling it calls the lambdified function.  Pickling stores the pickled
    ``(args, exprs)`` and their SHA-256; unpickling compiles nothing: the
    first call looks the key up in a per-process cache (64 functions, least
    recently used dropped) and lambdifies only on a miss, so a round trip
    gives the same generated code, hence the same numbers bit for bit.

    Parameters
    ----------
    args : sequence
        Lambdify arguments (symbols, or lists of symbols).
    exprs : sequence of sympy.Expr

    Raises
    ------
    NotPicklableError
        When pickled, if the expressions call a user function
        (``implemented_function``): the Python function cannot travel with
        them.

    Examples
    --------
    >>> import pickle
    >>> x = sympy.Symbol("x")
    >>> f = CompiledFunction([x], [x**2 + 1, 2*x])
    >>> g = pickle.loads(pickle.dumps(f))
    >>> g(3.0), g.key == f.key
    ([10.0, 6.0], True)
    """

    __slots__ = ("_args", "_exprs", "_fn", "_key", "_blob")

    def __init__(self, args: Sequence, exprs: Sequence[sympy.Expr]) -> None:
        self._args: Optional[list] = list(args)
        self._exprs: Optional[list] = list(exprs)
        self._fn: Optional[Callable] = lambdify_cse(self._args, self._exprs)
        self._key: Optional[str] = None
        self._blob: Optional[bytes] = None

    def __call__(self, *args: Any) -> Any:
        fn = self._fn
        if fn is None:
            fn = self._load()
        return fn(*args)

    @property
    def key(self) -> str:
        """SHA-256 (hex) of the pickled ``(args, exprs)``: equal keys, equal functions."""
        self._pickled()
        assert self._key is not None
        return self._key

    def _pickled(self) -> bytes:
        if self._blob is None:
            assert self._exprs is not None
            funcs = user_functions(self._exprs)
            if funcs:
                from .errors import NotPicklableError

                raise NotPicklableError(
                    f"the equations call the Python function(s) {', '.join(map(str, funcs))} "
                    "(sympy implemented_function), which cannot be pickled; compile the "
                    "model in each process instead")
            blob = pickle.dumps((self._args, self._exprs), protocol=pickle.HIGHEST_PROTOCOL)
            self._blob, self._key = blob, hashlib.sha256(blob).hexdigest()
            if self._fn is not None:           # a round trip in this process compiles nothing
                _remember(self._key, self._fn)
        return self._blob

    def _load(self) -> Callable:
        assert self._key is not None and self._blob is not None
        fn = _cached(self._key)
        if fn is None:
            args, exprs = pickle.loads(self._blob)
            fn = lambdify_cse(args, exprs)
            _remember(self._key, fn)
        self._fn = fn
        return fn

    def __getstate__(self) -> dict:
        blob = self._pickled()
        return {"key": self._key, "blob": blob}

    def __setstate__(self, state: dict) -> None:
        self._args = self._exprs = None
        self._key, self._blob = state["key"], state["blob"]
        self._fn = None                       # compiled (or found in the cache) on first call

    def __repr__(self) -> str:
        state = "compiled" if self._fn is not None else "not yet compiled"
        return f"<CompiledFunction {state}>"


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
