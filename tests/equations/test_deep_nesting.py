"""Issue 23, item 13 (audit R02b, R02c): a hierarchy nested too deeply is a named error."""

import sys

import pytest

import bondgraph as bg


@pytest.fixture
def low_recursion_limit():
    """A low limit makes the test cheap (copying is quadratic in the depth)."""
    old = sys.getrecursionlimit()
    sys.setrecursionlimit(250)
    yield
    sys.setrecursionlimit(old)


def test_sub_models_nested_beyond_the_recursion_limit(low_recursion_limit):
    inner = bg.BondGraph("s0")
    inner.add(bg.Port("p"), bg.C("k"))
    inner.connect("p", "k")
    depth = sys.getrecursionlimit() + 100
    for level in range(1, depth):
        outer = bg.BondGraph(f"s{level}")
        outer.add(bg.Port("p"))
        try:
            outer.add(inner)
        except bg.ModelStructureError as exc:
            assert f"sub-model 's{level - 1}' is nested too deeply" in str(exc)
            assert level > 50          # ordinary hierarchies are unaffected
            return
        outer.connect("p", f"s{level - 1}.p")
        inner = outer
    pytest.fail("no refusal even beyond the recursion limit")
