"""Structural analyses on small models derived by hand (Newton, Kirchhoff).

Every expected value is written here from the physics, not from the engine:

* a mass ``m`` driven by a force ``F`` with a position sensor:
  ``m x'' = F`` so ``x/F = 1/(m s^2)``: relative degree 2, no zeros;
* two masses and a spring, force on ``m1``: with ``K = k``,
  ``x1/F = (m2 s^2 + k) / (s^2 (m1 m2 s^2 + k (m1 + m2)))`` (zeros ``+-j sqrt(k/m2)``,
  relative degree 2) and ``x2/F = k / (s^2 (m1 m2 s^2 + k (m1 + m2)))``
  (relative degree 4, no finite zeros);
* an RC branch no source reaches, and two capacitors in series on one
  1-junction (``q1' = q2' = i``: one direction of the charges never moves);
* a collocated lossless chain (three masses, two springs, force and
  velocity at the first mass): poles are ``+-j sqrt(eig(M^-1 K))`` of the free
  chain, zeros those of the chain with the first mass clamped, and they
  interlace;
* a lattice of two RC dividers whose difference ``vC1 - vR2`` has the transfer
  function ``(1 - R1 C1 R2 C2 s^2) / ((1 + R1 C1 s)(1 + R2 C2 s))``: a zero in
  the right half plane.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import sympy

import bondgraph as bg
from bondgraph.structure import (StructureError, collocated, controllability, observability,
                                 zero_structure)


def mass():
    g = bg.BondGraph("mass")
    v = bg.One("v")
    g.add(bg.Se("F"), v, bg.I("m"))
    for t, h in [("F", v), (v, "m")]:
        g.connect(t, h)
    return g


def two_masses():
    g = bg.BondGraph("two_masses")
    v1, v2, s = bg.One("v1"), bg.One("v2"), bg.Zero("s")
    g.add(bg.Se("F"), v1, v2, s, bg.I("m1"), bg.I("m2"), bg.C("k", stiffness="k"))
    for t, h in [("F", v1), (v1, "m1"), (v1, s), (s, "k"), (s, v2), (v2, "m2")]:
        g.connect(t, h)
    return g


def test_mass_with_position_sensor_has_relative_degree_two():
    z = zero_structure(bg.derive(mass(), outputs={"x": bg.displacement("m")}))
    assert (z.relative_degree, z.structural_degree, z.finite_zeros) == (2, 2, 0)
    assert z.path == ("F", "p_m", "x", "x")
    assert "relative degree (order of the infinite zero): 2" in str(z)


def test_two_masses_far_sensor_relative_degree_four_no_zeros():
    z = zero_structure(bg.derive(two_masses(), outputs={"x2": bg.displacement("m2")}))
    assert (z.relative_degree, z.finite_zeros, z.zeros) == (4, 0, ())
    # the causal path crosses m1, the spring, m2 and the integrator of x2
    assert z.path == ("F", "p_m1", "q_k", "p_m2", "x2", "x2")


def test_two_masses_near_sensor_has_zeros_at_the_antiresonance():
    z = zero_structure(bg.derive(two_masses(), outputs={"x1": bg.displacement("m1")}))
    k, m2 = sympy.symbols("k m2", positive=True)
    assert z.relative_degree == 2 and z.finite_zeros == 2
    want = {sympy.I * sympy.sqrt(k / m2), -sympy.I * sympy.sqrt(k / m2)}
    assert {sympy.simplify(w) for w in z.zeros} == {sympy.simplify(w) for w in want}
    vals = {"m1": 2.0, "m2": 0.5, "k": 8.0}
    np.testing.assert_allclose(sorted(z.zeros_at(vals).imag), [-4.0, 4.0], rtol=1e-10)
    assert not z.minimum_phase(vals)      # zeros on the imaginary axis


def test_capacitor_no_source_reaches_is_named():
    g = bg.BondGraph("rc_branch")
    a, b = bg.Zero("a"), bg.One("b")
    g.add(bg.Sf("i"), a, bg.R("R1"), bg.C("C1"), b, bg.C("C2"), bg.R("R2"))
    for t, h in [("i", a), (a, "R1"), (a, "C1"), (b, "C2"), (b, "R2")]:
        g.connect(t, h)
    res = controllability(bg.derive(g))
    assert res.unreached == ("q_C2",) and res.lost == ("q_C2",)
    assert not res.structural and not res.controllable
    assert res.reason("q_C2") == "q_C2 (C:C2): no causal path from the inputs (i)"
    assert res.bond_paths[res.states.index("q_C1")] == ("i", "a", "C1")
    assert "q_C2 (C:C2): no causal path" in str(res)


def test_series_capacitors_rank_deficiency_at_the_junction():
    g = bg.BondGraph("series_c")
    j = bg.One("j")
    g.add(bg.Sf("i"), j, bg.C("C1"), bg.C("C2"), bg.R("R"))
    for t, h in [("i", j), (j, "C1"), (j, "C2"), (j, "R")]:
        g.connect(t, h)
    res = controllability(bg.derive(g))
    # q1' = q2' = i: A = 0, B = [1, 1]^T, rank [A B] = 1 < 2, while both are reached
    assert res.unreached == () and res.generic_rank == 1 and res.structural_rank == 1
    assert res.deficient == ("q_C1", "q_C2") and res.shared == ("j",)
    assert res.kalman_rank == 1
    assert "share the junction j" in res.reason("q_C1")


def test_observability_of_a_hidden_state():
    # velocity sensor on m1 of the two-mass chain sees everything; a force sensor on
    # a disconnected RC branch does not
    m = bg.derive(two_masses(), outputs={"v1": bg.flow("m1")})
    o = observability(m)
    assert o.structural and o.observable and o.generic_rank == 3
    with pytest.raises(StructureError, match="no output 'nope'"):
        observability(m, outputs="nope")


def chain():
    g = bg.BondGraph("chain")
    v = [bg.One(f"v{i}") for i in (1, 2, 3)]
    s = [bg.Zero(f"s{i}") for i in (1, 2)]
    g.add(bg.Se("F"), *v, *s, *(bg.I(f"m{i}") for i in (1, 2, 3)),
          *(bg.C(f"k{i}", stiffness=f"k{i}") for i in (1, 2)))
    g.connect("F", "v1")
    for i in (1, 2, 3):
        g.connect(f"v{i}", f"m{i}")
    for i in (1, 2):
        g.connect(f"v{i}", f"s{i}")
        g.connect(f"s{i}", f"k{i}")
        g.connect(f"s{i}", f"v{i + 1}")
    return g


def test_collocated_lossless_chain_interlaces():
    m = bg.derive(chain(), outputs={"v1": bg.flow("m1"), "v3": bg.flow("m3")})
    vals = {"m1": 1.0, "m2": 2.0, "m3": 0.5, "k1": 3.0, "k2": 5.0}
    assert collocated(m, "F", "v1") and not collocated(m, "F", "v3")
    z = zero_structure(m, output="v1")
    assert z.relative_degree == 1 and z.finite_zeros == 4
    # by hand: free chain M x'' + K x = 0, and the chain with m1 clamped
    M = np.diag([1.0, 2.0, 0.5])
    K = np.array([[3.0, -3.0, 0.0], [-3.0, 8.0, -5.0], [0.0, -5.0, 5.0]])
    w_poles = np.sqrt(np.clip(scipy.linalg.eigh(K, M, eigvals_only=True), 0, None))
    w_zeros = np.sqrt(scipy.linalg.eigh(K[1:, 1:], M[1:, 1:], eigvals_only=True))
    zz = z.zeros_at(vals)
    # five states (three momenta, two springs): poles 0 (rigid body) and +-j w_poles,
    # four zeros +-j w_zeros (the clamped chain's antiresonances)
    np.testing.assert_allclose(np.sort(np.abs(zz.imag[zz.imag > 1e-9])), np.sort(w_zeros),
                               rtol=1e-9)
    pp = z.poles_at(vals)
    np.testing.assert_allclose(np.sort(np.abs(pp.imag[pp.imag > 1e-9])),
                               np.sort(w_poles[w_poles > 1e-6]), rtol=1e-9)
    assert z.interlaced(vals)
    assert not zero_structure(m, output="v3").interlaced(vals)


def lattice():
    g = bg.BondGraph("lattice")
    n, a, b = bg.Zero("n"), bg.One("a"), bg.One("b")
    g.add(bg.Se("V"), n, a, b, bg.R("R1"), bg.C("C1"), bg.R("R2"), bg.C("C2"))
    for t, h in [("V", n), (n, a), (a, "R1"), (a, "C1"), (n, b), (b, "C2"), (b, "R2")]:
        g.connect(t, h)
    return g


def test_lattice_difference_is_non_minimum_phase():
    m = bg.derive(lattice(), outputs={"y": bg.effort("C1") - bg.effort("R2"),
                                      "vC1": bg.effort("C1")})
    vals = {"R1": 2.0, "C1": 0.5, "R2": 4.0, "C2": 0.25}
    z = zero_structure(m, output="y")
    assert z.relative_degree == 0 and z.finite_zeros == 2
    # zeros +-1/sqrt(R1 C1 R2 C2) = +-1
    np.testing.assert_allclose(np.sort(z.zeros_at(vals).real), [-1.0, 1.0], rtol=1e-10)
    assert not z.minimum_phase(vals)
    assert zero_structure(m, output="vC1").minimum_phase(vals)


def test_bad_channel_names():
    m = bg.derive(two_masses(), outputs={"x1": bg.displacement("m1"),
                                         "x2": bg.displacement("m2")})
    with pytest.raises(StructureError, match="has 2 outputs"):
        zero_structure(m)
    with pytest.raises(StructureError, match="no input 'G'"):
        zero_structure(m, "G", "x1")
    with pytest.raises(StructureError, match="expected a bondgraph.Model"):
        controllability("model")
