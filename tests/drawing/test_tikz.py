"""TikZ figures of the augmented bond graph (issue 14): pdflatex compiles them, the page is
not blank, strokes sit where the physics puts them, and no name breaks or injects into LaTeX.

Expected stroke ends come from the physics, not from the drawing code: a source of
effort imposes effort on its junction (stroke at the junction end); an inertia in
integral causality receives effort (stroke at the inertia); an inertia in derivative
causality imposes effort (stroke at the junction end).  The stroke positions are parsed
from the TikZ source and compared with the bond line's two ends.

pdflatex runs in parallel threads; without pdflatex the compiling tests are skipped
(the reason is shown by ``pytest -rs``).
"""

from __future__ import annotations

import math
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

import bondgraph as bg
from bondgraph.cli import main
from bondgraph.drawing import DrawingError, draw
from bondgraph.drawing.tikz import tex_escape
from bondgraph.modelfile import load_model
from helpers import connect_all

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "codegen"))
from test_hostile_names import accepted_element_names, corpus, hostile_graph  # noqa: E402

PDFLATEX = shutil.which("pdflatex")
needs_pdflatex = pytest.mark.skipif(PDFLATEX is None, reason="pdflatex is not installed "
                                    "(Debian: texlive-latex-base texlive-pictures)")


# ----------------------------------------------------------------------------- graphs
def dc_motor_two_inertias():
    """DC motor whose shaft carries two rigidly joined inertias: one is in derivative causality."""
    g = bg.BondGraph("dc_motor_two_inertias")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"), bg.I("J2"))
    return connect_all(g, [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"),
                           (w, "b"), (w, "J2")])


def resistor_loop():
    g = bg.BondGraph("resistor_loop")
    V, a, b, c = bg.Se("V"), bg.One("a"), bg.Zero("b"), bg.One("c")
    g.add(V, a, b, c, bg.R("R1"), bg.R("R2"), bg.R("R3"), bg.C("C"))
    return connect_all(g, [(V, a), (a, "R1"), (a, b), (b, "R2"), (b, c), (c, "R3"), (c, "C")])


def geared_motor():
    """TF and GY: a motor (gyrator K) driving a load through a gear (transformer n)."""
    g = bg.BondGraph("geared_motor")
    V, ia, w1, w2 = bg.Se("V"), bg.One("ia"), bg.One("w1"), bg.One("w2")
    g.add(V, ia, w1, w2, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J1"), bg.TF("n"),
          bg.I("J_load"), bg.R("b_load"))
    return connect_all(g, [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w1), (w1, "J1"),
                           (w1, "n"), ("n", w2), (w2, "J_load"), (w2, "b_load")])


HOSTILE_LABEL = r"R:%#&{\^~$_}<|>" + '"'


class HostileR(bg.R):
    """A resistor whose drawing label holds every LaTeX special character (a user's element)."""

    def drawing_label(self):
        return HOSTILE_LABEL, r"\input{x}%"


def hostile_labels():
    g = bg.BondGraph("hostile_labels")
    F, v = bg.Se("F_in"), bg.One("v_1")
    g.add(F, v, bg.I("m__x"), HostileR("r_0"))
    return connect_all(g, [(F, v), (v, "m__x"), (v, "r_0")])


def twin_motors():
    """Two motor sub-models on one shaft, drawn as boxes with their port names."""
    m1 = bg.BondGraph("m1")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    m1.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.Port("shaft"))
    connect_all(m1, [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "shaft")])
    top = bg.BondGraph("twin")
    top.add(m1, m1.copy("m2"), bg.One("shaft"), bg.I("J"))
    return connect_all(top, [("m1.shaft", "shaft"), ("m2.shaft", "shaft"), ("shaft", "J")])


def hostile_names():
    """The codegen corpus's names that elements accept (underscores, __LINE__, 300 L's, ...)."""
    names = accepted_element_names(corpus("marker"))
    return hostile_graph(["k3"] * len(names), graph_name="__LINE__", element_names=names)


FORMULATIONS = ("paper", "system")     # of models/appendages.py and models/flexcam.py


def model_variants():
    """Every model of models/ in each formulation its model() offers."""
    import inspect

    sys.path.insert(0, str(ROOT / "models"))
    out = {}
    for path in sorted((ROOT / "models").glob("*.py")):
        mod = __import__(path.stem)
        if "formulation" in inspect.signature(mod.model).parameters:
            for form in FORMULATIONS:
                out[f"{path.stem}_{form}"] = mod.model(formulation=form).graph
        else:
            out[path.stem] = mod.model().graph
    import srv02

    out["srv02_no_inductance"] = srv02.model(inductance=False).graph
    out["srv02_load_inertia"] = srv02.model(load_inertia=True).graph
    return out


# ----------------------------------------------------------------------------- compiling
@dataclass
class Compiled:
    name: str
    pdf: Path
    log: str
    ok: bool


def pdflatex(tex: Path) -> Compiled:
    proc = subprocess.run([PDFLATEX, "-interaction=nonstopmode", "-halt-on-error", "-no-shell-escape",
                           tex.name], cwd=tex.parent, capture_output=True, text=True,
                          errors="replace", timeout=120)
    pdf = tex.with_suffix(".pdf")
    return Compiled(tex.stem, pdf, proc.stdout[-3000:], proc.returncode == 0 and pdf.exists())


def compile_all(texs: list[Path]) -> dict[str, Compiled]:
    with ThreadPoolExecutor(max_workers=2) as pool:
        return {c.name: c for c in pool.map(pdflatex, texs)}


def page_image(pdf: Path) -> np.ndarray:
    """The first page as a grayscale array (0 black .. 255 white), 2 px per pt."""
    import pypdfium2 as pdfium

    doc = pdfium.PdfDocument(str(pdf))
    try:
        assert len(doc) == 1
        image = doc[0].render(scale=2).to_pil().convert("L")
        return np.asarray(image)
    finally:
        doc.close()


def check_not_blank(img: np.ndarray, what: str) -> None:
    dark = img < 128
    assert dark.mean() > 0.004, f"{what}: only {dark.mean():.2%} of the page is ink"
    rows, cols = np.flatnonzero(dark.any(axis=1)), np.flatnonzero(dark.any(axis=0))
    # the ink reaches across most of the page (the margins are 16 px of the drawing)
    assert (cols[-1] - cols[0]) / img.shape[1] > 0.6, f"{what}: ink spans too little width"
    assert (rows[-1] - rows[0]) / img.shape[0] > 0.5, f"{what}: ink spans too little height"


@pytest.fixture(scope="module")
def figures(tmp_path_factory):
    """name -> (object drawn, TikZ source written by bg.draw, compile result)."""
    d = tmp_path_factory.mktemp("tikz")
    objects = dict(model_variants())
    objects["dc_motor_two_inertias"] = bg.derive(dc_motor_two_inertias())   # a derived Model
    objects["resistor_loop"] = resistor_loop()
    objects["geared_motor"] = geared_motor()
    objects["hostile_labels"] = hostile_labels()
    objects["hostile_names"] = hostile_names()
    objects["twin_boxes"] = twin_motors()
    texs, sources = [], {}
    for name, obj in objects.items():
        path = d / f"{name}.tex"
        sources[name] = draw(obj, path, expand=name != "twin_boxes")
        assert path.read_text(encoding="ascii") == sources[name]
        texs.append(path)
    compiled = compile_all(texs) if PDFLATEX else {}
    return {name: (objects[name], sources[name], compiled.get(name)) for name in objects}


# ----------------------------------------------------------------------------- tests
@needs_pdflatex
def test_every_figure_compiles_and_is_not_blank(figures):
    assert len(figures) >= 12
    for name, (_, _, result) in figures.items():
        assert result.ok, f"{name} did not compile:\n{result.log}"
        check_not_blank(page_image(result.pdf), name)


@needs_pdflatex
def test_tikzpicture_only_inputs_into_a_document(tmp_path):
    g = geared_motor()
    body = draw(g, tmp_path / "fig.tex", standalone=False)
    assert "\\documentclass" not in body and body.count("\\begin{tikzpicture}") == 1
    assert draw(g, fmt="tex", standalone=False) == body
    (tmp_path / "paper.tex").write_text(
        "\\documentclass[twocolumn]{article}\n\\usepackage{tikz}\n\\begin{document}\n"
        "Figure~\\ref{fig} shows the motor.\n"
        "\\begin{figure}\\centering\n\\resizebox{\\columnwidth}{!}{\\input{fig}}\n"
        "\\caption{Geared motor.}\\label{fig}\n\\end{figure}\n\\end{document}\n")
    result = pdflatex(tmp_path / "paper.tex")
    assert result.ok, result.log
    img = page_image(result.pdf)
    dark = img < 128
    cols = np.flatnonzero(dark[: img.shape[0] // 2].any(axis=0))    # figure on the top half
    assert dark.mean() > 0.0005 and (cols[-1] - cols[0]) / img.shape[1] > 0.3   # a column


def test_tikz_coordinates_are_the_svg_coordinates():
    g = geared_motor()
    svg, tikz = draw(g), draw(g, fmt="tex")
    root = ET.fromstring(svg)
    ns = "{http://www.w3.org/2000/svg}"
    bonds = parse_bonds(tikz)
    for group in root.iter(f"{ns}g"):
        if group.get("class") != "bond":
            continue
        line = group.find(f"{ns}line[@class='bond-line']")
        if line is None:
            continue
        start = (float(line.get("x1")), float(line.get("y1")))
        end = (float(line.get("x2")), float(line.get("y2")))
        tb = bonds[int(group.get("data-bond"))]
        assert math.dist(start, tb.start) < 0.06 and math.dist(end, tb.end) < 0.06


@dataclass
class TikzBond:
    number: int
    tail: str
    head: str
    start: tuple
    end: tuple
    barb: tuple
    stroke: tuple | None = None
    stroke_end: str | None = None


POINT = r"\((-?[\d.]+),(-?[\d.]+)\)"


def parse_bonds(tikz: str) -> dict[int, TikzBond]:
    """Bonds of a TikZ figure: the line's ends and barb, the stroke, from the source text."""
    bonds: dict[int, TikzBond] = {}
    current = None
    for line in tikz.splitlines():
        m = re.fullmatch(r"% bond (\d+): (\S+) -> (\S+)", line)
        if m:
            current = (int(m[1]), m[2], m[3])
            continue
        m = re.fullmatch(rf"\\draw\[bondgraph (?:bond|loop)\] {POINT} -- {POINT} -- {POINT};", line)
        if m and current:
            pts = [(float(m[i]), float(m[i + 1])) for i in (1, 3, 5)]
            bonds[current[0]] = TikzBond(current[0], current[1], current[2], *pts)
            continue
        m = re.fullmatch(rf"\\draw\[bondgraph (?:bond|loop), bondgraph stroke\] {POINT} -- {POINT};"
                         rf" % stroke (\d+) at (\S+)", line)
        if m:
            b = bonds[int(m[5])]
            b.stroke = ((float(m[1]), float(m[2])), (float(m[3]), float(m[4])))
            b.stroke_end = m[6]
    return bonds


def stroke_at(b: TikzBond) -> str:
    """The element at the stroke end, by geometry: the stroke's middle on one end of the line,
    across it."""
    (a, c) = b.stroke
    mid = ((a[0] + c[0]) / 2, (a[1] + c[1]) / 2)
    at_tail, at_head = math.dist(mid, b.start), math.dist(mid, b.end)
    assert min(at_tail, at_head) < 0.02, "the stroke is not at an end of the bond"
    u = (b.end[0] - b.start[0], b.end[1] - b.start[1])
    s = (c[0] - a[0], c[1] - a[1])
    cos = abs(u[0] * s[0] + u[1] * s[1]) / (math.hypot(*u) * math.hypot(*s))
    assert cos < 1e-3, "the stroke is not across the bond"
    assert math.dist(b.barb, b.end) < 12, "the half-arrow is not at the head"
    return b.tail if at_tail < at_head else b.head


def test_strokes_agree_with_the_engines_causality():
    model = bg.derive(dc_motor_two_inertias())
    aug = model.augmented
    bonds = parse_bonds(draw(model, fmt="tex"))
    assert len(bonds) == 8 and all(b.stroke is not None for b in bonds.values())
    flat = {b.number: b for b in aug.flat.bonds}
    for n, b in bonds.items():
        assert (b.tail, b.head) == (flat[n].tail, flat[n].head)
        assert stroke_at(b) == aug.bond(n).stroke == b.stroke_end
    # the physics, for the three kinds of end
    assert stroke_at(bonds[1]) == "ia"                   # Se:V imposes effort on its junction
    assert aug.derivative and set(aug.derivative) <= {"J", "J2"}
    (derivative,) = aug.derivative
    integral = {"J", "J2"} - {derivative}
    for n, b in bonds.items():
        if b.head == "La" or b.head in integral:
            assert stroke_at(b) == b.head                # integral I receives effort
        if b.head == derivative:
            assert stroke_at(b) == "w"                   # derivative I imposes effort


def test_escaping_refuses_or_neutralizes_every_hostile_text(tmp_path):
    marker = tmp_path / "INJECTED"
    texts = corpus(marker) + [
        r"\immediate\openout1=INJECTED\immediate\closeout1", r"\input{/etc/hostname}", "}}}\\end{document}",
        "a_b", "%", "#", "&", "{", "\\", "^", "~", "$x$", r"\\", "\\csname", HOSTILE_LABEL]
    escaped = []
    for text in texts:
        try:
            out = tex_escape(text, "name")
        except DrawingError as exc:
            assert repr(text) in str(exc)
            assert any(not (" " <= ch <= "~") for ch in text)
            continue
        # no unescaped special character is left: outside the escapes, only plain text
        plain = re.sub(r"\\(textbackslash|textless|textgreater|textbar)\{\}|\\[{}$&#%_]|\\[\^~]\{\}",
                       "", out)
        assert not set(plain) & set("\\{}$&#%_^~"), (text, out)
        escaped.append(out)
    assert len(escaped) > 60
    if PDFLATEX is None:
        pytest.skip("pdflatex is not installed: the escaped texts were checked, not compiled")
    nodes = "\n".join(f"\\node[anchor=west] at (0,{-0.5 * i}) {{{e}}};"
                      for i, e in enumerate(escaped) if len(e) < 200)
    (tmp_path / "all.tex").write_text("\\documentclass{article}\n\\usepackage{tikz}\n\\begin{document}\n"
                                      f"\\begin{{tikzpicture}}\n{nodes}\n\\end{{tikzpicture}}\n"
                                      "\\end{document}\n")
    result = pdflatex(tmp_path / "all.tex")
    assert result.ok, result.log
    assert not marker.exists() and not (tmp_path / "INJECTED.tex").exists()


def test_non_ascii_label_is_refused_naming_it():
    class Greek(bg.R):
        def drawing_label(self):
            return "R:Ω", ""

    g = bg.BondGraph("greek")
    g.add(bg.Se("V"), Greek("r"))
    g.connect("V", "r")
    with pytest.raises(DrawingError, match=r"label of element 'r' 'R:Ω' has the character 'Ω'"):
        draw(g, fmt="tex")
    assert "R:Ω" in draw(g)                              # SVG can show it


@needs_pdflatex
def test_command_line_draw_tex(tmp_path, capsys):
    model = str(ROOT / "tests" / "data" / "dc_motor.py")
    full, bare = tmp_path / "m.tex", tmp_path / "m_body.tex"
    assert main(["draw", model, "-o", str(full)]) == 0
    assert main(["draw", model, "-o", str(bare), "--tikz-only"]) == 0
    graph = load_model(model).graph
    assert full.read_text() == draw(graph, fmt="tex")
    assert bare.read_text() == draw(graph, fmt="tex", standalone=False)
    assert main(["draw", model, "-o", str(tmp_path / "m.svg"), "--tikz-only"]) == 2
    assert "--tikz-only applies to TikZ output" in capsys.readouterr().err
    result = pdflatex(full)
    assert result.ok, result.log
    check_not_blank(page_image(result.pdf), "dc_motor from the command line")
