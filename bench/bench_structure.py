"""Benchmark: CPU seconds of the structural analyses on chains of masses (issue 37, item 3).

A force on the first of ``n`` masses joined by springs, each with a damper to
ground (the audit's chain, ``../shared/audit/turn4/cases/_chain.py``):

* ``controllability`` of the whole model (``2n - 1`` states);
* exact ``identifiability`` with the displacement of the last mass measured;
* ``fault_signatures`` with the velocity of every mass measured, and with the
  velocity of the last mass only (its relations grow about fourfold per mass:
  refused past ``FAULT_SIZE_BUDGET``, the time to the refusal is shown);

CPU seconds (``time.process_time``) of the analysis alone, after ``derive``.

    python bench/bench_structure.py                  # 20, 40, 80 masses; 2, 3; 5, 10
    python bench/bench_structure.py --control 80 --ident 3 --faults 10
"""

from __future__ import annotations

import argparse
import time


def chain(n: int):
    import bondgraph as bg

    g = bg.BondGraph("chain")
    g.add(bg.Se("F"))
    for i in range(n):
        g.add(bg.One(f"v{i}"), bg.I(f"m{i}"), bg.R(f"b{i}"))
        g.connect(f"v{i}", f"m{i}")
        g.connect(f"v{i}", f"b{i}")
        if i == 0:
            g.connect("F", "v0")
        else:
            g.add(bg.Zero(f"s{i}"), bg.C(f"k{i}"))
            g.connect(f"v{i - 1}", f"s{i}")
            g.connect(f"s{i}", f"k{i}")
            g.connect(f"s{i}", f"v{i}")
    return g


def main(argv=None) -> int:
    import bondgraph as bg
    from bondgraph.structure import controllability, fault_signatures, identifiability

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--control", type=int, nargs="*", default=[20, 40, 80])
    ap.add_argument("--ident", type=int, nargs="*", default=[2, 3])
    ap.add_argument("--faults", type=int, nargs="*", default=[5, 10])
    a = ap.parse_args(argv)
    for n in a.control:
        model = bg.derive(chain(n))
        t = time.process_time()
        r = controllability(model)
        print(f"controllability, {n:3d} masses ({len(model.states):3d} states): "
              f"{time.process_time() - t:7.2f} CPU s  (generic rank {r.generic_rank}, "
              f"Kalman rank {r.kalman_rank})", flush=True)
    for n in a.ident:
        model = bg.derive(chain(n), outputs={"x": bg.displacement(f"m{n - 1}")})
        t = time.process_time()
        r = identifiability(model)
        print(f"identifiability (exact), {n} masses ({len(r.unknown)} parameters): "
              f"{time.process_time() - t:7.2f} CPU s  (rank {r.rank})", flush=True)
    for n in a.faults:
        for sensors in ("every mass", "last mass"):
            outs = ({f"v{i}": bg.flow(f"m{i}") for i in range(n)} if sensors == "every mass"
                    else {"v": bg.flow(f"m{n - 1}")})
            model = bg.derive(chain(n), outputs=outs)
            t = time.process_time()
            try:
                what = f"{len(fault_signatures(model).arrs)} relations"
            except bg.BondGraphError as exc:
                what = f"refused: {str(exc)[:60]}..."
            print(f"fault_signatures, {n:2d} masses, velocity of the {sensors}: "
                  f"{time.process_time() - t:7.2f} CPU s  ({what})", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
