"""Differential check of switched modes on random graphs (more seeds than the test suite).

Runs ``tests/hybrid/test_random_switched.check_seed`` on seeds ``0..N-1``:
two switches on random junctions of a random linear graph, every mode
against the independent reference solver.  Prints the outcome counts and the
time; a wrong mode raises.

    PYTHONPATH=$PWD python bench/hybrid_random.py 100
"""

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "hybrid"))
sys.path.insert(0, str(ROOT / "tests"))

from test_random_switched import check_seed  # noqa: E402


def main(n: int) -> None:
    total: dict = {}
    t0 = time.perf_counter()
    for seed in range(n):
        for k, v in check_seed(seed).items():
            total[k] = total.get(k, 0) + v
    dt = time.perf_counter() - t0
    print(f"{n} random switched graphs, {sum(total.values())} modes: {total}; 0 wrong; {dt:.1f} s")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100)
