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
