"""Symbolic state equations from an augmented bond graph.

Bond variables are computed once each, in causal order, and substituted into
what follows them: no solve, simplify or row reduction over the whole system.

* Storage elements in integral causality give the states (``p_`` of an I,
  ``q_`` of a C); displacement and momentum outputs that are not already
  states add integrator states.
* Algebraic loops: the input of each arbitrarily-causal R is replaced by an
  unknown; each loop's closure equations form a small linear block, solved in
  causal order (blocks are the strongly connected components of the unknowns).
* Derivative causality: a dependent storage element's effort (I) or flow (C)
  is the time derivative of its momentum/displacement, expressed through the
  chain rule in the state derivatives; the resulting equations are linear in
  those derivatives, ``E(x) x' = F(x, u)`` (kept as the descriptor form) and
  solved block by block, which yields the effective inertia ``J1 + n**2 J2``.

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("msd")
>>> F, v = bg.Se("F"), bg.One("v")
>>> g.add(F, v, bg.I("m"), bg.R("b"), bg.C("c"))
>>> for t, h in [(F, v), (v, "m"), (v, "b"), (v, "c")]: _ = g.connect(t, h)
>>> model = bg.derive(g, outputs={"x": bg.effort("c")})
>>> model.states
(p_m, q_c)
>>> model.rhs
(F - b*p_m/m - q_c/c, p_m/m)
>>> model.output_exprs
(q_c/c,)
"""

from __future__ import annotations

import warnings
from typing import Mapping, Optional, Union, cast

import sympy

from .causality import AugmentedBondGraph, assign_causality, dependencies
from .elements import Element, OnePort, TwoPort
from .errors import (AlgebraicLoopError, BondGraphWarning, CausalityError, NameClashError,
                     OutputError)
from .flatten import FlatGraph
from .graph import BondGraph
from .integrators import state_combination
from .loops import SingularLoopError, compact_linear, solve_blocks
from .model import Model
from .signals import LawVariable, Signal, e as E_VAR, f as F_VAR, p as P_VAR, q as Q_VAR, t as T_SYM

__all__ = ["derive"]

OutputSpec = Union[Mapping[str, sympy.Expr], None]


def derive(graph: Union[BondGraph, AugmentedBondGraph], outputs: OutputSpec = None) -> Model:
    """Derive explicit state equations (and outputs) from a bond graph.

    Parameters
    ----------
    graph : BondGraph or AugmentedBondGraph
        Causality is assigned (by SCAP) when a plain graph is given.
    outputs : mapping of str to expression, optional
        Named outputs: expressions of signals such as ``bg.flow("J")``,
        ``bg.displacement("J")`` or ``L*bg.displacement("hub") + ...``.

    Returns
    -------
    Model
        States, inputs, ``rhs`` (x' = f(x, u)), outputs and, when derivative
        causality is present, the descriptor form.

    Raises
    ------
    OutputError
        An output names no element or bond, or is not an expression.
    AlgebraicLoopError
        A loop that is not linear in its unknowns.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("dc_motor")
    >>> V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    >>> g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
    >>> for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
    ...     _ = g.connect(tail, head)
    >>> model = bg.derive(g, outputs={"omega": bg.flow("J"), "theta": bg.displacement("J")})
    >>> model.state_names
    ('p_La', 'p_J', 'theta')
    >>> model.rhs
    (V - Ra*p_La/La - K*p_J/J, K*p_La/La - b*p_J/J, p_J/J)
    """
    outputs = _check_outputs(outputs)
    if isinstance(graph, AugmentedBondGraph):
        _warn_reversed(graph.flat)
        return _Deriver(graph, outputs).run()
    aug = assign_causality(graph)
    _warn_reversed(aug.flat)
    # An integral storage element whose effort (C) or flow (I) the junction structure
    # fixes algebraically leaves a singular loop: put such elements in derivative
    # causality, one at a time, before calling the graph ill-posed.
    forced: frozenset = frozenset()
    first: Optional[SingularLoopError] = None
    for _ in range(len(aug.integral) + 1):
        try:
            return _Deriver(aug, outputs).run()
        except SingularLoopError as err:
            first = first or err
            keep = None
            for name in err.storage:       # the first flip that derives wins
                if name in forced:
                    continue
                try:
                    trial = assign_causality(aug.flat, prefer_derivative=forced | {name})
                except CausalityError:
                    continue
                if name not in trial.derivative:
                    continue
                try:
                    return _Deriver(trial, outputs).run()
                except SingularLoopError:
                    keep = keep or (name, trial)
            if keep is None:
                break
            forced, aug = forced | {keep[0]}, keep[1]   # none alone: keep one, go on
    assert first is not None
    raise first


def _warn_reversed(flat: FlatGraph) -> None:
    """Warn once per element whose bond carries power out of an I, C or R."""
    for el in flat.elements:
        if isinstance(el, OnePort):
            (k,) = flat.incidence[el.name]
            b = flat.bonds[k]
            if b.tail == el.name:
                warnings.warn(
                    f"bond {b.number} points out of {el.label()} ({b.tail} -> {b.head}): its "
                    "law holds for power flowing into it, so its flow (and momentum or "
                    f"displacement) has the opposite sign; connect(..., {el.name!r}) is the usual "
                    "direction. Silence with warnings.simplefilter('ignore', "
                    "bondgraph.BondGraphWarning)",
                    BondGraphWarning, stacklevel=3)


def _check_outputs(outputs: OutputSpec) -> dict[str, sympy.Expr]:
    if outputs is None:
        return {}
    if not isinstance(outputs, Mapping):
        raise OutputError(f"outputs must be a mapping of name to signal expression; got {type(outputs).__name__}")
    out = {}
    for name, expr in outputs.items():
        if not isinstance(name, str) or not name.isidentifier():
            raise OutputError(f"output name {name!r} must be an identifier such as 'theta'")
        if not isinstance(expr, sympy.Expr):
            raise OutputError(
                f"output {name!r} must be a signal expression such as bondgraph.flow('J'); "
                f"got {type(expr).__name__} {expr!r}"
            )
        if not any(isinstance(s, Signal) for s in expr.free_symbols):
            raise OutputError(f"output {name!r} = {expr} uses no signal (effort, flow, displacement, momentum)")
        out[name] = expr
    return out


class _Deriver:
    def __init__(self, aug: AugmentedBondGraph, outputs: dict[str, sympy.Expr]) -> None:
        self.aug = aug
        self.flat: FlatGraph = aug.flat
        self.outputs = outputs
        self.producer, self.inputs = dependencies(aug)
        self.bonds = self.flat.bonds
        self.nvar = 2 * len(self.bonds)
        self.val: list = [None] * self.nvar
        self.states: list[sympy.Symbol] = []
        self.state_names: list[str] = []
        self.state_of: dict[str, sympy.Symbol] = {}   # integral storage element -> state
        self.integrators: dict[Signal, sympy.Symbol] = {}
        self.input_syms: list[sympy.Symbol] = []
        self.input_of: dict[str, sympy.Symbol] = {}
        self.xdot: dict[sympy.Symbol, sympy.Symbol] = {}
        self.udot: dict[sympy.Symbol, sympy.Symbol] = {}
        self.broken: dict[int, sympy.Symbol] = {}     # var -> loop unknown
        # storage in derivative causality: its output variable and stored quantity are
        # unknowns during the causal sweep, resolved once the algebraic loops are solved
        self.dependent: dict[int, str] = {}            # output var -> element name
        self.stored_sym: dict[str, sympy.Symbol] = {}  # element name -> its p or q
        # an integrator that is exactly an output takes the output's name
        self.preferred = {ex: n for n, ex in outputs.items() if isinstance(ex, Signal)}

    # ------------------------------------------------------------ naming
    def _sign(self, name: str, k: int) -> int:
        """+1 when bond k points into element `name`."""
        return 1 if self.bonds[k].head == name else -1

    def _ein(self, name: str, k: int) -> bool:
        hge = self.aug.stroke_at_head[k]
        return hge if self.bonds[k].head == name else not hge

    def _claim(self, name: str, role: str) -> None:
        """Reserve a printed name for a state, an input or time; refuse a clash."""
        if name in self.roles:
            raise NameClashError(
                f"model {self.flat.name!r}: the name {name!r} would stand for both "
                f"{self.roles[name]} and {role}; rename one of the elements"
            )
        self.roles[name] = role

    def _make_symbols(self) -> None:
        integral = set(self.aug.integral)
        self.roles: dict[str, str] = {T_SYM.name: "time"}
        for el in self.flat.elements:
            if el.kind in ("I", "C") and el.name in integral:
                sym = sympy.Symbol(("p_" if el.kind == "I" else "q_") + el.name, real=True)
                self._claim(sym.name, f"the state of {el.label()}")
                self.state_of[el.name] = sym
                self.states.append(sym)
                self.state_names.append(sym.name)
        for el in self.flat.elements:
            if el.kind in ("Se", "Sf") and getattr(el, "value", None) is None:
                sym = sympy.Symbol(el.name, real=True)
                self._claim(sym.name, f"the input of {el.label()}")
                self.input_of[el.name] = sym
                self.input_syms.append(sym)
        for sym in self.states:
            self.xdot[sym] = sympy.Dummy(f"d{sym.name}/dt", real=True)
        for sym in self.input_syms:
            self.udot[sym] = sympy.Symbol(f"d{sym.name}/dt", real=True)

    def _integrator(self, sig: Signal) -> sympy.Symbol:
        if sig not in self.integrators:
            base = "x" if sig.variable == "displacement" else "h"
            name = self.preferred.get(sig) or f"{base}_{sig.target}"
            if name in self.roles:
                name = f"{base}_{sig.target}"
            stem, n = name, 2
            while name in self.roles:
                name, n = f"{stem}_{n}", n + 1
            self._claim(name, f"the integral of {sig}")
            sym = sympy.Symbol(name, real=True)
            self.integrators[sig] = sym
            self.states.append(sym)
            self.state_names.append(name)
            self.xdot[sym] = sympy.Dummy(f"d{name}/dt", real=True)
        return self.integrators[sig]

    def _check_parameter_names(self, exprs) -> None:
        """A parameter must not print like a state, an input or time."""
        known = set(self.states) | set(self.input_syms) | set(self.udot.values()) | {T_SYM}
        for ex in exprs:
            for sym in ex.free_symbols - known:
                if isinstance(sym, sympy.Dummy):
                    continue
                if sym.name in self.roles:
                    raise NameClashError(
                        f"model {self.flat.name!r}: the parameter {sym.name!r} would print "
                        f"like {self.roles[sym.name]}; rename the element or parameter"
                    )

    # ------------------------------------------------------------ signals
    def _signal_var(self, sig: Signal) -> tuple[int, int]:
        """(var, sign) of an effort/flow signal; var is a bond variable id."""
        kind, target = sig.variable, sig.target
        want_flow = kind in ("flow", "displacement")
        if isinstance(target, int):
            if not 1 <= target <= len(self.bonds):
                raise OutputError(f"signal {sig} names nothing: model {self.flat.name!r} has "
                                  f"bonds 1..{len(self.bonds)}; got bond {target}")
            k = target - 1
            return 2 * k + (1 if want_flow else 0), 1
        if target not in self.flat.index:
            known = ", ".join(list(self.flat.index)[:15])
            raise OutputError(
                f"signal {sig} names nothing: model {self.flat.name!r} has no element "
                f"{target!r} (elements: {known}{', ...' if len(self.flat.index) > 15 else ''})"
            )
        el = self.flat.element(target)
        inc = self.flat.incidence[target]
        if el.kind in ("Se", "Sf", "I", "C", "R"):
            (k,) = inc
            return 2 * k + (1 if want_flow else 0), (self._sign(target, k) if want_flow else 1)
        if el.kind == "0" and not want_flow:
            return 2 * inc[0], 1
        if el.kind == "1" and want_flow:
            k = inc[0]
            return 2 * k + 1, 1
        raise OutputError(
            f"signal {sig}: the {'flow' if want_flow else 'effort'} of {el.label()} is not a "
            "single variable; name a one-port element, the effort of a 0-junction, the flow "
            f"of a 1-junction, or a bond number ({', '.join(str(k + 1) for k in inc)})"
        )

    def _signal_deps(self, expr: Optional[sympy.Expr]) -> list[int]:
        if expr is None:
            return []
        deps = []
        for s in expr.free_symbols:
            if isinstance(s, Signal) and s.variable in ("effort", "flow"):
                deps.append(self._signal_var(s)[0])
        return deps

    def _signal_value(self, sig: Signal) -> sympy.Expr:
        if sig.variable in ("effort", "flow"):
            v, sign = self._signal_var(sig)
            return sign * self._inp(v)
        if isinstance(sig.target, str) and sig.target in self.flat.index:
            el = self.flat.element(sig.target)
            if (sig.variable == "displacement" and el.kind == "C") or (sig.variable == "momentum" and el.kind == "I"):
                if sig.target in self.state_of:
                    return self.state_of[sig.target]
                if sig.target in self.stored_sym:
                    # a storage element in derivative causality: its momentum or
                    # displacement is an algebraic function (p = I*f, q = C*e), not a state
                    return self.stored_sym[sig.target]
        self._signal_var(sig)  # validate the target
        return self._integrator(sig)

    def _resolve(self, expr: sympy.Expr) -> sympy.Expr:
        sigs = {s: self._signal_value(s) for s in expr.free_symbols if isinstance(s, Signal)}
        return expr.xreplace(sigs) if sigs else expr

    # ------------------------------------------------------------ ordering
    def _dependent_var(self, name: str) -> int:
        (k,) = self.flat.incidence[name]
        return 2 * k if self.flat.element(name).kind == "I" else 2 * k + 1

    @staticmethod
    def _unknown(v: int) -> sympy.Symbol:
        """Loop unknown for bond variable v: a Dummy, so no user name can clash with it."""
        return sympy.Dummy(f"{'e' if v % 2 == 0 else 'f'}_{v // 2 + 1}", real=True)

    def _break_dependent(self) -> None:
        for name in self.aug.derivative:
            el = self.flat.element(name)
            (k,) = self.flat.incidence[name]
            v = 2 * k if el.kind == "I" else 2 * k + 1   # I gives effort, C gives flow
            self.dependent[v] = name
            self.broken[v] = sympy.Dummy(f"{'e' if el.kind == 'I' else 'f'}_{name}", real=True)
            self.stored_sym[name] = sympy.Dummy(f"{'p' if el.kind == 'I' else 'q'}_{name}", real=True)

    def _stored(self, name: str) -> tuple[sympy.Expr, int]:
        """Stored quantity (p or q) of a storage element in derivative causality, and the
        sign of its output on the bond, from the bond variable it receives."""
        el = cast(OnePort, self.flat.element(name))
        (k,) = self.flat.incidence[name]
        s = self._sign(name, k)
        if el.kind == "I":
            stored = _subs(el.backward(), F_VAR, s * self.val[2 * k + 1])
            return (self._resolve(stored) if el.signals() else stored), 1
        stored = _subs(el.backward(), E_VAR, self.val[2 * k])
        return (self._resolve(stored) if el.signals() else stored), s

    def _break_loops(self) -> None:
        for name in self.aug.arbitrary:
            (k,) = self.flat.incidence[name]
            v = 2 * k if self._ein(name, k) else 2 * k + 1
            self.broken[v] = self._unknown(v)
        for number in self.aug.arbitrary_bonds:
            k = number - 1
            v = 2 * k if self.aug.stroke_at_head[k] else 2 * k + 1
            self.broken[v] = self._unknown(v)

    def _order(self) -> list[int]:
        """Variables in causal order (iterative depth-first, linear time)."""
        elements = self.flat.elements
        extra: dict[int, list[int]] = {}
        for el in elements:
            deps = self._signal_deps(_law_expr(el))
            if deps:
                for k in self.flat.incidence[el.name]:
                    for v in (2 * k, 2 * k + 1):
                        if self.producer[v] == self.flat.index[el.name]:
                            extra[v] = deps
        state = [0] * self.nvar  # 0 new, 1 on stack, 2 done
        order: list[int] = []
        for root in range(self.nvar):
            if state[root]:
                continue
            stack = [(root, iter(self._deps(root, extra)))]
            state[root] = 1
            while stack:
                v, it = stack[-1]
                for u in it:
                    if state[u] == 0:
                        state[u] = 1
                        stack.append((u, iter(self._deps(u, extra))))
                        break
                    if state[u] == 1 and u not in self.broken:
                        # a zero-order causal cycle that no arbitrary choice broke (junction
                        # cycles, parallel bonds): tear it here with an unknown for u
                        self.broken[u] = self._unknown(u)
                        continue
                else:
                    state[v] = 2
                    order.append(v)
                    stack.pop()
        return order

    def _deps(self, v: int, extra: dict[int, list[int]]) -> list[int]:
        ins = [u for u in self.inputs[v] if u not in self.broken]
        return ins + extra.get(v, [])

    # ------------------------------------------------------------ evaluation
    def _inp(self, u: int) -> sympy.Expr:
        z = self.broken.get(u)
        return z if z is not None else self.val[u]

    def _ddt(self, expr: sympy.Expr, el: Element) -> sympy.Expr:
        """Total time derivative through states, inputs and t."""
        terms = []
        for s in expr.free_symbols:
            if s in self.xdot:
                terms.append(sympy.diff(expr, s) * self.xdot[s])
            elif s in self.udot:
                terms.append(sympy.diff(expr, s) * self.udot[s])
            elif s == T_SYM:
                terms.append(sympy.diff(expr, s))
            elif s in self.broken.values():
                raise AlgebraicLoopError(
                    f"{el.label()} is in derivative causality through an algebraic loop; "
                    "this combination is not supported"
                )
        return sympy.Add(*terms)

    def _compute(self, v: int) -> sympy.Expr:
        el = self.flat.elements[self.producer[v]]
        out = self._rule(el, v)
        if el.kind in ("I", "C", "R") and el.signals():
            out = self._resolve(out)
        return out

    def _rule(self, el: Element, v: int) -> sympy.Expr:
        name, kind = el.name, el.kind
        k = v // 2
        is_flow = v % 2 == 1
        inc = self.flat.incidence[name]
        if kind in ("Se", "Sf"):
            given = getattr(el, "value", None)
            u = self.input_of[name] if given is None else self._resolve(given)
            return u if kind == "Se" else -self._sign(name, k) * u
        if isinstance(el, OnePort):
            s = self._sign(name, k)
            own = {"I": P_VAR, "C": Q_VAR, "R": F_VAR}[kind]
            if name in self.state_of:  # integral: output from the state
                out = _subs(el.forward(), own, self.state_of[name])
                return s * out if kind == "I" else out
            dual_in = self._inp(v ^ 1)
            if kind == "R":
                if is_flow:   # f = inverse(e)
                    return s * _subs(el.backward(), E_VAR, dual_in)
                return _subs(el.forward(), F_VAR, s * dual_in)
            raise AssertionError(f"{el.label()} is in derivative causality")  # pragma: no cover
        if kind in ("0", "1"):
            strong_in = kind == "0"
            strong = next(j for j in inc if self._ein(name, j) is strong_in)
            if k != strong:
                return self._inp(self.inputs[v][0])
            terms = [self._sign(name, j) * self._inp(2 * j + (1 if strong_in else 0))
                     for j in inc if j != strong]
            return -self._sign(name, strong) * sympy.Add(*terms)
        if isinstance(el, TwoPort):
            mod = cast(sympy.Expr, el.modulus)     # resolved to an expression by the element
            if kind in ("MTF", "MGY"):
                mod = self._resolve(mod)
            k_in = inc[0] if self.bonds[inc[0]].head == name else inc[1]
            other = inc[1] if k_in == inc[0] else inc[0]
            x = self._inp(self.inputs[v][0])
            eta = cast(sympy.Expr, el.efficiency)
            if kind in ("TF", "MTF"):
                # e1 = n e2 / eta, f2 = n f1 ; or e2 = eta e1 / n, f1 = f2 / n
                if is_flow:
                    return mod * x if k == other else x / mod
                return mod * x / eta if k == k_in else eta * x / mod
            # GY: e1 = r f2, e2 = eta r f1 ; or f2 = e1 / r, f1 = e2 / (eta r)
            if not is_flow:
                return mod * x if k == k_in else eta * mod * x
            return x / mod if k == other else x / (eta * mod)
        raise AssertionError(f"no rule for {el.label()}")  # pragma: no cover

    # ------------------------------------------------------------ solving
    def _knowns(self) -> set:
        """Symbols that are not parameters: states, inputs, their derivatives, unknowns, t."""
        return (set(self.states) | set(self.input_syms) | set(self.xdot.values())
                | set(self.udot.values()) | set(self.broken.values())
                | set(self.stored_sym.values()) | {T_SYM})

    def _solve_blocks(self, unknowns: dict[sympy.Symbol, sympy.Expr], what: str) -> dict:
        """Solve u = expr(u, ...) for the unknowns (see :func:`bondgraph.loops.solve_blocks`)."""
        try:
            return solve_blocks(unknowns, knowns=self._knowns(), what=what,
                                model=self.flat.name, states=self.state_of)
        except SingularLoopError as err:
            err.storage = tuple(dict.fromkeys(err.storage + self._storage_near(err.block)))
            var_of = {sym: v for v, sym in self.broken.items()}
            bonds = [f"{u.name} is the {'effort' if var_of[u] % 2 == 0 else 'flow'} of bond "
                     f"{self.bonds[var_of[u] // 2]}" for u in err.block
                     if u in var_of and var_of[u] // 2 < len(self.bonds)]
            if bonds and err.args:
                err.args = (f"{err.args[0]}; {'; '.join(bonds)}",)
            raise

    def _storage_near(self, block) -> tuple[str, ...]:
        """Integral storage on the junctions that a singular block's bonds touch."""
        var_of = {sym: v for v, sym in self.broken.items()}
        state_el = {x: n for n, x in self.state_of.items()}
        xdot_state = {xd: x for x, xd in self.xdot.items()}
        junctions: set[str] = set()
        for u in block:
            if u in var_of:
                b = self.bonds[var_of[u] // 2]
                junctions |= {b.tail, b.head}
            elif u in xdot_state and xdot_state[u] in state_el:
                (k,) = self.flat.incidence[state_el[xdot_state[u]]]
                junctions |= {self.bonds[k].tail, self.bonds[k].head}
        near = []
        for j in sorted(junctions):
            for k in self.flat.incidence.get(j, ()):
                for end in (self.bonds[k].tail, self.bonds[k].head):
                    if end in self.state_of and end not in near:
                        near.append(end)
        return tuple(near)

    # ------------------------------------------------------------ main
    def run(self) -> Model:
        self._make_symbols()
        self._break_dependent()
        self._break_loops()
        for v in self._order():
            if v not in self.dependent:
                self.val[v] = self._compute(v)

        # raw state equations (may contain loop unknowns and state derivatives)
        raw: list[sympy.Expr] = []
        for el in self.flat.elements:
            if el.name in self.state_of:
                (k,) = self.flat.incidence[el.name]
                if el.kind == "I":
                    raw.append(self.val[2 * k])
                else:
                    raw.append(self._sign(el.name, k) * self.val[2 * k + 1])
        out_exprs = []
        for expr in self.outputs.values():
            out_exprs.append(self._resolve(expr))
        # integrator states (added while resolving outputs/moduli): x' = signal
        n_storage = len(raw)
        done = 0
        while done < len(self.integrators):
            sig = list(self.integrators)[done]
            base = Signal("flow" if sig.variable == "displacement" else "effort", sig.target)
            raw.append(self._signal_value(base))
            done += 1
        # unknowns of algebraic loops
        zsol = self._solve_blocks({z: self.val[v] for v, z in self.broken.items()
                                   if v not in self.dependent}, "algebraic loop")
        # storage in derivative causality: stored quantity and its time derivative
        dep_syms = set(self.stored_sym.values()) | {self.broken[v] for v in self.dependent}
        for v, name in self.dependent.items():
            el = self.flat.element(name)
            stored, sign = self._stored(name)
            stored = stored.xreplace(zsol)
            if stored.free_symbols & dep_syms:
                others = sorted(n for n, sym in self.stored_sym.items()
                                if sym in stored.free_symbols or
                                self.broken[self._dependent_var(n)] in stored.free_symbols)
                raise AlgebraicLoopError(
                    f"{el.label()} is in derivative causality and its input depends on the "
                    f"storage element(s) {', '.join(others or [name])}, also in derivative "
                    "causality (a higher-index model); make one of them compliant or add a "
                    "storage element between them"
                )
            zsol[self.stored_sym[name]] = stored
            zsol[self.broken[v]] = sign * self._ddt(stored, el)
        if zsol:
            # loop unknowns may hold dependent-storage unknowns: substitute to the bottom
            for u in list(zsol):
                zsol[u] = zsol[u].xreplace(zsol)
            raw = [r.xreplace(zsol) for r in raw]
            out_exprs = [o.xreplace(zsol) for o in out_exprs]
        # derivative causality: x' = raw(x, u, x')
        xd_syms = set(self.xdot.values())
        states = list(self.states)
        xd_of = [self.xdot[s] for s in states]
        implicit = any(r.free_symbols & xd_syms for r in raw)
        descriptor = None
        if implicit:
            xd_list = [self.xdot[s] for s in states]
            E = sympy.eye(len(states))
            F = []
            zero = {xd: 0 for xd in xd_list}
            for i, r in enumerate(raw):
                for j, xd in enumerate(xd_list):
                    if xd in r.free_symbols:
                        E[i, j] -= sympy.diff(r, xd)
                F.append(r.xreplace(zero))
            descriptor = (sympy.ImmutableMatrix(E), tuple(F))
            xsol = self._solve_blocks(dict(zip(xd_of, raw)), "derivative-causality block")
            rhs = [xsol[xd] for xd in xd_of]
        else:
            rhs = raw
            xsol = dict(zip(xd_of, raw))
        out_exprs = [o.xreplace(xsol) if o.free_symbols & xd_syms else o for o in out_exprs]
        states, rhs, out_exprs, descriptor = self._reuse_states(
            states, list(rhs), out_exprs, descriptor, n_storage)
        if self.broken:
            # loop solutions were substituted: one reduced fraction per coefficient
            knowns = self._knowns()
            rhs = compact_linear(list(rhs), knowns)
            out_exprs = compact_linear(list(out_exprs), knowns)
        self._check_parameter_names(list(rhs) + list(out_exprs))
        inputs = tuple(self.input_syms)
        udots = tuple(self.udot[u] for u in inputs
                      if any(self.udot[u] in r.free_symbols for r in list(rhs) + out_exprs))
        return Model(
            name=self.flat.name,
            augmented=self.aug,
            states=tuple(states),
            inputs=inputs,
            output_names=tuple(self.outputs),
            rhs=tuple(rhs),
            output_exprs=tuple(out_exprs),
            input_derivatives=udots,
            descriptor=descriptor,
            storage_states=n_storage,
            integrators=tuple((sym.name, str(sig)) for sig, sym in self.integrators.items()
                              if sym in states),
        )

    def _reuse_states(self, states, rhs, out_exprs, descriptor, n_storage):
        """Replace integrators whose integrand is a combination of state derivatives."""
        if len(states) == n_storage:
            return states, rhs, out_exprs, descriptor
        drop: dict[int, sympy.Expr] = {}
        in_rhs = set().union(*(r.free_symbols for r in rhs))
        E = descriptor[0] if descriptor is not None else None
        for i in range(n_storage, len(states)):
            x = states[i]
            if x in in_rhs:
                continue    # an integrator read by a modulus stays a state
            if E is not None and any(E[i, j] != (1 if i == j else 0) or
                                     E[j, i] != (1 if i == j else 0) for j in range(len(states))):
                continue
            combo = state_combination(rhs[i], states[:n_storage], rhs[:n_storage],
                                      self.input_syms)
            if combo is not None:
                drop[i] = combo
        if not drop:
            return states, rhs, out_exprs, descriptor
        sub = {states[i]: c for i, c in drop.items()}
        keep = [i for i in range(len(states)) if i not in drop]
        out_exprs = [o.xreplace(sub) for o in out_exprs]
        if descriptor is not None:
            E, F = descriptor
            descriptor = (sympy.ImmutableMatrix(E.extract(keep, keep)),
                          tuple(F[i] for i in keep))
        return [states[i] for i in keep], [rhs[i] for i in keep], out_exprs, descriptor


def _subs(expr: sympy.Expr, var: LawVariable, value: sympy.Expr) -> sympy.Expr:
    return expr.xreplace({var: value})


def _law_expr(el: Element) -> Optional[sympy.Expr]:
    """Expression of an element holding signals (modulus or modulated law)."""
    sigs = el.signals()
    if not sigs:
        return None
    return sympy.Add(*sigs)
