"""model() returns a bare BondGraph instead of a ModelDefinition."""

import bondgraph as bg


def model():
    return bg.BondGraph("bare")
