"""Symbolic linear state-space systems with named signals.

Examples
--------
>>> import sympy
>>> from bondgraph.statespace import SymbolicStateSpace
>>> m, k = sympy.symbols("m k", positive=True)
>>> ss = SymbolicStateSpace(sympy.ImmutableMatrix([[0, 1/m], [-k, 0]]),
...     sympy.ImmutableMatrix([[1], [0]]), sympy.ImmutableMatrix([[0, 1]]),
...     sympy.ImmutableMatrix([[0]]), ("p", "q"), ("F",), ("x",))
>>> ss.nstates, ss.ninputs, ss.noutputs
(2, 1, 1)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import sympy

from .errors import BondGraphError

__all__ = ["SymbolicStateSpace"]


def expected_shape(label: str, n: int, m: int, p: int) -> tuple[int, int]:
    """Shape of matrix ``label`` ("A".."D") for ``n`` states, ``m`` inputs, ``p`` outputs."""
    return {"A": (n, n), "B": (n, m), "C": (p, n), "D": (p, m)}[label]


def check_matrix_shape(label: str, shape: tuple[int, ...], n: int, m: int, p: int,
                       error: type[Exception]) -> None:
    """Raise ``error`` naming the matrix unless ``shape`` is :func:`expected_shape`."""
    expected = expected_shape(label, n, m, p)
    if tuple(shape) != expected:
        raise error(f"state-space matrix {label} has shape {tuple(shape)}; expected {expected} "
                    f"for {n} states, {m} inputs, {p} outputs")


class SignalCounts:
    """``nstates``, ``ninputs``, ``noutputs`` of a system with named signals (mixin)."""

    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]

    @property
    def nstates(self) -> int:
        return len(self.state_names)

    @property
    def ninputs(self) -> int:
        return len(self.input_names)

    @property
    def noutputs(self) -> int:
        return len(self.output_names)


@dataclass(frozen=True)
class SymbolicStateSpace(SignalCounts):
    """``x' = A x + B u``, ``y = C x + D u`` with symbolic entries and names.

    When ``E`` is given the system is in descriptor form ``E x' = A x + B u``.
    Results of :meth:`bondgraph.Model.state_space` hold sparse immutable
    matrices (bond-graph models are sparse); any sympy immutable matrix works.

    Examples
    --------
    >>> import sympy
    >>> m, k = sympy.symbols("m k", positive=True)
    >>> ss = SymbolicStateSpace(sympy.ImmutableMatrix([[0, 1/m], [-k, 0]]),
    ...     sympy.ImmutableMatrix([[1], [0]]), sympy.ImmutableMatrix([[0, 1]]),
    ...     sympy.ImmutableMatrix([[0]]), ("p", "q"), ("F",), ("x",))
    >>> ss.subs({"m": 2, "k": 8}).A
    Matrix([
    [ 0, 1/2],
    [-8,   0]])
    """

    A: sympy.ImmutableMatrix
    B: sympy.ImmutableMatrix
    C: sympy.ImmutableMatrix
    D: sympy.ImmutableMatrix
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    E: sympy.ImmutableMatrix | None = None

    def __post_init__(self) -> None:
        for label in "ABCD":
            check_matrix_shape(label, getattr(self, label).shape, self.nstates, self.ninputs,
                               self.noutputs, BondGraphError)

    @property
    def parameters(self) -> tuple[sympy.Symbol, ...]:
        """Free symbols of the matrices, sorted by name."""
        syms = set()
        for mat in (self.A, self.B, self.C, self.D) + ((self.E,) if self.E is not None else ()):
            syms |= mat.free_symbols
        return tuple(sorted(syms, key=lambda s: s.name))

    def subs(self, values: Mapping) -> "SymbolicStateSpace":
        """Substitute parameter values (symbols or numbers) in every matrix."""
        sub = {(_sym(self, k) if isinstance(k, str) else k): v for k, v in values.items()}
        for k, v in sub.items():
            if isinstance(v, str) or not isinstance(v, (sympy.Basic, int, float)):
                raise BondGraphError(f"value of {k}: expected a number or sympy expression, "
                                     f"got {type(v).__name__} {v!r} (text is never parsed)")
        def f(mat):
            return None if mat is None else sympy.ImmutableMatrix(mat.xreplace(
                {k: sympy.sympify(v) for k, v in sub.items()}))
        return SymbolicStateSpace(f(self.A), f(self.B), f(self.C), f(self.D),
                                  self.state_names, self.input_names, self.output_names, f(self.E))

    def to_latex(self) -> str:
        r"""Matrix form ``E x' = A x + B u``, ``y = C x + D u`` in LaTeX.

        Examples
        --------
        >>> import sympy
        >>> ss = SymbolicStateSpace(sympy.ImmutableMatrix([[-1]]), sympy.ImmutableMatrix([[1]]),
        ...     sympy.ImmutableMatrix([[1]]), sympy.ImmutableMatrix([[0]]), ("x",), ("u",), ("y",))
        >>> r"\dot{x}" in ss.to_latex()
        True
        """
        from .tf import state_space_latex

        return state_space_latex(self.A, self.B, self.C, self.D, E=self.E,
                                 state_names=self.state_names, input_names=self.input_names,
                                 output_names=self.output_names)

    def _repr_latex_(self) -> str:
        return "$$" + self.to_latex() + "$$"

    def __str__(self) -> str:
        parts = [f"states  {list(self.state_names)}", f"inputs  {list(self.input_names)}",
                 f"outputs {list(self.output_names)}"]
        for label in ("E", "A", "B", "C", "D"):
            mat = getattr(self, label)
            if mat is not None:
                parts.append(f"{label} = {sympy.pretty(mat, use_unicode=False)}")
        return "\n".join(parts)


def _sym(ss: SymbolicStateSpace, name: str) -> sympy.Symbol:
    for s in ss.parameters:
        if s.name == name:
            return s
    raise BondGraphError(f"no parameter named {name!r}; parameters are "
                         f"{', '.join(s.name for s in ss.parameters)}")
