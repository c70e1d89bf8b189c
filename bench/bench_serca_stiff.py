"""Benchmark: simulating the SERCA pump, BondGraphs.jl's stiff test, with ``bondgraph.simulate``.

The model is the one of ``tests/library/test_peer_biochem.py`` (Tran et al.
2009, the parameters of BondGraphTools' and BondGraphs.jl's SERCA examples)
with the SR calcium rising as ``(0.05 + 0.01 t) * 2.28`` and BondGraphs.jl's
initial state.  Its rate coefficients reach 1e11 per second while the states
move on a scale of 1e3 s, and the right-hand side at the slow manifold is the
difference of terms of order 1e7: each solver is timed to ``T`` seconds and
its drift off the conserved pump total (the sum of the nine states, 0.99999
at t = 0) reported, with the distance to BondGraphs.jl's values at t = 200
(test/simulation_tests.jl, "SERCA (stiff equations)", atol 1e-5 there).

    python bench/bench_serca_stiff.py            # T = 20, BDF and Radau
    python bench/bench_serca_stiff.py 200 BDF    # BondGraphs.jl's span
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

X0 = {"q_P1": 0.000483061870385487, "q_P2": 0.0574915174273067, "q_P2a": 0.527445119834607,
      "q_P4": 1.51818391164022e-09, "q_P5": 0.000521923287622898, "q_P6": 7.80721128535043e-05,
      "q_P8": 0.156693953834181, "q_P9": 0.149232225342376, "q_P10": 0.108044124948978}
#: BondGraphs.jl's values at t = 200
AT_200 = {"q_P1": 4.4404656222265794e-5, "q_P2": 0.09777422826977565,
          "q_P2a": 0.8970112784324162, "q_P4": 2.6596475539704174e-9,
          "q_P5": 0.0009426424413096248, "q_P6": 0.001015195974904865,
          "q_P8": 0.001212098675876874, "q_P9": 0.0011543788312157496,
          "q_P10": 0.0008357702283899367}


def main(argv: list[str]) -> None:
    import bondgraph as bg

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "library"))
    from test_peer_biochem import _serca

    t1 = float(argv[0]) if argv else 20.0
    methods = argv[1:] or ["BDF", "Radau"]
    model = bg.derive(_serca((0.05 + 0.01 * bg.t) * 2.28).graph())
    total0 = sum(X0.values())
    print(f"SERCA to t = {t1:g} s; pump total at t = 0: {total0:.6f}")
    for method in methods:
        start = time.perf_counter()
        try:
            res = bg.simulate(model, {}, (0.0, t1), X0, t_eval=[t1], method=method, rtol=1e-7,
                              atol=1e-11)
        except bg.BondGraphError as exc:
            print(f"{method:6s} failed after {time.perf_counter() - start:.1f} s: {exc}")
            continue
        wall = time.perf_counter() - start
        x = {n: float(res[n][-1]) for n in model.state_names}
        drift = sum(x.values()) - total0
        line = f"{method:6s} {wall:7.1f} s   pump total drift {drift:+.2e}"
        if t1 == 200.0:
            line += f"   max |x - BondGraphs.jl| {max(abs(x[n] - AT_200[n]) for n in x):.2e}"
        print(line)


if __name__ == "__main__":
    main(sys.argv[1:])
