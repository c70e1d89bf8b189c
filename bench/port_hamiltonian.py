"""Benchmark: ``port_hamiltonian(model)`` on the model library and random graphs.

The time is the port-Hamiltonian construction only (the model is derived
first, outside the timer); it includes one derivation of the collocated
outputs with the model's own causality and the symbolic check that the
rebuilt ``x'`` equals the derived ``rhs``.

    python bench/port_hamiltonian.py            # models/ and 30 random graphs
    python bench/port_hamiltonian.py --random 0 # models/ only
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "models"), str(ROOT / "tests")]

import bondgraph as bg  # noqa: E402
from bondgraph.hamiltonian import PortHamiltonianError, port_hamiltonian  # noqa: E402


def library():
    import appendages
    import flexcam
    import srv02

    return [("srv02", srv02.model()), ("srv02 + J_l (derivative)", srv02.model(load_inertia=True)),
            ("flexcam paper", flexcam.model()), ("flexcam system", flexcam.model(formulation="system")),
            ("appendages", appendages.model())]


def timed(model):
    t0 = time.perf_counter()
    try:
        ph = port_hamiltonian(model)
    except PortHamiltonianError as err:
        return time.perf_counter() - t0, f"refused: {str(err)[:60]}"
    return time.perf_counter() - t0, f"{len(ph.states)} states"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--random", type=int, default=30, help="random graphs (default 30)")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore", bg.BondGraphWarning)
    rows = []
    for name, d in library():
        rows.append((name, *timed(d.derive())))
    if args.random:
        from verification import generator as gen

        seed = 0
        while sum(r[0].startswith("random") for r in rows) < args.random and seed < 1000:
            seed += 1
            graph, outputs, _ = gen.build(gen.generate(seed, p_clash=0.0, max_elements=16))
            try:
                model = bg.derive(graph, outputs=outputs)
            except bg.BondGraphError:
                continue
            rows.append((f"random seed {seed}", *timed(model)))
    for name, secs, what in rows:
        print(f"{name:28s} {secs * 1e3:9.1f} ms  {what}")
    total = sum(r[1] for r in rows)
    print(f"{'total':28s} {total * 1e3:9.1f} ms  ({len(rows)} models)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
