"""Random switched circuits as bond graphs and netlists, and the differential check.

* :func:`generate` -- a random circuit of the kind users build (a
  :class:`Case`): 1-3 non-ground nodes; one or two sources (voltage or current,
  constant or ``a + b sin(w t + phi)``); 1-3 capacitors and inductors and 1-3
  resistors with values over two decades (0.1 to 10); 1-2 ideal diodes; none
  or one switch gated by a PWM (:func:`bondgraph.hybrid.pwm`) or by a state (a
  capacitor voltage or an inductor current against a threshold).  Each part is
  a branch of its own or in series with others.  A node is a 0-junction; a
  branch is a 1-junction (a part alone between a node and the ground may sit
  on the node's 0-junction directly), its two node bonds pointing through it
  either way; every part's bond points either way (a diode's bond decides its
  direction at a 1-junction; at a 0-junction a diode conducts from the node to
  the ground); elements and bonds are added in a random order.  Every node
  has a resistor or capacitor to the ground (a bleed resistor is added where
  none was drawn), so no node floats.  The netlist is built alongside, series
  branches expanded with inner nodes.
* :func:`build` -- the :class:`bondgraph.hybrid.SwitchedModel`, its values and
  initial state.
* :func:`check` -- ``bondgraph.hybrid.simulate`` against
  :class:`~verification.switched_reference.SwitchedReference`: the mode at
  ``t = 0`` and after every event, every event time, every stored quantity
  and the mode at 100 instants away from events.  One of :data:`CLASSES`.
* :func:`script` -- a runnable reproducer of a case.

Examples
--------
>>> case = generate(7)
>>> case.seed, 1 <= sum(p.kind == "D" for p in case.net.parts) <= 2
(7, True)
>>> check(case).cls in CLASSES
True
"""

from __future__ import annotations

import math
import random
import signal
import time
import traceback
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from verification.switched_reference import IllPosed, Netlist, Part, SwitchedReference

__all__ = ["Case", "Outcome", "CLASSES", "FAILURES", "generate", "build", "check", "script"]

#: outcome classes, worst first.  "ill-posed-answered": the reference finds no unique
#: solution (a source shorted by a diode, a sliding mode, ...) and the package simulated
#: anyway (reported, not a failure: what it should do there is not defined)
CLASSES = ("wrong", "crash", "timeout", "refused-well-posed", "refused-ill-posed",
           "ill-posed-answered", "agree")
FAILURES = ("wrong", "crash", "timeout", "refused-well-posed")

#: tolerances: stored quantities (of the largest), event times (of the span)
TOL_X, TOL_T = 1e-6, 1e-6
#: samples closer than this fraction of the span to an event are not compared
AWAY = 1e-4


@dataclass(frozen=True)
class Case:
    """One random circuit: the bond graph recipe and the netlist of the same circuit.

    ``elements``: (constructor, name, options) in insertion order; ``bonds``:
    (tail, head) in insertion order; ``values``: parameter values; ``x0``: the
    initial stored quantities (``q_C1``, ``p_L1``); ``s0``: the same as capacitor
    voltages and inductor currents for the reference.
    """

    seed: int
    net: Netlist
    elements: tuple
    bonds: tuple
    values: dict
    x0: dict
    s0: dict
    t1: float


@dataclass
class Outcome:
    seed: int
    cls: str
    detail: str = ""
    seconds: float = 0.0
    checks: dict = field(default_factory=dict)


def _v(rng: random.Random, lo: float = 0.1, hi: float = 10.0) -> float:
    return float(f"{lo * (hi / lo) ** rng.random():.3g}")


def _wave(rng: random.Random) -> tuple:
    if rng.random() < 0.4:
        return (rng.choice([-1, 1]) * _v(rng, 0.5, 5.0), 0.0, 0.0, 0.0)
    a = 0.0 if rng.random() < 0.5 else round(rng.uniform(-1.0, 1.0), 3)
    phi = 0.0 if rng.random() < 0.4 else round(rng.uniform(0.0, 2 * math.pi), 3)
    return (a, _v(rng, 0.5, 5.0), _v(rng, 1.0, 6.0), phi)


def generate(seed: int) -> Case:
    """A random switched circuit (see the module docstring)."""
    rng = random.Random(seed)
    n_nodes = rng.randint(1, 3)
    parts: list[tuple[str, str]] = []            # (kind, name) of the circuit's parts
    count: dict[str, int] = {}

    def name(kind: str) -> str:
        count[kind] = count.get(kind, 0) + 1
        return f"{kind}{count[kind]}"

    for _ in range(1 if rng.random() < 0.7 else 2):
        parts.append(("V", name("V")) if rng.random() < 0.85 else ("J", name("J")))
    for _ in range(rng.randint(1, 3)):
        parts.append(("C", name("C")) if rng.random() < 0.5 else ("L", name("L")))
    for _ in range(rng.randint(1, 3)):
        parts.append(("R", name("R")))
    for _ in range(rng.choice([1, 1, 2])):
        parts.append(("D", name("D")))
    r = rng.random()
    switch = "pwm" if r < 0.3 else ("state" if r < 0.45 else None)
    if switch:
        parts.append(("S", name("S")))
    rng.shuffle(parts)
    nodes = list(range(1, n_nodes + 1))
    # branches: [a, b, [part names]]; current sources only as shunts (node to ground)
    branches: list[list] = []
    kind_of = dict((n, k) for k, n in parts)
    for kind, nm in parts:
        series = [br for br in branches if kind != "J" and kind_of[br[2][0]] != "J"
                  and not (kind in "DS" and any(kind_of[x] in "DS" for x in br[2]))]
        if series and rng.random() < 0.3:
            rng.choice(series)[2].append(nm)
            continue
        a = rng.choice(nodes)
        b = 0 if kind == "J" or rng.random() < 0.6 else rng.choice([0] + [x for x in nodes if x != a])
        branches.append([a, b, [nm]])
    for br in branches:      # a voltage source has a resistance or inductance in series
        if any(kind_of[x] == "V" for x in br[2]) and not any(kind_of[x] in "RL" for x in br[2]):
            nm = name("R")
            kind_of[nm] = "R"
            br[2].insert(rng.randrange(len(br[2]) + 1), nm)
    used = sorted({x for br in branches for x in br[:2] if x})
    renumber = {a: k for k, a in enumerate(used, 1)}
    for br in branches:
        br[0], br[1] = renumber[br[0]], renumber.get(br[1], 0)
    nodes = list(range(1, len(used) + 1))
    n_nodes = len(nodes)
    for a in nodes:          # no node floats: a shunt R (C); no junction with one bond
        here = [br for br in branches if a in br[:2]]
        fed = any(kind_of[x] == "J" for br in here for x in br[2])
        shunt = any(br[1] == 0 and len(br[2]) == 1 and kind_of[br[2][0]] in ("R" if fed else "RC")
                    for br in here)
        for _ in range(max(int(not shunt), 2 - len(here))):
            nm = name("R")
            kind_of[nm] = "R"
            branches.append([a, 0, [nm]])
    # values
    values: dict = {}
    waves: dict = {}
    for nm, kind in kind_of.items():
        if kind in "RCL":
            values[nm] = _v(rng)
        elif kind in "VJ":
            waves[nm] = _wave(rng)
    gate: tuple = ()
    if switch == "pwm":
        period = _v(rng, 0.3, 2.0)
        gate = ("pwm", round(rng.uniform(0.2, 0.8), 3), period,
                round(rng.uniform(0.05, 0.95) * period, 4))
    elif switch == "state":
        store = [nm for nm, k in kind_of.items() if k in "CL"]
        gate = ("state", rng.choice(store), rng.choice([-1, 1]), round(rng.uniform(-0.3, 0.3), 3))
    # the bond graph and the netlist side by side
    elements: list[tuple] = [("Zero", f"n{a}", {}) for a in nodes]
    bonds: list[tuple[str, str]] = []
    net_parts: list[Part] = []
    next_node = [n_nodes + 1]

    def part(nm: str, plus: int, minus: int) -> None:
        kind = kind_of[nm]
        net_parts.append(Part(nm, kind, plus, minus, values.get(nm, 0.0), waves.get(nm, ()),
                              gate if kind == "S" else ()))
        ctor = {"R": "R", "C": "C", "L": "I", "V": "Se", "J": "Sf", "D": "Diode",
                "S": "ControlledSwitch"}[kind]
        opts: dict = {}
        if kind in "VJ":
            opts["wave"] = waves[nm]
        if kind in "DS":
            opts["on"] = rng.random() < 0.5
        if kind == "S":
            opts["gate"] = gate
        elements.append((ctor, nm, opts))

    for k, (a, b, names) in enumerate(branches, 1):
        if b == 0 and len(names) == 1 and (kind_of[names[0]] == "J" or rng.random() < 0.6):
            nm = names[0]                        # on the node's 0-junction: from node to ground
            part(nm, a, 0)
            bonds.append((f"n{a}", nm) if rng.random() < 0.75 else (nm, f"n{a}"))
            continue
        j = f"b{k}"
        elements.append(("One", j, {}))
        # the through direction: from node p (its bond into the 1-junction) to node q
        if rng.random() < 0.5:
            p, q = a, b
        else:
            p, q = b, a
        if p:
            bonds.append((f"n{p}", j))
        if q:
            bonds.append((j, f"n{q}"))
        chain = [p] + [next_node[0] + i for i in range(len(names) - 1)] + [q]
        next_node[0] += len(names) - 1
        for i, nm in enumerate(names):
            if rng.random() < 0.7:               # out of the junction: plus on p's side
                part(nm, chain[i], chain[i + 1])
                bonds.append((j, nm))
            else:
                part(nm, chain[i + 1], chain[i])
                bonds.append((nm, j))
    rng.shuffle(elements)
    rng.shuffle(bonds)
    x0: dict = {}
    s0: dict = {}
    for nm, kind in kind_of.items():
        if kind in "CL" and rng.random() < 0.5:
            v = round(rng.uniform(-2.0, 2.0), 3)
            s0[nm] = v
            x0[("q_" if kind == "C" else "p_") + nm] = v * values[nm]
    t1 = float(rng.choice([2.0, 3.0, 4.0]))
    net = Netlist(next_node[0] - 1, tuple(net_parts))
    return Case(seed, net, tuple(elements), tuple(bonds), values, x0, s0, t1)


def _gate(bg, sympy, hybrid, g: tuple):
    if g[0] == "pwm":
        _, duty, period, delay = g
        return hybrid.pwm(sympy.Float(duty), sympy.Float(period), delay=sympy.Float(delay)), period
    _, src, sign, thr = g
    sig = bg.effort(src) if src.startswith("C") else bg.flow(src)
    return sign * (sig - sympy.Float(thr)), None


def build(case: Case):
    """The :class:`bondgraph.hybrid.SwitchedModel` of the case."""
    import sympy

    import bondgraph as bg
    from bondgraph import hybrid

    g = bg.BondGraph(f"switched{case.seed}")
    for ctor, nm, opts in case.elements:
        if ctor in ("Se", "Sf"):
            a, b, w, phi = opts["wave"]
            val = sympy.Float(a) + (sympy.Float(b) * sympy.sin(sympy.Float(w) * bg.t + sympy.Float(phi))
                                    if b else 0)
            g.add(getattr(bg, ctor)(nm, value=val))
        elif ctor == "Diode":
            g.add(hybrid.Diode(nm, on=opts["on"]))
        elif ctor == "ControlledSwitch":
            gate, period = _gate(bg, sympy, hybrid, opts["gate"])
            g.add(hybrid.ControlledSwitch(nm, gate=gate, on=opts["on"],
                                          **({"period": sympy.Float(period)} if period else {})))
        else:
            g.add(getattr(bg, ctor)(nm))
    for tail, head in case.bonds:
        g.connect(tail, head)
    return hybrid.SwitchedModel(g)


def script(case: Case) -> str:
    """A runnable reproducer: the graph, the simulation, the reference's expectation."""
    lines = ["import sympy", "import bondgraph as bg", "from bondgraph import hybrid", "",
             f"g = bg.BondGraph('switched{case.seed}')"]
    for ctor, nm, opts in case.elements:
        if ctor in ("Se", "Sf"):
            a, b, w, phi = opts["wave"]
            val = f"{a!r}" + (f" + {b!r}*sympy.sin({w!r}*bg.t + {phi!r})" if b else "")
            lines.append(f"g.add(bg.{ctor}({nm!r}, value={val}))")
        elif ctor == "Diode":
            lines.append(f"g.add(hybrid.Diode({nm!r}, on={opts['on']}))")
        elif ctor == "ControlledSwitch":
            gt = opts["gate"]
            if gt[0] == "pwm":
                gate = f"hybrid.pwm({gt[1]!r}, {gt[2]!r}, delay={gt[3]!r}), period={gt[2]!r}"
            else:
                sig = f"bg.effort({gt[1]!r})" if gt[1].startswith("C") else f"bg.flow({gt[1]!r})"
                gate = f"{gt[2]} * ({sig} - {gt[3]!r})"
            lines.append(f"g.add(hybrid.ControlledSwitch({nm!r}, gate={gate}, on={opts['on']}))")
        else:
            lines.append(f"g.add(bg.{ctor}({nm!r}))")
    lines.append(f"for a, b in {list(case.bonds)!r}:\n    g.connect(a, b)")
    lines.append("sm = hybrid.SwitchedModel(g)")
    lines.append(f"res = hybrid.simulate(sm, (0, {case.t1!r}), {case.x0!r}, values={case.values!r})")
    lines.append("print([(round(e.time, 9), str(e.after)) for e in res.events])")
    lines.append("print({k: v[-1] for k, v in res.stored.items()})")
    return "\n".join(lines)


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


def check(case: Case, timeout: float = 20.0) -> Outcome:
    """The differential check of one case (see the module docstring)."""
    from bondgraph.errors import BondGraphError
    from bondgraph.hybrid import simulate

    out = Outcome(case.seed, "agree")
    start = time.process_time()
    grid = np.linspace(0.0, case.t1, 102)[1:-1]
    try:
        with _limit(timeout):
            try:
                built = frozenset(nm for _, nm, o in case.elements if o.get("on"))
                ref = SwitchedReference(case.net).simulate(case.t1, case.s0, grid, built)
                ill = None
            except IllPosed as e:
                ref, ill = None, str(e)
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    sm = build(case)
                    x0 = _initial(sm, case.x0, out)
                    res = simulate(sm, (0.0, case.t1), x0, values=case.values, t_eval=grid)
            except BondGraphError as e:
                out.cls = "refused-ill-posed" if ill else "refused-well-posed"
                out.detail = f"{type(e).__name__}: {e}" + (f" [reference: {ill}]" if ill else "")
                return out
            if ill:
                out.cls, out.detail = "ill-posed-answered", ill
                return out
            _compare(case, ref, res, grid, out)
    except GraphTimeout as e:
        out.cls, out.detail = "timeout", str(e)
    except Exception as e:        # noqa: BLE001 -- a crash is an outcome
        out.cls = "crash"
        out.detail = f"{type(e).__name__}: {e} | " + traceback.format_exc(limit=-3).replace("\n", " ")
    finally:
        out.seconds = time.process_time() - start
    return out


def _initial(sm, x0: dict, out: Outcome) -> dict:
    """``x0`` by the names the package gives: a storage element in derivative causality in
    every mode has no state ``q_C``/``p_L``; its stored quantity is named by its signal."""
    states = {n for m in sm.modes for n in sm.derived(m).user.state_names}
    given = {}
    for key, v in x0.items():
        if key not in states:
            key = f"{'displacement' if key[0] == 'q' else 'momentum'}[{key[2:]}]"
            out.checks["x0_by_signal"] = out.checks.get("x0_by_signal", 0) + 1
        given[key] = v
    return given


def _collapse(events: list, tol: float) -> list:
    """Mode changes: several within ``tol`` of the first are one, to the last mode; a change
    that returns to the mode before is none."""
    out: list = []
    for t, on in events:
        if out and t - out[-1][0] <= tol:
            t = out.pop()[0]
        if not out or out[-1][1] != on:
            out.append((t, on))
    return out


def _compare(case: Case, ref, res, grid: np.ndarray, out: Outcome) -> None:
    tol = TOL_T * case.t1
    first = res.modes[int(res.mode_index[0])]
    got = _collapse([(0.0, frozenset(first.on))]
                    + [(e.time, frozenset(e.after.on)) for e in res.events], tol)
    exp: list = []                             # the reference's, merged the same way
    for t, on, allowed in ref.events:
        if exp and t - exp[-1][0] <= tol:
            t = exp.pop()[0]
        if not exp or exp[-1][2] != allowed:
            exp.append((t, on, allowed))
    out.checks.update(events=len(exp) - 1, jumps=len(ref.jumps))
    for (_, a, _), (_, b, _) in zip(exp, exp[1:]):     # which kinds of switching were seen
        for nm in a ^ b:
            p = case.net.part(nm)
            key = "diode_events" if p.kind == "D" else f"{p.gate[0]}_switch_events"
            out.checks[key] = out.checks.get(key, 0) + 1

    def fail(msg: str) -> None:
        out.cls, out.detail = "wrong", msg

    def allowed_at(t: float) -> frozenset:
        return [a for te, _, a in exp if te <= t + tol][-1]

    def fits(m: frozenset, allowed: frozenset, t: float) -> bool:
        """``m`` is allowed, or differs from an allowed mode only in idle diodes."""
        if m in allowed:
            return True
        idle = ref.idle(t)
        return any((m ^ a) <= idle for a in allowed)

    if got[0][1] not in exp[0][2]:
        return fail(f"initial mode: got on={sorted(got[0][1])}, expected on={sorted(exp[0][1])}")
    for k in range(1, len(exp)):              # every change the motion needs, in time
        te, on, allowed = exp[k]
        if not exp[k - 1][2] & allowed and not any(abs(t - te) <= tol and fits(m, allowed, te)
                                                   for t, m in got[1:]):
            near = [(round(t, 12), sorted(m)) for t, m in got[1:] if abs(t - te) < 0.1 * case.t1]
            return fail(f"missed the event at t = {te:.12g} to on={sorted(on)}; got {near or 'none'} "
                        "near it")
    for t, m in got[1:]:                       # every change the package made, to a mode allowed
        match = [a for te, _, a in exp[1:] if abs(te - t) <= tol]
        if not (match and fits(m, match[-1], t)) and not fits(m, allowed_at(t), t):
            return fail(f"event at t = {t:.12g} to on={sorted(m)}; expected one of "
                        f"{[sorted(x) for x in (match[-1] if match else allowed_at(t))]} there")
    times = np.array([t for t, _, _ in exp[1:]] + ref.jumps)
    away = [i for i, t in enumerate(grid) if not times.size or np.abs(times - t).min() > AWAY * case.t1]
    ts = np.asarray(res.t)
    top = max(float(np.nanmax(np.abs(v))) for v in ref.states.values()) if ref.states else 0.0
    for i in away:
        idx = np.nonzero(ts == grid[i])[0]
        if not idx.size:
            return fail(f"no sample at t = {grid[i]:.9g}")
        j = int(idx[-1])
        mode = frozenset(res.modes[int(res.mode_index[j])].on)
        if not fits(mode, ref.modes[i], grid[i]):
            return fail(f"t = {grid[i]:.9g}: mode on={sorted(mode)}, expected one of "
                        f"{[sorted(x) for x in ref.modes[i]]}")
        for nm, q_ref in ref.states.items():
            lab = ("q_" if case.net.part(nm).kind == "C" else "p_") + nm
            if lab not in res.stored:        # in derivative causality in every mode
                lab = ("displacement[" if case.net.part(nm).kind == "C" else "momentum[") + nm + "]"
            q = res.stored[lab][j] if lab in res.stored else None
            scale = max(float(np.nanmax(np.abs(q_ref))), 1e-3 * top, 1e-3)
            if q is None or not abs(q - q_ref[i]) <= TOL_X * scale:
                return fail(f"t = {grid[i]:.9g}: {lab} = {q!r}, expected {q_ref[i]!r} "
                            f"(tolerance {TOL_X * scale:.3g})")
    out.checks["compared"] = len(away)
