"""Term budgets of symbolic transfer functions: the bound before expansion and the refusal.

References: hand counts of the expanded determinants (a diagonal pencil of
``n`` entries with ``t`` terms each expands to ``t**n`` products; a modal
beam's ``det(sI - A)`` is the hub's factor times the ``n`` modes' factors),
and sympy's own expansion of the determinant for the bound's soundness.
"""

from __future__ import annotations

import pytest
import sympy as sp

import bondgraph as bg
from bondgraph.tf import transfer_function, transfer_matrix
from bondgraph.tf._budget import term_bound
from bondgraph.tf._encode import encode_system
from bondgraph.tf.errors import InvalidOptionError, TermBudgetError


def hub_beam(modes: int):
    """Hub angle/rate and ``modes`` modal coordinates (eta_i, eta_i'), tip deflection."""
    J, b, K, R, Lb = sp.symbols("J b K R L_b", positive=True)
    m = sp.symbols(f"m1:{modes + 1}", positive=True)
    k = sp.symbols(f"k1:{modes + 1}", positive=True)
    c = sp.symbols(f"c1:{modes + 1}", positive=True)
    g = sp.symbols(f"g1:{modes + 1}", positive=True)
    h = sp.symbols(f"h1:{modes + 1}", positive=True)
    n = 2 + 2 * modes
    A, B, C = sp.zeros(n, n), sp.zeros(n, 1), sp.zeros(1, n)
    A[0, 1] = 1
    A[1, 1] = -(b + K**2 / R) / J
    B[1, 0] = K / (R * J)
    C[0, 0] = Lb
    for i in range(modes):
        e, v = 2 + 2 * i, 3 + 2 * i
        A[e, v] = 1
        A[v, e] = -k[i] / m[i]
        A[v, v] = -c[i] / m[i]
        A[v, 1] = -g[i] * K**2 / (R * m[i])
        B[v, 0] = g[i] * K / (R * m[i])
        C[0, e] = h[i]
    return A, B, C, sp.zeros(1, 1)


def _encoded(A, B, C, D):
    return encode_system(sp.Matrix(A), sp.Matrix(B), sp.Matrix(C), sp.Matrix(D), None,
                         sp.Symbol("s"))


def test_diagonal_pencil_bound_is_the_product_of_the_term_counts():
    a = sp.symbols("a1:6")
    A = sp.diag(*[-(x + 1) for x in a])          # s + a_i + 1: three terms each
    enc = _encoded(A, sp.ones(5, 1), sp.ones(1, 5), sp.zeros(1, 1))
    assert term_bound(enc.pencil(), enc.ring) == 3 ** 5


def test_bound_is_an_upper_bound_of_sympys_expansion():
    A, B, C, D = hub_beam(2)
    s = sp.Symbol("s")
    enc = _encoded(A, B, C, D)
    bound = term_bound(enc.pencil(), enc.ring)
    # sympy's expansion of det(sI - A), reciprocals kept as they are (what the ring holds)
    det = sp.expand((s * sp.eye(A.shape[0]) - A).det(method="berkowitz"))
    assert bound >= len(sp.Add.make_args(det))
    # nothing cancels or merges in this star of second-order blocks: the bound is exact
    assert bound == len(sp.Add.make_args(det))


def test_refused_before_expansion_naming_the_budget():
    A, B, C, D = hub_beam(6)
    with pytest.raises(TermBudgetError, match=r"max_terms=1,000.*refused before expansion") as info:
        transfer_function(A, B, C, D, input_names=["V"], output_names=["y"], max_terms=1000)
    assert isinstance(info.value, bg.BondGraphError) and isinstance(info.value, ValueError)
    assert "V -> y" in str(info.value)
    with pytest.raises(TermBudgetError, match="transfer matrix"):
        transfer_matrix(A, B, C, D, max_terms=1000)


def test_budget_refuses_a_twenty_mode_beam_and_none_disables():
    A, B, C, D = hub_beam(20)
    with pytest.raises(TermBudgetError, match=r"\d{2,3},\d{3},\d{3},\d{3} terms"):
        transfer_function(A, B, C, D, max_terms=10_000_000_000)
    with pytest.raises(TermBudgetError, match=r"\d{3},\d{3},\d{3} terms"):
        transfer_function(*hub_beam(14), max_terms=30_000_000)
    G = transfer_function(*hub_beam(1), max_terms=None)
    assert G.den.degree() == 4                          # hub (2 states) and one mode (2)


@pytest.mark.parametrize("bad", [0, -5, 2.5, True, "many"])
def test_bad_budget_is_an_option_error(bad):
    with pytest.raises(InvalidOptionError, match="max_terms"):
        transfer_function(*hub_beam(1), max_terms=bad)


def test_budget_reaches_the_model_method():
    g = bg.BondGraph("msd")
    F, v = bg.Se("F"), bg.One("v")
    g.add(F, v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
    for t, h in [(F, v), (v, "m"), (v, "b"), (v, "k")]:
        g.connect(t, h)
    model = bg.derive(g, outputs={"x": bg.displacement("k")})
    with pytest.raises(TermBudgetError):
        model.transfer_function("F", "x", max_terms=2)
    # 1/(m s^2 + b s + k): within a budget of 100
    G = model.transfer_function("F", "x", max_terms=100, normalize="as-derived")
    m, b, k = sp.symbols("m b k", positive=True)
    s = sp.Symbol("s")
    assert sp.simplify(G.expr - 1 / (m * s**2 + b * s + k)) == 0      # Newton: m x'' + b x' + k x = F
