"""Issue 23, items 3 and 12: long computations refused up front with a clear message.

Audit R06a (RK45 on a stiff plant ran past 90 s with growing memory), I43
(``prbs(32)`` needed 32 GiB before failing).
"""

import numpy as np
import pytest

import bondgraph as bg
from bondgraph.numeric import SimulationError


def _msd():
    g = bg.BondGraph("msd")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"), bg.C("c"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "c")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"x": bg.displacement("c")})


STIFF = {"m": 1e-9, "b": 1.0, "c": 1.0}      # poles -b/m ~ -1e9 and -1/(b c) = -1


def test_stiff_plant_refused_for_explicit_methods_with_the_hint():
    with pytest.raises(SimulationError, match=r"model 'msd' is stiff: its fastest eigenvalue at the "
                       r"initial state is -1e\+09.*use method='Radau', 'BDF' or 'LSODA'"):
        bg.simulate(_msd(), STIFF, (0.0, 100.0), u=[1.0])


def test_stiff_plant_with_radau_matches_the_slow_pole():
    """With m -> 0: b x' + x/c = F, x(t) = c F (1 - exp(-t/(b c))) (first-order lag)."""
    res = bg.simulate(_msd(), STIFF, (0.0, 5.0), u=[1.0], method="Radau", t_eval=[1.0, 5.0])
    np.testing.assert_allclose(res["x"], 1.0 - np.exp(-np.array([1.0, 5.0])), rtol=1e-5)


def test_ordinary_plant_still_runs_with_rk45():
    """m x'' + b x' + x/c = F, steady state x = c F."""
    res = bg.simulate(_msd(), {"m": 2.0, "b": 6.0, "c": 0.25}, (0.0, 40.0), u=[1.0], t_eval=[40.0])
    assert res["x"][-1] == pytest.approx(0.25, rel=1e-5)


def test_prbs_refuses_a_sequence_too_long_to_build_before_allocating():
    """I43: prbs(32), the documented maximum order, allocated 32 GiB then failed."""
    from bondgraph.identification import IdentificationError, prbs

    with pytest.raises(IdentificationError, match=r"length: the sequence would have 4,294,967,295 samples"):
        prbs(32)
    x = prbs(32, length=1000)           # a part of the period is still available
    assert x.shape == (1000,) and set(np.unique(x)) <= {-1.0, 1.0}
    # a maximum-length sequence of order 5 has 2**4 ones and 2**4 - 1 zeros in its 31 bits
    y = prbs(5)
    assert y.size == 31 and np.count_nonzero(y > 0) == 16
