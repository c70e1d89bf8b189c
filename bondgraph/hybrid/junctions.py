"""Switched junctions (Mosterman and Biswas' controlled junctions).

A switched junction is an ordinary 0- or 1-junction while **on**.  Turned
**off**, a 0-junction imposes zero effort on every one of its bonds and a
1-junction zero flow: the junction and what hangs on it are cut out of the
structure.  Like the switches, it answers SCAP and the derivation from its
state, and the hybrid machinery asks it :meth:`in_state` and :meth:`guard`.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.hybrid import SwitchedModel, SwitchedOne
>>> g = bg.BondGraph("branch")
>>> g.add(bg.Se("E"), bg.Zero("n"), bg.R("Ra"), SwitchedOne("b", gate=1 - bg.t), bg.R("Rb"))
>>> for a, b in [("E", "n"), ("n", "Ra"), ("n", "b"), ("b", "Rb")]: _ = g.connect(a, b)
>>> sm = SwitchedModel(g, outputs={"i": -bg.flow("E")})
>>> sm.mode(on={"b"}).output_exprs, sm.mode(off={"b"}).output_exprs
((E/Rb + E/Ra,), (E/Ra,))
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar, Optional, Sequence, cast

import sympy

from ..elements import One, Zero
from ..errors import ParameterError
from ..elements.protocol import CausalPorts, Decision, Element, LocalVariables, prefix_signals, rename
from .elements import SwitchElement

__all__ = ["SwitchedZero", "SwitchedOne"]


class _Switched:
    """What the two switched junctions add to a junction (mixed in before it)."""

    if TYPE_CHECKING:   # supplied by the junction and switch classes it is mixed with
        on: bool
        gate: Optional[sympy.Expr]
        name: str
        strong_in: ClassVar[bool]
        kind: ClassVar[str]

        def label(self) -> str: ...

    def __post_init__(self) -> None:
        cast(Any, super()).__post_init__()
        gate = self.gate
        if isinstance(gate, (int, float)) and not isinstance(gate, bool):
            gate = sympy.Float(gate) if isinstance(gate, float) else sympy.Integer(gate)
        if gate is not None and not isinstance(gate, sympy.Expr):
            raise ParameterError(f"{self.label()}: gate must be a sympy expression of time "
                                 f"bondgraph.t, parameters and signals; got {type(gate).__name__} {gate!r}")
        object.__setattr__(self, "gate", gate)

    def resolved(self, path: str) -> Element:
        el = rename(cast(Element, self), path)
        object.__setattr__(el, "gate", prefix_signals(self.gate, path[: len(path) - len(self.name)]))
        return el

    def guard(self, on: bool) -> Optional[sympy.Expr]:
        if self.gate is None:
            return None
        return self.gate if on else -self.gate

    def state_text(self, on: bool) -> str:
        zero = "effort" if self.strong_in else "flow"
        return "on (a junction)" if on else f"off (zero {zero} on every bond)"

    def forced_causality(self, ports: CausalPorts) -> Sequence[Decision]:
        if self.on:
            return ()
        why = f"switched junction {self.label()} {self.state_text(False)}"
        return tuple(Decision(p, not self.strong_in, why) for p in range(ports.count))

    def propagate(self, ports: CausalPorts) -> Sequence[Decision]:
        return cast(Any, super()).propagate(ports) if self.on else ()

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        if self.on:
            return cast(Any, super()).output_dependencies(effort_in, causality)
        return ((),) * len(effort_in)

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        return cast(Any, super()).output(local, port) if self.on else sympy.Integer(0)

    def drawing_label(self) -> tuple[str, str]:
        return self.kind, f"{self.name} {'on' if self.on else 'off'}"


@dataclass(frozen=True, eq=False)
class SwitchedZero(_Switched, Zero, SwitchElement):
    """A 0-junction that can be turned off (zero effort on all its bonds).

    Parameters
    ----------
    name : str
    on : bool, keyword-only
        Initial state (default on).
    gate : sympy expression, optional, keyword-only
        On while ``gate > 0`` (a controlled junction); None: set by the user.

    Examples
    --------
    >>> SwitchedZero("n").label(), SwitchedZero("n", on=False).drawing_label()
    ('S0:n', ('S0', 'n off'))
    """

    on: bool = field(default=True, kw_only=True)
    gate: Optional[sympy.Expr] = field(default=None, kw_only=True)
    kind: ClassVar[str] = "S0"


@dataclass(frozen=True, eq=False)
class SwitchedOne(_Switched, One, SwitchElement):
    """A 1-junction that can be turned off (zero flow on all its bonds).

    Examples
    --------
    >>> SwitchedOne("b", on=False).guard(False) is None
    True
    """

    on: bool = field(default=True, kw_only=True)
    gate: Optional[sympy.Expr] = field(default=None, kw_only=True)
    kind: ClassVar[str] = "S1"
