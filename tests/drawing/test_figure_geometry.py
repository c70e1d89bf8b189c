"""Figures a journal accepts: no bond through a label, a width in cm, label options.

The checks read the scene's coordinates (what the SVG, PNG and TikZ writers
draw).  References: segment/box and segment/segment intersection worked by
hand on small hand-made scenes; the printed size from the definition of
the scale (a 14 px label printed at 8 pt makes one px 8/14 pt, 1 pt =
2.54/72.27 cm).
"""

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import bondgraph as bg
from bondgraph.drawing.geometry import bond_crossings, bonds_through_labels, printed_size
from bondgraph.drawing.scene import BondShape, Label, Scene, build_scene
from bondgraph.drawing.source import diagram

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "models"))
sys.path.insert(0, str(REPO / "tests"))
import appendages  # noqa: E402
import buck  # noqa: E402
import clutch  # noqa: E402
import flexcam  # noqa: E402
import srv02  # noqa: E402

#: every model of models/, each formulation and variant
MODELS = {
    "srv02": lambda: srv02.build(),
    "srv02-no-inductance": lambda: srv02.build(inductance=False),
    "flexcam-paper": lambda: flexcam.build()[0],
    "flexcam-system": lambda: flexcam.build(formulation="system")[0],
    "flexcam-paper-5-modes": lambda: flexcam.build(5)[0],
    "appendages-system": lambda: appendages.build(3)[0],
    "appendages-paper": lambda: appendages.build_paper(3)[0],
    "buck-on": lambda: buck.build(),
    "buck-off": lambda: buck.build(switch_on=False),
    "clutch-slipping": lambda: clutch.build(),
    "clutch-engaged": lambda: clutch.build(engaged=True),
}


def _label(name, x, y, w=20.0, h=20.0):
    return Label(name, "R", name, "", x, y, w, (x - w / 2, y - h / 2, w, h))


def _bond(number, tail, head, start, end, number_at=(0.0, -100.0)):
    return BondShape(number, tail, head, start, end, end, None, None, number_at)


def _scene(labels, bonds, width=200.0, height=100.0):
    return Scene("hand", width, height, tuple(labels), tuple(bonds), (), (0.0, 0.0), "", False)


def test_hand_made_scene_bond_through_a_label_and_a_crossing():
    # a at (10, 50), b at (190, 50), c in the middle at (100, 50): the bond a-b runs through c;
    # d (100, 10) - e (100, 90) crosses a-b at (100, 50) (and passes through c as well)
    labels = [_label(n, x, y) for n, x, y in
              [("a", 10, 50), ("b", 190, 50), ("c", 100, 50), ("d", 100, 10), ("e", 100, 90)]]
    bonds = [_bond(1, "a", "b", (20, 50), (180, 50)), _bond(2, "d", "e", (100, 20), (100, 80))]
    sc = _scene(labels, bonds)
    assert sorted(bonds_through_labels(sc)) == [(1, "c"), (2, "c")]
    assert bond_crossings(sc) == [(1, 2)]
    # moved 30 px down, the bond a-b passes under c (box 40..60) and still crosses d-e
    bonds[0] = _bond(1, "a", "b", (20, 80), (180, 80))
    assert bonds_through_labels(_scene(labels, bonds)) == [(2, "c")]
    # a bond running over another bond's number counts (the number's box is about 6 x 10 px)
    bonds = [_bond(1, "a", "b", (20, 80), (180, 80), number_at=(60, 80))]
    bonds.append(_bond(2, "d", "e", (60, 20), (60, 95), number_at=(150, 10)))
    assert (2, "#1") in bonds_through_labels(_scene(labels, bonds))


def test_printed_size_scale():
    sc = _scene([], [], width=1400.0, height=700.0)
    w, h = printed_size(sc, font_pt=8.0)
    assert w == pytest.approx(1400 * 8 / 14 * 2.54 / 72.27)
    assert h == pytest.approx(w / 2)


@pytest.mark.parametrize("name", list(MODELS))
def test_models_fit_17_cm_with_no_bond_through_a_label(name):
    # the default of draw(): 17 cm at 8 pt labels
    sc = build_scene(diagram(MODELS[name]()), max_width=17.0)
    assert bonds_through_labels(sc) == [] and sc.overlaps() == []
    assert printed_size(sc, font_pt=8.0)[0] <= 17.0
    assert bond_crossings(sc) == []
    print(f"\n{name}: {printed_size(sc)[0]:.1f} x {printed_size(sc)[1]:.1f} cm at 8 pt")


def test_flexcam_fits_17_cm_at_8_pt():
    g = flexcam.build()[0]
    wide = build_scene(diagram(g), max_width=None)                # one long row, as before
    assert printed_size(wide)[0] > 17.0
    sc = build_scene(diagram(g), max_width=17.0)
    assert printed_size(sc, font_pt=8.0)[0] <= 17.0
    assert bonds_through_labels(sc) == [] and bond_crossings(sc) == []


def test_200_random_graphs_have_no_bond_through_a_label():
    from verification.generator import build, generate

    bad, crossings = {}, 0
    for seed in range(200):
        g = build(generate(seed))[0]
        try:
            d = diagram(g)
        except bg.BondGraphError:        # no causal assignment: drawn without strokes
            d = diagram(g, causality=False)
        sc = build_scene(d, max_width=17.0)
        hits = bonds_through_labels(sc)
        if hits or sc.overlaps() or printed_size(sc)[0] > 17.0:
            bad[seed] = (hits, sc.overlaps(), printed_size(sc)[0])
        crossings += len(bond_crossings(sc))
    print(f"\n200 random graphs: {crossings} bond crossings in all")
    assert bad == {}
    # Graphviz dot lays the same 200 graphs out with 43 crossings (bench/drawing_crossings.py,
    # its spline control polygons counted the same way): the stated margin is 0, not above dot
    # (ours: 0 since the layered candidates; 47 with the comb alone)
    assert crossings <= 43


def test_options_title_prefixes_numbers():
    g = flexcam.build()[0]
    full = bg.draw(g)
    assert "flexcam_paper" in full and "I:link.m_1" in full and 'class="bond-number"' in full
    bare = bg.draw(g, title=False, prefixes=False, numbers=False)
    assert 'class="title"' in full and 'class="title"' not in bare
    assert "I:link.m_1" not in bare and ">I:m_1<" in bare
    assert 'class="bond-number"' not in bare
    from bondgraph.drawing.labels import without_prefixes

    texts = [lb.text + lb.note for lb in build_scene(without_prefixes(diagram(g))).labels]
    assert not [t for t in texts if "." in t]
    tikz = bg.draw(g, fmt="tex", numbers=False)
    assert "bondgraph number] at" not in tikz


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="no pdflatex")
def test_latex_labels_compile(tmp_path):
    g = appendages.build(3)[0]
    tex = bg.draw(g, tmp_path / "fig.tex", latex=True, prefixes=False, title=False)
    assert "Se:$\\tau$" in tex
    assert re.search(r"\{I:\$m_\{1\}\$\}", tex)
    done = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "fig.tex"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout[-2000:]
    # the page is the picture: at most 17 cm wide (pdf points, 72 per inch)
    import pypdfium2

    width_pt = pypdfium2.PdfDocument(str(tmp_path / "fig.pdf"))[0].get_size()[0]
    assert width_pt / 72 * 2.54 <= 17.0
