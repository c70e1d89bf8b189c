"""Linear analysis of a model with a constant source (gravity) about its operating point.

Hand derivation, written here.  A mass ``m`` on a spring ``k`` and a damper
``b``, pushed up by the input force ``F`` and pulled down by its weight ``W``
(a constant source).  Sign convention: ``v`` is the mass's upward velocity,
``x`` (the spring's displacement ``q_k``) its upward displacement from where
the unloaded spring holds it; the weight's bond points from the 1-junction
into ``Se:weight``, so gravity absorbs the power ``W v`` when the mass rises.
Newton: ``m x'' = F - W - b x' - k x``; states ``p_m = m x'``, ``q_k = x``:

    p_m' = F - W - b p_m/m - k q_k,    q_k' = p_m/m.

Equilibrium at ``F = F0``: ``p_m = 0``, ``x0 = (F0 - W)/k``, so without a push
the mass settles ``W/k`` *below* the unloaded position: ``x0 = -W/k``.  In
deviations ``dx = x - x0``, ``dF = F - F0`` the weight cancels:
``m dx'' = dF - b dx' - k dx``, so ``x/F = 1/(m s^2 + b s + k)`` whatever
``W``, with ``A = [[-b/m, -k], [1/m, 0]]``, ``B = [[1], [0]]``, ``C = [[0, 1]]``.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.linear import OperatingPointError

m, b, k, W = sympy.symbols("m b k W", positive=True)
F0 = sympy.Symbol("F0", real=True)          # the nominal input: the input F's assumptions
s = sympy.Symbol("s")
VALUES = {"m": 2.0, "b": 1.5, "k": 100.0, "W": 19.62}


def hanging(weight=W, *, spring: bool = True) -> bg.Model:
    g = bg.BondGraph("hanging")
    v = bg.One("v")
    g.add(bg.Se("F"), bg.Se("weight", value=weight), v, bg.I("m"), bg.R("b"))
    pairs = [("F", v), (v, "weight"), (v, "m"), (v, "b")]
    if spring:
        g.add(bg.C("k", stiffness="k"))
        pairs.append((v, "k"))
    for tail, head in pairs:
        g.connect(tail, head)
    return bg.derive(g, outputs={"x": bg.displacement("k") if spring else bg.displacement("m")})


def same(a, b_) -> bool:
    return sympy.simplify(sympy.sympify(a) - b_) == 0


def test_transfer_function_whatever_the_weight():
    model = hanging()
    G = model.transfer_function("F", "x")
    assert same(G.expr, 1 / (m * s**2 + b * s + k))
    assert same(hanging(weight=0).transfer_function("F", "x").expr, G.expr)
    # the default point is at the nominal input F0 (a symbol)
    op = G.operating_point
    assert same(op.states["q_k"], (F0 - W) / k) and op.states["p_m"] == 0
    assert op.inputs["F"].name == "F0"
    assert "deviations about the operating point" in op.note


def test_equilibrium_hangs_below_the_unloaded_spring():
    model = hanging()
    op = model.operating_point({"F": 0})
    assert same(op.states["q_k"], -W / k)
    assert same(op.outputs["x"], -W / k)
    eq = model.equilibrium(VALUES)                      # numeric: the same point
    assert eq.states["q_k"] == pytest.approx(-19.62 / 100.0, rel=1e-12)
    assert eq.stability == "stable"


def test_state_space_and_linearize_in_deviations():
    model = hanging()
    A = sympy.Matrix([[-b / m, -k], [1 / m, 0]])
    ss = model.state_space()
    assert ss.A == A and ss.B == sympy.Matrix([[1], [0]]) and ss.C == sympy.Matrix([[0, 1]])
    assert same(ss.operating_point.states["q_k"], (F0 - W) / k)
    lin = model.linearize(u0={"F": 0})                  # the point solved, not given
    assert lin.A == A and same(lin.operating_point.states["q_k"], -W / k)
    at = model.state_space(at={"F": 3})
    assert at.A == A and same(at.operating_point.states["q_k"], (3 - W) / k)
    assert model.is_linear is False                     # the model itself has the offset


def test_plant_exists_with_its_operating_point():
    model = hanging()
    plant = bg.compile_plant(model).plant(VALUES)
    mv, bv, kv, Wv = (VALUES[n] for n in ("m", "b", "k", "W"))
    np.testing.assert_allclose(plant.A, [[-bv / mv, -kv], [1 / mv, 0.0]], rtol=1e-15)
    np.testing.assert_allclose(plant.B, [[1.0], [0.0]])
    op = plant.operating_point
    assert op.states == {"p_m": pytest.approx(0.0, abs=1e-14 * Wv),
                         "q_k": pytest.approx(-Wv / kv, rel=1e-14)}
    assert op.inputs == {"F": 0.0} and op.outputs["x"] == pytest.approx(-Wv / kv, rel=1e-14)
    w = np.array([0.0, 3.0, 50.0])
    H = plant.frequency_response(w)[:, 0, 0]
    np.testing.assert_allclose(H, 1 / (kv - mv * w**2 + 1j * bv * w), rtol=1e-12)
    # the numeric linearization at a pushed equilibrium: same matrices, its own point
    lin = model.linearize(values=VALUES, u0={"F": 5.0})
    np.testing.assert_allclose(lin.A, plant.A, rtol=1e-12)
    assert lin.operating_point.states["q_k"] == pytest.approx((5.0 - Wv) / kv, rel=1e-12)
    # a batch evaluates the same matrices
    batch = bg.compile_plant(model).batch({**VALUES, "k": [100.0, 400.0]})
    np.testing.assert_allclose(batch.A[1], [[-bv / mv, -400.0], [1 / mv, 0.0]])


def test_no_equilibrium_is_refused_clearly():
    # without the spring the mass sinks at the speed W/b for ever: no isolated equilibrium
    model = hanging(spring=False)
    with pytest.raises(bg.NonlinearModelError, match="not isolated"):
        model.transfer_function("F", "x")
    with pytest.raises(bg.ParameterValueError, match="no isolated equilibrium"):
        bg.compile_plant(model).plant({"m": 1.0, "b": 1.0, "W": 9.81})
    with pytest.raises(OperatingPointError, match="input 'G'"):
        hanging().operating_point({"G": 1.0})


def test_nonlinear_in_the_states_needs_a_point():
    # a cubic spring under gravity: no automatic point (several equilibria in general)
    g = bg.BondGraph("cubic")
    v = bg.One("v")
    g.add(bg.Se("F"), bg.Se("weight", value=W), v, bg.I("m"), bg.R("b"),
          bg.C("k", law=k * bg.q**3))
    for tail, head in [("F", v), (v, "weight"), (v, "m"), (v, "b"), (v, "k")]:
        g.connect(tail, head)
    model = bg.derive(g, outputs={"x": bg.displacement("k")})
    with pytest.raises(bg.NonlinearModelError, match="at="):
        model.transfer_function("F", "x")
    # at the point x0 = -(W/k)^(1/3) with F0 = 0: spring slope 3 k x0^2
    x0 = -sympy.cbrt(W / k)
    G = model.transfer_function("F", "x", at={"F": 0, "q_k": x0, "p_m": 0})
    assert same(G.expr, 1 / (m * s**2 + b * s + 3 * k * x0**2))


def test_structural_analysis_takes_the_deviation_form():
    # [B, A B] = [[1, -b/m], [0, 1/m]] and [C; C A] = [[0, 1], [1/m, 0]]: both rank 2
    from bondgraph import structure

    model = hanging()
    assert structure.controllability(model).kalman_rank == 2
    assert structure.observability(model).kalman_rank == 2
