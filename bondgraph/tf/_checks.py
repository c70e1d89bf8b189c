"""Argument checks of the transfer-function entry points.

Matrices (sympy, nested lists or numpy arrays) become sympy matrices of
consistent shapes, signal names are checked, ``input=``/``output=`` selections
are resolved, and the ``normalize``/``method`` options are validated.  Every
failure is a :class:`~bondgraph.tf.errors.TransferFunctionError` naming the
argument at fault.

Examples
--------
>>> resolve_signal("omega", ("i", "omega"), "output")
1
>>> _signal_names(None, 2, "u", "input_names")
('u1', 'u2')
"""

from __future__ import annotations

from typing import Literal

import numpy as np
import sympy as sp

from .._support.sympify import as_expr, as_matrix
from .errors import InvalidOptionError, ShapeError, UnknownSignalError

__all__ = ["Normalize", "NORMALIZATIONS", "METHODS"]

Normalize = Literal["monic", "as-derived", "leading-one-denominator"]
NORMALIZATIONS = ("monic", "as-derived", "leading-one-denominator")
METHODS = ("auto", "laplace", "bareiss", "berkowitz")


def _as_matrix(M, what: str, *, vector: str = "column") -> sp.ImmutableMatrix:
    """A sympy matrix; a 1-D sequence is a column (``B``) or a row (``C``, ``D``)."""
    if not isinstance(M, sp.MatrixBase):
        arr = M.tolist() if isinstance(M, np.ndarray) else M
        if isinstance(arr, (list, tuple)) and arr and not isinstance(arr[0], (list, tuple)):
            arr = [[x] for x in arr] if vector == "column" else [list(arr)]
        M = arr
    return as_matrix(M, what=what, error=ShapeError)


def _check_shapes(A, B, C, D, E):
    A = _as_matrix(A, "A")
    n = A.shape[0]
    if A.shape != (n, n):
        raise ShapeError(f"A: expected a square matrix, got shape {A.shape}")
    B = _as_matrix(B, "B")
    if B.shape[0] != n:
        raise ShapeError(f"B: expected {n} rows (A is {n}x{n}), got shape {B.shape}")
    C = _as_matrix(C, "C", vector="row")
    if C.shape[1] != n:
        raise ShapeError(f"C: expected {n} columns (A is {n}x{n}), got shape {C.shape}")
    m, p = B.shape[1], C.shape[0]
    if D is None or (not isinstance(D, (sp.MatrixBase, np.ndarray, list, tuple))
                     and as_expr(D, what="D", error=ShapeError) == 0):
        D = sp.ImmutableMatrix.zeros(p, m)
    elif not isinstance(D, (sp.MatrixBase, np.ndarray, list, tuple)):
        D = sp.ImmutableMatrix([[D]])
    D = _as_matrix(D, "D", vector="row")
    if D.shape != (p, m):
        raise ShapeError(f"D: expected shape ({p}, {m}) (C has {p} rows, B has {m} "
                         f"columns), got {D.shape}")
    if E is not None:
        E = _as_matrix(E, "E")
        if E.shape != (n, n):
            raise ShapeError(f"E: expected shape ({n}, {n}) like A, got {E.shape}")
        if E == sp.eye(n):
            E = None
    return A, B, C, D, E


def _signal_names(names, count: int, default: str, what: str) -> tuple[str, ...]:
    if names is None:
        return (default,) if count == 1 else tuple(f"{default}{i + 1}" for i in range(count))
    if isinstance(names, str):
        names = (names,)
    names = tuple(str(x) for x in names)
    if len(names) != count:
        raise ShapeError(f"{what}: expected {count} names, got {len(names)}: {names}")
    if len(set(names)) != len(names):
        raise ShapeError(f"{what}: expected distinct names, got {names}")
    return names


def resolve_signal(sel, names: tuple[str, ...], what: str) -> int:
    plural = what + "s"
    valid = ", ".join(repr(x) for x in names)
    if sel is None:
        if len(names) == 1:
            return 0
        raise UnknownSignalError(f"{what}: the system has {len(names)} {plural} ({valid}); "
                                 f"pass {what}= one of them")
    if isinstance(sel, (int, np.integer)) and not isinstance(sel, bool):
        if -len(names) <= sel < len(names):
            return int(sel) % len(names)
        raise UnknownSignalError(f"{what}: expected an index in 0..{len(names) - 1} or a "
                                 f"name ({valid}), got {sel}")
    if str(sel) in names:
        return names.index(str(sel))
    raise UnknownSignalError(f"{what}: {sel!r} is not an {what} of the system; valid "
                             f"{plural}: {valid}")


def _check_options(normalize, method):
    if normalize not in NORMALIZATIONS:
        raise InvalidOptionError(f"normalize: expected one of {NORMALIZATIONS}, "
                                 f"got {normalize!r}")
    if method not in METHODS:
        raise InvalidOptionError(f"method: expected one of {METHODS}, got {method!r}")
