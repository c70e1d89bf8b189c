r"""Paper-ready LaTeX: transfer functions, state equations and matrices.

All functions return LaTeX *without* math delimiters (put them inside
``equation``/``align`` or ``$...$``); multi-line results use ``aligned``.
Signal names are strings; they print like sympy prints a symbol of that name
(``"omega" -> \omega``, ``"p_J" -> p_{J}``, ``"E_in" -> E_{in}``).

Examples
--------
>>> import sympy as sp
>>> from bondgraph.tf.latex import tf_latex
>>> a, b = sp.symbols("a b", positive=True)
>>> tf_latex([1], [a, b, 0], input_name="E_in", output_name="Theta")
'\\frac{\\Theta(s)}{E_{in}(s)} = \\frac{1}{a s^{2} + b s}'
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
import sympy as sp

from .._support.labels import latex_dot, latex_name, tex
from .._support.sympify import as_matrix
from ._terms import monomial, numeric_sum, poly_terms, symbolic_sum
from .errors import InvalidOptionError, ShapeError
from .tables import latex_number, snap_roots

__all__ = ["name_latex", "dot_latex", "poly_latex", "tf_latex", "numeric_poly_latex",
           "numeric_tf_latex", "factored_latex", "matrix_latex", "state_equations_latex",
           "state_space_latex"]


def name_latex(name: str) -> str:
    r"""LaTeX of a signal or state name, as sympy prints ``Symbol(name)``.

    Parameters
    ----------
    name : str
        Signal or state name, e.g. ``"omega"`` or ``"p_J"``.

    Returns
    -------
    str

    Examples
    --------
    >>> name_latex("omega"), name_latex("p_J"), name_latex("x2")
    ('\\omega', 'p_{J}', 'x_{2}')
    """
    return latex_name(name)


def dot_latex(name: str) -> str:
    r"""LaTeX of the time derivative of a state name (:func:`bondgraph._support.labels.latex_dot`).

    The dot goes over the symbol, subscripts stay outside, as sympy prints
    ``Symbol("xdot_2")``.

    Parameters
    ----------
    name : str
        State name, e.g. ``"p_J"``.

    Returns
    -------
    str

    Examples
    --------
    >>> dot_latex("p_J"), dot_latex("omega"), dot_latex("x2")
    ('\\dot{p}_{J}', '\\dot{\\omega}', '\\dot{x}_{2}')
    """
    return latex_dot(name)


def _combo(terms: Sequence[tuple[object, str]], *, numeric: bool = False,
           digits: int = 4) -> str:
    r"""``c1 m1 + c2 m2 + ...`` with signs folded and sums in parentheses."""
    if numeric:
        return numeric_sum(terms, lambda x: latex_number(x, digits))
    return symbolic_sum(terms)


def poly_latex(coeffs: Sequence[object], s: str = "s") -> str:
    r"""Polynomial with symbolic ``coeffs`` (highest power first).

    Parameters
    ----------
    coeffs : sequence of sympy expressions
        Coefficients, highest power first.
    s : str
        LaTeX of the variable.

    Returns
    -------
    str

    Examples
    --------
    >>> import sympy as sp
    >>> J, b, K = sp.symbols("J b K")
    >>> poly_latex([J, b + K**2, -1])
    'J s^{2} + \\left(K^{2} + b\\right) s - 1'
    """
    return _combo(poly_terms(coeffs, s))


def numeric_poly_latex(coeffs: Sequence[float], s: str = "s", *, digits: int = 4) -> str:
    r"""Polynomial with float ``coeffs`` (highest power first); zeros skipped.

    Parameters
    ----------
    coeffs : sequence of float
        Coefficients, highest power first.
    s : str
        LaTeX of the variable.
    digits : int
        Significant digits shown.

    Returns
    -------
    str

    Examples
    --------
    >>> numeric_poly_latex([1.0, 0.0, -1.07e-05, 2.5])
    's^{3} - 1.07 \\cdot 10^{-5} s + 2.5'
    """
    return _combo(poly_terms(coeffs, s), numeric=True, digits=digits)


def _lhs(lhs, input_name: str, output_name: str, s: str) -> str:
    if lhs is True:
        return f"\\frac{{{name_latex(output_name)}({s})}}{{{name_latex(input_name)}({s})}}"
    if not lhs:
        return ""
    return str(lhs)


def _frac(num: str, den: str) -> str:
    if den == "1":
        return num
    return f"\\frac{{{num}}}{{{den}}}"


def tf_latex(num_coeffs: Sequence[object], den_coeffs: Sequence[object], *,
             input_name: str = "u", output_name: str = "y", s: str = "s",
             form: str = "coefficients", lhs: bool | str = True,
             num_letter: str = "a", den_letter: str = "b") -> str:
    r"""LaTeX of a symbolic transfer function.

    Parameters
    ----------
    num_coeffs, den_coeffs : sequence of sympy expressions
        Coefficients, highest power of ``s`` first (sympy expressions).
    input_name, output_name : str
        Signal names used in the left-hand side ``\frac{Y(s)}{U(s)}``.
    s : str
        LaTeX of the Laplace variable.
    form : {'coefficients', 'named'}
        ``'coefficients'``: ``\frac{...}{...}`` with the coefficient
        expressions; ``'named'``: ``\frac{a_1 s + a_0}{b_2 s^2 + ...}`` followed
        by one line per (nonzero) coefficient ``a_k = ...``, in an ``aligned``
        environment, like Eq. (13) of the seed paper.
    lhs : bool or str
        ``True`` writes ``\frac{Y(s)}{U(s)} =`` from the names, a string is
        used as is (e.g. ``'G(s)'``), ``False`` omits it.
    num_letter, den_letter : str
        Letters of the numerator and denominator coefficients when ``form='named'``.

    Returns
    -------
    str

    Examples
    --------
    >>> import sympy as sp
    >>> K, J, R = sp.symbols("K J R")
    >>> print(tf_latex([K], [J, R], input_name="V", output_name="omega", form="named"))
    \begin{aligned}
    \frac{\omega(s)}{V(s)} &= \frac{a_{0}}{b_{1} s + b_{0}} \\
    a_{0} &= K \\
    b_{1} &= J \\
    b_{0} &= R
    \end{aligned}
    """
    left = _lhs(lhs, input_name, output_name, s)
    if form == "coefficients":
        body = _frac(poly_latex(num_coeffs, s), poly_latex(den_coeffs, s))
        return f"{left} = {body}" if left else body
    if form != "named":
        raise InvalidOptionError(f"form: expected 'coefficients' or 'named', got {form!r}")
    lines = []
    named = []
    fracs = []
    for letter, coeffs in ((num_letter, num_coeffs), (den_letter, den_coeffs)):
        n = len(coeffs) - 1
        terms = []
        for k, c in enumerate(coeffs):
            c = sp.sympify(c, strict=True)
            if c == 0:
                continue
            sym = sp.Symbol(f"{letter}_{n - k}")
            terms.append((sym, monomial(s, n - k)))
            named.append((sym, c))
        fracs.append(_combo(terms))
    body = _frac(*fracs)
    lines.append(f"{left} &= {body}" if left else f"&{body}")
    for sym, c in named:
        lines.append(f"{sp.latex(sym)} &= {tex(c)}")
    return "\\begin{aligned}\n" + " \\\\\n".join(lines) + "\n\\end{aligned}"


def numeric_tf_latex(num: Sequence[float], den: Sequence[float], *, input_name: str = "u",
                     output_name: str = "y", s: str = "s", form: str = "coefficients",
                     lhs: bool | str = True, digits: int = 4, zeta_omega: bool = False) -> str:
    r"""LaTeX of a numeric transfer function, coefficient or factored form.

    Parameters
    ----------
    num, den : sequence of float
        Coefficients, highest power first.
    input_name, output_name : str
        Signal names used in the left-hand side.
    s : str
        LaTeX of the Laplace variable.
    form : {'coefficients', 'factored'}
        Expanded polynomials or :func:`factored_latex`.
    lhs : bool or str
        ``True``: ``\frac{Y(s)}{U(s)} =`` from the names; a string: used as is; ``False``: none.
    digits : int
        Significant digits shown.
    zeta_omega : bool
        Write complex pairs as ``2 \cdot zeta \cdot w`` (``form='factored'`` only).

    Returns
    -------
    str

    Examples
    --------
    >>> numeric_tf_latex([2.0], [1.0, 3.0, 2.0], lhs=False)
    '\\frac{2}{s^{2} + 3 s + 2}'
    >>> numeric_tf_latex([2.0], [1.0, 3.0, 2.0], lhs=False, form="factored")
    '\\frac{2}{\\left(s + 1\\right) \\left(s + 2\\right)}'
    """
    left = _lhs(lhs, input_name, output_name, s)
    if form == "coefficients":
        body = _frac(numeric_poly_latex(num, s, digits=digits),
                     numeric_poly_latex(den, s, digits=digits))
    elif form == "factored":
        body = factored_latex(num, den, s=s, digits=digits, zeta_omega=zeta_omega)
    else:
        raise InvalidOptionError(f"form: expected 'coefficients' or 'factored', got {form!r}")
    return f"{left} = {body}" if left else body


def _factors(coeffs: np.ndarray, s: str, digits: int, zeta_omega: bool,
             tol: float = 1e-9) -> list[str]:
    if coeffs.size <= 1:
        return []
    roots = snap_roots(np.roots(coeffs), tol)
    out = []
    real = sorted((r.real for r in roots if r.imag == 0), key=lambda x: (abs(x), x))
    pairs = sorted((r for r in roots if r.imag > 0), key=abs)
    for x in real:
        if x == 0:
            out.append(s)
        else:
            sign = "-" if x > 0 else "+"
            out.append(f"\\left({s} {sign} {latex_number(abs(x), digits)}\\right)")
    for r in pairs:
        wn = abs(r)
        zeta = -r.real / wn
        if zeta_omega:
            out.append(f"\\left({s}^{{2}} + 2 \\cdot {latex_number(zeta, digits)} \\cdot "
                       f"{latex_number(wn, digits)}\\, {s} + {latex_number(wn, digits)}^{{2}}"
                       f"\\right)")
        else:
            out.append("\\left(" + _combo([(1.0, f"{s}^{{2}}"), (-2 * r.real, s),
                                           (wn * wn, "")], numeric=True, digits=digits)
                       + "\\right)")
    return out


def _join_factors(parts: list[str]) -> str:
    # collapse repeated identical factors into powers
    out: list[str] = []
    seen: dict[str, int] = {}
    for p in parts:
        seen[p] = seen.get(p, 0) + 1
    for p, k in seen.items():
        out.append(p if k == 1 else f"{p}^{{{k}}}")
    return " ".join(out)


def factored_latex(num: Sequence[float], den: Sequence[float], *, s: str = "s",
                   digits: int = 4, zeta_omega: bool = False) -> str:
    r"""``k \frac{(s + z_1)(s^2 + 2 zeta w s + w^2)...}{(s + p_1)...}`` from floats.

    Real roots give ``(s + a)`` (``s`` for a root at 0), complex pairs give
    ``(s^2 + 2 zeta w s + w^2)`` with the numbers evaluated, or written as
    ``2 \cdot zeta \cdot w`` when ``zeta_omega``.  ``k`` is the ratio of
    leading coefficients.

    Parameters
    ----------
    num, den : sequence of float
        Coefficients, highest power first (``den`` not all zero).
    s : str
        LaTeX of the Laplace variable.
    digits : int
        Significant digits shown.
    zeta_omega : bool
        Write complex pairs with ``zeta`` and ``w`` instead of evaluated coefficients.

    Returns
    -------
    str

    Examples
    --------
    >>> factored_latex([1.0, 0.0], [1.0, 0.2, 4.0])
    '\\frac{s}{\\left(s^{2} + 0.2 s + 4\\right)}'
    """
    n_arr = np.trim_zeros(np.asarray(num, dtype=float), "f")
    d_arr = np.trim_zeros(np.asarray(den, dtype=float), "f")
    if d_arr.size == 0:
        raise InvalidOptionError("den: expected a nonzero polynomial, got all zeros")
    if n_arr.size == 0:
        return "0"
    k = n_arr[0] / d_arr[0]
    nf = _join_factors(_factors(n_arr, s, digits, zeta_omega))
    df = _join_factors(_factors(d_arr, s, digits, zeta_omega))
    gain = latex_number(abs(k), digits)
    sign = "-" if k < 0 else ""
    if not df:
        body = nf or ""
        lead = "" if (gain == "1" and body) else gain
        return f"{sign}{lead} {body}".strip() if body else f"{sign}{gain}"
    if gain == "1":
        return f"{sign}\\frac{{{nf or '1'}}}{{{df}}}"
    if not nf:
        return f"{sign}\\frac{{{gain}}}{{{df}}}"
    return f"{sign}{gain} \\frac{{{nf}}}{{{df}}}"


def matrix_latex(M, name: str | None = None) -> str:
    r"""``name = \left[\begin{matrix}...\end{matrix}\right]``.

    Parameters
    ----------
    M : sympy matrix, nested list or numpy array
        The matrix.
    name : str or None
        LaTeX written before ``=``; ``None`` or ``""``: the matrix alone.

    Returns
    -------
    str

    Examples
    --------
    >>> import sympy as sp
    >>> k, m = sp.symbols("k m")
    >>> matrix_latex(sp.Matrix([[0, 1/m], [-k, 0]]), "A")
    'A = \\left[\\begin{matrix}0 & \\frac{1}{m}\\\\- k & 0\\end{matrix}\\right]'
    """
    body = tex(as_matrix(M, what=name or "M", error=ShapeError))
    return f"{name} = {body}" if name else body


def _names(names, n, default, what):
    if names is None:
        return tuple(default if n == 1 else f"{default}{i + 1}" for i in range(n))
    names = tuple(names)
    if len(names) != n:
        raise ShapeError(f"{what}: expected {n} names, got {len(names)}: {names}")
    return names


def state_equations_latex(A, B, state_names: Sequence[str] | None = None,
                          input_names: Sequence[str] | None = None, *, E=None, C=None,
                          D=None, output_names: Sequence[str] | None = None) -> str:
    r"""One line per state equation (and per output when ``C`` is given).

    ``E`` (descriptor form) puts ``sum_j E_ij \dot{x}_j`` on the left.

    Parameters
    ----------
    A, B : sympy matrix, nested list or numpy array
        State and input matrices.
    state_names, input_names : sequence of str or None
        State and input names (``None``: ``x``/``u``, numbered if more than one).
    E : sympy matrix, nested list, numpy array or None
        Descriptor matrix (``None``: identity).
    C, D : sympy matrix, nested list, numpy array or None
        Output and feedthrough matrices (``C=None``: no output lines; ``D=None``: zero).
    output_names : sequence of str or None
        Output names (``None``: ``y``, numbered if more than one).

    Returns
    -------
    str

    Examples
    --------
    >>> import sympy as sp
    >>> k, m = sp.symbols("k m")
    >>> print(state_equations_latex(sp.Matrix([[0, 1/m], [-k, 0]]), sp.Matrix([0, 1]),
    ...       ["q", "p"], ["F"], C=sp.Matrix([[1, 0]]), output_names=["x"]))
    \begin{aligned}
    \dot{q} &= \frac{1}{m} p \\
    \dot{p} &= -k q + F \\
    x &= q
    \end{aligned}
    """
    A, B = as_matrix(A, what="A", error=ShapeError), as_matrix(B, what="B", error=ShapeError)
    n = A.shape[0]
    xs = _names(state_names, n, "x", "state_names")
    us = _names(input_names, B.shape[1], "u", "input_names")
    xl = [name_latex(x) for x in xs]
    ul = [name_latex(u) for u in us]
    lines = []
    for i in range(n):
        if E is None:
            left = latex_dot(xs[i])
        else:
            Em = as_matrix(E, what="E", error=ShapeError)
            left = _combo([(Em[i, j], latex_dot(xs[j])) for j in range(n)])
        right = _combo([(A[i, j], xl[j]) for j in range(n)]
                       + [(B[i, j], ul[j]) for j in range(len(us))])
        lines.append(f"{left} &= {right}")
    if C is not None:
        C = as_matrix(C, what="C", error=ShapeError)
        D = sp.zeros(C.shape[0], len(us)) if D is None else as_matrix(D, what="D", error=ShapeError)
        ys = _names(output_names, C.shape[0], "y", "output_names")
        for i, y in enumerate(ys):
            right = _combo([(C[i, j], xl[j]) for j in range(n)]
                           + [(D[i, j], ul[j]) for j in range(len(us))])
            lines.append(f"{name_latex(y)} &= {right}")
    return "\\begin{aligned}\n" + " \\\\\n".join(lines) + "\n\\end{aligned}"


def _vector(names, dotted=False) -> str:
    items = [latex_dot(x) if dotted else name_latex(x) for x in names]
    return "\\left[\\begin{matrix}" + "\\\\".join(items) + "\\end{matrix}\\right]"


def state_space_latex(A, B, C=None, D=None, *, E=None,
                      state_names: Sequence[str] | None = None,
                      input_names: Sequence[str] | None = None,
                      output_names: Sequence[str] | None = None) -> str:
    r"""Matrix form ``[x'] = A [x] + B [u]``, ``[y] = C [x] + D [u]``.

    A zero ``D`` is left out.

    Parameters
    ----------
    A, B : sympy matrix, nested list or numpy array
        State and input matrices.
    C, D : sympy matrix, nested list, numpy array or None
        Output and feedthrough matrices (``C=None``: no output line; ``D=None``: zero).
    E : sympy matrix, nested list, numpy array or None
        Descriptor matrix (``None``: identity).
    state_names, input_names, output_names : sequence of str or None
        State, input and output names (``None``: ``x``/``u``/``y``, numbered if more than one).

    Returns
    -------
    str

    Examples
    --------
    >>> import sympy as sp
    >>> print(state_space_latex(sp.Matrix([[-1]]), sp.Matrix([[1]]), sp.Matrix([[2]]),
    ...                         sp.Matrix([[0]]), state_names=["x"]))
    \begin{aligned}
    \left[\begin{matrix}\dot{x}\end{matrix}\right] &= \left[\begin{matrix}-1\end{matrix}\right] \left[\begin{matrix}x\end{matrix}\right] + \left[\begin{matrix}1\end{matrix}\right] \left[\begin{matrix}u\end{matrix}\right] \\
    \left[\begin{matrix}y\end{matrix}\right] &= \left[\begin{matrix}2\end{matrix}\right] \left[\begin{matrix}x\end{matrix}\right]
    \end{aligned}
    """
    A, B = as_matrix(A, what="A", error=ShapeError), as_matrix(B, what="B", error=ShapeError)
    xs = _names(state_names, A.shape[0], "x", "state_names")
    us = _names(input_names, B.shape[1], "u", "input_names")
    left = _vector(xs, dotted=True)
    if E is not None:
        left = f"{tex(as_matrix(E, what='E', error=ShapeError))} {left}"
    lines = [f"{left} &= {tex(A)} {_vector(xs)} + {tex(B)} {_vector(us)}"]
    if C is not None:
        C = as_matrix(C, what="C", error=ShapeError)
        ys = _names(output_names, C.shape[0], "y", "output_names")
        right = f"{tex(C)} {_vector(xs)}"
        if D is not None and not as_matrix(D, what="D", error=ShapeError).is_zero_matrix:
            right += f" + {tex(as_matrix(D, what='D', error=ShapeError))} {_vector(us)}"
        lines.append(f"{_vector(ys)} &= {right}")
    return "\\begin{aligned}\n" + " \\\\\n".join(lines) + "\n\\end{aligned}"


