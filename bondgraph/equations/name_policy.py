"""Name clashes decided on printed names, whatever a Symbol's assumptions (issue 23, item 4).

sympy tells ``Symbol("p_m", real=True)`` and ``Symbol("p_m", positive=True)``
apart, and the equation builder's states and inputs are
``Symbol(name, real=True)``: a parameter written as ``Symbol("p_m",
real=True)`` *is* the state ``p_m``, and one written ``Symbol("F",
real=True)`` *is* the input ``F``, so the later check on the derived
equations (which skips the model's own states and inputs) cannot see them.
:func:`check_element_symbols` looks at every symbol the elements hold, before
any equation is built, and refuses one that prints like a state, an input,
an integrator or time unless it is that very thing by design: the law
variables (``bg.p``, ``bg.q``, ``bg.e``, ``bg.f``) and time itself
(``bg.t``, which is ``Symbol("t", real=True)``: written that way it is time,
as documented; any other ``t`` is refused).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Iterable, Iterator, Mapping

import sympy

from ..errors import NameClashError
from ..signals import LawVariable, Signal, t as T_SYM

__all__ = ["check_element_symbols", "twin_symbols"]


def _symbols(value: Any) -> Iterator[sympy.Symbol]:
    if isinstance(value, (sympy.Basic, sympy.MatrixBase)):
        yield from (s for s in value.free_symbols if isinstance(s, sympy.Symbol))
    elif isinstance(value, (tuple, list, frozenset, set)):
        for item in value:
            yield from _symbols(item)
    elif isinstance(value, Mapping):
        for item in value.values():
            yield from _symbols(item)


def check_element_symbols(elements: Iterable[Any], roles: Mapping[str, str], model: str) -> None:
    """Refuse an element's symbol whose printed name is taken by a state, an input or time.

    Parameters
    ----------
    elements : iterable of Element
        The flattened model's elements (frozen dataclasses).
    roles : mapping
        Printed name -> what it stands for (``"the state of I:m"``, ``"time"``).
    model : str
        The model's name, for the message.

    Examples
    --------
    >>> import sympy, bondgraph as bg
    >>> g = bg.BondGraph("g")
    >>> g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b", sympy.Symbol("p_m", real=True)))
    >>> for tail, head in [("F", "v"), ("v", "m"), ("v", "b")]:
    ...     _ = g.connect(tail, head)
    >>> bg.derive(g)
    Traceback (most recent call last):
    ...
    bondgraph.errors.NameClashError: model 'g': R:b holds the symbol 'p_m', which prints like the state of I:m; rename the parameter
    """
    for el in elements:
        if not dataclasses.is_dataclass(el):
            continue
        seen: set[sympy.Symbol] = set()
        for field in dataclasses.fields(el):
            for sym in _symbols(getattr(el, field.name, None)):
                if sym in seen or isinstance(sym, (LawVariable, Signal, sympy.Dummy)) or sym == T_SYM:
                    continue
                seen.add(sym)
                role = roles.get(sym.name)
                if role is not None:
                    label = el.label() if hasattr(el, "label") else repr(el)
                    raise NameClashError(
                        f"model {model!r}: {label} holds the symbol {sym.name!r}, which prints "
                        f"like {role}; rename the parameter")


def twin_symbols(model: str, first: sympy.Symbol, second: sympy.Symbol) -> NameClashError:
    """The error for two different parameter Symbols that print alike (``k`` positive and
    ``k`` real): one value given by name could not tell them apart.

    Examples
    --------
    >>> import sympy
    >>> print(twin_symbols("m", sympy.Symbol("k", positive=True), sympy.Symbol("k")))
    model 'm': two different parameter Symbols print as 'k' (assumptions {positive: True} and {}); one value could not tell them apart: use one Symbol, or rename one
    """
    def assumed(sym: sympy.Symbol) -> str:
        given = dict(getattr(sym, "_assumptions_orig", None) or {})
        return "{" + ", ".join(f"{k}: {v}" for k, v in sorted(given.items())) + "}"
    one, two = sorted((assumed(first), assumed(second)))     # the same text in every process
    return NameClashError(
        f"model {model!r}: two different parameter Symbols print as {first.name!r} "
        f"(assumptions {one} and {two}); one value could not tell them apart: use one "
        "Symbol, or rename one")

