"""Random nonlinear bond graphs, their bondgraph builds, and the differential check.

* :func:`generate` -- a random nonlinear graph (:class:`NGraph`): a tree of
  alternating 0/1 junctions (directly, through a TF or MTF, or through a GY or
  MGY that joins junctions of the same kind), each with storage and resistors:
  linear, cubic and saturating (``tanh``) springs, cubic inertias, linear,
  quadratic (``f|f|``) and smooth-Coulomb (``tanh``) dampers, orifices given as
  a flow law (``inverse=``), an MTF whose ratio follows an angle
  (``n0 cos(q) + n1``), an MGY ``r (1 + tanh(q)/2)``, modulated effort sources
  ``e0 - kp q``, one or two input sources ``a + b sin(w t)``.  Junctions carry
  at most one storage element of their kind, so storage is mostly in integral
  causality; where gyrators or a modulated transformer still join storage
  rigidly (fewer model states than storage elements), the reference reduces the
  index itself (:mod:`verification.nonlinear_reduced`).
* :func:`build` -- the :class:`bondgraph.BondGraph` (numbers in the laws).
* :func:`check` -- ``simulate`` against the reference's trajectory,
  ``linearize`` at a random point and at the equilibrium against central
  differences of the reference's ``f``, ``equilibrium`` against the
  reference's residual and eigenvalues; one of :data:`CLASSES`.  Laws whose
  inverse has no closed form (``a f + b tanh(f/v)``) and nonlinear loops give
  implicit models: compared the same way, through their numeric plants.

Examples
--------
>>> g = generate(3)
>>> g.seed, any(e.kind in ("Se", "Sf") for e in g.elements)
(3, True)
>>> check(g).cls in CLASSES
True
"""

from __future__ import annotations

import math
import random
import signal
import time
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from verification.nonlinear_reduced import ReducedReference
from verification.nonlinear_reference import DAEReference, NElement, NGraph, ReferenceError_

__all__ = ["generate", "build", "check", "Outcome", "CLASSES", "dsl"]

#: outcome classes, worst first; "refused" are derivations the package declines (issue
#: 29: nonlinear loops and laws with no inverse are kept implicit, storage constrained
#: through them reduced; what remains is a stored quantity depending on another dependent
#: storage's rate), "no-equilibrium-found" a trim the package did not find that the
#: reference did (reported apart), "reference-failed" the reference's own failure.
#: Implicit models (0 = g(x, z, u)) are compared like the others, their Jacobians through
#: the numeric plant (the implicit-function theorem).  Models with dependent storage are
#: compared against the reference's own index reduction
#: (:mod:`verification.nonlinear_reduced`); one whose dependent storage needs du/dt (an
#: effort source across a compliance) cannot be simulated from input values, so its x'
#: is compared at random states and times (the check "input_derivative_rhs")
CLASSES = ("wrong", "crash", "timeout", "refused", "no-equilibrium-found", "reference-failed",
           "agree")

#: tolerances: trajectories, Jacobians (central differences, h = 1e-6), equilibrium residual
TOL_X, TOL_J, TOL_F = 1e-6, 1e-5, 1e-7


def _v(rng: random.Random, lo: float = 0.5, hi: float = 2.0) -> float:
    return float(f"{lo * (hi / lo) ** rng.random():.4g}")


def generate(seed: int, max_junctions: int = 4) -> NGraph:
    """A random nonlinear bond graph (see the module docstring)."""
    rng = random.Random(seed)
    els: list[NElement] = []
    bonds: list[tuple[str, str]] = []
    junctions: list[tuple[str, str]] = []
    count = [0]

    def new(prefix: str) -> str:
        count[0] += 1
        return f"{prefix}{count[0]}"

    def junction(kind: str) -> str:
        name = new("z" if kind == "Zero" else "o")
        els.append(NElement(name, kind))
        junctions.append((name, kind))
        return name

    root = junction(rng.choice(["One", "Zero"]))
    inputs = {}

    def source(j: str, jkind: str) -> None:
        kind = "Se" if jkind == "One" else "Sf"
        name = new("E" if kind == "Se" else "F")
        els.append(NElement(name, kind, "input"))
        bonds.append((name, j))
        inputs[name] = (rng.uniform(-1.5, 1.5), rng.uniform(0.0, 1.0), rng.uniform(0.5, 3.0))

    source(root, junctions[0][1])
    for _ in range(rng.randint(0, max_junctions - 1)):
        parent, pkind = rng.choice(junctions)
        other = "Zero" if pkind == "One" else "One"
        how = rng.choices(["direct", "TF", "MTF", "GY", "MGY"], [4, 2, 1, 1, 1])[0]
        child = junction(pkind if how in ("GY", "MGY") else other)
        if how == "direct":
            bonds.append((parent, child))
            continue
        tp = new("T" if how in ("TF", "MTF") else "G")
        params = {"TF": (_v(rng),), "GY": (_v(rng),), "MTF": (_v(rng, 0.2, 0.5), _v(rng, 1.0, 2.0)),
                  "MGY": (_v(rng),)}[how]
        els.append(NElement(tp, how, "linear" if how in ("TF", "GY") else "mod", params))
        bonds += [(parent, tp), (tp, child)]
    for j, kind in junctions:
        if rng.random() < 0.8:
            if kind == "One":
                law = rng.choices(["linear", "cubic"], [3, 1])[0]
                params = (_v(rng),) if law == "linear" else (_v(rng), _v(rng, 0.05, 0.5))
                name = new("I")
                els.append(NElement(name, "I", law, params))
            else:
                law = rng.choice(["linear", "cubic", "sat"])
                params = {"linear": (_v(rng),), "cubic": (_v(rng), _v(rng, 0.1, 1.0)),
                          "sat": (_v(rng, 1.0, 4.0), _v(rng, 0.5, 2.0))}[law]
                name = new("C")
                els.append(NElement(name, "C", law, params))
            bonds.append((j, name))
        for _ in range(rng.choices([0, 1, 2], [1, 3, 1])[0]):
            # an R on a 0-junction mostly receives its effort (a flow law fits: an orifice),
            # on a 1-junction its flow (an effort law fits); the others are still drawn
            # "orifice1" (a pure orifice, given as its flow law only) and "quad1" (given as
            # its effort law only) leave the other direction to the package to invert
            law = rng.choices(["linear", "quad", "tanh", "orifice", "orifice1", "quad1"],
                              [2, 1, 1, 2, 1, 1] if kind == "Zero" else [2, 2, 2, 1, 1, 1])[0]
            params = {"linear": (_v(rng),), "quad": (_v(rng), _v(rng, 0.1, 1.0)),
                      "tanh": (_v(rng), _v(rng, 0.2, 1.0), _v(rng, 0.2, 1.0)),
                      "orifice": (_v(rng, 0.2, 1.0), _v(rng, 0.5, 2.0)),
                      "orifice1": (0.0, _v(rng, 0.5, 2.0)),
                      "quad1": (_v(rng), _v(rng, 0.1, 1.0))}[law]
            name = new("R")
            els.append(NElement(name, "R", law, params))
            bonds.append((j, name))
        if kind == "One" and rng.random() < 0.15:
            name = new("M")                # modulated effort source e0 - kp q_ref
            els.append(NElement(name, "Se", "mod", (rng.uniform(-1, 1), _v(rng, 0.2, 1.0))))
            bonds.append((name, j))
        if rng.random() < 0.1:
            source(j, kind)
    caps = [e.name for e in els if e.kind == "C"]
    out = []
    for e in els:
        if e.law == "mod":
            if caps:
                e = NElement(e.name, e.kind, e.law, e.params, rng.choice(caps))
            elif e.kind in ("MTF", "MGY"):
                e = NElement(e.name, e.kind[1:], "linear", (e.params[-1],))
            else:
                e = NElement(e.name, "Se", "input")
                inputs[e.name] = (rng.uniform(-1, 1), rng.uniform(0, 1), rng.uniform(0.5, 3))
        out.append(e)
    for j, _ in junctions:          # a junction with nothing on it gets a resistor
        if sum(1 for t, h in bonds if j in (t, h)) < 2:
            name = new("R")
            out.append(NElement(name, "R", "linear", (_v(rng),)))
            bonds.append((j, name))
    return NGraph(tuple(out), tuple(bonds), seed, inputs)


def _law(el: NElement):
    import sympy

    import bondgraph as bg

    P = el.params
    if el.law == "linear":
        return None
    laws = {("I", "cubic"): lambda: bg.p / P[0] + P[1] * bg.p ** 3,
            ("C", "cubic"): lambda: P[0] * bg.q + P[1] * bg.q ** 3,
            ("C", "sat"): lambda: P[0] * sympy.tanh(bg.q / P[1]),
            ("R", "quad"): lambda: P[0] * bg.f + P[1] * bg.f * sympy.Abs(bg.f),
            ("R", "tanh"): lambda: P[0] * bg.f + P[1] * sympy.tanh(bg.f / P[2]),
            ("R", "orifice"): lambda: P[0] * bg.e + P[1] * sympy.sign(bg.e) * sympy.sqrt(
                sympy.Abs(bg.e)),
            ("R", "orifice1"): lambda: P[1] * sympy.sign(bg.e) * sympy.sqrt(sympy.Abs(bg.e)),
            ("R", "quad1"): lambda: P[0] * bg.f + P[1] * bg.f * sympy.Abs(bg.f)}
    return laws[(el.kind, el.law)]()


def build(graph: NGraph):
    """The :class:`bondgraph.BondGraph` of ``graph`` (numbers in the laws, no parameters)."""
    import sympy

    import bondgraph as bg

    g = bg.BondGraph(f"n{graph.seed}")
    for el in graph.elements:
        k, P = el.kind, el.params
        if k in ("Zero", "One"):
            g.add(getattr(bg, k)(el.name))
        elif k == "Se":
            g.add(bg.Se(el.name) if el.law == "input" else
                  bg.Se(el.name, value=P[0] - P[1] * bg.displacement(el.ref)))
        elif k == "Sf":
            g.add(bg.Sf(el.name))
        elif k in ("TF", "GY"):
            g.add(getattr(bg, k)(el.name, P[0]))
        elif k == "MTF":
            g.add(bg.MTF(el.name, P[0] * sympy.cos(bg.displacement(el.ref)) + P[1]))
        elif k == "MGY":
            g.add(bg.MGY(el.name, P[0] * (1 + sympy.tanh(bg.displacement(el.ref)) / 2)))
        else:
            law = _law(el)
            if law is None:
                g.add(getattr(bg, k)(el.name, P[0]))
            elif k == "R" and el.law in ("orifice", "quad"):
                # both directions, the other one solved by hand (a quadratic in f or in
                # sqrt|e|), so either causality works; the reference uses neither inverse
                a, b = P[0], P[1]
                if el.law == "quad":      # e = a f + b f|f|  <=>  f = sgn(e)(-a + sqrt(a^2 + 4b|e|))/2b
                    other = sympy.sign(bg.e) * (-a + sympy.sqrt(a ** 2 + 4 * b * sympy.Abs(bg.e))) / (2 * b)
                    g.add(bg.R(el.name, law=law, inverse=other))
                else:                     # f = a e + b sgn(e) sqrt|e|  <=>  e = sgn(f) s^2,
                    s_ = (-b + sympy.sqrt(b ** 2 + 4 * a * sympy.Abs(bg.f))) / (2 * a)   # s = sqrt|e|
                    g.add(bg.R(el.name, law=sympy.sign(bg.f) * s_ ** 2, inverse=law))
            elif k == "R" and el.law == "orifice1":
                g.add(bg.R(el.name, inverse=law))         # a flow law only
            else:
                g.add(getattr(bg, k)(el.name, law=law))
    for t, h in graph.bonds:
        g.connect(t, h)
    return g


def dsl(graph: NGraph) -> str:
    """The graph as a description (to paste into a reproducer)."""
    return (f"NGraph(elements={graph.elements!r},\n       bonds={graph.bonds!r}, "
            f"seed={graph.seed}, inputs={graph.inputs!r})")


@dataclass
class Outcome:
    seed: int
    cls: str
    detail: str = ""
    seconds: float = 0.0
    checks: dict = field(default_factory=dict)


class GraphTimeout(Exception):
    pass


@contextmanager
def _limit(seconds: float):
    """CPU time of this process (the machine may be shared: wall time would lie)."""
    def on_alarm(signum, frame):
        raise GraphTimeout(f"over {seconds:g} CPU seconds")
    old = signal.signal(signal.SIGPROF, on_alarm)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.signal(signal.SIGPROF, old)


def _matrix(M) -> np.ndarray:
    if isinstance(M, np.ndarray):         # a numeric plant (implicit models)
        return np.asarray(M, dtype=float)
    return np.array([[float(M[i, j]) for j in range(M.cols)] for i in range(M.rows)],
                    dtype=float).reshape(M.shape)


def check(graph: NGraph, timeout: float = 20.0, t_end: float = 2.0) -> Outcome:
    """The differential check of one graph (see the module docstring)."""
    t0 = time.perf_counter()
    out = Outcome(graph.seed, "agree")
    try:
        with _limit(timeout), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            _check(graph, out, t_end)
    except GraphTimeout as exc:
        out.cls, out.detail = "timeout", str(exc)
    except ReferenceError_ as exc:
        out.cls, out.detail = "reference-failed", str(exc)
    except Exception as exc:  # noqa: BLE001 -- every other escape is a crash to report
        out.cls, out.detail = "crash", f"{type(exc).__name__}: {exc}"
    out.seconds = time.perf_counter() - t0
    return out


def _check(graph: NGraph, out: Outcome, t_end: float) -> None:
    import bondgraph as bg

    ref = DAEReference(graph)
    try:
        model = bg.derive(build(graph))
    except bg.BondGraphError as exc:
        out.cls, out.detail = "refused", f"derive: {type(exc).__name__}: {exc}"
        return
    if set(model.state_names) < set(ref.state_names) and \
            set(model.input_names) == set(ref.input_names):
        # storage in derivative causality: the reference's own index reduction (the
        # constraint differentiated numerically along the motion) with the model's choice
        # of independent storage
        ref = ReducedReference(graph, {n for (n, _), s in zip(ref.states, ref.state_names)
                                       if s not in model.state_names})
        if model.input_derivatives and set(model.state_names) == set(ref.state_names):
            # x' needs du/dt, which no simulation from input values has: the equations
            # are compared at random states and times instead
            _check_with_input_derivatives(model, ref, graph, out)
            return
    if set(model.state_names) != set(ref.state_names) or \
            set(model.input_names) != set(ref.input_names):
        out.cls = "wrong"
        out.detail = (f"states/inputs {model.state_names}/{model.input_names}, reference "
                      f"{ref.state_names}/{ref.input_names}")
        return
    xi = [model.state_names.index(n) for n in ref.state_names]      # reference order
    ui = [model.input_names.index(n) for n in ref.input_names]
    rng = np.random.default_rng(graph.seed)
    x0 = rng.normal(0.0, 0.4, len(ref.states))
    t_eval = np.linspace(0.0, t_end, 11)

    def u_model(t):
        u = ref.u_of_t(t)
        v = np.empty(len(u))
        v[ui] = u
        return v

    if not ref.states:
        out.detail = "no states"
        return
    if isinstance(ref, ReducedReference):
        out.checks["reduced"] = 1.0
    # ---- simulate
    x_ref = ref.simulate(t_end, t_eval, x0)
    try:
        res = bg.simulate(model, {}, (0.0, t_end), dict(zip(ref.state_names, x0)),
                          u=u_model if len(ui) else None, t_eval=t_eval, rtol=1e-10, atol=1e-12)
    except bg.BondGraphError as exc:
        out.cls, out.detail = "refused", f"simulate: {type(exc).__name__}: {exc}"
        return
    x_bg = np.asarray(res.x, dtype=float).reshape(len(t_eval), -1)[:, xi]
    scale = 1.0 + np.max(np.abs(x_ref), axis=0)
    err = float(np.max(np.abs(x_bg - x_ref) / scale))
    out.checks["trajectory"] = err
    if not err <= TOL_X:
        out.cls, out.detail = "wrong", f"trajectory differs by {err:.3g} (scaled)"
        return
    # ---- linearize at a random point (not an equilibrium)
    u_point = ref.u_of_t(0.3)
    lin = model.linearize(dict(zip(ref.state_names, x0)),
                          dict(zip(ref.input_names, u_point)), equilibrium=False,
                          values={} if getattr(model, "algebraic", ()) else None)
    A_ref, B_ref = ref.jacobians(x0, u_point)
    A_bg = _matrix(lin.A)[np.ix_(xi, xi)]
    B_bg = _matrix(lin.B)[np.ix_(xi, ui)] if len(ui) else np.zeros((len(xi), 0))
    e_j = _rel(A_bg, A_ref, B_bg, B_ref)
    out.checks["jacobian"] = e_j
    if not e_j <= TOL_J:
        out.cls, out.detail = "wrong", f"linearize at a point differs by {e_j:.3g}"
        return
    # ---- equilibrium at the inputs' mean values
    u0 = np.array([graph.inputs[n][0] for n in ref.input_names])
    try:
        eq = model.equilibrium({}, dict(zip(ref.input_names, u0)))
    except bg.BondGraphError as exc:
        found = ref.equilibria(u0)
        if found and "not isolated" in str(exc):
            # the reference agrees when its own Jacobian is singular at what it found
            sv = [np.linalg.svd(ref.jacobians(x, u0)[0], compute_uv=False) for x in found]
            if all(s[-1] <= 1e-7 * max(s[0], 1e-300) for s in sv):
                out.checks["not_isolated_confirmed"] = 1.0
                return
        if found:
            out.cls = "no-equilibrium-found"
            out.detail = (f"equilibrium: {type(exc).__name__}: {str(exc)[:200]}; the reference "
                          f"found x = {list(np.round(found[0], 6))}")
        return
    xe = np.array([eq.states[n] for n in ref.state_names])
    fe = ref.f(xe, u0)
    sizes = 1.0 + float(np.max(np.abs(ref._z)))
    out.checks["equilibrium"] = float(np.max(np.abs(fe))) / sizes if fe.size else 0.0
    if not out.checks["equilibrium"] <= TOL_F:
        out.cls, out.detail = "wrong", f"equilibrium {dict(eq.states)} has residual {fe}"
        return
    A_ref, B_ref = ref.jacobians(xe, u0)
    A_wide = ref.jacobians(xe, u0, h=1e-5)[0]
    spread = _rel(A_wide, A_ref, B_ref, B_ref)      # the reference's own uncertainty
    if spread > 1e-4:
        # f is not differentiable at this equilibrium (an orifice at zero pressure drop:
        # slope sqrt(1/|e|) -> inf); no Jacobian to compare, the residual was checked
        out.checks["nondifferentiable_equilibrium"] = 1.0
        return
    plant = model.linearize(eq)
    pA = np.asarray(plant.A)[np.ix_(xi, xi)]
    pB = np.asarray(plant.B)[np.ix_(xi, ui)] if len(ui) else np.zeros((len(xi), 0))
    e_eq = _rel(pA, A_ref, pB, B_ref)
    out.checks["jacobian_at_equilibrium"] = e_eq
    # next to a kink (an orifice at zero flow) the reference's differences with h = 1e-6
    # and 1e-5 differ by up to 1e-4: the comparison cannot be tighter than that spread
    if not e_eq <= max(TOL_J, 10 * spread):
        out.cls, out.detail = "wrong", f"linearize at the equilibrium differs by {e_eq:.3g}"
        return
    if eq.stability == "unknown":
        # the package could not decide (a Jacobian not finite at the point): said, not wrong
        out.checks["stability_undecided"] = 1.0
        return
    lam = np.linalg.eigvals(A_ref) if A_ref.size else np.zeros(0)
    # eigenvalues within rounding of the differences (relative to the Jacobian's entries)
    # decide nothing
    margin = 1e-6 * (1.0 + float(np.max(np.abs(A_ref))) if A_ref.size else 1.0)
    if lam.size and (np.all(lam.real < -margin) and eq.stability != "stable" or
                     np.any(lam.real > margin) and eq.stability != "unstable"):
        out.cls = "wrong"
        out.detail = f"stability {eq.stability!r}, reference eigenvalues {lam}"


def _check_with_input_derivatives(model, ref, graph: NGraph, out: Outcome) -> None:
    """``x' = f(x, z, u, du/dt)`` of the model (``z`` by the package's Newton solve)
    against the reduced reference along the inputs' time law, at random states and
    times (a model that needs ``du/dt`` cannot be simulated from input values)."""
    import sympy

    from bondgraph.numeric.implicit import ImplicitSolver

    if not ref.states:
        out.detail = "no states"
        return
    xs, us, zs = list(model.states), list(model.inputs), list(model.algebraic)
    uds = [sympy.Symbol(f"d{u.name}/dt", real=True) for u in us]
    if not set(model.input_derivatives) <= set(uds):
        out.cls, out.detail = "wrong", f"input derivatives {model.input_derivatives}"
        return
    f = sympy.lambdify([xs, us, uds, zs], list(model.rhs), modules="numpy")
    solver = ImplicitSolver(model, ()) if zs else None
    xi = [model.state_names.index(n) for n in ref.state_names]
    ui = [model.input_names.index(n) for n in ref.input_names]
    rng = np.random.default_rng(graph.seed)
    worst = 0.0
    for _ in range(4):
        t = float(rng.uniform(0.0, 2.0))
        x_ref = rng.normal(0.0, 0.4, len(ref.states))
        u_ref = ref.u_of_t(t)
        ud_ref = np.array([b * w * math.cos(w * t) for a, b, w in
                           (graph.inputs[n] for n in ref.input_names)])
        x, u, ud = np.empty(len(xs)), np.empty(len(us)), np.empty(len(us))
        x[xi], u[ui], ud[ui] = x_ref, u_ref, ud_ref
        z = solver.solve(t, x, u, np.zeros(0)) if solver is not None else np.zeros(0)
        got = np.asarray(f(x, u, ud, z), dtype=float)[xi]
        want = ref.f(x_ref, u_ref, t)
        worst = max(worst, float(np.max(np.abs(got - want))) / (1.0 + float(np.max(np.abs(want)))))
    out.checks["reduced"] = 1.0
    out.checks["input_derivative_rhs"] = worst
    if not worst <= TOL_J:
        out.cls, out.detail = "wrong", f"x' with input derivatives differs by {worst:.3g}"


def _rel(A, A_ref, B, B_ref) -> float:
    s = 1.0 + max(float(np.max(np.abs(A_ref))) if A_ref.size else 0.0,
                  float(np.max(np.abs(B_ref))) if B_ref.size else 0.0)
    eA = float(np.max(np.abs(A - A_ref))) if A.size else 0.0
    eB = float(np.max(np.abs(B - B_ref))) if B.size else 0.0
    return max(eA, eB) / s


def run(seeds, timeout: float = 20.0) -> dict:
    """Counts per class over ``seeds`` (and the outcomes), in this process."""
    counts = {c: 0 for c in CLASSES}
    outcomes = []
    for seed in seeds:
        o = check(generate(seed), timeout=timeout)
        counts[o.cls] += 1
        outcomes.append(o)
    return {"counts": counts, "outcomes": outcomes}


if __name__ == "__main__":      # pragma: no cover - quick look: python -m verification.nonlinear
    import sys

    r = run(range(int(sys.argv[1]) if len(sys.argv) > 1 else 20))
    print(r["counts"])
    for o in r["outcomes"]:
        if o.cls not in ("agree",):
            print(o.seed, o.cls, o.detail[:300])
    _ = math
