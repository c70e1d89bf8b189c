"""Junctions (0, 1) and sub-model ports.

Re-exported by :mod:`bondgraph.elements`; the conventions are in its docstring.
A junction has exactly one strong bond (the one bringing the effort into a
0-junction, the one setting the flow of a 1-junction); a :class:`Port` is a
sub-model's connection point, removed when the graph is flattened.

Examples
--------
>>> import bondgraph as bg
>>> bg.One("w").bonds, bg.Zero("n").bonds
((2, None), (2, None))
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, Optional, Sequence

import sympy

from ..errors import CausalityConflictError
from .protocol import (CausalPorts, Decision, Element, LocalVariables)

if TYPE_CHECKING:  # pragma: no cover
    pass

__all__ = ["Zero", "One", "Port"]


@dataclass(frozen=True, eq=False)
class _Junction(Element):
    """A junction: exactly one *strong* bond, the one that sets the common variable.

    On a 0-junction the strong bond brings the common effort in; on a
    1-junction it sets the common flow (it takes effort out).
    """

    bonds: ClassVar[tuple[int, Optional[int]]] = (2, None)
    drawing_role: ClassVar[str] = "junction"
    #: whether the element receives effort on its strong bond (a 0-junction)
    strong_in: ClassVar[bool] = True
    #: the variable shared by every bond: 'effort' or 'flow'
    common: ClassVar[str] = "effort"

    def propagate(self, ports: CausalPorts) -> Sequence[Decision]:
        strong_in = self.strong_in
        n = ports.count
        strong = ports.efforts_in if strong_in else n - ports.undecided - ports.efforts_in
        if strong > 1:
            ps = [p for p in range(n) if ports.effort_in(p) is strong_in]
            raise CausalityConflictError(
                f"causality conflict at {self.label()}: bonds "
                f"{', '.join(str(ports.number(p)) for p in ps)} all "
                f"{'impose its effort' if strong_in else 'set its flow'} "
                f"(from {', '.join(str(ports.reason(p)) for p in ps)}); a "
                f"{self.kind}-junction takes exactly one. Remove one of the sources "
                "or add a storage or R element between them."
            )
        if ports.undecided == 0:
            if strong == 0:
                raise CausalityConflictError(
                    f"causality conflict at {self.label()}: no bond "
                    f"{'imposes its effort' if strong_in else 'sets its flow'}"
                )
            return ()
        if strong == 1:     # every other bond is weak
            return [Decision(p, not strong_in, self.label()) for p in ports.open()]
        if ports.undecided == 1:   # the last bond must be the strong one
            return [Decision(p, strong_in, self.label()) for p in ports.open()]
        return ()

    def _strong(self, effort_in) -> int:
        return next(p for p, e in enumerate(effort_in) if e is self.strong_in)

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        strong = self._strong(effort_in)
        n = len(effort_in)
        reads: list[Sequence[int]] = [(strong,)] * n     # the common variable
        reads[strong] = tuple([q for q in range(n) if q != strong])
        return reads

    def signal_port(self, variable: str) -> Optional[tuple[int, bool]]:
        return (0, False) if variable == self.common else None

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        n = local.count
        strong = self._strong(local.effort_in(p) for p in range(n))
        if port != strong:       # the common variable
            return local.input(strong)
        # the signs folded into the terms: one Add, no distributed -1 * Add(...)
        flip = -local.sign(strong)
        return sympy.Add(*[local.input(p) if flip * local.sign(p) > 0 else -local.input(p)
                           for p in range(n) if p != strong])

    def drawing_label(self) -> tuple[str, str]:
        return self.kind, self.name


@dataclass(frozen=True, eq=False)
class Zero(_Junction):
    """0-junction: common effort, signed flows sum to zero.

    Examples
    --------
    >>> Zero("node").bonds
    (2, None)
    """

    kind: ClassVar[str] = "0"


@dataclass(frozen=True, eq=False)
class One(_Junction):
    """1-junction: common flow, signed efforts sum to zero.

    Examples
    --------
    >>> One("w").label()
    '1:w'
    """

    kind: ClassVar[str] = "1"
    strong_in: ClassVar[bool] = False
    common: ClassVar[str] = "flow"


@dataclass(frozen=True, eq=False)
class Port(Element):
    """External port of a graph used as a sub-model (exactly one inner bond).

    Examples
    --------
    >>> Port("shaft").label()
    'Port:shaft'
    """

    kind: ClassVar[str] = "Port"
    drawing_role: ClassVar[str] = "source"
