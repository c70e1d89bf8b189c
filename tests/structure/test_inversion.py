"""Inversion: the computed input, simulated forward on hand-written ODEs, gives the output.

* DC motor (Kirchhoff and Newton): ``La i' = V - Ra i - K w``, ``J w' = K i - b w``;
  so ``V = La (J w'' + b w')/K + Ra (J w' + b w)/K + K w`` for a speed profile
  ``w(t) = W (1 - cos(pi t/T))/2``.
* SRV-02 hub with armature inductance: ``Lm i' = e - Rm i - km Kg theta'``,
  ``Jm Kg theta'' = eta_m kt i - Beq theta'/(eta_g Kg)``; a smooth (quintic) angle
  step has zero position, speed and acceleration at ``t = 0`` (relative degree 3).
* two masses with a damper beside the spring, sensor on the driven mass: the zeros
  are those of ``m2 s^2 + c s + k`` (stable), so the zero dynamics are integrated.
* the RC lattice ``(1 - R1 C1 R2 C2 s^2)/(...)`` is non-minimum-phase: refused,
  zeros named.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.integrate
import sympy

import bondgraph as bg
from bondgraph.structure import StructureError, invert

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from models import srv02  # noqa: E402

t = bg.t


def dc_motor():
    g = bg.BondGraph("dc_motor")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
    for a, b in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
        g.connect(a, b)
    return bg.derive(g, outputs={"omega": bg.flow("J")})


def test_dc_motor_voltage_for_a_speed_profile():
    W, T = 100.0, 0.5
    traj = W * (1 - sympy.cos(sympy.pi * t / T)) / 2
    inv = invert(dc_motor(), traj)
    assert inv.relative_degree == 2 and inv.zero_dynamics == 0
    Ra, La, K, J, b = sympy.symbols("Ra La K J b", positive=True)
    w = traj
    hand = (La * (J * w.diff(t, 2) + b * w.diff(t)) / K + Ra * (J * w.diff(t) + b * w) / K
            + K * w)
    assert sympy.expand(inv.input_expr - hand) == 0
    vals = {"Ra": 1.2, "La": 0.05, "K": 0.8, "J": 0.01, "b": 0.002}
    V = sympy.lambdify(t, inv.input_expr.subs({sympy.Symbol(k, positive=True): v
                                               for k, v in vals.items()}))

    def rhs(tt, x):
        i, om = x
        return [(V(tt) - vals["Ra"] * i - vals["K"] * om) / vals["La"],
                (vals["K"] * i - vals["b"] * om) / vals["J"]]

    ts = np.linspace(0, T, 51)
    sol = scipy.integrate.solve_ivp(rhs, (0, T), [0.0, 0.0], t_eval=ts, rtol=1e-10, atol=1e-10)
    want = W * (1 - np.cos(np.pi * ts / T)) / 2
    np.testing.assert_allclose(sol.y[1], want, atol=1e-6 * W)
    assert "relative degree 2" in str(inv) and "no zero dynamics" in str(inv)


def test_hub_voltage_for_a_smooth_angle_step():
    m = bg.derive(srv02.build(inductance=True), outputs={"theta": srv02.outputs()["theta"]})
    T, A = 0.3, 1.0
    tau = t / T
    traj = A * (10 * tau**3 - 15 * tau**4 + 6 * tau**5)
    vals = {p.name: srv02.PARAMETERS[p.name] for p in m.parameters}
    inv = invert(m, traj, values=vals)
    assert inv.relative_degree == 3 and inv.zero_dynamics == 0
    ts = np.linspace(0, T, 301)
    u_s = inv.input_at(ts)
    P = srv02.PARAMETERS
    e = scipy.interpolate.CubicSpline(ts, u_s)

    def rhs(tt, x):
        i, w, th = x
        di = (e(tt) - P["Rm"] * i - P["km"] * P["Kg"] * w) / P["Lm"]
        dw = (P["eta_m"] * P["kt"] * i - P["Beq"] * w / (P["eta_g"] * P["Kg"])) / \
            (P["Jm"] * P["Kg"])
        return [di, dw, w]

    sol = scipy.integrate.solve_ivp(rhs, (0, T), [0.0, 0.0, 0.0], t_eval=ts, method="Radau",
                                    rtol=1e-10, atol=1e-12)
    want = A * (10 * (ts / T) ** 3 - 15 * (ts / T) ** 4 + 6 * (ts / T) ** 5)
    np.testing.assert_allclose(sol.y[2], want, atol=1e-5 * A)


def damped_two_masses():
    g = bg.BondGraph("two_masses_damped")
    v1, s, v2 = bg.One("v1"), bg.Zero("s"), bg.One("v2")
    d = bg.One("d")
    g.add(bg.Se("F"), v1, v2, s, d, bg.I("m1"), bg.I("m2"), bg.C("k", stiffness="k"),
          bg.R("c"))
    for a, b in [("F", v1), (v1, "m1"), (v1, s), (s, d), (d, "k"), (d, "c"), (s, v2),
                 (v2, "m2")]:
        g.connect(a, b)
    return bg.derive(g, outputs={"x1": bg.displacement("m1")})


def test_zero_dynamics_are_integrated():
    m = damped_two_masses()
    vals = {"m1": 1.0, "m2": 0.5, "k": 20.0, "c": 0.6}
    T = 2.0
    traj = (1 - sympy.cos(sympy.pi * t / T)) ** 3 / 8
    inv = invert(m, traj, values=vals)
    assert inv.relative_degree == 2 and inv.zero_dynamics == 2 and inv.minimum_phase
    ts = np.linspace(0, T, 2001)
    F = scipy.interpolate.CubicSpline(ts, inv.input_at(ts))

    def rhs(tt, x):       # Newton: m1 x1'' = F - k (x1 - x2) - c (v1 - v2), m2 x2'' = ...
        x1, v1, x2, v2 = x
        f = vals["k"] * (x1 - x2) + vals["c"] * (v1 - v2)
        return [v1, (F(tt) - f) / vals["m1"], v2, f / vals["m2"]]

    sol = scipy.integrate.solve_ivp(rhs, (0, T), [0.0] * 4, t_eval=ts, rtol=1e-10, atol=1e-12)
    want = (1 - np.cos(np.pi * ts / T)) ** 3 / 8
    np.testing.assert_allclose(sol.y[0], want, atol=1e-5)


def test_non_minimum_phase_pair_is_refused_and_named():
    g = bg.BondGraph("lattice")
    n, a, b = bg.Zero("n"), bg.One("a"), bg.One("b")
    g.add(bg.Se("V"), n, a, b, bg.R("R1"), bg.C("C1"), bg.R("R2"), bg.C("C2"))
    for x, y in [("V", n), (n, a), (a, "R1"), (a, "C1"), (n, b), (b, "C2"), (b, "R2")]:
        g.connect(x, y)
    m = bg.derive(g, outputs={"y": bg.effort("C1") - bg.effort("R2")})
    vals = {"R1": 2.0, "C1": 0.5, "R2": 4.0, "C2": 0.25}
    with pytest.raises(StructureError, match=r"non-minimum-phase \(zeros .*1"):
        invert(m, t**2, values=vals)
    inv = invert(m, t**2, values=vals, minimum_phase_part=True)
    assert inv.minimum_phase is False and len(inv.mirrored) == 1
    assert inv.mirrored[0].real == pytest.approx(1.0)
    with pytest.raises(StructureError, match="give values="):
        invert(m, t**2)
