"""Issue 23, item 10 (audit F02, F04, F04b, F05): a field's matrix checked wherever numbers meet it.

``plant()`` and ``batch()`` refused an indefinite mass matrix, but
``simulate`` ran it (a velocity of -1/3 under a positive force) and
``transfer_function(...).subs`` gave -1/(3s); a symbolically singular field
raised sympy's ``NonInvertibleMatrixError``.
"""

import pytest
import sympy

import bondgraph as bg
from bondgraph.elements.fields import FieldError

m = sympy.Symbol("m", positive=True)


def _field_model(matrix):
    g = bg.BondGraph("fld")
    g.add(bg.Se("F1"), bg.Se("F2"), bg.IField("M", matrix))
    g.connect("F1", "M")
    g.connect("F2", "M")
    return bg.derive(g, outputs={"v": bg.flow("M", port=1)})


INDEFINITE = [[m, 2 * m], [2 * m, m]]          # eigenvalues 3m and -m


def test_simulate_refuses_an_indefinite_field():
    with pytest.raises(FieldError, match=r"IF:M: the mass matrix is not positive definite \(smallest eigenvalue -1\)"):
        bg.simulate(_field_model(INDEFINITE), {"m": 1.0}, (0, 1), u=[1.0, 0.0])


def test_subs_refuses_an_indefinite_field():
    G = _field_model(INDEFINITE).transfer_function("F1", "v")
    with pytest.raises(FieldError, match="IF:M: the mass matrix is not positive definite"):
        G.subs({"m": 1.0})


def test_definite_field_still_simulates_and_matches_newton():
    """M = [[2m, m], [m, 2m]] at m = 1: v = M^-1 F t = (2/3, -1/3) t for F = (1, 0)."""
    model = _field_model([[2 * m, m], [m, 2 * m]])
    res = bg.simulate(model, {"m": 1.0}, (0, 1), u=[1.0, 0.0], t_eval=[1.0])
    assert res["v"][-1] == pytest.approx(2.0 / 3.0, rel=1e-6)
    G = model.transfer_function("F1", "v").subs({"m": 1.0})
    import numpy as np

    assert np.polyval(G.num, 2.0) / np.polyval(G.den, 2.0) == pytest.approx((2.0 / 3.0) / 2.0)


def test_singular_field_refused_naming_it():
    """F02: [[m, m], [m, m]] is singular for every m."""
    with pytest.raises(FieldError, match=r"IF:M: the mass matrix is singular for every parameter value"):
        _field_model([[m, m], [m, m]])
