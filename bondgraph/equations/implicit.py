"""What no symbolic solve eliminates: algebraic unknowns ``z`` and residuals ``0 = g(x, z, u)``.

The derivation solves algebraic loops and inverts laws symbolically first.
Two things can remain:

* a loop block that is nonlinear in its own unknowns (a diode or a ``tanh``
  friction in series with a resistor, a quadratic orifice in a loop of
  pipes): its unknowns ``u`` stay, with residuals ``u - expr(u) = 0``;
* a law met in the causality that needs its inverse when sympy finds no
  single closed-form inverse (``e = f |f|``): the element's output ``z``
  stays, with the residual the element gives
  (:meth:`~bondgraph.elements.Element.implicit_output`), e.g.
  ``e_in - law(z) = 0``.

:class:`ImplicitPart` collects them during one derivation and names the
unknowns after the element or bond they belong to (``f_D``: the flow of the
R called ``D``; ``e_3``: the effort of bond 3).  The model is then
``x' = f(x, z, u)``, ``0 = g(x, z, u)``, ``y = h(x, z, u)``; the numeric
stage solves ``g = 0`` for ``z`` at each evaluation.

Examples
--------
A diode ``f = Is (exp(e/Vt) - 1)`` in series with a resistor, fed from a
capacitor: the loop current has no closed form.

>>> import sympy, bondgraph as bg
>>> Is, Vt = sympy.symbols("Is Vt", positive=True)
>>> g = bg.BondGraph("diode")
>>> g.add(bg.C("C"), bg.One("s"), bg.R("R"), bg.R("D", inverse=Is*(sympy.exp(bg.e/Vt) - 1)))
>>> for t, h in [("s", "C"), ("s", "R"), ("s", "D")]: _ = g.connect(t, h)
>>> model = bg.derive(g)
>>> model.algebraic, model.residuals
((f_D,), (f_D - (-Vt*log(1 + f_D/Is) - q_C/C)/R,))
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Optional

import sympy

from ..errors import AlgebraicLoopError

if TYPE_CHECKING:
    from ..elements.protocol import Element

__all__ = ["ImplicitPart"]


class ImplicitPart:
    """The algebraic unknowns and residuals of one derivation (internal to it)."""

    def __init__(self, deriver) -> None:
        self.d = deriver
        #: [symbol during derivation, named symbol, residual, origin, elements]
        self.entries: list[list] = []

    # ------------------------------------------------------------ naming
    def _name(self, stem: str, role: str) -> sympy.Symbol:
        name, n = stem, 2
        while name in self.d.roles:
            name, n = f"{stem}_{n}", n + 1
        self.d._claim(name, role)
        return sympy.Symbol(name, real=True)

    def _bond(self, v: int) -> str:
        b = self.d.bonds[v // 2]
        return f"bond {b.number} ({b.tail} -> {b.head})"

    @staticmethod
    def _what(v: int) -> str:
        return "effort" if v % 2 == 0 else "flow"

    # ------------------------------------------------------------ collecting
    def law_unknown(self, el: "Element", v: int) -> sympy.Symbol:
        """A named unknown for the output variable ``v`` of ``el`` (whose law has no inverse)."""
        inc = self.d.flat.incidence[el.name]
        tag = f"_{inc.index(v // 2) + 1}" if len(inc) > 1 else ""
        return self._name(f"{self._what(v)[0]}_{el.name}{tag}",
                          f"the {self._what(v)} of {el.label()} (an algebraic unknown)")

    def add_law(self, z: sympy.Symbol, residual: sympy.Expr, el: "Element", v: int) -> None:
        origin = (f"the {self._what(v)} of {el.label()} on {self._bond(v)}: its law has no "
                  "closed-form inverse in this causality")
        self.entries.append([z, z, residual, origin, (el.label(),)])

    def add_loops(self, blocks: list) -> None:
        """Loop blocks kept unsolved by :func:`~bondgraph.equations.loops.solve_blocks`:
        ``(block, residuals, nature)``, ``nature`` ``"nonlinear"`` or ``"linear"`` (a
        linear loop past the exact solver's term budget)."""
        var_of = {sym: v for v, sym in self.d.broken.items()}
        arbitrary = set(self.d.aug.arbitrary)
        for block, residuals, nature in blocks:
            bonds = [self.d.bonds[var_of[u] // 2] for u in block]
            elements = tuple(dict.fromkeys(
                self.d.flat.element(end).label() for b in bonds for end in (b.tail, b.head)
                if end in arbitrary))
            for u, r in zip(block, residuals):
                v = var_of[u]
                b = self.d.bonds[v // 2]
                owner = next((end for end in (b.head, b.tail) if end in arbitrary), None)
                stem = f"{self._what(v)[0]}_{owner if owner is not None else b.number}"
                named = self._name(stem, f"the {self._what(v)} of {self._bond(v)} "
                                         "(an algebraic unknown)")
                why = ("" if nature == "nonlinear" else
                       " (kept unsolved: its exact symbolic solution passes the term budget "
                       "bondgraph.equations.loops.LOOP_TERM_BUDGET)")
                origin = (f"the {self._what(v)} of {self._bond(v)}, in a {nature} algebraic "
                          f"loop through {', '.join(elements) or 'the junction structure'}{why}")
                self.entries.append([u, named, r, origin, elements])

    def add_stored(self, s: sympy.Symbol, named: sympy.Symbol, residual: sympy.Expr,
                   origin: str, elements: tuple) -> None:
        """A stored quantity of storage in derivative causality kept as an unknown
        (see :mod:`~bondgraph.equations.dependent`)."""
        self.entries.append([s, named, residual, origin, elements])

    def law_symbols(self) -> set:
        return {e[0] for e in self.entries if e[0] is e[1]}

    def named_symbols(self) -> set:
        return {e[1] for e in self.entries}

    def substitute(self, solution: dict, only: Optional[set] = None) -> None:
        """Substitute into the residuals (those holding a symbol of ``only``, if given)."""
        for e in self.entries:
            if only is None or e[2].free_symbols & only:
                e[2] = e[2].xreplace(solution)

    # ------------------------------------------------------------ result
    def renaming(self) -> dict:
        """The symbols used during the derivation -> the unknowns' names."""
        return {e[0]: e[1] for e in self.entries if e[0] is not e[1]}

    def finish(self, rates: set, rhs, outputs):
        """``(algebraic, residuals, origin, rhs, outputs)`` with the unknowns named.

        Raises
        ------
        AlgebraicLoopError
            A residual that holds a state derivative (storage in derivative
            causality constrained through the implicit part: a higher-index
            model), naming the elements.
        """
        if not self.entries:
            return (), (), (), rhs, outputs
        for e in self.entries:
            if e[2].free_symbols & rates:
                raise AlgebraicLoopError(
                    f"model {self.d.flat.name!r}: {e[3]} depends on a storage element in "
                    "derivative causality (a higher-index model with a nonlinear constraint); "
                    f"elements: {', '.join(e[4])}; make the storage element compliant or add "
                    "one between them")
        rename = self.renaming()
        residuals = tuple(e[2].xreplace(rename) for e in self.entries)
        return (tuple(e[1] for e in self.entries), residuals, tuple(e[3] for e in self.entries),
                [r.xreplace(rename) for r in rhs], [o.xreplace(rename) for o in outputs])
