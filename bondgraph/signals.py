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

    Examples
    --------
    >>> s = Signal("flow", "motor.J")
    >>> s, s.variable, s.target
    (flow[motor.J], 'flow', 'motor.J')
    >>> Signal("effort[3]").target
    3
    """

    def __new__(cls, kind: str, target: Target | None = None, **assumptions):
        if target is None:  # reconstruction from the name alone
            kind, _, rest = kind.partition("[")
            rest = rest[:-1]
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
        obj = super().__new__(cls, f"{kind}[{target}]", real=True)
        obj.variable = kind
        obj.target = target
        return obj

    def __getnewargs_ex__(self):
        return ((self.variable, self.target), {})

    def retarget(self, target: Target) -> "Signal":
        """The same kind of signal on another target."""
        return Signal(self.variable, target)


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


def effort(target: Target) -> Signal:
    """Effort of an element (its bond) or of bond number ``target``.

    Parameters
    ----------
    target : str or int
        Element name (hierarchical, ``"motor.J"``) or bond number.

    Examples
    --------
    >>> effort("Ra")
    effort[Ra]
    """
    return Signal("effort", target)


def flow(target: Target) -> Signal:
    """Flow of an element, of a 1-junction (its common flow), or of a bond.

    Parameters
    ----------
    target : str or int
        Element name (hierarchical, ``"motor.J"``) or bond number.

    Examples
    --------
    >>> flow(4)
    flow[4]
    """
    return Signal("flow", target)


def displacement(target: Target) -> Signal:
    """Time integral of the flow: q of a C, or an angle/position of an I.

    Adds an integrator state when the displacement is not already a state.

    Parameters
    ----------
    target : str or int
        Element name (hierarchical, ``"motor.J"``) or bond number.

    Examples
    --------
    >>> displacement("J").variable
    'displacement'
    """
    return Signal("displacement", target)


def momentum(target: Target) -> Signal:
    """Time integral of the effort: p of an I, or an added integrator.

    Parameters
    ----------
    target : str or int
        Element name (hierarchical, ``"motor.J"``) or bond number.

    Examples
    --------
    >>> momentum("La").target
    'La'
    """
    return Signal("momentum", target)


p = LawVariable("p")
q = LawVariable("q")
e = LawVariable("e")
f = LawVariable("f")
t = sympy.Symbol("t", real=True)
