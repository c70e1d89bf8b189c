"""``bg.draw`` of a switched model: one mode's causal strokes, each switch's state beside it.

Hand causality of the buck converter (library.buck): with S on (a zero-effort source) the
source Vin's bond gets its stroke at the 1-junction s as for any effort source; in every
consistent mode L and C keep integral causality except in discontinuous conduction
(S off, D off), where L's flow is fixed to zero by the open switches and L is in derivative
causality (drawn red).
"""

from __future__ import annotations

import pytest

import bondgraph as bg
from bondgraph.drawing import DrawingError, diagram
from bondgraph.hybrid import ModeError, SwitchedModel, library


@pytest.fixture(scope="module")
def buck():
    return SwitchedModel(library.buck(), outputs={"v": bg.effort("C")})


def test_draw_writes_an_svg_of_the_initial_mode(buck, tmp_path):
    path = tmp_path / "buck.svg"
    svg = bg.draw(buck, path)
    assert path.read_text() == svg and svg.startswith("<svg") or "<svg" in svg
    assert "buck (D off, S on)" in svg
    assert "CSw:S" in svg and "D:D" in svg


def test_mode_choice_changes_states_and_strokes(buck):
    on = diagram(buck)
    dcm = diagram(buck, mode={"off": {"S", "D"}})
    assert (on.node("S").note, on.node("D").note) == ("on", "off")
    assert (dcm.node("S").note, dcm.node("D").note) == ("off", "off")
    assert not on.node("L").derivative and dcm.node("L").derivative
    assert [e.stroke_end for e in on.edges] != [e.stroke_end for e in dcm.edges]
    assert dcm.name == "buck (D off, S off)"


def test_inconsistent_mode_and_mode_of_a_plain_graph_are_refused(buck):
    with pytest.raises(ModeError, match="consistent modes are"):
        bg.draw(buck, mode={"on": {"S", "D"}})
    g = bg.BondGraph("r"); g.add(bg.Se("V"), bg.R("R")); g.connect("V", "R")
    with pytest.raises(DrawingError, match="switched models"):
        bg.draw(g, mode={"on": {"S"}})
