"""A clutch locking two inertias driven by a torque (switched bond graph, cf. MTT Hybrid/Clutch).

Model
-----
The torque input ``tau`` drives the inertia ``J1``; the clutch ``K`` joins it
to ``J2`` and engages at ``t = t_lock`` (:func:`bondgraph.hybrid.library.clutch`).
The clutch is a switch on the 0-junction of the slip velocity: disengaged =
on (zero torque: two independent inertias, states ``p_J1``, ``p_J2``),
engaged = off (zero slip: ``J2`` in derivative causality, one state).

At the lock the total momentum is conserved, the shafts take the common
velocity ``(J1 w1 + J2 w2)/(J1 + J2)``, and ``J1 J2 (w1 - w2)^2 / (2 (J1 + J2))``
of kinetic energy is lost in the clutch (``python models/clutch.py`` prints
the event).

For the ``bondgraph`` command line, ``model()`` is the switched graph, built
disengaged (``engaged=False``, the initial mode) or locked: ``equations``
prints both modes, ``simulate`` runs the lock as an event, and ``tf`` takes
``--mode on=K`` (disengaged) or ``--mode off=K`` (locked).
"""

from __future__ import annotations

import bondgraph as bg
from bondgraph.hybrid import SwitchedModel, library

PARAMETERS = {"J1": 1.0, "J2": 2.0, "t_lock": 1.0}
OUTPUTS = {"w1": bg.flow("J1"), "w2": bg.flow("J2"), "torque": bg.effort("K")}


def build(*, engaged: bool = False) -> bg.BondGraph:
    """The clutch graph, disengaged (switch on) or engaged (switch off)."""
    g = library.clutch()
    if not engaged:
        return g
    out = bg.BondGraph(g.name)
    out.add(*(el.in_state(False) if el.name == "K" else el for el in g.elements))
    for b in g.bonds:
        out.connect(b.tail, b.head)
    return out


def switched() -> SwitchedModel:
    """The switched model with the outputs ``w1``, ``w2`` and the clutch ``torque``."""
    return SwitchedModel(library.clutch(), outputs=OUTPUTS)


def model(*, engaged: bool = False):
    """Model definition (the model-file protocol): the switched clutch, built disengaged or
    locked."""
    from bondgraph.modelfile import ModelDefinition

    return ModelDefinition(graph=build(engaged=engaged), outputs=OUTPUTS, parameters=PARAMETERS,
                           description=f"two inertias, clutch {'engaged' if engaged else 'disengaged'}")


def main(argv: list[str] | None = None) -> int:
    """Print both modes and simulate a lock: w2(0) = 3 rad/s, tau = 1 N m."""
    sm = switched()
    for mode in sm.modes:
        m = sm.derived(mode).user
        print(f"mode ({mode}): states {', '.join(m.state_names)}; "
              + "; ".join(f"d{s.name}/dt = {r}" for s, r in zip(m.states, m.rhs)))
    print("causality changes:", sm.causality_changes)
    p = PARAMETERS
    res = bg.simulate(sm, p, (0, 2), {"p_J2": p["J2"] * 3.0}, u={"tau": 1.0})
    for ev in res.events:
        print(f"t = {ev.time:.6f}: {ev.before} -> {ev.after}; energy lost {ev.energy_loss:.6f} J; "
              + ", ".join(f"{k}: {a:.6f} -> {b:.6f}" for k, (a, b) in ev.jumps.items()))
    print(f"at t = 2: w1 = {res.outputs['w1'][-1]:.6f}, w2 = {res.outputs['w2'][-1]:.6f} rad/s, "
          f"clutch torque {res.outputs['torque'][-1]:.6f} N m")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
