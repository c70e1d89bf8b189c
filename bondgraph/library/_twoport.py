"""Resistive two-ports that take the effort on both ports: reactions, radiation, RS.

:class:`ConductanceTwoPort` is the element-protocol part shared by the
chemical reaction ``Re``, thermal radiation and true-thermal conduction:
port 1 is the bond into the element, port 2 the bond out of it; the element
receives the effort of both (a forced decision: it is never inverted) and
answers the flow on each bond, in the bond's direction, from both efforts.
A subclass only writes :meth:`ConductanceTwoPort.flows`.

Examples
--------
>>> import sympy
>>> from bondgraph.library.thermal import Radiation
>>> T1, T2 = sympy.symbols("T1 T2", positive=True)
>>> Radiation("rad", area=2, emissivity=1).flows(T1, T2)[0].expand()
2*T1**4*sigma_SB - 2*T2**4*sigma_SB
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, Optional, Sequence

import sympy

from ..errors import ParameterError
from ..elements.protocol import CausalPorts, Decision, Element, LocalVariables
from ..signals import Signal, t as T_SYM
from .._support.sympify import ParameterLike, nonzero, to_expr

if TYPE_CHECKING:  # pragma: no cover
    from ..graph import Bond

__all__ = ["DirectedTwoPort", "ConductanceTwoPort", "positive_parameter"]


def positive_parameter(value: ParameterLike, default: sympy.Expr, *, owner: str,
                       what: str) -> sympy.Expr:
    """``value`` as a constant expression (``default`` when None); a number must be positive.

    Examples
    --------
    >>> positive_parameter(None, sympy.Symbol("h"), owner="R:conv", what="h")
    h
    >>> positive_parameter(-1, sympy.Symbol("h"), owner="R:conv", what="h")
    Traceback (most recent call last):
    ...
    bondgraph.errors.ParameterError: R:conv: h must be positive, got -1
    """
    expr = nonzero(to_expr(value, owner=owner, what=what), owner=owner, what=what)
    if expr is None:
        return default
    if any(isinstance(s, Signal) for s in expr.free_symbols) or expr.has(T_SYM):
        raise ParameterError(f"{owner}: {what} {expr} must be a constant parameter (no signals, "
                             "no time)")
    if expr.is_number and not expr.is_positive:
        raise ParameterError(f"{owner}: {what} must be positive, got {expr}")
    return expr


@dataclass(frozen=True, eq=False)
class DirectedTwoPort(Element):
    """A two-port with one bond into it and one out of it (checked at ``connect``)."""

    bonds: ClassVar[tuple[int, Optional[int]]] = (2, 2)
    drawing_role: ClassVar[str] = "backbone"
    #: what its two sides are, for messages
    sides: ClassVar[str] = "port 1 is the bond into it, port 2 the bond out"

    def _directions(self, first: "Bond", second: "Bond") -> Optional[str]:
        into = first.head == self.name
        if (second.head == self.name) != into:
            return None
        return (f"{self.label()} already has bond {first.number} pointing "
                f"{'into' if into else 'out of'} it; its other bond must point the other way "
                f"({self.sides})")

    def bond_error(self, existing: Sequence["Bond"], bond: "Bond") -> Optional[str]:
        err = super().bond_error(existing, bond)
        return err if err is not None or not existing else self._directions(existing[0], bond)

    def structure_error(self, bonds: Sequence["Bond"]) -> Optional[str]:
        err = super().structure_error(bonds)
        return err if err is not None else self._directions(bonds[0], bonds[1])


@dataclass(frozen=True, eq=False)
class ConductanceTwoPort(DirectedTwoPort):
    """A two-port that receives both efforts and answers both flows (see the module)."""

    def flows(self, effort_in: sympy.Expr, effort_out: sympy.Expr) -> tuple[sympy.Expr, sympy.Expr]:
        """The flows on the bond into it and on the bond out of it (each in its bond's
        direction), from the efforts of those bonds."""
        raise NotImplementedError(f"{self.label()}: {type(self).__name__} does not define flows")

    def forced_causality(self, ports: CausalPorts) -> Sequence[Decision]:
        why = f"{self.label()} takes the effort of both bonds"
        return (Decision(0, True, why), Decision(1, True, why))

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        return ((0, 1), (0, 1))

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        return (f"{self.label()}: its law is nonlinear in both efforts; the port-Hamiltonian "
                "form needs linear R elements")

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        first = 0 if local.into(0) else 1        # the bond into the element
        f_in, f_out = self.flows(local.input(first), local.input(1 - first))
        return f_in if port == first else f_out
