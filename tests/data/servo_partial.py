"""Motor sub-model driving a load: hierarchical names (motor.Ra); defaults miss the load's J and b."""

import bondgraph as bg
from bondgraph.modelfile import ModelDefinition


def motor() -> bg.BondGraph:
    g = bg.BondGraph("motor")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.Port("shaft"))
    for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "shaft")]:
        g.connect(tail, head)
    return g


def model() -> ModelDefinition:
    top = bg.BondGraph("servo")
    load = bg.One("load")
    top.add(motor(), load, bg.I("J"), bg.R("b"))
    for tail, head in [("motor.shaft", load), (load, "J"), (load, "b")]:
        top.connect(tail, head)
    return ModelDefinition(top, {"omega": bg.flow("J"), "theta": bg.displacement("J")},
                           {"motor.Ra": 2.0, "motor.La": 0.5, "motor.K": 0.1})
