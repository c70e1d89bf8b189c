"""Random linear bond graphs, their bondgraph builds, and the differential check.

* :func:`generate` -- a random *valid* linear bond graph (a
  :class:`~verification.reference.Graph`) with the structures real models
  have: RC/RLC ladders, bridges, random circuits (nodes as 0-junctions,
  branches as 1-junctions), trees and chains of 0/1 junctions carrying
  several storage and R elements, TF/GY chains (drivetrains), parallel bonds,
  junction cycles (algebraic loops), rigidly joined storage (derivative
  causality), several Se/Sf inputs, random bond directions, outputs of every
  kind and linear combinations of them; half of them are dualized
  (0<->1, I<->C, Se<->Sf).  Some use source names that clash with engine
  internals (``p_m``, ``q_k``, ``f_2``, ``x_m``).
* :func:`build` -- the :class:`bondgraph.BondGraph` of a description, with
  ``add``/``connect`` in a random order chosen by a seed; parameters are left
  to the engine's default (a positive symbol named after the element).
* :func:`check` -- the differential verification of one graph: the symbolic
  transfer matrix (evaluated) and the numeric plant's frequency response,
  each in two insertion orders, against the exact reference of
  :mod:`verification.reference`; the outcome is one of :data:`CLASSES`.
* :func:`shrink` -- a minimal reproducer of a failure class;
  :func:`dsl` prints a graph as plain bondgraph code.

Examples
--------
>>> g = generate(7)
>>> g.family in FAMILIES, 2 <= len(g.elements) <= 25
(True, True)
>>> check(generate(7)).cls in CLASSES
True
"""

from __future__ import annotations

import random
import signal
import time
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from typing import Callable, Optional

import numpy as np

from verification.reference import (PARAM_KINDS, SOURCES, Bond, DescriptionError,
                                    Element, Graph, Output, Reference, Term, check_graph)

__all__ = ["generate", "build", "check", "shrink", "dsl", "Outcome", "CLASSES", "FAILURES",
           "FAMILIES", "GraphTimeout"]

FAMILIES = ("ladder", "bridge", "circuit", "tree", "drivetrain", "rigid")

#: outcome classes, worst first
CLASSES = ("WRONG", "crash", "timeout", "ill-posed-but-answered", "refused-but-well-posed",
           "refused-name-clash", "ill-posed-correctly-refused", "agree")
#: classes that are failures
FAILURES = ("WRONG", "crash", "timeout", "ill-posed-but-answered", "refused-but-well-posed")

_PREFIX = {"Se": "E", "Sf": "F", "I": "I", "C": "C", "R": "R", "TF": "T", "GY": "G",
           "Zero": "z", "One": "o"}
_DUAL = {"Zero": "One", "One": "Zero", "I": "C", "C": "I", "Se": "Sf", "Sf": "Se",
         "R": "R", "TF": "TF", "GY": "GY"}
_DUAL_SIGNAL = {"effort": "flow", "flow": "effort", "displacement": "momentum",
                "momentum": "displacement"}


# ============================================================ generation
def _value(rng: random.Random) -> float:
    """Log-uniform in [0.1, 10], four significant digits (exact as decimal)."""
    return float(f"{10 ** rng.uniform(-1, 1):.4g}")


class _Draft:
    """Mutable graph under generation."""

    def __init__(self, rng: random.Random, p_reverse: float = 0.2) -> None:
        self.rng = rng
        self.kind: dict[str, str] = {}
        self.value: dict[str, Optional[float]] = {}
        self.bonds: list[tuple[str, str]] = []
        self.count: dict[str, int] = {}
        self.p_reverse = p_reverse

    def add(self, kind: str) -> str:
        self.count[kind] = self.count.get(kind, 0) + 1
        name = f"{_PREFIX[kind]}{self.count[kind]}"
        self.kind[name] = kind
        self.value[name] = _value(self.rng) if kind in PARAM_KINDS else None
        return name

    def degree(self, name: str) -> int:
        return sum(name in b for b in self.bonds)

    def attach(self, junction: str, kind: str) -> str:
        """A one-port on a junction; power normally into storage/R and out of sources."""
        el = self.add(kind)
        normal = (el, junction) if kind in SOURCES else (junction, el)
        p = 0.15 if kind in SOURCES else self.p_reverse
        self.bonds.append(normal[::-1] if self.rng.random() < p else normal)
        return el

    def link(self, a: str, b: str, via: Optional[str] = None) -> None:
        """Junction to junction, directly (random direction) or through a TF/GY."""
        if self.rng.random() < 0.5:
            a, b = b, a
        if via is None:
            self.bonds.append((a, b))
        else:
            t = self.add(via)
            self.bonds += [(a, t), (t, b)]

    def junctions(self, kind: Optional[str] = None) -> list[str]:
        return [n for n, k in self.kind.items() if k in ((kind,) if kind else ("Zero", "One"))]

    def fix_degrees(self) -> None:
        """Every junction gets at least two bonds (an R or C where missing)."""
        for j in self.junctions():
            while self.degree(j) < 2:
                self.attach(j, self.rng.choice(["R", "R", "C", "I"]))

    def size(self) -> int:
        return len(self.kind)


def _branch_contents(rng: random.Random, storage: float = 0.6) -> list[str]:
    n = rng.choice([1, 1, 1, 2, 2, 3])
    out = []
    for _ in range(n):
        r = rng.random()
        out.append("R" if r > storage else ("C" if rng.random() < 0.5 else "I"))
    return out


def _circuit(d: _Draft, n_nodes: int, branches: list[tuple[Optional[int], Optional[int], list[str]]]):
    """Nodes are 0-junctions (ground removed); each branch a 1-junction in series
    between two nodes, or an element straight on a node when it goes to ground."""
    rng = d.rng
    nodes = [d.add("Zero") for _ in range(n_nodes)]
    for i, j, contents in branches:
        ends = [nodes[x] for x in (i, j) if x is not None]
        if len(ends) == 1 and len(contents) == 1 and rng.random() < 0.6:
            d.attach(ends[0], contents[0])          # shunt to ground
            continue
        if not ends:
            continue
        o = d.add("One")
        for end in ends:
            # node -> branch -> node with occasional reversal
            if rng.random() < 0.25:
                d.bonds.append((o, end) if end == ends[0] else (end, o))
            else:
                d.bonds.append((end, o) if end == ends[0] else (o, end))
        for kind in contents:
            d.attach(o, kind)
    return nodes


def _source(rng: random.Random, se: float = 0.7) -> str:
    return "Se" if rng.random() < se else "Sf"


def _ladder(d: _Draft) -> None:
    rng = d.rng
    n = rng.randint(1, 5)
    src = _source(rng)
    branches: list = [(None, 0, [src] + (["R"] if src == "Se" or rng.random() < 0.3 else [])
                       + (["I"] if rng.random() < 0.2 else []))]
    for k in range(n):
        shunt = ["C"] + (["R"] if rng.random() < 0.25 else [])
        if rng.random() < 0.2:
            shunt = ["C", "C"] if rng.random() < 0.5 else ["R"]
        branches.append((k, None, shunt))
        if rng.random() < 0.25:
            branches.append((k, None, ["R"]))       # drain: C fed through R, drained by R
        if k + 1 < n:
            series = ["R"] + (["I"] if rng.random() < 0.3 else [])
            branches.append((k, k + 1, series))
    if rng.random() < 0.7:
        branches.append((n - 1, None, ["R"]))
    if rng.random() < 0.3:
        branches.append((rng.randrange(n), None, [_source(rng, 0.3)]))
    _circuit(d, n, branches)


def _bridge(d: _Draft) -> None:
    rng = d.rng
    top, a, b = 0, 1, 2
    src = _source(rng)
    branches: list = [(None, top, [src] + (["R"] if rng.random() < 0.7 else []))]
    for i, j in [(top, a), (top, b), (a, None), (b, None)]:
        branches.append((i, j, _branch_contents(rng, 0.4)))
    branches.append((a, b, ["R"] + (["C"] if rng.random() < 0.5 else (["I"] if rng.random() < 0.5 else []))))
    if rng.random() < 0.3:
        branches.append((a, None, ["C"]))
    _circuit(d, 3, branches)


def _random_circuit(d: _Draft) -> None:
    rng = d.rng
    n = rng.randint(2, 5)
    branches: list = []
    # spanning tree over nodes and ground (None)
    pts: list[Optional[int]] = [None]
    for k in range(n):
        branches.append((rng.choice(pts), k, _branch_contents(rng)))
        pts.append(k)
    for _ in range(rng.randint(0, 3)):
        i, j = rng.sample(pts, 2)
        branches.append((i, j, _branch_contents(rng)))
    for _ in range(rng.randint(1, 2)):
        k = rng.randrange(n)
        src = _source(rng, 0.6)
        branches.append((None, k, [src] + (["R"] if rng.random() < 0.5 else [])))
    _circuit(d, n, branches)


def _tree(d: _Draft, *, chain: bool = False, p_two: float = 0.3) -> None:
    rng = d.rng
    n = rng.randint(2, 7)
    js: list[str] = []
    for k in range(n):
        kind = ("Zero" if k % 2 else "One") if (chain and rng.random() < 0.7) else rng.choice(["Zero", "One"])
        j = d.add(kind)
        if js:
            parent = js[-1] if chain else rng.choice(js)
            r = rng.random()
            via = ("TF" if rng.random() < 0.55 else "GY") if r < p_two else None
            d.link(parent, j, via)
        js.append(j)
        for _ in range(rng.choice([0, 1, 1, 2, 2, 3])):
            d.attach(j, rng.choice(["I", "C", "R", "R"] if not chain else
                                   (["I", "R"] if kind == "One" else ["C", "R"]) + ["I", "C", "R"]))
    for _ in range(rng.choice([1, 1, 2, 3])):
        d.attach(rng.choice(js), _source(rng, 0.6))
    if rng.random() < 0.2 and n >= 2:                      # parallel bonds
        a, b = rng.sample(js, 2)
        d.link(a, b)
        d.link(a, b)
    if rng.random() < 0.25 and n >= 3:                     # a junction cycle
        a, b = rng.sample(js, 2)
        d.link(a, b, "TF" if rng.random() < 0.2 else None)
    if rng.random() < 0.3:                                 # rigidly joined storage
        j = rng.choice(js)
        st = "I" if d.kind[j] == "One" else "C"
        d.attach(j, st)
        d.attach(j, st)


def _drivetrain(d: _Draft) -> None:
    _tree(d, chain=True, p_two=0.6)


def _rigid(d: _Draft) -> None:
    """Storage joined rigidly: inertias through a TF/GY, twin storage, sources on storage."""
    rng = d.rng
    a, b = d.add("One"), d.add("One")
    d.attach(a, "I")
    if rng.random() < 0.5:
        d.attach(a, "R")
    d.link(a, b, rng.choice(["TF", "TF", "GY", None]))
    d.attach(b, "I")
    if rng.random() < 0.5:
        d.attach(b, "R")
    if rng.random() < 0.5:
        c = d.add("Zero")
        d.link(b, c)
        d.attach(c, "C")
        if rng.random() < 0.5:
            d.attach(c, "C")
        if rng.random() < 0.5:
            e = d.add("One")
            d.link(c, e, "TF" if rng.random() < 0.5 else None)
            d.attach(e, "I")
            d.attach(e, rng.choice(["R", "I"]))
    js = d.junctions()
    for _ in range(rng.choice([1, 1, 2])):
        d.attach(rng.choice(js), _source(rng, 0.5))


_BUILDERS: dict[str, Callable[[_Draft], None]] = {
    "ladder": _ladder, "bridge": _bridge, "circuit": _random_circuit, "tree": _tree,
    "drivetrain": _drivetrain, "rigid": _rigid,
}


def _signals(g: Graph) -> list[tuple[str, object]]:
    """Every (kind, target) the engine accepts as a signal, weighted by repetition."""
    out: list[tuple[str, object]] = []
    for el in g.elements:
        if el.kind in ("I", "C", "R"):
            out += [(k, el.name) for k in ("effort", "flow", "displacement", "momentum")] * 2
        elif el.kind in SOURCES:
            out += [(k, el.name) for k in ("effort", "flow", "displacement", "momentum")]
        elif el.kind == "Zero":
            out += [("effort", el.name), ("momentum", el.name)]
        elif el.kind == "One":
            out += [("flow", el.name), ("displacement", el.name)]
    for b in g.bonds:
        out += [(k, b.id) for k in ("effort", "flow", "displacement", "momentum")]
    return out


def _outputs(rng: random.Random, g: Graph) -> tuple[Output, ...]:
    sigs = _signals(g)
    outs = []
    for i in range(rng.choice([1, 1, 2, 2, 3, 4])):
        if rng.random() < 0.7:
            kind, target = rng.choice(sigs)
            terms: tuple[Term, ...] = (Term(1, kind, target),)
        else:
            drawn = [Term(rng.choice([-3, -2, -1, 1, 2, 3]), *rng.choice(sigs))
                     for _ in range(rng.choice([2, 2, 3]))]
            # a signal drawn twice is one term: 2*x - 2*x would reach the engine as the
            # number 0, which no engine can tell from a forgotten signal
            merged: dict[tuple, int] = {}
            for t in drawn:
                merged[(t.kind, t.target)] = merged.get((t.kind, t.target), 0) + t.coef
            terms = tuple(Term(c, k, tg) for (k, tg), c in merged.items() if c) or \
                (Term(1, drawn[0].kind, drawn[0].target),)
        outs.append(Output(f"y{i + 1}", terms))
    return tuple(outs)


def _dual(g: Graph) -> Graph:
    els = tuple(replace(el, kind=_DUAL[el.kind]) for el in g.elements)
    # names keep the original prefix letters; rename to match the new kind
    count: dict[str, int] = {}
    rename = {}
    for el in els:
        count[el.kind] = count.get(el.kind, 0) + 1
        rename[el.name] = f"{_PREFIX[el.kind]}{count[el.kind]}"
    return _renamed(replace(g, elements=els, outputs=tuple(
        Output(o.name, tuple(Term(t.coef, _DUAL_SIGNAL[t.kind], t.target) for t in o.terms))
        for o in g.outputs)), rename)


def _renamed(g: Graph, rename: dict[str, str]) -> Graph:
    def r(n):
        return rename.get(n, n) if isinstance(n, str) else n
    return replace(
        g,
        elements=tuple(replace(el, name=r(el.name)) for el in g.elements),
        bonds=tuple(Bond(b.id, r(b.tail), r(b.head)) for b in g.bonds),
        outputs=tuple(Output(o.name, tuple(Term(t.coef, t.kind, r(t.target)) for t in o.terms))
                      for o in g.outputs))


def _clash(rng: random.Random, g: Graph) -> Graph:
    """Rename one source to a name the engine also uses internally (issue 11, case 2)."""
    srcs = [el.name for el in g.sources]
    if not srcs:
        return g
    src = rng.choice(srcs)
    Is = [el.name for el in g.elements if el.kind == "I"]
    Cs = [el.name for el in g.elements if el.kind == "C"]
    choices = ["f_bond", "e_bond", "x_out", "h_out"] + (["p_I"] * 2 if Is else []) + (["q_C"] * 2 if Cs else [])
    pick = rng.choice(choices)
    taken = {el.name for el in g.elements}
    outputs = list(g.outputs)
    if pick == "p_I":
        new = "p_" + rng.choice(Is)
    elif pick == "q_C":
        new = "q_" + rng.choice(Cs)
    elif pick in ("f_bond", "e_bond"):
        new = f"{pick[0]}_{rng.randint(1, len(g.bonds))}"
    else:  # an output named like the source that is exactly a displacement / momentum
        targets = [el.name for el in g.elements if el.kind in ("I", "C", "R") and el.name != src]
        if not targets:
            return g
        t = rng.choice(targets)
        kind = "displacement" if pick == "x_out" else "momentum"
        new = f"{pick[0]}_{t}"
        outputs.append(Output(new, (Term(1, kind, t),)))
    if new in taken:
        return g
    g = replace(g, outputs=tuple(outputs))
    g = _renamed(g, {src: new})
    meta = dict(g.meta)
    meta["clash"] = new
    return replace(g, meta=meta)


def generate(seed: int, *, max_elements: int = 25, family: Optional[str] = None,
             p_clash: float = 0.08) -> Graph:
    """A random valid linear bond graph, reproducible from ``seed``."""
    rng = random.Random(seed * 7919 + 17)
    fam = family or rng.choice(FAMILIES)
    for attempt in range(400):
        if attempt == 200:
            fam = "rigid"          # the smallest family, when the size limit is tight
        d = _Draft(rng)
        _BUILDERS[fam](d)
        d.fix_degrees()
        if not any(k in SOURCES for k in d.kind.values()):
            d.attach(rng.choice(d.junctions()), _source(rng))
        if d.size() <= max_elements:
            break
    else:  # pragma: no cover
        raise RuntimeError(f"no graph of at most {max_elements} elements for seed {seed}")
    els = tuple(Element(n, k, d.value[n]) for n, k in d.kind.items())
    bonds = tuple(Bond(i + 1, t, h) for i, (t, h) in enumerate(d.bonds))
    g = Graph(f"g{seed}", els, bonds, (), family=fam, seed=seed)
    if rng.random() < 0.5:
        g = _dual(g)
        g = replace(g, family=fam + "*")
    g = replace(g, outputs=_outputs(rng, g))
    if rng.random() < p_clash:
        g = _clash(rng, g)
    check_graph(g)
    return g


# ============================================================ building
def _signal_expr(bg, g: Graph, out: Output, number: dict[int, int]):
    expr = 0
    for t in out.terms:
        target = number[t.target] if isinstance(t.target, int) else t.target
        expr = expr + t.coef * getattr(bg, t.kind)(target)
    return expr


def order(g: Graph, order_seed: Optional[int]) -> list[tuple]:
    """Actions ``("add", [names])`` / ``("connect", bond)`` in a random valid order.

    ``order_seed=None`` is the description's order: every element, then every bond.
    """
    if order_seed is None:
        return [("add", [el.name for el in g.elements])] + [("connect", b) for b in g.bonds]
    rng = random.Random(order_seed)
    names = [el.name for el in g.elements]
    rng.shuffle(names)
    pos = {n: i for i, n in enumerate(names)}
    keyed: list[tuple[float, int, tuple]] = [(float(i), 0, ("add", [n])) for n, i in pos.items()]
    for b in g.bonds:
        lo = max(pos[b.tail], pos[b.head])
        keyed.append((lo + 1e-9 + rng.random() * (len(names) - lo), 1, ("connect", b)))
    keyed.sort(key=lambda x: (x[0], x[1]))
    actions: list[tuple] = []
    for _, _, act in keyed:   # merge some consecutive adds into one add(*items) call
        if act[0] == "add" and actions and actions[-1][0] == "add" and rng.random() < 0.5:
            actions[-1] = ("add", actions[-1][1] + act[1])
        else:
            actions.append(act)
    return actions


def build(g: Graph, order_seed: Optional[int] = None):
    """``(BondGraph, outputs, bond number of each bond id)`` in a random insertion order."""
    import bondgraph as bg

    ctor = {"Se": bg.Se, "Sf": bg.Sf, "I": bg.I, "C": bg.C, "R": bg.R, "TF": bg.TF, "GY": bg.GY,
            "Zero": bg.Zero, "One": bg.One}
    kinds = {el.name: el.kind for el in g.elements}
    bgg = bg.BondGraph(g.name)
    number: dict[int, int] = {}
    for act in order(g, order_seed):
        if act[0] == "add":
            bgg.add(*(ctor[kinds[n]](n) for n in act[1]))
        else:
            b = act[1]
            number[b.id] = bgg.connect(b.tail, b.head).number
    outputs = {o.name: _signal_expr(bg, g, o, number) for o in g.outputs}
    return bgg, outputs, number


def values(g: Graph) -> dict[str, float]:
    return {el.name: el.value for el in g.elements if el.value is not None}


def dsl(g: Graph, order_seed: Optional[int] = None, *, s: Optional[complex] = None,
        expected=None, got=None, path: str = "symbolic") -> str:
    """Plain bondgraph code building ``g`` in the given insertion order."""
    ctor = {"Zero": "Zero", "One": "One"}
    kinds = {el.name: el.kind for el in g.elements}
    lines = ["import bondgraph as bg", "", f'g = bg.BondGraph("{g.name}")']
    number: dict[int, int] = {}
    pending: list[str] = []

    def flush():
        if pending:
            lines.append("for tail, head in [" + ", ".join(pending) + "]:")
            lines.append("    g.connect(tail, head)")
            pending.clear()

    for act in order(g, order_seed):
        if act[0] == "add":
            flush()
            items = ", ".join(f'bg.{ctor.get(kinds[n], kinds[n])}("{n}")' for n in act[1])
            lines.append(f"g.add({items})")
        else:
            b = act[1]
            number[b.id] = len(number) + 1
            pending.append(f'("{b.tail}", "{b.head}")')
    flush()

    def term(t: Term) -> str:
        target = number[t.target] if isinstance(t.target, int) else f'"{t.target}"'
        sig = f"bg.{t.kind}({target})"
        return sig if t.coef == 1 else (f"-{sig}" if t.coef == -1 else f"{t.coef}*{sig}")

    outs = ", ".join(f'"{o.name}": ' + " + ".join(term(t) for t in o.terms).replace("+ -", "- ")
                     for o in g.outputs)
    lines.append(f"model = bg.derive(g, outputs={{{outs}}})")
    lines.append(f"values = {values(g)!r}")
    if s is not None:
        lines[0] = "import bondgraph as bg\nimport numpy as np"
        lines.append(f"s = {s!r}")
        if path == "numeric":
            lines.append("P = bg.compile_plant(model).plant(values)")
            lines.append("print(P.C @ np.linalg.solve(s * np.eye(len(P.A)) - P.A, P.B) + P.D)")
        else:
            lines.append("T = model.transfer_matrix().subs(values)")
            lines.append("print(T.output_names, T.input_names, [[np.polyval(n, s) / np.polyval(T.den, s) "
                         "for n in row] for row in T.nums])")
    if expected is not None:
        lines.append(f"# reference G(s) [outputs x inputs]: {_fmt(expected)}")
    if got is not None:
        lines.append(f"# engine gave: {got}")
    return "\n".join(lines)


def _fmt(a) -> str:
    a = np.asarray(a)
    return np.array2string(a, precision=8, separator=", ", max_line_width=200).replace("\n", "")


# ============================================================ checking
class GraphTimeout(BaseException):
    """Raised by the time limit (a BaseException so ``except Exception`` in the
    engine cannot swallow it)."""


@contextmanager
def time_limit(seconds: Optional[float]):
    """Limit the CPU time of the block to ``seconds`` (``ITIMER_PROF``, so a loaded
    machine does not cause spurious timeouts), with a wall-clock backstop of
    ``4*seconds + 10`` (``ITIMER_REAL``); raises :class:`GraphTimeout`.  Main
    thread only (as under pytest and pytest-xdist workers); no-op when None.
    """
    if not seconds:
        yield
        return

    def handler(signum, frame):
        kind = "CPU" if signum == signal.SIGPROF else "wall-clock"
        raise GraphTimeout(f"{kind} time limit of {seconds if kind == 'CPU' else 4 * seconds + 10:g} s")

    old = {sig: signal.signal(sig, handler) for sig in (signal.SIGPROF, signal.SIGALRM)}
    signal.setitimer(signal.ITIMER_PROF, seconds)
    signal.setitimer(signal.ITIMER_REAL, 4 * seconds + 10)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.setitimer(signal.ITIMER_REAL, 0)
        for sig, h in old.items():
            signal.signal(sig, h)


@dataclass
class PathResult:
    """One engine path (``symbolic`` or ``numeric``) in one insertion order."""

    path: str
    order_seed: Optional[int]
    status: str            # agree / wrong / refused / crash / answered (ill-posed)
    detail: str = ""
    got: object = None


@dataclass
class Outcome:
    cls: str
    graph: Graph
    detail: str = ""
    order_seed: Optional[int] = None
    s: Optional[complex] = None
    expected: object = None
    got: object = None
    paths: list = field(default_factory=list)
    seconds: float = 0.0
    order_dependent: bool = False
    tol_above_1e8: bool = False   # an evaluation error bound exceeded the 1e-8 tolerance

    def reproducer(self) -> str:
        head = f"# {self.cls}: {self.detail}".rstrip()
        return head + "\n" + dsl(self.graph, self.order_seed, s=self.s, expected=self.expected,
                                 got=self.got, path="numeric" if "numeric" in self.detail else "symbolic")


_EPS = np.finfo(float).eps
RTOL = 1e-8


def _compare(ref: np.ndarray, val: np.ndarray, bound: np.ndarray) -> tuple[bool, float, tuple]:
    """Entrywise ``|val - ref| <= 1e-8*max(|ref|, floor) + bound``; floor is 1e-12 of
    the largest reference entry (so exact zeros compare absolutely)."""
    floor = 1e-12 * float(np.max(np.abs(ref))) if ref.size else 0.0
    scale = np.maximum(np.abs(ref), max(floor, 1e-300))
    err = np.abs(val - ref)
    ok = err <= RTOL * scale + bound
    rel = err / scale
    worst = np.unravel_index(int(np.argmax(rel - bound / scale)), ref.shape) if ref.size else ()
    return bool(np.all(ok)), float(np.max(rel)) if ref.size else 0.0, tuple(int(i) for i in worst)


def _poly_eval(c, s: complex) -> tuple[complex, float]:
    """Horner value and the sum of |c_k| |s|^k (for the rounding bound)."""
    v = 0j
    a = 0.0
    for x in c:
        v = v * s + x
        a = a * abs(s) + abs(x)
    return v, a


def _symbolic_at(tm, vals: dict, s_list, in_names, out_names):
    """Entries of ``model.transfer_matrix()`` at each s, aligned to (outputs, inputs)."""
    N = tm.subs(vals)
    ins, outs = list(N.input_names), list(N.output_names)
    res = []
    for s in s_list:
        G = np.zeros((len(out_names), len(in_names)), complex)
        B = np.zeros(G.shape)
        dv, da = _poly_eval(N.den, s)
        deg = len(N.den) + 2
        for i, o in enumerate(out_names):
            for j, u in enumerate(in_names):
                if u not in ins or o not in outs:
                    continue   # an input the engine lost: a zero column
                nv, na = _poly_eval(N.nums[outs.index(o)][ins.index(u)], s)
                G[i, j] = nv / dv
                B[i, j] = 8 * deg * _EPS * (na + abs(G[i, j]) * da) / abs(dv)
        res.append((G, B))
    return res, ins, outs


def _numeric_at(plant, s_list, in_names, out_names):
    """``C (sI-A)^-1 B + D + sum_k D_derivatives[k-1] s^k`` at each s, aligned to
    (outputs, inputs).  A purely imaginary ``s = j*w`` goes through the plant's
    public ``frequency_response([w])`` instead."""
    A, Bm, C, D = (np.asarray(M, float) for M in (plant.A, plant.B, plant.C, plant.D))
    Dd = [np.asarray(M, float) for M in getattr(plant, "D_derivatives", ())]
    ins, outs = list(plant.input_names), list(plant.output_names)
    n = A.shape[0]
    res = []
    for s in s_list:
        G = np.zeros((len(out_names), len(in_names)), complex)
        Bd = np.zeros(G.shape)
        if n:
            M = s * np.eye(n) - A
            X = np.linalg.solve(M, Bm.astype(complex))
            cond = np.linalg.cond(M)
            H = C @ X + D
            # norm-wise: the rounding error of X's column is relative to its norm, so an
            # exact zero may come out as ~eps*cond*|C_i|*|X_j| (never entrywise |C||X|)
            Hb = 8 * (n + 2) * _EPS * (cond * np.outer(np.linalg.norm(C, axis=1),
                                                       np.linalg.norm(X, axis=0)) + np.abs(D))
        else:
            H = D.astype(complex)
            Hb = 4 * _EPS * np.abs(D)
        for k, Mk in enumerate(Dd, start=1):
            H = H + Mk * s ** k
            Hb = Hb + 4 * _EPS * np.abs(Mk) * abs(s) ** k
        if s.real == 0:
            H = np.asarray(plant.frequency_response([s.imag]))[0]
        for i, o in enumerate(out_names):
            for j, u in enumerate(in_names):
                if u in ins and o in outs:
                    G[i, j] = H[outs.index(o), ins.index(u)]
                    Bd[i, j] = Hb[outs.index(o), ins.index(u)]
        res.append((G, Bd))
    return res, ins, outs


def _run_order(g: Graph, order_seed, ref: Optional[Reference], s_list, G_ref, well_posed: bool):
    """Both engine paths in one insertion order -> list of PathResult.

    Engine warnings (reversed bonds are generated on purpose) are silenced.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return _run_order_quiet(g, order_seed, s_list, G_ref, well_posed)


def _run_order_quiet(g: Graph, order_seed, s_list, G_ref, well_posed: bool):
    import bondgraph as bg

    vals = values(g)
    in_names = [el.name for el in g.sources]
    out_names = [o.name for o in g.outputs]
    try:
        bgg, outputs, _ = build(g, order_seed)
        model = bg.derive(bgg, outputs)
    except bg.BondGraphError as exc:
        return [PathResult("derive", order_seed, "refused", f"{type(exc).__name__}: {exc}")]
    except (GraphTimeout, KeyboardInterrupt):
        raise
    except Exception as exc:  # noqa: BLE001 - classifying
        return [PathResult("derive", order_seed, "crash", f"{type(exc).__name__}: {exc}")]
    results = []
    for path in ("symbolic", "numeric"):
        try:
            if path == "symbolic":
                tm = model.transfer_matrix()
                at, ins, outs = _symbolic_at(tm, vals, s_list, in_names, out_names)
            else:
                nm = bg.compile_plant(model)
                plant = nm.plant({k: vals[k] for k in nm.parameter_names})
                at, ins, outs = _numeric_at(plant, s_list, in_names, out_names)
        except bg.BondGraphError as exc:
            results.append(PathResult(path, order_seed, "refused", f"{type(exc).__name__}: {exc}"))
            continue
        except (GraphTimeout, KeyboardInterrupt):
            raise
        except Exception as exc:  # noqa: BLE001
            results.append(PathResult(path, order_seed, "crash", f"{type(exc).__name__}: {exc}"))
            continue
        if not well_posed:
            results.append(PathResult(path, order_seed, "answered",
                                      f"{path} path answered an ill-posed graph", at[0][0]))
            continue
        extra = sorted(set(ins) - set(in_names)) + sorted(set(outs) - set(out_names))
        missing = sorted(set(in_names) - set(ins))
        status, detail, got = "agree", "", None
        big_bound = False
        for s, G_r, (G, Bd) in zip(s_list, G_ref, at):
            ok, rel, worst = _compare(G_r, G, Bd)
            big_bound |= bool(np.any(Bd > RTOL * np.maximum(np.abs(G_r), 1e-300)))
            if not ok or extra:
                status = "wrong"
                detail = (f"{path} path, s={s}: max rel error {rel:.3g} at (output "
                          f"{out_names[worst[0]] if worst else '?'}, input "
                          f"{in_names[worst[1]] if worst else '?'})"
                          + (f"; engine lost inputs {missing}" if missing else "")
                          + (f"; unexpected signals {extra}" if extra else ""))
                got = (s, G)
                break
        r = PathResult(path, order_seed, status, detail, got)
        r.big_bound = big_bound  # type: ignore[attr-defined]
        results.append(r)
    return results


def check(g: Graph, *, orders=(None, 1), n_s: int = 2, seed: int = 0,
          time_limit_s: Optional[float] = None) -> Outcome:
    """Differential check of one graph; see :data:`CLASSES`.

    ``orders`` are insertion-order seeds for :func:`build` (``None``: the
    description's order).
    """
    t0 = time.perf_counter()
    rng = random.Random(seed * 31 + g.seed)
    paths: list[PathResult] = []
    current: object = "reference"     # what runs when a time limit strikes
    try:
        with time_limit(time_limit_s):
            ref = Reference(g, seed=seed)
            well = ref.well_posed
            s_list = ref.pick_s(rng, n_s, axis=True) if well else []
            G_ref = [ref.evaluate(s) for s in s_list]
            for o in orders:
                current = o
                paths += _run_order(g, o, ref, s_list, G_ref, well)
    except GraphTimeout as exc:
        where = "in the reference" if current == "reference" else f"insertion order {current}"
        return Outcome("timeout", g, f"{exc} ({where})", None if current == "reference" else current,
                       paths=paths,
                       seconds=time.perf_counter() - t0)
    out = _classify(g, well, paths, s_list, G_ref)
    out.seconds = time.perf_counter() - t0
    return out


def _classify(g: Graph, well: bool, paths: list[PathResult], s_list, G_ref) -> Outcome:
    clash = g.meta.get("clash")
    by_order: dict = {}
    for p in paths:
        by_order.setdefault(p.order_seed, []).append(p)
    per_order = {}
    for o, ps in by_order.items():
        sts = {p.status for p in ps}
        if "wrong" in sts:
            per_order[o] = "WRONG"
        elif "crash" in sts:
            per_order[o] = "crash"
        elif not well:
            per_order[o] = "ill-posed-but-answered" if "answered" in sts else "ill-posed-correctly-refused"
        elif "refused" in sts:
            msgs = " ".join(p.detail for p in ps if p.status == "refused")
            per_order[o] = ("refused-name-clash" if clash and clash in msgs
                            else "refused-but-well-posed")
        else:
            per_order[o] = "agree"
    worst = min(per_order.values(), key=CLASSES.index)
    o = next(k for k, v in per_order.items() if v == worst)
    status_key = {"WRONG": "wrong", "crash": "crash", "ill-posed-but-answered": "answered",
                  "refused-but-well-posed": "refused", "refused-name-clash": "refused"}
    p = next((p for p in by_order[o] if p.status == status_key.get(worst)), None)
    out = Outcome(worst, g, p.detail if p else "", o, paths=paths,
                  order_dependent=len(set(per_order.values())) > 1,
                  tol_above_1e8=any(getattr(q, "big_bound", False) for q in paths))
    if s_list:
        out.s = s_list[0]
        out.expected = G_ref[0]
    if p is not None and p.got is not None and worst == "WRONG":
        out.s, G = p.got
        out.expected = G_ref[list(s_list).index(out.s)]
        out.got = _fmt(G)
    return out


# ============================================================ shrinking
def _drop_element(g: Graph, name: str) -> Optional[Graph]:
    """Remove a one-port (and its bond), outputs that use it, and repair junctions."""
    bonds = tuple(b for b in g.bonds if name not in (b.tail, b.head))
    dropped = {b.id for b in g.bonds} - {b.id for b in bonds}
    els = tuple(el for el in g.elements if el.name != name)
    return _tidy(replace(g, elements=els, bonds=bonds), dropped | {name})


def _tidy(g: Graph, gone: set) -> Optional[Graph]:
    outs = tuple(o for o in g.outputs if not any(t.target in gone for t in o.terms))
    if not outs:
        return None
    g = replace(g, outputs=outs)
    # junctions left with one bond: remove them with their bond (repeat)
    changed = True
    while changed:
        changed = False
        for el in g.elements:
            if el.kind in ("Zero", "One") and len(g.bonds_of(el.name)) < 2:
                ks = g.bonds_of(el.name)
                bid = {g.bonds[k].id for k in ks}
                g = replace(g, elements=tuple(e for e in g.elements if e.name != el.name),
                            bonds=tuple(b for b in g.bonds if b.id not in bid))
                gone |= bid | {el.name}
                changed = True
                break
    outs = tuple(o for o in g.outputs if not any(t.target in gone for t in o.terms))
    if not outs or not g.sources:
        return None
    g = replace(g, outputs=outs)
    try:
        check_graph(g)
    except (DescriptionError, KeyError):
        return None
    return g


def _contract(g: Graph, bond: Bond) -> Optional[Graph]:
    """Merge two same-kind junctions joined by ``bond`` (or bypass a TF/GY)."""
    kinds = {el.name: el.kind for el in g.elements}
    a, b = bond.tail, bond.head
    if kinds[a] in ("Zero", "One") and kinds[a] == kinds[b]:
        keep, gone = a, b
        bonds = tuple(Bond(x.id, keep if x.tail == gone else x.tail, keep if x.head == gone else x.head)
                      for x in g.bonds if x.id != bond.id)
        if any(x.tail == x.head for x in bonds):
            return None
        els = tuple(el for el in g.elements if el.name != gone)
        outs = tuple(Output(o.name, tuple(Term(t.coef, t.kind, keep if t.target == gone else t.target)
                                          for t in o.terms)) for o in g.outputs)
        return _tidy(replace(g, elements=els, bonds=bonds, outputs=outs), {bond.id})
    return None


def _bypass(g: Graph, name: str) -> Optional[Graph]:
    """Replace a TF/GY by a direct bond."""
    ks = g.bonds_of(name)
    b_in = next(g.bonds[k] for k in ks if g.bonds[k].head == name)
    b_out = next(g.bonds[k] for k in ks if g.bonds[k].tail == name)
    new = Bond(b_in.id, b_in.tail, b_out.head)
    bonds = tuple(new if x.id == b_in.id else x for x in g.bonds if x.id != b_out.id)
    els = tuple(el for el in g.elements if el.name != name)
    if new.tail == new.head:
        return None
    return _tidy(replace(g, elements=els, bonds=bonds), {b_out.id, name})


def _candidates(g: Graph):
    """Smaller variants of ``g``, most aggressive first."""
    kinds = {el.name: el.kind for el in g.elements}
    for o in g.outputs:                                   # fewer outputs
        if len(g.outputs) > 1:
            yield replace(g, outputs=tuple(x for x in g.outputs if x is not o))
    for el in g.elements:                                 # drop one-ports (sources last)
        if el.kind in ("I", "C", "R"):
            c = _drop_element(g, el.name)
            if c is not None:
                yield c
    for el in g.elements:
        if el.kind in ("TF", "GY"):
            c = _bypass(g, el.name)
            if c is not None:
                yield c
    for b in g.bonds:
        c = _contract(g, b)
        if c is not None:
            yield c
    for b in g.bonds:                                     # drop a junction-junction bond
        if kinds[b.tail] in ("Zero", "One") and kinds[b.head] in ("Zero", "One"):
            c = _tidy(replace(g, bonds=tuple(x for x in g.bonds if x.id != b.id)), {b.id})
            if c is not None:
                yield c
    for el in g.sources:
        if len(g.sources) > 1:
            c = _drop_element(g, el.name)
            if c is not None:
                yield c
    for o in g.outputs:                                   # simpler output terms
        if len(o.terms) > 1:
            for t in o.terms:
                yield replace(g, outputs=tuple(Output(x.name, (t,) if x is o else x.terms)
                                               for x in g.outputs))
    for el in g.elements:                                 # round parameter values
        if el.value is not None and el.value != round(el.value, 1) and round(el.value, 1) > 0:
            yield replace(g, elements=tuple(replace(e, value=round(e.value, 1)) if e is el else e
                                            for e in g.elements))


def shrink(outcome: Outcome, *, budget_s: float = 60.0, time_limit_s: float = 20.0,
           orders=(None, 1)) -> Outcome:
    """Greedy minimization of a failure, keeping its class (any failing order)."""
    cls = outcome.cls
    best = outcome
    t_end = time.perf_counter() + budget_s
    improved = True
    while improved and time.perf_counter() < t_end:
        improved = False
        for cand in _candidates(best.graph):
            if time.perf_counter() > t_end:
                break
            try:
                res = check(cand, orders=orders, time_limit_s=time_limit_s)
            except DescriptionError:
                continue
            if res.cls == cls:
                best = res
                improved = True
                break
    return best
