"""Benchmark: causality and derivation time for a chain of N mass-spring-damper cells.

"total" is causality + derivation; "ABCD" is the extra time of
``Model.state_space()`` (sparse A, B, C, D); "all" is causality + derivation
+ ``state_space()`` (the issue's target: 10,000 cells under 5 s, 20,000 under
10 s); "us/bond" is "all" per bond (constant when growing linearly).  Times
are CPU seconds of the process (``time.process_time``), less sensitive than
wall time to other work on the machine; "peak MB" is the process's peak
resident set.

Each cell is a 1-junction with an I (mass) and an R (damper to ground); a
0-junction with a C (spring) joins neighbouring masses; an Se drives the
first mass.  Each size runs in a fresh process.

    python bench/bench_chain.py            # N = 10 50 100 200 500 1000
    python bench/bench_chain.py --large    # N = 1000 5000 10000 20000
    python bench/bench_chain.py 10 50      # chosen sizes
"""

from __future__ import annotations

import json
import subprocess
import sys
import time


def build(n: int):
    import bondgraph as bg

    g = bg.BondGraph(f"chain{n}")
    F = bg.Se("F")
    g.add(F)
    prev = None
    for i in range(n):
        v = bg.One(f"v{i}")
        g.add(v, bg.I(f"m{i}"), bg.R(f"b{i}"))
        g.connect(v, f"m{i}")
        g.connect(v, f"b{i}")
        if prev is None:
            g.connect(F, v)
        else:
            s = bg.Zero(f"s{i}")
            g.add(s, bg.C(f"k{i}"))
            g.connect(prev, s)
            g.connect(s, v)
            g.connect(s, f"k{i}")
        prev = v
    return g


def one(n: int) -> dict:
    import resource

    import bondgraph as bg

    clock = time.process_time
    t0 = clock()
    g = build(n)
    t1 = clock()
    aug = bg.assign_causality(g)
    t2 = clock()
    model = bg.derive(aug)
    t3 = clock()
    ss = model.state_space()
    t4 = clock()
    assert not aug.derivative and len(model.states) == 2 * n - 1 and ss.A.shape[0] == 2 * n - 1
    return {"N": n, "bonds": len(aug.flat.bonds), "states": len(model.states),
            "build": t1 - t0, "causality": t2 - t1, "derive": t3 - t2, "abcd": t4 - t3,
            "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def main(argv: list[str]) -> None:
    if argv and argv[0] == "--one":
        print(json.dumps(one(int(argv[1]))))
        return
    if argv and argv[0] == "--large":
        sizes = [1000, 5000, 10000, 20000]
    else:
        sizes = [int(a) for a in argv] or [10, 50, 100, 200, 500, 1000]
    print(f"{'N':>6} {'bonds':>6} {'states':>6} {'causality s':>12} {'derive s':>9} "
          f"{'total s':>8} {'ABCD s':>7} {'all s':>7} {'us/bond':>8} {'peak MB':>8}")
    for n in sizes:
        out = subprocess.run([sys.executable, __file__, "--one", str(n)], check=True,
                             capture_output=True, text=True).stdout
        r = json.loads(out)
        tot = r["causality"] + r["derive"]
        every = tot + r["abcd"]
        print(f"{r['N']:>6} {r['bonds']:>6} {r['states']:>6} {r['causality']:>12.4f} "
              f"{r['derive']:>9.4f} {tot:>8.4f} {r['abcd']:>7.3f} {every:>7.3f} "
              f"{1e6 * every / r['bonds']:>8.1f} {r['peak_mb']:>8.0f}")


if __name__ == "__main__":
    main(sys.argv[1:])
