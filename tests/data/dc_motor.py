"""DC motor test model: voltage V to speed omega and current i, every default given."""

import bondgraph as bg
from bondgraph.modelfile import ModelDefinition


def model() -> ModelDefinition:
    g = bg.BondGraph("dc_motor")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
    for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
        g.connect(tail, head)
    return ModelDefinition(
        graph=g,
        outputs={"omega": bg.flow("J"), "i": bg.flow("La")},
        parameters={"Ra": 2.0, "La": 0.5, "K": 0.1, "J": 0.02, "b": 0.2},
        description="DC motor, armature voltage to speed and current",
    )
