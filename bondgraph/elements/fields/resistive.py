"""The resistive field :class:`RField` (re-exported by :mod:`bondgraph.elements.fields`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar, Optional, Sequence

import sympy

from .algebra import FieldError, field_matrix, partial_solve, solve_law
from .base import Field, law_function, field_variables
from ..protocol import ARBITRARY, RESISTIVE, Choice, LocalVariables
from ...signals import LawVariable

__all__ = ["RField"]


@dataclass(frozen=True, eq=False)
class RField(Field):
    """Resistive field: ``e = R f`` with a resistance matrix, or ``e_k = law_k(f)``.

    Each port takes either causality (arbitrary, as a one-port R); ports that
    receive effort are solved for their flows (linear: a Schur complement;
    nonlinear: :class:`FieldError` when the law cannot be inverted there).

    Parameters
    ----------
    name : str
    resistance : square matrix, optional
        Symmetric, positive semi-definite when numeric.
    law : sequence of sympy expressions, optional
        The effort of each port as a function of the flows into the ports.
    variables : sequence of sympy.Symbol
        The flows ``law`` is written in, one per port.

    Examples
    --------
    >>> import bondgraph as bg
    >>> d = bg.RField("D", [[3, 1], [1, 2]])
    >>> d.ports, d.drawing_label()
    (2, ('RF', 'D'))
    """

    resistance: object = None
    matrix: Optional[sympy.ImmutableMatrix] = field(default=None, init=False)
    laws: sympy.Tuple = field(default=sympy.Tuple(), init=False, repr=False)
    variables: tuple = field(default=(), init=False, repr=False)
    kind: ClassVar[str] = "RF"
    definite: ClassVar[bool] = False
    drawing_role: ClassVar[str] = "dissipative"

    def __init__(self, name: str, resistance: object = None, *, law: object = None,
                 variables: Optional[Sequence[sympy.Symbol]] = None) -> None:
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "resistance", resistance)
        self.__post_init__()
        owner = self.label()
        if (resistance is None) == (law is None):
            raise FieldError(f"{owner}: give either a resistance matrix or law=, "
                             f"{'not both' if law is not None else 'one of them'}")
        if resistance is not None:
            M = field_matrix(resistance, owner=owner, what="resistance matrix", definite=False)
            object.__setattr__(self, "matrix", M)
            object.__setattr__(self, "port_kinds", "R" * M.rows)
            object.__setattr__(self, "variables",
                               tuple(LawVariable(f"f{k + 1}") for k in range(M.rows)))
            return
        laws = tuple(law) if isinstance(law, (list, tuple)) else None
        if not laws:
            raise FieldError(f"{owner}: law= must be a sequence of expressions, the effort of "
                             f"each port; got {law!r}")
        own, vs = field_variables(law, variables, len(laws), owner=owner,
                             prefixes="f" * len(laws), what="law")
        object.__setattr__(self, "laws", sympy.Tuple(*[law_function(x, vs, own, owner=owner,
                                                                 what="law") for x in laws]))
        object.__setattr__(self, "variables", own)
        object.__setattr__(self, "port_kinds", "R" * len(laws))
        jac = sympy.Matrix(self.laws).jacobian(own)
        if not jac.free_symbols & set(own) and all(e.xreplace({v: 0 for v in own}) == 0
                                                   for e in self.laws):
            object.__setattr__(self, "matrix", field_matrix(
                jac, owner=owner, what="resistance matrix (Jacobian of the law)", definite=False))

    def causal_choices(self, prefer_derivative: bool) -> Sequence[Choice]:
        return tuple(Choice(p, False, f"arbitrary choice for {self.label()} port {p + 1}",
                            RESISTIVE) for p in range(self.ports))

    def causal_class(self, effort_in: Sequence[bool], free: Sequence[bool]) -> Optional[str]:
        return ARBITRARY if any(free) else None

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        every = tuple(range(self.ports))
        return tuple(every for _ in every)

    def _solve(self, local: LocalVariables) -> tuple[list, list]:
        """(flows into the ports, efforts)."""
        f_in = {p: local.sign(p) * local.input(p) for p in range(self.ports)
                if not local.effort_in(p)}
        e_in = {p: local.input(p) for p in range(self.ports) if local.effort_in(p)}
        if self.matrix is not None:
            return partial_solve(self.matrix, f_in, e_in, owner=self.label(),
                                 what=getattr(self, "matrix_name", "matrix"))
        own = self.variables
        f = [f_in.get(p) for p in range(self.ports)]
        if e_in:
            known = {own[p]: v for p, v in f_in.items()}
            b = sorted(e_in)
            sol = solve_law([self.laws[p].xreplace(known) - e_in[p] for p in b],
                            [own[p] for p in b], owner=self.label(), ports=[p + 1 for p in b],
                            what="effort-in causality (flow out)")
            for p in b:
                f[p] = sol[own[p]]
        full = dict(zip(own, f))
        return f, [e_in[p] if p in e_in else self.laws[p].xreplace(full)
                   for p in range(self.ports)]

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        f, e = self._solve(local)
        return local.sign(port) * f[port] if local.effort_in(port) else e[port]

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        if self.matrix is None:
            return (f"{self.label()}: the nonlinear law {list(self.laws)} makes the "
                    "dissipation depend on the state; the port-Hamiltonian form needs a "
                    "linear RField (a resistance matrix)")
        return None
