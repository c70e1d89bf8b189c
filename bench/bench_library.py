"""Benchmark: reaction networks and the dimensional check on growing graphs.

A linear chain of reactions ``X0 = X1 = ... = XN`` (N reactions, N + 1
species, every ``K`` and ``r`` a symbol) is built with the reaction builder,
derived, and its stoichiometric matrix and conservation law computed; a
chain of N masses and springs (library components, every parameter with
units) is checked dimensionally.  Times are wall-clock seconds of one run.

    python bench/bench_library.py            # N = 10, 40, 160
    python bench/bench_library.py 20 80      # chosen sizes
"""

from __future__ import annotations

import sys
import time


def reaction_chain(n: int):
    from bondgraph.library.chemical import ReactionNetwork

    net = ReactionNetwork(f"chain{n}")
    species = [net.species(f"X{i}") for i in range(n + 1)]
    for i in range(n):
        net.reaction(f"r{i}", species[i], species[i + 1])
    return net


def mass_chain(n: int):
    import sympy.physics.units as u

    import bondgraph as bg
    from bondgraph.library import mechanical as me

    g = bg.BondGraph(f"masses{n}")
    g.add(me.ForceSource("F"))
    values = {}
    prev = "F.p"
    for i in range(n):
        g.add(bg.One(f"v{i}"), me.Mass(f"m{i}", mass=f"m{i}"),
              me.Spring(f"k{i}", stiffness=f"k{i}"))
        g.connect(prev, f"v{i}")
        g.connect(f"v{i}", f"m{i}.p")
        g.connect(f"v{i}", f"k{i}.a")
        prev = f"k{i}.b"
        values[f"m{i}"] = 1 * u.kilogram
        values[f"k{i}"] = 2 * u.newton / u.millimeter
    g.add(me.Fixed("wall"))
    g.connect(prev, "wall.p")
    return g, values


def main(sizes) -> None:
    import bondgraph as bg
    from bondgraph.library.chemical import conservation_laws, stoichiometric_matrix
    from bondgraph.library.units import check_units

    print(f"{'N':>5} {'derive':>8} {'N matrix':>9} {'moieties':>9} {'units check':>12}")
    for n in sizes:
        net = reaction_chain(n)
        t0 = time.perf_counter()
        bg.derive(net.graph())
        t1 = time.perf_counter()
        stoichiometric_matrix(net.graph())
        t2 = time.perf_counter()
        laws = conservation_laws(net.graph())
        t3 = time.perf_counter()
        assert len(laws) == 1 and set(laws[0].values()) == {1}
        g, values = mass_chain(n)
        t4 = time.perf_counter()
        rep = check_units(g, values)
        t5 = time.perf_counter()
        assert not rep.unchecked
        print(f"{n:>5} {t1 - t0:>8.2f} {t2 - t1:>9.2f} {t3 - t2:>9.2f} {t5 - t4:>12.2f}")


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [10, 40, 160])
