"""A Python file that defines no model() function."""

import bondgraph as bg

GRAPH = bg.BondGraph("nothing")
