"""Benchmark: batched numeric plants of a 7-mass chain (14 states, 21 parameters).

Mass ``m1`` is tied to the wall by a spring ``k1`` and a damper ``b1``; each
further mass ``m{i}`` is tied to ``m{i-1}`` by ``k{i}`` and ``b{i}``; a force
``F`` drives the last mass; the output is the velocity of the last mass (a position output would
add an integrator state).
The table gives the time to derive and compile once, to evaluate A, B, C, D
for P parameter sets at once, their eigenvalues, and a 100-point frequency
response.

    python bench/bench_batch.py              # P = 20000
    python bench/bench_batch.py 1000 20000   # chosen batch sizes
"""

from __future__ import annotations

import sys
import time

import numpy as np

N_MASSES = 7


def build(n: int = N_MASSES):
    import bondgraph as bg

    g = bg.BondGraph(f"chain{n}")
    prev = None
    for i in range(1, n + 1):
        v = bg.One(f"v{i}")
        g.add(v, bg.I(f"m{i}"))
        g.connect(v, f"m{i}")
        if prev is None:        # spring and damper to the wall
            g.add(bg.C(f"k{i}", stiffness=f"k{i}"), bg.R(f"b{i}"))
            g.connect(v, f"k{i}")
            g.connect(v, f"b{i}")
        else:                   # spring and damper between neighbours
            a, rel = bg.Zero(f"a{i}"), bg.One(f"rel{i}")
            g.add(a, rel, bg.C(f"k{i}", stiffness=f"k{i}"), bg.R(f"b{i}"))
            g.connect(prev, a)
            g.connect(a, v)
            g.connect(a, rel)
            g.connect(rel, f"k{i}")
            g.connect(rel, f"b{i}")
        prev = v
    F = bg.Se("F")
    g.add(F)
    g.connect(F, prev)
    return bg.derive(g, outputs={"v": bg.flow(f"m{n}")})


def run(sizes: list[int]) -> list[dict]:
    from bondgraph.numeric import compile_plant

    t0 = time.perf_counter()
    model = build()
    t1 = time.perf_counter()
    plant = compile_plant(model)
    t2 = time.perf_counter()
    assert len(model.states) == 2 * N_MASSES and len(plant.parameter_names) == 3 * N_MASSES
    rng = np.random.default_rng(0)
    omega = np.logspace(-1, 2, 100)
    rows = []
    for P in sizes:
        values = {name: rng.uniform(0.5, 2.0, P) for name in plant.parameter_names}
        a = time.perf_counter()
        batch = plant.batch(values)
        b = time.perf_counter()
        ev = batch.eigenvalues()
        c = time.perf_counter()
        H = batch.frequency_response(omega)
        d = time.perf_counter()
        assert ev.shape == (P, 2 * N_MASSES) and H.shape == (P, 100, 1, 1)
        assert np.all(ev.real < 0)
        rows.append({"P": P, "derive": t1 - t0, "compile": t2 - t1, "batch": b - a,
                     "eig": c - b, "freq": d - c})
    return rows


def main(argv: list[str]) -> None:
    sizes = [int(a) for a in argv] or [20000]
    rows = run(sizes)
    print(f"chain of {N_MASSES} masses: {2 * N_MASSES} states, {3 * N_MASSES} parameters")
    print(f"{'P':>7} {'derive s':>9} {'compile s':>10} {'ABCD s':>8} {'compile+ABCD s':>15} "
          f"{'eig s':>7} {'freq(100) s':>12} {'us/set ABCD':>12}")
    for r in rows:
        print(f"{r['P']:>7} {r['derive']:>9.3f} {r['compile']:>10.3f} {r['batch']:>8.4f} "
              f"{r['compile'] + r['batch']:>15.3f} {r['eig']:>7.3f} {r['freq']:>12.3f} "
              f"{1e6 * r['batch'] / r['P']:>12.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
