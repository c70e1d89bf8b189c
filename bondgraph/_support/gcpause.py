"""The cyclic garbage collector paused while a large model or answer is built.

Derivation, ``state_space()`` and the symbolic transfer functions allocate
millions of small objects (sympy expressions, tuples, dicts) that form no
reference cycles; on a 10,000-cell chain the collector's full passes over
the growing heap cost about a fifth of causality + derivation +
``state_space()``, and a third of a 20-state chain's symbolic transfer
function.  The collector's previous state is restored on exit (nesting is
fine), and garbage made meanwhile is collected by the next pass as usual.

Examples
--------
>>> import gc
>>> with paused_gc():
...     gc.isenabled()
False
>>> gc.isenabled()
True
>>> @with_paused_gc
... def f():
...     return gc.isenabled()
>>> f(), gc.isenabled()
(False, True)
"""

from __future__ import annotations

import contextlib
import functools
import gc
from typing import Callable, Iterator, TypeVar

__all__ = ["paused_gc", "with_paused_gc"]

F = TypeVar("F", bound=Callable)


@contextlib.contextmanager
def paused_gc() -> Iterator[None]:
    """Context manager: the garbage collector off inside, as before outside."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def with_paused_gc(func: F) -> F:
    """Decorator: run ``func`` inside :func:`paused_gc`."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        with paused_gc():
            return func(*args, **kwargs)

    return wrapper  # type: ignore[return-value]
