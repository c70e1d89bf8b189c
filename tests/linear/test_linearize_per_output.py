"""Linearization per output: improper outputs kept as ``D_derivatives``, proper ones exact.

The model: a pump (flow source ``Q``) pushing through a pipe (inertance
``Lp``, resistance ``Rp``) into an accumulator ``Ca`` drained by a square-root
orifice.  The pipe's inertance sees the imposed flow (derivative causality):
the pump pressure ``p_pump = Lp dQ/dt + Rp Q + q_Ca/Ca`` needs ``dQ/dt``; the
accumulator pressure and the orifice flow do not.  By hand at ``Q0``:
``pa = (Q0/Kv)^2``; ``A = -g/Ca``, ``B = 1`` with the orifice slope
``g = Kv/(2 sqrt(pa)) = Kv^2/(2 Q0)``; ``C = [1/Ca, 1/Ca, g/Ca]``,
``D = [Rp, 0, 0]``, ``D_derivatives[0] = [Lp, 0, 0]``.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy

import bondgraph as bg

KV = sympy.Symbol("Kv", positive=True)
VALS = {"Lp": 2.165e7, "Rp": 2.44e8, "Ca": 4.1e-11, "Kv": 3.395e-8}
Q0 = 1e-4


def pump_model() -> bg.Model:
    g = bg.BondGraph("pump")
    pipe, acc = bg.One("pipe"), bg.Zero("acc")
    g.add(bg.Sf("Q"), pipe, bg.I("Lp"), bg.R("Rp"), acc, bg.C("Ca"),
          bg.R("orifice", inverse=KV * sympy.sign(bg.e) * sympy.sqrt(abs(bg.e))))
    for t, h in [("Q", pipe), (pipe, "Lp"), (pipe, "Rp"), (pipe, acc), (acc, "Ca"),
                 (acc, "orifice")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"p_pump": bg.effort("Q"), "p_acc": bg.effort("Ca"),
                                 "Q_out": bg.flow("orifice")})


@pytest.fixture(scope="module")
def model():
    return pump_model()


def test_numeric_linearization_keeps_the_improper_output(model):
    assert model.state_names == ("q_Ca",)
    eq = model.equilibrium(VALS, {"Q": Q0})
    pa = (Q0 / VALS["Kv"]) ** 2
    assert eq.states["q_Ca"] == pytest.approx(VALS["Ca"] * pa, rel=1e-10)
    plant = model.linearize(eq)
    g = VALS["Kv"] ** 2 / (2 * Q0)
    Ca = VALS["Ca"]
    assert np.asarray(plant.A) == pytest.approx(np.array([[-g / Ca]]), rel=1e-9)
    assert np.asarray(plant.B) == pytest.approx(np.array([[1.0]]), rel=1e-12)
    assert np.asarray(plant.C) == pytest.approx(np.array([[1 / Ca], [1 / Ca], [g / Ca]]), rel=1e-9)
    assert np.asarray(plant.D) == pytest.approx(np.array([[VALS["Rp"]], [0.0], [0.0]]), rel=1e-12)
    assert len(plant.D_derivatives) == 1
    assert np.asarray(plant.D_derivatives[0]) == pytest.approx(np.array([[VALS["Lp"]], [0], [0]]))
    assert not plant.is_proper
    # the frequency response holds the s Lp term: p_pump/Q(jw) = Rp + jw Lp + 1/(Ca (jw + g/Ca))
    w = 3.0
    H = plant.frequency_response([w])
    expected = VALS["Rp"] + 1j * w * VALS["Lp"] + 1 / (Ca * (1j * w + g / Ca))
    assert complex(np.asarray(H).reshape(-1)[0]) == pytest.approx(expected, rel=1e-9)


def test_to_control_still_refuses_the_improper_plant(model):
    plant = model.linearize(model.equilibrium(VALS, {"Q": Q0}))
    with pytest.raises(bg.numeric.ImproperPlantError, match="D_derivatives"):
        plant.to_control()


def test_symbolic_linearization_per_output(model):
    Lp, Rp, Ca = sympy.symbols("Lp Rp Ca", positive=True)
    qa = sympy.Symbol("qa", positive=True)
    lin = model.linearize({"q_Ca": qa}, {"Q": KV * sympy.sqrt(qa / Ca)})
    assert lin.D == sympy.ImmutableMatrix([[Rp], [0], [0]])
    assert lin.D_derivatives == (sympy.ImmutableMatrix([[Lp], [0], [0]]),)
    g = KV / (2 * sympy.sqrt(qa / Ca))
    assert sympy.simplify(lin.A[0, 0] + g / Ca) == 0
    assert all(sympy.simplify(c - h) == 0 for c, h in zip(lin.C, [1 / Ca, 1 / Ca, g / Ca]))
    sub = lin.subs({"Lp": 2.0})
    assert sub.D_derivatives == (sympy.ImmutableMatrix([[2], [0], [0]]),)
    assert "D_derivatives[0]" in str(lin)


def test_state_equations_with_input_derivatives_are_still_refused():
    """x' = -a x + u' (a hand-built model): the state equation itself needs du/dt, so
    there is no (A, B); outputs alone may need input derivatives, state equations not."""
    from bondgraph.model import Model

    x, u, du = (sympy.Symbol(n, real=True) for n in ("x", "u", "du/dt"))
    a = sympy.Symbol("a", positive=True)
    m = Model(name="hand", augmented=None, states=(x,), inputs=(u,), output_names=("y",),
              rhs=(-a * x + du,), output_exprs=(x,), input_derivatives=(du,), descriptor=None,
              storage_states=1)
    with pytest.raises(bg.NonlinearModelError, match="du/dt.*cannot be linearized"):
        m.linearize({"x": 0}, {"u": 0})
    proper = Model(name="hand2", augmented=None, states=(x,), inputs=(u,),
                   output_names=("y", "z"), rhs=(-a * x + u,), output_exprs=(x, x + a * du),
                   input_derivatives=(du,), descriptor=None, storage_states=1)
    lin = proper.linearize({"x": 0}, {"u": 0})
    assert lin.D_derivatives == (sympy.ImmutableMatrix([[0], [a]]),)
    assert lin.A == sympy.ImmutableMatrix([[-a]]) and lin.C == sympy.ImmutableMatrix([[1], [1]])


PUMP_FILE = '''
import sympy
import bondgraph as bg

def model():
    Kv = sympy.Symbol("Kv", positive=True)
    g = bg.BondGraph("pump")
    pipe, acc = bg.One("pipe"), bg.Zero("acc")
    g.add(bg.Sf("Q"), pipe, bg.I("Lp"), bg.R("Rp"), acc, bg.C("Ca"),
          bg.R("orifice", inverse=Kv * sympy.sign(bg.e) * sympy.sqrt(abs(bg.e))))
    for t, h in [("Q", pipe), (pipe, "Lp"), (pipe, "Rp"), (pipe, acc), (acc, "Ca"),
                 (acc, "orifice")]:
        g.connect(t, h)
    return bg.ModelDefinition(g, outputs={"p_pump": bg.effort("Q"), "p_acc": bg.effort("Ca")},
                              parameters={"Lp": 2.0, "Rp": 3.0, "Ca": 0.5, "Kv": 1.0})
'''


def test_cli_tf_at_a_trim_keeps_the_derivative_term(tmp_path, monkeypatch, capsys):
    """Q0 = 1: pa = 1, g = 1/2, so p_pump/Q = Lp s + Rp + (1/Ca)/(s + g/Ca)
    = 2 s + 3 + 2/(s + 1) = (2 s^2 + 5 s + 5)/(s + 1)."""
    from bondgraph.cli import main

    (tmp_path / "pump.py").write_text(PUMP_FILE)
    monkeypatch.chdir(tmp_path)
    status = main(["tf", "pump.py", "--output", "p_pump", "--numeric", "--trim",
                   "--input-value", "Q=1"])
    out, err = capsys.readouterr()
    assert status == 0, err
    lines = [ln.strip() for ln in out.splitlines()]
    assert "2 s^2 + 5 s + 5" in lines and "s + 1" in lines
