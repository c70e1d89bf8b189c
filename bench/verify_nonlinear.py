"""Differential verification of bondgraph on random NONLINEAR bond graphs (issue 22).

Each graph (``tests/verification/nonlinear.py``: cubic and saturating springs,
cubic inertias, quadratic, tanh and orifice dampers, MTF with an angle, MGY,
modulated sources) is checked against the independent DAE reference of
``tests/verification/nonlinear_reference.py``: ``simulate`` trajectories,
``linearize`` Jacobians at a random point and at the equilibrium (against
central differences of the reference), ``equilibrium`` (the reference's
residual at the point found, the stability verdict against the reference's
eigenvalues).  Classes: wrong, crash, timeout (CPU seconds per graph),
refused (by reason), no-equilibrium-found (the package found none where the
reference did), reference-failed, input-derivatives (dependent storage whose
equations need du/dt: not simulated, not compared), agree.  Graphs with storage
in derivative causality are compared against the reference's own index
reduction (``tests/verification/nonlinear_reduced.py``; the check "reduced").

    python bench/verify_nonlinear.py --n 5000 --seed 0 --jobs 2 --timeout 30

Exit status 1 when a graph is answered wrongly or crashes.
"""

from __future__ import annotations

import argparse
import collections
import json
import multiprocessing as mp
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from verification import nonlinear as nl  # noqa: E402


def _one(args):
    seed, timeout = args
    import warnings
    warnings.simplefilter("ignore")
    o = nl.check(nl.generate(seed), timeout=timeout)
    return {"seed": seed, "cls": o.cls, "detail": o.detail, "seconds": o.seconds,
            "checks": o.checks}


def _refusal_kind(detail: str) -> str:
    if "rate of the storage" in detail:
        return "higher index (a stored quantity needs another dependent storage's rate)"
    if "inverse" in detail:
        return "law not invertible (give inverse=)"
    if "nonlinear in its unknowns" in detail or "AlgebraicLoopError" in detail:
        return "nonlinear algebraic loop"
    return detail.split(":")[1].strip() if ":" in detail else detail


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=30.0, help="CPU seconds per graph")
    ap.add_argument("--json", type=Path, help="write per-graph results here, one JSON line "
                    "each as they come (a run stopped early keeps them)")
    ap.add_argument("--progress", type=int, default=250, help="print counts every N graphs")
    args = ap.parse_args(argv)

    import bondgraph  # noqa: F401 -- imported before forking
    t0 = time.perf_counter()
    counts: collections.Counter = collections.Counter()
    refusals: collections.Counter = collections.Counter()
    flags: collections.Counter = collections.Counter()
    records = []
    tasks = [(args.seed + i, args.timeout) for i in range(args.n)]
    sink = open(args.json, "w") if args.json else None
    with mp.get_context("fork").Pool(args.jobs, maxtasksperchild=200) as pool:
        for k, r in enumerate(pool.imap_unordered(_one, tasks, chunksize=4), 1):
            counts[r["cls"]] += 1
            records.append(r)
            if sink:
                sink.write(json.dumps(r) + "\n")
                sink.flush()
            if r["cls"] == "refused":
                refusals[_refusal_kind(r["detail"])] += 1
            for key in r["checks"]:
                flags[key] += 1
            if args.progress and k % args.progress == 0:
                print(f"  {k} graphs, {time.perf_counter() - t0:.0f} s: "
                      + ", ".join(f"{c} {counts[c]}" for c in nl.CLASSES if counts[c]),
                      flush=True)
    wall = time.perf_counter() - t0
    secs = sorted(r["seconds"] for r in records)
    print(f"\nnonlinear differential verification: {args.n} graphs (seeds {args.seed}.."
          f"{args.seed + args.n - 1}), {args.jobs} jobs, CPU limit {args.timeout:g} s per graph")
    print(f"wall time {wall:.1f} s; per graph in a worker: median {secs[len(secs) // 2]:.2f} s, "
          f"max {secs[-1]:.1f} s\n")
    print(f"{'class':24s} {'count':>7s} {'%':>7s}")
    for c in nl.CLASSES:
        print(f"{c:24s} {counts[c]:7d} {100 * counts[c] / max(1, args.n):7.2f}"
              + ("   <- failure" if c in ("wrong", "crash") and counts[c] else ""))
    print("\nrefused, by reason (issue 29's):")
    for why, n in refusals.most_common():
        print(f"  {n:6d}  {why}")
    print("\nchecks run: " + ", ".join(f"{k} {v}" for k, v in sorted(flags.items())))
    bad = [r for r in records if r["cls"] in ("wrong", "crash", "timeout", "no-equilibrium-found",
                                              "reference-failed")]
    for r in sorted(bad, key=lambda r: (r["cls"], r["seed"]))[:40]:
        print(f"  seed {r['seed']} {r['cls']}: {r['detail'][:300]}")
    if sink:
        sink.close()
    return 1 if counts["wrong"] or counts["crash"] else 0


if __name__ == "__main__":
    sys.exit(main())
