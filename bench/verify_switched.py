"""Differential verification of switched models on random circuits (issue 34).

Each circuit (``tests/verification/switched_generator.py``: 1-3 nodes, voltage
and current sources constant or sinusoidal, 1-3 capacitors and inductors and
1-3 resistors over two decades, 1-2 ideal diodes, none or one switch gated by a
PWM or by a state, series and parallel branches, bonds either way, random
insertion order) is simulated by ``bondgraph.hybrid.simulate`` and by the
independent reference of ``tests/verification/switched_reference.py``
(nodal analysis per mode, diode complementarity by enumeration, exact
exponential dynamics, events on a fine grid refined by brentq).  Compared: the
mode at t = 0 and after every event, every event time, every stored quantity
and the mode at 100 instants away from events.  Classes: wrong, crash,
timeout (CPU seconds per graph), refused-well-posed, refused-ill-posed,
ill-posed-answered (the reference finds no unique solution and the package
simulated anyway: not judged), agree.

    python bench/verify_switched.py --n 5000 --seed 0 --jobs 2 --timeout 30

Exit status 1 when a graph is answered wrongly, crashes, times out or a well-posed
one is refused.
"""

from __future__ import annotations

import os

# tiny matrices: a multithreaded BLAS only costs here (set before numpy is imported)
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import collections  # noqa: E402
import json  # noqa: E402
import multiprocessing as mp  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from verification import switched_generator as sg  # noqa: E402


def _one(args):
    seed, timeout = args
    o = sg.check(sg.generate(seed), timeout=timeout)
    return {"seed": seed, "cls": o.cls, "detail": o.detail, "seconds": o.seconds,
            "checks": o.checks}


def _reason(detail: str) -> str:
    """A short kind of refusal or ill-posedness, for the summary."""
    for key in ("no consistent mode", "chatters", "no consistent state", "undetermined",
                "move differently", "keeps changing", "events by", "not determined"):
        if key in detail:
            return key
    return detail.split(":")[0]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=30.0, help="CPU seconds per graph")
    ap.add_argument("--json", type=Path, help="write per-graph results here, one JSON line "
                    "each as they come (a run stopped early keeps them)")
    ap.add_argument("--progress", type=int, default=250, help="print counts every N graphs")
    ap.add_argument("--summary", type=Path, help="only print the table of a --json file "
                    "(of a run stopped early, say)")
    args = ap.parse_args(argv)
    if args.summary:
        records = [json.loads(line) for line in open(args.summary) if line.strip()]
        seeds = sorted(r["seed"] for r in records)
        print(f"\nswitched differential verification: {len(records)} graphs (seeds "
              f"{seeds[0]}..{seeds[-1]}, from {args.summary})")
        return _table(records)

    import bondgraph.hybrid  # noqa: F401 -- imported before forking
    t0 = time.perf_counter()
    counts: collections.Counter = collections.Counter()
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
            if args.progress and k % args.progress == 0:
                print(f"  {k} graphs, {time.perf_counter() - t0:.0f} s: "
                      + ", ".join(f"{c} {counts[c]}" for c in sg.CLASSES if counts[c]), flush=True)
    wall = time.perf_counter() - t0
    print(f"\nswitched differential verification: {args.n} graphs (seeds {args.seed}.."
          f"{args.seed + args.n - 1}), {args.jobs} jobs, CPU limit {args.timeout:g} s per graph")
    print(f"wall time {wall:.1f} s")
    if sink:
        sink.close()
    return _table(records)


def _table(records: list) -> int:
    """Print the counts by class, the kinds of refusal, what was compared, the failures."""
    counts = collections.Counter(r["cls"] for r in records)
    reasons = collections.Counter((r["cls"], _reason(r["detail"])) for r in records
                                  if r["cls"] in ("refused-ill-posed", "ill-posed-answered",
                                                  "refused-well-posed"))
    flags: collections.Counter = collections.Counter()
    for r in records:
        for key, v in r["checks"].items():
            flags[key] += v
    secs = sorted(r["seconds"] for r in records)
    print(f"CPU per graph: median {secs[len(secs) // 2]:.2f} s, max {secs[-1]:.1f} s\n")
    print(f"{'class':22s} {'count':>7s} {'%':>7s}")
    for c in sg.CLASSES:
        print(f"{c:22s} {counts[c]:7d} {100 * counts[c] / max(1, len(records)):7.2f}"
              + ("   <- failure" if c in sg.FAILURES and counts[c] else ""))
    print("\nrefusals and ill-posed graphs, by kind:")
    for (cls, why), n in sorted(reasons.items()):
        print(f"  {n:6d}  {cls}: {why}")
    print("\ncompared: " + ", ".join(f"{k} {v}" for k, v in sorted(flags.items())))
    bad = [r for r in records if r["cls"] in sg.FAILURES]
    for r in sorted(bad, key=lambda r: (r["cls"], r["seed"]))[:60]:
        print(f"  seed {r['seed']} {r['cls']}: {r['detail'][:300]}")
    if bad:
        print("\nreproduce one: python -c 'import sys; sys.path.insert(0, \"tests\"); from verification "
              "import switched_generator as sg; print(sg.script(sg.generate(SEED)))'")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
