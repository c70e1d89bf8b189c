"""Nonlinear differential verification in CI: random nonlinear graphs against the
independent DAE reference (``verification/nonlinear_reference.py``, no bondgraph code),
and the reference itself against closed forms.

The long run (thousands of graphs) is ``python bench/verify_nonlinear.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from verification import nonlinear as nl
from verification.nonlinear_reference import DAEReference, NElement, NGraph

#: seeds checked here (each graph is simulated, linearized at two points and trimmed:
#: about half a CPU second each), in chunks that pytest-xdist spreads over the workers
CI_SEEDS = range(200)
CHUNKS = 8


def msd(law="linear", params=(2.0,)):
    return NGraph(elements=(NElement("F", "Se", "input"), NElement("v", "One"),
                            NElement("m", "I", "linear", (1.0,)),
                            NElement("k", "C", law, params),
                            NElement("b", "R", "linear", (0.4,))),
                  bonds=(("F", "v"), ("v", "m"), ("v", "k"), ("v", "b")),
                  inputs={"F": (0.0, 0.0, 1.0)})


def test_reference_mass_spring_damper_against_the_closed_form():
    """m = 1, compliance 2 (k = 1/2), b = 0.4, free from q(0) = 1: q = e^{-0.2 t}
    (cos(w t) + 0.2/w sin(w t)), w = sqrt(0.5 - 0.04)."""
    ref = DAEReference(msd())
    t = np.linspace(0.0, 3.0, 7)
    x = ref.simulate(3.0, t, [0.0, 1.0])
    w = math.sqrt(0.5 - 0.04)
    q = np.exp(-0.2 * t) * (np.cos(w * t) + 0.2 / w * np.sin(w * t))
    assert x[:, 1] == pytest.approx(q, abs=1e-8)
    A, B = ref.jacobians([0.3, -0.2], [0.0])
    assert A == pytest.approx(np.array([[-0.4, -0.5], [1.0, 0.0]]), abs=1e-8)
    assert B == pytest.approx(np.array([[1.0], [0.0]]), abs=1e-8)


def test_reference_orifice_written_as_a_flow_law():
    """A flow source Q = 1 into a tank C = 1 drained by f = 0.5 e + sqrt(e): at rest
    0.5 e + sqrt(e) = 1, a quadratic in sqrt(e): sqrt(e) = -1 + sqrt(3), e = 4 - 2 sqrt(3)."""
    g = NGraph(elements=(NElement("Q", "Sf", "input"), NElement("z", "Zero"),
                         NElement("c", "C", "linear", (1.0,)),
                         NElement("o", "R", "orifice", (0.5, 1.0))),
               bonds=(("Q", "z"), ("z", "c"), ("z", "o")), inputs={"Q": (1.0, 0.0, 1.0)})
    ref = DAEReference(g)
    e = 4 - 2 * math.sqrt(3)
    assert ref.f([e], [1.0]) == pytest.approx([0.0], abs=1e-12)
    (found,) = {round(float(x[0]), 9) for x in ref.equilibria([1.0])}
    assert found == pytest.approx(e, abs=1e-9)


@pytest.mark.parametrize("chunk", range(CHUNKS))
def test_random_nonlinear_graphs_agree_with_the_reference(chunk):
    seeds = CI_SEEDS[chunk::CHUNKS]
    outcomes = [nl.check(nl.generate(seed), timeout=10.0) for seed in seeds]
    by_class = {c: [o.seed for o in outcomes if o.cls == c] for c in nl.CLASSES}
    details = {o.seed: o.detail for o in outcomes if o.cls in ("wrong", "crash", "timeout",
                                                                  "no-equilibrium-found")}
    assert not by_class["wrong"] and not by_class["crash"], details
    # seeds 0..199 at the time of writing: 196 agree (65 and 188 with storage in derivative
    # causality, against the reference's own index reduction; 38 and 150 need du/dt, their
    # x' compared at random points), 4 no-equilibrium-found ("not isolated" at a kink)
    assert len(by_class["agree"]) >= 0.85 * len(seeds), by_class
    # the comparisons actually ran: trajectories, Jacobians, equilibria
    checks = [o.checks for o in outcomes if o.cls == "agree" and o.checks   # {}: no states
              and "input_derivative_rhs" not in o.checks]        # not simulated: needs du/dt
    assert sum("trajectory" in c for c in checks) == len(checks)
    assert sum("jacobian" in c for c in checks) == len(checks)
    assert sum("equilibrium" in c for c in checks) >= len(checks) // 2


def test_reduced_reference_against_the_hand_derivation():
    """A compliance c fed through an MTF of ratio N = 2 + cos(q_c) (its own displacement)
    from a node held by the compliance k, under a flow source J (compliances c = 0.7,
    k = 0.4, a = c/k): q_c N = a q_k, and differentiating by hand,
    q_k' = J (N^2 - a q_k sin q_c) / (N^2 - a q_k sin q_c + a)."""
    from scipy.optimize import brentq

    from verification.nonlinear_reduced import ReducedReference

    g = NGraph(elements=(NElement("J", "Sf", "input"), NElement("m", "Zero"),
                         NElement("k", "C", "linear", (0.4,)),
                         NElement("M", "MTF", "mod", (1.0, 2.0), "c"), NElement("n", "Zero"),
                         NElement("c", "C", "linear", (0.7,))),
               bonds=(("J", "m"), ("m", "k"), ("m", "M"), ("M", "n"), ("n", "c")),
               inputs={"J": (0.5, 0.0, 1.0)})
    ref = ReducedReference(g, {"c"})
    assert ref.state_names == ("q_k",)
    a = 0.7 / 0.4
    for qk, J in [(0.5, 0.8), (-1.2, 0.3), (1.0, -1.0)]:     # q N(q) monotone there
        qc = brentq(lambda q: q * (2 + math.cos(q)) - a * qk, -10, 10, xtol=1e-15)
        D = (2 + math.cos(qc))**2 - a * qk * math.sin(qc)
        assert ref.f([qk], [J])[0] == pytest.approx(J * D / (D + a), rel=1e-9)


#: graphs with storage in derivative causality: compared against the reference's index
#: reduction (912 was refused before issue 29's index reduction: an MTF follows the
#: displacement of the compliance it feeds; 528 has its equilibrium at an orifice's kink,
#: where the reference's constrained solve once failed; in 1808 a saturating spring nears
#: its limit, where the reference's rates once failed to converge; 3862 once differed by
#: 1e-4 in a Jacobian: the reference's two-point differences near an orifice)
DEPENDENT = (65, 528, 912, 1808, 3862)


@pytest.mark.parametrize("seed", DEPENDENT)
def test_graphs_with_dependent_storage_agree(seed):
    o = nl.check(nl.generate(seed), timeout=20.0)
    assert o.cls == "agree" and "reduced" in o.checks and "trajectory" in o.checks, \
        (seed, o.cls, o.detail)


#: seeds the long run once answered wrongly or crashed on (fixed since): an accepted point
#: with a residual (321, 715: a huge slope of sqrt|x| near 0 made the Newton step look
#: converged), dg/dz singular at an equilibrium (529), an unevaluated derivative in an
#: implicit Jacobian (694, 1195, 1247, 1313), the SVD of an infinite slope (115, 134), a
#: slope read as sign(0)**2 = 0 at a kink of (sqrt(a|p| + b) - c) sign(p) (1727), an
#: Equilibrium's own z refused at an orifice's kink (1902), z not found beside such a kink
#: for central differences (3946, 3984, 4646), dg/dz singular at such a kink (4840, 4918)
ONCE_FAILING = (115, 134, 321, 529, 694, 715, 1195, 1247, 1313, 1727, 1902, 3946, 3984, 4646,
                4840, 4918)


@pytest.mark.parametrize("seed", ONCE_FAILING)
def test_seeds_that_once_failed(seed):
    o = nl.check(nl.generate(seed), timeout=20.0)
    assert o.cls not in ("wrong", "crash"), (seed, o.cls, o.detail)
