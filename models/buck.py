"""Buck converter with an ideal PWM switch and an ideal freewheeling diode (switched bond graph).

Model
-----
``Vin`` feeds node A through the controlled switch ``S`` (PWM gate: on for
the fraction ``duty`` of each period ``T``); the diode ``D`` conducts from
ground to node A; the inductor ``L`` runs from A to the output node with the
capacitor ``C`` and the load ``R`` (:func:`bondgraph.hybrid.library.buck`).

Modes (``python models/buck.py`` prints them): S on / D off and S off / D on
(continuous conduction, both with the states ``p_L``, ``q_C``); S off / D off
(discontinuous conduction: ``L`` in derivative causality, ``p_L = 0``); S on /
D on shorts the source and is not a consistent mode.

The state-space average over a period, in the duty cycle ``d``, is an ordinary
model whose duty-to-output transfer function is the textbook
``Vin/(L C s^2 + (L/R) s + 1)``.

For the ``bondgraph`` command line, ``model()`` is the switched graph (built with
S on and D off, the initial mode): ``bondgraph equations`` prints every mode,
``simulate`` runs it with its events, ``export -f fmu`` writes every mode, and
``tf`` or a numeric ``export`` take ``--mode on=S`` or the average
``--average d on=S on=D``.
"""

from __future__ import annotations

import sympy

import bondgraph as bg
from bondgraph.hybrid import Mode, SwitchedModel, library

PARAMETERS = {"Vin": 10.0, "duty": 0.5, "T": 1e-5, "L": 1e-4, "C": 1e-4, "R": 5.0}
OUTPUTS = {"v": bg.effort("C"), "iL": bg.flow("L")}
ACTIVE, PASSIVE = Mode(on={"S"}, off={"D"}), Mode(on={"D"}, off={"S"})


def build(*, switch_on: bool = True) -> bg.BondGraph:
    """The buck converter's graph with the switch (and the diode opposite) in the given state."""
    g = library.buck()
    if not switch_on:
        g = _with_states(g, {"S": False, "D": True})
    return g


def _with_states(g: bg.BondGraph, states: dict) -> bg.BondGraph:
    out = bg.BondGraph(g.name)
    out.add(*(el.in_state(states[el.name]) if el.name in states else el for el in g.elements))
    for b in g.bonds:
        out.connect(b.tail, b.head)
    return out


def switched() -> SwitchedModel:
    """The switched model with the outputs ``v`` (capacitor voltage) and ``iL``."""
    return SwitchedModel(library.buck(), outputs=OUTPUTS)


def averaged(duty: str = "d") -> bg.Model:
    """The state-space averaged model, the duty cycle ``d`` its input."""
    return switched().average(duty, ACTIVE, PASSIVE)


def model(*, switch_on: bool = True):
    """Model definition (the model-file protocol): the switched converter, built in the mode
    ``switch_on`` gives (S on, D off; or S off, D on)."""
    from bondgraph.modelfile import ModelDefinition

    return ModelDefinition(graph=build(switch_on=switch_on), outputs=OUTPUTS,
                           parameters=PARAMETERS,
                           description="buck converter: PWM switch S, freewheeling diode D")


def main(argv: list[str] | None = None) -> int:
    """Print the modes, the averaged duty-to-output TF and a switched run's mean and ripple."""
    import numpy as np

    sm = switched()
    for mode in sm.all_modes:
        try:
            m = sm.derived(mode).user
        except bg.BondGraphError as err:
            print(f"mode ({mode}): inconsistent -- {str(err).split(': ', 2)[-1][:100]}...")
            continue
        print(f"mode ({mode}): states {', '.join(m.state_names) or '-'}")
        for s, r in zip(m.states, m.rhs):
            print(f"    d{s.name}/dt = {r}")
    avg = averaged()
    G = avg.transfer_function("d", "v").expr
    print(f"\naveraged: d(p_L)/dt = {avg.rhs[0]}, d(q_C)/dt = {avg.rhs[1]}")
    print(f"duty-to-output TF: {sympy.factor(G)}")
    p = PARAMETERS
    d, T = p["duty"], p["T"]
    i0 = d * p["Vin"] / p["R"] - p["Vin"] * (1 - d) * d * T / p["L"] / 2
    grid = np.linspace(30 * T, 40 * T, 2001)
    res = bg.simulate(sm, p, (0, 40 * T), {"p_L": p["L"] * i0, "q_C": p["C"] * d * p["Vin"]},
                      t_eval=grid)
    keep = res.t >= 30 * T
    v = res.outputs["v"][keep]
    print(f"\nswitched run ({len(res.events)} events): mean v = {v.mean():.6f} V "
          f"(averaged equilibrium {d * p['Vin']:.6f}), ripple {v.max() - v.min():.6e} V "
          f"(textbook {p['Vin'] * (1 - d) * d * T ** 2 / (8 * p['L'] * p['C']):.6e})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
