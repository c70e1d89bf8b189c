"""Orders of the infinite zeros of MIMO pairs against transfer matrices written by hand.

The transfer matrix is built here from Newton's equations of a chain of
masses and springs, ``(M s^2 + K) X = P F`` (``M`` diagonal masses, ``K`` the
stiffness matrix of the springs, ``P`` where each force acts), and the orders
of its infinite zeros taken from the Smith-McMillan form at infinity by the
classical minor rule: with ``sigma_k`` the least relative degree (degree of
denominator minus degree of numerator) over the nonzero ``k x k`` minors,
``n_k = sigma_k - sigma_(k-1)``.  The engine must give the same orders from
the disjoint causal paths of the bond graph and from its Markov parameters.
"""

from __future__ import annotations

import itertools

import pytest
import sympy

import bondgraph as bg
from bondgraph.structure import StructureError, infinite_zeros

s = sympy.Symbol("s")


def _orders(G: sympy.Matrix) -> tuple[int, ...]:
    sig = [0]
    for k in range(1, min(G.shape) + 1):
        best = None
        for rows in itertools.combinations(range(G.rows), k):
            for cols in itertools.combinations(range(G.cols), k):
                minor = sympy.cancel(G.extract(list(rows), list(cols)).det())
                if minor == 0:
                    continue
                num, den = sympy.fraction(minor)
                rd = sympy.degree(den, s) - sympy.degree(num, s)
                best = rd if best is None else min(best, rd)
        if best is None:
            break
        sig.append(best)
    return tuple(b - a for a, b in zip(sig, sig[1:]))


def chain(n_masses: int, forces: dict):
    """Masses m1..mn joined by springs k1..k(n-1); forces {name: mass index}."""
    g = bg.BondGraph("chain")
    vs = [bg.One(f"v{i}") for i in range(1, n_masses + 1)]
    g.add(*vs, *(bg.I(f"m{i}") for i in range(1, n_masses + 1)))
    for i, v in enumerate(vs, 1):
        g.connect(v, f"m{i}")
    for i in range(1, n_masses):
        sj = bg.Zero(f"s{i}")
        g.add(sj, bg.C(f"k{i}", stiffness=f"k{i}"))
        g.connect(vs[i - 1], sj)
        g.connect(sj, f"k{i}")
        g.connect(sj, vs[i])
    for name, i in forces.items():
        g.add(bg.Se(name))
        g.connect(name, vs[i - 1])
    return g


def newton(n_masses: int, force_at: list[int], sensed: list[int]) -> sympy.Matrix:
    """X/F of the chain by hand: (M s^2 + K) X = P F, rows of the sensed masses."""
    m = sympy.symbols(f"m1:{n_masses + 1}", positive=True)
    k = sympy.symbols(f"k1:{n_masses}", positive=True)
    M = sympy.diag(*m)
    K = sympy.zeros(n_masses)
    for i, ki in enumerate(k):
        K[i, i] += ki
        K[i + 1, i + 1] += ki
        K[i, i + 1] -= ki
        K[i + 1, i] -= ki
    P = sympy.zeros(n_masses, len(force_at))
    for c, i in enumerate(force_at):
        P[i - 1, c] = 1
    X = (M * s**2 + K).LUsolve(P)
    return sympy.Matrix([[sympy.cancel(X[i - 1, c]) for c in range(len(force_at))]
                         for i in sensed])


def test_two_masses_two_forces_two_positions_orders_two_two():
    expected = _orders(newton(2, [1, 2], [1, 2]))
    assert expected == (2, 2)
    model = bg.derive(chain(2, {"F1": 1, "F2": 2}),
                      outputs={"x1": bg.displacement("m1"), "x2": bg.displacement("m2")})
    iz = infinite_zeros(model)
    assert iz.orders == iz.structural_orders == expected
    assert iz.rank == 2 and len(iz.paths) == 2


def test_three_masses_end_forces_orders_two_four():
    # F1 on m1, F3 on m3, positions of m1 and m2: disjoint paths F1 -> x1 (2 integrations)
    # and F3 -> x2 (4): orders 2 and 4
    expected = _orders(newton(3, [1, 3], [1, 2]))
    assert expected == (2, 4)
    model = bg.derive(chain(3, {"F1": 1, "F3": 3}),
                      outputs={"x1": bg.displacement("m1"), "x2": bg.displacement("m2")})
    iz = infinite_zeros(model)
    assert iz.orders == iz.structural_orders == expected
    assert iz.lengths == (2, 6)
    assert sorted(p[0] + ">" + p[-1] for p in iz.paths) == ["F1>x1", "F3>x2"]
    assert "orders [2, 4]" in str(iz)


def test_velocity_outputs_and_a_single_channel():
    # velocities: one integration less; a 1x1 selection is the relative degree
    vel = newton(3, [1, 3], [1, 2]) * s
    expected = _orders(vel)
    assert expected == (1, 3)
    model = bg.derive(chain(3, {"F1": 1, "F3": 3}),
                      outputs={"v1": bg.flow("m1"), "v2": bg.flow("m2")})
    assert infinite_zeros(model).orders == expected
    one = infinite_zeros(model, "F3", "v1")
    assert one.orders == _orders(vel[0:1, 1:2]) == (5,)


def test_rank_deficient_selection():
    # both forces on m1: G has rank 1, one infinite zero
    expected = _orders(newton(2, [1, 1], [1, 2]))
    assert expected == (2,)
    model = bg.derive(chain(2, {"Fa": 1, "Fb": 1}),
                      outputs={"x1": bg.displacement("m1"), "x2": bg.displacement("m2")})
    iz = infinite_zeros(model)
    assert iz.orders == expected and iz.rank == 1
    # every causal path from either force passes through the state of m1: no two are disjoint
    assert iz.structural_rank == 1 and iz.structural_orders == expected
    assert iz.paths[0][1] == "p_m1"


def test_unknown_channel_is_named():
    model = bg.derive(chain(2, {"F1": 1}), outputs={"x1": bg.displacement("m1")})
    with pytest.raises(StructureError, match="no input 'F9'"):
        infinite_zeros(model, "F9")
