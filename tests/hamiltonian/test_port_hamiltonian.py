"""Port-Hamiltonian form (issue 13, item 3): ``bondgraph.hamiltonian``.

Every expected J, R, G, H below is derived by hand in the test, from the
element laws and the junction equations, never from the engine.  The power
balance is checked against the bond-level powers of the R elements and the
sources (``effort(k)*flow(k)`` of each bond, signed by its direction), which
use none of the port-Hamiltonian construction.
"""

from __future__ import annotations

import random
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.hamiltonian import PortHamiltonian, PortHamiltonianError, energy, port_hamiltonian

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "models"))

S = sympy.Symbol


def pos(names: str):
    return sympy.symbols(names, positive=True)


def zero(expr) -> bool:
    """Exactly zero: canonical for rational functions, simplify for anything else."""
    reduced = sympy.cancel(sympy.together(sympy.sympify(expr)))
    return reduced == 0 or (not reduced.is_rational_function() and sympy.simplify(reduced) == 0)


def same(a, b) -> bool:
    a, b = sympy.Matrix(a), sympy.Matrix(b)
    return a.shape == b.shape and all(zero(x - y) for x, y in zip(a, b))


def xs(model, names):
    by = {s.name: s for s in model.states}
    return [by[n] for n in names]


def structure_ok(ph: PortHamiltonian) -> None:
    assert (ph.J + ph.J.T).is_zero_matrix
    assert (ph.R - ph.R.T).is_zero_matrix
    assert (ph.N + ph.N.T).is_zero_matrix
    assert (ph.S - ph.S.T).is_zero_matrix


def rebuilds(ph: PortHamiltonian, model) -> bool:
    n = len(ph.states)
    return ph.states == tuple(model.states[:n]) and same(ph.rhs(), model.rhs[:n])


# ------------------------------------------------------------------ models by hand
def msd():
    g = bg.BondGraph("msd")
    v = bg.One("v")
    g.add(bg.Se("F"), v, bg.I("m"), bg.R("b"), bg.C("C"))
    for t, h in [("F", v), (v, "m"), (v, "b"), (v, "C")]:
        g.connect(t, h)
    return g


def dc_motor():
    g = bg.BondGraph("dc_motor")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
    for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
        g.connect(tail, head)
    return g


def two_inertias():
    g = bg.BondGraph("two")
    w = bg.One("w")
    g.add(bg.Se("T"), w, bg.I("J1"), bg.I("J2"), bg.R("b"))
    for t, h in [("T", w), (w, "J1"), (w, "J2"), (w, "b")]:
        g.connect(t, h)
    return g


def test_mass_spring_damper():
    """F on a mass m with damper b and spring (compliance C) on one 1-junction.

    Common velocity v = p/m; p' = F - b v - q/C; q' = v.  In z = (p/m, q/C):
    x' = [[-b, -1], [1, 0]] z + [1, 0]^T F, so J = [[0, -1], [1, 0]],
    R = [[b, 0], [0, 0]], G = [1, 0]^T, y = v (the flow out of F).
    """
    m, b, C = pos("m b C")
    model = bg.derive(msd(), outputs={"x": bg.displacement("C")})
    p, q = xs(model, ["p_m", "q_C"])
    ph = port_hamiltonian(model)
    assert ph.state_names == ("p_m", "q_C") and ph.input_names == ("F",)
    assert zero(ph.H - (p**2 / (2 * m) + q**2 / (2 * C)))
    assert same(ph.gradient, [p / m, q / C])
    assert ph.J == sympy.Matrix([[0, -1], [1, 0]])
    assert ph.R == sympy.Matrix([[b, 0], [0, 0]])
    assert ph.G == sympy.Matrix([[1], [0]])
    assert ph.P.is_zero_matrix and ph.S.is_zero_matrix and ph.N.is_zero_matrix
    assert ph.D.is_zero_matrix
    assert ph.Q == sympy.diag(1 / m, 1 / C)
    assert ph.output_names == ("f_F",) and same(ph.outputs(), [p / m])
    assert ph.nonconservative == ()
    assert rebuilds(ph, model)
    assert zero(energy(model) - ph.H)


def test_dc_motor_gyrator():
    """V -> 1:ia [Ra, La, GY K] -> 1:w [J, b].

    i = p_La/La, w = p_J/J.  GY: torque K i on the shaft, back-emf K w on the
    armature: p_La' = V - Ra i - K w, p_J' = K i - b w.  So in z = (i, w):
    J = [[0, -K], [K, 0]], R = diag(Ra, b), G = [1, 0]^T, y = i.
    """
    Ra, La, K, J, b = pos("Ra La K J b")
    model = bg.derive(dc_motor(), outputs={"omega": bg.flow("J"), "theta": bg.displacement("J")})
    pL, pJ = xs(model, ["p_La", "p_J"])
    ph = port_hamiltonian(model)
    # the integrator state theta stores no energy: it is left out
    assert model.state_names == ("p_La", "p_J", "theta")
    assert ph.state_names == ("p_La", "p_J")
    assert zero(ph.H - (pL**2 / (2 * La) + pJ**2 / (2 * J)))
    assert ph.J == sympy.Matrix([[0, -K], [K, 0]])
    assert ph.R == sympy.diag(Ra, b)
    assert ph.G == sympy.Matrix([[1], [0]])
    assert ph.P.is_zero_matrix and ph.S.is_zero_matrix
    assert same(ph.outputs(), [pL / La])
    assert rebuilds(ph, model)


def test_lossy_gyrator_is_flagged():
    """efficiency eta: torque eta*K*i, back-emf K*w.  F = [[-Ra, -K], [eta K, -b]]:
    J = [[0, -(1+eta)K/2], [(1+eta)K/2, 0]], R = [[Ra, (1-eta)K/2], [(1-eta)K/2, b]],
    indefinite when Ra*b < ((1-eta)K/2)**2."""
    Ra, K, b, eta = pos("Ra K b eta")
    g2 = bg.BondGraph("dc_lossy")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g2.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K", efficiency=eta), bg.I("J"), bg.R("b"))
    for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
        g2.connect(tail, head)
    model = bg.derive(g2)
    ph = port_hamiltonian(model)
    assert ph.nonconservative == ("GY:K",)
    assert same(ph.J, [[0, -(1 + eta) * K / 2], [(1 + eta) * K / 2, 0]])
    assert same(ph.R, [[Ra, (1 - eta) * K / 2], [(1 - eta) * K / 2, b]])
    assert rebuilds(ph, model)
    base = {"La": 1, "J": 1, "K": 2}
    assert ph.is_passive({**base, "Ra": 1, "b": 1, "eta": 0.9})
    assert not ph.is_passive({**base, "Ra": 0.01, "b": 0.01, "eta": 0.5})
    assert "not power-conserving: GY:K" in str(ph)


def test_feedthrough_rc():
    """V -> 1:i [R, C]: the resistor sets the current, i = (V - q/C)/R.

    q' = -z/R + V/R with z = q/C; y = i = -z/R + V/R.  So G - P = 1/R,
    (G + P)^T = -1/R: G = 0, P = -1/R; D = S - N = 1/R, S = 1/R, N = 0.
    W = [[1/R, -1/R], [-1/R, 1/R]] (rank one, PSD).
    """
    R, C = pos("R C")
    g = bg.BondGraph("rc")
    V, n = bg.Se("V"), bg.One("i")
    g.add(V, n, bg.R("R"), bg.C("C"))
    for t, h in [(V, n), (n, "R"), (n, "C")]:
        g.connect(t, h)
    model = bg.derive(g)
    ph = port_hamiltonian(model)
    assert ph.R == sympy.Matrix([[1 / R]]) and ph.J == sympy.zeros(1, 1)
    assert ph.G == sympy.zeros(1, 1) and ph.P == sympy.Matrix([[-1 / R]])
    assert ph.S == sympy.Matrix([[1 / R]]) and ph.N == sympy.zeros(1, 1)
    assert ph.D == sympy.Matrix([[1 / R]])
    assert ph.W == sympy.Matrix([[1 / R, -1 / R], [-1 / R, 1 / R]])
    assert rebuilds(ph, model)
    assert ph.is_passive({"R": 3.0, "C": 0.5})
    assert r"(G - P)\,u" in ph.to_latex()


def test_flow_source():
    """Sf I0 -> 0:n [C, R]: common effort e = q/C; q' = I0 - e/R; the
    collocated output of a flow source is the effort on its bond, e."""
    R, C = pos("R C")
    g = bg.BondGraph("sf")
    n = bg.Zero("n")
    g.add(bg.Sf("I0"), n, bg.C("C"), bg.R("R"))
    for t, h in [("I0", n), (n, "C"), (n, "R")]:
        g.connect(t, h)
    model = bg.derive(g)
    (q,) = model.states
    ph = port_hamiltonian(model)
    assert ph.R == sympy.Matrix([[1 / R]]) and ph.G == sympy.Matrix([[1]])
    assert ph.output_names == ("e_I0",) and same(ph.outputs(), [q / C])
    assert rebuilds(ph, model)


def test_skew_feedthrough_through_gyrator():
    """V1 -> 1:a -> GY r -> 1:b <- V2, no storage, no R.

    1:a: e1 = V1; GY: f2 = e1/r = V1/r, and f1 = e2/r where 1:b gives
    e2 + V2 = 0.  Flow out of V1: f1 = -V2/r; flow out of V2 (its bond points
    into b): f2 = V1/r.  D = [[0, -1/r], [1/r, 0]] is skew: S = 0, N = -D.
    """
    r = S("r", positive=True)
    g = bg.BondGraph("gy")
    a, b = bg.One("a"), bg.One("b")
    g.add(bg.Se("V1"), bg.Se("V2"), a, b, bg.GY("r"))
    for t, h in [("V1", a), (a, "r"), ("r", b), ("V2", b)]:
        g.connect(t, h)
    model = bg.derive(g)
    ph = port_hamiltonian(model)
    assert ph.states == () and ph.H == 0
    assert ph.D == sympy.Matrix([[0, -1 / r], [1 / r, 0]])
    assert ph.S.is_zero_matrix and ph.N == -ph.D
    assert ph.supplied_power() == 0 and ph.is_passive({"r": 2.0})


def test_nonlinear_spring():
    """C law e = k q + k3 q^3: H_C = int_0^q (k s + k3 s^3) ds = k q^2/2 + k3 q^4/4.

    With z = (p/m, k q + k3 q^3) the equations are linear in z, as for the
    linear mass-spring-damper: J = [[0, -1], [1, 0]], R = diag(b, 0).
    """
    m, b, k, k3 = pos("m b k k3")
    g = bg.BondGraph("duffing")
    v = bg.One("v")
    g.add(bg.Se("F"), v, bg.I("m"), bg.R("b"), bg.C("s", law=k * bg.q + k3 * bg.q**3))
    for t, h in [("F", v), (v, "m"), (v, "b"), (v, "s")]:
        g.connect(t, h)
    model = bg.derive(g)
    p, q = xs(model, ["p_m", "q_s"])
    ph = port_hamiltonian(model)
    assert zero(ph.H - (p**2 / (2 * m) + k * q**2 / 2 + k3 * q**4 / 4))
    assert same(ph.gradient, [p / m, k * q + k3 * q**3])
    assert ph.J == sympy.Matrix([[0, -1], [1, 0]]) and ph.R == sympy.diag(b, 0)
    assert ph.G == sympy.Matrix([[1], [0]]) and ph.Q is None
    assert rebuilds(ph, model)
    assert zero(energy(model) - ph.H)


def test_nonlinear_inertia():
    """I law f = p/m + a p^3: H = p^2/(2m) + a p^4/4; with an R to ground,
    p' = F - b f: J = 0, R = b, G = 1."""
    m, a, b = pos("m a b")
    g = bg.BondGraph("nlmass")
    v = bg.One("v")
    g.add(bg.Se("F"), v, bg.I("m", law=bg.p / m + a * bg.p**3), bg.R("b"))
    for t, h in [("F", v), (v, "m"), (v, "b")]:
        g.connect(t, h)
    model = bg.derive(g)
    (p,) = model.states
    ph = port_hamiltonian(model)
    assert zero(ph.H - (p**2 / (2 * m) + a * p**4 / 4))
    assert ph.R == sympy.Matrix([[b]]) and ph.J == sympy.zeros(1, 1)
    assert rebuilds(ph, model)


def test_derivative_causality_two_inertias():
    """T -> 1:w [J1, J2, b]: J2 is rigidly joined to J1 (derivative causality).

    State p = p_J1, w = p/J1.  Energy (J1 + J2) w^2/2 = (J1 + J2) p^2/(2 J1^2),
    i.e. P^2/(2 (J1 + J2)) for the total momentum P = (J1 + J2)/J1 p.
    p' = J1 (T - b w)/(J1 + J2).  grad H = (J1 + J2) p/J1^2 = z, so
    w = J1 z/(J1 + J2) and p' = -b J1^2/(J1 + J2)^2 z + J1/(J1 + J2) T:
    R = b J1^2/(J1 + J2)^2, G = J1/(J1 + J2); y = w = G z, P = 0.
    """
    J1, J2, b = pos("J1 J2 b")
    model = bg.derive(two_inertias())
    assert model.descriptor is not None and model.augmented.derivative == ("J2",)
    (p,) = model.states
    ph = port_hamiltonian(model)
    Ptot = (J1 + J2) / J1 * p
    assert zero(ph.H - Ptot**2 / (2 * (J1 + J2)))
    assert zero(ph.H - (J1 + J2) * p**2 / (2 * J1**2))
    assert same(ph.R, [[b * J1**2 / (J1 + J2) ** 2]]) and ph.J == sympy.zeros(1, 1)
    assert same(ph.G, [[J1 / (J1 + J2)]]) and ph.P.is_zero_matrix
    assert same(ph.outputs(), [p / J1])
    assert rebuilds(ph, model)
    assert ph.is_passive({"J1": 2.0, "J2": 3.0, "b": 0.5})


def test_derivative_causality_through_gear():
    """T -> 1:w1 [J1, b] -> TF n -> 1:w2 [J2]: w2 = n w1, effective inertia
    Je = J1 + n^2 J2.  H = (J1 + n^2 J2) p^2/(2 J1^2); p' = J1 (T - b w1)/Je,
    so R = b J1^2/Je^2, G = J1/Je, J = 0."""
    J1, J2, b, n = pos("J1 J2 b n")
    g = bg.BondGraph("gear")
    w1, w2 = bg.One("w1"), bg.One("w2")
    g.add(bg.Se("T"), w1, w2, bg.I("J1"), bg.R("b"), bg.TF("n"), bg.I("J2"))
    for t, h in [("T", w1), (w1, "J1"), (w1, "b"), (w1, "n"), ("n", w2), (w2, "J2")]:
        g.connect(t, h)
    model = bg.derive(g)
    assert model.augmented.derivative == ("J2",)
    (p,) = model.states
    Je = J1 + n**2 * J2
    ph = port_hamiltonian(model)
    assert zero(ph.H - Je * p**2 / (2 * J1**2))
    assert same(ph.R, [[b * J1**2 / Je**2]]) and same(ph.G, [[J1 / Je]])
    assert rebuilds(ph, model)


# ------------------------------------------------------------------ power balance
def bond_powers(model):
    """(power dissipated in R elements, power delivered by sources) from the
    bond variables, signed by each bond's direction, as functions of (x, u)."""
    flat = model.augmented.flat
    outs, sign = {}, {}
    for el in flat.elements:
        if el.kind in ("R", "RF", "Se", "Sf"):       # a resistive field: each of its bonds
            kind = "R" if el.kind == "RF" else el.kind
            for k in flat.incidence[el.name]:
                bond = flat.bonds[k]
                outs[f"e{k}"], outs[f"f{k}"] = bg.effort(bond.number), bg.flow(bond.number)
                into = bond.head == el.name
                sign[k] = (kind, 1 if into == (kind == "R") else -1)
    if not outs:
        return sympy.Integer(0), sympy.Integer(0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bg.BondGraphWarning)
        aux = bg.derive(model.augmented, outputs=outs)
    val = dict(zip(aux.output_names, aux.output_exprs))
    p_R = sum((s * val[f"e{k}"] * val[f"f{k}"] for k, (kind, s) in sign.items() if kind == "R"),
              sympy.Integer(0))
    p_src = sum((s * val[f"e{k}"] * val[f"f{k}"] for k, (kind, s) in sign.items() if kind != "R"),
                sympy.Integer(0))
    return p_R, p_src


def check_power_balance(model, ph) -> None:
    """dH/dt = -w^T W w + y^T u, each side against the bond-level powers."""
    n = len(ph.states)
    dHdt = sum((sympy.diff(ph.H, x) * f for x, f in zip(model.states[:n], model.rhs[:n])),
               sympy.Integer(0))
    p_R, p_src = bond_powers(model)
    assert zero(dHdt - (p_src - p_R)), "energy balance of the derived equations"
    assert zero(ph.dissipation() - p_R), "w^T W w is the power of the R elements"
    assert zero(ph.supplied_power() - p_src), "y^T u is the power of the sources"
    assert zero(dHdt - (-ph.dissipation() + ph.supplied_power()))


@pytest.mark.parametrize("build", [msd, dc_motor, two_inertias], ids=lambda f: f.__name__)
def test_power_balance(build):
    model = bg.derive(build())
    check_power_balance(model, port_hamiltonian(model))


def test_power_balance_nonlinear_spring():
    k, k3 = pos("k k3")
    g = bg.BondGraph("duffing")
    v = bg.One("v")
    g.add(bg.Sf("vel"), v, bg.R("b"), bg.C("s", law=k * bg.q + k3 * bg.q**3))
    for t, h in [("vel", v), (v, "b"), (v, "s")]:
        g.connect(t, h)
    model = bg.derive(g)
    check_power_balance(model, port_hamiltonian(model))


# ------------------------------------------------------------------ refusals
def refused(g, match: str, outputs=None):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bg.BondGraphWarning)
        model = bg.derive(g, outputs=outputs)
    with pytest.raises(PortHamiltonianError, match=match) as info:
        port_hamiltonian(model)
    assert isinstance(info.value, bg.NonlinearModelError)
    assert isinstance(info.value, bg.BondGraphError) and isinstance(info.value, ValueError)
    return str(info.value)


def mass_with(*extra, edges=()):
    g = bg.BondGraph("m")
    v = bg.One("v")
    g.add(v, bg.I("m"), *extra)
    g.connect(v, "m")
    for t, h in edges:
        g.connect(t, h)
    return g


def test_refuses_nonlinear_R():
    c = S("c", positive=True)
    g = mass_with(bg.Se("F"), bg.R("d", law=c * bg.f * abs(bg.f)), edges=[("F", "v"), ("v", "d")])
    msg = refused(g, r"R:d")
    assert "nonlinear law" in msg


def test_refuses_modulated_transformer():
    r = S("r", positive=True)
    g = mass_with(bg.Se("F"), bg.MTF("yoke", modulus=r * sympy.cos(bg.t)), bg.One("w"),
                  bg.R("b"), edges=[("F", "w"), ("w", "yoke"), ("yoke", "v"), ("w", "b")])
    refused(g, r"MTF:yoke")


def test_refuses_modulated_and_prescribed_sources():
    kp, m_, g_ = pos("kp mass grav")
    g = mass_with(bg.Se("F"), bg.Se("ctrl", value=-kp * bg.flow("m")), bg.R("b"),
                  edges=[("F", "v"), ("ctrl", "v"), ("v", "b")])
    assert "modulated source" in refused(g, r"MSe:ctrl")
    g = mass_with(bg.Se("F"), bg.Se("gravity", value=m_ * g_), edges=[("F", "v"), ("gravity", "v")])
    assert "not a port" in refused(g, r"Se:gravity")
    g = mass_with(bg.Se("drive", value=sympy.sin(bg.t)), bg.R("b"),
                  edges=[("drive", "v"), ("v", "b")])
    refused(g, r"MSe:drive")


def test_refuses_source_driving_storage():
    """A flow source on the inertia's junction fixes its flow: m is in derivative
    causality and its momentum m*v is the input's, not a state's."""
    g = mass_with(bg.Sf("vel"), bg.R("b"), edges=[("vel", "v"), ("v", "b")])
    refused(g, r"I:m .*depends on vel")


def test_refuses_nonlinear_storage_in_derivative_causality():
    """J2 (law f = a p^3, inverse p = (f/a)^(1/3)) rigidly joined to J1."""
    a = S("a", positive=True)
    g = bg.BondGraph("two_nl")
    w = bg.One("w")
    g.add(bg.Se("T"), w, bg.I("J1"),
          bg.I("J2", law=a * bg.p**3, inverse=(bg.f / a) ** sympy.Rational(1, 3)), bg.R("b"))
    for t, h in [("T", w), (w, "J1"), (w, "J2"), (w, "b")]:
        g.connect(t, h)
    refused(g, r"I:J2 is in derivative causality with the nonlinear law")


def test_refuses_energy_that_cannot_be_integrated():
    g = mass_with(bg.Se("F"), bg.C("s", law=sympy.exp(sympy.sin(bg.q))),
                  edges=[("F", "v"), ("v", "s")])
    refused(g, r"C:s: sympy cannot integrate")
    with pytest.raises(PortHamiltonianError, match="C:s"):
        energy(bg.derive(g))


def test_energy_of_a_model_without_port_hamiltonian_form():
    """energy() needs storage laws only: a nonlinear damper does not matter."""
    m, c, k = pos("m c k")
    g = mass_with(bg.Se("F"), bg.R("d", law=c * bg.f * abs(bg.f)), bg.C("k", stiffness="k"),
                  edges=[("F", "v"), ("v", "d"), ("v", "k")])
    model = bg.derive(g)
    p, q = xs(model, ["p_m", "q_k"])
    assert zero(energy(model) - (p**2 / (2 * m) + k * q**2 / 2))


# ------------------------------------------------------------------ the model library
def library():
    import appendages
    import flexcam
    import srv02

    return {
        "srv02": lambda: srv02.model(),
        "srv02-no-inductance": lambda: srv02.model(inductance=False),
        "srv02-load-inertia (derivative causality)": lambda: srv02.model(load_inertia=True),
        "flexcam-paper": lambda: flexcam.model(),
        "flexcam-system": lambda: flexcam.model(formulation="system"),
        "flexcam-damped": lambda: flexcam.model(damping_ratio=0.02),
        "appendages": lambda: appendages.model(),
        "appendages-tip-mass": lambda: appendages.model(tip_mass=0.05),
        "appendages-paper (IField, CField)": lambda: appendages.model(formulation="paper"),
    }


def conservative_values(ph, model, rng: random.Random) -> dict:
    """Random positive values with every TF/GY efficiency pinned to 1."""
    vals = {p: rng.uniform(0.2, 5.0) for p in ph.parameters}
    for el_label in ph.nonconservative:
        eff = next(el.efficiency for el in model.augmented.flat.elements
                   if el.label() == el_label)
        free = sorted(eff.free_symbols, key=lambda s: s.name)
        pick = free[0]
        others = {s: vals[s] for s in free[1:]}
        (sol,) = sympy.solve(sympy.Eq(eff.xreplace(others), 1), pick)
        vals[pick] = float(sol)
    return {p.name: v for p, v in vals.items()}


@pytest.mark.parametrize("variant", list(library()))
def test_model_library(variant):
    """Every model under models/ is linear and gets the form: x' rebuilt from
    (J, R, G, P, H) equals the derived rhs; J skew; W >= 0 at random positive
    values once the data-sheet efficiencies are 1 (with efficiency < 1 the
    TF/GY are not power-conserving and are listed)."""
    d = library()[variant]()
    model = d.derive()
    ph = port_hamiltonian(model)
    structure_ok(ph)
    assert rebuilds(ph, model)
    lossy = tuple(el.label() for el in model.augmented.flat.elements
                  if el.kind in ("TF", "GY") and el.efficiency != 1)
    assert ph.nonconservative == lossy
    assert ph.state_names == model.state_names[:model.storage_states]
    rng = random.Random(13)
    for _ in range(3):
        assert ph.is_passive(conservative_values(ph, model, rng), tol=1e-9)
    if not lossy:
        assert ph.is_passive(dict(d.parameters), tol=1e-9)


def test_srv02_energy_of_the_rigid_load():
    """With the load J_l on the output shaft (derivative causality through the
    gear, w_l = w_m/Kg) the energy holds J_l w_l^2/2."""
    import srv02

    Lm, Jm, J_l, Kg = pos("Lm Jm J_l Kg")
    model = srv02.model(load_inertia=True).derive()
    pL, pJ = xs(model, ["p_Lm", "p_Jm"])
    w_m = pJ / Jm
    expect = pL**2 / (2 * Lm) + Jm * w_m**2 / 2 + J_l * (w_m / Kg) ** 2 / 2
    assert zero(energy(model) - expect)


# ------------------------------------------------------------------ random graphs
def _random_models(count: int, *, derivative: bool):
    from verification import generator as gen

    found, seed = [], 0
    while len(found) < count and seed < 400:
        seed += 1
        g = gen.generate(seed, p_clash=0.0, max_elements=14)
        graph, outputs, _ = gen.build(g)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", bg.BondGraphWarning)
                model = bg.derive(graph, outputs=outputs)
        except bg.BondGraphError:
            continue                      # ill-posed graphs are refused by derive
        if bool(model.augmented.derivative) != derivative:
            continue
        found.append((seed, model))
    return found


def _check_random(seed, model):
    ph = port_hamiltonian(model)
    structure_ok(ph)
    assert rebuilds(ph, model), f"seed {seed}"
    rng = np.random.default_rng(seed)
    for _ in range(2):
        vals = {p.name: float(rng.uniform(0.1, 10.0)) for p in ph.parameters}
        num = ph.numeric(vals)
        assert np.allclose(num["J"], -num["J"].T)
        assert ph.is_passive(vals), f"seed {seed}: W not PSD at {vals}"
    return ph


def test_random_graphs_integral_causality():
    """~30 random linear graphs (ladders, bridges, circuits, trees, drivetrains,
    algebraic loops) in integral causality: reconstruction equals rhs, J skew,
    W = [[R, P], [P^T, S]] >= 0 at random positive values; on every third
    graph the power balance against the bond-level powers as well."""
    models = _random_models(30, derivative=False)
    assert len(models) == 30
    for i, (seed, model) in enumerate(models):
        ph = _check_random(seed, model)
        if i % 3 == 0:
            check_power_balance(model, ph)


def test_random_graphs_derivative_causality():
    """Random graphs with rigidly joined storage: either the reduced form
    (same checks) or a refusal naming the storage element a source drives."""
    models = _random_models(12, derivative=True)
    done = 0
    for seed, model in models:
        try:
            _check_random(seed, model)
            done += 1
        except PortHamiltonianError as err:
            assert "a source fixes its" in str(err) and (":" in str(err).split()[0]), str(err)
    assert done >= 4


# ------------------------------------------------------------------ printing, values
def test_latex_str_subs_numeric():
    m, b, C = pos("m b C")
    ph = port_hamiltonian(bg.derive(msd()))
    tex = ph._repr_latex_()
    assert tex.startswith("$$") and r"\nabla H" in tex and r"\frac{p_{m}^{2}}{2 m}" in tex
    assert r"(J - R)\,\nabla H(x) + G\,u" in tex
    assert "H = p_m**2/(2*m) + q_C**2/(2*C)" in str(ph)
    half = ph.subs({"m": 2, "b": 0.5})
    assert half.R == sympy.Matrix([[sympy.Rational(1, 2), 0], [0, 0]])
    assert half.parameters == (C,)
    num = ph.numeric({"m": 2.0, "b": 0.5, "C": 0.1})
    assert np.allclose(num["Q"], np.diag([0.5, 10.0])) and num["G"].shape == (2, 1)
    with pytest.raises(bg.ParameterValueError, match="unknown parameter 'bb'"):
        ph.subs({"bb": 1})
    with pytest.raises(bg.MissingValueError):
        ph.numeric({"m": 1.0})


def test_free_oscillator_without_inputs():
    """1:n [L, C, R], no source: p' = -R i - q/C, q' = i; J = [[0, -1], [1, 0]],
    R = diag(R, 0), G is 2 x 0 and the form has no outputs."""
    R = S("R", positive=True)
    g = bg.BondGraph("lc")
    n = bg.One("n")
    g.add(n, bg.I("L"), bg.C("C"), bg.R("R"))
    for t, h in [(n, "L"), (n, "C"), (n, "R")]:
        g.connect(t, h)
    model = bg.derive(g)
    ph = port_hamiltonian(model)
    assert ph.J == sympy.Matrix([[0, -1], [1, 0]]) and ph.R == sympy.diag(R, 0)
    assert ph.G.shape == (2, 0) and ph.output_names == () and ph.outputs() == ()
    assert rebuilds(ph, model)
    assert "u =" not in ph.to_latex()


# ------------------------------------------------------------------ multiport fields
def two_dof_fields():
    """Se F on coordinate 1; p = M v (IField), e = K q (CField), e = D v (RField)."""
    m1, m2, m12, k1, k2, k12, d1, d2 = pos("m1 m2 m12 k1 k2 k12 d1 d2")
    M = sympy.Matrix([[m1, m12], [m12, m2]])
    K = sympy.Matrix([[k1, k12], [k12, k2]])
    D = sympy.diag(d1, d2)
    g = bg.BondGraph("fields")
    g.add(bg.Se("F"), bg.One("v1"), bg.One("v2"), bg.IField("M", M),
          bg.CField("K", stiffness=K), bg.RField("D", D))
    for t, h in [("F", "v1"), ("v1", "M"), ("v2", "M"), ("v1", "K"), ("v2", "K"),
                 ("v1", "D"), ("v2", "D")]:
        g.connect(t, h)
    return g, M, K, D


def test_fields_give_the_quadratic_energy_and_the_canonical_structure():
    """By hand: x = (p, q); grad H = (M^-1 p, K q); p' = F e1 - K q - D v, q' = v,
    so J = [[0, -1], [1, 0]] (blocks), R = diag(D, 0), G = e1."""
    g, M, K, D = two_dof_fields()
    model = bg.derive(g)
    p = sympy.Matrix(xs(model, ["p_M_1", "p_M_2"]))
    q = sympy.Matrix(xs(model, ["q_K_1", "q_K_2"]))
    ph = port_hamiltonian(model)
    H = (p.T * M.inv() * p)[0, 0] / 2 + (q.T * K * q)[0, 0] / 2
    assert zero(ph.H - H) and zero(model.energy() - H)
    Z, I2 = sympy.zeros(2), sympy.eye(2)
    assert same(ph.J, sympy.BlockMatrix([[Z, -I2], [I2, Z]]).as_explicit())
    assert same(ph.R, sympy.BlockMatrix([[D, Z], [Z, Z]]).as_explicit())
    assert same(ph.G, [[1], [0], [0], [0]]) and same(ph.Q, sympy.diag(M.inv(), K))
    assert rebuilds(ph, model)
    check_power_balance(model, ph)


def test_field_in_mixed_causality_gives_the_effective_inertia():
    """Both ports of p = M v on one junction: port 2 is in derivative causality,
    v = p1/(m1 + m12) and H = (m1 + 2 m12 + m2) v^2/2 (by hand, v^T M v/2 with v = (v, v))."""
    m1, m2, m12, b = pos("m1 m2 m12 b")
    g = bg.BondGraph("joined")
    g.add(bg.Se("F"), bg.One("v"), bg.R("b"), bg.IField("M", [[m1, m12], [m12, m2]]))
    for t, h in [("F", "v"), ("v", "b"), ("v", "M"), ("v", "M")]:
        g.connect(t, h)
    model = bg.derive(g)
    assert model.state_names == ("p_M_1",) and model.augmented.derivative == ("M",)
    (p,) = model.states
    v = p / (m1 + m12)
    m_eff = m1 + 2 * m12 + m2
    ph = port_hamiltonian(model)
    assert zero(ph.H - m_eff * v**2 / 2)
    # Newton on the effective body: m_eff v' = F - b v, and p = (m1 + m12) v
    F = S("F", real=True)
    assert zero(model.rhs[0] - (m1 + m12) * (F - b * v) / m_eff)
    assert rebuilds(ph, model)
    check_power_balance(model, ph)


def _random_spd(rng: random.Random, n: int) -> sympy.Matrix:
    """A random symmetric positive-definite rational matrix: L L^T + I/2."""
    L = sympy.Matrix(n, n, lambda i, j: sympy.Rational(rng.randint(-4, 4), 3) if j <= i else 0)
    return L * L.T + sympy.eye(n) / 2


@pytest.mark.parametrize("seed", range(5))
def test_random_field_models(seed):
    """Random chains of 1-junctions sharing an IField, a CField and an RField with random
    SPD matrices, with one-port I/C/R added at random: x' rebuilt from (J, R, H, G),
    J skew, W >= 0, and the power balance against the bond powers."""
    rng = random.Random(seed)
    n = rng.randint(2, 3)
    g = bg.BondGraph(f"random{seed}")
    juncs = [bg.One(f"v{i}") for i in range(n)]
    g.add(*juncs, bg.IField("M", _random_spd(rng, n)))
    c_ports = sorted(rng.sample(range(n), rng.randint(1, n)))
    r_ports = sorted(rng.sample(range(n), rng.randint(1, n)))
    g.add(bg.CField("K", stiffness=_random_spd(rng, len(c_ports))),
          bg.RField("D", _random_spd(rng, len(r_ports))))
    for i in range(n):
        g.connect(juncs[i], "M")
    for i in c_ports:
        g.connect(juncs[i], "K")
    for i in r_ports:
        g.connect(juncs[i], "D")
    for i in range(n):
        extra = rng.choice(["Se", "I", "C", "R", None])
        if extra == "Se":
            g.add(bg.Se(f"F{i}"))
            g.connect(f"F{i}", juncs[i])
        elif extra:
            g.add(getattr(bg, extra)(f"{extra.lower()}{i}"))
            g.connect(juncs[i], f"{extra.lower()}{i}")
    model = bg.derive(g)
    ph = port_hamiltonian(model)
    structure_ok(ph)
    assert rebuilds(ph, model), f"seed {seed}"
    vals = {p.name: rng.uniform(0.2, 5.0) for p in ph.parameters}
    assert ph.is_passive(vals), f"seed {seed}"
    check_power_balance(model, ph)


def test_refuses_nonlinear_resistive_field_and_nonlinear_field_in_derivative_causality():
    f1, f2, p1, p2 = sympy.symbols("f1 f2 p1 p2")
    g = mass_with(bg.Se("F"), bg.One("w"), bg.I("m2"),
                  bg.RField("D", law=(f1**3, f2), variables=(f1, f2)),
                  edges=[("F", "v"), ("v", "D"), ("w", "D"), ("w", "m2")])
    assert "linear RField" in refused(g, r"RF:D: the nonlinear law")
    g = bg.BondGraph("nl")
    g.add(bg.Se("F"), bg.One("v"),
          bg.IField("M", energy=p1**2 / 2 + p2**2 / 2 + p1**4 * p2**4, variables=(p1, p2)))
    for t, h in [("F", "v"), ("v", "M"), ("v", "M")]:
        g.connect(t, h)
    with pytest.raises(bg.FieldError, match=r"IF:M: the causality puts port 2 in derivative"):
        bg.derive(g)
