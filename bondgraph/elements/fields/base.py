"""The base of the multiport fields (:mod:`bondgraph.elements.fields`): ports, port signals,
value checks, and the user's energy or law rewritten in the field's own variables."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar, Optional, Sequence

import numpy as np
import sympy

from .algebra import FieldError, no_signals, check_definite
from ...errors import OutputError, ParameterValueError
from ..protocol import Element
from ...signals import LawVariable
from ..._support.sympify import to_expr

__all__ = ["Field"]


def field_variables(energy, variables, n_hint: Optional[int], *, owner: str, prefixes: Sequence[str],
               what: str) -> tuple[sympy.Expr, tuple]:
    """The user's function rewritten in the field's own variables ``p1, q2, ...``."""
    if variables is None:
        raise FieldError(f"{owner}: {what}= needs variables=(...): the sympy symbols it is "
                         "written in, one per port in port order")
    vs = tuple(variables)
    if not vs or not all(isinstance(v, sympy.Symbol) for v in vs) or len(set(vs)) != len(vs):
        raise FieldError(f"{owner}: variables must be distinct sympy symbols, one per port; "
                         f"got {variables!r}")
    if n_hint is not None and len(vs) != n_hint:
        raise FieldError(f"{owner}: {len(vs)} variables for {n_hint} ports")
    own = tuple(LawVariable(f"{prefixes[k]}{k + 1}") for k in range(len(vs)))
    return own, vs


def law_function(value, vs, own, *, owner: str, what: str) -> sympy.Expr:
    expr = to_expr(value, owner=owner, what=what, law=True)
    if expr is None:  # pragma: no cover - caller checked
        raise FieldError(f"{owner}: no {what}")
    expr = expr.xreplace(dict(zip(vs, own)))
    no_signals(expr, owner, what)
    return expr


@dataclass(frozen=True, eq=False)
class Field(Element):
    """A field: ``n`` ports, each a bond; signals need a port."""

    #: one character per port: 'I', 'C' (storage) or 'R'
    #: whether the matrix must be positive definite (an RField's: semi-definite)
    definite: ClassVar[bool] = True
    port_kinds: str = field(default="", init=False, repr=False)

    @property
    def bonds(self) -> tuple[int, Optional[int]]:   # type: ignore[override]
        n = len(self.port_kinds)
        return (n, n)

    @property
    def ports(self) -> int:
        """Number of ports."""
        return len(self.port_kinds)

    def signal_port(self, variable: str) -> Optional[tuple[int, bool]]:
        raise OutputError(
            f"signal {variable}[{self.name}]: {self.label()} has {self.ports} ports, so its "
            f"{variable} is ambiguous; name one, e.g. bg.{variable}({self.name!r}, port=1) "
            f"(ports 1..{self.ports}, in the order of its bonds)")

    def energy_variable(self, variable: str) -> Optional[int]:
        self.signal_port(variable)     # raises: ambiguous
        return None                    # pragma: no cover

    def _port(self, variable: str, port: int) -> int:
        if isinstance(port, bool) or not isinstance(port, int) or not 1 <= port <= self.ports:
            raise OutputError(f"signal {variable}[{self.name}][{port}]: {self.label()} has ports "
                              f"1..{self.ports}; got port {port!r}")
        return port - 1

    def port_signal(self, variable: str, port: int) -> Optional[tuple[int, bool]]:
        return self._port(variable, port), variable == "flow"

    def drawing_label(self) -> tuple[str, str]:
        return self.kind, self.name

    def _sides(self, effort_in: Sequence[bool]) -> tuple[list[int], list[int]]:
        raise NotImplementedError

    def check_values(self, values) -> None:
        """Check the matrix positive definite (an RField's semi-definite) at ``values``.

        Raises
        ------
        FieldError
            Naming the field and its matrix.
        ParameterValueError
            A parameter of the matrix has no value.

        Examples
        --------
        >>> import bondgraph as bg
        >>> m, c = sympy.symbols("m c", positive=True)
        >>> bg.IField("M", [[m, c], [c, m]]).check_values({"m": 1.0, "c": 2.0})
        Traceback (most recent call last):
        ...
        bondgraph.FieldError: IF:M: the mass matrix is not positive definite (smallest eigenvalue -1); ...
        """
        matrix = getattr(self, "matrix", None)
        if matrix is None:
            return
        name = getattr(self, "matrix_name", "resistance matrix")
        sub = {}
        for s in matrix.free_symbols:
            key = s.name if s.name in values else s
            if key not in values:
                raise ParameterValueError(f"{self.label()}: parameter {s.name!r} of its "
                                          f"{name} has no value")
            sub[s] = values[key]
        arr = np.array(matrix.xreplace(sub).tolist(), dtype=float)
        check_definite(arr, owner=self.label(), what=name, definite=self.definite)
