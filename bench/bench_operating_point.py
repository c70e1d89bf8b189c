"""Benchmark: the symbolic operating point of a thermal chain with a constant ambient.

``n`` capacities ``C{i}`` in a row, each losing heat through ``R{i}`` to the
next and the last to the ambient ``Ta`` (a constant source); the heat input
``Q`` enters the first.  ``model.state_space()`` takes the linear form in
deviations about the equilibrium and solves ``x0`` exactly (the
``DomainMatrix`` solve of :mod:`bondgraph.linear.offsets`); the hand result
``T_i0 = Ta + Q0 (R_i + ... + R_{n-1})`` is checked for the first capacity.
Above :data:`~bondgraph.linear.offsets.SYMBOLIC_MAX_STATES` states ``x0`` is
left to the numeric point.  The table gives the time of the first
``state_space()`` (derivation excluded) and of one numeric plant with its
point.

    python bench/bench_operating_point.py            # n = 4 8 16 32 40 80
    python bench/bench_operating_point.py 10 20
"""

from __future__ import annotations

import sys
import time


def build(n: int):
    import sympy

    import bondgraph as bg

    Ta = sympy.Symbol("Ta", positive=True)
    g = bg.BondGraph(f"chain{n}")
    g.add(bg.Sf("Q"), bg.Se("ambient", value=Ta))
    for i in range(n):
        g.add(bg.Zero(f"T{i}"), bg.C(f"C{i}"), bg.One(f"l{i}"), bg.R(f"R{i}"))
        g.connect(f"T{i}", f"C{i}")
        g.connect(f"T{i}", f"l{i}")
        g.connect(f"l{i}", f"R{i}")
    g.connect("Q", "T0")
    for i in range(n - 1):
        g.connect(f"l{i}", f"T{i + 1}")
    g.connect(f"l{n - 1}", "ambient")
    return bg.derive(g, outputs={"T": bg.effort(f"C{n - 1}")})


def main(sizes) -> None:
    import sympy

    import bondgraph as bg

    print(f"{'n':>4}  {'state_space (s)':>15}  {'x0 symbolic':>11}  {'plant (s)':>9}")
    for n in sizes:
        model = build(n)
        t0 = time.perf_counter()
        ss = model.state_space()
        t1 = time.perf_counter()
        op = ss.operating_point
        solved = bool(op.states)
        if solved:
            Q0, Ta = op.inputs["Q"], sympy.Symbol("Ta", positive=True)
            R = [sympy.Symbol(f"R{i}", positive=True) for i in range(n)]
            C0 = sympy.Symbol("C0", positive=True)
            assert sympy.expand(op.states["q_C0"] - C0 * (Ta + Q0 * sum(R))) == 0
        values = {f"{k}{i}": 1.0 + 0.1 * i for i in range(n) for k in "CR"}
        values["Ta"] = 293.15
        t2 = time.perf_counter()
        plant = bg.compile_plant(model).plant(values)
        t3 = time.perf_counter()
        assert abs(plant.operating_point.outputs["T"] - 293.15) < 1e-9
        print(f"{n:>4}  {t1 - t0:>15.2f}  {'yes' if solved else 'no':>11}  {t3 - t2:>9.3f}")


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [4, 8, 16, 32, 40, 80])
