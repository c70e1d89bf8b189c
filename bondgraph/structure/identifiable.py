"""Structural identifiability of physical parameters from a transfer function.

A transfer function identified from data fixes its coefficients, nothing
more.  For the pair ``input -> output`` of a linear model this module writes
``G(s)`` in lowest terms with a monic denominator, takes the map from the
unknown parameters ``theta`` to its coefficients, and the Jacobian of that map
in logarithmic coordinates, ``J[i, j] = theta_j dc_i/dtheta_j``:

* its rank, symbolically (a ``DomainMatrix`` over the fraction field of the
  parameters), confirmed by the exact rank at random rational points: the
  number of independent parameter combinations the data can fix;
* the parameters that are identifiable one by one (locally): those whose unit
  vector lies in the row space of ``J``;
* the identifiable monomials ``prod theta_j^alpha_j``: the integer vectors
  ``alpha`` orthogonal to the null space of ``J`` at every parameter point
  (scaling symmetries), with the coefficients themselves as the identifiable
  combinations that are not monomials.

Parameters not listed as unknown are treated as known constants (they stay
symbolic).

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.structure import identifiability
>>> g = bg.BondGraph("rc")
>>> j = bg.One("j")
>>> g.add(bg.Se("V"), j, bg.R("R"), bg.C("C"))
>>> for t, h in [("V", j), (j, "R"), (j, "C")]: _ = g.connect(t, h)
>>> res = identifiability(bg.derive(g, outputs={"v": bg.effort("C")}))
>>> res.rank, res.identifiable, res.combinations
(1, (), (C*R,))
"""

from __future__ import annotations

import math
import warnings
import weakref
from dataclasses import dataclass
from typing import Optional, Sequence

import sympy
from sympy.polys.domains import QQ
from sympy.polys.matrices import DomainMatrix

from ..equations.fraction_free import TOO_LARGE, rank_fraction_free
from ..errors import BondGraphError, BondGraphWarning
from ..model import Model
from ._generic import StructureError, at_point, exact_rank, random_points
from .zeros import S

__all__ = ["Identifiability", "identifiability", "tf_coefficients", "IdentifiabilityWarning",
           "warn_unidentifiable"]


@dataclass(frozen=True)
class Identifiability:
    """What a transfer function can reveal of the unknown parameters (immutable).

    Attributes
    ----------
    model, input, output : str
    unknown : tuple of str
        The parameters treated as unknown (the rest are known constants).
    coefficients : tuple of (str, sympy.Expr)
        ``("b0", ...)`` numerator and ``("a1", ...)`` monic-denominator
        coefficients of ``G(s)`` in lowest terms (structural zeros left out).
    rank : int
        Rank of the Jacobian of the coefficients: symbolic (``exact=True``), or the
        largest rank at the random points (``exact=False``), equal to the symbolic
        rank except on a set of points of measure zero (Schwartz-Zippel).
    rank_at_points : tuple of int
        The exact rank at random rational points (confirmation).
    identifiable, unidentifiable : tuple of str
        Unknown parameters the coefficients fix one by one (locally), and the rest.
    combinations : tuple of sympy.Expr
        A basis of the identifiable monomials of the unknown parameters.
    """

    model: str
    input: str
    output: str
    unknown: tuple[str, ...]
    coefficients: tuple[tuple[str, sympy.Expr], ...]
    rank: int
    rank_at_points: tuple[int, ...]
    identifiable: tuple[str, ...]
    unidentifiable: tuple[str, ...]
    combinations: tuple[sympy.Expr, ...]

    @property
    def deficiency(self) -> int:
        """Number of independent directions in parameter space the data cannot see."""
        return len(self.unknown) - self.rank

    def __str__(self) -> str:
        lines = [f"structural identifiability of {', '.join(self.unknown)} from "
                 f"{self.output}/{self.input} in {self.model!r}"]
        for name, c in self.coefficients:
            lines.append(f"  {name} = {c}")
        lines.append(f"  rank of the Jacobian: {self.rank} of {len(self.unknown)} "
                     f"(at random points: {', '.join(map(str, self.rank_at_points))})")
        lines.append(f"  identifiable one by one: {', '.join(self.identifiable) or '-'}")
        lines.append(f"  not identifiable: {', '.join(self.unidentifiable) or '-'}")
        lines.append("  identifiable monomials: "
                     + (", ".join(str(c) for c in self.combinations) or "-"))
        return "\n".join(lines)


def tf_coefficients(model: Model, input: Optional[str] = None, output: Optional[str] = None
                    ) -> tuple[tuple[str, sympy.Expr], ...]:
    """The coefficients of ``G(s)`` in lowest terms with a monic denominator.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.structure import tf_coefficients
    >>> g = bg.BondGraph("rl")
    >>> j = bg.One("j")
    >>> g.add(bg.Se("V"), j, bg.R("R"), bg.I("L"))
    >>> for t, h in [("V", j), (j, "R"), (j, "L")]: _ = g.connect(t, h)
    >>> tf_coefficients(bg.derive(g, outputs={"i": bg.flow("L")}))
    (('b0', 1/L), ('a0', R/L))
    """
    tf = model.transfer_function(input, output)
    expr = sympy.cancel(sympy.together(tf.num.as_expr() / tf.den.as_expr()))
    num, den = sympy.fraction(expr)
    pn, pd = sympy.Poly(num, S), sympy.Poly(den, S)
    lead = pd.LC()
    out = []
    for k, c in sorted(((m[0], c) for m, c in pn.terms()), reverse=True):
        out.append((f"b{k}", sympy.factor(sympy.cancel(c / lead))))
    for k, c in sorted(((m[0], c) for m, c in pd.terms()), reverse=True):
        if k == pd.degree():
            continue
        out.append((f"a{k}", sympy.factor(sympy.cancel(c / lead))))
    return tuple(sorted(out, key=lambda t: (t[0][0] != "b", -int(t[0][1:]))))


def _integer_rows(M: sympy.Matrix) -> list[list[int]]:
    rows = []
    for i in range(M.rows):
        r = [sympy.Rational(x) for x in M.row(i)]
        lcm = math.lcm(*[int(x.q) for x in r]) if r else 1
        ints = [int(x * lcm) for x in r]
        g = math.gcd(*ints) or 1
        ints = [v // g for v in ints]
        first = next((v for v in ints if v), 1)
        rows.append([-v for v in ints] if first < 0 else ints)
    return rows


#: largest number of polynomial terms the exact (symbolic) rank of the Jacobian may hold
#: while it eliminates; past it, ``identifiability`` refuses and points to ``exact=False``
EXACT_RANK_BUDGET = 200_000


def _exact_rank(J: sympy.Matrix, at_points: int, model: str) -> int:
    """The rank of ``J`` over the rational functions of the parameters, exactly.

    A rank at a point never exceeds the symbolic one, so a full rank at a
    random point is exact; otherwise fraction-free elimination over flint
    polynomials (:func:`bondgraph.equations.fraction_free.rank_fraction_free`)
    decides, within :data:`EXACT_RANK_BUDGET` terms.
    """
    if at_points == min(J.shape):
        return at_points
    r = rank_fraction_free(J, budget=EXACT_RANK_BUDGET)
    if r is None:           # entries that are not rational functions (a sqrt)
        return DomainMatrix.from_Matrix(J).rank()
    if r == TOO_LARGE:
        raise StructureError(
            f"model {model!r}: the exact rank of the {J.rows} x {J.cols} identifiability "
            f"Jacobian passes {EXACT_RANK_BUDGET} polynomial terms while eliminating (its rank "
            f"at random points is {at_points}); use identifiability(..., exact=False), the rank "
            "at random rational points (the same number with probability one)")
    return int(r)


def identifiability(model: Model, input: Optional[str] = None, output: Optional[str] = None, *,
                    unknown: Optional[Sequence[str]] = None, seed: int = 0,
                    exact: bool = True) -> Identifiability:
    """Which unknown parameters the transfer function ``output/input`` determines.

    Parameters
    ----------
    model : Model
        A linear model.
    input, output : str, optional
        Required when the model has several inputs (outputs).
    unknown : sequence of str, optional
        The parameters to identify (default: every parameter of ``G``); the
        others are known constants.
    seed : int
        Seed of the random rational points of the confirmation.
    exact : bool
        Rank the Jacobian exactly, over the fraction field of the parameters
        (default): full at a random rational point proves it; otherwise a
        fraction-free elimination over python-flint polynomials decides (refused
        past :data:`EXACT_RANK_BUDGET` terms).  False takes the largest exact rank
        at three random rational points instead: the same number with
        probability one.

    Returns
    -------
    Identifiability

    Raises
    ------
    StructureError
        An unknown parameter that ``G`` does not contain, or unknown channels.
    """
    coeffs = tf_coefficients(model, input, output)
    tf_syms = set()
    for _, c in coeffs:
        tf_syms |= c.free_symbols
    by_name = {p.name: p for p in model.parameters}
    if unknown is None:
        theta = sorted(tf_syms, key=lambda s: s.name)
    else:
        theta = []
        for name in unknown:
            if name not in by_name:
                raise StructureError(f"model {model.name!r} has no parameter {name!r}; "
                                     f"parameters: {', '.join(sorted(by_name))}")
            theta.append(by_name[name])
    p = len(theta)
    J = sympy.Matrix([[sympy.cancel(t * sympy.diff(c, t)) for t in theta] for _, c in coeffs]) \
        if coeffs and p else sympy.zeros(len(coeffs), p)
    everything = sorted(tf_syms | set(theta), key=lambda s: s.name)
    points = random_points(everything, max(p, 3), seed=seed)
    ranks = tuple(exact_rank(at_point(J, pt)) for pt in points[:3 if not exact else 2])
    if not (J.rows and J.cols):
        rank = 0
    elif exact:
        rank = _exact_rank(J, max(ranks), model.name)
    else:
        rank = max(ranks)
    # individually identifiable: e_j in the row space at a random point
    Jv = at_point(J, points[0])
    ident = []
    for j, t in enumerate(theta):
        e = sympy.zeros(1, p)
        e[0, j] = 1
        if exact_rank(Jv.col_join(e)) == exact_rank(Jv):
            ident.append(t.name)
    # null directions at several points; identifiable monomials are orthogonal to all of them
    null_rows: list = []
    for pt in points:
        dm = DomainMatrix.from_Matrix(at_point(J, pt)).convert_to(QQ) if J.rows else None
        if dm is None:
            basis = sympy.eye(p)
        else:
            basis = dm.nullspace().to_Matrix()
        null_rows += [basis.row(i) for i in range(basis.rows)]
    Nmat = sympy.Matrix.vstack(*null_rows) if null_rows else sympy.zeros(0, p)
    if Nmat.rows:
        alphas = DomainMatrix.from_Matrix(Nmat).convert_to(QQ).nullspace().to_Matrix()
    else:
        alphas = sympy.eye(p)
    combos = tuple(sympy.Mul(*[t**a for t, a in zip(theta, row)])
                   for row in _integer_rows(alphas)) if p else ()
    names = tuple(t.name for t in theta)
    tf = model.transfer_function(input, output)
    return Identifiability(
        model=model.name, input=tf.input_name, output=tf.output_name, unknown=names,
        coefficients=coeffs, rank=rank, rank_at_points=ranks, identifiable=tuple(ident),
        unidentifiable=tuple(n for n in names if n not in ident), combinations=combos)


#: results of warn_unidentifiable per (model, free, input, output): a fit repeated on one
#: model (a Monte Carlo study) analyses it once; the weak reference tells a reused id apart
_MEMO: dict = {}


class IdentifiabilityWarning(BondGraphWarning):
    """Parameters asked for that the input-output data cannot determine."""


def warn_unidentifiable(model: object, free: Sequence[str], input: str, output: str, *,
                        max_states: int = 8, stacklevel: int = 3) -> Optional[Identifiability]:
    """Warn (:class:`IdentifiabilityWarning`) when ``free`` is not structurally identifiable.

    Used by :func:`bondgraph.identification.greybox_fit` for one input and one
    output.  Models with more than ``max_states`` states, and models the
    analysis cannot handle, are skipped silently (returns None).

    Examples
    --------
    >>> import warnings, bondgraph as bg
    >>> g = bg.BondGraph("rc")
    >>> j = bg.One("j")
    >>> g.add(bg.Se("V"), j, bg.R("R"), bg.C("C"))
    >>> for t, h in [("V", j), (j, "R"), (j, "C")]: _ = g.connect(t, h)
    >>> m = bg.derive(g, outputs={"v": bg.effort("C")})
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     _ = warn_unidentifiable(m, ["R", "C"], "V", "v")
    >>> print(next(x.message for x in w if "identifiable" in str(x.message)))
    free parameters R, C are not all identifiable from v/V: its coefficients fix 1 combination(s) of 2 (rank of the Jacobian); not identifiable one by one: R, C; identifiable monomials: C*R. Fix some of them to known values.
    """
    if not isinstance(model, Model) or len(model.states) > max_states:
        return None
    key = (id(model), tuple(free), input, output)
    hit = _MEMO.get(key)
    if hit is not None and hit[0]() is model:
        res = hit[1]
    else:
        try:
            res = identifiability(model, input, output, unknown=list(free), exact=False)
        except BondGraphError:
            res = None
        if len(_MEMO) >= 64:
            _MEMO.clear()
        _MEMO[key] = (weakref.ref(model), res)
    if res is None:
        return None
    if res.rank < len(res.unknown):
        warnings.warn(IdentifiabilityWarning(
            f"free parameters {', '.join(res.unknown)} are not all identifiable from "
            f"{res.output}/{res.input}: its coefficients fix {res.rank} combination(s) of "
            f"{len(res.unknown)} (rank of the Jacobian); not identifiable one by one: "
            f"{', '.join(res.unidentifiable)}; identifiable monomials: "
            f"{', '.join(str(c) for c in res.combinations) or '-'}. Fix some of them to "
            "known values."), stacklevel=stacklevel)
    return res
