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

Friction clutch (Karnopp)
-------------------------
:func:`karnopp` is the same pair of inertias joined by a friction clutch
(:func:`bondgraph.hybrid.library.friction_clutch`): stuck while the torque it
must transmit stays within the static torque ``Ts``, slipping with the kinetic
torque ``Tk`` against the slip otherwise (modes: stuck, slipping forwards,
slipping backwards).  ``python models/clutch.py`` drives ``J1`` with the ramp
``a t`` while ``J2`` spins at 2 rad/s: the clutch slips backwards until the
slip closes at ``t1 = 0.7583`` s (``a t^2/(2 J1) + Tk (1/J1 + 1/J2) t = w2(0)``),
sticks while ``J2 a t/(J1 + J2) <= Ts`` and slips forwards from ``t2 = Ts (J1 +
J2)/(J2 a) = 1`` s.
"""

from __future__ import annotations

import sympy

import bondgraph as bg
from bondgraph.hybrid import SwitchedModel, library

PARAMETERS = {"J1": 1.0, "J2": 2.0, "t_lock": 1.0}
OUTPUTS = {"w1": bg.flow("J1"), "w2": bg.flow("J2"), "torque": bg.effort("K")}
#: the friction clutch: kinetic and static torques (N m), the ramp rate of the drive (N m/s)
KARNOPP = {"J1": 1.0, "J2": 2.0, "Tk": 1.0, "Ts": 2.0, "a": 3.0}


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


def karnopp() -> SwitchedModel:
    """The friction clutch driven by the ramp torque ``a t``, with the outputs ``w1``, ``w2`` and
    the clutch ``torque`` (Karnopp: stuck, slipping forwards or backwards)."""
    a = sympy.Symbol("a", positive=True)
    return SwitchedModel(library.friction_clutch(torque=a * bg.t),
                         outputs={"w1": bg.flow("J1"), "w2": bg.flow("J2"), "torque": bg.effort("c")})


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
    print("friction clutch (Karnopp), ramp torque a t on J1, w2(0) = 2 rad/s:")
    fc = karnopp()
    k = KARNOPP
    fres = bg.simulate(fc, k, (0, 2), {"p_J2": k["J2"] * 2.0}, rtol=1e-10, atol=1e-12)
    for ev in fres.events:
        print(f"t = {ev.time:.6f}: {ev.after}")
    print(f"at t = 2: w1 = {fres.outputs['w1'][-1]:.6f}, w2 = {fres.outputs['w2'][-1]:.6f} rad/s, "
          f"clutch torque {fres.outputs['torque'][-1]:.6f} N m")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
