"""Why the symbolic resistive ladder's derivation grows exponentially (issue 23, item 3).

The ladder ``Se V -> (series Rs_i, shunt Rp_i) x n -> C`` has one state q_C;
its exact state equation is ``dq/dt = (V_th - q/C) / R_th`` with ``V_th``
and ``R_th`` the Thevenin equivalent, a continued fraction of the 2n
resistances.  Written as one reduced fraction (what ``derive`` returns:
loop solutions are reduced in the field of rational functions), the
numerator of the q coefficient is the continuant of the 2n resistances,
which has Fibonacci F(2n+1) monomials: 2, 5, 13, 34, 89, 233, ... (about
2.6^n).  No algorithm producing the expanded reduced fraction can be
polynomial in n; a 40-section ladder's answer has F(81) ~ 3.8e16 monomials.
A 40-section ladder in seconds needs nested (continued-fraction) results,
i.e. a different tearing of the loop in the equation builder, not a faster
solver.  This script measures time and monomial counts against F(2n+1).

Run:  PYTHONPATH=$PWD python bench/ladder_terms.py [max_sections]   (default 5)
"""

import sys
import time

import sympy

import bondgraph as bg


def ladder(n):
    g = bg.BondGraph("lad")
    g.add(bg.Se("V"))
    prev = "V"
    for i in range(n):
        g.add(bg.One(f"s{i}"), bg.Zero(f"p{i}"), bg.R(f"Rs{i}"), bg.R(f"Rp{i}"))
        for t, h in [(prev, f"s{i}"), (f"s{i}", f"Rs{i}"), (f"s{i}", f"p{i}"), (f"p{i}", f"Rp{i}")]:
            g.connect(t, h)
        prev = f"p{i}"
    g.add(bg.C("C"))
    g.connect(prev, "C")
    return g


def fibonacci(k):
    a, b = 0, 1
    for _ in range(k):
        a, b = b, a + b
    return a


def main(top):
    print(f"{'sections':>8} {'derive s':>9} {'monomials':>10} {'F(2n+1)':>8}")
    for n in range(1, top + 1):
        t0 = time.perf_counter()
        model = bg.derive(ladder(n))
        dt = time.perf_counter() - t0
        q = sympy.Symbol("q_C", real=True)
        coeff = sympy.together(sympy.diff(model.rhs[0], q))
        num, _ = sympy.fraction(coeff)
        terms = len(sympy.Add.make_args(sympy.expand(num)))
        print(f"{n:>8} {dt:>9.2f} {terms:>10} {fibonacci(2 * n + 1):>8}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
