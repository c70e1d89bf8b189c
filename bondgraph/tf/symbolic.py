"""Symbolic transfer functions from sympy state-space matrices.

``G(s) = C (sE - A)^{-1} B + D`` is never formed by inverting a matrix: the
denominator is ``det(sE - A)`` and each numerator the bordered determinant

.. math:: n_{ij}(s) = \\det\\begin{bmatrix} sE - A & B_j \\\\ -C_i & D_{ij} \\end{bmatrix}
          = \\det(sE - A)\\,(D_{ij} + C_i (sE - A)^{-1} B_j),

both computed exactly over a polynomial ring in ``s`` and the parameters (see
:mod:`bondgraph.tf._algebra`); common factors of numerator and denominator
are cancelled by an exact multivariate gcd.  ``B`` and ``D`` may hold
polynomials in ``s`` (input derivatives, ``B(s) = B0 + B1 s``): the bordered
determinant is linear in its last column, so the same formula gives
``C (sE - A)^{-1} B(s) + D(s)``, improper when ``D(s)`` has a power of ``s``
or ``C`` meets ``B1`` often enough.

The pipeline, one module each: arguments checked (:mod:`bondgraph.tf._checks`)
-> matrices encoded, determinants, reciprocals cleared, common factors
cancelled (:mod:`bondgraph.tf._algebra`) -> sympy Polys normalized
(:mod:`bondgraph.tf._convert`) -> :class:`~bondgraph.tf.symbolic_tf.SymbolicTF`
or :class:`~bondgraph.tf.matrix.TransferMatrix` -> exact evaluation at
parameter values (:mod:`bondgraph.tf._exact`) ->
:class:`~bondgraph.tf.numeric_tf.NumericTF` /
:class:`~bondgraph.tf.numeric_tf.NumericTransferMatrix`.  This module holds
the entry points, :func:`transfer_function` and :func:`transfer_matrix`, and
gathers the classes under their historical import path.

Examples
--------
>>> import sympy as sp
>>> from bondgraph.tf import transfer_function
>>> R, L, C = sp.symbols("R L C", positive=True)
>>> A = sp.Matrix([[0, 1/L], [-1/C, -R/L]])       # states q_C, p_L
>>> B = sp.Matrix([0, 1]); Cm = sp.Matrix([[1/C, 0]])
>>> G = transfer_function(A, B, Cm, 0, input_names=["V"], output_names=["v_C"],
...                       normalize="leading-one-denominator")
>>> G.expr
1/(C*L*s**2 + C*R*s + 1)
>>> G.subs({"R": 1, "L": 0.5, "C": 0.5}).den
(0.25, 0.5, 1.0)
"""

from __future__ import annotations

from typing import Sequence

import sympy as sp

from . import _algebra as alg
from ._budget import DEFAULT_MAX_TERMS, check_budget
from ._checks import (METHODS, NORMALIZATIONS, Normalize, _check_options, _check_shapes,
                      resolve_signal, _signal_names)
from ._convert import _Converter
from ._lift import lifted_determinant
from .._support.gcpause import paused_gc
from ._packed import can_pack, packed_determinants
from ._packed_ops import clear_terms, normalize_terms
from .errors import InvalidOptionError, SingularPencilError
from .matrix import TransferMatrix
from .numeric_tf import NumericTF, NumericTransferMatrix
from .symbolic_tf import SymbolicTF, _entry

__all__ = ["SymbolicTF", "NumericTF", "TransferMatrix", "NumericTransferMatrix",
           "transfer_function", "transfer_matrix", "Normalize", "NORMALIZATIONS", "METHODS"]


def _prepare(A, B, C, D, E, input_names, output_names, s, normalize, method):
    """Checked options, matrices, signal names and Laplace variable of an entry point."""
    _check_options(normalize, method)
    A, B, C, D, E = _check_shapes(A, B, C, D, E)
    ins = _signal_names(input_names, B.shape[1], "u", "input_names")
    outs = _signal_names(output_names, C.shape[0], "y", "output_names")
    s = sp.Symbol("s") if s is None else s
    if not isinstance(s, sp.Symbol):
        raise InvalidOptionError(f"s: expected a sympy Symbol, got {s!r}")
    return A, B, C, D, E, ins, outs, s


def _compute(A, B, C, D, E, s, method, backend, max_terms=None, what="transfer function"):
    enc = alg.encode_system(A, B, C, D, E, s, backend=backend)
    ring = enc.ring
    p, m = C.shape[0], B.shape[1]
    check_budget(enc, [(i, j) for i in range(p) for j in range(m)], max_terms, what)
    if method != "berkowitz" and can_pack(enc):
        # fast path: packed determinants, results as exponent arrays (see _packed)
        den, flat = packed_determinants(enc, [(i, j) for i in range(p) for j in range(m)],
                                        method=method)
        if not len(den):
            raise SingularPencilError("E, A: det(sE - A) is identically zero (singular "
                                      "pencil); the system has no transfer function")
        flat = clear_terms([den] + flat, enc)
        return enc, flat[0], [flat[1 + i * m:1 + (i + 1) * m] for i in range(p)]
    if method == "berkowitz":
        if E is not None:
            raise InvalidOptionError("method: 'berkowitz' (DomainMatrix.charpoly) needs "
                                     "E = I; got a descriptor E; use method='auto'")
        den, nums = alg.charpoly_berkowitz(enc)
    else:
        pencil = enc.pencil()
        den = lifted_determinant(pencil, ring, method=method)
        if ring.is_zero(den):
            raise SingularPencilError("E, A: det(sE - A) is identically zero (singular "
                                      "pencil); the system has no transfer function")
        nums = [[lifted_determinant(enc.bordered(pencil, i, j), ring, method=method)
                 for j in range(m)] for i in range(p)]
    flat = alg.clear_reciprocals([den] + [x for row in nums for x in row], enc)
    den = flat[0]
    nums = [flat[1 + i * m:1 + (i + 1) * m] for i in range(p)]
    return enc, den, nums


def transfer_function(A, B, C, D=None, *, E=None, input: str | int | None = None,
                      output: str | int | None = None,
                      input_names: Sequence[str] | None = None,
                      output_names: Sequence[str] | None = None,
                      s: sp.Symbol | None = None, normalize: Normalize = "monic",
                      cancel: bool = True, method: str = "auto",
                      backend: str | None = None,
                      max_terms: int | None = DEFAULT_MAX_TERMS) -> SymbolicTF:
    """Symbolic ``G(s) = C_i (sE - A)^{-1} B_j + D_ij`` for one input/output.

    Parameters
    ----------
    A, B, C, D
        State-space matrices (sympy matrices, nested lists or numpy arrays);
        ``D`` may be ``None``/``0`` for zero.  Entries are rational functions
        of the parameters (``1/m`` is fine); floats are read as the decimals
        they print as.  Entries of ``B`` and ``D`` may be polynomials in
        ``s`` (input derivatives: ``x' = A x + B0 u + B1 u'`` has
        ``B = B0 + s*B1``); ``G`` is then ``C (sE - A)^{-1} B(s) + D(s)``
        and may be improper (``is_proper`` False).
    E
        Descriptor matrix of ``E x' = A x + B u`` (``None``: identity).  It is
        never inverted; ``det(sE - A)`` must not vanish identically.
    input, output
        Name (or index) of the input and output; may be omitted when there is
        only one.
    input_names, output_names
        Names of the columns of ``B`` and rows of ``C`` (default ``u``/``u1..``
        and ``y``/``y1..``).
    s
        The Laplace variable (default ``Symbol('s')``).
    normalize
        ``'monic'``: denominator's highest coefficient is 1 (coefficients are
        rational functions of the parameters); ``'as-derived'``: numerator and
        denominator are polynomials in the parameters (fraction free, common
        content removed, positive leading term), as from the determinants;
        ``'leading-one-denominator'``: the denominator's lowest-order nonzero
        coefficient is 1 (``1/(LC s^2 + RC s + 1)``).
    cancel
        Cancel common factors of numerator and denominator (exact gcd).
    method
        Determinants: ``'auto'`` (Laplace expansion over row subsets, Bareiss
        for dense matrices), ``'laplace'``, ``'bareiss'`` or ``'berkowitz'``
        (sympy ``DomainMatrix.charpoly`` and the matrix determinant lemma;
        only for ``E = I``; much slower beyond a few states).
    backend
        Polynomial arithmetic: ``'flint'`` (python-flint, default when
        installed) or ``'sympy'``.
    max_terms
        Term budget: before expanding, the number of terms of ``det(sE - A)``
        and of the numerator is bounded from the sparsity and the terms of
        each entry (:mod:`bondgraph.tf._budget`); past ``max_terms``
        (default None: no budget) the call is refused with
        :class:`~bondgraph.tf.errors.TermBudgetError`.  ``None``: no budget.

    Returns
    -------
    SymbolicTF

    Raises
    ------
    ShapeError, UnknownSignalError, SingularPencilError, MatrixEntryError,
    InvalidOptionError, TermBudgetError
        All ``ValueError`` subclasses, naming the argument at fault.

    Examples
    --------
    DC motor, states ``i`` (armature current) and ``w`` (speed):

    >>> import sympy as sp
    >>> La, Ra, J, b, K = sp.symbols("L_a R_a J b K", positive=True)
    >>> A = sp.Matrix([[-Ra/La, -K/La], [K/J, -b/J]])
    >>> G = transfer_function(A, [1/La, 0], [[0, 1]], 0, input_names=["V"],
    ...                       output_names=["omega"], normalize="as-derived")
    >>> G.num_coeffs, G.den_coeffs
    ((K,), (J*L_a, J*R_a + L_a*b, K**2 + R_a*b))
    >>> transfer_function(A, [1/La, 0], [[0, 1]]).den_coeffs
    (1, (J*R_a + L_a*b)/(J*L_a), (K**2 + R_a*b)/(J*L_a))
    """
    A, B, C, D, E, ins, outs, s = _prepare(A, B, C, D, E, input_names, output_names, s,
                                           normalize, method)
    j = resolve_signal(input, ins, "input")
    i = resolve_signal(output, outs, "output")
    with paused_gc():
        enc, den, nums = _compute(A, B[:, j], C[i, :], D[i, j:j + 1], E, s, method, backend,
                                  max_terms, f"transfer function {ins[j]} -> {outs[i]}")
        return _entry(_Converter(enc.ring, enc.params), nums[0][0], den, s, ins[j], outs[i],
                      normalize, cancel=cancel)


def transfer_matrix(A, B, C, D=None, *, E=None, input_names: Sequence[str] | None = None,
                    output_names: Sequence[str] | None = None, s: sp.Symbol | None = None,
                    normalize: Normalize = "monic", method: str = "auto",
                    backend: str | None = None,
                    max_terms: int | None = DEFAULT_MAX_TERMS) -> TransferMatrix:
    """All input/output transfer functions over the shared ``det(sE - A)``.

    Same arguments as :func:`transfer_function` (without ``input``/``output``
    and ``cancel``: the shared form is uncancelled; index the result to get a
    cancelled entry).

    Parameters
    ----------
    A, B, C, D
        State-space matrices (sympy matrices, nested lists or numpy arrays);
        ``D`` may be ``None``/``0`` for zero.
    E
        Descriptor matrix (``None``: identity).
    input_names, output_names
        Names of the columns of ``B`` and rows of ``C``.
    s
        The Laplace variable (default ``Symbol('s')``).
    normalize
        ``'monic'``, ``'as-derived'`` or ``'leading-one-denominator'``, as in
        :func:`transfer_function`.
    method
        Determinant method: ``'auto'``, ``'laplace'``, ``'bareiss'`` or
        ``'berkowitz'``.
    backend
        Polynomial arithmetic: ``'flint'`` or ``'sympy'``.
    max_terms
        Term budget of the shared denominator and all the numerators
        together, as in :func:`transfer_function`.

    Returns
    -------
    TransferMatrix

    Examples
    --------
    >>> import sympy as sp
    >>> R, C = sp.symbols("R C", positive=True)
    >>> G = transfer_matrix([[-1/(R*C)]], [[1/(R*C), 1/C]], [[1]], None,
    ...                     input_names=["V", "I"], output_names=["v"],
    ...                     normalize="as-derived")
    >>> G.den.as_expr(), [n.as_expr() for n in G.nums[0]]
    (C*R*s + 1, [1, R])
    """
    A, B, C, D, E, ins, outs, s = _prepare(A, B, C, D, E, input_names, output_names, s,
                                           normalize, method)
    with paused_gc():
        enc, den, nums = _compute(A, B, C, D, E, s, method, backend, max_terms, "transfer matrix")
        conv = _Converter(enc.ring, enc.params)
        flat = [x for row in nums for x in row]
        Pd, Pns = normalize_terms(conv, den, flat, normalize, s)
    m = len(ins)
    rows = tuple(tuple(Pns[i * m:(i + 1) * m]) for i in range(len(outs)))
    raw = (conv, den, tuple(tuple(r) for r in nums))
    return TransferMatrix(rows, Pd, ins, outs, normalize, _raw=raw)
