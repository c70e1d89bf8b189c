"""Equilibria of nonlinear models that are found, in any units, each against a hand result.

Hand results: the hydraulic circuit of issue 22 (pump flow through the
orifice: ``dp = (Q/Kv)^2``; the pipe drop ``Rp Q``; the charge of each
compliance ``C p``; the pipe momentum ``Lp Q``), its Jacobian written out by
hand; a pendulum hanging and upright (``lambda^2 + (b/J) lambda +- m g l/J``);
Duffing's double well (``q = 0, +-sqrt(a/c)``); a saturating spring
``e = Fs tanh(q/qs)`` under a load (``q = qs atanh(F/Fs)``); an exponential
spring, a one-sided (``Piecewise``/``Heaviside``/``Max``) spring.
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.linear import EquilibriumError

KV = sympy.Symbol("Kv", positive=True)
#: the circuit of the issue, SI units
SI = {"Ch": 8.3e-14, "Lp": 2.165e7, "Rp": 2.44e8, "Ca": 4.1e-11, "Kv": 3.395e-8}
Q_SI = 1e-4
#: bar and litres: p_bar = p / 1e5, volume_L = V * 1e3 (so C * 1e8, L / 1e8, R / 1e8,
#: Kv * 1e3 * sqrt(1e5)), Q = 0.1 L/s
BAR = {"Ch": SI["Ch"] * 1e8, "Lp": SI["Lp"] / 1e8, "Rp": SI["Rp"] / 1e8, "Ca": SI["Ca"] * 1e8,
       "Kv": SI["Kv"] * 1e3 * math.sqrt(1e5)}
Q_BAR = 0.1
#: state conversions bar/litres -> SI
TO_SI = {"q_Ch": 1e-3, "p_Lp": 1e5, "q_Ca": 1e-3}


def hydraulic(signed: bool = True) -> bg.Model:
    g = bg.BondGraph("hydraulic")
    hose, pipe, acc = bg.Zero("hose"), bg.One("pipe"), bg.Zero("acc")
    e = bg.e
    flow_law = KV * sympy.sign(e) * sympy.sqrt(abs(e)) if signed else KV * sympy.sqrt(e)
    g.add(bg.Sf("Q"), hose, bg.C("Ch"), pipe, bg.I("Lp"), bg.R("Rp"), acc, bg.C("Ca"),
          bg.R("orifice", inverse=flow_law))
    for t, h in [("Q", hose), (hose, "Ch"), (hose, pipe), (pipe, "Lp"), (pipe, "Rp"),
                 (pipe, acc), (acc, "Ca"), (acc, "orifice")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"p_hose": bg.effort("Ch"), "p_acc": bg.effort("Ca"),
                                 "Q_pipe": bg.flow("Lp")})


def hand_hydraulic(v, Q):
    """The equilibrium by hand: every element carries the pump flow Q."""
    pa = (Q / v["Kv"]) ** 2                 # orifice: Q = Kv sqrt(pa)
    ph = pa + v["Rp"] * Q                   # pipe: p_hose - p_acc = Rp Q
    return {"q_Ch": v["Ch"] * ph, "p_Lp": v["Lp"] * Q, "q_Ca": v["Ca"] * pa}


def hand_hydraulic_jacobian(v, Q):
    """df/dx at the equilibrium, states (q_Ch, p_Lp, q_Ca); the orifice's slope
    dQ/dp = Kv / (2 sqrt(pa)) = Kv^2 / (2 Q)."""
    g1 = v["Kv"] ** 2 / (2 * Q)
    return np.array([[0.0, -1 / v["Lp"], 0.0],
                     [1 / v["Ch"], -v["Rp"] / v["Lp"], -1 / v["Ca"]],
                     [0.0, 1 / v["Lp"], -g1 / v["Ca"]]])


@pytest.fixture(scope="module", params=[True, False], ids=["signed", "unsigned"])
def hyd(request):
    return hydraulic(request.param)


def test_hydraulic_si_against_the_hand_solution(hyd):
    eq = hyd.equilibrium(SI, {"Q": Q_SI})
    hand = hand_hydraulic(SI, Q_SI)
    for name, value in hand.items():
        assert eq.states[name] == pytest.approx(value, rel=1e-9), name
    assert eq.method == "numeric" and eq.scaled_residual <= 1e-10
    assert "scipy.optimize.root" in eq.how
    assert eq.stability == "stable"
    lam = np.sort_complex(np.linalg.eigvals(hand_hydraulic_jacobian(SI, Q_SI)))
    assert np.allclose(np.sort_complex(np.array(eq.eigenvalues)), lam, rtol=1e-6)
    assert math.isfinite(eq.condition) and eq.condition >= 1


def test_hydraulic_bar_litres_gives_the_same_equilibrium(hyd):
    si = hyd.equilibrium(SI, {"Q": Q_SI})
    bar = hyd.equilibrium(BAR, {"Q": Q_BAR})
    hand = hand_hydraulic(SI, Q_SI)
    for name, value in hand.items():
        assert bar.states[name] * TO_SI[name] == pytest.approx(value, rel=1e-9), name
        assert bar.states[name] * TO_SI[name] == pytest.approx(si.states[name], rel=1e-9)
    # the time constants do not depend on the units
    assert np.allclose(np.sort_complex(np.array(bar.eigenvalues)),
                       np.sort_complex(np.array(si.eigenvalues)), rtol=1e-6)
    assert bar.condition == pytest.approx(si.condition, rel=1e-6)


def test_hydraulic_linearization_and_control_plant_in_si(hyd):
    """derive -> equilibrium -> linearize -> python-control, SI units, no error."""
    eq = hyd.equilibrium(SI, {"Q": Q_SI})
    plant = hyd.linearize(eq)
    A = hand_hydraulic_jacobian(SI, Q_SI)
    assert np.allclose(np.asarray(plant.A), A, rtol=1e-9, atol=0)
    sys = plant.to_control()
    poles = np.sort_complex(np.asarray(sys.poles()))
    assert np.allclose(poles, np.sort_complex(np.linalg.eigvals(A)), rtol=1e-6)
    # DC gains from the pump flow: d pa/dQ = 2 Q / Kv^2, d p_hose/dQ = that + Rp, dQ_pipe/dQ = 1
    dc = np.asarray(sys.dcgain()).reshape(3)
    g_acc = 2 * Q_SI / SI["Kv"] ** 2
    assert plant.output_names == ("p_hose", "p_acc", "Q_pipe")
    assert dc == pytest.approx([g_acc + SI["Rp"], g_acc, 1.0], rel=1e-6)


def test_signed_law_jacobian_never_reaches_lambdify_as_diracdelta():
    """The derivative of sign is 2 DiracDelta: 0 away from 0, never a NameError."""
    m = hydraulic(True)
    eq = m.equilibrium(BAR, {"Q": Q_BAR}, exact=False)
    assert eq.jacobian.startswith("symbolic")


def pendulum():
    m, g_, l = sympy.symbols("m g l", positive=True)
    gr = bg.BondGraph("pendulum")
    w = bg.One("w")
    gr.add(bg.Se("T"), w, bg.I("J"), bg.R("b"), bg.C("grav", law=m * g_ * l * sympy.sin(bg.q)))
    for t, h in [("T", w), (w, "J"), (w, "b"), (w, "grav")]:
        gr.connect(t, h)
    return bg.derive(gr)


PEND = {"m": 1.0, "g": 9.81, "l": 0.5, "J": 0.25, "b": 0.1}


@pytest.mark.parametrize("guess, theta, verdict, sign", [
    (0.4, 0.0, "stable", 1.0), (2.6, math.pi, "unstable", -1.0), (-3.6, -math.pi, "unstable", -1.0)])
def test_pendulum_hanging_and_upright(guess, theta, verdict, sign):
    eq = pendulum().equilibrium(PEND, {"T": 0.0}, guess={"q_grav": guess})
    assert eq.states["q_grav"] == pytest.approx(theta, abs=1e-12)
    assert eq.states["p_J"] == pytest.approx(0.0, abs=1e-12)
    assert eq.stability == verdict
    # lambda^2 + (b/J) lambda + sign m g l / J = 0
    a, c = PEND["b"] / PEND["J"], sign * PEND["m"] * PEND["g"] * PEND["l"] / PEND["J"]
    roots = np.sort_complex(np.roots([1.0, a, c]).astype(complex))
    assert np.allclose(np.sort_complex(np.array(eq.eigenvalues)), roots, rtol=1e-8)


def duffing():
    a, c = sympy.symbols("a c", positive=True)
    gr = bg.BondGraph("duffing")
    v = bg.One("v")
    gr.add(bg.Se("F"), v, bg.I("m"), bg.R("b"), bg.C("k", law=-a * bg.q + c * bg.q ** 3))
    for t, h in [("F", v), (v, "m"), (v, "b"), (v, "k")]:
        gr.connect(t, h)
    return bg.derive(gr)


DUFF = {"m": 1.0, "b": 0.3, "a": 2.0, "c": 0.5}


@pytest.mark.parametrize("exact", [True, False])
@pytest.mark.parametrize("guess, q, verdict", [(-1.7, -2.0, "stable"), (0.2, 0.0, "unstable"),
                                               (1.6, 2.0, "stable")])
def test_duffing_three_equilibria(exact, guess, q, verdict):
    """-a q + c q^3 = 0: q = 0 (stiffness -a) and +-sqrt(a/c) = +-2 (stiffness 2a)."""
    eq = duffing().equilibrium(DUFF, {"F": 0.0}, guess={"q_k": guess}, exact=exact)
    assert eq.states["q_k"] == pytest.approx(q, abs=1e-10)
    assert eq.method == ("exact" if exact else "numeric")
    assert eq.stability == verdict
    k = -DUFF["a"] + 3 * DUFF["c"] * q ** 2
    roots = np.sort_complex(np.roots([1.0, DUFF["b"] / DUFF["m"], k / DUFF["m"]]).astype(complex))
    assert np.allclose(np.sort_complex(np.array(eq.eigenvalues)), roots, rtol=1e-8, atol=1e-12)


def spring(law, name="spring"):
    gr = bg.BondGraph(name)
    v = bg.One("v")
    gr.add(bg.Se("F"), v, bg.I("m"), bg.R("b"), bg.C("k", law=law))
    for t, h in [("F", v), (v, "m"), (v, "b"), (v, "k")]:
        gr.connect(t, h)
    return bg.derive(gr)


@pytest.mark.parametrize("load", [0.5, 0.9, 0.999])
def test_saturating_spring_at_a_loaded_point(load):
    """e = Fs tanh(q/qs): q = qs atanh(F/Fs); stiffness (Fs/qs)(1 - (F/Fs)^2)."""
    Fs, qs = sympy.symbols("Fs qs", positive=True)
    vals = {"m": 2.0, "b": 0.5, "Fs": 40.0, "qs": 0.02}
    F = load * vals["Fs"]
    eq = spring(Fs * sympy.tanh(bg.q / qs)).equilibrium(vals, {"F": F})
    assert eq.states["q_k"] == pytest.approx(vals["qs"] * math.atanh(load), rel=1e-9)
    kd = vals["Fs"] / vals["qs"] * (1 - load ** 2)
    roots = np.roots([1.0, vals["b"] / vals["m"], kd / vals["m"]]).astype(complex)
    assert np.allclose(np.sort_complex(np.array(eq.eigenvalues)), np.sort_complex(roots),
                       rtol=1e-6)


@pytest.mark.parametrize("F", [1e4, 1e15])
def test_exponential_spring_and_the_homotopy(F):
    """e = a (exp(q/q0) - 1): q = q0 ln(1 + F/a), far from the start q = 0; at F = 1e15
    Newton and Levenberg-Marquardt from q = 0 both fail, the homotopy in F finds it."""
    a, q0 = sympy.symbols("a q0", positive=True)
    vals = {"m": 1.0, "b": 1.0, "a": 1e-3, "q0": 0.01}
    eq = spring(a * (sympy.exp(bg.q / q0) - 1)).equilibrium(vals, {"F": F})
    assert eq.states["q_k"] == pytest.approx(0.01 * math.log1p(F / 1e-3), rel=1e-9)
    if F > 1e12:
        assert eq.how.startswith("homotopy in the inputs")


@pytest.mark.parametrize("law", [
    lambda k: sympy.Piecewise((k * bg.q, bg.q > 0), (0, True)),
    lambda k: k * bg.q * sympy.Heaviside(bg.q),
    lambda k: sympy.Max(0, k * bg.q) + sympy.Min(0, 0 * bg.q)],
    ids=["Piecewise", "Heaviside", "Max-Min"])
def test_one_sided_spring(law):
    """A contact spring pushed with F: q = F/k; the derivative of the jump is handled."""
    k = sympy.Symbol("k", positive=True)
    eq = spring(law(k), "contact").equilibrium({"m": 1.0, "b": 1.0, "k": 1e5}, {"F": 50.0},
                                               guess={"q_k": 1e-4})
    assert eq.states["q_k"] == pytest.approx(5e-4, rel=1e-9)
    assert eq.stability == "stable"


def test_unevaluable_jacobian_falls_back_to_finite_differences():
    """d floor(q)/dq stays a sympy Derivative: finite differences, and the result says so."""
    eq = spring(bg.q + sympy.floor(bg.q) / 10, "stepped").equilibrium(
        {"m": 1.0, "b": 1.0}, {"F": 2.5}, guess={"q_k": 2.1})
    assert eq.states["q_k"] == pytest.approx(2.3, rel=1e-12)     # 2.3 + floor(2.3)/10 = 2.5
    assert eq.jacobian == "finite differences"
    roots = np.roots([1.0, 1.0, 1.0]).astype(complex)          # m = b = 1, stiffness 1
    assert np.allclose(np.sort_complex(np.array(eq.eigenvalues)), np.sort_complex(roots),
                       rtol=1e-5)


def test_the_failure_names_residual_state_and_methods():
    """A free mass under a constant force has no equilibrium."""
    gr = bg.BondGraph("free")
    v = bg.One("v")
    gr.add(bg.Se("F"), v, bg.I("m"), bg.C("k", law=bg.q ** 2))
    for t, h in [("F", v), (v, "m"), (v, "k")]:
        gr.connect(t, h)
    with pytest.raises(EquilibriumError) as info:
        bg.derive(gr).equilibrium({"m": 1.0}, {"F": -1.0})      # q^2 = -1: none
    text = str(info.value)
    assert "dp_m/dt" in text and "scaled residual" in text
    assert "hybr" in text and "homotopy" in text and "starts" in text


def test_a_fixed_free_position_is_marginally_stable():
    """A damped mass with its position as a state: eigenvalues -b/m and 0."""
    gr = bg.BondGraph("slide")
    v = bg.One("v")
    gr.add(bg.Se("F"), v, bg.I("m"), bg.R("b"))
    for t, h in [("F", v), (v, "m"), (v, "b")]:
        gr.connect(t, h)
    m = bg.derive(gr, outputs={"x": bg.displacement("m")})
    eq = m.equilibrium({"m": 2.0, "b": 0.5}, {"F": 0.0}, fixed={"x": 1.25})
    assert eq.states == {"p_m": 0.0, "x": 1.25}
    assert eq.stability == "marginal"
    assert np.allclose(np.sort_complex(np.array(eq.eigenvalues)), [-0.25, 0.0], atol=1e-12)


def test_result_pickles_with_its_diagnostics():
    eq = duffing().equilibrium(DUFF, {"F": 0.0}, guess={"q_k": 1.0})
    back = pickle.loads(pickle.dumps(eq))
    assert back == eq and back.eigenvalues == eq.eigenvalues and back.how == eq.how


HYD_FILE = '''
import sympy
import bondgraph as bg

def model():
    Kv = sympy.Symbol("Kv", positive=True)
    g = bg.BondGraph("hydraulic")
    hose, pipe, acc = bg.Zero("hose"), bg.One("pipe"), bg.Zero("acc")
    g.add(bg.Sf("Q"), hose, bg.C("Ch"), pipe, bg.I("Lp"), bg.R("Rp"), acc, bg.C("Ca"),
          bg.R("orifice", inverse=Kv * sympy.sign(bg.e) * sympy.sqrt(abs(bg.e))))
    for t, h in [("Q", hose), (hose, "Ch"), (hose, pipe), (pipe, "Lp"), (pipe, "Rp"),
                 (pipe, acc), (acc, "Ca"), (acc, "orifice")]:
        g.connect(t, h)
    return bg.ModelDefinition(g, outputs={"p_acc": bg.effort("Ca")},
                              parameters={"Ch": 8.3e-14, "Lp": 2.165e7, "Rp": 2.44e8,
                                          "Ca": 4.1e-11, "Kv": 3.395e-8})
'''


def test_cli_export_trim_of_the_si_hydraulic_circuit(tmp_path, monkeypatch, capsys):
    """``bondgraph export --trim`` (it crashed with NameError: DiracDelta) gives the hand A."""
    import json

    from bondgraph.cli import main

    (tmp_path / "hyd.py").write_text(HYD_FILE)
    monkeypatch.chdir(tmp_path)
    status = main(["export", "hyd.py", "--trim", "--input-value", "Q=1e-4", "-o", "plant.json"])
    err = capsys.readouterr().err
    assert status == 0, err
    assert "operating point trim (numeric, stable; scipy.optimize.root" in err
    data = json.loads((tmp_path / "plant.json").read_text())
    assert np.allclose(np.array(data["A"], dtype=float), hand_hydraulic_jacobian(SI, Q_SI),
                       rtol=1e-9, atol=0)


def test_equilibrium_where_the_jacobian_is_not_finite():
    """No pump flow: the accumulator empties through the orifice, q_Ca = 0 exactly, where
    sqrt has an infinite slope; the point is returned and says that df/dx does not exist
    there (it was reported as "not isolated" before)."""
    g = bg.BondGraph("tank")
    a = bg.Zero("a")
    g.add(bg.Sf("Q"), a, bg.C("Ca"), bg.R("orifice", inverse=KV * sympy.sqrt(bg.e)))
    for t, h in [("Q", a), (a, "Ca"), (a, "orifice")]:
        g.connect(t, h)
    eq = bg.derive(g).equilibrium({"Ca": 0.25, "Kv": 0.5}, {"Q": 0.0})
    assert eq.states["q_Ca"] == 0.0
    assert eq.stability == "unknown" and "not finite" in eq.how and eq.eigenvalues == ()
