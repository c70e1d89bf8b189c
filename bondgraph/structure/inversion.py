"""Model inversion: the input that makes an output follow a given trajectory.

Causally, inverting a source-sensor pair turns the integral causality along
the shortest causal path between them into derivative causality (Gawthrop's
bicausal bond graph): the ``r`` storage elements on that path (``r`` the
relative degree, :func:`bondgraph.structure.zero_structure`) become
differentiators, so the trajectory must be ``r`` times differentiable, and the
remaining ``n - r`` states form the *zero dynamics*, driven by the output,
whose poles are the invariant zeros.  This module computes the inverse from
the transfer function in lowest terms ``G = N/D`` (``deg D - deg N = r``):

* no zero dynamics (``N`` constant): ``u = D(d/dt) y / N`` exactly, a symbolic
  expression of the trajectory and its derivatives;
* stable zero dynamics (minimum phase at the given values):
  ``D/N = Q + R/N`` with ``Q`` a polynomial (the differentiating part) and
  ``R/N`` proper; ``u = Q(d/dt) y + (R/N) y``, the second term by
  :func:`scipy.signal.lsim`;
* a non-minimum-phase pair is refused with the zeros named, unless
  ``minimum_phase_part=True``: then the zeros in the right half plane are
  mirrored into the left (the inverse of the minimum-phase factor of ``G``,
  whose output differs from ``y`` by an all-pass filter).

Examples
--------
>>> import sympy, bondgraph as bg
>>> from bondgraph.structure import invert
>>> g = bg.BondGraph("mass")
>>> v = bg.One("v")
>>> g.add(bg.Se("F"), v, bg.I("m"))
>>> for a, b in [("F", v), (v, "m")]: _ = g.connect(a, b)
>>> inv = invert(bg.derive(g, outputs={"x": bg.displacement("m")}), bg.t**3)
>>> inv.input_expr, inv.relative_degree
(6*m*t, 2)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Optional

import numpy as np
import scipy.signal
import sympy

from ..parameters import real_value
from ..model import Model
from ..signals import t as T
from ._generic import StructureError
from ._smooth import derivatives
from .zeros import S, zero_structure

__all__ = ["Inversion", "invert"]


@dataclass(frozen=True)
class Inversion:
    """The input that produces a requested output trajectory (immutable).

    Attributes
    ----------
    model, input, output : str
    trajectory : sympy.Expr
        The requested output ``y(t)``.
    relative_degree : int
        Derivatives of ``y`` the input needs (the causal path's storage elements
        put in derivative causality).
    zero_dynamics : int
        Order of the zero dynamics (the number of finite zeros of ``G`` in lowest terms).
    numerator, denominator : sympy.Expr
        ``G = numerator/denominator`` in lowest terms (polynomials in ``s``).
    input_expr : sympy.Expr or None
        ``u(t)`` symbolically when there are no zero dynamics.
    minimum_phase : bool or None
        Zeros all in the open left half plane at ``values`` (None without values
        or without zeros to check).
    mirrored : tuple of complex
        Zeros mirrored into the left half plane (``minimum_phase_part=True``).
    conditions : tuple of str
        The conditions of the inversion, each stated and checked.
    values : tuple of (str, float)
        Parameter values used for the numeric checks (empty when none).
    """

    model: str
    input: str
    output: str
    trajectory: sympy.Expr
    relative_degree: int
    zero_dynamics: int
    numerator: sympy.Expr
    denominator: sympy.Expr
    input_expr: Optional[sympy.Expr]
    minimum_phase: Optional[bool]
    mirrored: tuple
    conditions: tuple[str, ...]
    values: tuple[tuple[str, float], ...]

    def input_at(self, times, values: Optional[Mapping[str, float]] = None) -> np.ndarray:
        """The input at ``times`` (from 0, evenly spaced when there are zero dynamics)."""
        vals = dict(self.values) if values is None else dict(values)
        times = np.asarray(times, dtype=float)
        num = _numeric_poly(self.numerator, vals)
        den = _numeric_poly(self.denominator, vals)
        if self.mirrored:
            roots = np.roots(num)
            roots = np.where(roots.real > 0, -roots.conj(), roots)
            num = np.real_if_close(num[0] * np.poly(roots))
        q, r = np.polydiv(den, num)
        y = sympy.Float(1) * self.trajectory
        out = np.zeros_like(times)
        for k, c in enumerate(q[::-1]):     # Q(d/dt) y
            if c != 0:
                out += c * _lamb(sympy.diff(y, T, k), vals)(times)
        if np.any(np.abs(r) > 1e-14 * max(1.0, np.max(np.abs(den)))):
            yv = _lamb(y, vals)(times)
            _, part, _ = scipy.signal.lsim((r, num), yv, times)
            out += part
        return out

    def __str__(self) -> str:
        lines = [f"inversion of {self.output}/{self.input} in {self.model!r} for "
                 f"{self.output}(t) = {self.trajectory}"]
        lines += [f"  {c}" for c in self.conditions]
        if self.input_expr is not None:
            lines.append(f"  {self.input}(t) = {self.input_expr}")
        return "\n".join(lines)


def _subs(expr: sympy.Expr, vals: Mapping[str, float]) -> dict:
    out = {}
    for s in expr.free_symbols:
        if s in (S, T):
            continue
        if s.name not in vals:
            raise StructureError(f"values: missing parameter {s.name!r} for the inversion")
        out[s] = sympy.Float(real_value(vals[s.name], s.name, "values: "), 30)
    return out


def _numeric_poly(p: sympy.Expr, vals: Mapping[str, float]) -> np.ndarray:
    P = sympy.Poly(p.xreplace(_subs(p, vals)), S)
    return np.array([float(c) for c in P.all_coeffs()])


def _lamb(expr: sympy.Expr, vals: Mapping[str, float]):
    f = sympy.lambdify(T, expr.xreplace(_subs(expr, vals)), "numpy")
    return lambda tt: np.broadcast_to(np.asarray(f(tt), dtype=float), np.shape(tt)).copy()


def invert(model: Model, trajectory: sympy.Expr, *, input: Optional[str] = None,
           output: Optional[str] = None, values: Optional[Mapping[str, float]] = None,
           minimum_phase_part: bool = False) -> Inversion:
    """The input that makes ``output`` follow ``trajectory`` (a sympy expression of ``bg.t``).

    Parameters
    ----------
    model : Model
        A linear model.
    trajectory : sympy.Expr
        ``y(t)``, differentiable at least ``relative_degree`` times.
    input, output : str, optional
        Required when the model has several inputs (outputs).
    values : mapping of str to float, optional
        Parameter values for the minimum-phase check and :meth:`Inversion.input_at`.
    minimum_phase_part : bool
        For a non-minimum-phase pair, invert the minimum-phase factor instead
        of refusing.

    Returns
    -------
    Inversion

    Raises
    ------
    StructureError
        ``G = 0`` (no causal path or cancelling paths), a trajectory that is not
        an expression of ``t``, zero dynamics without ``values``, or a
        non-minimum-phase pair (zeros named) without ``minimum_phase_part``.
    """
    if not isinstance(model, Model):
        raise StructureError(f"model: expected a derived bondgraph Model, got {type(model).__name__}")
    if not isinstance(minimum_phase_part, bool):
        raise StructureError(f"minimum_phase_part: expected True or False, got "
                             f"{type(minimum_phase_part).__name__} {minimum_phase_part!r}")
    if values is not None and not isinstance(values, Mapping):
        raise StructureError(f"values: expected a mapping of parameter name to number, got "
                             f"{type(values).__name__}")
    traj = sympy.sympify(trajectory, strict=True) if isinstance(trajectory, (int, float)) \
        else trajectory
    if not isinstance(traj, sympy.Expr):
        raise StructureError(f"trajectory: expected a sympy expression of bg.t, got "
                             f"{type(trajectory).__name__}")
    z = zero_structure(model, input, output, max_states=0)
    if z.relative_degree is None:
        raise StructureError(f"{z.output}/{z.input} in model {model.name!r}: G(s) = 0 "
                             f"({'no causal path' if not z.path else 'the causal paths cancel'}); "
                             "no input can set this output")
    tf = model.transfer_function(z.input, z.output)
    expr = sympy.cancel(sympy.together(tf.num.as_expr() / tf.den.as_expr()))
    num, den = sympy.fraction(expr)
    pn, pd = sympy.Poly(num, S), sympy.Poly(den, S)
    r = pd.degree() - pn.degree()
    nz = pn.degree()
    conds = [f"relative degree {r} (shortest causal path {' -> '.join(z.path)}): "
             f"{z.output}(t) must be {max(r, 0)} times differentiable"]
    diffs = derivatives(traj, max(r, 0))     # refuses kinks, jumps and nan (Dirac impulses)
    conds[-1] += " (it is)"
    vals = dict(values or {})
    mp: Optional[bool] = None
    mirrored: tuple = ()
    if nz:
        if values is None:
            raise StructureError(f"{z.output}/{z.input} has zero dynamics of order {nz} "
                                 "(finite zeros): give values= to check and integrate them")
        zeros = np.roots(_numeric_poly(pn.as_expr(), vals))
        mp = bool(np.all(zeros.real < 0))
        ztxt = ", ".join(f"{w:.4g}" for w in zeros)
        if mp:
            conds.append(f"zero dynamics of order {nz}, stable: zeros {ztxt} in the left half "
                         "plane (minimum phase)")
        elif not minimum_phase_part:
            raise StructureError(
                f"{z.output}/{z.input} in model {model.name!r} is non-minimum-phase (zeros "
                f"{ztxt}): the exact inverse is unstable; pass minimum_phase_part=True to "
                "invert the minimum-phase factor")
        else:
            mirrored = tuple(complex(w) for w in zeros if w.real >= 0)
            conds.append(f"non-minimum-phase (zeros {ztxt}): inverting the minimum-phase "
                         "factor, the output then differs from the trajectory by an all-pass "
                         "filter")
    else:
        conds.append("no zero dynamics: the input is a combination of the trajectory and "
                     "its derivatives")
    u_expr = None
    if not nz:
        c0 = pn.LC()
        u_expr = sympy.expand(sum(c * diffs[m[0]] for m, c in pd.terms()) / c0)
    return Inversion(model=model.name, input=z.input, output=z.output, trajectory=traj,
                     relative_degree=r, zero_dynamics=nz, numerator=pn.as_expr(),
                     denominator=pd.as_expr(), input_expr=u_expr, minimum_phase=mp,
                     mirrored=mirrored, conditions=tuple(conds),
                     values=tuple(sorted((k, float(v)) for k, v in vals.items())))
