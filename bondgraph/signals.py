"""Placeholders for bond-graph variables used in outputs and laws.

Two families of sympy symbols stand for things that only get a value once the
graph has been derived:

* :class:`Signal` -- the effort, flow, displacement (time integral of flow) or
  momentum (time integral of effort) of a named element or of a numbered bond.
  Signals are built with :func:`effort`, :func:`flow`, :func:`displacement`
  and :func:`momentum`, and combine with ordinary sympy arithmetic, so a
  beam's tip deflection is written ``L*displacement("hub") + phi1*displacement("m1")``.
  They are used for model outputs and inside the modulus of MTF / MGY
  elements (and of modulated one-port laws).
* :class:`LawVariable` -- the element's *own* variable in a constitutive law:
  :data:`p` (momentum of an I), :data:`q` (displacement of a C), :data:`e`
  and :data:`f` (effort and flow of an R).  ``C("spring", effort=k*q + k3*q**3)``.

The time symbol :data:`t` may appear in modulated laws.

Examples
--------
>>> import bondgraph as bg
>>> y = 2*bg.displacement("J") + bg.flow(3)
>>> sorted(str(s) for s in y.free_symbols)
['displacement[J]', 'flow[3]']
"""

from __future__ import annotations

from typing import Union

import sympy

from .errors import OutputError

__all__ = [
    "Signal",
    "LawVariable",
    "effort",
    "flow",
    "displacement",
    "momentum",
    "p",
    "q",
    "e",
    "f",
    "t",
    "SIGNAL_KINDS",
]

SIGNAL_KINDS = ("effort", "flow", "displacement", "momentum")

Target = Union[str, int]


class Signal(sympy.Symbol):
    """A bond-graph variable named by kind and target, resolved at derivation.

    Parameters
    ----------
    kind : {'effort', 'flow', 'displacement', 'momentum'}
    target : str or int
        Element name (hierarchical, ``"motor.J"``) or bond number.
    port : int, optional
        The port (1-based, in the order of its bonds) of a multiport field
        (:mod:`bondgraph.elements.fields`); None for every other element.

    Examples
    --------
    >>> s = Signal("flow", "motor.J")
    >>> s, s.variable, s.target, s.port
    (flow[motor.J], 'flow', 'motor.J', None)
    >>> Signal("effort[3]").target
    3
    >>> Signal("flow", "M", port=2), Signal("flow[M][2]").port
    (flow[M][2], 2)
    """

    def __new__(cls, kind: str, target: Target | None = None, port: int | None = None,
                **assumptions):
        if target is None:  # reconstruction from the name alone
            kind, _, rest = kind.partition("[")
            rest = rest[:-1]
            if "][" in rest:
                rest, _, num = rest.partition("][")
                port = int(num)
            target = int(rest) if rest.isdigit() else rest
        if kind not in SIGNAL_KINDS:
            raise OutputError(
                f"unknown signal kind {kind!r}; expected one of {', '.join(SIGNAL_KINDS)}"
            )
        if isinstance(target, bool) or not isinstance(target, (str, int)):
            raise OutputError(
                f"{kind}() takes an element name or a bond number; got {target!r}"
            )
        if isinstance(target, str) and not target:
            raise OutputError(f"{kind}() needs a non-empty element name")
        if port is not None and (isinstance(port, bool) or not isinstance(port, int) or
                                 port < 1 or not isinstance(target, str)):
            raise OutputError(f"{kind}({target!r}, port={port!r}): port must be an integer >= 1 "
                              "(the port of a multiport field, in the order of its bonds)")
        tail = "" if port is None else f"[{port}]"
        obj = super().__new__(cls, f"{kind}[{target}]{tail}", real=True)
        obj.variable = kind
        obj.target = target
        obj.port = port
        return obj

    def __getnewargs_ex__(self):
        return ((self.variable, self.target, self.port), {})

    def retarget(self, target: Target) -> "Signal":
        """The same kind of signal (and port) on another target."""
        return Signal(self.variable, target, self.port)

    def of(self, variable: str) -> "Signal":
        """The signal of another kind on the same target and port."""
        return Signal(variable, self.target, self.port)


class LawVariable(sympy.Symbol):
    """The own variable of an element in a constitutive law (p, q, e or f).

    Parameters
    ----------
    name : str
        The symbol's name; the module provides :data:`p`, :data:`q`,
        :data:`e` and :data:`f`.

    Examples
    --------
    >>> import bondgraph as bg
    >>> bg.q, bg.q.is_real
    (q, True)
    >>> bg.C("spring", law=2*bg.q + bg.q**3).forward()
    q**3 + 2*q
    """

    def __new__(cls, name: str):
        return super().__new__(cls, name, real=True)

    def __getnewargs_ex__(self):
        return ((self.name,), {})


def effort(target: Target, port: int | None = None) -> Signal:
    """Effort of an element (its bond) or of bond number ``target``.

    Parameters
    ----------
    target : str or int
        Element name (hierarchical, ``"motor.J"``) or bond number.
    port : int, optional
        The port of a multiport field (1-based, in the order of its bonds):
        ``bg.effort("M", port=2)``; a field refuses the signal without it.

    Examples
    --------
    >>> effort("Ra")
    effort[Ra]
    """
    return Signal("effort", target, port)


def flow(target: Target, port: int | None = None) -> Signal:
    """Flow of an element, of a 1-junction (its common flow), or of a bond.

    Parameters
    ----------
    target : str or int
        Element name (hierarchical, ``"motor.J"``) or bond number.
    port : int, optional
        The port of a multiport field (1-based, in the order of its bonds):
        ``bg.flow("M", port=2)``; a field refuses the signal without it.

    Examples
    --------
    >>> flow(4)
    flow[4]
    """
    return Signal("flow", target, port)


def displacement(target: Target, port: int | None = None) -> Signal:
    """Time integral of the flow: q of a C, or an angle/position of an I.

    Adds an integrator state when the displacement is not already a state.

    Parameters
    ----------
    target : str or int
        Element name (hierarchical, ``"motor.J"``) or bond number.
    port : int, optional
        The port of a multiport field (1-based, in the order of its bonds):
        ``bg.displacement("M", port=2)``; a field refuses the signal without it.

    Examples
    --------
    >>> displacement("J").variable
    'displacement'
    """
    return Signal("displacement", target, port)


def momentum(target: Target, port: int | None = None) -> Signal:
    """Time integral of the effort: p of an I, or an added integrator.

    Parameters
    ----------
    target : str or int
        Element name (hierarchical, ``"motor.J"``) or bond number.
    port : int, optional
        The port of a multiport field (1-based, in the order of its bonds):
        ``bg.momentum("M", port=2)``; a field refuses the signal without it.

    Examples
    --------
    >>> momentum("La").target
    'La'
    """
    return Signal("momentum", target, port)


#: Momentum of the element whose law is being written (``bg.I("m", law=...)``).
p = LawVariable("p")
#: Displacement of the element whose law is being written (``bg.C("s", law=k*bg.q)``).
q = LawVariable("q")
#: Effort of the element whose law is being written.
e = LawVariable("e")
#: Flow of the element whose law is being written (``bg.R("d", law=c*bg.f*abs(bg.f))``).
f = LawVariable("f")
#: Time, for modulated laws and sources (``bg.Se("u", value=sympy.sin(bg.t))``).
t = sympy.Symbol("t", real=True)
