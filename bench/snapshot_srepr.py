"""Fingerprints of every symbolic result on random graphs, to prove a refactoring changed nothing.

For each seed the random linear bond graph of ``tests/verification/generator.py``
is built (insertion order of the seed), derived, and the ``srepr`` of the
model's states, inputs, right-hand sides, outputs, descriptor form, the
symbolic state space and the symbolic transfer matrix (numerators and
denominators) are hashed; a refusal is recorded by its class and message.
Run it before and after a change with the same ``PYTHONHASHSEED`` and compare
the two files::

    PYTHONHASHSEED=0 python bench/snapshot_srepr.py --n 2000 -o before.json
    # ... change the code ...
    PYTHONHASHSEED=0 python bench/snapshot_srepr.py --n 2000 -o after.json
    python bench/snapshot_srepr.py --compare before.json after.json

Each graph has a time limit (default 20 s, recorded as ``timeout``).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import multiprocessing as mp
import os
import sys
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))


def fingerprint(seed: int, timeout: float) -> tuple[int, str]:
    """``(seed, digest)`` of every symbolic result of graph ``seed``."""
    import sympy

    import bondgraph as bg
    from verification import generator as gen

    warnings.simplefilter("ignore")
    parts: list[str] = []
    try:
        with gen.time_limit(timeout):
            g = gen.generate(seed)
            bgg, outputs, _ = gen.build(g, seed)
            try:
                model = bg.derive(bgg, outputs)
            except bg.BondGraphError as exc:
                return seed, f"derive refused {type(exc).__name__}: {exc}"
            parts += [sympy.srepr(x) for x in (model.states, model.inputs, model.rhs,
                                                model.output_exprs, model.input_derivatives)]
            parts.append(repr(model.output_names))
            for what in ("state_space", "descriptor_form", "transfer_matrix"):
                try:
                    res = getattr(model, what)()
                except bg.BondGraphError as exc:
                    parts.append(f"{what} refused {type(exc).__name__}: {exc}")
                    continue
                if what == "transfer_matrix":
                    parts.append(sympy.srepr(res.den))
                    parts += [sympy.srepr(n) for row in res.nums for n in row]
                    parts.append(repr((res.input_names, res.output_names)))
                else:
                    parts += [sympy.srepr(getattr(res, k)) for k in ("A", "B", "C", "D")]
                    parts.append(sympy.srepr(getattr(res, "E", None)))
    except gen.GraphTimeout:
        return seed, "timeout"
    except Exception as exc:  # noqa: BLE001 - recorded, compared like any result
        return seed, f"crash {type(exc).__name__}: {exc}"
    return seed, hashlib.sha256("\n".join(parts).encode()).hexdigest()


def _run(args_: tuple[int, float]) -> tuple[int, str]:
    return fingerprint(*args_)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--seeds", type=int, nargs="*", default=(),
                    help="extra seeds (the slow ones of bench/bench_loops.py)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=20.0)
    ap.add_argument("-o", "--out", default="srepr.json")
    ap.add_argument("--compare", nargs=2, metavar=("BEFORE", "AFTER"))
    a = ap.parse_args(argv)
    if a.compare:
        before, after = (json.loads(Path(p).read_text()) for p in a.compare)
        diff = [k for k in before if before[k] != after.get(k)]
        timeouts = sum(v == "timeout" for v in before.values())
        print(f"{len(before)} graphs, {len(diff)} differ, {timeouts} timeouts before")
        for k in diff[:20]:
            print(f"  seed {k}: {before[k][:80]!r} -> {after.get(k, '')[:80]!r}")
        return 1 if diff else 0
    if os.environ.get("PYTHONHASHSEED") is None:
        print("warning: set PYTHONHASHSEED (e.g. 0) so the hashes are reproducible", file=sys.stderr)
    seeds = sorted(set(range(a.seed, a.seed + a.n)) | set(a.seeds))
    with mp.get_context("fork").Pool(a.jobs, maxtasksperchild=200) as pool:
        res = dict(pool.imap_unordered(_run, [(s, a.timeout) for s in seeds], chunksize=4))
    Path(a.out).write_text(json.dumps({str(k): res[k] for k in sorted(res)}, indent=0))
    kinds = {}
    for v in res.values():
        k = v.split(" ")[0] if not all(c in "0123456789abcdef" for c in v) else "digest"
        kinds[k] = kinds.get(k, 0) + 1
    print(f"{len(res)} graphs -> {a.out}: {kinds}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
