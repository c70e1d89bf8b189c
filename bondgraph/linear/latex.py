"""The equations as a paper prints them: dotted states, aligned, LaTeX names.

Examples
--------
>>> from bondgraph import examples
>>> from bondgraph.equations import derive_equations
>>> from bondgraph.linear.latex import model_latex
>>> print(model_latex(derive_equations(examples.free_mass())))
\\begin{aligned}
\\dot{p}_{m} &= F
\\end{aligned}
"""

from __future__ import annotations

from .._support.labels import latex_dot, latex_name, tex
from ..equations import StateEquations
from .model_forms import descriptor_form, state_space

__all__ = ["model_latex", "equations_latex"]


def model_latex(model: StateEquations, *, matrices: bool = False) -> str:
    """An ``aligned`` block of the state equations and outputs (see :meth:`bondgraph.Model.to_latex`)."""
    body = equations_latex(model)[len(r"$$\begin{aligned}"):-len(r"\end{aligned}$$")]
    text = "\\begin{aligned}\n" + body.replace(" \\\\ ", " \\\\\n") + "\n\\end{aligned}"
    if matrices:
        form = descriptor_form(model) if model.descriptor is not None else state_space(model)
        text += "\n" + form.to_latex()
    return text


def equations_latex(model: StateEquations) -> str:
    r"""``\dot x = f`` and ``y = g`` lines as a LaTeX aligned block."""
    rows = [r"%s &= %s" % (latex_dot(s.name), tex(r)) for s, r in zip(model.states, model.rhs)]
    rows += [r"0 &= %s" % tex(g) for g in model.residuals]     # an implicit model's g(x, z, u)
    rows += [r"%s &= %s" % (latex_name(n), tex(g))
             for n, g in zip(model.output_names, model.output_exprs)]
    return r"$$\begin{aligned}" + r" \\ ".join(rows) + r"\end{aligned}$$"
