"""Independent Laplace-domain reference solver for linear bond graphs.

This module shares no code with :mod:`bondgraph` (it imports nothing from
it): it works on its own plain description of a graph (:class:`Graph`) and
writes the bond graph's own equations, nothing derived by causality:

* unknowns: the effort ``e_k`` and flow ``f_k`` of every bond ``k``;
* 0-junction: equal efforts on all its bonds, signed flows sum to zero
  (``+`` for a bond pointing into the junction, ``-`` out of it);
* 1-junction: equal flows, signed efforts sum to zero;
* one-ports, written for the power flowing *into* the element, ``f_in = sigma*f_k``
  with ``sigma = +1`` when bond ``k`` points into the element, ``-1`` otherwise:
  ``I``: ``e = s*I*f_in``; ``C`` (compliance): ``f_in = s*C*e``; ``R``: ``e = R*f_in``;
* ``TF`` (port 1 = the bond into it, port 2 = the bond out): ``e1 = n*e2``, ``f2 = n*f1``;
* ``GY``: ``e1 = r*f2``, ``e2 = r*f1``;
* ``Se``: the bond effort is the input ``u`` (whatever the bond direction);
* ``Sf``: the flow *out of* the source is ``u``: ``-sigma*f_k = u`` (so the
  bond flow is ``u`` for the usual bond pointing away from the source).

These are the conventions of the user guide (docs/guide/conventions.md) and of
``bondgraph/elements.py``; the source-sign and signal conventions below were
read off ``bondgraph/equations.py`` (``_rule`` and ``_signal_var``), which the
documentation does not spell out for reversed source bonds.

Output signals (zero initial conditions, so integrals are ``1/s``):

* ``effort`` of a one-port: its bond effort; ``flow`` of a one-port: the flow
  *into* the element (``sigma*f_k``), so a reversed bond does not change the
  sign of an element's own effort, flow, momentum or displacement;
* ``effort`` of a 0-junction and ``flow`` of a 1-junction: the common value;
* ``effort``/``flow`` of a bond number: the bond's variables as directed;
* ``displacement`` = flow / s, ``momentum`` = effort / s.

The linear system ``M(s) x = B u`` (``M = M0 + s*M1``) is solved *exactly*
over the rationals (``python-flint``), with the complex ``s`` a Gaussian
rational: the real and imaginary parts are stacked into a real system of
twice the size.  Parameter values and ``s`` are given as floats and read by
their decimal representation, so a value printed with few digits is exact.
A graph is *ill-posed* when ``M(s)`` is singular at two random ``s`` (exact
rank), i.e. ``det(M0 + s*M1)`` vanishes identically: some bond variable is
not determined, and a correct engine must refuse such a graph.

Examples
--------
>>> g = Graph("rc", (Element("V", "Se"), Element("i", "One"), Element("R", "R", 2.0),
...                  Element("C", "C", 0.5)),
...           (Bond(1, "V", "i"), Bond(2, "i", "R"), Bond(3, "i", "C")),
...           (Output("vC", (Term(1, "effort", "C"),)),))
>>> ref = Reference(g)
>>> ref.well_posed, ref.input_names, ref.output_names
(True, ('V',), ('vC',))
>>> complex(ref.evaluate(1j)[0, 0])       # 1/(R*C*s + 1) at s = i
(0.5-0.5j)
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Optional, Sequence, Union

import flint
import numpy as np

__all__ = ["Element", "Bond", "Term", "Output", "Graph", "Reference", "KINDS", "PARAM_KINDS",
           "ONE_PORTS", "SOURCES", "exact", "DescriptionError"]

KINDS = ("Se", "Sf", "I", "C", "R", "TF", "GY", "Zero", "One")
PARAM_KINDS = ("I", "C", "R", "TF", "GY")
ONE_PORTS = ("Se", "Sf", "I", "C", "R")
SOURCES = ("Se", "Sf")
SIGNAL_KINDS = ("effort", "flow", "displacement", "momentum")


class DescriptionError(ValueError):
    """A description that is malformed (not a bond graph the reference can read)."""


# ============================================================ description
@dataclass(frozen=True)
class Element:
    """One element: ``kind`` in :data:`KINDS`; ``value`` the parameter of I, C
    (compliance), R, TF (modulus n), GY (modulus r); None otherwise."""

    name: str
    kind: str
    value: Optional[float] = None


@dataclass(frozen=True)
class Bond:
    """A bond from ``tail`` to ``head``; ``id`` is stable (outputs refer to it)
    while its *number* is its position in :attr:`Graph.bonds` (from 1)."""

    id: int
    tail: str
    head: str


@dataclass(frozen=True)
class Term:
    """``coef * kind(target)``: target an element name or a bond id (int)."""

    coef: int
    kind: str
    target: Union[str, int]


@dataclass(frozen=True)
class Output:
    name: str
    terms: tuple[Term, ...]


@dataclass(frozen=True)
class Graph:
    """A linear bond graph: elements, bonds (in order), named outputs."""

    name: str
    elements: tuple[Element, ...]
    bonds: tuple[Bond, ...]
    outputs: tuple[Output, ...]
    family: str = ""
    seed: int = -1
    meta: dict = field(default_factory=dict, compare=False, hash=False)

    def element(self, name: str) -> Element:
        for el in self.elements:
            if el.name == name:
                return el
        raise KeyError(name)

    def bonds_of(self, name: str) -> list[int]:
        """Indices (0-based positions) of the bonds attached to ``name``."""
        return [k for k, b in enumerate(self.bonds) if name in (b.tail, b.head)]

    def bond_index(self, bond_id: int) -> int:
        for k, b in enumerate(self.bonds):
            if b.id == bond_id:
                return k
        raise KeyError(bond_id)

    @property
    def sources(self) -> tuple[Element, ...]:
        return tuple(el for el in self.elements if el.kind in SOURCES)

    @property
    def size(self) -> tuple[int, int]:
        """(elements, bonds): the size used to rank reproducers."""
        return len(self.elements), len(self.bonds)


def exact(x: Union[float, int, Fraction]) -> Fraction:
    """A float read by its decimal representation (``0.3172`` -> 3172/10000)."""
    if isinstance(x, Fraction):
        return x
    if isinstance(x, int):
        return Fraction(x)
    return Fraction(repr(float(x)))


def _exact_complex(s) -> tuple[Fraction, Fraction]:
    s = complex(s)
    return exact(s.real), exact(s.imag)


# ============================================================ assembly
def check_graph(g: Graph) -> None:
    """Structural validity (the reference's own, independent of bondgraph)."""
    names = [el.name for el in g.elements]
    if len(set(names)) != len(names):
        raise DescriptionError(f"{g.name}: duplicate element names")
    kinds = {el.name: el.kind for el in g.elements}
    for el in g.elements:
        if el.kind not in KINDS:
            raise DescriptionError(f"{el.name}: unknown kind {el.kind}")
        if (el.value is None) != (el.kind not in PARAM_KINDS):
            raise DescriptionError(f"{el.name}: value given/missing for {el.kind}")
    ids = [b.id for b in g.bonds]
    if len(set(ids)) != len(ids):
        raise DescriptionError(f"{g.name}: duplicate bond ids")
    for b in g.bonds:
        if b.tail not in kinds or b.head not in kinds or b.tail == b.head:
            raise DescriptionError(f"{g.name}: bad bond {b}")
    for el in g.elements:
        ks = g.bonds_of(el.name)
        n = len(ks)
        if el.kind in ONE_PORTS and n != 1:
            raise DescriptionError(f"{el.name}: {el.kind} needs 1 bond, has {n}")
        if el.kind in ("TF", "GY"):
            heads = sum(g.bonds[k].head == el.name for k in ks)
            if n != 2 or heads != 1:
                raise DescriptionError(f"{el.name}: {el.kind} needs one bond in and one out")
        if el.kind in ("Zero", "One") and n < 2:
            raise DescriptionError(f"{el.name}: junction needs 2 bonds, has {n}")
    for out in g.outputs:
        for t in out.terms:
            if t.kind not in SIGNAL_KINDS:
                raise DescriptionError(f"{out.name}: bad signal kind {t.kind}")
            if isinstance(t.target, int):
                g.bond_index(t.target)
                continue
            k = kinds.get(t.target)
            flowish = t.kind in ("flow", "displacement")
            ok = (k in ONE_PORTS) or (k == "Zero" and not flowish) or (k == "One" and flowish)
            if not ok:
                raise DescriptionError(f"{out.name}: {t.kind} of {k} {t.target} is not a signal")


class Reference:
    """The bond graph's equations ``(M0 + s*M1) x = B u`` over bond variables.

    Unknown ``2k`` is the effort of bond position ``k``, ``2k+1`` its flow.
    Outputs are ``y = (C0 + C1/s) x``.
    """

    def __init__(self, g: Graph, *, seed: int = 0) -> None:
        check_graph(g)
        self.graph = g
        nb = len(g.bonds)
        self.n = 2 * nb
        self.inputs = [el for el in g.elements if el.kind in SOURCES]
        self.input_names = tuple(el.name for el in self.inputs)
        self.output_names = tuple(o.name for o in g.outputs)
        # sparse rows: list of dicts {col: Fraction} for M0 and M1, B as {input: Fraction}
        self.M0: list[dict[int, Fraction]] = []
        self.M1: list[dict[int, Fraction]] = []
        self.B: list[dict[int, Fraction]] = []
        self._assemble()
        if len(self.M0) != self.n:  # pragma: no cover - guaranteed by check_graph
            raise DescriptionError(f"{len(self.M0)} equations for {self.n} unknowns")
        self.C0, self.C1 = self._outputs()
        rng = random.Random(seed)
        self.well_posed = any(self._rank_at(self._random_s(rng)) == self.n for _ in range(2))

    # -------------------------------------------------------------- equations
    def _sigma(self, name: str, k: int) -> int:
        return 1 if self.graph.bonds[k].head == name else -1

    def _row(self, m0=None, m1=None, b=None) -> None:
        self.M0.append({c: Fraction(v) for c, v in (m0 or {}).items() if v != 0})
        self.M1.append({c: Fraction(v) for c, v in (m1 or {}).items() if v != 0})
        self.B.append({c: Fraction(v) for c, v in (b or {}).items() if v != 0})

    def _assemble(self) -> None:
        g = self.graph
        src_index = {el.name: j for j, el in enumerate(self.inputs)}
        for el in g.elements:
            ks = g.bonds_of(el.name)
            kind = el.kind
            if kind in ("Zero", "One"):
                same = 0 if kind == "Zero" else 1        # shared variable: effort / flow
                summed = 1 - same
                for k in ks[1:]:
                    self._row({2 * ks[0] + same: 1, 2 * k + same: -1})
                self._row({2 * k + summed: self._sigma(el.name, k) for k in ks})
                continue
            if kind in ("TF", "GY"):
                a = ks[0] if g.bonds[ks[0]].head == el.name else ks[1]   # port 1: into
                b = ks[1] if a == ks[0] else ks[0]                        # port 2: out
                m = exact(el.value)
                if kind == "TF":
                    self._row({2 * a: 1, 2 * b: -m})                 # e1 = n e2
                    self._row({2 * b + 1: 1, 2 * a + 1: -m})         # f2 = n f1
                else:
                    self._row({2 * a: 1, 2 * b + 1: -m})             # e1 = r f2
                    self._row({2 * b: 1, 2 * a + 1: -m})             # e2 = r f1
                continue
            (k,) = ks
            sg = self._sigma(el.name, k)
            e, f = 2 * k, 2 * k + 1
            if kind == "Se":
                self._row({e: 1}, b={src_index[el.name]: 1})
            elif kind == "Sf":
                self._row({f: -sg}, b={src_index[el.name]: 1})
            elif kind == "I":
                self._row({e: 1}, {f: -exact(el.value) * sg})       # e = s I f_in
            elif kind == "C":
                self._row({f: sg}, {e: -exact(el.value)})           # f_in = s C e
            elif kind == "R":
                self._row({e: 1, f: -exact(el.value) * sg})         # e = R f_in
            else:  # pragma: no cover
                raise DescriptionError(kind)

    def _signal(self, kind: str, target) -> tuple[int, int, bool]:
        """(unknown, sign, integrated) of one signal."""
        g = self.graph
        flowish = kind in ("flow", "displacement")
        integ = kind in ("displacement", "momentum")
        if isinstance(target, int):
            k = g.bond_index(target)
            return 2 * k + int(flowish), 1, integ
        el = g.element(target)
        k = g.bonds_of(target)[0]
        sign = self._sigma(target, k) if (flowish and el.kind in ONE_PORTS) else 1
        return 2 * k + int(flowish), sign, integ

    def _outputs(self):
        C0, C1 = [], []
        for out in self.graph.outputs:
            r0: dict[int, Fraction] = {}
            r1: dict[int, Fraction] = {}
            for t in out.terms:
                v, sign, integ = self._signal(t.kind, t.target)
                r = r1 if integ else r0
                r[v] = r.get(v, Fraction(0)) + Fraction(t.coef) * sign
            C0.append(r0)
            C1.append(r1)
        return C0, C1

    # -------------------------------------------------------------- numbers
    @staticmethod
    def _random_s(rng: random.Random) -> tuple[Fraction, Fraction]:
        return Fraction(rng.randint(1, 10**6), 10**5), Fraction(rng.randint(1, 10**6), 10**5)

    def _real_system(self, sr: Fraction, si: Fraction) -> flint.fmpq_mat:
        """[[Re M, -Im M], [Im M, Re M]] of M(s) = M0 + s M1."""
        n = self.n
        K = flint.fmpq_mat(2 * n, 2 * n)
        for i in range(n):
            for c, v in self.M0[i].items():
                q = flint.fmpq(v.numerator, v.denominator)
                K[i, c] += q
                K[n + i, n + c] += q
            for c, v in self.M1[i].items():
                re, im = v * sr, v * si
                qr = flint.fmpq(re.numerator, re.denominator)
                qi = flint.fmpq(im.numerator, im.denominator)
                K[i, c] += qr
                K[n + i, n + c] += qr
                K[i, n + c] -= qi
                K[n + i, c] += qi
        return K

    def _rank_at(self, s: tuple[Fraction, Fraction]) -> int:
        return self._real_system(*s).rank() // 2

    def pencil(self) -> tuple[np.ndarray, np.ndarray]:
        """Dense float M0, M1 (for pole locations)."""
        M0 = np.zeros((self.n, self.n))
        M1 = np.zeros((self.n, self.n))
        for i in range(self.n):
            for c, v in self.M0[i].items():
                M0[i, c] = float(v)
            for c, v in self.M1[i].items():
                M1[i, c] = float(v)
        return M0, M1

    def poles(self) -> np.ndarray:
        """Finite generalized eigenvalues of ``M0 + s*M1`` (a superset of the poles)."""
        import scipy.linalg

        M0, M1 = self.pencil()
        if self.n == 0:
            return np.array([])
        w = scipy.linalg.eigvals(M0, -M1)
        return w[np.isfinite(w)]

    def evaluate_exact(self, s) -> list[list[tuple[Fraction, Fraction]]]:
        """G(s) exactly: rows outputs, columns inputs, entries (re, im) Fractions.

        Raises
        ------
        ZeroDivisionError
            If ``M(s)`` is singular at this ``s`` (ill-posed graph or a pole).
        """
        sr, si = _exact_complex(s)
        n = self.n
        m = len(self.inputs)
        K = self._real_system(sr, si)
        if K.rank() < 2 * n:
            raise ZeroDivisionError(f"{self.graph.name}: the bond equations are singular at s={s}")
        rhs = flint.fmpq_mat(2 * n, max(m, 1))
        for i in range(n):
            for j, v in self.B[i].items():
                rhs[i, j] = flint.fmpq(v.numerator, v.denominator)
        X = K.solve(rhs)

        def fr(q) -> Fraction:
            return Fraction(int(q.p), int(q.q))

        xs = [[(fr(X[r, j]), fr(X[n + r, j])) for r in range(n)] for j in range(m)]
        # 1/s = conj(s)/|s|^2
        d = sr * sr + si * si
        inv = (sr / d, -si / d)
        out = []
        for r0, r1 in zip(self.C0, self.C1):
            row = []
            for j in range(m):
                x = xs[j]
                a = (sum((c * x[v][0] for v, c in r0.items()), Fraction(0)),
                     sum((c * x[v][1] for v, c in r0.items()), Fraction(0)))
                b = (sum((c * x[v][0] for v, c in r1.items()), Fraction(0)),
                     sum((c * x[v][1] for v, c in r1.items()), Fraction(0)))
                bi = (b[0] * inv[0] - b[1] * inv[1], b[0] * inv[1] + b[1] * inv[0])
                row.append((a[0] + bi[0], a[1] + bi[1]))
            out.append(row)
        return out

    def evaluate(self, s) -> np.ndarray:
        """G(s) as a complex array (outputs x inputs), from the exact solution."""
        ex = self.evaluate_exact(s)
        return np.array([[complex(float(re), float(im)) for re, im in row] for row in ex],
                        dtype=complex).reshape(len(self.output_names), len(self.inputs))

    def pick_s(self, rng: random.Random, count: int, *, clearance: float = 0.05,
               axis: bool = False) -> list[complex]:
        """``count`` random ``s = 10**U(-1,1) * exp(i*U(0.2, 2.9))`` with four
        significant digits, each at least ``clearance*|s|`` from every pole;
        with ``axis``, one more on the imaginary axis, ``s = i*10**U(-1,1)``."""
        poles = self.poles()
        picked: list[complex] = []
        want = count + int(axis)
        for _ in range(200 * want):
            if len(picked) == want:
                break
            mag = 10 ** rng.uniform(-1, 1)
            ang = math.pi / 2 if (axis and len(picked) == count) else rng.uniform(0.2, 2.9)
            z = mag * complex(math.cos(ang), math.sin(ang))
            z = complex(float(f"{z.real:.4g}"), float(f"{z.imag:.4g}"))
            if ang == math.pi / 2:
                z = complex(0.0, z.imag)
            if poles.size and np.min(np.abs(poles - z)) < clearance * abs(z):
                continue
            picked.append(z)
        while len(picked) < want:  # pragma: no cover - dense poles everywhere
            picked.append(complex(0.3, 1.7 + len(picked)))
        return picked


def solve(g: Graph, s: complex) -> np.ndarray:
    """Shorthand: ``Reference(g).evaluate(s)``."""
    return Reference(g).evaluate(s)


def to_array(rows: Sequence[Sequence[tuple[Fraction, Fraction]]]) -> np.ndarray:
    return np.array([[complex(float(a), float(b)) for a, b in row] for row in rows], dtype=complex)
