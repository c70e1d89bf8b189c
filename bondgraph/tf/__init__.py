"""Symbolic transfer functions, pole/zero tables and LaTeX from state-space matrices.

The public API:

- :func:`transfer_function`, :func:`transfer_matrix` -> :class:`SymbolicTF`,
  :class:`TransferMatrix`; ``.subs(values)`` -> :class:`NumericTF`.
- :func:`pole_zero_table` -> :class:`PoleZeroTable` (``.rows``, ``str``,
  ``.to_latex()``).
- LaTeX helpers: :func:`tf_latex`, :func:`numeric_tf_latex`,
  :func:`factored_latex`, :func:`state_equations_latex`,
  :func:`state_space_latex`, :func:`matrix_latex`.

Modules, in pipeline order: ``_checks`` (arguments) -> ``_algebra`` (exact
ring arithmetic: ``_rings``, ``_encode``, ``_determinants``, ``_cancel``) ->
``_convert`` (sympy Polys, normalization) -> ``symbolic_tf`` /
``matrix`` (:class:`SymbolicTF`, :class:`TransferMatrix`) -> ``_exact``
(evaluation at parameter values) -> ``numeric_tf`` (:class:`NumericTF`,
:class:`NumericTransferMatrix`); ``symbolic`` holds the entry points,
``latex`` and ``tables`` the printing.

Examples
--------
>>> import sympy as sp
>>> from bondgraph.tf import transfer_function
>>> m, k = sp.symbols("m k", positive=True)
>>> G = transfer_function([[0, 1], [-k/m, 0]], [0, 1/m], [[1, 0]], 0,
...                       normalize="as-derived")
>>> G.expr
1/(k + m*s**2)
"""

from .errors import (InvalidOptionError, MatrixEntryError, MissingValueError,
                     ParameterValueError, ShapeError, SingularPencilError,
                     TransferFunctionError, UnknownSignalError)
from .latex import (factored_latex, matrix_latex, numeric_tf_latex, poly_latex,
                    state_equations_latex, state_space_latex, tf_latex)
from .symbolic import (NORMALIZATIONS, NumericTF, NumericTransferMatrix, SymbolicTF,
                       TransferMatrix, transfer_function, transfer_matrix)
from .tables import PoleZeroRow, PoleZeroTable, pole_zero_table
from ._checks import resolve_signal

__all__ = [
    "transfer_function", "transfer_matrix", "SymbolicTF", "NumericTF", "TransferMatrix",
    "NumericTransferMatrix", "NORMALIZATIONS",
    "pole_zero_table", "PoleZeroTable", "PoleZeroRow",
    "tf_latex", "numeric_tf_latex", "factored_latex", "poly_latex", "matrix_latex",
    "state_equations_latex", "state_space_latex",
    "TransferFunctionError", "ShapeError", "UnknownSignalError", "SingularPencilError",
    "MissingValueError", "ParameterValueError", "InvalidOptionError", "MatrixEntryError",
    "resolve_signal",
]
