"""Fault signatures of the two-tank system, derived by hand, and residuals on simulated data.

Two tanks (capacities C1, C2) fed by a pump ``Qp`` into tank 1, a pipe ``R12``
between them and an outlet valve ``R2``; sensors: the pressures (levels)
``De1``, ``De2`` and the outlet flow ``Df``.  By mass balance, with the
measurements in place of the unknowns (the detectors in derivative causality):

    ARR from the outlet sensor: Df - De2/R2 = 0
    ARR from tank 1:  Qp - (De1 - De2)/R12 - C1 De1' = 0
    ARR from tank 2:  (De1 - De2)/R12 - De2/R2 - C2 De2' = 0

so the signatures (ARR_Df, ARR_1, ARR_2) are: Qp (0,1,0), C1 (0,1,0),
R12 (0,1,1), C2 (0,0,1), R2 (1,0,1), De1 (0,1,1), De2 (1,1,1), Df (1,0,0).
Detectable: all.  Isolable: C2, R2, De2, Df (unique signatures); not: Qp
and C1 (same), R12 and De1 (same).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.integrate
import sympy

import bondgraph as bg
from bondgraph.structure import fault_signatures

t = bg.t


def two_tanks():
    g = bg.BondGraph("two_tanks")
    z1, z2, p = bg.Zero("z1"), bg.Zero("z2"), bg.One("p12")
    g.add(bg.Sf("Qp"), z1, z2, p, bg.C("C1"), bg.C("C2"), bg.R("R12"), bg.R("R2"))
    for a, b in [("Qp", z1), (z1, "C1"), (z1, p), (p, "R12"), (p, z2), (z2, "C2"), (z2, "R2")]:
        g.connect(a, b)
    return bg.derive(g, outputs={"De1": bg.effort("z1"), "De2": bg.effort("z2"),
                                 "Df": bg.flow("R2")})


def test_two_tank_arrs_and_signatures_by_hand():
    fd = fault_signatures(two_tanks())
    C1, C2, R12, R2 = sympy.symbols("C1 C2 R12 R2", positive=True)
    De1, De2, Df, Qp = (sympy.Function(n)(t) for n in ("De1", "De2", "Df", "Qp"))
    hand = {
        "sensor Df": Df - De2 / R2,
        "state q_C1": Qp - (De1 - De2) / R12 - C1 * De1.diff(t),
        "state q_C2": (De1 - De2) / R12 - De2 / R2 - C2 * De2.diff(t),
    }
    got = dict(zip(fd.sources, fd.arrs))
    assert set(got) == set(hand)
    for k, r in hand.items():
        assert sympy.simplify(got[k] - r) == 0 or sympy.simplify(got[k] + r) == 0
    order = [fd.sources.index(k) for k in ("sensor Df", "state q_C1", "state q_C2")]
    want = {"Qp": (0, 1, 0), "C1": (0, 1, 0), "R12": (0, 1, 1), "C2": (0, 0, 1),
            "R2": (1, 0, 1), "De1": (0, 1, 1), "De2": (1, 1, 1), "Df": (1, 0, 0)}
    assert set(fd.components) == set(want)
    for comp, sig in want.items():
        assert tuple(fd.signature(comp)[i] for i in order) == sig
    assert set(fd.detectable) == set(want)
    assert set(fd.isolable) == {"C2", "R2", "De2", "Df"}
    assert fd.unresolved == ()
    assert "ARR" in str(fd)


def test_residuals_flag_a_clogged_outlet_valve():
    fd = fault_signatures(two_tanks())
    vals = {"C1": 2.0, "C2": 1.0, "R12": 0.5, "R2": 1.5}
    T = 20.0
    ts = np.linspace(0, T, 4001)

    def qp(tt):
        return 1.0 + 0.5 * np.sin(0.7 * tt)

    def r2(tt):               # the fault: the valve's resistance doubles at t = 10
        return vals["R2"] * (1.0 if tt < 10.0 else 2.0)

    def rhs(tt, p):           # hand mass balance, pressures p1, p2
        q12 = (p[0] - p[1]) / vals["R12"]
        return [(qp(tt) - q12) / vals["C1"], (q12 - p[1] / r2(tt)) / vals["C2"]]

    sol = scipy.integrate.solve_ivp(rhs, (0, T), [0.0, 0.0], t_eval=ts, rtol=1e-10,
                                    atol=1e-12, max_step=0.01)
    p1, p2 = sol.y
    df = p2 / np.array([r2(tt) for tt in ts])
    res = fd.residuals(ts, {"Qp": qp(ts)}, {"De1": p1, "De2": p2, "Df": df}, vals)
    k = {src: i for i, src in enumerate(fd.sources)}
    before = (ts > 1.0) & (ts < 9.5)
    after = ts > 11.0
    for src in k:
        assert np.max(np.abs(res[k[src], before])) < 1e-3
    assert np.max(np.abs(res[k["state q_C1"], after])) < 1e-3      # R2 is not in ARR 1
    assert np.max(np.abs(res[k["sensor Df"], after])) > 0.05
    assert np.max(np.abs(res[k["state q_C2"], after])) > 0.05


def test_relations_past_the_size_budget_are_refused(monkeypatch):
    """A chain of masses seen through one sensor: its relation grows about fourfold per
    mass; past the budget the analysis stops with a message naming the model."""
    from bondgraph.structure import StructureError, faults

    g = bg.BondGraph("chain4")
    g.add(bg.Se("F"))
    for i in range(4):
        g.add(bg.One(f"v{i}"), bg.I(f"m{i}"), bg.R(f"b{i}"))
        g.connect(f"v{i}", f"m{i}")
        g.connect(f"v{i}", f"b{i}")
        if i == 0:
            g.connect("F", "v0")
        else:
            g.add(bg.Zero(f"s{i}"), bg.C(f"k{i}"))
            g.connect(f"v{i - 1}", f"s{i}")
            g.connect(f"s{i}", f"k{i}")
            g.connect(f"s{i}", f"v{i}")
    model = bg.derive(g, outputs={"v": bg.flow("m3")})
    monkeypatch.setattr(faults, "FAULT_SIZE_BUDGET", 200)
    with pytest.raises(StructureError, match="'chain4'.*FAULT_SIZE_BUDGET"):
        fault_signatures(model)
