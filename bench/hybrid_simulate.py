"""Timings of switched bond graphs: mode derivation and event simulation.

    PYTHONPATH=$PWD python bench/hybrid_simulate.py

Prints, for each case, the wall time, the number of events and events per
second (one core; the first derivation of each mode included where said).
"""

import time

import bondgraph as bg
from bondgraph.hybrid import SwitchedModel, library, simulate


def timed(label, fn):
    t0 = time.perf_counter()
    out = fn()
    dt = time.perf_counter() - t0
    n = len(out.events) if hasattr(out, "events") else None
    extra = f", {n} events, {n / dt:.0f} events/s" if n else ""
    print(f"{label}: {dt:.3f} s{extra}")
    return out


def main() -> None:
    buck = SwitchedModel(library.buck(), outputs={"v": bg.effort("C")})
    timed("buck: derive all 4 modes", lambda: buck.modes)
    vals = {"Vin": 10, "duty": 0.5, "T": 1e-5, "L": 1e-4, "C": 1e-4, "R": 5}
    timed("buck: 200 PWM periods (first run: compiles 2 modes)",
          lambda: simulate(buck, (0, 200e-5), values=vals))
    timed("buck: 200 PWM periods (again)", lambda: simulate(buck, (0, 200e-5), values=vals))
    timed("buck: 200 periods, max_step = T/10", lambda: simulate(buck, (0, 200e-5), values=vals,
                                                                  max_step=1e-6))
    rect = SwitchedModel(library.rectifier(), outputs={"v": bg.effort("C")})
    timed("rectifier: 50 mains periods", lambda: simulate(
        rect, (0, 1.0), values={"Vm": 10, "w": 314.159, "R": 100, "C": 1e-4}))
    ball = SwitchedModel(library.bounce(), outputs={"h": bg.displacement("ball")})
    timed("MTT bounce: 10 s", lambda: simulate(ball, (0, 10), {"h": 10.0},
                                              values={"m": 1, "r": 1, "k_g": 100, "g": 9.81}))


if __name__ == "__main__":
    main()
