"""Long run: structural analyses (bondgraph.structure) against the numeric reference.

For random graphs of ``tests/verification/generator.py`` compares the engine's
dynamic order, generic ``rank [A B]``, ``rank [A; C]``, relative degree and
number of finite zeros with the numbers of ``tests/verification/structure_ref.py``
(exact ranks of the reference's bond equations, finite generalized eigenvalues
of its Rosenbrock pencil by ``scipy.linalg.eig``), and checks that the
bond-graph ranks (Sueur and Dauphin-Tanguy: derivative causality with dualised
sources / detectors) are never below the reference's ranks.  Prints the counts
per outcome, how often each structural bound (maximum matching of the nonzero
pattern of the model's matrices, shortest causal path, the bond graph in
derivative causality) was not tight, how many graphs had a bond-graph rank to
compare, and every disagreement.

    python bench/structure_agreement.py --start 0 --n 5000
    python bench/structure_agreement.py --start 0 --n 500 --timeout 60

Exit status 1 on any disagreement.
"""

from __future__ import annotations

import argparse
import collections
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from verification.generator import GraphTimeout, time_limit  # noqa: E402
from verification.structure_ref import compare  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--start", type=int, default=0)
    ap.add_argument("--n", type=int, default=5000)
    ap.add_argument("--timeout", type=float, default=60.0)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    counts: collections.Counter = collections.Counter()
    loose: collections.Counter = collections.Counter()
    graphs: collections.Counter = collections.Counter()
    bad = []
    t0 = time.perf_counter()
    for seed in range(args.start, args.start + args.n):
        try:
            with time_limit(args.timeout):
                c = compare(seed)
        except GraphTimeout:
            counts["timeout"] += 1
            print(f"seed {seed}: timeout", flush=True)
            continue
        except Exception as err:      # a crash of the engine or the reference: report it
            counts["crash"] += 1
            print(f"seed {seed}: crash {type(err).__name__}: {err}", flush=True)
            continue
        counts[c.status] += 1
        loose.update(c.bound_not_tight)
        if c.eng is not None:
            graphs.update(k for k in ("graph_ab", "graph_ac", "bicausal_rel")
                          if c.eng[k] is not None)
        if c.status == "disagree":
            bad.append(c)
            print(f"seed {seed}: DISAGREE {c.detail}", flush=True)
        elif c.status == "refused":
            print(f"seed {seed}: refused {c.detail[:120]}", flush=True)
        else:       # one line per graph: a stopped run can still be counted from its log
            print(f"seed {seed}: {c.status}", flush=True)
    dt = time.perf_counter() - t0
    print(f"graphs {args.start}..{args.start + args.n - 1}: {dict(counts)} in {dt:.0f} s "
          f"({dt / max(args.n, 1):.2f} s per graph)")
    print(f"structural bound not tight (graphs): {dict(loose)}")
    print(f"bond-graph rank / bicausal relative degree compared (graphs): {dict(graphs)}")
    return 1 if bad or counts["crash"] else 0


if __name__ == "__main__":
    sys.exit(main())
