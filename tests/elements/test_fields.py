"""Multiport fields (issue 13, item 2): ``bg.IField``, ``bg.CField``, ``bg.ICField``, ``bg.RField``.

Every expectation is derived by hand in the test (Newton, Lagrange,
Kirchhoff, a change of coordinates, a finite-element assembly written here,
numpy's eigenvalues of the hand matrices), never by running the engine twice.
"""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.hamiltonian import port_hamiltonian


def pos(names: str):
    return sympy.symbols(names, positive=True)


def real(names: str):
    return sympy.symbols(names, real=True)


def zero(expr) -> bool:
    return sympy.simplify(sympy.cancel(sympy.together(expr))) == 0


def build(name, elements, bonds) -> bg.BondGraph:
    g = bg.BondGraph(name)
    g.add(*elements)
    for t, h in bonds:
        g.connect(t, h)
    return g


def transfer(model, values=None):
    """``C (sI - A)^-1 B + D`` by hand from the symbolic state space."""
    s = sympy.Symbol("s")
    ss = model.state_space()
    A, B, C, D = ss.A, ss.B, ss.C, ss.D
    if values:
        A, B, C, D = (M.xreplace(values) for M in (A, B, C, D))
    return C * (s * sympy.eye(A.rows) - A).LUsolve(B) + D


# ------------------------------------------------------------------ IField vs one-port I + TF
def test_full_mass_matrix_matches_one_port_inertias_through_a_change_of_coordinates():
    # Two bodies a, b; generalised coordinates q1 = x_a and q2 with x_b = x_a + n q2.
    # T = ma va^2/2 + mb (v1 + n v2)^2/2, so M = [[ma + mb, n mb], [n mb, n^2 mb]].
    # F pushes body a (generalised force on q1), a damper b0 holds body a, a spring k acts on q2.
    ma, mb, n, k, b0 = pos("ma mb n k b0")
    M = [[ma + mb, n * mb], [n * mb, n**2 * mb]]
    field = build("field", [bg.Se("F"), bg.One("v1"), bg.One("v2"), bg.IField("M", M),
                            bg.R("b0"), bg.C("k", stiffness=k)],
                  [("F", "v1"), ("v1", "M"), ("v2", "M"), ("v1", "b0"), ("v2", "k")])
    # the same bodies as one-port inertias: v_b = v1 + n v2 is a 0-junction summing v1 and
    # the TF's n*v2 (TF: f2 = n f1, port 1 on the q2 junction), its sum flowing to body b
    bodies = build("bodies", [bg.Se("F"), bg.One("v1"), bg.One("v2"), bg.One("vb"),
                              bg.Zero("sum"), bg.I("ma"), bg.I("mb"), bg.TF("n", n), bg.R("b0"),
                              bg.C("k", stiffness=k)],
                   [("F", "v1"), ("v1", "ma"), ("v1", "b0"), ("v1", "sum"), ("v2", "n"),
                    ("n", "sum"), ("sum", "vb"), ("vb", "mb"), ("v2", "k")])
    outs = {"x1": bg.flow("v1"), "spring": bg.effort("k")}
    a, b = bg.derive(field, outputs=outs), bg.derive(bodies, outputs=outs)
    assert a.state_names == ("p_M_1", "p_M_2", "q_k")
    Ga, Gb = transfer(a), transfer(b)
    assert Ga.shape == (2, 1) and all(zero(x - y) for x, y in zip(Ga, Gb))
    # and Lagrange by hand: M q'' = (F - b0 v1, -k q2), first output v1
    s = sympy.Symbol("s")
    Ms = sympy.Matrix(M)
    Z = Ms * s**2 + sympy.Matrix([[b0 * s, 0], [0, k]])
    q = Z.LUsolve(sympy.Matrix([1, 0]))
    assert zero(Ga[0] - s * q[0]) and zero(Ga[1] - k * q[1])


# ------------------------------------------------------------------ CField: finite-element bar
def test_finite_element_bar_as_a_stiffness_field_fixed_at_one_end():
    # 3 two-node bar elements of stiffness ke = EA/h; node 0 clamped; nodes 1..3 free.
    # Assembly by hand: each element adds ke [[1, -1], [-1, 1]] on its two nodes.
    ke, m = 4.0e3, 0.5
    K = np.zeros((4, 4))
    for e in range(3):
        K[e:e + 2, e:e + 2] += ke * np.array([[1.0, -1.0], [-1.0, 1.0]])
    K = K[1:, 1:]                              # node 0 fixed
    masses = [m, m, m / 2]                     # lumped: half of each element at its nodes
    g = build("bar", [bg.CField("K", stiffness=K.tolist())]
              + [bg.One(f"n{i}") for i in (1, 2, 3)]
              + [bg.I(f"m{i}", masses[i - 1]) for i in (1, 2, 3)],
              [(f"n{i}", f"m{i}") for i in (1, 2, 3)] + [(f"n{i}", "K") for i in (1, 2, 3)])
    model = bg.derive(g)
    A = np.array(model.state_space().A.tolist(), dtype=float)
    got = np.sort(np.abs(np.linalg.eigvals(A)))
    w2 = np.linalg.eigvals(np.linalg.solve(np.diag(masses), K))
    want = np.sort(np.repeat(np.sqrt(w2.real), 2))
    assert np.allclose(got, want, rtol=1e-9)
    assert np.allclose(np.linalg.eigvals(A).real, 0, atol=1e-9)


# ------------------------------------------------------------------ nonlinear CField
def test_nonlinear_coupled_potential_power_balance_on_random_states():
    q1, q2 = sympy.symbols("q1 q2")
    k1, k2, k3, ma, mb, b = pos("k1 k2 k3 ma mb b")
    V = k1 * q1**2 / 2 + k2 * q2**2 / 2 + k3 * q1**2 * q2**2
    g = build("duo", [bg.Se("F"), bg.One("v1"), bg.I("ma"), bg.One("v2"), bg.I("mb"), bg.R("b"),
                      bg.CField("V", energy=V, variables=(q1, q2))],
              [("F", "v1"), ("v1", "ma"), ("v1", "V"), ("v2", "V"), ("v2", "mb"), ("v2", "b")])
    model = bg.derive(g, outputs={"x1": bg.displacement("V", port=1)})
    F, pa, pb, x1, x2 = real("F p_ma p_mb q_V_1 q_V_2")
    assert set(model.states) == {pa, pb, x1, x2}
    # Newton with e = dV/dq: ma v1' = F - dV/dq1, mb v2' = -dV/dq2 - b v2
    e1, e2 = (sympy.diff(V, q).xreplace({q1: x1, q2: x2}) for q in (q1, q2))
    rhs = dict(zip(model.states, model.rhs))
    assert zero(rhs[pa] - (F - e1)) and zero(rhs[pb] - (-e2 - b * pb / mb))
    assert model.output_exprs[0] == x1
    # power balance by hand: H = pa^2/2ma + pb^2/2mb + V; dH/dt = F v1 - b v2^2
    H = pa**2 / (2 * ma) + pb**2 / (2 * mb) + V.xreplace({q1: x1, q2: x2})
    dH = sum(sympy.diff(H, x) * rhs[x] for x in model.states)
    supplied = F * pa / ma - b * (pb / mb) ** 2
    rng = random.Random(7)
    for _ in range(5):
        point = {s: rng.uniform(-2, 2) for s in (F, pa, pb, x1, x2)}
        point.update({s: rng.uniform(0.5, 3) for s in (k1, k2, k3, ma, mb, b)})
        assert float(dH.xreplace(point)) == pytest.approx(float(supplied.xreplace(point)),
                                                          rel=1e-10, abs=1e-10)
    assert zero(model.energy() - H)
    # the coupled potential still has a port-Hamiltonian form: J - R constant
    ph = port_hamiltonian(model)
    assert ph.Q is None and zero(ph.H - H)
    assert (ph.J + ph.J.T).is_zero_matrix


# ------------------------------------------------------------------ mixed causality
def test_inertia_field_with_one_port_driven_by_a_flow_source_matches_the_hand_reduction():
    # p = M f; port 1 pushed by F through a damper junction, port 2 driven at velocity V.
    m1, m2, m12, c = pos("m1 m2 m12 c")
    g = build("driven", [bg.Se("F"), bg.One("v"), bg.R("c"), bg.Sf("V"),
                         bg.IField("M", [[m1, m12], [m12, m2]])],
              [("F", "v"), ("v", "c"), ("v", "M"), ("V", "M")])
    model = bg.derive(g, outputs={"v1": bg.flow("M", port=1), "e2": bg.effort("M", port=2),
                                  "p2": bg.momentum("M", port=2)})
    assert model.state_names == ("p_M_1",) and model.augmented.derivative == ("M",)
    F, V, dV, p1 = real("F V dV/dt p_M_1")
    # hand reduction: f1 = (p1 - m12 V)/m1; p1' = F - c f1;
    # e2 = d/dt (m12 f1 + m2 V) = m12 (p1' - m12 V')/m1 + m2 V'
    f1 = (p1 - m12 * V) / m1
    dp1 = F - c * f1
    assert zero(model.rhs[0] - dp1)
    v1, e2, p2 = model.output_exprs
    assert zero(v1 - f1)
    assert zero(e2 - (m12 * (dp1 - m12 * dV) / m1 + m2 * dV))
    assert zero(p2 - (m12 * f1 + m2 * V))


def test_stiffness_field_with_one_port_held_at_a_given_force():
    # e = K q; port 1 carries a mass m (integral: q1 a state), port 2 is held by a force E
    # (the field receives the effort: derivative causality).  By hand: E = k12 q1 + k22 q2
    # gives q2 = (E - k12 q1)/k22, e1 = k11 q1 + k12 q2, and port 2 moves at dq2/dt.
    k11, k12, k22, m = pos("k11 k12 k22 m")
    g = build("held", [bg.One("v"), bg.I("m"), bg.Se("E"),
                       bg.CField("K", stiffness=[[k11, k12], [k12, k22]])],
              [("v", "m"), ("v", "K"), ("E", "K")])
    model = bg.derive(g, outputs={"f2": bg.flow("K", port=2), "q2": bg.displacement("K", port=2)})
    assert model.state_names == ("p_m", "q_K_1") and model.augmented.derivative == ("K",)
    E, dE, p, q1 = real("E dE/dt p_m q_K_1")
    q2 = (E - k12 * q1) / k22
    rhs = dict(zip(model.state_names, model.rhs))
    assert zero(rhs["p_m"] + k11 * q1 + k12 * q2)              # m v' = -e1
    assert zero(rhs["q_K_1"] - p / m)
    f2, x2 = model.output_exprs
    assert zero(x2 - q2)
    assert zero(f2 - (dE - k12 * p / m) / k22)                 # dq2/dt, into the field


def test_field_rigidly_joined_to_another_field_gives_the_summed_mass_matrix():
    # IF:A (p = M_A v on v1, v2) and a one-port IF:B (mass mb) on v2: B is in derivative
    # causality.  Lagrange: T = v^T M_A v/2 + mb v2^2/2, so (M_A + diag(0, mb)) v' = (F, 0).
    m1, m2, m12, mb = pos("m1 m2 m12 mb")
    MA = sympy.Matrix([[m1, m12], [m12, m2]])
    g = build("joined", [bg.Se("F"), bg.One("v1"), bg.One("v2"), bg.IField("A", MA),
                         bg.IField("B", [[mb]])],
              [("F", "v1"), ("v1", "A"), ("v2", "A"), ("v2", "B")])
    model = bg.derive(g)
    assert model.state_names == ("p_A_1", "p_A_2") and model.augmented.derivative == ("B",)
    F = sympy.Symbol("F", real=True)
    dv = MA.inv() * sympy.Matrix(model.rhs)          # v' = M_A^-1 p_A'
    want = (MA + sympy.diag(0, mb)).inv() * sympy.Matrix([F, 0])
    assert all(zero(a - b) for a, b in zip(dv, want))
    assert model.descriptor is not None


# ------------------------------------------------------------------ RField
def test_coupled_dampers_receiving_flows_match_newton():
    r11, r12, r22, ma, mb = pos("r11 r12 r22 ma mb")
    g = build("dampers", [bg.Se("F"), bg.One("v1"), bg.I("ma"), bg.One("v2"), bg.I("mb"),
                          bg.RField("D", [[r11, r12], [r12, r22]])],
              [("F", "v1"), ("v1", "ma"), ("v1", "D"), ("v2", "mb"), ("v2", "D")])
    model = bg.derive(g, outputs={"e1": bg.effort("D", port=1)})
    F, pa, pb = real("F p_ma p_mb")
    v1, v2 = pa / ma, pb / mb
    # Newton: e = R v on each body
    assert zero(model.rhs[0] - (F - r11 * v1 - r12 * v2))
    assert zero(model.rhs[1] - (-r12 * v1 - r22 * v2))
    assert zero(model.output_exprs[0] - (r11 * v1 + r12 * v2))
    ph = port_hamiltonian(model)
    assert sympy.simplify(ph.R - sympy.Matrix([[r11, r12], [r12, r22]]) *
                          sympy.eye(2)) == sympy.zeros(2, 2)


def test_coupled_resistors_receiving_efforts_and_mixed_match_kirchhoff():
    r11, r12, r22, C1 = pos("r11 r12 r22 C1")
    R = [[r11, r12], [r12, r22]]
    # two voltage sources: the field receives both efforts, f = R^-1 e
    g = build("both", [bg.Se("E1"), bg.Se("E2"), bg.RField("D", R)], [("E1", "D"), ("E2", "D")])
    model = bg.derive(g, outputs={"i1": bg.flow("D", port=1), "i2": bg.flow("D", port=2)})
    E1, E2 = real("E1 E2")
    det = r11 * r22 - r12**2
    assert zero(model.output_exprs[0] - (r22 * E1 - r12 * E2) / det)
    assert zero(model.output_exprs[1] - (r11 * E2 - r12 * E1) / det)
    # mixed: port 1 sees a capacitor's voltage, port 2 a current source I2
    g = build("mixed", [bg.Sf("I2"), bg.Zero("n"), bg.C("C1"), bg.Sf("Q"),
                        bg.RField("D", R)],
              [("Q", "n"), ("n", "C1"), ("n", "D"), ("I2", "D")])
    model = bg.derive(g, outputs={"u2": bg.effort("D", port=2)})
    Q, I2, q = real("Q I2 q_C1")
    i1 = (q / C1 - r12 * I2) / r11                # from e1 = r11 i1 + r12 I2
    assert zero(model.rhs[0] - (Q - i1))
    assert zero(model.output_exprs[0] - (r12 * i1 + r22 * I2))


def test_nonlinear_resistive_law_in_either_causality():
    f1, f2 = sympy.symbols("f1 f2")
    a, c = pos("a c")
    law = (a * f1 + c * f1**3, a * f2)
    g = build("nl", [bg.Sf("V"), bg.Se("E"), bg.RField("D", law=law, variables=(f1, f2))],
              [("V", "D"), ("E", "D")])
    model = bg.derive(g, outputs={"e1": bg.effort("D", port=1), "f2": bg.flow("D", port=2)})
    V, E = real("V E")
    assert zero(model.output_exprs[0] - (a * V + c * V**3))
    assert zero(model.output_exprs[1] - E / a)
    # port 1 receiving effort needs the cubic inverted: refused, naming the field and port
    g = build("nl2", [bg.Se("E1"), bg.Sf("V2"), bg.RField("D", law=law, variables=(f1, f2))],
              [("E1", "D"), ("V2", "D")])
    with pytest.raises(bg.FieldError, match=r"RF:D: the causality puts port 1 .* 3 solutions"):
        bg.derive(g, outputs={"f1": bg.flow("D", port=1)})


# ------------------------------------------------------------------ ICField
def test_ic_field_matches_lagrange():
    # a mass on a hardening spring, both in one IC field: H = p^2/2m + k q^2/2 + a q^3/3.
    # Lagrange: L = m v^2/2 - k q^2/2 - a q^3/3  =>  m q'' = F - k q - a q^2.
    p, q = sympy.symbols("p q")
    m, k, a = pos("m k a")
    H = p**2 / (2 * m) + k * q**2 / 2 + a * q**3 / 3
    g = build("ic", [bg.Se("F"), bg.One("v"), bg.ICField("S", "IC", energy=H, variables=(p, q))],
              [("F", "v"), ("v", "S"), ("v", "S")])
    model = bg.derive(g, outputs={"x": bg.displacement("S", port=2)})
    F, pS, qS = real("F p_S_1 q_S_2")
    assert model.state_names == ("p_S_1", "q_S_2")
    assert zero(model.rhs[0] - (F - k * qS - a * qS**2))     # m v' with p = m v
    assert zero(model.rhs[1] - pS / m)
    assert model.output_exprs[0] == qS and model.integrators == ()
    assert zero(model.energy() - H.xreplace({p: pS, q: qS}))


def test_linear_ic_field_from_its_hessian_gives_the_port_hamiltonian_form():
    m, k = pos("m k")
    g = build("osc", [bg.Se("F"), bg.One("v"), bg.R("b"),
                      bg.ICField("S", "IC", matrix=[[1 / m, 0], [0, k]])],
              [("F", "v"), ("v", "b"), ("v", "S"), ("v", "S")])
    ph = port_hamiltonian(bg.derive(g))
    b = sympy.Symbol("b", positive=True)
    pS, qS = real("p_S_1 q_S_2")
    assert zero(ph.H - (pS**2 / (2 * m) + k * qS**2 / 2))
    assert ph.J == sympy.Matrix([[0, -1], [1, 0]]) and ph.R == sympy.Matrix([[b, 0], [0, 0]])


# ------------------------------------------------------------------ signals and drawing
def test_port_signals_and_names():
    M = bg.IField("M", [[2, 1], [1, 2]])
    assert M.port_signal("flow", 2) == (1, True) and M.bonds == (2, 2)
    assert bg.flow("M", port=2).port == 2 and str(bg.momentum("M", port=1)) == "momentum[M][1]"
    with pytest.raises(bg.OutputError, match=r"IF:M has ports 1..2; got port 3"):
        M.port_signal("flow", 3)
    with pytest.raises(bg.OutputError, match=r"R:b is not a multiport field"):
        bg.R("b").port_signal("flow", 1)
    with pytest.raises(bg.OutputError, match="port must be an integer >= 1"):
        bg.flow("M", port=0)
    # inside a sub-model the port survives the renaming
    inner = build("arm", [bg.Port("hub"), bg.One("w"), bg.Sf("drive"),
                          bg.IField("M", [[2, 1], [1, 2]])],
                  [("hub", "w"), ("w", "M"), ("drive", "M")])
    top = build("top", [bg.Se("T"), inner], [("T", "arm.hub")])
    model = bg.derive(top, outputs={"w": bg.flow("arm.M", port=1)})
    T, p1, drive = real("T p_arm.M_1 arm.drive")
    assert model.state_names == ("p_arm.M_1",)
    assert zero(model.output_exprs[0] - (p1 - drive) / 2)


def test_drawing_shows_fields_and_all_their_bonds(tmp_path):
    m1, m2, m12, k = pos("m1 m2 m12 k")
    g = build("drawn", [bg.Se("F"), bg.One("v1"), bg.One("v2"),
                        bg.IField("M", [[m1, m12], [m12, m2]]),
                        bg.CField("K", stiffness=[[k, 0], [0, k]]),
                        bg.RField("D", [[1, 0], [0, 1]])],
                  [("F", "v1"), ("v1", "M"), ("v2", "M"), ("v1", "K"), ("v2", "K"),
                   ("v1", "D"), ("v2", "D")])
    path = tmp_path / "x.svg"
    bg.draw(g, path)
    svg = path.read_text()
    for label in ("IF", "CF", "RF"):
        assert f">{label}<" in svg or f">{label}:" in svg
    for number in range(1, 8):
        assert f">{number}<" in svg


# ------------------------------------------------------------------ bad inputs
def test_bad_inputs_name_the_field():
    m, c = pos("m c")
    with pytest.raises(bg.FieldError, match=r"IF:M: the mass matrix is 2x3; expected a square"):
        bg.IField("M", [[1, 0, 0], [0, 1, 0]])
    with pytest.raises(bg.FieldError, match=r"IF:M: the mass matrix is not symmetric: "
                                            r"entry \[2,1\] is 2 but \[1,2\] is 1"):
        bg.IField("M", [[3, 1], [2, 3]])
    with pytest.raises(bg.FieldError, match=r"CF:K: the stiffness matrix is not positive "
                                            r"definite \(smallest eigenvalue -1\)"):
        bg.CField("K", stiffness=[[1, 2], [2, 1]])
    with pytest.raises(bg.FieldError, match=r"IF:M: the mass matrix is not positive definite"):
        bg.IField("M", [[m, c], [c, m]]).check_values({"m": 1.0, "c": 2.0})
    bg.IField("M", [[m, c], [c, m]]).check_values({"m": 2.0, "c": 1.0})
    # a 3x3 field with two bonds: refused when the graph is flattened
    g = build("short", [bg.Se("F"), bg.Se("G"), bg.IField("M", np.eye(3))],
              [("F", "M"), ("G", "M")])
    with pytest.raises(bg.ModelStructureError, match=r"IF:M has 2 bonds; expected 3"):
        bg.derive(g)
    g = build("long", [bg.Se("F"), bg.Se("G"), bg.Se("H"), bg.IField("M", np.eye(2))],
              [("F", "M"), ("G", "M")])
    with pytest.raises(bg.ModelStructureError, match=r"IF:M takes 2 bonds"):
        g.connect("H", "M")
    # ambiguous signal
    g = build("amb", [bg.Se("F"), bg.Se("G"), bg.IField("M", np.eye(2))],
              [("F", "M"), ("G", "M")])
    with pytest.raises(bg.OutputError, match=r"IF:M has 2 ports, so its flow is ambiguous; "
                                             r"name one, e.g. bg.flow\('M', port=1\)"):
        bg.derive(g, outputs={"v": bg.flow("M")})
    # a nonlinear energy that cannot be inverted on a port in derivative causality
    p1, p2 = sympy.symbols("p1 p2")
    T = p1**2 / 2 + p2**4 / 4 + p1 * p2**2
    g = build("nl", [bg.Se("F"), bg.Sf("V"), bg.IField("M", energy=T, variables=(p1, p2))],
              [("F", "M"), ("V", "M")])
    with pytest.raises(bg.FieldError, match=r"IF:M: the causality puts port 2 in derivative "
                                            r"causality"):
        bg.derive(g)
    with pytest.raises(bg.FieldError, match=r"IF:M: energy= needs variables="):
        bg.IField("M", energy=T)
    with pytest.raises(bg.FieldError, match=r"CF:K: give either a matrix or energy=, not both"):
        bg.CField("K", stiffness=[[1]], energy=p1**2, variables=(p1,))
    with pytest.raises(bg.FieldError, match=r"ICF:X: kinds must be a string of 'I' and 'C'"):
        bg.ICField("X", "IR", matrix=np.eye(2))
    assert issubclass(bg.FieldError, bg.BondGraphError)


def test_plant_and_batch_check_the_mass_matrix_definite_at_the_values():
    # M = [[m, c], [c, m]] has eigenvalues m + c and m - c (by hand): definite iff m > |c|
    m, c = sympy.symbols("m c", positive=True)
    g = bg.BondGraph("pair")
    g.add(bg.Se("F1"), bg.Se("F2"), bg.IField("M", [[m, c], [c, m]]))
    g.connect("F1", "M")
    g.connect("F2", "M")
    nm = bg.compile_plant(bg.derive(g, outputs={"v1": bg.flow("M", port=1)}))
    # dp/dt = F on both ports; v1 = (M^-1 p)_1 = (m p1 - c p2)/(m^2 - c^2)
    plant = nm.plant({"m": 2.0, "c": 1.0})
    np.testing.assert_allclose(plant.B, np.eye(2), atol=1e-15)
    np.testing.assert_allclose(plant.C, [[2 / 3, -1 / 3]], rtol=1e-14)
    with pytest.raises(bg.FieldError, match=r"IF:M: the mass matrix is not positive definite "
                                            r"\(smallest eigenvalue -2\)"):
        nm.plant({"m": 1.0, "c": 3.0})
    with pytest.raises(bg.FieldError, match=r"IF:M: parameter set 2: .*smallest eigenvalue -2\b"):
        nm.batch({"m": np.array([2.0, 2.0, 1.0]), "c": np.array([1.0, 0.0, 3.0])})
    with pytest.raises(bg.FieldError, match="parameter set 0: .*smallest eigenvalue 0"):
        nm.batch({"m": np.array([1.0]), "c": np.array([1.0])}, sparse=True)
    assert nm.batch({"m": np.array([2.0, 2.0]), "c": np.array([1.0, 0.0])}).A.shape == (2, 2, 2)
