"""The symbolic resistive ladder: derive time, loop handling and answer size (issue 23).

The ladder ``Se V -> (series Rs_i, shunt Rp_i) x n -> C`` has one state q_C;
its exact state equation is ``dq/dt = (V_th - q/C) / R_th`` with ``V_th``
and ``R_th`` the Thevenin equivalent, a continued fraction of the 2n
resistances.  Written as one reduced fraction, the numerator of the q
coefficient is the continuant of the 2n resistances, which has Fibonacci
F(2n+1) monomials: 2, 5, 13, 34, 89, 233, ... (about 2.6^n); a 40-section
ladder's reduced answer would have F(81) ~ 3.8e16 monomials.  No algorithm
producing that expanded fraction can be polynomial in n.

So the loop is solved exactly (fraction-free elimination) while its working
matrix stays within ``LOOP_TERM_BUDGET`` terms, and past it is kept as linear
algebraic unknowns that ``compile_plant`` eliminates numerically.  This script
prints, per size: derive seconds, the number of algebraic unknowns kept, the
q coefficient's monomials when explicit (against F(2n+1)), compile + plant
seconds, and the plant's A against the continued fraction at random values.

Run:  PYTHONPATH=$PWD python bench/ladder_terms.py [sizes...]   (default 3 5 6 7 10 20 40)
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


def continued_fraction(n, vals):
    """-1/(C R_th): R_th seen by the capacitor, by the continued fraction."""
    Z = vals["Rs0"]
    for k in range(n - 1):
        Rp = vals[f"Rp{k}"]
        Z = Z * Rp / (Z + Rp) + vals[f"Rs{k + 1}"]
    Rp = vals[f"Rp{n - 1}"]
    return -1.0 / (vals["C"] * Z * Rp / (Z + Rp))


def main(sizes):
    import random

    print(f"{'sections':>8} {'derive s':>9} {'kept z':>6} {'monomials':>10} {'F(2n+1)':>10} "
          f"{'plant s':>8} {'A rel. err':>10}")
    for n in sizes:
        t0 = time.perf_counter()
        model = bg.derive(ladder(n))
        dt = time.perf_counter() - t0
        terms = "-"
        if not model.algebraic:
            q = model.states[0]
            coeff = sympy.together(sympy.diff(model.rhs[0], q))
            num, _ = sympy.fraction(coeff)
            terms = len(sympy.Add.make_args(sympy.expand(num)))
        rng = random.Random(n)
        vals = {f"R{kind}{i}": rng.uniform(0.5, 3.0) for kind in "sp" for i in range(n)}
        vals["C"] = 0.7
        t0 = time.perf_counter()
        plant = bg.compile_plant(model).plant(vals)
        pt = time.perf_counter() - t0
        ref = continued_fraction(n, vals)
        err = abs(plant.A[0, 0] - ref) / abs(ref)
        print(f"{n:>8} {dt:>9.2f} {len(model.algebraic):>6} {terms:>10} "
              f"{fibonacci(2 * n + 1):>10} {pt:>8.2f} {err:>10.1e}")


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [3, 5, 6, 7, 10, 20, 40])
