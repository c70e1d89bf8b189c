"""Timings of switched bond graphs: mode derivation, event simulation, cost per event.

    PYTHONPATH=$PWD python bench/hybrid_simulate.py          # everything, the 1 s buck included
    PYTHONPATH=$PWD python bench/hybrid_simulate.py --quick  # without the 1 s buck

Prints, for each case, the CPU time, the number of events and the cost per
event.  The 100 kHz buck converter is run over 1, 4 and 16 ms and over one
second (200,000 events): the cost per event should not grow with the
horizon (issue 37).  The one-second run is checked against shorter runs in
overlapping windows: the first 4 ms against a run of 4 ms from the same
start, the last 0.5 ms against a run restarted from the long run's state at
t = 0.9995 s.
"""

import argparse
import resource
import time

import numpy as np

import bondgraph as bg
from bondgraph.hybrid import SwitchedModel, library, simulate

BUCK = {"Vin": 10, "duty": 0.5, "T": 1e-5, "L": 1e-4, "C": 1e-4, "R": 5}


def cpu(label, fn):
    t0 = time.process_time()
    out = fn()
    dt = time.process_time() - t0
    n = len(out.events) if hasattr(out, "events") else 0
    extra = f", {n} events, {1e6 * dt / n:.0f} us CPU per event" if n else ""
    print(f"{label}: {dt:.3f} s CPU{extra}", flush=True)
    return out, dt


def buck_horizons(long_run: bool) -> None:
    buck = SwitchedModel(library.buck(), outputs={"v": bg.effort("C"), "iL": bg.flow("L")})
    simulate(buck, (0, 1e-4), values=BUCK)              # derive the modes once
    for horizon in (1e-3, 4e-3, 16e-3):
        cpu(f"buck 100 kHz over {horizon * 1e3:g} ms", lambda: simulate(buck, (0, horizon), values=BUCK))
    if not long_run:
        return
    head = np.linspace(0, 4e-3, 401)
    tail = np.linspace(1 - 5e-4, 1.0, 51)
    res, dt = cpu("buck 100 kHz over 1 s", lambda: simulate(
        buck, (0, 1.0), values=BUCK, t_eval=np.concatenate([head, tail]), max_events=10**6))
    print(f"    peak resident memory of the process {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MiB")
    short = simulate(buck, (0, 4e-3), values=BUCK, t_eval=head)

    def on(r, grid):
        keep = np.isin(r.t, grid) & np.r_[np.diff(r.t) != 0, True]
        return r.outputs["v"][keep], r.outputs["iL"][keep]

    (v1, i1), (v2, i2) = on(res, head), on(short, head)
    print(f"    first 4 ms against a 4 ms run: max |dv| = {np.max(np.abs(v1 - v2)):.2e} V, "
          f"max |di| = {np.max(np.abs(i1 - i2)):.2e} A")
    k = int(np.nonzero(np.isclose(res.t, tail[0], rtol=0, atol=1e-15))[0][-1])
    x0 = {name: float(vals[k]) for name, vals in res.stored.items()}
    again = simulate(buck, (tail[0], 1.0), x0, values=BUCK, t_eval=tail)
    (v1, i1), (v2, i2) = on(res, tail[1:]), on(again, tail[1:])
    print(f"    last 0.5 ms against a run restarted at {tail[0]}: max |dv| = "
          f"{np.max(np.abs(v1 - v2)):.2e} V, max |di| = {np.max(np.abs(i1 - i2)):.2e} A")


def calibration() -> None:
    """A reference cost of this machine now (2 shared cores are often loaded 5x)."""
    t0 = time.process_time()
    for _ in range(20000):
        np.linspace(0.0, 1.0, 6)
    print(f"machine: np.linspace(0, 1, 6) costs {(time.process_time() - t0) / 20000 * 1e6:.1f} us CPU "
          "(a loaded machine inflates every figure below by the same factor)", flush=True)


def main() -> None:
    calibration()
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="skip the one-second buck run")
    quick = ap.parse_args().quick
    buck = SwitchedModel(library.buck(), outputs={"v": bg.effort("C")})
    cpu("buck: derive all 4 modes", lambda: buck.modes)
    buck_horizons(long_run=not quick)
    rect = SwitchedModel(library.rectifier(), outputs={"v": bg.effort("C")})
    cpu("rectifier 50 Hz: 50 mains periods", lambda: simulate(
        rect, (0, 1.0), values={"Vm": 10, "w": 314.159, "R": 100, "C": 1e-4}))
    cpu("rectifier 1 Hz, RC = 0.5 s: 3 periods from an empty capacitor", lambda: simulate(
        rect, (0, 3.0), values={"Vm": 10, "w": 2 * np.pi, "R": 1000, "C": 5e-4}))
    ball = SwitchedModel(library.bounce(), outputs={"h": bg.displacement("ball")})
    cpu("MTT bounce: 10 s", lambda: simulate(ball, (0, 10), {"h": 10.0},
                                            values={"m": 1, "r": 1, "k_g": 100, "g": 9.81}))


if __name__ == "__main__":
    main()
