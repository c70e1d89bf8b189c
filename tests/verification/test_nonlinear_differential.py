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
    # seeds 0..199 at the time of writing: 194 agree, 2 refused, 4 derivative causality
    assert len(by_class["agree"]) >= 0.85 * len(seeds), by_class
    # the comparisons actually ran: trajectories, Jacobians, equilibria
    checks = [o.checks for o in outcomes if o.cls == "agree" and o.checks]   # {}: no states
    assert sum("trajectory" in c for c in checks) == len(checks)
    assert sum("jacobian" in c for c in checks) == len(checks)
    assert sum("equilibrium" in c for c in checks) >= len(checks) // 2


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
