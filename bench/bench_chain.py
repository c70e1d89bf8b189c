"""Benchmark: causality and derivation time for a chain of N mass-spring-damper cells.

"total" is causality + derivation (the issue's target); "ABCD" is the extra
time of ``Model.state_space()`` (sparse A, B, C, D).

Each cell is a 1-junction with an I (mass) and an R (damper to ground); a
0-junction with a C (spring) joins neighbouring masses; an Se drives the
first mass.  Each size runs in a fresh process.

    python bench/bench_chain.py            # N = 10 50 100 200 500 1000
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
    import bondgraph as bg

    t0 = time.perf_counter()
    g = build(n)
    t1 = time.perf_counter()
    aug = bg.assign_causality(g)
    t2 = time.perf_counter()
    model = bg.derive(aug)
    t3 = time.perf_counter()
    ss = model.state_space()
    t4 = time.perf_counter()
    assert not aug.derivative and len(model.states) == 2 * n - 1 and ss.A.shape[0] == 2 * n - 1
    return {"N": n, "bonds": len(aug.flat.bonds), "states": len(model.states),
            "build": t1 - t0, "causality": t2 - t1, "derive": t3 - t2, "abcd": t4 - t3}


def main(argv: list[str]) -> None:
    if argv and argv[0] == "--one":
        print(json.dumps(one(int(argv[1]))))
        return
    sizes = [int(a) for a in argv] or [10, 50, 100, 200, 500, 1000]
    print(f"{'N':>5} {'bonds':>6} {'states':>6} {'causality s':>12} {'derive s':>9} "
          f"{'total s':>8} {'us/bond':>8} {'ABCD s':>7}")
    for n in sizes:
        out = subprocess.run([sys.executable, __file__, "--one", str(n)], check=True,
                             capture_output=True, text=True).stdout
        r = json.loads(out)
        tot = r["causality"] + r["derive"]
        print(f"{r['N']:>5} {r['bonds']:>6} {r['states']:>6} {r['causality']:>12.4f} "
              f"{r['derive']:>9.4f} {tot:>8.4f} {1e6 * tot / r['bonds']:>8.1f} {r['abcd']:>7.3f}")


if __name__ == "__main__":
    main(sys.argv[1:])
