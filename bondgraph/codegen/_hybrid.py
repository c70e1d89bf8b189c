r"""The modes of a switched model as equations over one mode-independent state (private).

A switched model's modes have different states (a clutch engaged has one
momentum, disengaged two).  Generated code and FMUs need one state vector,
so it is the switched simulation's own mode-independent state
(:mod:`bondgraph.hybrid.events`): the stored quantity of every storage
element (``p_J1``, ``p_J2``, ``q_C``: also those in derivative causality),
then every integrated displacement/momentum signal.  Per reachable mode this
module derives, in those variables:

* ``rhs`` -- their time derivatives: a state of the mode is its own
  equation; a stored quantity in derivative causality, ``q = q(t, x)``, has
  ``dq/dt = (dq/dx) x' + dq/dt`` (chain rule, symbolic);
* ``outputs`` -- the user's outputs;
* ``guards`` -- one per switch with a guard (``>= 0`` while consistent);
* ``enter`` -- the re-initialisation on entering the mode: the projection of
  :mod:`bondgraph.hybrid` (``x = (M^T Q M)^-1 M^T Q (q_old - c)`` with the
  stored quantities ``q = M x + c`` and the energy Hessian ``Q``: total
  momentum conserved when two inertias lock, a shorted capacitor emptied),
  solved symbolically; ``None`` when the mode has no storage in derivative
  causality (nothing jumps).  A mode whose constraint is not affine in its
  states, or whose stored energy is not quadratic (``Q`` depends on the
  state), has no linear re-initialisation and is refused with
  :class:`SwitchedExportError` naming its switches.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.hybrid import SwitchedModel, library
>>> sp = prepare_switched(SwitchedModel(library.clutch()), reserved=())
>>> sp.state_names, [str(m) for m in sp.modes]
(('p_J1', 'p_J2'), ['K off', 'K on'])
>>> sp.enter[0]
(J1*(p_J1 + p_J2)/(J1 + J2), J2*(p_J1 + p_J2)/(J1 + J2))
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterable, Mapping, Optional

import sympy

from ..signals import Signal
from ..signals import t as T_SYM
from ._common import CodegenError, check_text, sanitize

__all__ = ["SwitchedExportError", "SwitchedPrepared", "prepare_switched"]


class SwitchedExportError(CodegenError):
    """A switched model cannot be exported: a mode whose re-initialisation is not a linear
    map, input derivatives, no reachable mode.  The message names the mode's switches."""


@dataclass(frozen=True)
class SwitchedPrepared:
    """A switched model's reachable modes in target identifiers (see the module docstring).

    ``state_names`` are the mode-independent state (stored quantities, then
    integrated signals); ``mode_on[k]`` has bit ``i`` set when switch ``i`` is
    on in mode ``k``; ``guard_switch[j]`` is the switch of guard ``j``.
    Expressions use symbols named by the ``*_ids`` and ``Symbol('t')``.
    """

    name: str
    switches: tuple[str, ...]
    modes: tuple[Any, ...]
    mode_on: tuple[int, ...]
    initial_on: int
    guard_switch: tuple[int, ...]
    self_switched: int
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    parameter_names: tuple[str, ...]
    state_ids: tuple[str, ...]
    input_ids: tuple[str, ...]
    output_ids: tuple[str, ...]
    parameter_ids: tuple[str, ...]
    rhs: tuple[tuple[sympy.Expr, ...], ...]
    outputs: tuple[tuple[sympy.Expr, ...], ...]
    guards: tuple[tuple[sympy.Expr, ...], ...]
    enter: tuple[Optional[tuple[sympy.Expr, ...]], ...]
    energy: sympy.Expr
    defaults: Optional[tuple[float, ...]]
    parameters: tuple[sympy.Symbol, ...] = ()
    #: no algebraic unknowns: each mode is explicit (the shared C printer asks)
    algebraic_ids: tuple[str, ...] = ()

    @property
    def taken(self) -> set[str]:
        return set(self.state_ids) | set(self.input_ids) | set(self.parameter_ids) | {"t"}

    def mode_label(self, k: int) -> str:
        return str(self.modes[k])


def _refuse(sm, mode, why: str) -> SwitchedExportError:
    return SwitchedExportError(f"model {sm.name!r}, mode ({mode}): {why}")


def prepare_switched(sm, *, reserved: Iterable[str], matlab: bool = False,
                     defaults: Optional[Mapping] = None) -> SwitchedPrepared:
    """The reachable modes of switched model ``sm`` over one state, in target identifiers.

    Raises
    ------
    SwitchedExportError
        No reachable mode; a mode with input derivatives, with storage whose
        re-initialisation is not a linear map, or with an integrated signal
        that another mode does not define (the message names the mode).
    CodegenError
        A name no escape can carry.
    """
    from ..hybrid import ModeSet

    if not isinstance(sm, ModeSet):
        raise CodegenError(f"expected a switched model (bondgraph.hybrid.SwitchedModel); got "
                           f"{type(sm).__name__}")
    modes = sm.reachable_modes
    if not modes:
        raise SwitchedExportError(f"model {sm.name!r} has no reachable consistent mode")
    fulls = [sm.derived(m).full for m in modes]
    nq = len(sm.energy_signals)
    # ---- the mode-independent state: stored quantities, then integrated signals
    labels = [str(s) for s in sm.energy_signals]
    for full in fulls:
        for k in range(nq):
            ex = full.output_exprs[full.output_names.index(f"hyb_E{k}")]
            if ex in full.states[: full.storage_states]:
                labels[k] = ex.name
    integ: dict[str, str] = {}       # signal -> state name: a user output that is the signal, else it
    for full in fulls:
        for name, sig in full.integrators:
            integ.setdefault(sig, name)
    for sig, first in integ.items():
        named = [k for k, e in sm.user_outputs.items() if isinstance(e, Signal) and str(e) == sig]
        integ[sig] = str(named[0]) if named else (first if not first.startswith("hyb_") else sig)
    sig_list = list(integ)
    Q = [sympy.Dummy(f"q{k}", real=True) for k in range(nq)]
    Z = [sympy.Dummy(f"z{k}", real=True) for k in range(len(sig_list))]
    s_vars = Q + Z
    qs, H = sm.energy()
    H = H.xreplace(dict(zip(qs, Q)))
    # ---- parameters (the modes' and the guards'), inputs
    params: dict[str, sympy.Symbol] = {}
    for full in fulls:
        for p in full.parameters:
            params.setdefault(p.name, p)
    guarded = [i for i, n in enumerate(sm.switches) if sm.element(n).guard(True) is not None]
    for i in guarded:
        for on in (True, False):
            g = sm.element(sm.switches[i]).guard(on)
            for s in sorted(g.free_symbols if g is not None else (), key=str):
                if not isinstance(s, Signal) and s != T_SYM:
                    params.setdefault(s.name, s)
    for s in sorted(H.free_symbols - set(Q), key=str):     # a storage parameter in no mode's equations
        params.setdefault(s.name, s)
    inputs: list = []
    for full in fulls:
        inputs += [s for s in full.inputs if s not in inputs]
    # ---- per mode
    rhs_all, out_all, guard_all, enter_all = [], [], [], []
    n_user = len(sm.user_outputs)
    for mode, full in zip(modes, fulls):
        if full.input_derivatives:
            raise _refuse(sm, mode, "its equations need the time derivatives of the inputs "
                          f"{', '.join(s.name for s in full.input_derivatives)}; generated code "
                          "and FMUs carry input values only: give that source a value= "
                          "expression of time bondgraph.t")
        outs = dict(zip(full.output_names, full.output_exprs))
        q_exprs = [outs[f"hyb_E{k}"] for k in range(nq)]
        s_exprs = [outs[f"hyb_S{k}"] for k in range(len(sm.guard_signals))]
        x = list(full.states)
        n = full.storage_states
        sub: dict = {}
        for j in range(n):
            rows = [k for k, e in enumerate(q_exprs) if e == x[j]]
            if not rows:  # pragma: no cover - a storage state is a stored quantity
                raise _refuse(sm, mode, f"state {x[j]} is no stored quantity")
            sub[x[j]] = Q[rows[0]]
        own = {sig for _, sig in full.integrators}
        for j, (_, sig) in enumerate(full.integrators):
            sub[x[n + j]] = Z[sig_list.index(sig)]
        f = [e.xreplace(sub) for e in full.rhs]
        fx = dict(zip(x, full.rhs))
        sig_expr: dict = {}
        for sig in sig_list:
            if sig in own:
                continue
            hit = [k for k, s in enumerate(sm.guard_signals) if str(s) == sig]
            if not hit:
                raise _refuse(sm, mode, f"the integrated signal {sig} is not defined in this mode")
            sig_expr[sig] = s_exprs[hit[0]]

        def rate(expr: sympy.Expr, mode=mode, full=full, fx=fx, sub=sub) -> sympy.Expr:
            """d expr/dt along the mode's equations (chain rule)."""
            if any(sympy.diff(expr, u) != 0 for u in full.inputs):
                raise _refuse(sm, mode, f"{expr} depends on an input: its rate needs the input's "
                              "time derivative")
            out = sympy.diff(expr, T_SYM)
            for xs, fs in fx.items():
                d = sympy.diff(expr, xs)
                if d != 0:
                    out += d * fs
            return out.xreplace(sub)

        rows_of = {sub[x[j]]: x[j] for j in range(n)}
        rhs = []
        for k in range(nq):
            rhs.append(f[x.index(rows_of[Q[k]])] if Q[k] in rows_of else rate(q_exprs[k]))
        for sig in sig_list:
            if sig in own:
                j = next(jj for jj, (_, s2) in enumerate(full.integrators) if s2 == sig)
                rhs.append(f[n + j])
            else:
                rhs.append(rate(sig_expr[sig]))
        rhs_all.append(tuple(rhs))
        out_all.append(tuple(e.xreplace(sub) for e in full.output_exprs[:n_user]))
        sig_map = dict(zip(sm.guard_signals, s_exprs))
        gs = []
        for i in guarded:
            raw = sm.element(sm.switches[i]).guard(mode.is_on(sm.switches[i]))
            assert raw is not None      # guarded: the switch answers a guard in both states
            g = raw.xreplace(sig_map)
            left = [s for s in g.free_symbols if isinstance(s, Signal)]
            if left:
                raise _refuse(sm, mode, f"the guard of switch {sm.switches[i]!r} reads {left[0]}, "
                              "which this mode does not define")
            gs.append(g.xreplace(sub))
        guard_all.append(tuple(gs))
        enter_all.append(_enter(sm, mode, full, q_exprs, x, n, sub, Q, Z, H, sig_list, own, sig_expr))
    # ---- names to identifiers
    state_names = tuple(labels) + tuple(integ[s] for s in sig_list)
    plist = [params[k] for k in sorted(params)]
    check_text(sm.name, what="model name")
    for what, group in (("state", state_names), ("input", [s.name for s in inputs]),
                        ("output", list(sm.user_outputs)), ("parameter", [p.name for p in plist]),
                        ("switch", sm.switches)):
        for text in group:
            check_text(text, what=f"model {sm.name!r}: {what} name")
    names = list(state_names) + [s.name for s in inputs] + [p.name for p in plist]
    ids = sanitize(names, reserved=set(reserved), matlab=matlab)
    ns, m = len(state_names), len(inputs)
    output_ids = sanitize([str(k) for k in sm.user_outputs], reserved=set(reserved), matlab=matlab)
    swap: dict = {T_SYM: sympy.Symbol("t", real=True)}
    for sym, ident in zip(s_vars + list(inputs), ids[: ns + m]):
        swap[sym] = sympy.Symbol(ident, real=True)
    by_name = dict(zip([p.name for p in plist], ids[ns + m:]))

    def ren(e: sympy.Expr) -> sympy.Expr:
        local = dict(swap)
        for s in e.free_symbols:
            if s not in local and getattr(s, "name", None) in by_name and not isinstance(s, sympy.Dummy):
                local[s] = sympy.Symbol(by_name[s.name], real=True)
        stray = e.free_symbols - set(local)
        if stray:  # pragma: no cover - modes hold states, inputs, parameters and t only
            raise CodegenError(f"model {sm.name!r}: unexpected symbols {stray} in the equations")
        return e.xreplace(local)

    default_values = None
    if defaults is not None:
        from ..numeric.resolve import resolve_parameters

        known = {k for full in fulls for k in full.known_parameters}
        default_values = tuple(resolve_parameters(plist, defaults, model=sm.name, known=known).tolist())
        from ..hybrid._numeric import nonfinite, periods

        subs = dict(zip(plist, default_values))
        why = nonfinite(sm, modes, fulls, subs) or periods(sm, subs)[1]
        if why:
            raise SwitchedExportError(why)
    mode_on = tuple(sum(1 << i for i, n_ in enumerate(sm.switches) if md.is_on(n_)) for md in modes)
    return SwitchedPrepared(
        name=sm.name, switches=tuple(sm.switches), modes=tuple(modes), mode_on=mode_on,
        initial_on=sum(1 << i for i, n_ in enumerate(sm.switches) if sm.initial.is_on(n_)),
        guard_switch=tuple(guarded),
        self_switched=sum(1 << i for i, n_ in enumerate(sm.switches) if sm.element(n_).self_switched),
        state_names=state_names, input_names=tuple(s.name for s in inputs),
        output_names=tuple(str(k) for k in sm.user_outputs), parameter_names=tuple(p.name for p in plist),
        state_ids=ids[:ns], input_ids=ids[ns:ns + m], output_ids=output_ids, parameter_ids=ids[ns + m:],
        rhs=tuple(tuple(ren(e) for e in r) for r in rhs_all),
        outputs=tuple(tuple(ren(e) for e in o) for o in out_all),
        guards=tuple(tuple(ren(e) for e in g) for g in guard_all),
        enter=tuple(None if e is None else tuple(ren(x_) for x_ in e) for e in enter_all),
        energy=ren(H), defaults=default_values, parameters=tuple(plist))


def _enter(sm, mode, full, q_exprs, x, n, sub, Q, Z, H, sig_list, own, sig_expr):
    """The state after entering ``mode`` as expressions of the state before (None: identity)."""
    dependent = tuple(full.augmented.derivative)
    if not dependent and not sig_expr:
        return None
    xs = x[:n]
    zero = {s: 0 for s in x}
    if dependent:
        M = sympy.Matrix(q_exprs).jacobian(xs) if xs else sympy.zeros(len(q_exprs), 0)
        if M.free_symbols & set(x):
            raise _refuse(sm, mode, f"{', '.join(dependent)} in derivative causality with stored "
                          "quantities that are not affine in the mode's states: the "
                          "re-initialisation at entering it is not a linear map")
        Qh = sympy.hessian(H, Q) if Q else sympy.zeros(0, 0)
        if n and Qh.free_symbols & set(Q):
            raise _refuse(sm, mode, f"{', '.join(dependent)} go into derivative causality with a "
                          "stored energy that is not quadratic: the re-initialisation (a projection "
                          "in the energy metric) is not a linear map; only linear storage can be "
                          "exported with this mode")
        c = sympy.Matrix([sympy.sympify(e, strict=True).xreplace(zero) for e in q_exprs])
        qv = sympy.Matrix(Q)
        if n:
            A = M.T * Qh * M
            sol = A.LUsolve(M.T * Qh * (qv - c))
            sol = sympy.Matrix([sympy.factor(sympy.cancel(e)) for e in sol])
            q_new = M * sol + c
        else:
            sol, q_new = sympy.zeros(0, 1), c
        q_new = [sympy.factor(sympy.cancel(e)) for e in q_new]
        new_x = dict(zip(xs, list(sol)))
    else:
        q_new = list(Q)
        new_x = {xs_: sub[xs_] for xs_ in xs}
    for j, (_, sig) in enumerate(full.integrators):
        new_x[x[n + j]] = Z[sig_list.index(sig)]
    z_new = [Z[i] if sig in own else sympy.sympify(sig_expr[sig], strict=True).xreplace(new_x)
             for i, sig in enumerate(sig_list)]
    return tuple(q_new) + tuple(z_new)
