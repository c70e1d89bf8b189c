"""Differential verification of bondgraph on many random linear bond graphs (issue 11).

Each graph (``tests/verification/generator.py``) is built in two insertion
orders; the symbolic transfer matrix (evaluated) and the numeric plant's
frequency response are compared, at two random complex ``s``, with the exact
Laplace-domain reference of ``tests/verification/reference.py`` (relative
1e-8).  Graphs run in a pool of worker processes with a time limit each
(SIGALRM inside the worker, and a watchdog that kills a worker stuck past the
limit).  Prints the per-class counts, the time, and minimal reproducers (plain
bondgraph code) of the first failures of each class.

    python bench/verify_random.py                       # 20,000 graphs, 2 jobs
    python bench/verify_random.py --n 2000 --seed 0 --jobs 2 --timeout 30
    python bench/verify_random.py --n 200 --reproducers 0      # counts only

Exit status 1 when any failure class is non-empty.
"""

from __future__ import annotations

import argparse
import collections
import json
import multiprocessing as mp
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from verification import generator as gen  # noqa: E402


def _work(conn, timeout: float, max_elements: int, orders: tuple) -> None:
    """Worker loop: receive ("check", seed) or ("shrink", outcome, budget), send results."""
    import warnings

    warnings.simplefilter("ignore")
    while True:
        msg = conn.recv()
        if msg is None:
            return
        if msg[0] == "check":
            seed = msg[1]
            t0 = time.perf_counter()
            try:
                g = gen.generate(seed, max_elements=max_elements)
                out = gen.check(g, time_limit_s=timeout, orders=orders)
                res = {"seed": seed, "cls": out.cls, "seconds": out.seconds,
                       "family": g.family, "size": g.size, "order_dependent": out.order_dependent,
                       "tol_above_1e8": out.tol_above_1e8, "detail": out.detail[:300]}
                if out.cls in gen.FAILURES:
                    out.paths = []
                    res["outcome"] = out
            except BaseException as exc:  # noqa: BLE001 - the harness itself failed
                res = {"seed": seed, "cls": "harness-error", "seconds": time.perf_counter() - t0,
                       "family": "?", "size": (0, 0), "order_dependent": False,
                       "tol_above_1e8": False, "detail": f"{type(exc).__name__}: {exc}"}
            conn.send(res)
        else:
            _, outcome, budget = msg
            small = gen.shrink(outcome, budget_s=budget, time_limit_s=timeout, orders=orders)
            small.paths = []
            conn.send({"shrunk": small})


class _Pool:
    """Worker processes with one task each at a time and a hard per-task deadline."""

    def __init__(self, jobs: int, timeout: float, max_elements: int, orders: tuple,
                 recycle: int = 400) -> None:
        self.ctx = mp.get_context("fork")
        self.timeout, self.max_elements, self.recycle = timeout, max_elements, recycle
        self.orders = orders
        self.workers = [self._spawn() for _ in range(jobs)]

    def _spawn(self) -> dict:
        parent, child = self.ctx.Pipe()
        p = self.ctx.Process(target=_work, args=(child, self.timeout, self.max_elements, self.orders),
                             daemon=True)
        p.start()
        child.close()
        return {"proc": p, "conn": parent, "task": None, "start": 0.0, "done": 0, "deadline": 0.0}

    def _replace(self, i: int) -> None:
        w = self.workers[i]
        w["proc"].kill()      # only a worker this script started, by its process object
        w["proc"].join()
        w["conn"].close()
        self.workers[i] = self._spawn()

    def run(self, tasks, deadline_of, on_result, on_hang) -> None:
        tasks = collections.deque(tasks)
        busy = 0
        while tasks or busy:
            for i, w in enumerate(self.workers):
                if w["task"] is None and tasks:
                    if w["done"] >= self.recycle:          # bound memory (sympy caches)
                        w["conn"].send(None)
                        w["proc"].join(5)
                        self._replace(i)
                        w = self.workers[i]
                    t = tasks.popleft()
                    w["conn"].send(t)
                    w["task"], w["start"] = t, time.perf_counter()
                    w["deadline"] = w["start"] + deadline_of(t)
                    busy += 1
            conns = [w["conn"] for w in self.workers if w["task"] is not None]
            ready = mp.connection.wait(conns, timeout=1.0)
            now = time.perf_counter()
            for i, w in enumerate(self.workers):
                if w["task"] is None:
                    continue
                if w["conn"] in ready:
                    try:
                        res = w["conn"].recv()
                    except EOFError:          # the worker died (segfault, OOM)
                        on_hang(w["task"], now - w["start"], "worker died")
                        self._replace(i)
                        busy -= 1
                        continue
                    on_result(w["task"], res)
                    w["task"] = None
                    w["done"] += 1
                    busy -= 1
                elif now > w["deadline"]:
                    on_hang(w["task"], now - w["start"], "killed past the time limit")
                    self._replace(i)
                    busy -= 1

    def close(self) -> None:
        for w in self.workers:
            try:
                w["conn"].send(None)
            except (BrokenPipeError, OSError):
                pass
            w["proc"].join(5)
            if w["proc"].is_alive():
                w["proc"].kill()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=20000, help="number of graphs (default 20000)")
    ap.add_argument("--seed", type=int, default=100000, help="first graph seed (default 100000; "
                    "the CI test uses 0..)")
    ap.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    ap.add_argument("--timeout", type=float, default=30.0,
                    help="CPU seconds per graph (default 30; wall-clock backstop 4x + 10)")
    ap.add_argument("--max-elements", type=int, default=25, help="graph size limit (default 25)")
    ap.add_argument("--orders", type=int, choices=(1, 2), default=2,
                    help="insertion orders per graph: 2 (the description's and a random one; "
                    "default) or 1 (a random one only, half the time)")
    ap.add_argument("--reproducers", type=int, default=3,
                    help="failures per class to minimize and print (default 3)")
    ap.add_argument("--shrink-budget", type=float, default=90.0,
                    help="seconds of minimization per reproducer (default 90)")
    ap.add_argument("--json", type=Path, help="write per-graph results (without graphs) here")
    args = ap.parse_args(argv)

    import bondgraph  # noqa: F401 - imported once before forking the workers
    import warnings
    warnings.simplefilter("ignore")

    counts: collections.Counter = collections.Counter()
    fam_counts: dict = collections.defaultdict(collections.Counter)
    times: list[float] = []
    failures: dict[str, list] = collections.defaultdict(list)
    records: list[dict] = []
    flags = collections.Counter()
    t0 = time.perf_counter()
    done = [0]

    def on_result(task, res):
        counts[res["cls"]] += 1
        fam_counts[res["family"].rstrip("*")][res["cls"]] += 1
        times.append(res["seconds"])
        flags["order-dependent outcome"] += res["order_dependent"]
        flags["evaluation error bound > 1e-8"] += res["tol_above_1e8"]
        if "outcome" in res:
            failures[res["cls"]].append(res["outcome"])
        records.append({k: v for k, v in res.items() if k != "outcome"})
        done[0] += 1
        if done[0] % 1000 == 0:
            el = time.perf_counter() - t0
            print(f"  {done[0]} graphs, {el:.0f} s, {dict(counts)}", file=sys.stderr, flush=True)

    def on_hang(task, seconds, why):
        seed = task[1]
        counts["timeout"] += 1
        times.append(seconds)
        g = gen.generate(seed, max_elements=args.max_elements)
        fam_counts[g.family.rstrip("*")]["timeout"] += 1
        failures["timeout"].append(gen.Outcome("timeout", g, why, None))
        records.append({"seed": seed, "cls": "timeout", "seconds": seconds, "detail": why})

    orders = (None, 1) if args.orders == 2 else (1,)
    pool = _Pool(args.jobs, args.timeout, args.max_elements, orders)
    try:
        pool.run([("check", args.seed + i) for i in range(args.n)],
                 lambda t: 4 * args.timeout + 30.0, on_result, on_hang)
        wall = time.perf_counter() - t0

        print(f"\ndifferential verification: {args.n} graphs (seeds {args.seed}.."
              f"{args.seed + args.n - 1}, up to {args.max_elements} elements, {args.orders} insertion "
              f"order(s)), {args.jobs} jobs, CPU time limit {args.timeout:g} s")
        print(f"wall time {wall:.1f} s = {wall / max(args.n, 1) * 1000:.1f} ms/graph; time per "
              f"graph in a worker: median {statistics.median(times) * 1000:.0f} ms, mean "
              f"{statistics.fmean(times) * 1000:.0f} ms, max {max(times):.1f} s\n")
        fams = sorted(fam_counts)
        header = f"{'class':30s} {'count':>7s} {'%':>6s}  " + " ".join(f"{f:>10s}" for f in fams)
        print(header)
        print("-" * len(header))
        for cls in gen.CLASSES + ("harness-error",):
            if cls == "harness-error" and not counts[cls]:
                continue
            c = counts[cls]
            mark = "  <- failure" if cls in gen.FAILURES + ("harness-error",) and c else ""
            print(f"{cls:30s} {c:7d} {100 * c / max(args.n, 1):6.2f}  "
                  + " ".join(f"{fam_counts[f][cls]:10d}" for f in fams) + mark)
        for k, v in flags.items():
            print(f"  ({k}: {v})")

        if args.json:
            args.json.write_text(json.dumps({"args": {k: str(v) for k, v in vars(args).items()},
                                             "counts": counts, "wall_s": wall,
                                             "graphs": records}, indent=1))
        if args.reproducers:
            picks = []
            for cls in gen.FAILURES:
                fs = sorted(failures.get(cls, []), key=lambda o: o.graph.size)
                picks += fs[: args.reproducers]
            shrunk: list = []
            if picks:
                print(f"\nminimizing {len(picks)} reproducers (budget {args.shrink_budget:g} s each)...",
                      file=sys.stderr, flush=True)
                pool.run([("shrink", o, args.shrink_budget) for o in picks],
                         lambda t: args.shrink_budget + 5 * args.timeout + 60,
                         lambda t, r: shrunk.append(r["shrunk"]),
                         lambda t, s, why: shrunk.append(t[1]))
            for cls in gen.FAILURES:
                mine = sorted((o for o in shrunk if o.cls == cls), key=lambda o: o.graph.size)
                if not mine:
                    continue
                print(f"\n=== {cls}: {counts[cls]} graphs; smallest reproducers ===")
                for o in mine:
                    print(f"\n# graph seed {o.graph.seed} ({o.graph.family}), "
                          f"{o.graph.size[0]} elements, {o.graph.size[1]} bonds")
                    print(o.reproducer())
    finally:
        pool.close()
    return 1 if any(counts[c] for c in gen.FAILURES + ("harness-error",)) else 0


if __name__ == "__main__":
    raise SystemExit(main())
