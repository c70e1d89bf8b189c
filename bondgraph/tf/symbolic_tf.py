"""Single-input single-output symbolic transfer functions: :class:`SymbolicTF`.

A :class:`SymbolicTF` holds ``num(s)/den(s)`` as sympy ``Poly`` objects in
``s`` whose coefficients are polynomials (or rational functions) of the
parameters; :meth:`SymbolicTF.subs` evaluates them exactly
(:mod:`bondgraph.tf._exact`) into a :class:`~bondgraph.tf.numeric_tf.NumericTF`.
The entry points building one from state-space matrices are in
:mod:`bondgraph.tf.symbolic`.

Examples
--------
>>> import sympy as sp
>>> tau, s = sp.symbols("tau s", positive=True)
>>> SymbolicTF.from_expr(1/(tau*s + 1), s, normalize="as-derived").subs({"tau": 0.5}).poles()
array([-2.])
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any, Mapping, Sequence

import numpy as np
import sympy as sp

from ..parameters import exact_value, match_values
from .._support.sympify import as_expr
from . import _algebra as alg
from ._checks import Normalize, _check_options
from .._support.gcpause import paused_gc
from ._convert import _Converter
from ._deferred import Deferred
from ._packed import Terms
from ._packed_ops import cancel_terms, normalize_terms
from ._exact import _domain_gens, _poly_values, _used_symbols, _value_map
from ._terms import poly_terms, symbolic_sum
from .errors import InvalidOptionError, SingularPencilError
from .latex import tf_latex
from .numeric_tf import NumericTF
from .tables import PoleZeroTable

__all__ = ["SymbolicTF"]


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
    #: the model's fields, each checked (``check_values``) at the values :meth:`subs` is given
    value_checks: tuple = field(default=(), compare=False, repr=False)
    #: the operating point of a model with constant sources (or nonlinear in its inputs):
    #: ``G`` maps the deviation ``u - u0`` to ``y - y0`` (see :mod:`bondgraph.linear.point`)
    operating_point: Any = field(default=None, compare=False, repr=False)

    @classmethod
    def _deferred(cls, source: Deferred, input_name: str, output_name: str, *,
                  known_parameters: tuple[str, ...] = (),
                  value_checks: tuple = (), operating_point: Any = None) -> "SymbolicTF":
        """A transfer function whose sympy ``num``/``den`` are built on first access
        (see :mod:`bondgraph.tf._deferred`)."""
        obj = object.__new__(cls)
        for name, value in (("input_name", input_name), ("output_name", output_name),
                            ("known_parameters", known_parameters),
                            ("value_checks", value_checks),
                            ("operating_point", operating_point), ("_source", source)):
            object.__setattr__(obj, name, value)
        return obj

    def __getattr__(self, name: str):
        # only reached for attributes not set: num and den of a deferred transfer function
        source = self.__dict__.get("_source") if name in ("num", "den") else None
        if source is None:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        with paused_gc():       # as the eager path: millions of objects, no cycles
            num, den = source.polys()
        object.__setattr__(self, "num", num)
        object.__setattr__(self, "den", den)
        object.__setattr__(self, "_source", None)     # the arrays are not needed any more
        return num if name == "num" else den

    def __reduce__(self):
        return (type(self), (self.num, self.den, self.input_name, self.output_name,
                             self.known_parameters, self.value_checks, self.operating_point))

    def _with_metadata(self, **changes) -> "SymbolicTF":
        """``dataclasses.replace`` of ``known_parameters``/``value_checks`` that keeps
        a deferred transfer function deferred."""
        source = self.__dict__.get("_source")
        if source is None or "num" in self.__dict__:
            return replace(self, **changes)
        meta = {"known_parameters": self.known_parameters, "value_checks": self.value_checks,
                "operating_point": self.operating_point}
        meta.update(changes)
        return SymbolicTF._deferred(source, self.input_name, self.output_name, **meta)

    def _arrays(self) -> Deferred | None:
        """The deferred source while ``num``/``den`` are not built and are arrays."""
        source = self.__dict__.get("_source")
        return source if source is not None and source.arrays else None

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
        _check_rational(expr, s)
        return _tf_from_exprs(expr, sp.Integer(1), s, input_name, output_name,
                              normalize, cancel=cancel)

    # -- views --------------------------------------------------------------------
    @property
    def s(self) -> sp.Symbol:
        """The Laplace variable."""
        source = self.__dict__.get("_source")
        return source.s if source is not None else self.num.gen

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
        source = self._arrays()
        return source.den_degree if source is not None else self.den.degree()

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
        >>> from bondgraph.tf import transfer_function
        >>> G = transfer_function(sp.zeros(0, 0), sp.zeros(0, 1), sp.zeros(1, 0),
        ...                       [[m*sp.Symbol("s") + b]])      # F = (m s + b) v
        >>> G.expr, G.is_proper, G.subs({"m": 2, "b": 3})(1j)
        (b + m*s, False, (3+2j))
        """
        source = self._arrays()
        if source is not None:
            return source.num_degree <= source.den_degree
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
        fast = self._numeric_from_arrays(values)
        if fast is not None:
            return fast
        gens = tuple(dict.fromkeys(_domain_gens(self.num) + _domain_gens(self.den)))
        used = _used_symbols(self.num) | _used_symbols(self.den)
        vm = _value_map(gens, values, self.known_parameters, used=used)
        for element in self.value_checks:       # a field positive definite at these values
            element.check_values(values or {})
        return NumericTF(tuple(_poly_values(self.num, gens, vm)),
                         tuple(_poly_values(self.den, gens, vm)),
                         self.input_name, self.output_name, str(self.s))

    def _numeric_from_arrays(self, values: Mapping | None) -> NumericTF | None:
        """:meth:`subs` read from the exponent arrays, without building sympy
        ``Poly`` objects; ``None`` when the sympy form must decide (a pivot
        of several terms or vanishing at the values, a float overflow)."""
        source = self._arrays()
        if source is None or source.pivot() is None:
            return None
        gens = source.params
        vm = _value_map(gens, values, self.known_parameters, used=source.used())
        for element in self.value_checks:       # a field positive definite at these values
            element.check_values(values or {})
        exact = source.values([vm[g] for g in gens])
        if exact is None:
            return None
        try:
            num, den = (tuple(float(c) for c in part) for part in exact)
        except OverflowError:
            return None
        return NumericTF(num, den, self.input_name, self.output_name, str(self.s))

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



#: the largest degree in ``s`` :meth:`SymbolicTF.from_expr` accepts (a budget: its
#: polynomials, tables and frequency responses grow with it)
MAX_DEGREE = 2000


def _check_rational(expr: sp.Expr, s: sp.Symbol) -> None:
    """A finite rational function of ``s`` of moderate degree, else :class:`InvalidOptionError`."""
    if expr.has(sp.zoo, sp.nan, sp.oo, -sp.oo):
        raise InvalidOptionError(
            f"expr: expected a finite rational function of {s}; got {expr} (a division by "
            "zero or an undefined value)")
    if not expr.is_rational_function(s):
        raise InvalidOptionError(
            f"expr: expected a rational function of {s} (a ratio of polynomials); got {expr}: "
            "a delay exp(-T s) or a fractional power has no finite-dimensional transfer "
            "function (approximate a delay with a Pade approximant first)")
    n, d = sp.fraction(sp.together(expr))
    for part, what in ((n, "numerator"), (d, "denominator")):
        if s in part.free_symbols:
            degree = sp.Poly(part, s).degree() if part.is_polynomial(s) else None
            if degree is not None and degree > MAX_DEGREE:
                raise InvalidOptionError(
                    f"expr: its {what} has degree {degree} in {s}, more than {MAX_DEGREE} "
                    "(bondgraph.tf.symbolic_tf.MAX_DEGREE)")


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
        if isinstance(den, Terms) and isinstance(num, Terms):
            num, den = cancel_terms(num, den, conv.ring, conv.k)
        else:
            num, den = alg.cancel_common(num, den, conv.ring, conv.k)
    if not isinstance(den, Terms) or not len(den):
        Pd, (Pn,) = normalize_terms(conv, den, [num], normalize, s)
        return SymbolicTF(Pn, Pd, input_name, output_name)
    # sympy Polys on first access (num, den, coefficients, printing)
    return SymbolicTF._deferred(Deferred(conv, num, den, normalize, s), input_name,
                                output_name)
