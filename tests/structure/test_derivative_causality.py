"""Sueur and Dauphin-Tanguy's bond-graph ranks against matrices written by hand.

For each model the state equations are written here from the physics
(Newton, Kirchhoff), the matrices ``[A B]`` / ``[A; C]`` built from them and
their rank taken by sympy at symbolic parameters; the engine's rank must come
from the bond graph in derivative causality (dualised sources / detectors),
and the storage element that stays integral must be named with the junction
where its derivative causality conflicts:

* two capacitors in series on a 1-junction driven by a current ``i``:
  ``q1' = i``, ``q2' = i``, ``A = 0``, ``B = [1, 1]^T``: rank 1;
* an RC branch no source reaches: ``A = diag(-1/(R1 C1), -1/(R2 C2))``,
  ``B = [1, 0]^T``: rank 2 (the rank is full; the missing causal path makes
  ``q_C2`` uncontrollable, a different reason);
* two capacitors in series across an ideal voltage source ``E``: the charge
  is ``q1 = E C1 C2/(C1 + C2)``, so ``q1' = (C1 C2/(C1 + C2)) E'``: ``A = 0``,
  ``B = 0`` (the source enters through its derivative only): rank 0;
* two free masses and a spring, force on ``m1``: states ``p1, q, p2``,
  ``p1' = F - k q``, ``q' = p1/m1 - p2/m2``, ``p2' = k q``; ``[A B]`` has rank 3;
  with the spring force ``k q`` (or its stretch ``q``) measured, ``[A; C]`` has
  rank 2 (the rigid-body motion is not seen), with the velocity of ``m2``
  measured rank 3.
"""

from __future__ import annotations

import pytest
import sympy

import bondgraph as bg
from bondgraph.structure import (StructureError, controllability, derivative_causality,
                                 observability)


def _rank(rows) -> int:
    return sympy.Matrix(rows).rank(simplify=True)


def series_c():
    g = bg.BondGraph("series_c")
    j = bg.One("j")
    g.add(bg.Sf("i"), j, bg.C("C1"), bg.C("C2"), bg.R("R"))
    for t, h in [("i", j), (j, "C1"), (j, "C2"), (j, "R")]:
        g.connect(t, h)
    return g


def rc_branch():
    g = bg.BondGraph("rc_branch")
    a, b = bg.Zero("a"), bg.One("b")
    g.add(bg.Sf("i"), a, bg.R("R1"), bg.C("C1"), b, bg.C("C2"), bg.R("R2"))
    for t, h in [("i", a), (a, "R1"), (a, "C1"), (b, "C2"), (b, "R2")]:
        g.connect(t, h)
    return g


def series_c_on_source():
    g = bg.BondGraph("divider")
    o = bg.One("o")
    g.add(bg.Se("E"), o, bg.C("C1"), bg.C("C2"))
    for t, h in [("E", o), (o, "C1"), (o, "C2")]:
        g.connect(t, h)
    return g


def two_masses():
    g = bg.BondGraph("two_masses")
    v1, v2, s = bg.One("v1"), bg.One("v2"), bg.Zero("s")
    g.add(bg.Se("F"), v1, v2, s, bg.I("m1"), bg.I("m2"), bg.C("k", stiffness="k"))
    for t, h in [("F", v1), (v1, "m1"), (v1, s), (s, "k"), (s, v2), (v2, "m2")]:
        g.connect(t, h)
    return g


def test_series_capacitors_lose_one_rank_at_their_junction():
    expected = _rank([[0, 0, 1], [0, 0, 1]])                    # [A B], A = 0, B = [1, 1]^T
    res = controllability(bg.derive(series_c()))
    assert res.graph_rank == expected == 1
    g = res.graph
    assert g.applicable and len(g.integral) == 1 and g.integral[0] in ("q_C1", "q_C2")
    assert g.junctions == ("j",)
    assert g.dualised == ("SS:i",)
    state = g.integral[0]
    assert "conflicts at the junction j" in res.reason(state)
    assert "rank lost at j" in str(g)


def test_unreached_branch_has_full_graph_rank_but_no_causal_path():
    R1, C1, R2, C2 = sympy.symbols("R1 C1 R2 C2", positive=True)
    expected = _rank([[-1 / (R1 * C1), 0, 1], [0, -1 / (R2 * C2), 0]])
    res = controllability(bg.derive(rc_branch()))
    assert res.graph_rank == expected == 2
    assert res.graph.integral == ()
    assert res.unreached == ("q_C2",)


def test_capacitors_across_a_voltage_source_have_rank_zero():
    # one state (the two capacitors are not independent); only E' drives it: A = 0, B = 0
    model = bg.derive(series_c_on_source())
    assert len(model.states) == 1
    expected = _rank([[0, 0]])
    res = controllability(model)
    assert res.graph_rank == expected == 0
    # the element in derivative causality in the model stays integral here: it counts
    assert len(res.graph.integral) == 1 and res.graph.junctions == ("o",)


def test_two_masses_controllable_rank_and_observability_by_detectors():
    m1, m2, k = sympy.symbols("m1 m2 k", positive=True)
    A = [[0, -k, 0], [1 / m1, 0, -1 / m2], [0, k, 0]]
    AB = [row + [b] for row, b in zip(A, [1, 0, 0])]
    assert _rank(AB) == 3
    res = controllability(bg.derive(two_masses()))
    assert res.graph_rank == 3 and res.graph.integral == ()
    # the spring force k*q: [A; C] of rank 2
    force = {"Fk": bg.effort("k")}
    assert _rank(A + [[0, k, 0]]) == 2
    obs = observability(bg.derive(two_masses(), outputs=force), detectors=force)
    assert obs.graph_rank == 2 and obs.generic_rank == 2
    assert obs.graph.dualised == ("SS:Fk",)
    (stuck,) = obs.graph.integral
    assert stuck in ("p_m1", "p_m2")
    assert obs.graph.junctions[0] in ("v1", "v2", "s", "e_Fk")
    # the velocity of m2: rank 3
    vel = {"v2": bg.flow("m2")}
    assert _rank(A + [[0, 0, 1 / m2]]) == 3
    obs = observability(bg.derive(two_masses(), outputs=vel), detectors=vel)
    assert obs.graph_rank == 3
    # the spring's own displacement q = F_k/k: the detector sits on its effort, rank 2
    stretch = {"xk": bg.displacement("k")}
    assert _rank(A + [[0, 1, 0]]) == 2
    obs = observability(bg.derive(two_masses(), outputs=stretch), detectors=stretch)
    assert obs.graph_rank == 2 and obs.graph.dualised == ("SS:xk",)
    # the position of a mass is an integrator outside the bond graph: not covered
    pos = {"x2": bg.displacement("m2")}
    obs = observability(bg.derive(two_masses(), outputs=pos), detectors=pos)
    assert obs.graph_rank is None and "not proportional" in obs.graph.why
    # found without detectors= on a small graph: the same detector bond
    auto = derivative_causality(bg.derive(two_masses(), outputs=force), kind="observability")
    assert auto.rank == 2


def test_outputs_the_graph_method_does_not_cover_are_named():
    out = {"y": bg.effort("k") + bg.flow("m2")}
    obs = observability(bg.derive(two_masses(), outputs=out), detectors=out)
    assert obs.graph_rank is None and not obs.graph.applicable
    assert "not proportional to one effort or flow" in obs.graph.why
    assert "not applicable" in str(obs)


def test_bad_arguments_name_the_culprit():
    model = bg.derive(two_masses(), outputs={"v2": bg.flow("m2")})
    with pytest.raises(StructureError, match="kind"):
        derivative_causality(model, kind="both")
    with pytest.raises(StructureError, match="no output 'x'"):
        derivative_causality(model, kind="observability", signals=["x"])
    with pytest.raises(StructureError, match="no signal given for output 'v2'"):
        derivative_causality(model, kind="observability", detectors={})
    with pytest.raises(StructureError, match="names no element"):
        derivative_causality(model, kind="observability", detectors={"v2": bg.flow("nope")})


def test_the_derivative_causality_graph_is_drawable():
    res = controllability(bg.derive(series_c()))
    svg = res.draw()
    assert "SS:i" in svg and 'class="stroke"' in svg
