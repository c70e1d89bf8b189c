"""Sub-models: hierarchical names, port joining, reuse."""

import sympy

import bondgraph as bg
from helpers import assert_same_tf, connect_all, s, tf_of


def motor(name="motor", *, K=None):
    g = bg.BondGraph(name)
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K", K), bg.Port("shaft"))
    connect_all(g, [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "shaft")])
    return g


def test_motor_as_submodel_with_load():
    top = bg.BondGraph("servo")
    load = bg.One("load")
    top.add(motor(), load, bg.I("J"), bg.R("b"))
    connect_all(top, [("motor.shaft", load), (load, "J"), (load, "b")])
    m = bg.derive(top, outputs={"omega": bg.flow("J")})
    assert m.state_names == ("p_J", "p_motor.La")
    assert m.input_names == ("motor.V",)
    Ra, La, K = (sympy.Symbol(f"motor.{n}", positive=True) for n in ("Ra", "La", "K"))
    J, b = sympy.symbols("J b", positive=True)
    assert_same_tf(tf_of(m, "motor.V", "omega"), K / ((La * s + Ra) * (J * s + b) + K**2))
    # the port bond was joined: one bond from the motor's junction to the load
    flat = m.augmented.flat
    assert [str(b) for b in flat.bonds][5] == "6: motor.w -> load"
    assert len(flat.bonds) == 8


def test_two_copies_get_distinct_parameters_and_shared_ones_stay():
    Kt = sympy.Symbol("Kt", positive=True)
    m1 = motor("m1", K=Kt)
    top = bg.BondGraph("twin")
    shaft = bg.One("shaft")
    top.add(m1, m1.copy("m2"), shaft, bg.I("J"))
    connect_all(top, [("m1.shaft", shaft), ("m2.shaft", shaft), (shaft, "J")])
    m = bg.derive(top, outputs={"w": bg.flow("J")})
    names = {p.name for p in m.parameters}
    assert names == {"J", "Kt", "m1.Ra", "m1.La", "m2.Ra", "m2.La"}
    assert m.augmented.derivative == ()
    assert m.input_names == ("m1.V", "m2.V")


def test_port_with_bonds_both_inward_becomes_zero_junction():
    sub = bg.BondGraph("spring")
    sub.add(bg.C("k", stiffness="k"), bg.Port("end"))
    sub.connect("end", "k")            # inner bond points away from the port
    top = bg.BondGraph("top")
    F, v = bg.Se("F"), bg.One("v")
    top.add(F, v, bg.I("m"), sub)
    connect_all(top, [(F, v), (v, "m"), ("spring.end", v)])   # outer bond also away
    mdl = bg.derive(top, outputs={"x": bg.displacement("m")})
    assert mdl.augmented.flat.element("spring.end").kind == "0"
    m, k = sympy.symbols("m k", positive=True)
    # the spring is turned round twice (port 0-junction with both bonds out): still m x'' = F - k x
    assert_same_tf(tf_of(mdl, "F", "x"), 1 / (m * s**2 + k))


def test_nested_submodels_names():
    inner = motor("drive")
    mid = bg.BondGraph("axis")
    mid.add(inner, bg.One("w2"), bg.R("f"), bg.Port("out"))
    connect_all(mid, [("drive.shaft", "w2"), ("w2", "f"), ("w2", "out")])
    top = bg.BondGraph("top")
    top.add(mid, bg.One("w"), bg.I("J"))
    connect_all(top, [("axis.out", "w"), ("w", "J")])
    m = bg.derive(top, outputs={"w": bg.flow("J"), "i": bg.flow("axis.drive.La")})
    assert "axis.drive.Ra" in {p.name for p in m.parameters}
    assert m.input_names == ("axis.drive.V",)
