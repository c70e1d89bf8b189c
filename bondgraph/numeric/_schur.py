"""Plants of linear implicit models: the algebraic unknowns eliminated numerically.

A linear model may keep algebraic unknowns ``z`` (a linear loop whose exact
symbolic solution is too large to write down, see
:mod:`bondgraph.equations.loops`)::

    x' = F_x x + F_z z + F_u u
    0  = G_x x + G_z z + G_u u
    y  = H_x x + H_z z + H_u u

Every block is small and symbolic; the plant at parameter values is the
Schur complement, formed in floating point after evaluation::

    A = F_x - F_z G_z^-1 G_x      B = F_u - F_z G_z^-1 G_u
    C = H_x - H_z G_z^-1 G_x      D = H_u - H_z G_z^-1 G_u

:func:`implicit_blocks` gives the stacked symbolic matrices that
:class:`~bondgraph.numeric.NumericModel` compiles; :func:`reduce` and
:func:`reduce_batch` eliminate ``z`` from one evaluation or a stack.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import sympy
from sympy.solvers.solveset import NonlinearError

from ..equations import StateEquations
from ..errors import NonlinearModelError
from ..linear.forms import sparse_matrix
from ..signals import t as T_SYM
from .errors import ParameterValueError

__all__ = ["implicit_blocks", "reduce", "reduce_batch"]


def implicit_blocks(model: StateEquations) -> tuple[list, list[str]]:
    """Symbolic ``[[F_x, F_z], [G_x, G_z]]``, ``[[F_u], [G_u]]``, ``[H_x, H_z]``,
    ``H_u`` of a linear implicit model, and their labels.

    Raises
    ------
    NonlinearModelError
        ``f``, ``g`` or the outputs are not linear in ``x, z, u``, or hold input
        derivatives.
    """
    if model.input_derivatives:
        raise NonlinearModelError(
            f"model {model.name!r}: an implicit model whose equations hold input "
            f"derivatives ({', '.join(map(str, model.input_derivatives))}) has no numeric "
            "plant here")
    xz = tuple(model.states) + tuple(model.algebraic)
    u = tuple(model.inputs)
    blocks = []
    for exprs, what in ((model.rhs, "state equation"), (model.residuals, "residual"),
                        (model.output_exprs, "output")):
        blocks.append(_coefficients(model, list(exprs), xz, u, what))
    (F, Fu), (G, Gu), (H, Hu) = blocks
    return [_stacked(F, G), _stacked(Fu, Gu), H, Hu], \
        ["[[F_x, F_z], [G_x, G_z]]", "[[F_u], [G_u]]", "[H_x, H_z]", "H_u"]


def _stacked(top, bottom):
    """``top.col_join(bottom)`` without sympy's sort of the entries by printed form."""
    entries = dict(top.todok())
    entries.update({(i + top.rows, j): v for (i, j), v in bottom.todok().items()})
    return sparse_matrix(top.rows + bottom.rows, top.cols, entries)


def _coefficients(model: StateEquations, exprs: list, xz: tuple, u: tuple, what: str):
    """Sparse ``(M_xz, M_u)`` with ``exprs = M_xz (x, z) + M_u u``, read in one pass
    over the terms (``sympy.linear_eq_to_matrix``)."""
    variables = xz + u
    if not exprs:
        return sparse_matrix(0, len(xz), {}), sparse_matrix(0, len(u), {})
    try:
        M, const = sympy.linear_eq_to_matrix(exprs, variables)
    except (NonlinearError, ValueError) as exc:
        raise NonlinearModelError(
            f"model {model.name!r}: a {what} is not linear in the states, algebraic "
            f"unknowns and inputs ({exc}); linearize it at an operating point") from None
    bad = {T_SYM} | set(variables)
    entries: tuple[dict, dict] = ({}, {})
    for (i, j), c in M.todok().items():
        if c.free_symbols & bad:
            raise NonlinearModelError(
                f"model {model.name!r}: {what} {i + 1} has the coefficient {c} of "
                f"{variables[j]}, which is not constant")
        if j < len(xz):
            entries[0][(i, j)] = c
        else:
            entries[1][(i, j - len(xz))] = c
    for i, c in enumerate(const):
        if c != 0:
            raise NonlinearModelError(
                f"model {model.name!r}: {what} {i + 1} has the constant term {-c}; model "
                "constant loads as sources (inputs)")
    return (sparse_matrix(len(exprs), len(xz), entries[0]),
            sparse_matrix(len(exprs), len(u), entries[1]))

def _singular(model: StateEquations, where: str = "") -> ParameterValueError:
    return ParameterValueError(
        f"model {model.name!r}: {where}the algebraic loop in "
        f"{', '.join(model.algebraic_names)} is singular at these values (dg/dz has no "
        "inverse): the junction structure does not determine these variables there")


def reduce(model: StateEquations, A, B, C, D, sparse: bool) -> tuple:
    """``(A, B, C, D)`` of the states only, from one evaluation of the stacked blocks."""
    n = len(model.states)
    if sparse:
        A, B, C = sp.csr_array(A), sp.csr_array(B), sp.csr_array(C)
        Gz = A[n:, n:].tocsc()
        rhs = sp.hstack([A[n:, :n], B[n:, :]]).toarray()
        try:
            lu = sp.linalg.splu(Gz)
            X = lu.solve(rhs)
        except RuntimeError:        # "Factor is exactly singular"
            raise _singular(model) from None
        if not np.all(np.isfinite(X)):
            raise _singular(model)
        Xs = sp.csr_array(X)
        Fz, Hz = A[:n, n:], C[:, n:]
        out_A = (A[:n, :n] - Fz @ Xs[:, :n]).tocsr()
        out_B = (B[:n, :] - Fz @ Xs[:, n:]).toarray()
        out_C = (C[:, :n] - Hz @ Xs[:, :n]).toarray()
        out_D = sp.csr_array(D).toarray() - (Hz @ Xs[:, n:]).toarray()
        return out_A, out_B, out_C, out_D
    A, B, C, D = (np.asarray(M, dtype=float) for M in (A, B, C, D))
    Gz = A[n:, n:]
    rhs = np.hstack([A[n:, :n], B[n:, :]])
    try:
        X = np.linalg.solve(Gz, rhs) if Gz.size else rhs
    except np.linalg.LinAlgError:
        raise _singular(model) from None
    if np.linalg.cond(Gz) > 1e14 or not np.all(np.isfinite(X)):
        raise _singular(model)
    Fz, Hz = A[:n, n:], C[:, n:]
    return (A[:n, :n] - Fz @ X[:, :n], B[:n, :] - Fz @ X[:, n:],
            C[:, :n] - Hz @ X[:, :n], D - Hz @ X[:, n:])


def reduce_batch(model: StateEquations, A, B, C, D) -> tuple:
    """As :func:`reduce` on dense stacks ``(P, ., .)``."""
    n = len(model.states)
    Gz = A[:, n:, n:]
    rhs = np.concatenate([A[:, n:, :n], B[:, n:, :]], axis=2)
    try:
        X = np.linalg.solve(Gz, rhs)
    except np.linalg.LinAlgError:
        bad = next(k for k in range(Gz.shape[0]) if np.linalg.matrix_rank(Gz[k]) < Gz.shape[1])
        raise _singular(model, f"parameter set {bad}: ") from None
    Fz, Hz = A[:, :n, n:], C[:, :, n:]
    return (A[:, :n, :n] - Fz @ X[:, :, :n], B[:, :n, :] - Fz @ X[:, :, n:],
            C[:, :, :n] - Hz @ X[:, :, :n], D - Hz @ X[:, :, n:])

