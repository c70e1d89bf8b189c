"""Benchmark: parameter sweeps of the FLEXCAM model (models/flexcam.py, paper form, 6 states).

Samples per second of two metrics over a Sobol design of four parameters
(Beq, Rm and the damping of the first two link modes), each run in this
process, on a ``ProcessPoolExecutor(2)`` and on a 2-worker Dask
``LocalCluster`` (processes, one thread each):

* ``min_damping`` -- batched eigenvalues of each chunk of plants;
* ``peak_gain`` of ``y / hub.e_in`` -- a 100-point frequency response per
  plant (plus a golden-section refinement of the peak), batched.

Each executor is warmed up first (its workers import bondgraph and compile
the model once), and the start-up time is given apart.  The sweeps run the
same chunks everywhere, so the tables are identical (checked).

    python bench/bench_sweep.py            # N = 16384 samples per sweep
    python bench/bench_sweep.py 4096
"""

from __future__ import annotations

import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PARAMETERS = {"Beq": (1e-4, 1e-2), "Rm": (2.0, 3.2), "link.b_1": (0.0, 20.0), "link.b_2": (0.0, 20.0)}
METRICS = {"min_damping": "min_damping", "peak_gain (100-pt FRF)": "peak_gain"}


def setup():
    import bondgraph as bg

    defn = bg.load_model(str(ROOT / "models" / "flexcam.py"))
    t0 = time.perf_counter()
    nm = bg.compile_plant(defn.derive())
    t1 = time.perf_counter()
    values = {k: v for k, v in defn.parameters.items() if k in nm.parameter_names}
    return nm, values, t1 - t0


def timed(nm, values, metric, n, executor):
    from bondgraph.study import sweep

    t0 = time.perf_counter()
    df = sweep(nm, PARAMETERS, metric, values=values, n=n, seed=1, executor=executor,
               output="y", progress=False)
    return time.perf_counter() - t0, df


def main(argv: list[str]) -> None:
    import pandas as pd

    n = int(argv[0]) if argv else 16384
    nm, values, compile_s = setup()
    print(f"FLEXCAM: {len(nm.state_names)} states, {len(nm.parameter_names)} parameters; "
          f"derive + compile {compile_s:.2f} s; {n} Sobol samples per sweep, "
          f"{os.cpu_count()} cores")
    rows = []
    frames: dict[str, list] = {label: [] for label in METRICS}

    def run(where: str, executor, start_s: float) -> None:
        for label, metric in METRICS.items():
            timed(nm, values, metric, 64, executor)             # warm-up: imports, compilation
            seconds, df = timed(nm, values, metric, n, executor)
            frames[label].append(df)
            rows.append((label, where, start_s, seconds, n / seconds))

    run("in process", None, 0.0)
    t0 = time.perf_counter()
    with ProcessPoolExecutor(2) as pool:
        pool.submit(int, 0).result()
        run("process pool (2)", pool, time.perf_counter() - t0)
    try:
        import distributed
    except ImportError:
        print("dask.distributed not installed: no cluster rows")
    else:
        t0 = time.perf_counter()
        with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                      dashboard_address=None) as cluster, \
                distributed.Client(cluster) as client:
            run("Dask LocalCluster (2)", client, time.perf_counter() - t0)
    for label, dfs in frames.items():
        for df in dfs[1:]:
            pd.testing.assert_frame_equal(dfs[0], df)
    print()
    print(f"{'metric':24s} {'executor':24s} {'start (s)':>10s} {'sweep (s)':>10s} {'samples/s':>10s}")
    for label, where, start_s, seconds, rate in rows:
        print(f"{label:24s} {where:24s} {start_s:10.2f} {seconds:10.2f} {rate:10.0f}")
    print("\nidentical tables on every executor: yes")


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    main(sys.argv[1:])
