"""Linear algebraic loops: exact and fraction-free while small, kept as linear
algebraic unknowns past the term budget (issue 23: the symbolic resistive ladder).

References are independent of the package: nodal analysis (Kirchhoff's current
law solved with numpy) and the ladder's continued fraction, both written here.
"""

import random
import warnings

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.equations.fraction_free import SINGULAR, TOO_LARGE, solve_fraction_free
from bondgraph.equations.loops import LOOP_TERM_BUDGET


def ladder(n: int) -> bg.BondGraph:
    """Se V -> (series Rs_i, shunt Rp_i) x n -> C, every parameter symbolic."""
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


def nodal(n: int, vals: dict) -> tuple[float, float, float, float]:
    """``(A, B, C_i, D_i)`` of dq/dt = A q + B V and i_Rs0 = C_i q + D_i V by Kirchhoff.

    Internal nodes 0..n-2 (node n-1 is the capacitor's, at q/C; node -1 the
    source's, at V); the node voltages solve the conductance system.
    """
    def currents(q: float, V: float) -> tuple[float, float]:
        vc = q / vals["C"]
        m = n - 1
        G = np.zeros((m, m))
        rhs = np.zeros(m)
        for k in range(m):
            gs, gp, gn = 1 / vals[f"Rs{k}"], 1 / vals[f"Rp{k}"], 1 / vals[f"Rs{k + 1}"]
            G[k, k] = gs + gp + gn
            if k > 0:
                G[k, k - 1] = -gs
            else:
                rhs[k] += gs * V
            if k < m - 1:
                G[k, k + 1] = -gn
            else:
                rhs[k] += gn * vc
        e = np.linalg.solve(G, rhs)
        i_c = (e[-1] - vc) / vals[f"Rs{n - 1}"] - vc / vals[f"Rp{n - 1}"]
        i_0 = (V - e[0]) / vals["Rs0"]
        return i_c, i_0
    a, c = currents(1.0, 0.0)
    b, d = currents(0.0, 1.0)
    return a, b, c, d


def thevenin(n: int, vals: dict):
    """The continued fraction: Thevenin resistance and voltage ratio seen by the capacitor."""
    Z, ratio = vals["Rs0"], 1
    for k in range(n - 1):
        Rp = vals[f"Rp{k}"]
        ratio = ratio * Rp / (Rp + Z)
        Z = Z * Rp / (Z + Rp) + vals[f"Rs{k + 1}"]
    Rp = vals[f"Rp{n - 1}"]
    return Z * Rp / (Z + Rp), ratio * Rp / (Rp + Z)


def values(n: int, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    vals = {f"Rs{i}": float(rng.uniform(0.05, 0.5)) for i in range(n)}
    vals |= {f"Rp{i}": float(rng.uniform(20.0, 60.0)) for i in range(n)}
    vals["C"] = float(rng.uniform(0.2, 2.0))
    return vals


@pytest.fixture(scope="module")
def ladder40():
    return bg.derive(ladder(40), outputs={"v": bg.effort("C"), "i": bg.flow("Rs0")})


def test_forty_section_symbolic_ladder_keeps_linear_algebraic_unknowns(ladder40):
    assert len(ladder40.algebraic) == 39
    assert all("linear algebraic loop" in o and "LOOP_TERM_BUDGET" in o
               for o in ladder40.algebraic_origin)
    assert ladder40.is_implicit


def test_forty_section_plant_equals_kirchhoff_and_the_continued_fraction(ladder40):
    n = 40
    vals = values(n, 1)
    plant = bg.compile_plant(ladder40).plant(vals)
    A, B, Ci, Di = nodal(n, vals)
    R_th, ratio = thevenin(n, vals)
    assert plant.A[0, 0] == pytest.approx(A, rel=1e-9)
    assert plant.A[0, 0] == pytest.approx(-1 / (vals["C"] * R_th), rel=1e-9)
    assert plant.B[0, 0] == pytest.approx(B, rel=1e-9)
    assert plant.B[0, 0] == pytest.approx(ratio / R_th, rel=1e-9)
    out = list(plant.output_names)
    assert plant.C[out.index("v"), 0] == pytest.approx(1 / vals["C"], rel=1e-12)
    assert plant.D[out.index("v"), 0] == 0
    assert plant.C[out.index("i"), 0] == pytest.approx(Ci, rel=1e-9, abs=1e-14)
    assert plant.D[out.index("i"), 0] == pytest.approx(Di, rel=1e-9)
    # the transfer function V -> v is B/C / (s - A): checked at one frequency
    H = plant.frequency_response([2.0])
    expect = (1 / vals["C"]) * B / (2.0j - A)
    assert np.asarray(H)[out.index("v"), 0, 0] == pytest.approx(expect, rel=1e-9)


def test_sparse_plant_and_batch_agree_with_kirchhoff(ladder40):
    n = 40
    nm = bg.compile_plant(ladder40)
    first, second = values(n, 2), values(n, 3)
    sparse = nm.plant(first, sparse=True)
    A, B, _, _ = nodal(n, first)
    assert sparse.A.toarray()[0, 0] == pytest.approx(A, rel=1e-9)
    assert sparse.B.toarray()[0, 0] == pytest.approx(B, rel=1e-9)
    batch = nm.batch({k: [first[k], second[k]] for k in first})
    for row, vals in enumerate((first, second)):
        A, B, _, _ = nodal(n, vals)
        assert batch.A[row, 0, 0] == pytest.approx(A, rel=1e-9)
        assert batch.B[row, 0, 0] == pytest.approx(B, rel=1e-9)


def test_symbolic_forms_of_the_kept_loop_are_refused_naming_the_unknowns(ladder40):
    with pytest.raises(bg.NonlinearModelError, match="f_Rs.*compile_plant"):
        ladder40.transfer_function("V", "v")
    with pytest.raises(bg.NonlinearModelError, match="implicit"):
        ladder40.state_space()


def test_small_ladders_stay_explicit_and_exact():
    """Six sections fit the budget: one reduced fraction, the continued fraction exactly."""
    n = 6
    model = bg.derive(ladder(n))
    assert not model.algebraic
    rng = random.Random(5)
    vals = {f"Rs{i}": sympy.Rational(rng.randint(1, 9), rng.randint(1, 5)) for i in range(n)}
    vals |= {f"Rp{i}": sympy.Rational(rng.randint(1, 9), rng.randint(1, 5)) for i in range(n)}
    vals["C"] = sympy.Rational(3, 7)
    R_th, ratio = thevenin(n, vals)
    (q,), (V,) = model.states, model.inputs
    rhs = model.rhs[0].xreplace({p: vals[p.name] for p in model.parameters})
    assert sympy.simplify(sympy.diff(rhs, q) + 1 / (vals["C"] * R_th)) == 0
    assert sympy.simplify(sympy.diff(rhs, V) - ratio / R_th) == 0


def test_simulated_step_of_a_kept_loop_is_the_exponential():
    n = 9
    model = bg.derive(ladder(n), outputs={"v": bg.effort("C")})
    assert model.algebraic            # 9 sections pass the budget
    vals = values(n, 4)
    A, B, _, _ = nodal(n, vals)
    t = np.linspace(0.0, 2.0 / abs(A), 7)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = bg.simulate(model, vals, (0.0, t[-1]), u={"V": 1.0}, t_eval=t, rtol=1e-10,
                          atol=1e-12)
    q = -B / A * (1 - np.exp(A * t))
    assert np.asarray(res.y)[:, 0] == pytest.approx(q / vals["C"], rel=1e-6, abs=1e-9)


# --------------------------------------------------------------- the solver itself
def _random_matrix(rng, syms, n, cols):
    def entry():
        if rng.random() < 0.3:
            return 0
        a, b = rng.sample(syms, 2)
        return rng.choice([a, a / b, a + 1 / b, 1 + a * b,
                           sympy.Rational(rng.randint(-3, 3), rng.randint(1, 3))])
    return sympy.Matrix(n, n, lambda i, j: entry()), sympy.Matrix(n, cols, lambda i, j: entry())


def test_fraction_free_solutions_equal_exact_rational_elimination():
    """Random matrices of sums of reciprocals and products: the solution at random
    rational points equals sympy's exact LU solve of the substituted matrix."""
    rng = random.Random(11)
    syms = list(sympy.symbols("a b c d e f g h"))
    checked = 0
    for _ in range(60):
        n = rng.randint(1, 4)
        M, R = _random_matrix(rng, syms, n, 2)
        got = solve_fraction_free(M, R, budget=10**6)
        point = {s: sympy.Rational(rng.randint(1, 9), rng.randint(1, 7)) for s in syms}
        Mn, Rn = M.xreplace(point), R.xreplace(point)
        if Mn.det() == 0:
            continue
        assert not isinstance(got, str)
        assert got.xreplace(point) == Mn.LUsolve(Rn)
        checked += 1
    assert checked > 30


def test_fraction_free_singular_and_budget():
    a, b = sympy.symbols("a b")
    M = sympy.Matrix([[a, b], [2 * a, 2 * b]])          # rank 1 for every a, b
    assert solve_fraction_free(M, sympy.Matrix([[1], [0]]), budget=100) == SINGULAR
    M = sympy.Matrix([[1 / a + 1 / b, 1], [1, a + b]])
    assert solve_fraction_free(M, sympy.Matrix([[1], [1]]), budget=2) == TOO_LARGE
    assert LOOP_TERM_BUDGET >= 1000
