"""Mass on a hardening spring (k q + k3 q^3) with a damper, driven by a force: nonlinear."""

import sympy

import bondgraph as bg
from bondgraph.modelfile import ModelDefinition


def model() -> ModelDefinition:
    k, k3 = sympy.symbols("k k3", positive=True)
    g = bg.BondGraph("duffing")
    F, v = bg.Se("F"), bg.One("v")
    g.add(F, v, bg.I("m"), bg.R("b"), bg.C("s", law=k * bg.q + k3 * bg.q**3))
    for tail, head in [(F, v), (v, "m"), (v, "b"), (v, "s")]:
        g.connect(tail, head)
    return ModelDefinition(g, {"x": bg.displacement("s"), "v": bg.flow("m")},
                           {"m": 1.0, "b": 0.3, "k": 2.0, "k3": 0.5})
