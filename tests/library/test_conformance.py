"""Every new element passes the package's element conformance checks (bondgraph.testing)."""

from __future__ import annotations

import pytest

from bondgraph.library.chemical import Ce, Chemostat, Flowstat, Re
from bondgraph.library.thermal import RS, EntropyCapacity, HeatConduction, Radiation
from bondgraph.testing import check_element

FACTORIES = {
    "Ce": lambda n: Ce(n, K=2),
    "Re": lambda n: Re(n, r=3),
    "Re_mass_action": lambda n: Re(n, kf=2, kr=1),
    "Chemostat": lambda n: Chemostat(n, K=1, amount=2),
    "Flowstat": lambda n: Flowstat(n),
    "RS": lambda n: RS(n, 4),
    "Radiation": lambda n: Radiation(n, area=1, emissivity=0.5),
    "HeatConduction": lambda n: HeatConduction(n, resistance=2),
    "EntropyCapacity": lambda n: EntropyCapacity(n, heat_capacity=3, reference_temperature=300),
}


@pytest.mark.parametrize("name", sorted(FACTORIES), ids=str)
def test_element_conforms(name):
    report = check_element(FACTORIES[name])
    assert report.causalities, report


def test_reaction_takes_the_affinity_on_both_ports_only():
    # the only causal pattern that derives: effort into both ports
    assert check_element(FACTORIES["Re"]).causalities == (((True, True), None),)
