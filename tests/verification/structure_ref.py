"""Independent numeric reference for the structural analyses (:mod:`bondgraph.structure`).

Written only for the tests and the bench; it imports nothing of the code under
test except to build and derive the model.  For a random graph of
:mod:`verification.generator` with one output ``y`` (an effort or flow signal,
no integrated signals, so the engine adds no integrator states) it computes,
from :class:`verification.reference.Reference`'s own bond equations
``(M0 + s M1) x = B u``, ``y = C0 x`` of size ``N`` (two unknowns per bond),
at the generator's random parameter values:

* ``n`` -- the number of finite generalized eigenvalues of ``(M0, -M1)``
  (:func:`scipy.linalg.eig`), the dynamic order ``deg det(M0 + s M1)``;
* ``rank [A B]`` -- ``rank [M0 B] - (N - n)`` and ``rank [A; C]`` --
  ``rank [M0; C0] - (N - n)``, exact ranks over the rationals (python-flint).
  In the Weierstrass form ``P (M0 + s M1) Q = diag(A_f + s I, I + s N)`` the
  matrix ``M(0)`` is ``diag(A_f, I)``: the fast part adds exactly ``N - n`` to
  the rank, and the slow part is similar to the model's ``(A, B, C)`` up to a
  column operation ``B + A K`` that keeps ``rank [A B]``;
* the bond-graph ranks (Sueur and Dauphin-Tanguy, derivative causality with
  dualised sources / detectors) are structural values: a graph rank below
  the reference's rank is a disagreement, one above it a bound that is not
  tight (causal-path gains that cancel);
* the number of differentiations in the bicausal bond graph of the inversion
  (one-term outputs, ``G != 0``) is a structural relative degree: never above
  the reference's;
* the number of finite zeros -- finite generalized eigenvalues of the
  Rosenbrock pencil ``[[M0 + s M1, -B_j], [C0, 0]]``; the relative degree is
  the degree difference ``n - zeros`` (``det`` of the pencil is
  ``det M(s) * G(s)``).  A transfer function that vanishes at two random
  ``s`` is ``G = 0`` (its pencil is singular and has no zeros to count).
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Optional

import flint
import numpy as np
import scipy.linalg

from verification.generator import _signals, build, generate
from verification.reference import Graph, Output, Reference, Term

__all__ = ["case", "reference_numbers", "engine_numbers", "compare", "Comparison"]

_FINITE = 1e7       # |lambda| above this counts as infinite (parameters are in [0.1, 10])


def case(seed: int) -> tuple[Graph, str]:
    """A random graph with one effort/flow output ``y`` and the chosen input's name."""
    g = generate(seed)
    rng = random.Random(seed * 31 + 5)
    sigs = [s for s in _signals(g) if s[0] in ("effort", "flow")]
    k = rng.choice([1, 1, 1, 2])
    terms = {}
    for _ in range(k):
        kind, target = rng.choice(sigs)
        terms[(kind, target)] = rng.choice([-2, -1, 1, 3])
    out = Output("y", tuple(Term(c, kd, tg) for (kd, tg), c in terms.items()))
    g = replace(g, outputs=(out,))
    inputs = [el.name for el in g.elements if el.kind in ("Se", "Sf")]
    return g, rng.choice(inputs)


def _fmpq(v: Fraction):
    return flint.fmpq(v.numerator, v.denominator)


def _rank(rows: list[dict[int, Fraction]], ncols: int) -> int:
    M = flint.fmpq_mat(len(rows), ncols)
    for i, r in enumerate(rows):
        for c, v in r.items():
            M[i, c] = _fmpq(v)
    return M.rank()


def _finite(a: np.ndarray, b: np.ndarray) -> int:
    if a.size == 0:
        return 0
    alpha, beta = scipy.linalg.eig(a, b, right=False, homogeneous_eigvals=True)
    return int(np.sum(np.abs(beta) * _FINITE > np.abs(alpha)))


def reference_numbers(g: Graph, u: str) -> Optional[dict]:
    """The reference numbers (see the module docstring); None for an ill-posed graph."""
    ref = Reference(g)
    if not ref.well_posed:
        return None
    N = ref.n
    M0, M1 = ref.pencil()
    n = _finite(M0, -M1)
    j = ref.input_names.index(u)
    m = len(ref.inputs)
    rows_ab = [dict(r) for r in ref.M0]
    for i, b in enumerate(ref.B):
        for jj, v in b.items():
            rows_ab[i][N + jj] = v
    rank_ab = _rank(rows_ab, N + m) - (N - n)
    rank_ac = _rank(list(ref.M0) + list(ref.C0), N) - (N - n)
    rng = random.Random(7)
    G = [ref.evaluate(s)[0, j] for s in ref.pick_s(rng, 2)]
    scale = max(1.0, *(abs(x) for x in G))
    if all(x == 0 for x in G):
        return dict(n=n, rank_ab=rank_ab, rank_ac=rank_ac, rel=None, zeros=None)
    Bj = np.array([float(b.get(j, 0)) for b in ref.B])
    C0 = np.zeros(N)
    for c, v in ref.C0[0].items():
        C0[c] = float(v)
    a = np.zeros((N + 1, N + 1))
    e = np.zeros((N + 1, N + 1))
    a[:N, :N], a[:N, N], a[N, :N] = M0, -Bj, C0
    e[:N, :N] = -M1
    nz = _finite(a, e)
    del scale
    return dict(n=n, rank_ab=rank_ab, rank_ac=rank_ac, rel=n - nz, zeros=nz)


def engine_numbers(g: Graph, u: str, *, order_seed: Optional[int] = None) -> dict:
    """The same numbers from :mod:`bondgraph.structure` on the derived model."""
    import bondgraph as bg
    from bondgraph.structure import (bicausal_graph, controllability, observability,
                                     zero_structure)

    bgg, outputs, _ = build(g, order_seed)
    model = bg.derive(bgg, outputs=outputs)
    c = controllability(model)
    o = observability(model, detectors=outputs)
    z = zero_structure(model, u, "y", max_states=0)
    bic = None
    terms = g.outputs[0].terms
    if len(terms) == 1 and z.relative_degree is not None:
        try:
            bic = bicausal_graph(model, u, "y", signal=outputs["y"]).differentiations
        except bg.BondGraphError:
            bic = "refused"
    return dict(bicausal_rel=bic, n=len(model.states), rank_ab=c.generic_rank, rank_ac=o.generic_rank,
                rel=z.relative_degree, zeros=z.finite_zeros,
                matching_ab=c.structural_rank, matching_ac=o.structural_rank,
                graph_ab=c.graph_rank, graph_ac=o.graph_rank,
                path_rel=z.structural_degree, integrators=len(model.integrators))


@dataclass
class Comparison:
    seed: int
    status: str                     # "agree", "disagree", "ill-posed", "refused"
    ref: Optional[dict] = None
    eng: Optional[dict] = None
    detail: str = ""
    bound_not_tight: tuple = field(default=())


KEYS = ("n", "rank_ab", "rank_ac", "rel", "zeros")


def compare(seed: int) -> Comparison:
    """Compare engine and reference on the random graph of ``seed``."""
    import bondgraph as bg

    g, u = case(seed)
    ref = reference_numbers(g, u)
    if ref is None:
        return Comparison(seed, "ill-posed")
    try:
        eng = engine_numbers(g, u)
    except bg.BondGraphError as err:
        return Comparison(seed, "refused", ref, None, f"{type(err).__name__}: {err}")
    bad = [k for k in KEYS if ref[k] != eng[k]]
    detail = [f"{k}: reference {ref[k]}, engine {eng[k]}" for k in bad]
    # the bond-graph rank (Sueur and Dauphin-Tanguy) is structural: never below the
    # generic rank, above it only where causal-path gains cancel
    for k, kk in (("rank_ab", "graph_ab"), ("rank_ac", "graph_ac")):
        if eng["integrators"]:           # the bond-graph rank covers the storage states only
            eng[kk] = None
        if eng[kk] is not None and eng[kk] < ref[k]:
            detail.append(f"{kk}: {eng[kk]} below the reference's {k} {ref[k]}")
    # the bicausal bond graph's differentiations are the structural relative degree: never
    # above the generic one (below it only where causal-path gains cancel)
    if eng["bicausal_rel"] == "refused" or (eng["bicausal_rel"] is not None and
                                            eng["bicausal_rel"] > ref["rel"]):
        detail.append(f"bicausal_rel: {eng['bicausal_rel']}, reference relative degree "
                      f"{ref['rel']}")
    if eng["bicausal_rel"] == "refused":
        eng["bicausal_rel"] = None
    pairs = (("matching_ab", "rank_ab"), ("matching_ac", "rank_ac"), ("path_rel", "rel"),
             ("graph_ab", "rank_ab"), ("graph_ac", "rank_ac"), ("bicausal_rel", "rel"))
    loose = tuple(b for b, k in pairs if eng[b] is not None and eng[b] != eng[k])
    if detail:
        return Comparison(seed, "disagree", ref, eng, "; ".join(detail), loose)
    return Comparison(seed, "agree", ref, eng, "", loose)
