"""Exact symbolic transfer functions before and after a change: fingerprints to compare.

For the models of ``bench/bench_tf.py`` (DC motor, the modal hub beam with 1 to
8 modes, the descriptor hub beam, the mass chains of 3 to 7 masses, the
bond-graph chains of 3 to 8 cells, and FLEXCAM's tip deflection from
``models/flexcam.py``, paper form with 1 to 9 modes and system form with 1 to
5), every normalization (``monic``,
``as-derived``, ``leading-one-denominator``), cancelled and uncancelled,
prints the SHA-256 of ``srepr`` of the numerator and denominator ``Poly``
(and the term counts).  Run it on two trees and compare the outputs::

    PYTHONPATH=/path/to/old python bench/check_tf_identical.py > old.txt
    PYTHONPATH=$PWD python bench/check_tf_identical.py > new.txt
    diff old.txt new.txt && echo identical

The random graphs' transfer matrices are covered by
``bench/snapshot_srepr.py`` (same procedure).
"""

from __future__ import annotations

import hashlib
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT))


def cases():
    import bench_tf

    yield "dc_motor", bench_tf.dc_motor()
    for n in range(1, 9):
        yield f"hub_beam{n}", bench_tf.hub_beam(n)
    yield "hub_beam_E3", bench_tf.hub_beam_descriptor(3)
    for n in range(3, 8):
        yield f"chain{n}", bench_tf.chain(n)
    for n in range(3, 9):
        yield f"bgchain{n}", bench_tf.bond_graph_chain(n)
    for n in range(1, 10):
        yield f"flexcam{n}", bench_tf.flexcam(n)
    for n in range(1, 6):
        yield f"flexcam_sys{n}", bench_tf.flexcam(n, "system")


def main() -> int:
    import sympy

    from bondgraph.tf import transfer_function

    for name, (A, B, C, D, *rest) in cases():
        E = rest[0] if rest else None
        for normalize in ("monic", "as-derived", "leading-one-denominator"):
            for cancel in (True, False):
                G = transfer_function(A, B, C, D, E=E, normalize=normalize, cancel=cancel)
                digest = hashlib.sha256((sympy.srepr(G.num) + "|" + sympy.srepr(G.den))
                                        .encode()).hexdigest()[:16]
                print(f"{name:<12} {normalize:<24} cancel={cancel!s:<5} {digest} "
                      f"{len(G.num.terms())} {len(G.den.terms())}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
