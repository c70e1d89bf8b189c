"""Storage in derivative causality: stored quantities, their rates, index reduction.

A storage element in derivative causality (an inertia rigidly joined to
another, a compliance across an effort source) stores a quantity ``s`` (its
momentum or displacement) that the rest of the graph fixes algebraically;
its output (effort of an I, flow of a C) is ``ds/dt``.  The derivation
writes ``s`` as an expression and differentiates it in time through the
states, the inputs and ``t``: the state equations become linear in the state
derivatives, ``E(x) x' = F``, solved block by block.

When ``s`` is not an explicit function of the states and inputs, the
constraint is differentiated instead (index reduction):

* ``s`` holds algebraic unknowns ``z`` that no symbolic solve eliminated (a
  nonlinear loop, a law with no closed-form inverse, see
  :mod:`~bondgraph.equations.implicit`): the residuals ``0 = g(x, z, u)``
  that fix those unknowns are differentiated, ``g_x x' + g_z z' + g_u u' +
  g_t = 0``, linear in the rates ``z'``; they are solved for ``z'`` (in terms
  of ``x'``) and substituted, so that ``x' = f(x, z, u)`` keeps the form of
  an implicit model with the same ``z`` and residuals;
* ``s`` depends on itself (an MTF whose ratio follows the displacement of the
  compliance it drives) or on another dependent quantity in a circle: those
  quantities are kept as algebraic unknowns named after them (``q_C``), with
  residuals ``s - S(x, s, u) = 0``, and differentiated the same way.  A
  chain without a circle (one dependent quantity modulating another's
  constraint) is substituted in order.

What stays refused: a stored quantity that depends on the *rate* of a storage
element in derivative causality (its effort or flow), directly or through
an algebraic unknown: differentiating it would need a second derivative (a
constraint of higher index than this scheme covers).  The message names the
elements.

Examples
--------
A compliance ``c`` fed through an MTF whose ratio ``2 + cos(q_c)`` follows
its own displacement, from a node held by the compliance ``k``: ``q_c = (c/k)
q_k / (2 + cos q_c)`` has no closed form, so ``q_c`` is an algebraic unknown,
and its rate comes from the differentiated constraint.

>>> import sympy, bondgraph as bg
>>> g = bg.BondGraph("selfmod")
>>> g.add(bg.Sf("J"), bg.Zero("m"), bg.C("k"), bg.Zero("n"), bg.C("c"),
...       bg.MTF("M", 2 + sympy.cos(bg.displacement("c"))))
>>> for t, h in [("J", "m"), ("m", "k"), ("m", "M"), ("M", "n"), ("n", "c")]:
...     _ = g.connect(t, h)
>>> model = bg.derive(g)
>>> model.state_names, model.algebraic_names, model.residuals
(('q_k',), ('q_c',), (-c*q_k/(k*(cos(q_c) + 2)) + q_c,))
"""

from __future__ import annotations

from typing import Optional

import networkx as nx
import sympy

from ..errors import AlgebraicLoopError, LawError
from ..signals import t as T_SYM

__all__ = ["DependentStorage"]


class DependentStorage:
    """The stored quantities and rates of the storage in derivative causality of one
    derivation (internal to it; see the module docstring).

    Parameters
    ----------
    deriver
        The derivation (:mod:`~bondgraph.equations.derive`), after its algebraic loops
        are solved.
    sub : dict
        The loop solutions (loop unknown -> expression); completed here with
        the stored quantities and the rates (dependent outputs).
    """

    def __init__(self, deriver, sub: dict) -> None:
        self.d = deriver
        self.sub = sub
        #: rate symbols of the algebraic unknowns that are differentiated (z -> dz/dt)
        self.zdot: dict[sympy.Symbol, sympy.Symbol] = {}
        #: z' = dz/dt + d/dt g(x, z, u) (zero), linear in the rates
        self.zdot_eqs: dict[sympy.Symbol, sympy.Expr] = {}
        self.rate_syms = {self.d.broken[v]: n for n, outs in self.d.dependent_vars.items()
                          for v in outs}
        self.rate_set = set(self.rate_syms)
        self.stored_of = {s: n for n, xs in self.d.stored_sym.items() for s in xs}
        #: stored quantities kept as algebraic unknowns
        self.kept: set = set()
        #: unknowns that no rate may hold (set once the rates are known)
        self.unknowns: set = set()

    # ------------------------------------------------------------ stored quantities
    def _stored(self) -> dict[sympy.Symbol, sympy.Expr]:
        """Each stored symbol -> its expression (loops substituted; may hold stored symbols)."""
        d, out = self.d, {}
        for name in d.dependent_vars:
            el = d.flat.element(name)
            local = d._local(el, d.val.__getitem__)
            try:
                values = el.stored(local)
            except LawError:        # no closed-form inverse: s kept, with its law's residual
                residuals = el.implicit_stored(local, d.stored_sym[name])
                if residuals is None:
                    raise
                values = d.stored_sym[name]
                for s, r in zip(values, residuals):
                    self._keep(s, r.xreplace(self.sub), (el.label(),),
                               "in derivative causality: its law has no closed-form "
                               "inverse in this causality")
            for s, x in zip(d.stored_sym[name], values):
                x = x.xreplace(self.sub)
                rates = x.free_symbols & self.rate_set
                if rates:
                    self._refuse_rate(name, sorted({self.rate_syms[r] for r in rates}))
                out[s] = x
        return out

    def _refuse_rate(self, name: str, others: list, through: str = "") -> None:
        el = self.d.flat.element(name)
        raise AlgebraicLoopError(
            f"{el.label()} is in derivative causality and its input depends{through} on the "
            f"rate of the storage element(s) {', '.join(others)}, also in derivative causality "
            "(a higher-index model: its constraint would have to be differentiated twice); "
            "make one of them compliant or add a storage element between them")

    def _resolve(self, stored: dict) -> None:
        """Substitute stored quantities into one another in order; keep a circle of them
        as algebraic unknowns with residuals ``s - S(s) = 0``."""
        d = self.d
        dg = nx.DiGraph()
        dg.add_nodes_from(stored)
        free = set(stored) - self.kept
        for s, x in stored.items():
            for o in x.free_symbols & free:
                if s not in self.kept:
                    dg.add_edge(o, s)
        cond = nx.condensation(dg)
        for c in nx.topological_sort(cond):
            members = sorted(cond.nodes[c]["members"], key=sympy.default_sort_key)
            if members[0] in self.kept:
                continue
            if len(members) == 1 and not dg.has_edge(members[0], members[0]):
                self.sub[members[0]] = stored[members[0]].xreplace(self.sub)
                continue
            labels = tuple(dict.fromkeys(d.flat.element(self.stored_of[s]).label()
                                         for s in members))
            for s in members:
                self._keep(s, s - stored[s].xreplace(self.sub), labels,
                           f"in derivative causality, fixed by a constraint through "
                           f"{', '.join(labels)} with no closed-form solution")

    def _keep(self, s: sympy.Symbol, residual: sympy.Expr, labels: tuple, why: str) -> None:
        """Keep the stored quantity ``s`` as an algebraic unknown with ``residual = 0``."""
        d = self.d
        self.kept.add(s)
        el = d.flat.element(self.stored_of[s])
        what = "momentum" if s.name.startswith("p_") else "displacement"
        named = d.implicit._name(s.name, f"the {what} of {el.label()} (an algebraic unknown)")
        d.implicit.add_stored(s, named, residual, f"the {what} of {el.label()}, {why}", labels)

    # ------------------------------------------------------------ rates
    def _differentiate_constraints(self, stored: dict) -> None:
        """Rates ``z'`` for the algebraic unknowns the stored quantities hold, and for those
        their residuals hold in turn; the residuals' time derivatives as their equations."""
        d = self.d
        residual = {e[0]: e[2] for e in d.implicit.entries}
        held, unknowns = set(), set(residual)
        for s in stored:            # its value, or itself when kept as an unknown
            held |= s.xreplace(self.sub).free_symbols & unknowns
        todo = sorted(held, key=sympy.default_sort_key)
        while todo:
            z = todo.pop()
            if z in self.zdot:
                continue
            self.zdot[z] = sympy.Dummy(f"d{z.name}/dt", real=True)
            g = residual[z].xreplace(self.sub)
            for o in g.free_symbols & unknowns:
                if o not in self.zdot:
                    todo.append(o)
            self.zdot_eqs[self.zdot[z]] = g
        origin = {e[0]: e for e in d.implicit.entries}
        for z, zd in self.zdot.items():
            g = self.zdot_eqs[zd]
            rates = g.free_symbols & self.rate_set
            if rates:
                users = [n for n, xs in d.stored_sym.items()
                         if any(s.xreplace(self.sub).free_symbols & set(self.zdot) for s in xs)]
                self._refuse_rate(users[0], sorted({self.rate_syms[r] for r in rates}),
                                  f" through {origin[z][3]}")
            self.zdot_eqs[zd] = zd + self.ddt(g)

    def ddt(self, expr: sympy.Expr) -> sympy.Expr:
        """Total time derivative through states, inputs, ``t`` and the differentiated
        algebraic unknowns."""
        d, terms = self.d, []
        for s in expr.free_symbols:
            rate = d.xdot.get(s) or d.udot.get(s) or self.zdot.get(s)
            if rate is not None:
                terms.append(sympy.diff(expr, s) * rate)
            elif s == T_SYM:
                terms.append(sympy.diff(expr, s))
            elif s in self.unknowns:     # pragma: no cover - substituted or refused before
                raise AssertionError(f"{s} is not differentiated in {expr}")
        return sympy.Add(*terms)

    # ------------------------------------------------------------ main
    def run(self) -> Optional[dict]:
        """Complete ``sub`` with the stored quantities and the rates; return the solution
        of the differentiated constraints for ``z'`` (in terms of ``x'``), or None."""
        d = self.d
        if not d.dependent_vars:
            return None
        stored = self._stored()
        self._resolve(stored)
        for u in list(self.sub):         # loop solutions may hold stored quantities
            self.sub[u] = self.sub[u].xreplace(self.sub)
        self._differentiate_constraints(stored)
        self.unknowns = (set(d.broken.values()) | set(self.stored_of)
                         | d.implicit.law_symbols()) - set(self.zdot)
        for name, outs in d.dependent_vars.items():
            el = d.flat.element(name)
            local = d._local(el, d.val.__getitem__)
            rates = [self.ddt(s.xreplace(self.sub)) for s in d.stored_sym[name]]
            for v in outs:
                k = v // 2
                port = d.port_at[k][d.bonds[k].head == name]
                self.sub[d.broken[v]] = el.derivative_output(local, port, rates)
        if not self.zdot_eqs:
            return None
        eqs = {zd: g.xreplace(self.sub) for zd, g in self.zdot_eqs.items()}
        return d._solve_blocks(eqs, "differentiated constraint")
