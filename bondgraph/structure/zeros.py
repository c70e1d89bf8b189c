"""Zero structure of an input-output pair: relative degree, finite zeros, collocation.

For a single input ``u`` and output ``y`` of a linear model with ``n`` states:

* the *relative degree* ``r`` (the order of the infinite zero) is the number
  of integrations between ``u`` and ``y``.  Its structural value is the weight
  of a shortest causal path from ``u`` to ``y`` in the signal digraph (each
  storage element crossed adds an integration, a derivative input removes
  one; Bertrand, Sueur and Dauphin-Tanguy); its generic value is the first
  nonzero Markov parameter at random rational parameter points.  Causal
  paths of the same length whose gains cancel make the two differ;
* the number of finite invariant zeros is ``n - r``: the degree of
  ``det [[sI - A, -B], [C, D]] = det(sI - A) G(s)`` (zeros of the Rosenbrock
  system matrix, decoupling zeros included);
* the zeros themselves, symbolically, from that determinant when ``n`` is
  small (``max_states``) and their number at most two;
* whether the pair is *collocated*: ``y`` proportional to the output
  power-conjugate to ``u`` (an ``Se`` and the flow into its bond, an ``Sf``
  and the effort), so that ``u*y`` is the power the source delivers.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.structure import zero_structure
>>> g = bg.BondGraph("mass")
>>> v = bg.One("v")
>>> g.add(bg.Se("F"), v, bg.I("m"))
>>> for t, h in [("F", v), (v, "m")]: _ = g.connect(t, h)
>>> z = zero_structure(bg.derive(g, outputs={"x": bg.displacement("m")}))
>>> z.relative_degree, z.finite_zeros, z.path
(2, 0, ('F', 'p_m', 'x', 'x'))
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Mapping, Optional

import networkx as nx
import numpy as np
import scipy.linalg
import sympy

from ..errors import BondGraphWarning
from ..parameters import real_value
from ..model import Model, derive
from ._generic import LinearForm, StructureError, at_point, linear_form, random_points
from ._paths import signal_digraph

__all__ = ["ZeroStructure", "zero_structure", "collocated", "S"]

#: the Laplace variable of the polynomials returned
S = sympy.Symbol("s")


@dataclass(frozen=True)
class ZeroStructure:
    """Infinite and finite zeros of one input-output pair (immutable).

    Attributes
    ----------
    model, input, output : str
    n : int
        Number of states.
    path : tuple of str
        A shortest causal path from the input to the output (signal digraph);
        ``()`` when none: then ``G(s) = 0``.
    structural_degree : int or None
        Number of integrations along ``path``.
    relative_degree : int or None
        Generic relative degree (degree of the denominator minus that of the
        numerator of ``G``); None when ``G(s) = 0`` for all parameter values.
    finite_zeros : int or None
        Number of finite invariant zeros, ``n - relative_degree``.
    numerator : sympy.Expr or None
        ``det [[sI - A, -B(s)], [C, D(s)]]``, a polynomial in :data:`S` whose roots
        are the invariant zeros (None when not computed: more than
        ``max_states`` states).
    zeros : tuple of sympy.Expr or None
        The invariant zeros symbolically (None when not computed or when more than two).
    """

    model: str
    input: str
    output: str
    n: int
    path: tuple[str, ...]
    structural_degree: Optional[int]
    relative_degree: Optional[int]
    finite_zeros: Optional[int]
    numerator: Optional[sympy.Expr]
    zeros: Optional[tuple]
    _poles_matrix: sympy.Matrix = None  # type: ignore[assignment]
    _system: tuple = ()

    def __hash__(self) -> int:
        return hash((self.model, self.input, self.output, self.n, self.path))

    def zeros_at(self, values: Mapping[str, float]) -> np.ndarray:
        """Numeric invariant zeros at parameter ``values``.

        The roots of :attr:`numerator` when it was computed; otherwise the
        finite generalized eigenvalues of the Rosenbrock pencil
        ``[[A, b], [-c, -d]] - s [[I, 0], [0, 0]]`` (:func:`scipy.linalg.eig`),
        the ``finite_zeros`` of largest ``|beta/alpha|``.
        """
        if self.numerator is not None:
            P = sympy.Poly(self.numerator.xreplace(_subs(self.numerator, values)), S)
            coeffs = [complex(c) for c in P.all_coeffs()]
            return np.roots(coeffs) if len(coeffs) > 1 else np.array([])
        A, b, c, d = self._system
        if any(M.has(S) for M in (b, d)):
            raise StructureError(f"zeros of {self.output}/{self.input} in model {self.model!r}: "
                                 "input derivatives appear; raise max_states to compute them")
        if not self.finite_zeros:
            return np.array([])
        n = A.rows
        top = sympy.Matrix.vstack(sympy.Matrix.hstack(A, b), sympy.Matrix.hstack(-c, -d))
        M = np.array(top.xreplace(_subs(top, values)).evalf(), dtype=complex)
        E = np.zeros_like(M)
        E[:n, :n] = np.eye(n)
        alpha, beta = scipy.linalg.eig(M, E, right=False, homogeneous_eigvals=True)
        order = np.argsort(-np.abs(beta) / np.maximum(np.abs(alpha), 1e-300))
        keep = order[:self.finite_zeros]
        return alpha[keep] / beta[keep]

    def rhp_zeros(self, values: Mapping[str, float], *, tol: float = 1e-9) -> np.ndarray:
        """The zeros at ``values`` in the closed right half plane beyond ``tol`` (relative)."""
        z = self.zeros_at(values)
        scale = max(1.0, float(np.max(np.abs(z), initial=0.0)))
        return z[z.real > tol * scale]

    def poles_at(self, values: Mapping[str, float]) -> np.ndarray:
        """Numeric eigenvalues of ``A`` at parameter ``values``."""
        A = self._poles_matrix
        Av = np.array(A.xreplace(_subs(A, values)).evalf(), dtype=complex)
        return np.linalg.eigvals(Av) if Av.size else np.array([])

    def minimum_phase(self, values: Mapping[str, float], *, tol: float = 1e-9) -> bool:
        """Whether every invariant zero at ``values`` has a negative real part.

        Raises
        ------
        StructureError
            ``tol`` not a finite number >= 0; a value missing, or not a finite
            real number (naming the parameter).
        """
        _tolerance(tol)
        z = self.zeros_at(values)
        return bool(np.all(z.real < -tol * max(1.0, float(np.max(np.abs(z), initial=0.0)))))

    def interlaced(self, values: Mapping[str, float], *, tol: float = 1e-7) -> bool:
        """Whether poles and zeros at ``values`` lie on the imaginary axis and alternate.

        A collocated lossless pair has this property: between two consecutive
        poles (frequencies, counted once with their conjugates) lies one zero.
        """
        _tolerance(tol)
        p, z = self.poles_at(values), self.zeros_at(values)
        scale = max(1.0, float(np.max(np.abs(np.concatenate([p, z])), initial=0.0)))
        if np.any(np.abs(p.real) > tol * scale) or np.any(np.abs(z.real) > tol * scale):
            return False
        wp = np.sort(np.abs(p.imag[p.imag >= -tol * scale]))
        wz = np.sort(np.abs(z.imag[z.imag >= -tol * scale]))
        merged = sorted([(w, "p") for w in wp] + [(w, "z") for w in wz])
        return all(a[1] != b[1] for a, b in zip(merged, merged[1:]))

    def plot(self, values: Mapping[str, float]):
        """Poles and zeros at ``values`` (:func:`bondgraph.structure.plots.plot_pole_zero`)."""
        from .plots import plot_pole_zero

        return plot_pole_zero(self, values)

    def __str__(self) -> str:
        lines = [f"zero structure of {self.output}/{self.input} in {self.model!r} "
                 f"({self.n} states)"]
        if not self.path:
            lines.append("  no causal path from the input to the output: G(s) = 0")
            return "\n".join(lines)
        lines.append(f"  shortest causal path: {' -> '.join(self.path)} "
                     f"({self.structural_degree} integrations)")
        if self.relative_degree is None:
            lines.append("  the causal paths cancel: G(s) = 0 for all parameter values")
            return "\n".join(lines)
        lines.append(f"  relative degree (order of the infinite zero): {self.relative_degree}")
        if self.relative_degree != self.structural_degree:
            lines.append("  (paths of the shortest length cancel; the generic degree is higher)")
        lines.append(f"  finite invariant zeros: {self.finite_zeros}")
        if self.zeros is not None:
            lines.append(f"  zeros: {', '.join(str(z) for z in self.zeros) or '-'}")
        return "\n".join(lines)


def _tolerance(tol: object) -> float:
    if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not 0 <= tol < float("inf"):
        raise StructureError(f"tol: expected a finite number >= 0, got {type(tol).__name__} {tol!r}")
    return float(tol)


def _subs(expr, values: Mapping[str, float]) -> dict:
    if not isinstance(values, Mapping):
        raise StructureError(f"values must be a mapping of parameter name to number; got "
                             f"{type(values).__name__}")
    values = {str(getattr(k, "name", k)): real_value(v, str(getattr(k, "name", k)))
              for k, v in values.items()}       # every value given: finite and real
    syms = {s.name: s for s in expr.free_symbols}
    missing = sorted(n for n in syms if n not in values and n != "s")
    if missing:
        raise StructureError(f"values missing for parameter(s) {', '.join(missing)}")
    return {syms[n]: sympy.Float(values[n], 30) for n in syms if n != "s"}


def _channel(names, wanted, what: str, model: str) -> int:
    if wanted is None:
        if len(names) != 1:
            raise StructureError(f"model {model!r} has {len(names)} {what}s "
                                 f"({', '.join(names)}); name the {what}")
        return 0
    if wanted not in names:
        raise StructureError(f"model {model!r} has no {what} {wanted!r}; {what}s: "
                             f"{', '.join(names) or 'none'}")
    return names.index(wanted)


def _markov_degree(lf: LinearForm, j: int, i: int, points) -> Optional[int]:
    """Generic relative degree from the expansion of G at infinity."""
    n = lf.A.rows
    K = max(len(lf.Bs), len(lf.Ds)) - 1
    best: Optional[int] = None
    for pt in points:
        A = at_point(lf.A, pt)
        C = at_point(lf.C[i, :], pt)
        Bs = [at_point(B[:, j], pt) for B in lf.Bs]
        Ds = [at_point(D[i:i + 1, j:j + 1], pt) for D in lf.Ds]
        # CA^jB_k for j = 0..n+K
        powers = [C]
        for _ in range(n + K + 1):
            powers.append(powers[-1] * A)
        found = None
        for m in range(K, -n - 1, -1):
            c = Ds[m][0, 0] if 0 <= m < len(Ds) else 0
            for k, B in enumerate(Bs):
                jj = k - m - 1
                if jj >= 0 and n:
                    c += (powers[jj] * B)[0, 0]
            if c != 0:
                found = -m
                break
        if found is not None and (best is None or found < best):
            best = found
    return best


def collocated(model: Model, input: str | None = None, output: str | None = None) -> bool:
    """Whether ``output`` is proportional to the output power-conjugate to ``input``.

    The element that introduces the input answers which signal is its
    conjugate (:meth:`bondgraph.Element.collocated_output`: the flow into an
    ``Se``'s bond, the effort of an ``Sf``); the model is derived again with
    that signal as output and the two outputs are compared: their ratio must
    be free of states and inputs.

    Raises
    ------
    StructureError
        Unknown channel names, or an input whose element has no conjugate output.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.structure import collocated
    >>> g = bg.BondGraph("msd")
    >>> v = bg.One("v")
    >>> g.add(bg.Se("F"), v, bg.I("m"), bg.C("k"))
    >>> for t, h in [("F", v), (v, "m"), (v, "k")]: _ = g.connect(t, h)
    >>> m = bg.derive(g, outputs={"v": bg.flow("m"), "x": bg.displacement("k")})
    >>> collocated(m, "F", "v"), collocated(m, "F", "x")
    (True, False)
    """
    lf = linear_form(model)
    u = lf.inputs[_channel(lf.inputs, input, "input", model.name)]
    i = _channel(lf.outputs, output, "output", model.name)
    aug = model.augmented
    owner = [el for el in aug.flat.elements if el.input_name() == u] if aug is not None else []
    conj = owner[0].collocated_output() if owner else None
    if conj is None:
        raise StructureError(f"input {u!r} of model {model.name!r} has no power-conjugate "
                             "output (its element does not answer collocated_output)")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BondGraphWarning)   # already shown by derive
        other = derive(aug, outputs={conj[0]: conj[1]})
    live = set(model.states) | set(model.inputs) | set(model.input_derivatives)
    y, c = model.output_exprs[i], other.output_exprs[0]
    if other.states != model.states:      # a different state set: compare as functions
        return False
    if c == 0 or y == 0:
        return False
    ratio = sympy.cancel(y / c)
    return not (ratio.free_symbols & live)


def zero_structure(model: Model, input: str | None = None, output: str | None = None, *,
                   max_states: int = 6, seed: int = 0) -> ZeroStructure:
    """Relative degree, number of finite zeros, the zeros and collocation of one pair.

    Parameters
    ----------
    model : Model
        A linear model.
    input, output : str, optional
        Required when the model has several inputs (outputs).
    max_states : int
        Compute the numerator polynomial and the zeros symbolically only up to
        this many states.
    seed : int
        Seed of the random rational points of the generic degree.

    Returns
    -------
    ZeroStructure

    Raises
    ------
    StructureError
        A nonlinear model, an unknown or missing channel name.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.structure import zero_structure
    >>> g = bg.BondGraph("two_masses")
    >>> v1, v2, s = bg.One("v1"), bg.One("v2"), bg.Zero("s")
    >>> g.add(bg.Se("F"), v1, v2, s, bg.I("m1"), bg.I("m2"), bg.C("k", stiffness="k"))
    >>> for t, h in [("F", v1), (v1, "m1"), (v1, s), (s, "k"), (s, v2), (v2, "m2")]:
    ...     _ = g.connect(t, h)
    >>> far = zero_structure(bg.derive(g, outputs={"x2": bg.displacement("m2")}))
    >>> far.relative_degree, far.finite_zeros, far.n
    (4, 0, 4)
    >>> near = zero_structure(bg.derive(g, outputs={"x1": bg.displacement("m1")}))
    >>> near.relative_degree, near.zeros
    (2, (-I*sqrt(k)/sqrt(m2), I*sqrt(k)/sqrt(m2)))
    """
    lf = linear_form(model)
    j = _channel(lf.inputs, input, "input", model.name)
    i = _channel(lf.outputs, output, "output", model.name)
    u, y = lf.inputs[j], lf.outputs[i]
    n = lf.A.rows
    G = signal_digraph(lf)
    try:
        path = nx.bellman_ford_path(G, ("u", u), ("y", y), weight="weight")
        sdeg: Optional[int] = nx.path_weight(G, path, "weight")
        names = tuple(node[1] for node in path)
    except nx.NetworkXNoPath:
        sdeg, names = None, ()
    rdeg = _markov_degree(lf, j, i, random_points(lf.parameters, 2, seed=seed)) if names else None
    nz = None if rdeg is None else n - rdeg
    numerator, zeros = None, None
    Bcol = sum((B[:, j] * S**k for k, B in enumerate(lf.Bs)), sympy.zeros(n, 1))
    Dval = sum((D[i, j] * S**k for k, D in enumerate(lf.Ds)), sympy.Integer(0))
    if nz == 0:
        zeros = ()      # no finite zero: nothing to solve (the numerator is a constant)
    if 0 < n <= max_states and rdeg is not None:
        R = sympy.Matrix(sympy.BlockMatrix([[S * sympy.eye(n) - lf.A, -Bcol],
                                            [lf.C[i, :], sympy.Matrix([[Dval]])]]))
        numerator = sympy.factor(sympy.cancel(R.det(method="berkowitz")))
        if nz is not None and 0 < nz <= 2:
            zeros = tuple(sorted(sympy.solve(numerator, S), key=sympy.default_sort_key))
    return ZeroStructure(model=model.name, input=u, output=y, n=n, path=names,
                         structural_degree=sdeg, relative_degree=rdeg, finite_zeros=nz,
                         numerator=numerator, zeros=zeros, _poles_matrix=lf.A,
                         _system=(lf.A, Bcol, lf.C[i, :], sympy.Matrix([[Dval]])))
