"""Every built-in element passes ``bondgraph.testing.check_element``; the checks catch faults.

The causal patterns each element derives are compared with what bond-graph
theory says it admits (a source has one causality, a TF passes effort, a GY
takes effort on both ports or on neither, a junction has one strong bond,
storage both, a field either on each port), so the checks themselves are
checked against an independent statement, not against their own output.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import pytest
import sympy

import bondgraph as bg
from bondgraph.testing import ElementCheckError, check_element, check_port_rules

m, c, k = sympy.symbols("m c k", positive=True)
T, F = True, False          # effort in / flow in

#: factory, and the (effort_in per port) patterns theory admits with sources on every port
BUILT_INS = {
    "Se": (bg.Se, {(F,)}),
    "Sf": (bg.Sf, {(T,)}),
    "I": (bg.I, {(T,), (F,)}),
    "C": (bg.C, {(T,), (F,)}),
    "R": (bg.R, {(T,), (F,)}),
    "TF": (bg.TF, {(T, F), (F, T)}),
    "GY": (bg.GY, {(T, T), (F, F)}),
    "MTF": (lambda n: bg.MTF(n, 2 + sympy.sin(bg.t)), {(T, F), (F, T)}),
    "MGY": (lambda n: bg.MGY(n, 2 + sympy.cos(bg.t)), {(T, T), (F, F)}),
    # a junction with two bonds: exactly one strong bond (0: effort in, 1: flow in)
    "0": (bg.Zero, {(T, F), (F, T)}),
    "1": (bg.One, {(T, F), (F, T)}),
    "IF": (lambda n: bg.IField(n, [[2 * m, c], [c, m]]), {(T, T), (T, F), (F, T), (F, F)}),
    "CF": (lambda n: bg.CField(n, stiffness=[[2 * k, c], [c, k]]),
           {(T, T), (T, F), (F, T), (F, F)}),
    "ICF": (lambda n: bg.ICField(n, kinds="IC", matrix=[[1 / m, 0], [0, k]]),
            {(T, T), (T, F), (F, T), (F, F)}),
    "RF": (lambda n: bg.RField(n, [[2 * c, c], [c, c]]), {(T, T), (T, F), (F, T), (F, F)}),
    # a law without a closed-form inverse is kept implicit (an algebraic unknown) in the
    # other causality, so both derive
    # derivative causality: q from e by Cardano's real root (the law is monotonic)
    "C cubic": (lambda n: bg.C(n, law=k * bg.q + bg.q**3), {(T,), (F,)}),
    "R tanh": (lambda n: bg.R(n, law=c * sympy.tanh(bg.f)), {(T,), (F,)}),
}


@pytest.mark.parametrize("name", list(BUILT_INS))
def test_built_in_elements_conform(name):
    factory, admitted = BUILT_INS[name]
    report = check_element(factory)
    assert report.label == factory("x").label()
    derived = {effort_in for effort_in, _ in report.causalities}
    # every pattern theory admits derives
    assert derived == admitted


def test_storage_causal_classes():
    classes = dict(check_element(bg.I).causalities)
    assert classes == {(True,): "integral", (False,): "derivative"}
    classes = dict(check_element(bg.C).causalities)
    assert classes == {(False,): "integral", (True,): "derivative"}


@dataclass(frozen=True, eq=False)
class _Greedy(bg.Element):
    """An element that says it takes one bond but accepts any number."""

    kind: ClassVar[str] = "GREEDY"

    def bond_error(self, existing, bond):
        return None


@dataclass(frozen=True, eq=False)
class _Silent(bg.Element):
    """An element that claims a causal rule but has no constitutive relation."""

    kind: ClassVar[str] = "SILENT"


def test_the_checks_catch_faults():
    with pytest.raises(ElementCheckError, match="GREEDY:x: port rules: bond 2 was accepted"):
        check_port_rules(_Greedy)
    with pytest.raises(ElementCheckError, match=r"SILENT:x: causalities: sources \(True,\) raised "
                                                "NotImplementedError"):
        check_element(_Silent)
    negative = lambda n: bg.C(n, law=-k * bg.q)          # noqa: E731 - an active spring
    with pytest.raises(ElementCheckError, match=r"C:x: energy: stored energy .* < 0"):
        check_element(negative)
    with pytest.raises(ElementCheckError, match="returned int, not an Element"):
        check_element(lambda name: 3)
