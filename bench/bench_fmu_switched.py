"""Benchmark: FMUs of switched models (rectifier, clutch, buck) built and simulated by fmpy.

For each model and FMI version: the time to build the FMU (C generation of
the mode table, model description, compilation, archive), the wall time of
fmpy's Model Exchange run (CVode with the FMU's event indicators, relative
tolerance 1e-8) and Co-Simulation run (the FMU's RK4 through the events),
the wall time of ``bondgraph.hybrid.simulate`` (RK45, rtol 1e-9), the number
of events ME recorded and the largest deviation of the first output from
``hybrid.simulate`` at the communication points, relative to its largest
magnitude.  Median of ``--repeat`` runs (default 3).

* rectifier: Vm = 10 V, 50 Hz, R = 100 ohm, C = 100 uF, 50 ms, output every 0.1 ms;
* clutch: J1 = 1, J2 = 2, tau = 1 N m, w2(0) = 3 rad/s, lock at 1 s, 2 s, output every 10 ms;
* buck: Vin = 10 V, d = 0.5, T = 10 us, L = C = 100 u, R = 5 ohm, 2 ms (200 PWM periods,
  400 gate events and the diode's), output every 10 us, rk4_step 0.1 us.

    python bench/bench_fmu_switched.py
    python bench/bench_fmu_switched.py --repeat 1
"""

from __future__ import annotations

import argparse
import math
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

import bondgraph as bg
from bondgraph.fmu import build_fmu
from bondgraph.hybrid import SwitchedModel, library, simulate


def cases():
    rect = SwitchedModel(library.rectifier(), outputs={"v": bg.effort("C")})
    clutch = SwitchedModel(library.clutch(), outputs={"w2": bg.flow("J2")})
    buck = SwitchedModel(library.buck(), outputs={"v": bg.effort("C")})
    return [
        ("rectifier", rect, {"Vm": 10.0, "w": 2 * math.pi * 50, "R": 100.0, "C": 1e-4}, {}, {}, 0.05, 1e-4, 1e-4),
        ("clutch", clutch, {"J1": 1.0, "J2": 2.0, "t_lock": 1.0}, {"p_J2": 6.0}, {"tau": 1.0}, 2.0, 1e-2, 1e-3),
        ("buck", buck, {"Vin": 10.0, "duty": 0.5, "T": 1e-5, "L": 1e-4, "C": 1e-4, "R": 5.0}, {}, {},
         2e-3, 1e-5, 1e-7),
    ]


def _on_grid(t, y, grid):
    """The samples at the grid times (after the event where one falls on a grid time)."""
    tol = 1e-6 * (grid[1] - grid[0])
    idx = np.searchsorted(t, grid + tol, side="right") - 1
    if not np.allclose(t[idx], grid, rtol=0, atol=tol):
        raise RuntimeError("a grid time was not sampled")
    return y[idx]


def main(argv=None) -> int:
    from fmpy import simulate_fmu

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    med = statistics.median
    print(f"{'model':>10} FMI  build_s   ME_s   CS_s  ref_s  events  err_ME   err_CS")
    with tempfile.TemporaryDirectory() as tmp:
        for name, sm, vals, x0, u, t_end, dt, h in cases():
            grid = np.round(np.arange(0, t_end + dt / 2, dt), 12)
            t_ref = []
            for _ in range(args.repeat):
                t0 = time.perf_counter()
                ref = simulate(sm, (0, t_end), x0, values=vals, inputs=u, t_eval=grid)
                t_ref.append(time.perf_counter() - t0)
            out = next(iter(sm.user_outputs))
            y_ref = _on_grid(ref.t, ref.outputs[out], grid)
            scale = np.max(np.abs(y_ref))
            inp = None
            if u:
                inp = np.array([(0.0, *u.values()), (t_end, *u.values())],
                               dtype=[("time", np.float64)] + [(k, np.float64) for k in u])
            for fmi in (2, 3):
                builds, me, cs = [], [], []
                path = Path(tmp, f"{name}{fmi}.fmu")
                for _ in range(args.repeat):
                    t0 = time.perf_counter()
                    path.write_bytes(build_fmu(sm, fmi=fmi, values=vals, step=h))
                    builds.append(time.perf_counter() - t0)
                for kind, times in (("ModelExchange", me), ("CoSimulation", cs)):
                    for _ in range(args.repeat):
                        t0 = time.perf_counter()
                        res = simulate_fmu(str(path), fmi_type=kind, stop_time=t_end, output_interval=dt,
                                           relative_tolerance=1e-8, start_values=x0, input=inp,
                                           output=[out])
                        times.append(time.perf_counter() - t0)
                    t = res["time"]
                    y = _on_grid(t, res[out], grid)
                    err = float(np.max(np.abs(y - y_ref)) / scale)
                    if kind == "ModelExchange":
                        n_ev, err_me = int(np.sum(np.diff(t) == 0)), err
                    else:
                        err_cs = err
                print(f"{name:>10} {fmi:>3} {med(builds):8.2f} {med(me):6.2f} {med(cs):6.2f} "
                      f"{med(t_ref):6.2f} {n_ev:7d} {err_me:7.1e} {err_cs:8.1e}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
