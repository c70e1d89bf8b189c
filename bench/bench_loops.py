"""Benchmark: CPU seconds of ``bg.derive`` on the random linear graphs with the largest algebraic loops.

The graphs are those of ``tests/verification/generator.py`` (the 20,000-seed
differential run of ``bench/verify_random.py``); the seeds listed are the
slowest to derive found so far (bridges and ladders of 20-25 elements whose
loops are solved exactly).  Each graph is derived in the description's
insertion order and in insertion order 1, and the CPU time
(``time.process_time``) of ``derive`` alone is printed.  ``--scan A B`` also
derives every seed in ``range(A, B)`` and reports the slowest ones and the
total.

    python bench/bench_loops.py                     # the listed seeds
    python bench/bench_loops.py --scan 0 2000       # and a scan of 2,000 seeds

Run it on two checkouts to compare (``PYTHONPATH=<checkout>``).  To check that
a speed-up changed no result, ``--snapshot A B OUT`` writes the SHA-256 of the
``srepr`` of every derived model (states, inputs, right-hand sides, outputs,
input derivatives, descriptor form, algebraic unknowns and residuals; or the
refusal) of seeds ``A..B-1`` and the listed seeds, in both insertion orders;
``--compare BEFORE AFTER`` counts the differences::

    PYTHONHASHSEED=0 python bench/bench_loops.py --seeds --snapshot 0 250 after.json
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

#: the slowest seeds to derive, found by scans (issue 37)
SLOW = (18398, 901, 9168, 17243, 7533, 17280, 276, 5, 605, 145, 87)


def derive_seconds(seed: int, order) -> tuple[float, str, object]:
    """CPU seconds of ``derive`` for graph ``seed`` in insertion order ``order``."""
    import bondgraph as bg
    from verification import generator as gen

    g = gen.generate(seed)
    bgg, outputs, _ = gen.build(g, order)
    t = time.process_time()
    try:
        with gen.time_limit(120):
            bg.derive(bgg, outputs)
        what = "ok"
    except gen.GraphTimeout:
        what = "timeout (120 s)"
    except bg.BondGraphError as exc:
        what = type(exc).__name__
    return time.process_time() - t, what, g


def fingerprint(seed: int, order) -> str:
    """SHA-256 of the ``srepr`` of the model derived from graph ``seed``, or its refusal."""
    import sympy

    import bondgraph as bg
    from verification import generator as gen

    bgg, outputs, _ = gen.build(gen.generate(seed), order)
    try:
        m = bg.derive(bgg, outputs)
    except bg.BondGraphError as exc:
        return f"refused {type(exc).__name__}: {exc}"
    parts = [sympy.srepr(x) for x in (m.states, m.inputs, m.rhs, m.output_exprs,
                                       m.input_derivatives, m.descriptor, m.algebraic,
                                       m.residuals)]
    return hashlib.sha256("\n".join(parts).encode()).hexdigest()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scan", type=int, nargs=2, metavar=("A", "B"))
    ap.add_argument("--seeds", type=int, nargs="*", default=SLOW)
    ap.add_argument("--snapshot", nargs=3, metavar=("A", "B", "OUT"))
    ap.add_argument("--compare", nargs=2, metavar=("BEFORE", "AFTER"))
    a = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    if a.compare:
        before, after = (json.loads(Path(f).read_text()) for f in a.compare)
        diff = sorted(k for k in before if before[k] != after.get(k))
        print(f"{len(before)} derivations, {len(diff)} differ: {diff[:20]}")
        return 1 if diff else 0
    if a.snapshot:
        lo, hi, out = int(a.snapshot[0]), int(a.snapshot[1]), a.snapshot[2]
        seeds = list(range(lo, hi)) + [s for s in SLOW if not lo <= s < hi]
        Path(out).write_text(json.dumps({f"{seed}:{order}": fingerprint(seed, order)
                                         for seed in seeds for order in (None, 1)}))
        print(f"{2 * len(seeds)} derivations -> {out}")
        return 0
    import bondgraph  # noqa: F401 - imported before timing

    worst = 0.0
    print(f"{'seed':>6} {'order':>5}  {'family':10s} {'size':8s} {'CPU s':>7}")
    for seed in a.seeds:
        for order in (None, 1):
            dt, what, g = derive_seconds(seed, order)
            worst = max(worst, dt)
            print(f"{seed:6d} {str(order):>5}  {g.family:10s} {str(g.size):8s} {dt:7.2f}  {what}",
                  flush=True)
    print(f"slowest of the listed seeds: {worst:.2f} CPU s")
    if a.scan:
        times = []
        for seed in range(*a.scan):
            dt, what, g = derive_seconds(seed, None)
            times.append((dt, seed, what))
        times.sort(reverse=True)
        print(f"scan of seeds {a.scan[0]}..{a.scan[1] - 1}: total {sum(t for t, _, _ in times):.1f} "
              f"CPU s, slowest " + ", ".join(f"{s} ({t:.2f} s{'' if w == 'ok' else ', ' + w})"
                                             for t, s, w in times[:5]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
