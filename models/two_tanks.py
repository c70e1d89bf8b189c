"""Two interacting water tanks, built from library components, with parameters in units.

Model
-----
A pump delivers the flow ``q.Q`` into tank 1; tank 1 drains into tank 2
through a laminar restriction ``r1``, tank 2 into the open drain through
``r2`` (Ogata, *Modern Control Engineering*, 5th ed., Sec. 4-2, the
liquid-level system with interaction; MTT's ``TwoTanks`` teaching example
has the same parts).  Each tank is a ``GravityTank`` (``p = rho g V/A``:
capacitance ``C = A/(rho g)``), each outlet a ``LaminarRestriction``
(``dp = R Q``).  The parameters are given with their units
(``sympy.physics.units``: areas in m^2, resistances in bar s/l), so the model
declares units: its plants, the ``bondgraph`` command line's tables and its
exports carry the units of the volumes (m^3), the pump flow (m^3/s) and the
outputs.  Ogata's transfer function of the outflow,

    q2/q = 1/(R1 C1 R2 C2 s^2 + (R1 C1 + R2 C2 + R2 C1) s + 1),

has here (R in Pa s/m^3, C in m^3/Pa) the time constants printed by
``python models/two_tanks.py``.
"""

from __future__ import annotations

import sympy.physics.units as u

import bondgraph as bg
from bondgraph.library import hydraulic as hy

PARAMETERS = {"A1": 2.0 * u.meter**2, "A2": 1.0 * u.meter**2,
              "R1": 0.02 * u.bar * u.second / u.liter, "R2": 0.03 * u.bar * u.second / u.liter,
              "rho": 1000.0 * u.kilogram / u.meter**3, "g": 9.81 * u.meter / u.second**2}
OUTPUTS = {"q_out": bg.flow("r2.R"), "p1": bg.effort("t1.C"), "p2": bg.effort("t2.C")}


def build() -> bg.BondGraph:
    """The two tanks: pump -> tank 1 -> r1 -> tank 2 -> r2 -> drain."""
    g = bg.BondGraph("two_tanks")
    g.add(hy.FlowSource("q"), bg.Zero("h1"), bg.Zero("h2"),
          hy.GravityTank("t1", area="A1", density="rho", gravity="g"),
          hy.GravityTank("t2", area="A2", density="rho", gravity="g"),
          hy.LaminarRestriction("r1", resistance="R1"),
          hy.LaminarRestriction("r2", resistance="R2"), hy.Tank("drain"))
    for tail, head in [("q.p", "h1"), ("h1", "t1.p"), ("h1", "r1.a"), ("r1.b", "h2"),
                       ("h2", "t2.p"), ("h2", "r2.a"), ("r2.b", "drain.p")]:
        g.connect(tail, head)
    return g


def model():
    """Model definition (the model-file protocol), parameters with units."""
    from bondgraph.modelfile import ModelDefinition

    return ModelDefinition(graph=build(), outputs=OUTPUTS, parameters=PARAMETERS,
                           description="two interacting tanks (Ogata Sec. 4-2), units declared")


def main() -> int:
    """Print the plant's units and the tanks' time constants."""
    import numpy as np

    d = model()
    plant = d.plant()
    print("units:", ", ".join(f"{k} [{v}]" for k, v in plant.units.items()))
    taus = sorted(-1.0 / np.linalg.eigvals(plant.A).real)
    print("time constants:", ", ".join(f"{t:.1f} s" for t in taus))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
