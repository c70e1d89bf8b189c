"""Transfer functions with float coefficients: :class:`NumericTF` and
:class:`NumericTransferMatrix`, the results of ``subs`` on the symbolic ones.

Examples
--------
>>> NumericTF((1.0,), (1.0, 2.0), "V", "omega").dc_gain()
0.5
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .._support.labels import control_labels
from ._checks import resolve_signal
from ._terms import numeric_sum, poly_terms
from .errors import InvalidOptionError
from .latex import numeric_tf_latex
from .tables import PoleZeroTable, pole_zero_table

__all__ = ["NumericTF", "NumericTransferMatrix"]


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


@dataclass(frozen=True)
class NumericTransferMatrix:
    """All numeric entries ``nums[i][j](s) / den(s)`` sharing one denominator.

    Returned by :meth:`TransferMatrix.subs`; coefficients are highest power
    first.  Index ``[output, input]`` (names or indices) for one entry.

    Examples
    --------
    >>> import sympy as sp
    >>> k, m = sp.symbols("k m", positive=True)
    >>> from bondgraph.tf import transfer_matrix
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
        i = resolve_signal(out, self.output_names, "output")
        j = resolve_signal(inp, self.input_names, "input")
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
