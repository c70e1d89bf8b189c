"""Exact polynomial algebra behind the symbolic transfer functions (private).

The matrices ``A, B, C, D, E`` are encoded in one multivariate polynomial ring
``QQ[s, p_1..p_k, r_1..r_q]`` where the ``p`` are the parameters (and any other
non-polynomial atoms such as ``sqrt(2)``) and each ``r_j`` stands for ``1/f_j``,
``f_j`` an irreducible denominator factor of some entry (``1/m``, ``1/L``,
``1/(J1 + n**2*J2)``).  All entries are then polynomials, determinants are
computed division free, and the reciprocals are cleared at the end by
multiplying every result by the same product ``prod f_j**d_j`` (this keeps
ratios exact because evaluation ``r_j -> 1/f_j`` is a ring homomorphism).

Determinants of the (sparse) matrices ``sE - A`` and of the bordered matrices
``[[sE - A, B_j], [-C_i, D_ij]]`` are computed by a memoized Laplace expansion
over row subsets (cheap for the banded / arrow-shaped matrices of lumped
models), with a fraction-free Bareiss elimination as the fallback for dense
matrices.  The ring arithmetic is python-flint's ``fmpq_mpoly`` when available,
otherwise sympy's ``PolyRing``.  sympy's ``DomainMatrix.charpoly`` (Berkowitz)
is available as ``method="berkowitz"`` for cross-checking.


The stages, one module each, in pipeline order:

1. :mod:`bondgraph.tf._rings` -- the ring arithmetic (:class:`Ring`, :func:`make_ring`);
2. :mod:`bondgraph.tf._encode` -- matrices to ring elements (:func:`encode_system`);
3. :mod:`bondgraph.tf._determinants` -- ``det(sE - A)`` and the bordered
   determinants (:func:`determinant`, :func:`charpoly_berkowitz`);
4. :mod:`bondgraph.tf._cancel` -- reciprocals cleared, common factors cancelled
   (:func:`clear_reciprocals`, :func:`cancel_common`).

This module gathers their public names.

Examples
--------
>>> import sympy as sp
>>> from bondgraph.tf._algebra import encode_system, determinant
>>> m, k, s = sp.symbols("m k s", positive=True)
>>> enc = encode_system(sp.Matrix([[0, 1/m], [-k, 0]]), sp.Matrix([[0], [1]]),
...                     sp.Matrix([[1, 0]]), sp.Matrix([[0]]), None, s)
>>> den = determinant(enc.pencil(), enc.ring)
>>> enc.ring.to_sympy(den, enc.all_symbols)
_r*k + s**2
"""

from __future__ import annotations

from ._cancel import SDict, cancel_common, clear_reciprocals, from_sdict, to_sdict
from ._determinants import LAPLACE_MIN, charpoly_berkowitz, determinant, split_s
from ._encode import EncodedSystem, encode_system, polys_from_exprs
from ._rings import Ring, backend_name, make_ring

__all__ = ["Ring", "make_ring", "EncodedSystem", "encode_system", "determinant",
           "charpoly_berkowitz", "clear_reciprocals", "cancel_common", "backend_name",
           "polys_from_exprs", "split_s", "to_sdict", "from_sdict", "SDict", "LAPLACE_MIN"]
