"""Cost of the implicit path (issue 29): derivative evaluations with a Newton solve of g = 0.

Run from the repository root::

    PYTHONPATH=$PWD python bench/bench_implicit.py

Prints the time per ``derivatives`` call of the diode circuit (one algebraic
unknown, warm-started Newton) against the same circuit with a linear diode
(explicit), and the wall time of a 1-ms simulation of the diode circuit.
"""

from __future__ import annotations

import time

import numpy as np
import scipy.integrate  # noqa: F401  (imported before timing)
import sympy

import bondgraph as bg


def circuit(diode_law: bool) -> bg.Model:
    Is, Vt = sympy.symbols("Is Vt", positive=True)
    g = bg.BondGraph("diode")
    D = bg.R("D", inverse=Is * (sympy.exp(bg.e / Vt) - 1)) if diode_law else bg.R("D")
    g.add(bg.Se("V"), bg.One("a"), bg.R("R1"), bg.Zero("n"), bg.C("C"), bg.One("s"), bg.R("R"), D)
    for t, h in [("V", "a"), ("a", "R1"), ("a", "n"), ("n", "C"), ("n", "s"), ("s", "R"), ("s", "D")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"i": bg.flow("D")})


def per_call(dyn, p, n=2000) -> float:
    xs = np.linspace(0.0, 5e-6, n)
    t0 = time.perf_counter()
    for x in xs:
        dyn.derivatives(0.0, [x], [5.0], p)
    return (time.perf_counter() - t0) / n


def main() -> None:
    vals = {"R1": 500.0, "R": 500.0, "C": 1e-6, "Is": 1e-12, "Vt": 0.025}
    implicit = bg.numeric.compile_dynamics(circuit(True))
    explicit = bg.numeric.compile_dynamics(circuit(False))
    p_i = implicit.parameter_vector(vals)
    p_e = explicit.parameter_vector({k: v for k, v in vals.items() if k not in ("Is", "Vt")} | {"D": 10.0})
    print(f"derivatives, implicit (Newton, warm start): {per_call(implicit, p_i) * 1e6:8.1f} us/call")
    print(f"derivatives, explicit (linear diode):       {per_call(explicit, p_e) * 1e6:8.1f} us/call")
    t0 = time.perf_counter()
    res = bg.simulate(implicit, vals, (0.0, 5e-3), u=[5.0], rtol=1e-8, atol=1e-14)
    print(f"simulate 5 ms (5 RC time constants), rtol 1e-8: {time.perf_counter() - t0:.2f} s, "
          f"{res.t.size} steps, final i = {res['i'][-1]:.6g} A")


if __name__ == "__main__":
    main()
