"""Two-ports: transformers and gyrators, constant (TF, GY) or modulated (MTF, MGY).

Re-exported by :mod:`bondgraph.elements`; the conventions are in its docstring.
Their behaviour (:mod:`bondgraph.elements.protocol`): a TF passes effort from
one port to the other, a GY takes effort on both ports or on neither.

Examples
--------
>>> import bondgraph as bg
>>> bg.TF("gear", 3).bonds, bg.GY("K").bonds
((2, 2), (2, 2))
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, ClassVar, Optional, Sequence, cast

import sympy

from ..errors import CausalityConflictError, ParameterError
from .protocol import (CausalPorts, Decision, Element, LocalVariables, prefix_signals, rename,
                       signals_of)
from ..signals import LawVariable, Signal, t as T_SYM
from .._support.sympify import ParameterLike, nonzero, to_expr

if TYPE_CHECKING:  # pragma: no cover
    from .bond import Bond

__all__ = ["TwoPort", "TF", "GY", "MTF", "MGY"]


@dataclass(frozen=True, eq=False)
class TwoPort(Element):
    """Two-port element with a modulus: base of TF, GY, MTF and MGY.

    Parameters
    ----------
    name : str
    modulus : number, str or sympy expression, optional
        Defaults to a positive symbol named after the element's path.
    efficiency : number, str or sympy expression, optional
        Constant power efficiency (keyword only); 1 when not given.

    Examples
    --------
    >>> import bondgraph as bg
    >>> gear = bg.TF("gear", 3, efficiency=0.9)
    >>> isinstance(gear, bg.elements.TwoPort), gear.modulus, gear.bonds
    (True, 3, (2, 2))
    >>> bg.GY("K").resolved("motor.K").modulus
    motor.K
    """

    modulus: ParameterLike = None
    efficiency: ParameterLike = field(default=None, kw_only=True)
    bonds: ClassVar[tuple[int, Optional[int]]] = (2, 2)
    modulated: ClassVar[bool] = False

    def __post_init__(self) -> None:
        super().__post_init__()
        owner = self.label()
        eff = nonzero(to_expr(self.efficiency, owner=owner, what="efficiency"),
                      owner=owner, what="efficiency")
        if eff is not None and (eff.free_symbols & {T_SYM} or
                                any(isinstance(s, (Signal, LawVariable)) for s in eff.free_symbols)):
            raise ParameterError(f"{owner}: efficiency {eff} must be a constant parameter")
        object.__setattr__(self, "efficiency", sympy.Integer(1) if eff is None else eff)
        mod = nonzero(to_expr(self.modulus, owner=owner, what="modulus"), owner=owner,
                      what="modulus")
        if mod is None and self.modulated:
            raise ParameterError(f"{owner}: a modulated element needs modulus=<expression>")
        if mod is not None:
            dyn = [str(s) for s in mod.free_symbols if isinstance(s, (Signal, LawVariable)) or s == T_SYM]
            if dyn and not self.modulated:
                raise ParameterError(
                    f"{owner}: modulus {mod} depends on {', '.join(sorted(dyn))}; "
                    f"use M{self.kind} for a modulated {self.kind}"
                )
            law_vars = [str(s) for s in mod.free_symbols if isinstance(s, LawVariable)]
            if law_vars:
                raise ParameterError(
                    f"{owner}: modulus {mod} uses {', '.join(law_vars)}; a modulus may use "
                    "signals (bondgraph.displacement('J'), ...) and time bondgraph.t"
                )
        object.__setattr__(self, "modulus", mod)

    def resolved(self, path: str) -> Element:
        el = rename(self, path)
        prefix = path[: len(path) - len(self.name)]
        if self.modulus is None:
            object.__setattr__(el, "modulus", sympy.Symbol(path, positive=True))
        else:
            object.__setattr__(el, "modulus", prefix_signals(self.modulus, prefix))
        return el

    def signals(self) -> frozenset:
        return signals_of(self.modulus)

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        if self.modulated:
            return (f"{self.label()}: a modulated {self.kind[1:]} (modulus {self.modulus}) makes "
                    "J depend on the state or time; the port-Hamiltonian form needs "
                    "constant-modulus TF and GY")
        return None

    def conserves_power(self) -> bool:
        return self.efficiency == 1

    def domain_groups(self, count: int) -> tuple[tuple[int, ...], ...]:
        return ((0,), (1,))      # a TF or GY may change the domain

    # the protocol: port 1 is the bond into the element, port 2 the bond out
    #: a gyrator (GY, MGY) turns flow into effort; a transformer passes effort through
    gyrating: ClassVar[bool] = False

    def _directions(self, first: "Bond", second: "Bond") -> Optional[str]:
        into = first.head == self.name
        if (second.head == self.name) != into:
            return None
        return (f"{self.label()} already has bond {first.number} pointing "
                f"{'into' if into else 'out of'} it; its other bond must point the other way "
                f"(port 1 is the bond into a {self.kind}, port 2 the bond out)")

    def bond_error(self, existing: Sequence["Bond"], bond: "Bond") -> Optional[str]:
        err = super().bond_error(existing, bond)
        return err if err is not None or not existing else self._directions(existing[0], bond)

    def structure_error(self, bonds: Sequence["Bond"]) -> Optional[str]:
        err = super().structure_error(bonds)
        return err if err is not None else self._directions(bonds[0], bonds[1])

    def propagate(self, ports: CausalPorts) -> Sequence[Decision]:
        a, b = ports.effort_in(0), ports.effort_in(1)
        # TF passes effort through (exactly one port receives it); GY turns flow
        # into effort (both ports receive effort, or neither)
        same = self.gyrating
        if a is not None and b is None:
            return (Decision(1, a if same else not a, self.label()),)
        if b is not None and a is None:
            return (Decision(0, b if same else not b, self.label()),)
        if a is not None and b is not None and (a == b) != same:
            raise CausalityConflictError(
                f"causality conflict at {self.label()}: bonds {ports.number(0)} and "
                f"{ports.number(1)} were decided independently "
                f"(by {ports.reason(0)} and {ports.reason(1)}) and "
                + ("both bring effort into it or both take it out; a "
                   f"{self.kind} passes effort from one port to the other"
                   if not same else
                   "only one of them brings effort in; a "
                   f"{self.kind} takes effort on both ports or on neither")
            )
        return ()

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        return ((1,), (0,))   # each port's output from the other port's input

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        mod = cast(sympy.Expr, self.modulus)     # resolved to an expression by resolved()
        if self.modulated:
            mod = local.resolve(mod)
        first = 0 if local.into(0) else 1      # port 1: the bond into the element
        x = local.input(1 - port)
        eta = cast(sympy.Expr, self.efficiency)
        if not self.gyrating:
            # e1 = n e2 / eta, f2 = n f1 ; or e2 = eta e1 / n, f1 = f2 / n
            if local.effort_in(port):
                return mod * x if port != first else x / mod
            return mod * x / eta if port == first else eta * x / mod
        # GY: e1 = r f2, e2 = eta r f1 ; or f2 = e1 / r, f1 = e2 / (eta r)
        if not local.effort_in(port):
            return mod * x if port == first else eta * mod * x
        return x / mod if port != first else x / (eta * mod)


@dataclass(frozen=True, eq=False)
class TF(TwoPort):
    """Transformer: ``e1 = n*e2``, ``f2 = n*f1`` (port 1 = bond in).

    The modulus multiplies the *flow* from port 1 to port 2, so a gearbox
    that reduces the speed N times (motor on port 1, load on port 2,
    ``w_load = w_motor/N``, ``T_load = N T_motor``) is ``TF("gear", 1/N)``;
    ``TF("gear", N)`` is an N-fold speed-up.

    ``efficiency=eta`` makes it lossy the way servo-motor data sheets do
    (Quanser SRV-02 gearbox): ``f2 = n*f1`` still, but ``e2 = eta*e1/n``, so
    the power out of port 2 is ``eta`` times the power into port 1.  This is
    exact in the motoring quadrant (power from port 1 to port 2).

    Examples
    --------
    >>> TF("gear", sympy.Rational(1, 14)).modulus        # a 14:1 reduction
    1/14
    """

    kind: ClassVar[str] = "TF"


@dataclass(frozen=True, eq=False)
class GY(TwoPort):
    """Gyrator: ``e1 = r*f2``, ``e2 = r*f1``.

    ``efficiency=eta`` gives ``e2 = eta*r*f1`` with ``e1 = r*f2`` unchanged
    (a DC motor whose torque is ``eta_m*k*i`` and back-emf ``k*w``).

    Examples
    --------
    >>> GY("K").label()
    'GY:K'
    """

    kind: ClassVar[str] = "GY"
    gyrating: ClassVar[bool] = True


@dataclass(frozen=True, eq=False)
class MTF(TwoPort):
    """Modulated transformer; the modulus may use signals and time.

    Examples
    --------
    >>> import bondgraph as bg, sympy
    >>> yoke = bg.MTF("yoke", modulus=sympy.Symbol("r")*sympy.sin(bg.displacement("crank")))
    >>> sorted(str(s) for s in yoke.signals())
    ['displacement[crank]']
    """

    kind: ClassVar[str] = "MTF"
    modulated: ClassVar[bool] = True


@dataclass(frozen=True, eq=False)
class MGY(TwoPort):
    """Modulated gyrator; the modulus may use signals and time.

    Examples
    --------
    >>> import bondgraph as bg
    >>> MGY("g", modulus=2*bg.t).kind
    'MGY'
    """

    kind: ClassVar[str] = "MGY"
    modulated: ClassVar[bool] = True
    gyrating: ClassVar[bool] = True
