"""The element protocol (issue 13, item 1): elements carry their own behaviour.

Two user-defined elements go through the whole pipeline (port rules, SCAP,
derivation, drawing) without any change to causality or derivation, and
their equations are checked against hand derivations (Newton, Kirchhoff)
written here:

* ``MRDamper`` -- a magnetorheological damper, a modulated resistance
  ``e = (c0 + c1*i)*f`` whose coefficient depends on a signal of the model
  (the current of its coil), in both causalities and in an algebraic loop;
* ``Differential`` -- an open differential, a three-port element with a
  junction-like causal rule (exactly one port receives torque), whose side
  shafts force one wheel inertia into derivative causality.

A two-port inertia field in mixed causality (a sketch of issue 13 item 2)
shows that a multiport needs no change to causality or derivation either.
The last tests check that the modules that run the pipeline no longer test
element kinds, and what the built-in elements answer.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, Optional, Sequence

import pytest
import sympy

import bondgraph as bg
from bondgraph.elements.protocol import (ARBITRARY, DERIVATIVE, INTEGRAL, RESISTIVE, STORAGE, CausalPorts,
                                Choice, Decision, LocalVariables, prefix_signals, rename)

PACKAGE = Path(bg.__file__).resolve().parent


# ------------------------------------------------------------------ user-defined elements
@dataclass(frozen=True, eq=False)
class MRDamper(bg.Element):
    """Magnetorheological damper: ``e = (c0 + c1*i)*f``, ``i`` a signal (coil current)."""

    c0: sympy.Expr = sympy.Symbol("c0", positive=True)
    c1: sympy.Expr = sympy.Symbol("c1", positive=True)
    current: Optional[sympy.Expr] = None
    kind: ClassVar[str] = "MR"
    drawing_role: ClassVar[str] = "dissipative"

    def resolved(self, path: str) -> bg.Element:      # inside a sub-model: prefix the signal
        el = rename(self, path)
        object.__setattr__(el, "current",
                           prefix_signals(self.current, path[: len(path) - len(self.name)]))
        return el

    def signals(self) -> frozenset:
        return frozenset({self.current})

    def causal_choices(self, prefer_derivative: bool) -> Sequence[Choice]:
        return (Choice(0, False, f"arbitrary choice for {self.label()}", RESISTIVE),)

    def causal_class(self, effort_in, free) -> Optional[str]:
        return ARBITRARY if free[0] else None

    def output_dependencies(self, effort_in, causality):
        return ((0,),)

    def signal_port(self, variable: str):
        return 0, variable == "flow"

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        c = local.resolve(self.c0 + self.c1 * self.current)
        x, s = local.input(0), local.sign(0)
        return s * x / c if local.effort_in(0) else c * s * x    # f = e/c, or e = c*f


@dataclass(frozen=True, eq=False)
class Differential(bg.Element):
    """Open differential: port 1 the carrier (bond in), ports 2 and 3 the side shafts.

    ``w_c = (w_1 + w_2)/2`` and ``t_1 = t_2 = t_c/2``: each port's effort is
    ``weight*common`` and the weighted flows into it sum to zero, so exactly
    one port receives effort (like a 0-junction with weights 2, 1, 1).
    """

    kind: ClassVar[str] = "DIFF"
    bonds: ClassVar = (3, 3)
    weights: ClassVar = (2, 1, 1)

    def propagate(self, ports: CausalPorts) -> Sequence[Decision]:
        got = [p for p in range(ports.count) if ports.effort_in(p) is True]
        open_ = [p for p in range(ports.count) if ports.effort_in(p) is None]
        if len(got) > 1 or (not got and not open_):
            raise bg.CausalityConflictError(
                f"causality conflict at {self.label()}: bonds "
                f"{', '.join(str(ports.number(p)) for p in got)} bring torque in "
                "(exactly one must)")
        if got:
            return [Decision(p, False, self.label()) for p in open_]
        if len(open_) == 1:
            return [Decision(open_[0], True, self.label())]
        return []

    def _strong(self, effort_in) -> int:
        return next(p for p, e in enumerate(effort_in) if e)

    def output_dependencies(self, effort_in, causality):
        s = self._strong(effort_in)
        return tuple(tuple(q for q in range(3) if q != s) if p == s else (s,) for p in range(3))

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        w = self.weights
        s = self._strong([local.effort_in(p) for p in range(3)])
        if port != s:
            return sympy.Integer(w[port]) * local.input(s) / w[s]
        flows = sum(w[p] * local.sign(p) * local.input(p) for p in range(3) if p != s)
        return -local.sign(s) * flows / w[s]


def symbols(names: str):
    return sympy.symbols(names, positive=True)


def graph(name: str, elements, bonds, *, coil: bool = True) -> bg.BondGraph:
    """A graph of these elements and bonds, plus the damper's coil V -> 1 [Rc, Lc]
    (its current is flow('Lc'))."""
    g = bg.BondGraph(name)
    g.add(*elements)
    if coil:
        g.add(bg.Se("V"), bg.One("i"), bg.R("Rc"), bg.I("Lc"))
        bonds = [*bonds, ("V", "i"), ("i", "Rc"), ("i", "Lc")]
    for t, h in bonds:
        g.connect(t, h)
    return g


def zero(expr) -> bool:
    return sympy.simplify(expr) == 0


# ------------------------------------------------------------------ MR damper
def test_mr_damper_on_a_mass_matches_newton():
    g = graph("quarter_car", [bg.Se("F"), bg.One("v"), bg.I("m"),
                              MRDamper("d", current=bg.flow("Lc"))],
              [("F", "v"), ("v", "m"), ("v", "d")])
    model = bg.derive(g, outputs={"force": bg.effort("d")})
    m, c0, c1, Rc, Lc = symbols("m c0 c1 Rc Lc")
    F, V, p_m, p_Lc = sympy.symbols("F V p_m p_Lc", real=True)
    assert model.state_names == ("p_m", "p_Lc")
    # Newton: m dv/dt = F - (c0 + c1 i) v;  Kirchhoff: Lc di/dt = V - Rc i
    v, i = p_m / m, p_Lc / Lc
    assert zero(model.rhs[0] - (F - (c0 + c1 * i) * v))
    assert zero(model.rhs[1] - (V - Rc * i))
    assert zero(model.output_exprs[0] - (c0 + c1 * i) * v)
    assert model.augmented.bond(3).stroke == "v"      # the damper receives the flow


def test_mr_valve_receiving_effort_matches_kirchhoff():
    # a flow source fills an accumulator drained by the MR valve: the valve sees the
    # accumulator's pressure (effort in) and passes the flow e/(c0 + c1 i)
    g = graph("accumulator", [bg.Sf("Q"), bg.Zero("node"), bg.C("Ca"),
                              MRDamper("valve", current=bg.flow("Lc"))],
              [("Q", "node"), ("node", "Ca"), ("node", "valve")])
    model = bg.derive(g, outputs={"drain": bg.flow("valve")})
    Ca, c0, c1, Lc = symbols("Ca c0 c1 Lc")
    Q, q, p_Lc = sympy.symbols("Q q_Ca p_Lc", real=True)
    pressure, i = q / Ca, p_Lc / Lc
    assert zero(model.rhs[0] - (Q - pressure / (c0 + c1 * i)))
    assert zero(model.output_exprs[0] - pressure / (c0 + c1 * i))
    assert model.augmented.bond(3).stroke == "valve"   # the valve receives the effort


def test_mr_damper_in_an_algebraic_loop_is_arbitrary_and_solved():
    # a resistive divider with no storage: V -> 1 [R1] -> 0 [R2, MR]; the current
    # drawn from the source by Kirchhoff is V / (R1 + R2 c / (R2 + c))
    g = graph("divider", [bg.Se("U"), bg.One("s"), bg.R("R1"), bg.Zero("n"), bg.R("R2"),
                          MRDamper("mr", current=bg.flow("Lc"))],
              [("U", "s"), ("s", "R1"), ("s", "n"), ("n", "R2"), ("n", "mr")])
    model = bg.derive(g, outputs={"i": bg.flow("U"), "i_mr": bg.flow("mr")})
    aug = model.augmented
    assert aug.arbitrary and aug.loops
    R1, R2, c0, c1, Lc = symbols("R1 R2 c0 c1 Lc")
    U, p_Lc = sympy.symbols("U p_Lc", real=True)
    c = c0 + c1 * p_Lc / Lc
    i = U / (R1 + R2 * c / (R2 + c))
    assert zero(model.output_exprs[0] + i)        # flow of the source's bond points out of it
    assert zero(model.output_exprs[1] - i * R2 / (R2 + c))


def test_mr_damper_port_rules_drawing_and_sub_models():
    g = graph("g", [bg.Se("F"), bg.One("v"), bg.I("m"), MRDamper("d", current=bg.flow("m"))],
              [("F", "v"), ("v", "m"), ("v", "d")], coil=False)
    crowded = g.copy()
    crowded.add(bg.Zero("z"))
    with pytest.raises(bg.ModelStructureError, match=r"element MR:d takes 1 bond and already "
                                                     r"has bond 3"):
        crowded.connect("z", "d")
    g2 = bg.BondGraph("lonely")
    g2.add(MRDamper("d", current=bg.flow("d")))
    with pytest.raises(bg.ModelStructureError, match="element MR:d has 0 bonds; expected 1"):
        bg.flatten(g2)
    svg = bg.draw(g, causality=True)
    assert ">MR:d<" in svg and 'data-kind="MR"' in svg
    # inside a sub-model the signal is renamed with the element
    inner = graph("susp", [bg.One("v"), bg.I("m"), MRDamper("d", current=bg.flow("m")),
                           bg.Port("hub")], [("hub", "v"), ("v", "m"), ("v", "d")], coil=False)
    top = bg.BondGraph("top")
    top.add(bg.Se("F"), inner)
    top.connect("F", "susp.hub")
    flat = bg.flatten(top)
    assert flat.element("susp.d").current == bg.flow("susp.m")
    m, c0, c1 = sympy.Symbol("susp.m", positive=True), *symbols("c0 c1")
    p = sympy.Symbol("p_susp.m", real=True)
    assert zero(bg.derive(top).rhs[0] - (sympy.Symbol("F", real=True) - (c0 + c1 * p / m) * p / m))


# ------------------------------------------------------------------ differential
def rear_axle() -> bg.BondGraph:
    return graph("axle", [bg.Se("T"), bg.One("wc"), bg.I("Jc"), Differential("diff"), bg.One("w1"),
                          bg.I("J1"), bg.R("b1"), bg.One("w2"), bg.I("J2"), bg.R("b2")],
                 [("T", "wc"), ("wc", "Jc"), ("wc", "diff"), ("diff", "w1"), ("w1", "J1"),
                  ("w1", "b1"), ("diff", "w2"), ("w2", "J2"), ("w2", "b2")], coil=False)


def test_differential_matches_newton_with_a_dependent_wheel():
    model = bg.derive(rear_axle(), outputs={"w2": bg.flow("J2"), "tc": bg.effort(3)})
    aug = model.augmented
    # SCAP: the carrier inertia and the first wheel integral, the second wheel dependent
    assert aug.integral == ("Jc", "J1") and aug.derivative == ("J2",)
    assert model.state_names == ("p_Jc", "p_J1")
    Jc, J1, J2, b1, b2 = symbols("Jc J1 J2 b1 b2")
    T, p_Jc, p_J1 = sympy.symbols("T p_Jc p_J1", real=True)
    wc, w1 = p_Jc / Jc, p_J1 / J1
    # Newton on each body, with the differential's kinematics and torque split:
    #   Jc wc' = T - tc,  J1 w1' = tc/2 - b1 w1,  J2 w2' = tc/2 - b2 w2,  2 wc = w1 + w2
    dwc, dw1, dw2, tc = sympy.symbols("dwc dw1 dw2 tc")
    w2 = 2 * wc - w1
    sol = sympy.solve([Jc * dwc - (T - tc), J1 * dw1 - (tc / 2 - b1 * w1),
                       J2 * dw2 - (tc / 2 - b2 * w2), 2 * dwc - dw1 - dw2],
                      [dwc, dw1, dw2, tc], dict=True)[0]
    assert zero(model.rhs[0] / Jc - sol[dwc])
    assert zero(model.rhs[1] / J1 - sol[dw1])
    assert zero(model.output_exprs[0] - w2)
    assert zero(model.output_exprs[1] - sol[tc])
    # the descriptor form holds the effective inertia of the dependent wheel
    assert model.descriptor is not None


def test_differential_port_rules_conflict_and_drawing():
    g = rear_axle()
    g.add(bg.One("extra"))
    with pytest.raises(bg.ModelStructureError, match="DIFF:diff takes 3 bonds"):
        g.connect("diff", "extra")
    # two torque sources on the side shafts and one on the carrier: no assignment exists
    h = graph("overdriven", [bg.Se("T"), Differential("diff"), bg.Se("L1"), bg.Se("L2")],
              [("T", "diff"), ("diff", "L1"), ("diff", "L2")], coil=False)
    with pytest.raises(bg.CausalityConflictError, match="bond 3 .* already decided by DIFF:diff"):
        bg.assign_causality(h)
    svg = bg.draw(rear_axle())
    assert ">DIFF:diff<" in svg


# ------------------------------------------------------------------ a field in mixed causality
@dataclass(frozen=True, eq=False)
class InertiaField(bg.Element):
    """A two-port I-field, ``p = M f`` (bonds into it), integral causality preferred per port.

    A sketch of issue 13 item 2 through the protocol as it stands: in mixed
    causality the integral port's flow reads the derivative port's flow.
    """

    mass: sympy.ImmutableMatrix = sympy.ImmutableMatrix(
        2, 2, sympy.symbols("m1 m12 m12 m2", positive=True))
    kind: ClassVar[str] = "IF"
    bonds: ClassVar = (2, 2)

    def causal_choices(self, prefer_derivative):
        return tuple(Choice(p, True, f"integral causality of {self.label()} port {p + 1}", STORAGE)
                     for p in range(2))

    def causal_class(self, effort_in, free):
        return INTEGRAL if all(effort_in) else DERIVATIVE

    def output_dependencies(self, effort_in, causality):
        dep = tuple(p for p in range(2) if not effort_in[p])
        return tuple(dep for _ in range(2))

    def state_names(self, effort_in):
        return tuple(f"p_{self.name}_{p + 1}" for p in range(2) if effort_in[p])

    def derivative_ports(self, effort_in):
        return tuple(p for p in range(2) if not effort_in[p])

    def stored_names(self, effort_in):
        return tuple(f"p_{self.name}_{p + 1}" for p in self.derivative_ports(effort_in))

    def _flows(self, local):
        """Flows into every port: the derivative ports' inputs, the others from p = M f."""
        a = [p for p in range(2) if local.effort_in(p)]
        b = [p for p in range(2) if not local.effort_in(p)]
        fb = sympy.Matrix([local.sign(p) * local.input(p) for p in b])
        M = self.mass
        fa = M.extract(a, a).inv() * (sympy.Matrix(local.states) - M.extract(a, b) * fb)
        f = [None, None]
        for i, p in enumerate(a):
            f[p] = fa[i]
        for i, p in enumerate(b):
            f[p] = fb[i]
        return f

    def output(self, local, port):       # the flow of an integral port
        return local.sign(port) * self._flows(local)[port]

    def state_derivatives(self, local):  # dp/dt = e on each integral port
        return tuple(local.input(p) for p in range(2) if local.effort_in(p))

    def stored(self, local):             # p_b = (M f)_b on each derivative port
        f = sympy.Matrix(self._flows(local))
        return tuple((self.mass * f)[p] for p in self.derivative_ports(
            [local.effort_in(q) for q in range(2)]))

    def derivative_output(self, local, port, rates):
        return rates[self.derivative_ports([local.effort_in(q) for q in range(2)]).index(port)]


def test_inertia_field_in_mixed_causality_matches_lagrange():
    g = graph("body", [bg.Se("F"), bg.Sf("V"), InertiaField("body")],
              [("F", "body"), ("V", "body")], coil=False)
    model = bg.derive(g, outputs={"v1": bg.flow(1), "e2": bg.effort(2)})
    assert model.augmented.derivative == ("body",) and model.state_names == ("p_body_1",)
    m1, m12, m2 = symbols("m1 m12 m2")
    F, V, p1, dV = sympy.symbols("F V p_body_1 dV/dt", real=True)
    # Lagrange with p = M v: F = d/dt(m1 v1 + m12 V), e2 = d/dt(m12 v1 + m2 V)
    dv1 = (F - m12 * dV) / m1
    assert model.rhs == (F,)
    assert zero(model.output_exprs[0] - (p1 - m12 * V) / m1)
    assert zero(model.output_exprs[1] - (m12 * dv1 + m2 * dV))


# ------------------------------------------------------------------ the pipeline asks
PIPELINE = ["causality.py", "graph.py", "flatten.py"] + [
    f"{d}/{p.name}" for d in ("equations", "linear", "drawing") for p in (PACKAGE / d).glob("*.py")]


@pytest.mark.parametrize("path", PIPELINE)
def test_pipeline_modules_do_not_test_element_kinds(path):
    tree = ast.parse((PACKAGE / path).read_text())
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Compare):
            for operand in [node.left, *node.comparators]:
                if (isinstance(operand, ast.Attribute) and operand.attr == "kind") or \
                        (isinstance(operand, ast.Name) and operand.id == "kind"):
                    found.append(f"line {node.lineno}")
        if isinstance(node, (ast.Name, ast.Constant)) and getattr(node, "value", None) in (
                "Se", "Sf", "TF", "GY", "MTF", "MGY"):
            found.append(f"line {node.lineno}: {node.value!r}")
    assert not found, f"{path} tests element kinds: {found}"


def test_builtin_elements_answer_the_protocol():
    # states by causality: an I integral when it receives effort, a C when it receives flow
    assert bg.I("m").state_names([True]) == ("p_m",) and bg.C("k").state_names([False]) == ("q_k",)
    assert bg.I("m").state_names([False]) == () and bg.I("m").derivative_ports([False]) == (0,)
    assert bg.C("k").stored_names([True]) == ("q_k",) and bg.C("k").derivative_ports([False]) == ()
    assert bg.I("m").energy_variable("momentum") == 0
    assert bg.I("m").energy_variable("displacement") is None
    assert bg.Se("V").input_name() == "V" and bg.Sf("g", value=3).input_name() is None
    assert bg.R("b").state_names([True]) == () and bg.R("b").input_name() is None
    assert bg.Zero("n").signal_port("effort") == (0, False)
    assert bg.Zero("n").signal_port("flow") is None
    assert bg.One("w").signal_port("flow") == (0, False)
    assert bg.R("b").signal_port("flow") == (0, True) and bg.TF("n").signal_port("effort") is None
    assert [el.drawing_label() for el in (bg.One("w"), bg.TF("n"), bg.Se("V", value=bg.t))] == \
        [("1", "w"), ("TF:n", ""), ("MSe:V", "")]
    assert [bg.elements.drawing_role(k) for k in ("Se", "I", "R", "0", "GY", "Port", "MR")] == \
        ["source", "storage", "dissipative", "junction", "backbone", "source", "dissipative"]
    # choice points: storage integral first (derivative when asked), R arbitrary
    (c,) = bg.I("m").causal_choices(False)
    assert (c.effort_in, c.priority, c.reason) == (True, 0, "integral causality of I:m")
    (c,) = bg.C("k").causal_choices(True)
    assert (c.effort_in, c.reason) == (True, "derivative causality of C:k")
    (c,) = bg.R("b").causal_choices(False)
    assert (c.effort_in, c.priority) == (False, RESISTIVE)
    assert bg.Sf("Q").forced_causality(None) == (Decision(0, True, "source Sf:Q"),)
    assert bg.C("k").causal_class((True,), (False,)) == "derivative"
    assert list(bg.One("w").output_dependencies((True, False, True), None)) == [(1,), (0, 2), (1,)]


def test_an_element_without_constitutive_relation_says_so():
    @dataclass(frozen=True, eq=False)
    class Bare(bg.Element):
        kind: ClassVar[str] = "BARE"

    g = graph("bare", [bg.Se("V"), Bare("x")], [("V", "x")], coil=False)
    with pytest.raises(NotImplementedError, match="BARE:x: Bare does not define output_dep"):
        bg.derive(g)
