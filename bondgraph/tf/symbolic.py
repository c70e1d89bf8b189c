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

from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Any, Iterable, Literal, Mapping, Sequence

import numpy as np
import sympy as sp
from sympy.polys.fields import FracField
from sympy.polys.polyclasses import DMP
from sympy.polys.rings import PolyRing

from .._labels import control_labels
from ..parameters import exact_value, match_values
from ..values import as_expr, as_matrix
from . import _algebra as alg
from ._terms import numeric_sum, poly_terms, symbolic_sum
from .errors import (InvalidOptionError, MissingValueError, ParameterValueError, ShapeError,
                     SingularPencilError, UnknownSignalError)
from .latex import numeric_tf_latex, poly_latex, tf_latex
from .tables import PoleZeroTable, pole_zero_table

__all__ = ["SymbolicTF", "NumericTF", "TransferMatrix", "NumericTransferMatrix",
           "transfer_function", "transfer_matrix", "Normalize", "NORMALIZATIONS"]

Normalize = Literal["monic", "as-derived", "leading-one-denominator"]
NORMALIZATIONS = ("monic", "as-derived", "leading-one-denominator")
METHODS = ("auto", "laplace", "bareiss", "berkowitz")


# =========================================================================== helpers
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


def _resolve(sel, names: tuple[str, ...], what: str) -> int:
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


def _to_fraction(v, key) -> Fraction:
    """Exact rational value of a parameter (floats read as their decimal repr)."""
    e = exact_value(v, str(key))
    if e.is_Rational:
        return Fraction(int(e.p), int(e.q))
    return Fraction(str(sp.N(e, 40)))


# ============================================================ conversion to sympy
class _Converter:
    """Turn normalized ring polynomials (in s and parameters) into sympy Polys."""

    def __init__(self, ring: alg.Ring, params: Sequence[sp.Expr]):
        self.ring = ring
        self.k = len(params)
        self.q = ring.nvars - 1 - self.k
        if self.k:
            self.ZZr = PolyRing(tuple(params), sp.ZZ)
            self.QQr = PolyRing(tuple(params), sp.QQ)
            self.FF = FracField(tuple(params), sp.ZZ)

    def ring_of(self, d: dict[tuple, int | Fraction]):
        """Ring element of one coefficient (a dict of parameter exponents)."""
        pad = (0,) * self.q
        return self.ring.from_terms({(0,) + e + pad: c for e, c in d.items()})

    def dict_of(self, p) -> dict[tuple, int | Fraction]:
        k = self.k
        return {e[1:1 + k]: c for e, c in self.ring.terms(p)}

    # -- building sympy Polys ----------------------------------------------------
    def poly(self, coeffs: dict[int, dict[tuple, Fraction]], s: sp.Symbol) -> sp.Poly:
        """Poly with polynomial coefficients (domain ZZ[...] or QQ[...])."""
        if not coeffs:
            return sp.Poly(0, s, domain=sp.ZZ)
        integer = all(c.denominator == 1 for d in coeffs.values() for c in d.values())
        deg = max(coeffs)
        if self.k:
            R = self.ZZr if integer else self.QQr
            K = R.to_domain()
            G = R.domain
            rep = [R.from_dict({e: G(c.numerator) if integer else G(c.numerator, c.denominator)
                                for e, c in coeffs.get(d, {}).items()})
                   for d in range(deg, -1, -1)]
        else:
            K = sp.ZZ if integer else sp.QQ
            rep = []
            for d in range(deg, -1, -1):
                c = coeffs.get(d, {}).get((), 0)
                rep.append(K(int(c.numerator)) if integer else
                           K(int(c.numerator), int(c.denominator)))
        return sp.Poly.new(DMP.from_list(rep, 0, K), s)

    def frac_poly(self, fracs: dict[int, tuple[dict, dict]], s: sp.Symbol) -> sp.Poly:
        """Poly whose coefficients are reduced fractions ``(num, den)`` of dicts."""
        if not fracs:
            return sp.Poly(0, s, domain=sp.ZZ)
        if all(list(den) == [(0,) * self.k] and den[(0,) * self.k] == 1
               for _, den in fracs.values()):
            return self.poly({d: num for d, (num, _) in fracs.items()}, s)
        deg = max(fracs)
        if not self.k:  # pragma: no cover - constant denominators handled above
            raise AssertionError
        F = self.FF
        K = F.to_domain()
        R = F.ring
        rep = []
        for d in range(deg, -1, -1):
            if d not in fracs:
                rep.append(K.zero)
                continue
            num, den = _integer_pair(*fracs[d])
            rep.append(F.raw_new(R.from_dict({e: sp.ZZ(int(c)) for e, c in num.items()}),
                                 R.from_dict({e: sp.ZZ(int(c)) for e, c in den.items()})))
        return sp.Poly.new(DMP.from_list(rep, 0, K), s)


def _lcm(a: int, b: int) -> int:
    from math import gcd
    return a // gcd(a, b) * b


def _integer_pair(num: dict, den: dict) -> tuple[dict, dict]:
    """Scale ``num/den`` to integer coefficients, coprime contents, den sign +."""
    from math import gcd
    L = 1
    for d in (num, den):
        for c in d.values():
            L = _lcm(L, c.denominator)
    num = {e: c * L for e, c in num.items()}
    den = {e: c * L for e, c in den.items()}
    g = 0
    for d in (num, den):
        for c in d.values():
            g = gcd(g, int(c))
    lead = den[max(den)]
    if lead < 0:
        g = -g
    return ({e: int(c) // g for e, c in num.items()}, {e: int(c) // g for e, c in den.items()})


def _lead_sign(d: dict) -> int:
    return 1 if d[max(d)] > 0 else -1


def _content(dicts: Iterable[dict]) -> Fraction:
    """Positive rational content: gcd of numerators / lcm of denominators."""
    from math import gcd
    g, L = 0, 1
    for d in dicts:
        for c in d.values():
            g = gcd(g, c.numerator)
            L = _lcm(L, c.denominator)
    return Fraction(g, L) if g else Fraction(1)


def _scale(sd: dict, c: Fraction) -> dict:
    return {k: {e: x / c for e, x in v.items()} for k, v in sd.items()}


def _normalize(converter: _Converter, dd: dict, nds: Sequence[dict], normalize: str,
               s: sp.Symbol) -> tuple[sp.Poly, list[sp.Poly]]:
    """Scale the s-dicts ``dd`` (denominator) and ``nds`` (numerators) by one
    common factor as ``normalize`` says; return sympy Polys."""
    ring = converter.ring
    top = max(dd)
    if normalize == "as-derived":
        c = _content(dd.values()) * _lead_sign(dd[top])
        return converter.poly(_scale(dd, c), s), [converter.poly(_scale(nd, c), s)
                                                  for nd in nds]
    pivot = dd[top] if normalize == "monic" else dd[min(dd)]
    if len(pivot) == 1 and not any(next(iter(pivot))):
        c = Fraction(next(iter(pivot.values())))
        return converter.poly(_scale(dd, c), s), [converter.poly(_scale(nd, c), s)
                                                  for nd in nds]
    if len(pivot) == 1:  # a monomial: gcds are monomials, no ring arithmetic needed
        (pe, pc), = pivot.items()

        def reduce(coeffs):
            out = {}
            for k, v in coeffs.items():
                g = tuple(min([pe[i]] + [e[i] for e in v]) for i in range(len(pe)))
                a = {tuple(x - y for x, y in zip(e, g)): c for e, c in v.items()}
                out[k] = (a, {tuple(x - y for x, y in zip(pe, g)): pc})
            return out
    else:
        pivot_ring = converter.ring_of(pivot)

        def reduce(coeffs):
            out = {}
            for k, v in coeffs.items():
                p = converter.ring_of(v)
                g = ring.gcd(p, pivot_ring)
                out[k] = (converter.dict_of(ring.exquo(p, g)),
                          converter.dict_of(ring.exquo(pivot_ring, g)))
            return out

    return (converter.frac_poly(reduce(dd), s),
            [converter.frac_poly(reduce(nd), s) for nd in nds])


# ======================================================================== numeric
def _strip(coeffs: Sequence[float]) -> tuple[float, ...]:
    coeffs = tuple(float(c) for c in coeffs)
    k = 0
    while k < len(coeffs) - 1 and coeffs[k] == 0.0:
        k += 1
    return coeffs[k:] if coeffs else (0.0,)


@dataclass(frozen=True)
class NumericTF:
    """A transfer function with float coefficients (highest power first).

    Coefficients that vanish symbolically are exactly ``0.0``.

    Examples
    --------
    >>> G = NumericTF((2.0,), (1.0, 3.0, 2.0), "u", "y")
    >>> G.poles()
    array([-2., -1.])
    >>> print(G)
    y/u =
          2
    -------------
    s^2 + 3 s + 2
    """

    num: tuple[float, ...]
    den: tuple[float, ...]
    input_name: str = "u"
    output_name: str = "y"
    s_name: str = "s"

    def __post_init__(self):
        object.__setattr__(self, "num", _strip(self.num))
        object.__setattr__(self, "den", _strip(self.den))
        if all(c == 0.0 for c in self.den):
            raise InvalidOptionError("den: expected a nonzero polynomial, got all zeros")

    def poles(self) -> np.ndarray:
        """Roots of the denominator (``numpy.roots``)."""
        return np.roots(self.den) if len(self.den) > 1 else np.array([])

    def zeros(self) -> np.ndarray:
        """Roots of the numerator (``numpy.roots``); none for a zero TF."""
        if all(c == 0.0 for c in self.num) or len(self.num) < 2:
            return np.array([])
        return np.roots(self.num)

    @property
    def gain(self) -> float:
        """Ratio of leading coefficients (the ``k`` of the zero-pole-gain form)."""
        return self.num[0] / self.den[0]

    def dc_gain(self) -> float:
        """``G(0)``; ``inf`` (signed) when ``s = 0`` is a pole."""
        n, d = self.num[-1], self.den[-1]
        if d == 0.0:
            return float("nan") if n == 0.0 else float(np.copysign(np.inf, n))
        return n / d

    def __call__(self, s: complex) -> complex:
        """Evaluate ``G(s)`` at a (complex) point."""
        return complex(np.polyval(self.num, s) / np.polyval(self.den, s))

    def table(self, *, digits: int = 4) -> PoleZeroTable:
        """Pole/zero table (natural frequencies in rad/s and Hz, damping)."""
        return pole_zero_table(self.num, self.den, digits=digits)

    def to_control(self, *, name: str | None = None):
        """``control.TransferFunction`` with the input and output names.

        python-control forbids dots in names: ``hub.e_in`` becomes ``hub_e_in``.
        """
        import control

        return control.tf(list(self.num), list(self.den),
                          inputs=control_labels([self.input_name]),
                          outputs=control_labels([self.output_name]), name=name)

    def to_latex(self, *, form: str = "coefficients", digits: int = 4,
                 lhs: bool | str = True, zeta_omega: bool = False) -> str:
        """LaTeX in ``'coefficients'`` or ``'factored'`` form.

        Examples
        --------
        >>> NumericTF((1.0,), (1.0, 0.0, 4.0)).to_latex(form="factored", lhs=False)
        '\\\\frac{1}{\\\\left(s^{2} + 4\\\\right)}'
        """
        return numeric_tf_latex(self.num, self.den, input_name=self.input_name,
                                output_name=self.output_name, s=self.s_name, form=form,
                                digits=digits, lhs=lhs, zeta_omega=zeta_omega)

    def _repr_latex_(self) -> str:
        return "$\\displaystyle " + self.to_latex() + "$"

    def __str__(self) -> str:
        num = _poly_text(self.num, self.s_name)
        den = _poly_text(self.den, self.s_name)
        w = max(len(num), len(den))
        return (f"{self.output_name}/{self.input_name} =\n{num.center(w).rstrip()}\n"
                f"{'-' * w}\n{den.center(w).rstrip()}")


def _poly_text(coeffs: Sequence[float], s: str) -> str:
    return numeric_sum(poly_terms(coeffs, s, power="{}^{}"), lambda x: f"{x:.4g}")


# ======================================================================= symbolic
def _eval_coeff(c, dom, values: list[Fraction]) -> Fraction:
    """Exact value of one Poly coefficient (domain element) at ``values``."""
    if dom.is_ZZ or dom.is_QQ:
        return Fraction(int(dom.numer(c)), int(dom.denom(c)))
    if dom.is_PolynomialRing:
        return _eval_ring_element(c, values)
    num = _eval_ring_element(c.numer, values)
    den = _eval_ring_element(c.denom, values)
    if den == 0:
        raise MissingValueError(
            f"values: a coefficient's denominator {c.denom.as_expr()} vanishes at the "
            f"given values; use normalize='as-derived'")
    return num / den


def _eval_ring_element(p, values: list[Fraction]) -> Fraction:
    dom = p.ring.domain
    total = Fraction(0)
    powers: dict[tuple[int, int], Fraction] = {}
    for exps, c in p.items():
        term = Fraction(int(dom.numer(c)), int(dom.denom(c)))
        for i, e in enumerate(exps):
            if e:
                key = (i, e)
                if key not in powers:
                    powers[key] = values[i] ** e
                term *= powers[key]
        total += term
    return total


def _poly_values(P: sp.Poly, gens: tuple[sp.Expr, ...], values: Mapping) -> list[float]:
    dom = P.domain
    if dom.is_ZZ or dom.is_QQ:
        vals = []
    else:
        dgens = dom.symbols if hasattr(dom, "symbols") else dom.gens
        vals = [values[g] for g in dgens]
    return [float(_eval_coeff(c, dom, vals)) for c in P.rep.to_list()] or [0.0]


def _domain_gens(P: sp.Poly) -> tuple[sp.Expr, ...]:
    dom = P.domain
    if dom.is_ZZ or dom.is_QQ:
        return ()
    return tuple(dom.symbols if hasattr(dom, "symbols") else dom.gens)


def _value_map(gens: Sequence[sp.Expr], values: Mapping | None,
               known: Sequence[str] = ()) -> dict:
    """Exact value of each domain generator, by the package's parameter policy."""
    params = sorted(set().union(*(g.free_symbols for g in gens)) if gens else set(),
                    key=lambda x: x.name)
    given = match_values(params, values, known=known)
    exact = {p: exact_value(v, p.name) for p, v in given.items()}
    return {g: _to_fraction(g.xreplace(exact), g) for g in gens}


def _poly_str(coeffs: Sequence[sp.Expr], s: sp.Symbol) -> str:
    return symbolic_sum(poly_terms(coeffs, str(s), power="{}**{}"), text=str, group="({})*{}",
                        product="{}*{}")


@dataclass(frozen=True)
class SymbolicTF:
    """Transfer function ``num(s)/den(s)`` with symbolic coefficients.

    ``num`` and ``den`` are sympy ``Poly`` in ``s`` whose coefficients are
    polynomials (or, for ``normalize='monic'``, rational functions) of the
    parameters.  Built by :func:`transfer_function`.

    Examples
    --------
    >>> import sympy as sp
    >>> a, b, s = sp.symbols("a b s")
    >>> G = SymbolicTF(sp.Poly(1, s), sp.Poly(a*s**2 + b*s, s), "E_in", "Theta")
    >>> G.den_coeffs
    (a, b, 0)
    >>> G.to_latex()
    '\\\\frac{\\\\Theta(s)}{E_{in}(s)} = \\\\frac{1}{a s^{2} + b s}'
    >>> G.subs({a: 2, b: 4}).poles()
    array([-2.,  0.])
    """

    num: sp.Poly
    den: sp.Poly
    input_name: str = "u"
    output_name: str = "y"
    #: names of every parameter of the model definition (see :mod:`bondgraph.parameters`)
    known_parameters: tuple[str, ...] = field(default=(), compare=False, repr=False)

    def __post_init__(self):
        for label in ("num", "den"):
            P = getattr(self, label)
            if not isinstance(P, sp.Poly) or len(P.gens) != 1:
                raise InvalidOptionError(f"{label}: expected a univariate sympy Poly, "
                                         f"got {P!r}")
        if self.num.gen != self.den.gen:
            raise InvalidOptionError(f"num, den: expected the same variable, got "
                                     f"{self.num.gen} and {self.den.gen}")
        if self.den.is_zero:
            raise SingularPencilError("den: expected a nonzero polynomial, got 0")

    @classmethod
    def from_expr(cls, expr, s: sp.Symbol | None = None, *, input_name: str = "u",
                  output_name: str = "y", normalize: Normalize = "monic",
                  cancel: bool = True) -> "SymbolicTF":
        """A transfer function from a rational expression in ``s``.

        Examples
        --------
        >>> import sympy as sp
        >>> K, tau, s = sp.symbols("K tau s", positive=True)
        >>> SymbolicTF.from_expr(K/(tau*s + 1), s).expr
        K/(tau*(s + 1/tau))
        >>> SymbolicTF.from_expr(K/(tau*s + 1), s, normalize="as-derived").den_coeffs
        (tau, 1)
        """
        _check_options(normalize, "auto")
        s = sp.Symbol("s") if s is None else s
        expr = as_expr(expr, what="expr", error=InvalidOptionError)
        if not isinstance(s, sp.Symbol):
            raise InvalidOptionError(f"s: expected a sympy Symbol, got {type(s).__name__} {s!r}")
        return _tf_from_exprs(expr, sp.Integer(1), s, input_name, output_name,
                              normalize, cancel=cancel)

    # -- views --------------------------------------------------------------------
    @property
    def s(self) -> sp.Symbol:
        """The Laplace variable."""
        return self.num.gen

    @property
    def num_coeffs(self) -> tuple[sp.Expr, ...]:
        """Numerator coefficients, highest power of ``s`` first."""
        return tuple(self.num.all_coeffs())

    @property
    def den_coeffs(self) -> tuple[sp.Expr, ...]:
        """Denominator coefficients, highest power of ``s`` first."""
        return tuple(self.den.all_coeffs())

    @property
    def expr(self) -> sp.Expr:
        """``num/den`` as a sympy expression."""
        return self.num.as_expr() / self.den.as_expr()

    @property
    def order(self) -> int:
        """Degree of the denominator."""
        return self.den.degree()

    @property
    def parameters(self) -> tuple[sp.Symbol, ...]:
        """Free symbols of the coefficients, sorted by name."""
        syms = set()
        for c in self.num_coeffs + self.den_coeffs:
            syms |= c.free_symbols
        return tuple(sorted(syms, key=lambda x: x.name))

    @property
    def is_proper(self) -> bool:
        """``deg num <= deg den``; False for input-derivative feedthrough.

        Examples
        --------
        >>> import sympy as sp
        >>> m, b = sp.symbols("m b", positive=True)
        >>> G = transfer_function(sp.zeros(0, 0), sp.zeros(0, 1), sp.zeros(1, 0),
        ...                       [[m*sp.Symbol("s") + b]])      # F = (m s + b) v
        >>> G.expr, G.is_proper, G.subs({"m": 2, "b": 3})(1j)
        (b + m*s, False, (3+2j))
        """
        return self.num.is_zero or self.num.degree() <= self.den.degree()

    # -- numeric --------------------------------------------------------------------
    def subs(self, values: Mapping | None = None, *, partial: bool = False):
        """Numeric transfer function for parameter ``values``.

        ``values`` maps symbols or their names to numbers, matched by the
        package-wide policy (:mod:`bondgraph.parameters`): an unknown or
        misspelled name is an error listing the valid ones; names of the
        model definition that this transfer function does not use are
        ignored.  Evaluation is exact (floats are read as their decimal
        representation), so coefficients that vanish, symbolically or at
        these values, are exactly ``0.0``.

        Parameters
        ----------
        values : mapping of parameter name (or Symbol) to number
        partial : bool, optional
            With ``True``, parameters may be left without a value and the
            result is a :class:`SymbolicTF` with the given values substituted
            exactly; with ``False`` (default) every parameter needs a value
            and the result is a :class:`NumericTF`.

        Raises
        ------
        ParameterValueError
            Unknown name or a value that is not a finite real number;
            :class:`MissingValueError` if a parameter has no value.

        Examples
        --------
        >>> import sympy as sp
        >>> m, b, s = sp.symbols("m b s")
        >>> G = SymbolicTF.from_expr(1/(m*s + b), s, normalize="as-derived")
        >>> G.subs({"m": 2, "b": 0.5}).den
        (2.0, 0.5)
        >>> G.subs({"m": 2}, partial=True).expr
        1/(b + 2*s)
        >>> G.subs({"mm": 2, "b": 1})
        Traceback (most recent call last):
        ...
        bondgraph.errors.ParameterValueError: unknown parameter 'mm' (did you mean 'm'?); missing m. Valid names: b, m
        """
        if partial:
            params = sorted((self.num.as_expr().free_symbols | self.den.as_expr().free_symbols)
                            - {self.s}, key=lambda x: x.name)
            given = match_values(params, values, known=self.known_parameters, partial=True)
            exact = {p: exact_value(v, p.name) for p, v in given.items()}
            return replace(self, num=sp.Poly(self.num.as_expr().xreplace(exact), self.s),
                           den=sp.Poly(self.den.as_expr().xreplace(exact), self.s))
        gens = tuple(dict.fromkeys(_domain_gens(self.num) + _domain_gens(self.den)))
        vm = _value_map(gens, values, self.known_parameters)
        return NumericTF(tuple(_poly_values(self.num, gens, vm)),
                         tuple(_poly_values(self.den, gens, vm)),
                         self.input_name, self.output_name, str(self.s))

    def poles(self, values: Mapping | None = None) -> np.ndarray:
        """Poles (numerically, after :meth:`subs`)."""
        return self.subs(values).poles()

    def zeros(self, values: Mapping | None = None) -> np.ndarray:
        """Zeros (numerically, after :meth:`subs`)."""
        return self.subs(values).zeros()

    def table(self, values: Mapping | None = None, *, digits: int = 4) -> PoleZeroTable:
        """Pole/zero table after :meth:`subs`."""
        return self.subs(values).table(digits=digits)

    def to_control(self, values: Mapping | None = None, *, name: str | None = None):
        """``control.TransferFunction`` (after :meth:`subs`), with names."""
        return self.subs(values).to_control(name=name)

    # -- printing -------------------------------------------------------------------
    def to_latex(self, *, form: str = "coefficients", lhs: bool | str = True,
                 num_letter: str = "a", den_letter: str = "b") -> str:
        """LaTeX; ``form='coefficients'`` or ``'named'`` (see :func:`tf_latex`)."""
        return tf_latex(self.num_coeffs, self.den_coeffs, input_name=self.input_name,
                        output_name=self.output_name, s=sp.latex(self.s), form=form,
                        lhs=lhs, num_letter=num_letter, den_letter=den_letter)

    def _repr_latex_(self) -> str:
        return "$\\displaystyle " + self.to_latex() + "$"

    def __str__(self) -> str:
        num = _poly_str(self.num_coeffs, self.s)
        den = _poly_str(self.den_coeffs, self.s)
        if den == "1":
            return f"{self.output_name}/{self.input_name} = {num}"
        return f"{self.output_name}/{self.input_name} = ({num})/({den})"


# ============================================================ transfer matrices
@dataclass(frozen=True)
class NumericTransferMatrix:
    """All numeric entries ``nums[i][j](s) / den(s)`` sharing one denominator.

    Returned by :meth:`TransferMatrix.subs`; coefficients are highest power
    first.  Index ``[output, input]`` (names or indices) for one entry.

    Examples
    --------
    >>> import sympy as sp
    >>> k, m = sp.symbols("k m", positive=True)
    >>> G = transfer_matrix(sp.Matrix([[0, 1/m], [-k, 0]]), sp.eye(2), sp.eye(2), None,
    ...                     input_names=["f_q", "F"], output_names=["q", "p"])
    >>> N = G.subs({"k": 4.0, "m": 1.0})
    >>> N.den, N.nums[0]
    ((1.0, 0.0, 4.0), ((1.0, 0.0), (1.0,)))
    >>> N["q", "F"]
    NumericTF(num=(1.0,), den=(1.0, 0.0, 4.0), input_name='F', output_name='q', s_name='s')
    >>> sorted(N.poles().imag.round(12).tolist()), N.to_control().input_labels
    ([-2.0, 2.0], ['f_q', 'F'])
    """

    nums: tuple[tuple[tuple[float, ...], ...], ...]
    den: tuple[float, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    s_name: str = "s"

    def __getitem__(self, key) -> NumericTF:
        out, inp = key
        i = _resolve(out, self.output_names, "output")
        j = _resolve(inp, self.input_names, "input")
        return NumericTF(self.nums[i][j], self.den, self.input_names[j],
                         self.output_names[i], self.s_name)

    def poles(self) -> np.ndarray:
        """Roots of the shared denominator."""
        return np.roots(_strip(self.den)) if len(_strip(self.den)) > 1 else np.array([])

    def to_control(self, *, name: str | None = None):
        """MIMO ``control.TransferFunction`` with input and output names."""
        import control

        num = [[list(_strip(n)) for n in row] for row in self.nums]
        den = [[list(_strip(self.den)) for _ in row] for row in self.nums]
        return control.tf(num, den, inputs=control_labels(self.input_names),
                          outputs=control_labels(self.output_names), name=name)


@dataclass(frozen=True)
class TransferMatrix:
    """``G(s)`` for all output/input pairs over the shared ``det(sE - A)``.

    ``nums[i][j]`` is the numerator from input ``j`` to output ``i``; the
    entries are not individually cancelled.  Indexing ``G[output, input]``
    (names or indices) returns the cancelled, normalized :class:`SymbolicTF`.

    Examples
    --------
    >>> import sympy as sp
    >>> k, m = sp.symbols("k m", positive=True)
    >>> G = transfer_matrix(sp.Matrix([[0, 1/m], [-k, 0]]), sp.eye(2), sp.eye(2), None,
    ...                     input_names=["f_q", "F"], output_names=["q", "p"])
    >>> G.den_coeffs
    (1, 0, k/m)
    >>> G["q", "F"].num_coeffs, G["q", "F"].den_coeffs
    ((1/m,), (1, 0, k/m))
    """

    nums: tuple[tuple[sp.Poly, ...], ...]
    den: sp.Poly
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    normalize: str = "monic"
    #: names of every parameter of the model definition (see :mod:`bondgraph.parameters`)
    known_parameters: tuple[str, ...] = field(default=(), compare=False, repr=False)
    #: exact ring data (converter, den s-dict, numerator s-dicts) for fast entries
    _raw: Any = field(default=None, compare=False, repr=False, hash=False)

    @property
    def shape(self) -> tuple[int, int]:
        return (len(self.output_names), len(self.input_names))

    @property
    def s(self) -> sp.Symbol:
        return self.den.gen

    @property
    def den_coeffs(self) -> tuple[sp.Expr, ...]:
        return tuple(self.den.all_coeffs())

    @property
    def expr(self) -> sp.ImmutableMatrix:
        """The matrix of ``num_ij/den`` expressions (uncancelled)."""
        d = self.den.as_expr()
        return sp.ImmutableMatrix([[n.as_expr() / d for n in row] for row in self.nums])

    def __getitem__(self, key) -> SymbolicTF:
        if not (isinstance(key, tuple) and len(key) == 2):
            raise UnknownSignalError(f"key: expected (output, input), got {key!r}")
        out, inp = key
        i = _resolve(out, self.output_names, "output")
        j = _resolve(inp, self.input_names, "input")
        if self._raw is not None:
            conv, dd, nds = self._raw
            G = _entry(conv, nds[i][j], dd, self.s, self.input_names[j], self.output_names[i],
                       self.normalize, cancel=True)
        else:
            G = _cancel_pair(self.nums[i][j], self.den, self.input_names[j],
                             self.output_names[i], self.normalize)
        return replace(G, known_parameters=self.known_parameters)

    def to_latex(self, *, lhs: bool | str = True) -> str:
        r"""``G(s) = \frac{1}{den(s)} [num_ij(s)]`` (rows: outputs, columns: inputs).

        Examples
        --------
        >>> import sympy as sp
        >>> a = sp.Symbol("a", positive=True)
        >>> transfer_matrix([[-a]], [[1, 2]], [[1]], None).to_latex()
        '\\mathbf{G}(s) = \\frac{1}{s + a} \\left[\\begin{matrix}1 & 2\\end{matrix}\\right]'
        """
        sl = sp.latex(self.s)
        rows = " \\\\ ".join(" & ".join(poly_latex(n.all_coeffs(), sl) for n in row)
                               for row in self.nums)
        body = (f"\\frac{{1}}{{{poly_latex(self.den_coeffs, sl)}}} "
                f"\\left[\\begin{{matrix}}{rows}\\end{{matrix}}\\right]")
        if lhs is True:
            return f"\\mathbf{{G}}({sl}) = {body}"
        return f"{lhs} = {body}" if lhs else body

    def _repr_latex_(self) -> str:
        return "$\\displaystyle " + self.to_latex() + "$"

    def subs(self, values: Mapping | None = None) -> NumericTransferMatrix:
        """Numeric matrix (uncancelled entries over the shared denominator)."""
        gen_set = set(_domain_gens(self.den))
        for row in self.nums:
            for n in row:
                gen_set |= set(_domain_gens(n))
        gens = tuple(sorted(gen_set, key=sp.default_sort_key))
        vm = _value_map(gens, values, self.known_parameters)
        nums = tuple(tuple(tuple(_poly_values(n, gens, vm)) for n in row) for row in self.nums)
        return NumericTransferMatrix(nums, tuple(_poly_values(self.den, gens, vm)),
                                     self.input_names, self.output_names, str(self.s))

    def to_control(self, values: Mapping | None = None, *, name: str | None = None):
        """MIMO ``control.TransferFunction`` after :meth:`subs`."""
        return self.subs(values).to_control(name=name)


def _cancel_pair(num: sp.Poly, den: sp.Poly, input_name: str, output_name: str,
                 normalize: str) -> SymbolicTF:
    """Cancel and renormalize one entry of a :class:`TransferMatrix`."""
    return _tf_from_exprs(num.as_expr(), den.as_expr(), den.gen, input_name, output_name,
                          normalize, cancel=True)


def _tf_from_exprs(num: sp.Expr, den: sp.Expr, s: sp.Symbol, input_name: str,
                   output_name: str, normalize: str, *, cancel: bool = True,
                   backend: str | None = None) -> SymbolicTF:
    n, d = sp.fraction(sp.together(sp.sympify(num, strict=True) / sp.sympify(den, strict=True)))
    if d == 0:
        raise SingularPencilError("den: expected a nonzero expression, got 0")
    ring, params, (pn, pd) = alg.polys_from_exprs([n, d], s, backend=backend)
    k = len(params)
    pn, pd = alg.to_sdict(pn, ring, k), alg.to_sdict(pd, ring, k)
    return _entry(_Converter(ring, params), pn, pd, s, input_name, output_name, normalize,
                  cancel=cancel)


def _entry(conv: _Converter, num: dict, den: dict, s: sp.Symbol, input_name: str,
           output_name: str, normalize: str, *, cancel: bool) -> SymbolicTF:
    """One transfer function from ring s-dicts: optionally cancelled, then normalized."""
    if cancel:
        num, den = alg.cancel_common(num, den, conv.ring, conv.k)
    Pd, (Pn,) = _normalize(conv, den, [num], normalize, s)
    return SymbolicTF(Pn, Pd, input_name, output_name)


# ================================================================== entry points
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


def _compute(A, B, C, D, E, s, method, backend):
    enc = alg.encode_system(A, B, C, D, E, s, backend=backend)
    ring = enc.ring
    p, m = C.shape[0], B.shape[1]
    if method == "berkowitz":
        if E is not None:
            raise InvalidOptionError("method: 'berkowitz' (DomainMatrix.charpoly) needs "
                                     "E = I; got a descriptor E; use method='auto'")
        den, nums = alg.charpoly_berkowitz(enc)
    else:
        pencil = enc.pencil()
        den = alg.determinant(pencil, ring, method=method)
        if ring.is_zero(den):
            raise SingularPencilError("E, A: det(sE - A) is identically zero (singular "
                                      "pencil); the system has no transfer function")
        nums = [[alg.determinant(enc.bordered(pencil, i, j), ring, method=method)
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
                      backend: str | None = None) -> SymbolicTF:
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

    Returns
    -------
    SymbolicTF

    Raises
    ------
    ShapeError, UnknownSignalError, SingularPencilError, MatrixEntryError,
    InvalidOptionError
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
    j = _resolve(input, ins, "input")
    i = _resolve(output, outs, "output")
    enc, den, nums = _compute(A, B[:, j], C[i, :], D[i, j:j + 1], E, s, method, backend)
    return _entry(_Converter(enc.ring, enc.params), nums[0][0], den, s, ins[j], outs[i],
                  normalize, cancel=cancel)


def transfer_matrix(A, B, C, D=None, *, E=None, input_names: Sequence[str] | None = None,
                    output_names: Sequence[str] | None = None, s: sp.Symbol | None = None,
                    normalize: Normalize = "monic", method: str = "auto",
                    backend: str | None = None) -> TransferMatrix:
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
    enc, den, nums = _compute(A, B, C, D, E, s, method, backend)
    conv = _Converter(enc.ring, enc.params)
    flat = [x for row in nums for x in row]
    Pd, Pns = _normalize(conv, den, flat, normalize, s)
    m = len(ins)
    rows = tuple(tuple(Pns[i * m:(i + 1) * m]) for i in range(len(outs)))
    raw = (conv, den, tuple(tuple(r) for r in nums))
    return TransferMatrix(rows, Pd, ins, outs, normalize, _raw=raw)

