"""Symbolic linear state-space systems with named signals.

Examples
--------
>>> import sympy
>>> from bondgraph.linear.statespace import SymbolicStateSpace
>>> m, k = sympy.symbols("m k", positive=True)
>>> ss = SymbolicStateSpace(sympy.ImmutableMatrix([[0, 1/m], [-k, 0]]),
...     sympy.ImmutableMatrix([[1], [0]]), sympy.ImmutableMatrix([[0, 1]]),
...     sympy.ImmutableMatrix([[0]]), ("p", "q"), ("F",), ("x",))
>>> ss.nstates, ss.ninputs, ss.noutputs
(2, 1, 1)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import sympy

from ..errors import BondGraphError
from ..parameters import ParameterValues, exact_value, match_values

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
    #: names of every parameter of the model definition (see :mod:`bondgraph.parameters`)
    known_parameters: tuple[str, ...] = field(default=(), compare=False, repr=False)
    #: feedthrough of input derivatives, ``y = C x + D u + D_derivatives[0] u' + ...``
    #: (outputs that need them: a linearization keeps them here); empty otherwise
    D_derivatives: tuple[sympy.ImmutableMatrix, ...] = ()
    #: the model's elements whose parameters have rules (a mass positive): :meth:`subs`
    #: checks them at the values it is given (:mod:`bondgraph.elements.rules`)
    value_checks: tuple = field(default=(), compare=False, repr=False)
    #: the operating point the form was taken about (deviations ``x - x0``, ``u - u0``,
    #: ``y - y0``): set for a model with constant sources or a linearization, else None
    operating_point: Any = field(default=None, compare=False, repr=False)

    def __post_init__(self) -> None:
        for label in "ABCD":
            check_matrix_shape(label, getattr(self, label).shape, self.nstates, self.ninputs,
                               self.noutputs, BondGraphError)
        for k, M in enumerate(self.D_derivatives):
            check_matrix_shape("D", M.shape, self.nstates, self.ninputs, self.noutputs,
                               BondGraphError)

    @property
    def parameters(self) -> tuple[sympy.Symbol, ...]:
        """Free symbols of the matrices, sorted by name."""
        syms = set()
        for mat in (self.A, self.B, self.C, self.D) + ((self.E,) if self.E is not None else ()) \
                + tuple(self.D_derivatives):
            syms |= mat.free_symbols
        return tuple(sorted(syms, key=lambda s: s.name))

    def subs(self, values: ParameterValues | None = None, *,
             partial: bool = True) -> "SymbolicStateSpace":
        """Substitute parameter values in every matrix.

        Parameters
        ----------
        values : mapping of parameter name (or Symbol) to number
            Exact: floats are read as the rational of their decimal
            representation, so entries that cancel do so exactly.  Names of
            the model definition this form does not use are ignored; other
            unknown names are an error listing the valid ones.
        partial : bool, optional
            ``True`` (default) leaves parameters without a value symbolic;
            ``False`` requires a value for each.

        Raises
        ------
        ParameterValueError
            Unknown name, missing value (``partial=False``), or a value that is
            not a finite real number (text is never parsed).
        """
        given = match_values(self.parameters, values, known=self.known_parameters,
                             partial=partial)
        sub = {p: exact_value(v, p.name) for p, v in given.items()}
        if self.value_checks:
            from ..elements.rules import check_values

            check_values(self.value_checks, {p.name: v for p, v in sub.items()})

        def f(mat):
            return None if mat is None else sympy.ImmutableMatrix(mat.xreplace(sub))
        return SymbolicStateSpace(f(self.A), f(self.B), f(self.C), f(self.D),
                                  self.state_names, self.input_names, self.output_names, f(self.E),
                                  known_parameters=self.known_parameters,
                                  D_derivatives=tuple(f(M) for M in self.D_derivatives),
                                  value_checks=self.value_checks,
                                  operating_point=(None if self.operating_point is None else
                                                   self.operating_point.subs(
                                                       {p.name: v for p, v in given.items()})))

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
        from ..tf import state_space_latex

        text = state_space_latex(self.A, self.B, self.C, self.D, E=self.E,
                                 state_names=self.state_names, input_names=self.input_names,
                                 output_names=self.output_names)
        for k, M in enumerate(self.D_derivatives, start=1):
            text += (r",\quad y \mathrel{+}= %s\, u^{(%d)}" % (sympy.latex(M), k))
        return text

    def _repr_latex_(self) -> str:
        return "$$" + self.to_latex() + "$$"

    def __str__(self) -> str:
        parts = [f"states  {list(self.state_names)}", f"inputs  {list(self.input_names)}",
                 f"outputs {list(self.output_names)}"]
        labelled = [(label, getattr(self, label)) for label in ("E", "A", "B", "C", "D")]
        labelled += [(f"D_derivatives[{k}]", M) for k, M in enumerate(self.D_derivatives)]
        for label, mat in labelled:
            if mat is not None:
                rows = sympy.pretty(mat, use_unicode=False).splitlines()
                pad = " " * len(f"{label} = ")
                mid = len(rows) // 2
                parts += [(f"{label} = " if i == mid else pad) + row for i, row in enumerate(rows)]
        return "\n".join(parts)
