"""TikZ junction names stay clear of the bonds beside them when pdflatex sets them.

Computer Modern's small optical sizes (cmr5 for a 5 pt junction name) are
wider than the DejaVu Sans the scene is measured with; the name used to run
under the next bond's causal stroke.  Reference: the glyph boxes pdflatex
actually placed, read back from the PDF (pypdfium2), against the bond's
start in the scene (px times the picture's unit; the page is cropped to the
picture, so PDF points from the left edge are the picture's x).
"""

import shutil
import subprocess

import pytest

import bondgraph as bg
from bondgraph.drawing.scene import FONT, build_scene
from bondgraph.drawing.source import diagram


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="no pdflatex")
def test_junction_name_ends_before_the_next_bond(tmp_path):
    pdfium = pytest.importorskip("pypdfium2")
    g = bg.BondGraph("n")
    g.add(bg.Se("V"), bg.One("hub_junction_wm"), bg.GY("K"), bg.One("w"), bg.I("J"))
    for t, h in [("V", "hub_junction_wm"), ("hub_junction_wm", "K"), ("K", "w"), ("w", "J")]:
        g.connect(t, h)
    bg.draw(g, tmp_path / "n.tex", title=False, numbers=False)
    done = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "n.tex"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stdout[-2000:]
    page = pdfium.PdfDocument(str(tmp_path / "n.pdf"))[0]
    text = page.get_textpage()
    chars = [(text.get_text_range(i, 1), text.get_charbox(i)) for i in range(text.count_chars())]
    content = "".join(c for c, _ in chars)
    start = content.index("hub")
    name = chars[start:start + len("hub_junction_wm")]
    right = max(box[2] for c, box in name if c.strip())
    sc = build_scene(diagram(g), title=False, numbers=False, max_width=17.0)
    bond = next(b for b in sc.bonds if b.tail == "hub_junction_wm")
    unit = 8.0 / FONT                         # pt per px at the default 8 pt labels
    stroke_x = min(p[0] for p in bond.stroke) if bond.stroke else bond.start[0]
    assert right < min(bond.start[0], stroke_x) * unit
