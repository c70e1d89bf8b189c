"""All input/output transfer functions over one shared denominator: :class:`TransferMatrix`.

Built by :func:`~bondgraph.tf.symbolic.transfer_matrix`; indexing returns a
cancelled :class:`~bondgraph.tf.symbolic_tf.SymbolicTF`, :meth:`TransferMatrix.subs`
a :class:`~bondgraph.tf.numeric_tf.NumericTransferMatrix`.

Examples
--------
>>> import sympy as sp
>>> a, s = sp.symbols("a s", positive=True)
>>> G = TransferMatrix(((sp.Poly(1, s), sp.Poly(s, s)),), sp.Poly(s + a, s), ("u", "v"), ("y",))
>>> G.shape, G["y", "v"].expr
((1, 2), s/(a + s))
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import sympy as sp

from ._checks import resolve_signal
from ._exact import _domain_gens, _poly_values, _value_map
from .errors import UnknownSignalError
from .latex import poly_latex
from .numeric_tf import NumericTransferMatrix
from .._support.gcpause import paused_gc
from .symbolic_tf import SymbolicTF, _entry, _tf_from_exprs

__all__ = ["TransferMatrix"]


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
    >>> from bondgraph.tf import transfer_matrix
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
    #: the operating point of a model with constant sources (deviations about it)
    operating_point: Any = field(default=None, compare=False, repr=False, hash=False)

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
        i = resolve_signal(out, self.output_names, "output")
        j = resolve_signal(inp, self.input_names, "input")
        if self._raw is not None:
            conv, dd, nds = self._raw
            with paused_gc():
                G = _entry(conv, nds[i][j], dd, self.s, self.input_names[j],
                           self.output_names[i], self.normalize, cancel=True)
        else:
            G = _cancel_pair(self.nums[i][j], self.den, self.input_names[j],
                             self.output_names[i], self.normalize)
        return G._with_metadata(known_parameters=self.known_parameters,
                                operating_point=self.operating_point)

    def to_latex(self, *, lhs: bool | str = True) -> str:
        r"""``G(s) = \frac{1}{den(s)} [num_ij(s)]`` (rows: outputs, columns: inputs).

        Examples
        --------
        >>> import sympy as sp
        >>> a = sp.Symbol("a", positive=True)
        >>> from bondgraph.tf import transfer_matrix
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
