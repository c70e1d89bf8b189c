"""Exact generic values of a model's linear form at random rational parameter points.

A structural property holds for *almost all* parameter values (outside a
proper algebraic subset).  Evaluating the matrices at a random point with
rational coordinates and computing exactly over the rationals (sympy's
``DomainMatrix`` over ``QQ``) gives the generic value with probability one
(Schwartz-Zippel); two points are taken and the larger rank kept.  Values
that are not rational after substitution (a ``sqrt`` of a parameter) are
evaluated with 40 significant digits instead, and ranks then use a
relative tolerance of ``1e-25``.

Everything here is private; the public analyses live in
:mod:`bondgraph.structure`.
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Mapping, Sequence

import networkx as nx
import sympy
from sympy.polys.domains import QQ
from sympy.polys.matrices import DomainMatrix

from ..errors import BondGraphError
from ..linear import derivative_form
from ..model import Model

__all__ = ["LinearForm", "linear_form", "random_points", "at_point", "exact_rank",
           "term_rank", "left_kernel_support", "StructureError", "PRIMES", "modular",
           "modular_rank_and_support"]

#: two primes below 2**62 for ranks modulo a prime (python-flint ``nmod_mat``)
PRIMES = (4611686018427387847, 4611686018427387817)


class StructureError(BondGraphError, ValueError):
    """A structural analysis cannot be made (nonlinear model, unknown channel)."""


@dataclass(frozen=True)
class LinearForm:
    """``x' = A x + sum_k B_k u^(k)``, ``y = C x + sum_k D_k u^(k)`` with names."""

    A: sympy.Matrix
    Bs: tuple
    C: sympy.Matrix
    Ds: tuple
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    parameters: tuple[sympy.Symbol, ...]
    #: the operating point of a model with constant sources (its deviation form), else None
    operating_point: object = None


def linear_form(model: Model) -> LinearForm:
    """The model's linear form; a clear error for a model that is not linear.

    A model with constant sources gives its form in deviations about its
    operating point (:meth:`bondgraph.Model.state_space`), kept in
    ``operating_point``: the same matrices, so the same structural properties.
    """
    if not isinstance(model, Model):
        raise StructureError(f"expected a bondgraph.Model (from bg.derive), got "
                             f"{type(model).__name__}")
    point = None
    try:
        A, Bs, C, Ds = derivative_form(model)
    except BondGraphError as err:
        # constant sources (gravity, an ambient) or inputs entering nonlinearly: the form in
        # deviations about the operating point (the same A, B, C, D for constant sources)
        try:
            ss = model.state_space()
        except BondGraphError:
            ss = None
        if ss is None or ss.operating_point is None:
            raise StructureError(f"model {model.name!r}: structural analysis needs a linear "
                                 f"model ({err})") from err
        A, Bs, C, Ds, point = ss.A, (ss.B,), ss.C, (ss.D,), ss.operating_point
    params = set()
    for M in (A, C) + tuple(Bs) + tuple(Ds):
        params |= M.free_symbols
    return LinearForm(sympy.Matrix(A), tuple(sympy.Matrix(B) for B in Bs), sympy.Matrix(C),
                      tuple(sympy.Matrix(D) for D in Ds), model.state_names, model.input_names,
                      model.output_names, tuple(sorted(params, key=lambda s: s.name)), point)


def random_points(params: Sequence[sympy.Symbol], count: int = 2, *, seed: int = 0
                  ) -> list[dict[sympy.Symbol, sympy.Rational]]:
    """``count`` random points: each parameter a rational ``p/q``, ``p`` in 1..997, ``q`` in
    1..97 (positive, so positivity assumptions hold); negated at random for symbols not
    declared positive or nonnegative."""
    rng = random.Random(seed)
    out = []
    for _ in range(count):
        pt = {}
        for p in params:
            v = sympy.Rational(rng.randint(1, 997), rng.randint(1, 97))
            if not (p.is_positive or p.is_nonnegative) and rng.random() < 0.5:
                v = -v
            pt[p] = v
        out.append(pt)
    return out


def at_point(M: sympy.Matrix, point: Mapping) -> sympy.Matrix:
    """``M`` with the parameters replaced by the point's values."""
    point = dict(point)
    out = sympy.zeros(M.rows, M.cols)
    for (i, j), e in M.todok().items():        # the nonzero entries only
        out[i, j] = e.xreplace(point)
    return out


def _domain(M: sympy.Matrix):
    try:
        return DomainMatrix.from_Matrix(M).convert_to(QQ)
    except Exception:       # an entry that is not rational (sqrt of a parameter)
        return None


def exact_rank(M: sympy.Matrix) -> int:
    """Rank of a matrix of numbers: exact over QQ, or at 40 digits when irrational."""
    if 0 in M.shape:
        return 0
    dm = _domain(M)
    if dm is not None:
        return dm.rank()
    import mpmath

    with mpmath.workdps(40):
        num = mpmath.matrix([[mpmath.mpf(sympy.N(e, 45)) if e.is_real else mpmath.mpc(complex(e))
                              for e in M.row(i)] for i in range(M.rows)])
        sv = mpmath.svd_r(num, compute_uv=False) if all(e.is_real for e in M) else \
            mpmath.svd_c(num, compute_uv=False)
        top = max((abs(s) for s in sv), default=0)
        return sum(1 for s in sv if abs(s) > top * mpmath.mpf("1e-25"))


def generic_rank(M: sympy.Matrix, points: Sequence[Mapping]) -> int:
    """The generic rank of a parametric matrix: the largest rank over the points."""
    return max((exact_rank(at_point(M, pt)) for pt in points), default=0)


def term_rank(M: sympy.Matrix) -> int:
    """Size of a maximum matching between rows and columns of the nonzero pattern."""
    G = nx.Graph()
    rows = [("r", i) for i in range(M.rows)]
    G.add_nodes_from(rows, bipartite=0)
    G.add_nodes_from((("c", j) for j in range(M.cols)), bipartite=1)
    for (i, j), e in M.todok().items():
        if e != 0:
            G.add_edge(("r", i), ("c", j))
    match = nx.bipartite.hopcroft_karp_matching(G, top_nodes=rows)
    return sum(1 for node in match if node[0] == "r")


def left_kernel_support(M: sympy.Matrix, point: Mapping) -> tuple[int, ...]:
    """Rows of ``M`` (at ``point``) on which some vector ``w`` with ``w^T M = 0`` is nonzero."""
    Mv = at_point(M, point)
    dm = _domain(Mv.T)
    if dm is None:        # irrational entries: at most the rows that are all zero
        return tuple(i for i in range(M.rows) if all(e == 0 for e in M.row(i)))
    basis = dm.nullspace().to_Matrix()
    return tuple(i for i in range(M.rows) if any(basis[k, i] != 0 for k in range(basis.rows)))


def modular(M: sympy.Matrix, prime: int):
    """``M`` (rational numbers) modulo ``prime`` as a flint ``nmod_mat``; None when an entry is
    not rational or its denominator is divisible by ``prime``."""
    import flint

    vals = [0] * (M.rows * M.cols)
    for (i, j), e in M.todok().items():
        if not e.is_Rational:
            return None
        q = int(e.q) % prime
        if q == 0:
            return None
        vals[i * M.cols + j] = int(e.p) * pow(q, -1, prime) % prime
    return flint.nmod_mat(M.rows, M.cols, vals, prime)


def modular_rank_and_support(K, rank_needed: int) -> tuple[int, tuple[int, ...]]:
    """Rank of a flint ``nmod_mat`` and, when below ``rank_needed``, the rows on which a
    vector of its left kernel is nonzero."""
    r = K.rank()
    if r >= rank_needed:
        return r, ()
    X, nullity = K.transpose().nullspace()
    return r, tuple(i for i in range(K.nrows())
                    if any(int(X[i, k]) for k in range(nullity)))
