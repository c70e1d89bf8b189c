"""Steady states of networks with conserved quantities, the totals given: an enzyme
(Michaelis-Menten) and a floating charge.

Hand derivations, written here.

Enzyme ``E + S <-> C <-> E + P`` in mass-action form (species with ``K = 1``,
so each reaction's flux is ``kf prod(substrates) - kr prod(products)``), the
substrate ``S`` and the product ``P`` chemostatted at ``xS`` and ``xP``:

    v1 = k1 xS E - km1 C,      v2 = k2 C - km2 xP E,
    E' = -v1 + v2,             C' = v1 - v2.

``E + C = E_T`` is conserved (the free plus the bound enzyme), so ``E' = -C'``
and the two equations leave the steady state free until ``E_T`` is given.
``C' = 0`` with ``E = E_T - C``:

    C = E_T (k1 xS + km2 xP) / (k1 xS + km2 xP + km1 + k2),

and the flux ``v = v2``.  With no product (``xP = 0``) this is Michaelis and
Menten's ``v = Vmax xS/(Km + xS)``, ``Vmax = k2 E_T``, ``Km = (km1 + k2)/k1``.

Floating charge: capacitors ``C1`` and ``C2`` exchanging charge through
``R``: ``q1' = -(q1/C1 - q2/C2)/R = -q2'``; ``q1 + q2 = Q`` is conserved and
the equilibrium ``q1/C1 = q2/C2`` gives ``q1 = C1 Q/(C1 + C2)``.
"""

from __future__ import annotations

import pytest
import sympy

import bondgraph as bg
from bondgraph.library.chemical import ReactionNetwork, conservation_laws
from bondgraph.linear import EquilibriumError, OperatingPointError

k1, km1, k2, km2, xS, xP, ET = sympy.symbols("k1 km1 k2 km2 x_S x_P E_T", positive=True)
MOIETY = ("q_E", "q_C")


def enzyme() -> tuple[bg.Model, bg.BondGraph]:
    net = ReactionNetwork("mm")
    E, C = net.species("E", K=1), net.species("C", K=1)
    S, P = net.chemostat("S", K=1, amount=xS), net.chemostat("P", K=1, amount=xP)
    net.reaction("r1", E + S, C, kf=k1, kr=km1)
    net.reaction("r2", C, E + P, kf=k2, kr=km2)
    g = net.graph()
    return bg.derive(g, outputs={"v": bg.flow("r2_r")}), g


def test_symbolic_steady_state_with_the_enzyme_total():
    model, g = enzyme()
    assert conservation_laws(g) == ({"E": 1, "C": 1},)
    op = model.operating_point(totals={MOIETY: ET})
    bound = ET * (k1 * xS + km2 * xP) / (k1 * xS + km2 * xP + km1 + k2)
    assert sympy.simplify(op.states["q_C"] - bound) == 0
    assert sympy.simplify(op.states["q_E"] - (ET - bound)) == 0
    flux = k2 * bound - km2 * xP * (ET - bound)
    assert sympy.simplify(op.outputs["v"] - flux) == 0
    # no product: Michaelis-Menten
    Km = (km1 + k2) / k1
    assert sympy.simplify(op.outputs["v"].subs(xP, 0) - k2 * ET * xS / (Km + xS)) == 0


@pytest.mark.parametrize("xs", [0.1, 1.0, 4.0, 40.0], ids=lambda v: f"xS={v}")
def test_numeric_steady_state_is_michaelis_menten(xs):
    model, _ = enzyme()
    vals = {"k1": 2.0, "km1": 1.0, "k2": 3.0, "km2": 0.5, "x_S": xs, "x_P": 0.0}
    eq = model.equilibrium(vals, totals={MOIETY: 1.5})
    Km, Vmax = (1.0 + 3.0) / 2.0, 3.0 * 1.5
    bound = 1.5 * xs / (Km + xs)
    assert eq.states["q_C"] == pytest.approx(bound, rel=1e-10)
    assert eq.states["q_E"] + eq.states["q_C"] == pytest.approx(1.5, rel=1e-12)
    assert eq.stability == "stable"          # the moiety's zero eigenvalue left out
    op = model.operating_point(values=vals, totals={MOIETY: 1.5})
    assert op.outputs["v"] == pytest.approx(Vmax * xs / (Km + xs), rel=1e-10)


def test_without_the_total_the_error_names_the_moiety():
    model, _ = enzyme()
    vals = {"k1": 2.0, "km1": 1.0, "k2": 3.0, "km2": 0.5, "x_S": 4.0, "x_P": 0.0}
    with pytest.raises(EquilibriumError, match=r"conserved: q_C \+ q_E.*totals="):
        model.equilibrium(vals)
    with pytest.raises(OperatingPointError, match=r"totals=\{\('q_C', 'q_E'\)"):
        model.operating_point()
    with pytest.raises(OperatingPointError, match="q_E is not conserved"):
        model.operating_point(totals={"q_E": ET})
    with pytest.raises(OperatingPointError, match="names no state"):
        model.operating_point(totals={("q_E", "E"): ET})


def test_floating_charge():
    g = bg.BondGraph("float")
    g.add(bg.Zero("a"), bg.Zero("b"), bg.One("i"), bg.C("C1"), bg.C("C2"), bg.R("R"))
    for tail, head in [("a", "C1"), ("a", "i"), ("i", "R"), ("i", "b"), ("b", "C2")]:
        g.connect(tail, head)
    model = bg.derive(g)
    C1, C2, Q = sympy.Symbol("C1", positive=True), sympy.Symbol("C2", positive=True), sympy.Symbol("Q")
    q1, q2 = model.states
    op = model.operating_point(totals={q1 + q2: Q})            # a sympy expression as the key
    assert sympy.simplify(op.states["q_C1"] - C1 * Q / (C1 + C2)) == 0
    eq = model.equilibrium({"C1": 1e-6, "C2": 3e-6, "R": 1e3}, totals={("q_C1", "q_C2"): 4e-6})
    assert eq.states["q_C1"] == pytest.approx(1e-6, rel=1e-9)
    assert eq.states["q_C2"] == pytest.approx(3e-6, rel=1e-9)
