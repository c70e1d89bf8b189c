"""Coefficients decided zero over the field of rational functions, never by printed form.

The coefficient of issue 22, ``-90*R/(64*R + 180) + 45*R/(32*R + 90)``, is 0 for
every ``R`` (``45 R/(32 R + 90)`` is ``90 R/(64 R + 180)``: multiply top and
bottom by 2), yet ``expr != 0`` says it is not.  Multiplying an unknown by it
made a linear loop look nonlinear.
"""

from __future__ import annotations

import pytest
import sympy

from bondgraph._support.zero import is_zero, reduced
from bondgraph.equations.loops import solve_blocks

R, S = sympy.symbols("R S", positive=True)
ZERO = -90 * R / (64 * R + 180) + 45 * R / (32 * R + 90)


def test_the_coefficient_of_the_issue_is_zero():
    assert ZERO != 0                  # the printed form does not say so
    assert is_zero(ZERO)
    assert is_zero(ZERO * S + ZERO ** 2)
    assert not is_zero(ZERO + 1 / R)
    assert not is_zero(sympy.sin(R) - sympy.cos(R))


def test_reduced_drops_a_vanishing_coefficient():
    x = sympy.Symbol("x")
    assert reduced(ZERO * x + 3 * x / R) == 3 * x / R


@pytest.mark.parametrize("order", [0, 1])
def test_linear_loop_with_a_vanishing_product_term(order):
    """z1 = x - R z1 + ZERO*z1*z2, z2 = z1/2: linear in the unknowns (ZERO = 0), so
    z1 = x/(R + 1), z2 = x/(2 (R + 1)); in either order of the unknowns."""
    z1, z2, x = sympy.symbols("z1 z2 x")
    eqs = [(z1, x - R * z1 + ZERO * z1 * z2), (z2, z1 / 2)]
    sol = solve_blocks(dict(eqs if order == 0 else eqs[::-1]), knowns={x}, what="loop",
                       model="m", states={})
    assert sympy.simplify(sol[z1] - x / (R + 1)) == 0
    assert sympy.simplify(sol[z2] - x / (2 * (R + 1))) == 0


def test_a_truly_nonlinear_loop_is_still_refused():
    import bondgraph as bg

    z1, z2, x = sympy.symbols("z1 z2 x")
    with pytest.raises(bg.AlgebraicLoopError, match="nonlinear in its unknowns"):
        solve_blocks({z1: x - R * z1 + z1 * z2 / R, z2: z1 / 2}, knowns={x}, what="loop",
                     model="m", states={})


def test_state_space_accepts_a_vanishing_constant_and_product():
    """A hand-built model whose equation holds ZERO as a constant term and ZERO*x*u: it is
    linear, A = -1/R, B = 1."""
    import bondgraph as bg
    from bondgraph.model import Model

    x, u = sympy.Symbol("x", real=True), sympy.Symbol("u", real=True)
    m = Model(name="z", augmented=None, states=(x,), inputs=(u,), output_names=("y",),
              rhs=(-x / R + u + ZERO + ZERO * x * u,), output_exprs=(x,), input_derivatives=(),
              descriptor=None, storage_states=1)
    ss = m.state_space()
    assert sympy.simplify(ss.A[0, 0] + 1 / R) == 0 and ss.B[0, 0] == 1
    bad = Model(name="z2", augmented=None, states=(x,), inputs=(u,), output_names=("y",),
                rhs=(-x / R + u + x**2 / R,), output_exprs=(x,), input_derivatives=(),
                descriptor=None, storage_states=1)
    with pytest.raises(bg.NonlinearModelError, match="nonlinear"):
        bad.state_space()
    # x u/R is linear in the state at a nominal input u0: the form about that equilibrium
    bilinear = Model(name="z3", augmented=None, states=(x,), inputs=(u,), output_names=("y",),
                     rhs=(-x / R + u + x * u / R,), output_exprs=(x,), input_derivatives=(),
                     descriptor=None, storage_states=1)
    ss = bilinear.state_space()
    u0 = ss.operating_point.inputs["u"]
    assert sympy.simplify(ss.A[0, 0] - (u0 - 1) / R) == 0
