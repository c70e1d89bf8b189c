"""Fault diagnosis: analytical redundancy relations and the fault signature matrix.

A model's outputs are its sensors.  With the sensors in derivative causality
(Samantaray and Ould Bouamama: a detector dualised into a source of its
measured variable), each measured variable fixes the storage element it
reads, and the causal paths carry that knowledge on: a state equation
``x_j' = A_j x + B_j u`` whose state is known and that holds one unknown state
gives it.  The propagation here runs on the model's equations:

* knowns: the inputs ``u(t)``, the measurements ``y(t)`` and their derivatives;
* an equation with a single unknown state is solved for it (a sensor equation
  ``y_i = C_i x + D_i u``, or a state equation, whose own state counts as
  unknown until known, its derivative then being the derivative of a known
  expression);
* the equations left over with every variable known are the *analytical
  redundancy relations* (ARRs): ``r_k(u, y, y', ...; theta) = 0`` when nothing
  is faulty.

The *fault signature matrix* says which components appear in which ARR: an
element through its parameters, a source through its input, a sensor through
its measurement.  A component is detectable when it appears in some ARR and
isolable when no other component has the same signature.  Equations on which
the propagation stalls (two unknown states in every remaining equation) give
no ARR here; :attr:`FaultDiagnosis.unresolved` lists them.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.structure import fault_signatures
>>> g = bg.BondGraph("tank")
>>> z = bg.Zero("z")
>>> g.add(bg.Sf("Qp"), z, bg.C("C1"), bg.R("R1"))
>>> for a, b in [("Qp", z), (z, "C1"), (z, "R1")]: _ = g.connect(a, b)
>>> fd = fault_signatures(bg.derive(g, outputs={"De1": bg.effort("z")}))
>>> fd.arrs
(-C1*Derivative(De1(t), t) + Qp(t) - De1(t)/R1,)
>>> fd.detectable, fd.isolable
(('C1', 'R1', 'Qp', 'De1'), ())
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Optional

import numpy as np
import sympy

from .._support.sympify import parameter_symbols
from ..parameters import real_value
from ..model import Model
from ..signals import t as T
from ._generic import StructureError, linear_form

__all__ = ["FaultDiagnosis", "fault_signatures"]


@dataclass(frozen=True)
class FaultDiagnosis:
    """ARRs and fault signature matrix of a model whose outputs are sensors (immutable).

    Attributes
    ----------
    model : str
    arrs : tuple of sympy.Expr
        ``r_k = 0`` in the fault-free case; functions ``u(t)``, ``y(t)`` of :data:`bondgraph.t`.
    sources : tuple of str
        The equation each ARR comes from (``"state p_m"``, ``"sensor y1"``).
    components : tuple of str
        Rows of the signature matrix: elements with parameters, inputs, sensors.
    signatures : tuple of tuple of int
        ``signatures[c][k]`` is 1 when component ``c`` appears in ARR ``k``.
    solved : tuple of (str, sympy.Expr)
        How each state was found from the measurements.
    unresolved : tuple of str
        Equations left with unknown states (no ARR from them).
    """

    model: str
    arrs: tuple[sympy.Expr, ...]
    sources: tuple[str, ...]
    components: tuple[str, ...]
    signatures: tuple[tuple[int, ...], ...]
    solved: tuple[tuple[str, sympy.Expr], ...]
    unresolved: tuple[str, ...]

    def signature(self, component: str) -> tuple[int, ...]:
        if component not in self.components:
            raise StructureError(f"model {self.model!r} has no component {component!r}; "
                                 f"components: {', '.join(self.components)}")
        return self.signatures[self.components.index(component)]

    @property
    def detectable(self) -> tuple[str, ...]:
        return tuple(c for c, s in zip(self.components, self.signatures) if any(s))

    @property
    def isolable(self) -> tuple[str, ...]:
        out = []
        for c, s in zip(self.components, self.signatures):
            if any(s) and sum(1 for o in self.signatures if o == s) == 1:
                out.append(c)
        return tuple(out)

    def residuals(self, t, inputs: Mapping[str, np.ndarray], measurements: Mapping[str, np.ndarray],
                  values: Mapping[str, float]) -> np.ndarray:
        """Residuals of every ARR on sampled data (rows: ARRs, columns: samples).

        Derivatives of the sampled signals are estimated by :func:`numpy.gradient`
        (second-order differences, exact for quadratics), so the data should be
        smooth and finely sampled.

        Raises
        ------
        StructureError
            Times that are not finite or not strictly monotonic; a signal that
            is not a finite 1-D array as long as ``t``; fewer samples than the
            derivatives the ARRs need (``2 k + 1`` for a ``k``-th derivative);
            a parameter value that is not a finite real number.
        """
        for what, given in (("inputs", inputs), ("measurements", measurements),
                            ("values", values)):
            if not isinstance(given, Mapping):
                raise StructureError(f"residuals: {what} must be a mapping of name to "
                                     f"{'number' if what == 'values' else 'samples'}; got "
                                     f"{type(given).__name__}")
        need = max((d.derivative_count for r in self.arrs for d in r.atoms(sympy.Derivative)),
                   default=0)
        t = _samples(t, "t")
        if t.ndim != 1:
            raise StructureError(f"residuals: t must be a 1-D array of sample times; got shape "
                                 f"{t.shape}")
        steps = np.diff(t)
        if not (np.all(steps > 0) or np.all(steps < 0)):
            raise StructureError("residuals: the sample times t must be strictly increasing (or "
                                 "strictly decreasing)")
        fewest = max(2 * need + 1, 1)
        if len(t) < fewest:
            raise StructureError(
                f"residuals: {len(t)} sample(s) are too few: the ARRs use derivatives up to order "
                f"{need}, estimated from at least {fewest} samples (a central difference per "
                "order); give more samples")
        arrays: dict = {}
        subs: dict = {}
        k = 0
        for what, given in (("input", inputs), ("measurement", measurements)):
            for name, data in given.items():
                f = sympy.Function(name)(T)
                d = _samples(data, f"{what} {name!r}")
                if d.shape != t.shape:
                    raise StructureError(f"residuals: {what} {name!r} has shape {d.shape}, but t "
                                         f"has {len(t)} samples; give one value per sample time")
                for order in range(need + 1):
                    sym = sympy.Symbol(f"_sig{k}")
                    k += 1
                    subs[f if order == 0 else sympy.Derivative(f, (T, order))] = sym
                    arrays[sym] = d
                    if order < need:
                        d = np.gradient(d, t, edge_order=2 if len(t) > 2 else 1)
        values = {str(getattr(name, "name", name)): real_value(v, str(getattr(name, "name", name)),
                                                               "residuals: ")
                  for name, v in values.items()}
        out = []
        for r in self.arrs:
            syms = {s: values[s.name] for s in r.free_symbols - {T} if s.name in values}
            expr = r.subs(syms)
            expr = expr.xreplace({key: subs[key] for key in
                                  sorted(subs, key=lambda e: -sympy.count_ops(e))
                                  if expr.has(key)})
            left = [a for a in expr.atoms(sympy.Function, sympy.Derivative) if a not in subs]
            if left or (expr.free_symbols - set(arrays) - {T}):
                missing = sorted({str(a) for a in left} |
                                 {s.name for s in expr.free_symbols - set(arrays) - {T}})
                raise StructureError(f"residuals: no data or value for {', '.join(missing)}")
            args = sorted(expr.free_symbols & set(arrays), key=lambda s: s.name)
            f = sympy.lambdify(args, expr, "numpy")
            out.append(np.broadcast_to(f(*[arrays[a] for a in args]), t.shape))
        return np.array(out)

    def __str__(self) -> str:
        lines = [f"analytical redundancy relations of {self.model!r}"]
        for k, (r, src) in enumerate(zip(self.arrs, self.sources), 1):
            lines.append(f"  ARR{k} (from {src}): {r} = 0")
        if self.unresolved:
            lines.append(f"  no ARR from: {', '.join(self.unresolved)}")
        width = max((len(c) for c in self.components), default=4)
        head = " ".join(f"ARR{k}" for k in range(1, len(self.arrs) + 1))
        lines.append(f"  {'':{width}} {head}  D I")
        iso = set(self.isolable)
        det = set(self.detectable)
        for c, s in zip(self.components, self.signatures):
            cells = " ".join(f"{v:>{len('ARR') + len(str(k + 1))}}" for k, v in enumerate(s))
            lines.append(f"  {c:{width}} {cells}  {int(c in det)} {int(c in iso)}")
        return "\n".join(lines)


def _samples(data, what: str) -> np.ndarray:
    """Sampled data as a float array: real, finite numbers (text is never parsed)."""
    arr = np.asarray(data)
    if arr.dtype.kind not in "iuf":
        raise StructureError(f"residuals: {what} must be real numbers; got {arr.dtype} values")
    arr = arr.astype(float)
    if not np.all(np.isfinite(arr)):
        i = int(np.argmax(~np.isfinite(arr.ravel())))
        raise StructureError(f"residuals: {what} must be finite; sample {i} is {arr.ravel()[i]}")
    return arr


def fault_signatures(model: Model) -> FaultDiagnosis:
    """ARRs and the fault signature matrix of a linear model whose outputs are sensors.

    Parameters
    ----------
    model : Model
        A linear model (:func:`bondgraph.derive`) with one output per sensor.

    Returns
    -------
    FaultDiagnosis

    Raises
    ------
    StructureError
        A nonlinear model, a model with input derivatives, or a relation or
        solved state past :data:`FAULT_SIZE_BUDGET` expression nodes.
    """
    lf = linear_form(model)
    if len(lf.Bs) > 1 or len(lf.Ds) > 1:
        raise StructureError(f"model {model.name!r}: input derivatives are not supported")
    x = list(model.states)
    u_fun = {u: sympy.Function(u.name)(T) for u in model.inputs}
    y_fun = [sympy.Function(name)(T) for name in lf.outputs]
    A, B, C, D = lf.A, lf.Bs[0], lf.C, lf.Ds[0]
    u_vec = sympy.Matrix([u_fun[u] for u in model.inputs])
    # equations: (kind, index, expression = 0 in x and known functions)
    eqs: list[tuple[str, Optional[int], sympy.Expr]] = []
    for i, name in enumerate(lf.outputs):
        eqs.append((f"sensor {name}", None, y_fun[i] - (C[i, :] * sympy.Matrix(x))[0]
                    - ((D[i, :] * u_vec)[0] if u_vec.rows else 0)))
    for row, s in enumerate(x):
        rhs = (A[row, :] * sympy.Matrix(x))[0] + ((B[row, :] * u_vec)[0] if u_vec.rows else 0)
        eqs.append((f"state {s.name}", row, rhs))
    known: dict = {}
    used = [False] * len(eqs)

    def unknowns(k: int) -> set:
        _, j, ex = eqs[k]
        us = {s for s in x if s not in known and ex.has(s)}
        if j is not None and x[j] not in known:
            us.add(x[j])
        return us

    progress = True
    while progress:
        progress = False
        for k in range(len(eqs)):
            if used[k]:
                continue
            us = unknowns(k)
            if len(us) != 1:
                continue
            (v,) = us
            label, j, ex = eqs[k]
            if j is not None and x[j] == v:
                continue       # its own state, unknown: an ODE, not an algebraic relation
            full = _substitute(ex, known, x, j)
            _within_budget(full, model.name, f"the {label} equation, solving for {v.name}")
            sol = _solve_linear(full, v, sympy.diff(ex, v).xreplace(known))
            if sol is None:
                continue
            _within_budget(sol, model.name, f"{v.name}, solved from the {label} equation")
            known[v] = sol
            used[k] = True
            progress = True
    arrs, srcs, unresolved = [], [], []
    for k, (label, j, ex) in enumerate(eqs):
        if used[k]:
            continue
        if unknowns(k):
            unresolved.append(label)
            continue
        r = _substitute(ex, known, x, j)
        r = _canonical(r)
        _within_budget(r, model.name, f"the relation from the {label} equation")
        r = sympy.expand(r)
        if r == 0:
            continue
        arrs.append(r)
        srcs.append(label)
    # components
    rows: list[tuple[str, set]] = []
    aug = model.augmented
    input_of = {}
    for el in aug.flat.elements if aug is not None else ():
        params = parameter_symbols(el)
        if params:
            rows.append((el.name, set(params)))
        if el.input_name() is not None:
            input_of[el.input_name()] = el.name
    for u in model.inputs:
        rows.append((input_of.get(u.name, u.name), {u_fun[u]}))
    for name, yf in zip(lf.outputs, y_fun):
        rows.append((name, {yf}))
    comps, sigs = [], []
    for name, marks in rows:
        sig = tuple(int(any(r.has(m) for m in marks)) for r in arrs)
        comps.append(name)
        sigs.append(sig)
    return FaultDiagnosis(model=model.name, arrs=tuple(arrs), sources=tuple(srcs),
                          components=tuple(comps), signatures=tuple(sigs),
                          solved=tuple((s.name, known[s]) for s in x if s in known),
                          unresolved=tuple(unresolved))


def _substitute(ex: sympy.Expr, known: dict, x: list, j: Optional[int]) -> sympy.Expr:
    """``ex`` with known states replaced; a state equation becomes ``rhs - x_j'``."""
    out = ex.xreplace(known)
    if j is not None:
        out = out - _dt(known[x[j]]) if x[j] in known else out
    return out


#: largest size (sympy expression nodes) of a solved state or a relation: the relations
#: of a chain of n masses observed through one sensor grow about fourfold with each mass
#: (n = 5: 5,600 nodes, 1 s; n = 6: 22,000, 3 s), a size no polynomial algorithm can write down
FAULT_SIZE_BUDGET = 25_000


def _within_budget(ex: sympy.Expr, model: str, what: str) -> None:
    size = 0
    for _ in sympy.preorder_traversal(ex):
        size += 1
        if size > FAULT_SIZE_BUDGET:
            raise StructureError(
                f"model {model!r}: fault_signatures stops: {what} passes "
                f"{FAULT_SIZE_BUDGET} expression nodes (relations through long chains of "
                "derivatives grow exponentially with the chain's length); measure more "
                "signals, nearer the unknowns (a sensor on each storage element keeps every "
                "relation short), or raise bondgraph.structure.faults.FAULT_SIZE_BUDGET")


def _canonical(ex: sympy.Expr) -> sympy.Expr:
    """``ex``, linear in the signals (inputs, sensor outputs and their derivatives), as
    ``sum_k c_k s_k + c_0`` with every coefficient one reduced fraction of the parameters
    (python-flint gcds: :func:`bondgraph.equations.loops.compact_linear`); exact, and in
    time linear in the size of ``ex`` where ``simplify`` grows steeply along a chain."""
    from ..equations.loops import compact_linear

    signals = sorted(ex.atoms(sympy.Derivative) | {
        a for a in ex.atoms(sympy.core.function.AppliedUndef)}, key=sympy.default_sort_key)
    if not signals:
        return compact_linear([ex], set())[0]
    stand = {a: sympy.Dummy(f"s{i}") for i, a in enumerate(signals)}
    back = {d: a for a, d in stand.items()}
    # derivatives first: a Derivative holds the function it differentiates
    flat = ex.xreplace({a: stand[a] for a in signals if isinstance(a, sympy.Derivative)})
    flat = flat.xreplace({a: stand[a] for a in signals if not isinstance(a, sympy.Derivative)})
    if flat.atoms(sympy.Derivative) or flat.atoms(sympy.core.function.AppliedUndef):
        return sympy.simplify(ex)       # pragma: no cover - signals nested in other functions
    return compact_linear([flat], set(stand.values()))[0].xreplace(back)


def _solve_linear(ex: sympy.Expr, v: sympy.Symbol, coeff: sympy.Expr) -> Optional[sympy.Expr]:
    """The solution ``v`` of ``ex = 0`` when ``ex`` is linear in ``v`` with the nonzero
    coefficient ``coeff`` (canonical form), else through ``sympy.solve``; None when not
    unique."""
    if v not in coeff.free_symbols:
        c = _canonical(coeff)
        if c == 0:
            return None
        return _canonical(-ex.xreplace({v: 0}) / c)
    sol = sympy.solve(ex, v, dict=False)
    return sympy.simplify(sol[0]) if len(sol) == 1 else None


def _dt(ex: sympy.Expr) -> sympy.Expr:
    """``d ex / dt`` of a sum of (time-free coefficient) x (signal) terms, differentiating
    the signals only; ``sympy.diff`` for anything else."""
    out = []
    for term in sympy.Add.make_args(ex):
        sig = [f for f in sympy.Mul.make_args(term)
               if isinstance(f, (sympy.Derivative, sympy.core.function.AppliedUndef))]
        if len(sig) != 1:
            if T in term.free_symbols or sig:
                return sympy.diff(ex, T)
            continue            # a constant
        coeff = term / sig[0]
        if T in coeff.free_symbols:
            return sympy.diff(ex, T)
        out.append(coeff * sympy.diff(sig[0], T))
    return sympy.Add(*out)
