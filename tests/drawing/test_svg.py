"""Drawings: well-formed SVG, causal strokes at the right end, layout, PNG output.

The expected stroke ends come from the physics, not from the code: a source
of effort imposes effort on its junction (stroke at the far end), an inertia
in integral causality receives effort (stroke at the inertia), and the second
inertia behind a transformer is in derivative causality (its junction's flow
is already set, so the stroke sits at the junction end).
"""

from __future__ import annotations

import math
import os
import random
import xml.etree.ElementTree as ET

import matplotlib.image
import numpy as np
import pytest

import bondgraph as bg
from bondgraph.drawing import (DrawingError, build_scene, diagram, draw, grid_layout,
                               overlapping_pairs, repr_svg)
from helpers import connect_all

SVG = "{http://www.w3.org/2000/svg}"


# ---------------------------------------------------------------- models
def dc_motor():
    g = bg.BondGraph("dc_motor")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
    return connect_all(g, [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")])


def quarter_car():
    g = bg.BondGraph("quarter_car")
    vr, vu, vs = bg.Sf("vr"), bg.One("vu"), bg.One("vs")
    tire, susp, rel = bg.Zero("tire"), bg.Zero("susp"), bg.One("rel")
    g.add(vr, vu, vs, tire, susp, rel, bg.C("kt"), bg.I("mu"), bg.I("ms"), bg.C("ks"), bg.R("bs"))
    return connect_all(g, [(vr, tire), (tire, "kt"), (tire, vu), (vu, "mu"), (vu, susp),
                           (susp, vs), (vs, "ms"), (susp, rel), (rel, "ks"), (rel, "bs")])


def geared_inertias():
    g = bg.BondGraph("geared_inertias")
    T, w1, w2 = bg.Se("T"), bg.One("w1"), bg.One("w2")
    g.add(T, w1, w2, bg.I("J1"), bg.R("b1"), bg.TF("n"), bg.I("J2"), bg.R("b2"))
    return connect_all(g, [(T, w1), (w1, "J1"), (w1, "b1"), (w1, "n"), ("n", w2), (w2, "J2"),
                           (w2, "b2")])


def resistor_loop():
    g = bg.BondGraph("resistor_loop")
    V, a, b, c = bg.Se("V"), bg.One("a"), bg.Zero("b"), bg.One("c")
    g.add(V, a, b, c, bg.R("R1"), bg.R("R2"), bg.R("R3"), bg.C("C"))
    return connect_all(g, [(V, a), (a, "R1"), (a, b), (b, "R2"), (b, c), (c, "R3"), (c, "C")])


def mass_chain(n=20):
    g = bg.BondGraph(f"mass_chain_{n}")
    g.add(bg.Se("F"))
    prev = "F"
    for i in range(1, n + 1):
        g.add(bg.One(f"v{i}"), bg.I(f"m{i}"), bg.R(f"b{i}"))
        connect_all(g, [(prev, f"v{i}"), (f"v{i}", f"m{i}"), (f"v{i}", f"b{i}")])
        if i < n:
            g.add(bg.Zero(f"s{i}"), bg.C(f"k{i}"))
            connect_all(g, [(f"v{i}", f"s{i}"), (f"s{i}", f"k{i}")])
            prev = f"s{i}"
    return g


def motor(name="motor"):
    g = bg.BondGraph(name)
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.Port("shaft"))
    return connect_all(g, [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "shaft")])


def servo():
    top = bg.BondGraph("servo")
    top.add(motor(), bg.One("load"), bg.I("J"), bg.R("b"))
    return connect_all(top, [("motor.shaft", "load"), ("load", "J"), ("load", "b")])


def twin():
    m1 = motor("m1")
    top = bg.BondGraph("twin")
    top.add(m1, m1.copy("m2"), bg.One("shaft"), bg.I("J"))
    return connect_all(top, [("m1.shaft", "shaft"), ("m2.shaft", "shaft"), ("shaft", "J")])


def random_tree(seed=3, size=60):
    """A bushy junction tree of ~60 elements (no loops of junctions)."""
    rnd = random.Random(seed)
    g = bg.BondGraph("tree")
    g.add(bg.Se("u"), bg.One("j0"))
    g.connect("u", "j0")
    juncs, n, k = ["j0"], 2, 1
    while n < size:
        parent = rnd.choice(juncs[-4:] + juncs[:1])
        name = f"j{k}"
        k += 1
        g.add((bg.Zero if rnd.random() < 0.5 else bg.One)(name))
        g.connect(parent, name)
        juncs.append(name)
        n += 1
        for _ in range(rnd.randint(1, 2)):
            el = rnd.choice([bg.I, bg.C, bg.R])(f"e{n}")
            g.add(el)
            g.connect(name, el.name)
            n += 1
    return g


MODELS = {"dc_motor": dc_motor, "quarter_car": quarter_car, "geared": geared_inertias,
          "loop": resistor_loop, "chain20": mass_chain, "servo": servo, "tree60": random_tree}


# ---------------------------------------------------------------- SVG parsing
def parse(svg: str):
    """Elements (name -> dict) and bonds (number -> dict) read back from the SVG."""
    root = ET.fromstring(svg)
    elements, bonds = {}, {}
    for g in root.iter(f"{SVG}g"):
        cls = g.get("class")
        if cls == "element":
            rect = g.find(f"{SVG}rect")
            box = tuple(float(rect.get(k)) for k in ("x", "y", "width", "height"))
            texts = {t.get("class"): "".join(t.itertext()) for t in g.iter(f"{SVG}text")}
            elements[g.get("data-name")] = dict(kind=g.get("data-kind"), box=box, rect=rect,
                                                causality=g.get("data-causality"), **texts)
        elif cls == "bond":
            line = g.find(f"{SVG}line[@class='bond-line']")
            curve = g.find(f"{SVG}path[@class='bond-line']")
            stroke = g.find(f"{SVG}line[@class='stroke']")
            barb = g.find(f"{SVG}polyline[@class='half-arrow']")
            num = g.find(f"{SVG}text[@class='bond-number']")
            seg = lambda el: ((float(el.get("x1")), float(el.get("y1"))),  # noqa: E731
                              (float(el.get("x2")), float(el.get("y2"))))
            bonds[int(g.get("data-bond"))] = dict(
                tail=g.get("data-tail"), head=g.get("data-head"), loop=g.get("data-loop") == "1",
                line=seg(line) if line is not None else bezier_ends(curve),
                control=None if curve is None else bezier_control(curve),
                stroke=seg(stroke) if stroke is not None else None,
                stroke_el=stroke, color=(line if line is not None else curve).get("stroke"),
                barb=[tuple(map(float, p.split(","))) for p in barb.get("points").split()],
                number=num.text,
            )
    return root, elements, bonds


def bezier_ends(path):
    # d="M x0 y0 Q cx cy x1 y1"
    v = path.get("d").split()
    return (float(v[1]), float(v[2])), (float(v[6]), float(v[7]))


def bezier_control(path):
    v = path.get("d").split()
    return float(v[4]), float(v[5])


def points_along(bond, n=60):
    (p0, p1), c = bond["line"], bond["control"]
    c = c or ((p0[0] + p1[0]) / 2, (p0[1] + p1[1]) / 2)
    for k in range(1, n):
        t = k / n
        yield ((1 - t) ** 2 * p0[0] + 2 * t * (1 - t) * c[0] + t * t * p1[0],
               (1 - t) ** 2 * p0[1] + 2 * t * (1 - t) * c[1] + t * t * p1[1])


def centre(box):
    x, y, w, h = box
    return x + w / 2, y + h / 2


def dist(p, q):
    return math.hypot(p[0] - q[0], p[1] - q[1])


def stroke_end_by_geometry(bond, elements):
    """Which element the stroke is drawn at: compare distances to the two label boxes."""
    (a, b) = bond["stroke"]
    mid = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
    dt = dist(mid, centre(elements[bond["tail"]]["box"]))
    dh = dist(mid, centre(elements[bond["head"]]["box"]))
    return bond["tail"] if dt < dh else bond["head"]


def boxes_overlap(a, b):
    return a[0] < b[0] + b[2] and b[0] < a[0] + a[2] and a[1] < b[1] + b[3] and b[1] < a[1] + a[3]


# ---------------------------------------------------------------- tests
@pytest.fixture(scope="module")
def svgs():
    return {k: draw(f()) for k, f in MODELS.items()}


@pytest.mark.parametrize("name", list(MODELS), ids=list(MODELS))
def test_svg_is_well_formed_and_labels_every_element_and_bond(svgs, name):
    root, elements, bonds = parse(svgs[name])
    assert root.tag == f"{SVG}svg"
    flat = bg.flatten(MODELS[name]())
    assert set(elements) == {el.name for el in flat.elements}
    for el in flat.elements:
        drawn = elements[el.name]
        if el.kind in ("0", "1"):
            assert drawn["label"] == el.kind and drawn["note"] == el.name
        else:
            assert drawn["label"] == el.label()      # Se:V, I:La, GY:K, ...
    assert sorted(bonds) == [b.number for b in flat.bonds]
    for b in flat.bonds:
        assert bonds[b.number]["number"] == str(b.number)
        assert (bonds[b.number]["tail"], bonds[b.number]["head"]) == (b.tail, b.head)
        assert bonds[b.number]["stroke"] is not None


@pytest.mark.parametrize("model, bond, end, why", [
    (dc_motor, 1, "ia", "Se imposes effort: stroke away from the source"),
    (dc_motor, 3, "La", "inertia in integral causality receives effort"),
    (dc_motor, 6, "J", "inertia in integral causality receives effort"),
    (quarter_car, 1, "vr", "Sf imposes flow: stroke at the source"),
    (quarter_car, 2, "tire", "capacitor in integral causality imposes effort"),
    (geared_inertias, 2, "J1", "first inertia integral"),
    (geared_inertias, 6, "w2", "second inertia behind the gear: derivative causality"),
], ids=["Se", "I-integral", "I-integral-2", "Sf", "C-integral", "J1", "I-derivative"])
def test_stroke_end_from_geometry(model, bond, end, why):
    _, elements, bonds = parse(draw(model()))
    b = bonds[bond]
    assert b["stroke_el"].get("data-end") == end, why
    assert b["stroke_el"].get("data-bond") == str(bond)
    assert stroke_end_by_geometry(b, elements) == end, why
    # the stroke crosses the bond's line at that end, perpendicular to it
    (s0, s1), (p0, p1) = b["stroke"], b["line"]
    mid = ((s0[0] + s1[0]) / 2, (s0[1] + s1[1]) / 2)
    at = p0 if end == b["tail"] else p1
    assert dist(mid, at) < 0.2
    dot = (s1[0] - s0[0]) * (p1[0] - p0[0]) + (s1[1] - s0[1]) * (p1[1] - p0[1])
    assert abs(dot) < 1e-6 * dist(s0, s1) * dist(p0, p1) + 0.5


def test_derivative_causality_is_highlighted_and_in_the_legend():
    root, elements, _ = parse(draw(geared_inertias()))
    assert elements["J2"]["causality"] == "derivative"
    assert elements["J2"]["rect"].get("stroke") == "#d62728"
    assert elements["J1"]["causality"] is None
    legend = " ".join(t.text or "" for t in root.iter(f"{SVG}text") if t.get("class") == "legend-text")
    assert "derivative causality" in legend


def test_strokes_agree_with_the_causal_graph(svgs):
    for name in ("dc_motor", "quarter_car", "geared", "loop", "chain20", "tree60"):
        aug = bg.assign_causality(MODELS[name]())
        _, elements, bonds = parse(svgs[name])
        for cb in aug.bonds:
            assert bonds[cb.number]["stroke_el"].get("data-end") == cb.stroke
            assert stroke_end_by_geometry(bonds[cb.number], elements) == cb.stroke


def test_half_arrow_is_one_barb_at_the_head(svgs):
    _, elements, bonds = parse(svgs["dc_motor"])
    for b in bonds.values():
        (p0, p1), barb = b["line"], b["barb"]
        assert len(barb) == 2 and dist(barb[0], p1) < 0.2
        # the head end of the line is the one nearer the head's label
        assert dist(p1, centre(elements[b["head"]]["box"])) < dist(p0, centre(elements[b["head"]]["box"]))
        # a single-sided barb: its free end is off the line
        ux, uy = p1[0] - p0[0], p1[1] - p0[1]
        cross = ux * (barb[1][1] - p1[1]) - uy * (barb[1][0] - p1[0])
        assert abs(cross) / math.hypot(ux, uy) > 3


def test_algebraic_loop_bonds_are_orange():
    aug = bg.assign_causality(resistor_loop())
    in_loop = set(aug.loops[0])
    root, elements, bonds = parse(draw(aug))
    for n, b in bonds.items():
        assert b["loop"] == (n in in_loop)
        assert (b["color"] == "#ff7f0e") == (n in in_loop)
    legend = " ".join(t.text or "" for t in root.iter(f"{SVG}text") if t.get("class") == "legend-text")
    assert "algebraic loop" in legend


@pytest.mark.parametrize("name", list(MODELS), ids=list(MODELS))
def test_labels_do_not_overlap(svgs, name):
    _, elements, _ = parse(svgs[name])
    boxes = [e["box"] for e in elements.values()]
    bad = [(i, j) for i in range(len(boxes)) for j in range(i + 1, len(boxes))
           if boxes_overlap(boxes[i], boxes[j])]
    assert bad == []
    root = ET.fromstring(svgs[name])
    W, H = float(root.get("width")), float(root.get("height"))
    assert all(0 <= x and 0 <= y and x + w <= W and y + h <= H for x, y, w, h in boxes)


def bridge():
    """A Wheatstone bridge: the junction structure has loops."""
    g = bg.BondGraph("bridge")
    g.add(bg.Se("V"), bg.One("src"), *(bg.Zero(n) for n in ("na", "nb", "nc", "nd")))
    connect_all(g, [("V", "src"), ("src", "na"), ("nd", "src")])
    for i, (p, q) in enumerate([("na", "nb"), ("na", "nc"), ("nb", "nd"), ("nc", "nd"),
                                ("nb", "nc")], start=1):
        g.add(bg.One(f"i{i}"), bg.R(f"R{i}") if i != 5 else bg.C("C5"))
        connect_all(g, [(p, f"i{i}"), (f"i{i}", q), (f"i{i}", f"R{i}" if i != 5 else "C5")])
    return g


@pytest.mark.parametrize("name", ["dc_motor", "quarter_car", "chain20", "tree60", "bridge"])
def test_bonds_do_not_run_through_other_labels(svgs, name):
    svg = svgs[name] if name in svgs else draw(bridge(), causality=False)
    _, elements, bonds = parse(svg)
    for n, b in bonds.items():
        for el_name, el in elements.items():
            if el_name in (b["tail"], b["head"]):
                continue
            x, y, w, h = el["box"]
            inside = [p for p in points_along(b) if x + 1 < p[0] < x + w - 1 and y + 1 < p[1] < y + h - 1]
            assert not inside, f"bond {n} runs through {el_name}"


def test_labels_do_not_overlap_unexpanded():
    for g in (servo(), twin()):
        sc = build_scene(diagram(g, expand=False))
        assert sc.overlaps() == []


def test_bonds_end_at_the_label_boxes(svgs):
    _, elements, bonds = parse(svgs["quarter_car"])
    for b in bonds.values():
        for pt, name in zip(b["line"], (b["tail"], b["head"])):
            x, y, w, h = elements[name]["box"]
            outside = max(x - pt[0], pt[0] - (x + w), y - pt[1], pt[1] - (y + h))
            assert 0 < outside < 4   # just outside the box, not inside, not far


def test_a_chain_reads_as_a_chain():
    _, el, _ = parse(draw(dc_motor()))
    xs = [centre(el[n]["box"])[0] for n in ("V", "ia", "K", "w")]
    ys = [centre(el[n]["box"])[1] for n in ("V", "ia", "K", "w")]
    assert xs == sorted(xs) and max(ys) - min(ys) < 0.2
    # storage above the junction, resistor below (y grows downward)
    assert centre(el["La"]["box"])[1] < centre(el["ia"]["box"])[1] < centre(el["Ra"]["box"])[1]


def test_long_chain_snakes_with_short_straight_bonds():
    g = mass_chain(20)
    cells = grid_layout([e.name for e in bg.flatten(g).elements],
                        {e.name: e.kind for e in bg.flatten(g).elements},
                        [(b.tail, b.head) for b in g.bonds], wrap=14)
    cols = {c for c, _ in cells.values()}
    assert len(cols) <= 16                      # wrapped, not 40 columns wide
    for b in g.bonds:
        (c0, r0), (c1, r1) = cells[b.tail], cells[b.head]
        if b.tail.startswith(("v", "s")) and b.head.startswith(("v", "s")):
            assert c0 == c1 or r0 == r1         # junction chain: horizontal or a vertical turn


def test_grid_layout_gives_every_node_its_own_cell():
    g = random_tree(seed=11, size=60)
    flat = bg.flatten(g)
    cells = grid_layout([e.name for e in flat.elements], {e.name: e.kind for e in flat.elements},
                        [(b.tail, b.head) for b in flat.bonds])
    assert len(set(cells.values())) == len(cells) == len(flat.elements)
    assert min(c for c, _ in cells.values()) == 0 and min(r for _, r in cells.values()) == 0


def test_overlapping_pairs_helper():
    assert overlapping_pairs({"a": (0, 0, 10, 10), "b": (9, 9, 5, 5), "c": (10, 0, 5, 5)}) == [("a", "b")]


def test_png_renders_and_reads_back(tmp_path):
    path = tmp_path / "dc_motor.png"
    svg = draw(dc_motor(), path)
    assert svg.startswith("<svg")
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 1000
    img = matplotlib.image.imread(path)
    assert img.ndim == 3 and img.shape[0] > 50 and img.shape[1] > 100
    assert float(np.asarray(img[..., :3]).min()) < 0.5    # something dark was drawn
    assert os.listdir(tmp_path) == ["dc_motor.png"]        # no temporary file left


def test_svg_file_and_format_choice(tmp_path):
    svg = draw(dc_motor(), tmp_path / "m.svg")
    assert (tmp_path / "m.svg").read_text() == svg
    draw(dc_motor(), tmp_path / "m.out", fmt="png")
    assert (tmp_path / "m.out").read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(DrawingError, match="suffix"):
        draw(dc_motor(), tmp_path / "m.pdf")
    with pytest.raises(DrawingError, match="format"):
        draw(dc_motor(), tmp_path / "m.svg", fmt="jpeg")


def test_model_and_augmented_graph_draw_the_same():
    g = geared_inertias()
    model = bg.derive(g, outputs={"w1": bg.flow("w1")})
    assert draw(model) == draw(bg.assign_causality(g)) == draw(g)


def test_without_causality_there_are_no_strokes():
    svg = draw(dc_motor(), causality=False)
    _, _, bonds = parse(svg)
    assert all(b["stroke"] is None for b in bonds.values())
    assert 'data-causal="0"' in svg


def test_submodels_as_boxes_with_port_ends():
    g = servo()
    root, elements, bonds = parse(draw(g, expand=False))
    assert elements["motor"]["kind"] == "sub" and elements["motor"]["label"] == "motor"
    assert set(elements) == {"motor", "load", "J", "b"}
    assert bonds[1]["tail"] == "motor.shaft"
    ports = [t.text for t in root.iter(f"{SVG}text") if t.get("class") == "port-name"]
    assert ports == ["shaft"]
    # the stroke of the port bond is where the flattened graph puts it (bond 6 there)
    flat_stroke = bg.assign_causality(g).bond(6).stroke
    want = "load" if flat_stroke == "load" else "motor.shaft"
    assert bonds[1]["stroke_el"].get("data-end") == want
    # and the expanded drawing has hierarchical names
    _, flat_elements, _ = parse(draw(g))
    assert {"motor.Ra", "motor.ia", "J"} <= set(flat_elements)


def test_unexpanded_strokes_follow_the_flattened_graph():
    g = twin()
    aug = bg.assign_causality(g)
    d = diagram(g, expand=False)
    by_top = {(e.tail, e.head): e for e in d.edges}
    for fb in aug.bonds:
        if fb.tail.startswith(("m1.", "m2.")) and fb.head == "shaft":
            sub = fb.tail.split(".")[0]
            e = by_top[(sub, "shaft")]
            assert e.stroke_end == ("shaft" if fb.stroke == "shaft" else f"{sub}.shaft")


def test_bad_inputs():
    aug = bg.assign_causality(dc_motor())
    with pytest.raises(DrawingError, match="expand=False"):
        draw(aug, expand=False)
    with pytest.raises(TypeError, match="BondGraph"):
        draw("not a graph")


def test_repr_svg_falls_back_instead_of_raising():
    g = bg.BondGraph("two_sf")
    g.add(bg.Sf("a"), bg.Sf("b"), bg.One("j"), bg.R("R"))
    connect_all(g, [("a", "j"), ("b", "j"), ("j", "R")])
    with pytest.raises(bg.CausalityConflictError):
        draw(g)
    svg = repr_svg(g)
    assert 'data-causal="0"' in svg and "Sf:a" in svg
    assert "Port:shaft" in repr_svg(motor())       # a sub-model alone, open port
    assert repr_svg(dc_motor()) == draw(dc_motor())


# ---------------------------------------------------------------- Jupyter displays (issue 13 item 6)
CORE_MODULES = ("graph.py", "causality.py", "model.py")


def _imported_modules(path):
    """Every module a source file imports (absolute names; relative ones as '.name')."""
    import ast

    names = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = "." * node.level + (node.module or "")
            names.add(base)
            names.update(f"{base}.{alias.name}" if node.module else base + alias.name
                         for alias in node.names)
    return names


def test_core_modules_do_not_import_drawing():
    package = os.path.join(os.path.dirname(bg.__file__))
    from pathlib import Path

    for name in CORE_MODULES:
        imported = _imported_modules(Path(package, name))
        bad = sorted(m for m in imported if "drawing" in m.split("."))
        assert bad == [], f"{name} imports {bad}"


def test_import_bondgraph_leaves_matplotlib_unloaded():
    import subprocess
    import sys

    # import bondgraph binds its names on first use; the first one registers the notebook
    # display, which loads the drawing package when it draws (never matplotlib for an SVG)
    code = ("import sys, bondgraph\n"
            "g = bondgraph.BondGraph('r'); g.add(bondgraph.Se('V'), bondgraph.R('R'))\n"
            "_ = g.connect('V', 'R')\n"
            "print('bondgraph.drawing' in sys.modules, 'matplotlib' in sys.modules,\n"
            "      callable(getattr(g, '_repr_svg_', None)))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False", "True"]


def test_displays_are_registered_by_the_drawing_package():
    import bondgraph.drawing as drawing

    g = dc_motor()
    model = bg.derive(dc_motor())
    for obj in (g, bg.assign_causality(g), model):
        svg = obj._repr_svg_()
        root = ET.fromstring(svg)
        assert root.tag == f"{SVG}svg"
        assert len(root.findall(f".//{SVG}line[@class='stroke']")) == 7  # one per bond
    for cls in (bg.BondGraph, bg.AugmentedBondGraph, bg.Model):
        assert cls._repr_svg_ is drawing._repr_svg_
