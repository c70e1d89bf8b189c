"""The bicausal bond graph of an inversion against transfer functions derived by hand.

Inverting a pair puts the storage elements between the source and the sensor
in derivative causality (one differentiation of the trajectory each: their
number is the relative degree) and leaves the others integral (the zero
dynamics: their number is the number of finite zeros).  Expected values by
Newton and Kirchhoff:

* mass and spring on one 1-junction, force to velocity: ``v/F = s/(m s^2 + k)``,
  relative degree 1, one zero: ``m`` differentiates, ``q_k`` is the zero dynamics;
* two masses and a spring, force on ``m1``: ``v2/F = k/(s (m1 m2 s^2 + k (m1 + m2)))``
  (relative degree 3, no zeros: every element differentiates);
  ``v1/F = (m2 s^2 + k)/(s (m1 m2 s^2 + k (m1 + m2)))`` (relative degree 1, two zeros:
  ``m1`` differentiates, ``k`` and ``m2`` are the zero dynamics);
* a DC motor, voltage to speed: ``w/V = K/((L s + R)(J s + b) + K^2)``, relative
  degree 2, no zeros: ``L`` and ``J`` differentiate; on the bonds from the
  sensor to the source effort and flow travel together (bicausal);
* a capacitor no source reaches cannot be set: no bicausal assignment.
"""

from __future__ import annotations

import pytest

import bondgraph as bg
from bondgraph.structure import StructureError, bicausal_graph


def two_masses():
    g = bg.BondGraph("two_masses")
    v1, v2, s = bg.One("v1"), bg.One("v2"), bg.Zero("s")
    g.add(bg.Se("F"), v1, v2, s, bg.I("m1"), bg.I("m2"), bg.C("k", stiffness="k"))
    for t, h in [("F", v1), (v1, "m1"), (v1, s), (s, "k"), (s, v2), (v2, "m2")]:
        g.connect(t, h)
    return g


def dc_motor():
    g = bg.BondGraph("dc_motor")
    e, m = bg.One("e"), bg.One("w")
    g.add(bg.Se("V"), e, bg.R("Ra"), bg.I("La"), bg.GY("K"), m, bg.I("J"), bg.R("b"))
    for t, h in [("V", e), (e, "Ra"), (e, "La"), (e, "K"), ("K", m), (m, "J"), (m, "b")]:
        g.connect(t, h)
    return g


def test_mass_spring_velocity():
    g = bg.BondGraph("ms")
    v = bg.One("v")
    g.add(bg.Se("F"), v, bg.I("m"), bg.C("k"))
    for a, b in [("F", v), (v, "m"), (v, "k")]:
        g.connect(a, b)
    bc = bicausal_graph(bg.derive(g, outputs={"vel": bg.flow("m")}), signal=bg.flow("m"))
    assert bc.derivative == ("I:m",) and bc.zero_dynamics == ("q_k",)
    # the source is a double sensor: effort and flow of its bond both go into F
    (src,) = [st for st in bc.strokes if "F" in st[1:3]]
    assert src[3] == src[4] == "F"


def test_two_masses_far_and_near_sensor():
    far = bicausal_graph(bg.derive(two_masses(), outputs={"v2": bg.flow("m2")}))
    assert sorted(far.derivative) == ["C:k", "I:m1", "I:m2"] and far.zero_dynamics == ()
    near = bicausal_graph(bg.derive(two_masses(), outputs={"v1": bg.flow("m1")}))
    assert near.derivative == ("I:m1",)
    assert sorted(near.zero_dynamics) == ["p_m2", "q_k"]


def test_dc_motor_speed_from_voltage():
    model = bg.derive(dc_motor(), outputs={"w": bg.flow("J")})
    bc = bicausal_graph(model, signal=bg.flow("J"))
    assert sorted(bc.derivative) == ["I:J", "I:La"] and bc.zero_dynamics == ()
    both = {st[0]: st for st in bc.strokes if st[3] == st[4]}
    assert set(bc.bicausal_bonds) == set(both)
    # the source's bond and the sensor's bond are bicausal
    assert any(st[3] == "V" for st in both.values())
    assert any(st[3] == st[4] and st[3].startswith("f_w") for st in both.values())
    text = str(bc)
    assert "SS:V receives effort and flow" in text and "bicausal" in text


def test_a_pair_the_input_cannot_set_is_refused():
    g = bg.BondGraph("rc_branch")
    a, b = bg.Zero("a"), bg.One("b")
    g.add(bg.Sf("i"), a, bg.R("R1"), bg.C("C1"), b, bg.C("C2"), bg.R("R2"))
    for x, y in [("i", a), (a, "R1"), (a, "C1"), (b, "C2"), (b, "R2")]:
        g.connect(x, y)
    model = bg.derive(g, outputs={"v2": bg.effort("C2")})
    with pytest.raises(StructureError, match="no bicausal assignment"):
        bicausal_graph(model, signal=bg.effort("C2"))
    with pytest.raises(StructureError, match="not proportional to one"):
        bicausal_graph(model, signal=bg.effort("C2") + bg.effort("C1"))


def test_srv02_hub_speed():
    # the hub (models/srv02.py): Kirchhoff and Newton give w_l/e_in = eta Kg kt /
    # ((Lm s + Rm)(Jeq s + Beq) + ...): two storage elements, relative degree 2, no zeros;
    # without the inductance one storage element, relative degree 1
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "models"))
    import srv02

    omega = srv02.outputs()["omega"]
    for inductance, expected in ((True, ["I:Jm", "I:Lm"]), (False, ["I:Jm"])):
        model = bg.derive(srv02.build(inductance=inductance), outputs={"omega": omega})
        bc = bicausal_graph(model, signal=omega)
        assert sorted(bc.derivative) == expected and bc.zero_dynamics == ()
        # the gear and the motor's gyrator carry effort and flow together
        ends = {st[3] for st in bc.strokes if st[0] in bc.bicausal_bonds}
        assert {"e_in", "km", "gear"} <= ends
