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
  A stored quantity fixed through algebraic unknowns (a nonlinear loop, a law
  with no closed-form inverse, its own displacement in a modulus) has its
  constraint differentiated instead (:mod:`~bondgraph.equations.dependent`).

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

from typing import Mapping, Optional, Union

import sympy

from .._support.gcpause import with_paused_gc
from .._support.warn import warn_user
from ..causality import AugmentedBondGraph, assign_causality, dependencies
from ..errors import (AlgebraicLoopError, BondGraphWarning, CausalityError, LawError,
                     NameClashError, OutputError)
from ..flatten import FlatGraph
from ..graph import BondGraph
from .dependent import DependentStorage
from .implicit import ImplicitPart
from .integrators import state_combination
from .loops import SingularLoopError, compact_linear, rate_coefficients, solve_blocks
from .name_policy import twin_symbols
from .record import StateEquations
from ..elements.protocol import Element, LocalVariables
from ..signals import Signal, t as T_SYM

__all__ = ["derive_equations"]

OutputSpec = Union[Mapping[str, sympy.Expr], None]


def derive_equations(graph: Union[BondGraph, AugmentedBondGraph], outputs: OutputSpec = None,
                     *, record: type[StateEquations] = StateEquations) -> StateEquations:
    """The state equations of a bond graph as a frozen record (see :func:`bondgraph.derive`).

    ``record`` is the class built: :class:`StateEquations`, or a subclass
    with the same fields (:func:`bondgraph.derive` builds a
    :class:`bondgraph.Model`, the record with its verbs).

    Parameters
    ----------
    graph : BondGraph or AugmentedBondGraph
        Causality is assigned (by SCAP) when a plain graph is given.
    outputs : mapping of str to expression, optional
        Named outputs: expressions of signals such as ``bg.flow("J")``.
    record : type
        The class of the result: :class:`StateEquations` or a subclass.

    Returns
    -------
    StateEquations
        States, inputs, ``rhs`` (x' = f(x, u)), outputs, the descriptor form
        when derivative causality is present, and the algebraic unknowns and
        residuals of laws and loops kept implicit.

    Raises
    ------
    OutputError
        An output names no element or bond, or is not an expression.
    AlgebraicLoopError
        A singular loop, or storage in derivative causality whose stored quantity
        depends on the rate of another storage element in derivative causality (a
        constraint of higher index; see :mod:`~bondgraph.equations.dependent`).

    Examples
    --------
    >>> from bondgraph import examples
    >>> eqs = derive_equations(examples.rc())
    >>> type(eqs).__name__, eqs.state_names, eqs.rhs
    ('StateEquations', ('q_C',), ((V - q_C/C)/R,))
    """
    outputs = _check_outputs(outputs)
    if isinstance(graph, AugmentedBondGraph):
        _warn_reversed(graph.flat)
        return _Deriver(graph, outputs, record).run()
    aug = assign_causality(graph)
    _warn_reversed(aug.flat)
    # An integral storage element whose effort (C) or flow (I) the junction structure
    # fixes algebraically leaves a singular loop: put such elements in derivative
    # causality, one at a time, before calling the graph ill-posed.
    forced: frozenset = frozenset()
    first: Optional[SingularLoopError] = None
    for _ in range(len(aug.integral) + 1):
        try:
            return _Deriver(aug, outputs, record).run()
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
                    return _Deriver(trial, outputs, record).run()
                except SingularLoopError:
                    keep = keep or (name, trial)
            if keep is None:
                break
            forced, aug = forced | {keep[0]}, keep[1]   # none alone: keep one, go on
    assert first is not None
    raise first


def _warn_reversed(flat: FlatGraph) -> None:
    """Warn what the elements find suspicious in their bonds' directions (a bond
    carrying power out of an I, C or R)."""
    for el in flat.elements:
        for message in el.bond_warnings(tuple(flat.bonds[k] for k in flat.incidence[el.name])):
            warn_user(message, BondGraphWarning)


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
    def __init__(self, aug: AugmentedBondGraph, outputs: dict[str, sympy.Expr],
                 record: type[StateEquations] = StateEquations) -> None:
        self.record = record
        self.aug = aug
        self.flat: FlatGraph = aug.flat
        self.outputs = outputs
        self.producer, self.inputs = dependencies(aug)
        self.bonds = self.flat.bonds
        self.nvar = 2 * len(self.bonds)
        self.val: list = [None] * self.nvar
        self.states: list[sympy.Symbol] = []
        self.state_names: list[str] = []
        self.state_of: dict[str, tuple[sympy.Symbol, ...]] = {}   # integral storage -> states
        self.integrators: dict[Signal, sympy.Symbol] = {}
        self.input_syms: list[sympy.Symbol] = []
        self.input_of: dict[str, sympy.Symbol] = {}
        self.xdot: dict[sympy.Symbol, sympy.Symbol] = {}
        self.udot: dict[sympy.Symbol, sympy.Symbol] = {}
        self.broken: dict[int, sympy.Symbol] = {}     # var -> loop unknown
        # what no symbolic solve eliminates: algebraic unknowns and residuals
        self.implicit = ImplicitPart(self)
        # derivative causality: output variable and stored quantity unknown until loops are solved
        self.dependent: dict[int, str] = {}            # output var -> element name
        self.dependent_vars: dict[str, list[int]] = {}  # element name -> its output vars
        self.stored_sym: dict[str, tuple[sympy.Symbol, ...]] = {}  # element -> its p or q
        # an integrator that is exactly an output takes the output's name
        self.preferred = {ex: n for n, ex in outputs.items() if isinstance(ex, Signal)}
        # port of each bond end: bond k is port port_at[k][0] of its tail, [1] of its head
        self.port_at: list[list[int]] = [[0, 0] for _ in self.bonds]
        for name, inc in self.flat.incidence.items():
            for port, k in enumerate(inc):
                self.port_at[k][self.bonds[k].head == name] = port

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

    def _effort_in(self, el: Element) -> list[bool]:
        """Per port of ``el``: does it receive the effort?"""
        name, hge, bonds = el.name, self.aug.stroke_at_head, self.bonds
        return [hge[k] if bonds[k].head == name else not hge[k] for k in self.flat.incidence[name]]

    def _make_symbols(self) -> None:
        self.roles: dict[str, str] = {T_SYM.name: "time"}
        for el in self.flat.elements:
            names = el.state_names(self._effort_in(el))
            if names:
                syms = tuple(sympy.Symbol(n, real=True) for n in names)
                for sym in syms:
                    self._claim(sym.name, f"the state of {el.label()}")
                    self.states.append(sym)
                    self.state_names.append(sym.name)
                self.state_of[el.name] = syms
        for el in self.flat.elements:
            name = el.input_name()
            if name is not None:
                sym = sympy.Symbol(name, real=True)
                self._claim(sym.name, f"the input of {el.label()}")
                self.input_of[el.name] = sym
                self.input_syms.append(sym)
        from .name_policy import check_element_symbols

        check_element_symbols(self.flat.elements, self.roles, self.flat.name)  # whatever assumptions
        for sym in self.states:
            self.xdot[sym] = sympy.Dummy(f"d{sym.name}/dt", real=True)
        for sym in self.input_syms:
            self.udot[sym] = sympy.Symbol(f"d{sym.name}/dt", real=True)

    def _integrator(self, sig: Signal) -> sympy.Symbol:
        if sig not in self.integrators:
            base = "x" if sig.variable == "displacement" else "h"
            stem = f"{base}_{sig.target}" + ("" if sig.port is None else f"_{sig.port}")
            name = self.preferred.get(sig) or stem
            if name in self.roles:
                name = stem
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
        """A parameter must not print like a state, an input, time or another parameter."""
        known = (set(self.states) | set(self.input_syms) | set(self.udot.values()) | {T_SYM}
                 | self.implicit.named_symbols())
        seen: dict[str, sympy.Symbol] = {}
        for ex in exprs:
            for sym in ex.free_symbols - known:
                if isinstance(sym, sympy.Dummy):
                    continue
                if sym.name in self.roles:
                    raise NameClashError(
                        f"model {self.flat.name!r}: the parameter {sym.name!r} would print "
                        f"like {self.roles[sym.name]}; rename the element or parameter"
                    )
                if seen.setdefault(sym.name, sym) != sym:
                    raise twin_symbols(self.flat.name, seen[sym.name], sym)

    # ------------------------------------------------------------ signals
    def _signal_var(self, sig: Signal) -> tuple[int, int]:
        """(var, sign) of an effort/flow signal; var is a bond variable id."""
        target = sig.target
        want_flow = sig.variable in ("flow", "displacement")
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
        variable = "flow" if want_flow else "effort"
        carried = (el.signal_port(variable) if sig.port is None else    # a field's port
                   el.port_signal(variable, sig.port))
        if carried is not None:
            port, signed = carried
            k = inc[port]
            return 2 * k + (1 if want_flow else 0), (self._sign(target, k) if signed else 1)
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
            i = (el.energy_variable(sig.variable) if sig.port is None else
                 el.port_energy_variable(sig.variable, sig.port, self._effort_in(el)))
            if i is not None:
                # its states, then (derivative causality) its stored quantities: algebraic
                # functions (p = I*f, q = C*e), not states
                held = self.state_of.get(sig.target, ()) + self.stored_sym.get(sig.target, ())
                if i < len(held):
                    return held[i]
        self._signal_var(sig)  # validate the target
        return self._integrator(sig)

    def _resolve(self, expr: sympy.Expr) -> sympy.Expr:
        sigs = {s: self._signal_value(s) for s in expr.free_symbols if isinstance(s, Signal)}
        return expr.xreplace(sigs) if sigs else expr

    # ------------------------------------------------------------ ordering
    @staticmethod
    def _unknown(v: int) -> sympy.Symbol:
        """Loop unknown for bond variable v: a Dummy, so no user name can clash with it."""
        return sympy.Dummy(f"{'e' if v % 2 == 0 else 'f'}_{v // 2 + 1}", real=True)

    def _break_dependent(self) -> None:
        for el in self.flat.elements:
            effort_in = self._effort_in(el)
            ports = el.derivative_ports(effort_in)
            if not ports:
                continue
            name, inc = el.name, self.flat.incidence[el.name]
            outs = self.dependent_vars[name] = []
            for port in ports:
                k = inc[port]
                v = 2 * k + 1 if effort_in[port] else 2 * k     # its output variable
                self.dependent[v] = name
                tag = f"_{port + 1}" if len(inc) > 1 else ""
                self.broken[v] = sympy.Dummy(f"{'f' if v % 2 else 'e'}_{name}{tag}", real=True)
                outs.append(v)
            self.stored_sym[name] = tuple(sympy.Dummy(n, real=True)
                                          for n in el.stored_names(effort_in))

    def _break_loops(self) -> None:
        for name in self.aug.arbitrary:      # each input of an arbitrarily-causal element
            for k in self.flat.incidence[name]:
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

    def _local(self, el: Element, read) -> "_Local":
        """The element's view of its variables; ``read`` gives a bond variable's value."""
        return _Local(self, el.name, self.flat.incidence[el.name], read)

    def _compute(self, v: int) -> sympy.Expr:
        el = self.flat.elements[self.producer[v]]
        k = v // 2
        local, port = self._local(el, self._inp), self.port_at[k][self.bonds[k].head == el.name]
        try:
            return el.output(local, port)
        except LawError:          # no closed form: keep the output as an algebraic unknown
            z = self.implicit.law_unknown(el, v)
            residual = el.implicit_output(local, port, z)
            if residual is None:
                raise
            self.implicit.add_law(z, residual, el, v)
            return z

    # ------------------------------------------------------------ solving
    def _knowns(self) -> set:
        """Symbols that are not parameters: states, inputs, their derivatives, unknowns, t."""
        return (set(self.states) | set(self.input_syms) | set(self.xdot.values())
                | set(self.udot.values()) | set(self.broken.values())
                | {x for xs in self.stored_sym.values() for x in xs} | {T_SYM}
                | self.implicit.law_symbols())

    def _solve_blocks(self, unknowns: dict[sympy.Symbol, sympy.Expr], what: str,
                      implicit: Optional[list] = None) -> dict:
        """Solve u = expr(u, ...) for the unknowns (see :func:`bondgraph.equations.loops.solve_blocks`)."""
        try:
            # one key per state; an element with several states has keys name, name\0 1, ...
            states = {name + (f"\0{i}" if i else ""): x for name, xs in self.state_of.items()
                      for i, x in enumerate(xs)}
            return solve_blocks(unknowns, knowns=self._knowns(), what=what,
                                model=self.flat.name, states=states, implicit=implicit)
        except SingularLoopError as err:
            storage = tuple(n.split("\0")[0] for n in err.storage)
            err.storage = tuple(dict.fromkeys(storage + self._storage_near(err.block)))
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
        state_el = {x: n for n, xs in self.state_of.items() for x in xs}
        xdot_state = {xd: x for x, xd in self.xdot.items()}
        junctions: set[str] = set()
        for u in block:
            if u in var_of:
                b = self.bonds[var_of[u] // 2]
                junctions |= {b.tail, b.head}
            elif u in xdot_state and xdot_state[u] in state_el:
                for k in self.flat.incidence[state_el[xdot_state[u]]]:
                    junctions |= {self.bonds[k].tail, self.bonds[k].head}
        near = []
        for j in sorted(junctions):
            for k in self.flat.incidence.get(j, ()):
                for end in (self.bonds[k].tail, self.bonds[k].head):
                    if end in self.state_of and end not in near:
                        near.append(end)
        return tuple(near)

    # ------------------------------------------------------------ main
    @with_paused_gc
    def run(self) -> StateEquations:
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
                raw.extend(el.state_derivatives(self._local(el, self.val.__getitem__)))
        out_exprs = []
        for expr in self.outputs.values():
            out_exprs.append(self._resolve(expr))
        # integrator states (added while resolving outputs/moduli): x' = signal
        n_storage = len(raw)
        done = 0
        while done < len(self.integrators):
            sig = list(self.integrators)[done]
            base = sig.of("flow" if sig.variable == "displacement" else "effort")
            raw.append(self._signal_value(base))
            done += 1
        # unknowns of algebraic loops
        loops: list = []
        zsol = self._solve_blocks({z: self.val[v] for v, z in self.broken.items()
                                   if v not in self.dependent}, "algebraic loop", loops)
        self.implicit.add_loops(loops)
        # storage in derivative causality: stored quantities and their rates (index
        # reduction where they hold algebraic unknowns: see equations.dependent)
        zdsol = DependentStorage(self, zsol).run() or {}
        if zsol:
            # loop unknowns may hold dependent-storage unknowns: substitute to the bottom
            for u in list(zsol):
                zsol[u] = zsol[u].xreplace(zsol)
            raw = [r.xreplace(zsol) for r in raw]
            out_exprs = [o.xreplace(zsol) for o in out_exprs]
            self.implicit.substitute(zsol)
        if zdsol:       # the rates of differentiated algebraic unknowns, in terms of x'
            raw = [r.xreplace(zdsol) for r in raw]
            out_exprs = [o.xreplace(zdsol) for o in out_exprs]
            self.implicit.substitute(zdsol)
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
                for j, c in rate_coefficients(r, xd_list):
                    E[i, j] -= c
                F.append(r.xreplace(zero))
            descriptor = (sympy.ImmutableMatrix(E), tuple(F))
            xsol = self._solve_blocks(dict(zip(xd_of, raw)), "derivative-causality block")
            rhs = [xsol[xd] for xd in xd_of]
        else:
            rhs = raw
            xsol = dict(zip(xd_of, raw))
        out_exprs = [o.xreplace(xsol) if o.free_symbols & xd_syms else o for o in out_exprs]
        self.implicit.substitute(xsol, only=xd_syms)   # a loop holding a dependent rate
        if self.broken:
            # loop solutions were substituted: one reduced fraction per coefficient (before
            # the integrators are matched against the state derivatives, on small expressions)
            rhs = compact_linear(list(rhs), self._knowns())
        states, rhs, out_exprs, descriptor = self._reuse_states(
            states, list(rhs), out_exprs, descriptor, n_storage)
        if self.broken:
            out_exprs = compact_linear(list(out_exprs), self._knowns())
        algebraic, residuals, origin, rhs, out_exprs = self.implicit.finish(
            set(self.xdot.values()), rhs, out_exprs)
        if descriptor is not None and algebraic:
            rename = self.implicit.renaming()
            descriptor = (descriptor[0].xreplace(rename),
                          tuple(f.xreplace(rename) for f in descriptor[1]))
        self._check_parameter_names(list(rhs) + list(out_exprs) + list(residuals))
        inputs = tuple(self.input_syms)
        udots = tuple(self.udot[u] for u in inputs if any(
            self.udot[u] in r.free_symbols for r in list(rhs) + out_exprs + list(residuals)))
        return self.record(
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
            algebraic=algebraic,
            residuals=residuals,
            algebraic_origin=origin,
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


def _law_expr(el: Element) -> Optional[sympy.Expr]:
    """Expression of an element holding signals (modulus or modulated law)."""
    sigs = el.signals()
    if not sigs:
        return None
    return sympy.Add(*sigs)


class _Local(LocalVariables):
    """An element's variables during derivation (the protocol's :class:`LocalVariables`)."""

    __slots__ = ("d", "name", "inc", "read", "count")

    def __init__(self, deriver: _Deriver, name: str, inc: tuple[int, ...], read) -> None:
        self.d = deriver
        self.name = name
        self.inc = inc
        self.read = read
        self.count = len(inc)

    @property
    def states(self) -> tuple:      # type: ignore[override]
        return self.d.state_of.get(self.name, ())

    @property
    def input_symbol(self) -> Optional[sympy.Symbol]:   # type: ignore[override]
        return self.d.input_of.get(self.name)

    def sign(self, port: int) -> int:
        return 1 if self.d.bonds[self.inc[port]].head == self.name else -1

    def into(self, port: int) -> bool:
        return self.d.bonds[self.inc[port]].head == self.name

    def effort_in(self, port: int) -> bool:
        k = self.inc[port]
        hge = self.d.aug.stroke_at_head[k]
        return hge if self.d.bonds[k].head == self.name else not hge

    def input(self, port: int) -> sympy.Expr:
        k = self.inc[port]
        hge = self.d.aug.stroke_at_head[k]
        return self.read(2 * k if (hge if self.d.bonds[k].head == self.name else not hge)
                         else 2 * k + 1)

    def resolve(self, expr: sympy.Expr) -> sympy.Expr:
        return self.d._resolve(expr)

