"""Geometry of a drawing: label boxes, bond lines, half-arrows, causal strokes.

:func:`build_scene` places a :class:`~bondgraph.drawing.source.Diagram` with
:func:`~bondgraph.drawing.layout.grid_layout` and computes every shape in
pixels (``y`` downward).  The SVG writer and the matplotlib renderer draw the
same :class:`Scene`, so both outputs agree.

Conventions
-----------
* A bond runs between the label boxes of its ends (clipped to the boxes);
  one that would cross another label (a loop of the junction structure)
  bends round it as a quadratic curve.
* The half-arrow is a single barb at the head, on the left of the direction
  of positive power (``⇀`` for a bond pointing right).
* The causal stroke is a short line across the bond at the end of the
  element that receives effort (``stroke_end``).
* The bond number sits beside the middle of the bond, opposite the barb.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.drawing.source import diagram
>>> g = bg.BondGraph("rl")
>>> V, j = bg.Se("V"), bg.One("j")
>>> g.add(V, j, bg.R("R"), bg.I("L"))
>>> for t, h in [(V, j), (j, "R"), (j, "L")]: _ = g.connect(t, h)
>>> sc = build_scene(diagram(g))
>>> b = sc.bonds[0]
>>> b.stroke_end, b.stroke is not None
('j', True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Optional

from .layered import layered_layout, layered_roots
from .layout import Box, grid_layout, overlapping_pairs
from .primitives import (FONT, FONT_FAMILY, NOTE_FONT, NUMBER_FONT, TITLE_FONT,  # noqa: F401
                         Point, bezier, polyline, segment_hits_box, text_width)
from ..elements.protocol import drawing_role
from .source import Diagram

__all__ = ["Label", "BondShape", "Scene", "build_scene", "text_width", "label_font",
           "FONT", "NOTE_FONT", "NUMBER_FONT", "COLORS"]

PAD = 3.0            # label box padding
HGAP = 46.0          # free space between columns
VGAP = 38.0          # free space between rows
EMPTY = 20.0         # size of an empty column or row
MARGIN = 16.0
BARB = (9.0, 5.5)    # half-arrow: length back along the bond, offset to the side
STROKE = 7.0         # half length of a causal stroke
NUMBER_OFFSET = 8.0

COLORS = {
    "ink": "#222222",
    "number": "#555555",
    "derivative": "#d62728",
    "derivative_fill": "#fde0e0",
    "loop": "#ff7f0e",
    "sub": "#1f5f9f",
    "sub_fill": "#eef4fb",
    "title": "#777777",
}


def label_font(role: str) -> tuple[float, bool]:
    """Font size (px) and boldness of a node's main text.

    Parameters
    ----------
    role : str
        The node's drawing role (``'junction'``, ``'sub'``, ...), as in
        :class:`~bondgraph.drawing.source.Node`, or an element kind (``'1'``,
        ``'R'``), which stands for its element class's role.

    Returns
    -------
    (float, bool)

    Examples
    --------
    >>> label_font("1"), label_font("R"), label_font("sub")
    ((15.0, True), (14.0, False), (14.0, True))
    """
    role = drawing_role(role)
    if role == "junction":
        return FONT + 1, True
    return FONT, role == "sub"


Segment = tuple[Point, Point]


@dataclass(frozen=True)
class Label:
    """A node's text and box, in px.

    ``x, y`` is the centre of the main text; ``box`` is ``(x, y, w, h)`` with
    its top-left corner and covers the main text and the note.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("rl")
    >>> g.add(bg.Se("V"), bg.One("j"), bg.R("R"), bg.I("L"))
    >>> for tail, head in [("V", "j"), ("j", "R"), ("j", "L")]: _ = g.connect(tail, head)
    >>> from bondgraph.drawing.source import diagram
    >>> lb = build_scene(diagram(g)).label("j")
    >>> lb.kind, lb.text, lb.note, lb.color, len(lb.box)
    ('1', '1', 'j', '#222222', 4)
    """

    name: str
    kind: str
    text: str
    note: str
    x: float
    y: float
    text_width: float
    box: Box
    derivative: bool = False
    arbitrary: bool = False
    role: str = "backbone"

    @property
    def note_at(self) -> Point:
        """Left end and vertical centre of the note (junction name)."""
        return self.x + self.text_width / 2 + 1.0, self.y + FONT * 0.32

    @property
    def color(self) -> str:
        if self.derivative:
            return COLORS["derivative"]
        if self.role == "sub":
            return COLORS["sub"]
        if self.arbitrary:
            return COLORS["loop"]
        return COLORS["ink"]


@dataclass(frozen=True)
class BondShape:
    """A bond's shapes, in px.

    Attributes
    ----------
    start, end : point
        The line from the tail box to the head box.
    barb : point
        Free end of the half-arrow (its other end is ``end``).
    stroke : segment or None
        The causal stroke, across the line at ``stroke_end``.
    number_at : point
        Centre of the bond number.
    ports : tuple of (text, point)
        Port names of sub-model ends.
    control : point or None
        Control point of a bond bent round a label (a quadratic Bezier curve
        from ``start`` to ``end``); None for a straight bond.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("rl")
    >>> g.add(bg.Se("V"), bg.One("j"), bg.R("R"), bg.I("L"))
    >>> for tail, head in [("V", "j"), ("j", "R"), ("j", "L")]: _ = g.connect(tail, head)
    >>> from bondgraph.drawing.source import diagram
    >>> b = build_scene(diagram(g)).bonds[2]
    >>> b.number, b.tail, b.head, b.stroke_end, b.control, b.loop
    (3, 'j', 'L', 'L', None, False)
    """

    number: int
    tail: str
    head: str
    start: Point
    end: Point
    barb: Point
    stroke: Optional[Segment]
    stroke_end: Optional[str]
    number_at: Point
    loop: bool = False
    ports: tuple[tuple[str, Point], ...] = ()
    control: Optional[Point] = None

    @property
    def color(self) -> str:
        return COLORS["loop"] if self.loop else COLORS["ink"]


@dataclass(frozen=True)
class Scene:
    """Everything to draw, in px (``y`` downward); made by :func:`build_scene`.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("rl")
    >>> g.add(bg.Se("V"), bg.One("j"), bg.R("R"), bg.I("L"))
    >>> for tail, head in [("V", "j"), ("j", "R"), ("j", "L")]: _ = g.connect(tail, head)
    >>> from bondgraph.drawing.source import diagram
    >>> sc = build_scene(diagram(g))
    >>> sc.title, sc.causal, len(sc.labels), len(sc.bonds), sc.overlaps()
    ('rl', True, 4, 3, [])
    >>> sc.label("R").text
    'R:R'
    """

    name: str
    width: float
    height: float
    labels: tuple[Label, ...]
    bonds: tuple[BondShape, ...]
    legend: tuple[tuple[str, str], ...]      # (entry, text); entry 'derivative' or 'loop'
    legend_at: Point
    title: str
    causal: bool
    #: draw the bond numbers
    numbers: bool = True
    #: label elements with LaTeX names in TikZ (``I:$m_{1}$``)
    latex: bool = False

    def label(self, name: str) -> Label:
        """The label of node ``name``."""
        for lb in self.labels:
            if lb.name == name:
                return lb
        raise KeyError(name)

    def overlaps(self) -> list[tuple[str, str]]:
        """Pairs of labels whose boxes overlap (empty for a good layout)."""
        return overlapping_pairs({lb.name: lb.box for lb in self.labels})


def _label_size(text: str, note: str, role: str) -> tuple[float, float, float, float]:
    """(text width, left extent, right extent, height) about the main text's centre."""
    size, bold = label_font(role)
    tw = text_width(text, size, bold)
    if role == "sub":
        half = tw / 2 + PAD + 7
        return tw, half, half, FONT + 2 * PAD + 10
    nw = text_width(note, NOTE_FONT)
    left = tw / 2 + PAD
    right = left + (nw + 1 if note else 0)
    h = FONT + 2 * PAD + (NOTE_FONT * 0.45 if note else 0)
    return tw, left, right, h


def build_scene(diag: Diagram, *, wrap: int = 14, title: bool = True, numbers: bool = True,
                max_width: Optional[float] = None, font_pt: float = 8.0, latex: bool = False) -> Scene:
    """Lay out a diagram and compute every shape.

    Parameters
    ----------
    diag : Diagram
    wrap : int
        Longest run of the main path on one row (see :func:`grid_layout`).
    title : bool
        Reserve a line at the top for the graph's name.
    numbers : bool
        Draw the bond numbers.
    max_width : float, optional
        Width in cm the figure must fit when its labels are printed at
        ``font_pt`` points.  Candidate layouts are tried in turn: the comb
        of :func:`grid_layout` with its main path wrapped into more, shorter
        rows (``wrap`` lowered step by step down to 2), then the layered
        layouts of :func:`~bondgraph.drawing.layered.layered_layout`.  The
        first that fits with no bond through a label and no bond crossing
        is kept; failing that, of those that fit, one with no bond through
        a label and the fewest crossings (else any that fits); the narrowest
        when none fits.
    font_pt : float
        Label size in points for ``max_width``.
    latex : bool
        Mark the scene for LaTeX element names in TikZ.

    Returns
    -------
    Scene

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.drawing.source import diagram
    >>> g = bg.BondGraph("r"); g.add(bg.Se("V"), bg.R("R")); _ = g.connect("V", "R")
    >>> sc = build_scene(diagram(g))
    >>> [lb.text for lb in sc.labels], sc.overlaps()
    (['Se:V', 'R:R'], [])
    """
    if max_width is None:
        return _build_scene(diag, _comb_cells(diag, wrap), title, numbers, latex)
    from .geometry import bond_crossings, bonds_through_labels, printed_size

    if not (isinstance(max_width, (int, float)) and math.isfinite(max_width) and max_width > 0):
        from .source import DrawingError
        raise DrawingError(f"max_width must be a positive width in cm; got {max_width!r}")
    best: Optional[tuple] = None
    for k, (comb, cells) in enumerate(_candidates(diag, wrap)):
        scene = _build_scene(diag, cells, title, numbers, latex)
        width = printed_size(scene, font_pt=font_pt)[0]
        fits = width <= max_width
        through = len(bonds_through_labels(scene))
        crossed = len(bond_crossings(scene)) if fits and not through else 0
        bent = sum(b.control is not None for b in scene.bonds)
        length = sum(math.dist(b.start, b.end) for b in scene.bonds)
        # fitting first, then no bond through a label, fewest crossings; then the first comb,
        # else the layered layout with the fewest bent bonds and the shortest bonds
        # (a figure that does not fit at all: the narrowest)
        key = (bool(scene.overlaps()), not fits, through > 0, crossed, 0.0 if fits else width,
               not comb, 0 if comb else bent, 0.0 if comb else length, k)
        if best is None or key < best[0]:
            best = (key, scene)
        if comb and fits and not through and not crossed:
            break
    assert best is not None
    return best[1]


def _comb_cells(diag: Diagram, wrap: int) -> dict[str, tuple[int, int]]:
    return grid_layout([n.name for n in diag.nodes], {n.name: n.role for n in diag.nodes},
                       [(e.tail, e.head) for e in diag.edges], wrap=wrap)


def _candidates(diag: Diagram, wrap: int):
    """Cell layouts tried to fit a width, best-looking first: the comb with the main path
    wrapped at ``wrap`` columns, then at fewer, down to 2 (the width is not monotonic in
    the wrap: every one is tried); then the layered layout from each centre of the junction
    structure, layers as rows and as columns (:mod:`~bondgraph.drawing.layered`)."""
    names = [n.name for n in diag.nodes]
    roles = {n.name: n.role for n in diag.nodes}
    edges = [(e.tail, e.head) for e in diag.edges]
    first = grid_layout(names, roles, edges, wrap=wrap)     # (refuses a wrap below 2)
    yield True, first
    seen = [first]
    for w in range(wrap - 1, 1, -1):
        cells = grid_layout(names, roles, edges, wrap=w)
        if cells not in seen:
            seen.append(cells)
            yield True, cells
    for root in layered_roots(names, roles, edges)[:3]:
        for transpose in (False, True):
            cells = layered_layout(names, roles, edges, root=root, transpose=transpose)
            if cells not in seen:
                seen.append(cells)
                yield False, cells


def _build_scene(diag: Diagram, cells: dict[str, tuple[int, int]], title: bool, numbers: bool,
                 latex: bool) -> Scene:
    sizes = {n.name: _label_size(n.text, n.note, n.role) for n in diag.nodes}

    ncol = max(c for c, _ in cells.values()) + 1
    nrow = max(r for _, r in cells.values()) + 1
    # a column is as wide as its labels reach left and right of its centre line
    # (a junction's name hangs to the right only)
    col_l = [0.0] * ncol
    col_r = [0.0] * ncol
    row_h = [EMPTY] * nrow
    room = _port_room(diag)
    for name, (c, r) in cells.items():
        _, left, right, h = sizes[name]
        col_l[c] = max(col_l[c], left + room.get(name, 0.0))
        col_r[c] = max(col_r[c], right + room.get(name, 0.0))
        row_h[r] = max(row_h[r], h + VGAP)
    col_w = [max(EMPTY, a + b + HGAP) for a, b in zip(col_l, col_r)]
    top = MARGIN + (TITLE_FONT + 8 if title else 0)
    # parallel bonds between the same two nodes are spread apart
    groups: dict[frozenset, list[int]] = {}
    for k, e in enumerate(diag.edges):
        groups.setdefault(frozenset((e.tail, e.head)), []).append(k)
    shift = {}
    for ks in groups.values():
        for i, k in enumerate(ks):
            shift[k] = (i - (len(ks) - 1) / 2) * 12.0

    # place everything; bonds bent round labels may stick out: then shift and grow
    dx = dy = grow_x = grow_y = 0.0
    for _ in range(2):
        xs = _centres(col_w, MARGIN + dx, [HGAP / 2 + a if a + b else w / 2
                                            for a, b, w in zip(col_l, col_r, col_w)])
        ys = _centres(row_h, top - VGAP / 2 + 4 + dy)
        labels = []
        for n in diag.nodes:
            c, r = cells[n.name]
            tw, left, right, h = sizes[n.name]
            cx, cy = xs[c], ys[r]
            # the main text is centred on its cell; a junction's name hangs to its right
            box = (cx - left, cy - h / 2, left + right, h)
            ty = cy - (NOTE_FONT * 0.45 / 2 if n.note else 0)
            labels.append(Label(n.name, n.kind, n.text, n.note, cx, ty, tw, box,
                                n.derivative, n.arbitrary, n.role))
        by_name = {lb.name: lb for lb in labels}
        avoid = [lb.box for lb in labels]
        bonds = _place_numbers([_bond_shape(e, by_name[e.tail], by_name[e.head], shift[k], avoid)
                                for k, e in enumerate(diag.edges)], avoid)
        width = MARGIN + sum(col_w) + MARGIN - HGAP / 2 + dx + grow_x
        height = top + sum(row_h) - VGAP / 2 + 4 + dy + grow_y
        x0, y0, x1, y1 = _extent(bonds)
        # labels (a junction's name hangs to its right) must fit on the canvas too
        x0 = min([x0] + [lb.box[0] for lb in labels])
        y0 = min([y0] + [lb.box[1] for lb in labels])
        x1 = max([x1] + [lb.box[0] + lb.box[2] for lb in labels])
        y1 = max([y1] + [lb.box[1] + lb.box[3] for lb in labels])
        if dx or dy or grow_x or grow_y:
            break
        dx, dy = max(0.0, MARGIN / 2 - x0), max(0.0, top - 4 - y0)
        grow_x = max(0.0, x1 + dx - (width - MARGIN / 2))
        grow_y = max(0.0, y1 + dy - (height - 4))
        if not (dx or dy or grow_x or grow_y):
            break
    legend = []
    if any(lb.derivative for lb in labels):
        legend.append(("derivative", "storage in derivative causality"))
    if any(b.loop for b in bonds):
        legend.append(("loop", "algebraic loop (arbitrary causality)"))
    legend_at = (MARGIN, height)
    if legend:
        height += 18 * len(legend) + 6
        lw = 40 + max(text_width(t, NOTE_FONT + 2) for _, t in legend)
        width = max(width, MARGIN + lw + MARGIN)
    height += MARGIN / 2
    ttl = diag.name if title else ""
    if ttl:
        width = max(width, 2 * MARGIN + text_width(ttl, TITLE_FONT))
    return Scene(diag.name, math.ceil(width), math.ceil(height), tuple(labels),
                 tuple(bonds), tuple(legend), legend_at, ttl, diag.causal, numbers, latex)


def _extent(bonds) -> tuple[float, float, float, float]:
    """Bounding box of the bent bonds and of all bond numbers."""
    xs, ys = [], []
    for b in bonds:
        pts = [b.number_at]
        if b.control is not None:
            pts += [bezier(b.start, b.control, b.end, k / 20) for k in range(21)]
        for x, y in pts:
            xs.append(x)
            ys.append(y)
    if not xs:
        return math.inf, math.inf, -math.inf, -math.inf
    return min(xs) - 8, min(ys) - 8, max(xs) + 8, max(ys) + 8


def _port_room(diag: Diagram) -> dict[str, float]:
    """Extra width beside sub-model boxes for the port names on their bonds."""
    room: dict[str, float] = {}
    for e in diag.edges:
        for node, port in ((e.tail, e.tail_port), (e.head, e.head_port)):
            if port:
                room[node] = max(room.get(node, 0.0), text_width(port, NOTE_FONT) + 6)
    return room


def _centres(sizes: list[float], start: float, offsets: Optional[list[float]] = None) -> list[float]:
    """Centre lines of consecutive cells of ``sizes`` from ``start`` (at ``offsets`` into
    each cell; the middle by default)."""
    out, x = [], start
    for k, s in enumerate(sizes):
        out.append(x + (offsets[k] if offsets is not None else s / 2))
        x += s
    return out


def _clip(cx: float, cy: float, box: Box, ux: float, uy: float) -> float:
    """Distance from (cx, cy) along unit (ux, uy) to the edge of ``box`` (+2 px)."""
    bx, by, bw, bh = box
    tx = ((bx + bw - cx) if ux > 0 else (cx - bx)) / abs(ux) if abs(ux) > 1e-9 else math.inf
    ty = ((by + bh - cy) if uy > 0 else (cy - by)) / abs(uy) if abs(uy) > 1e-9 else math.inf
    return min(tx, ty) + 2.0


def _anchor(lb: Label) -> Point:
    """Where bonds aim: the main text's centre across, the box's centre down."""
    return lb.x, lb.box[1] + lb.box[3] / 2


def _unit(dx: float, dy: float) -> Point:
    L = math.hypot(dx, dy) or 1.0
    return dx / L, dy / L


def _crossed(p0: Point, c: Optional[Point], p1: Point, boxes: list[Box]) -> int:
    """How many of ``boxes`` (grown by 2 px) the line (or curve) from p0 to p1 passes through."""
    pts = [bezier(p0, c, p1, k / 40) for k in range(41)] if c is not None else [p0, p1]
    segs = list(zip(pts, pts[1:]))
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    near = [box for box in boxes if _hit(box, (min(xs) - 3, min(ys) - 3, max(xs) - min(xs) + 6,
                                               max(ys) - min(ys) + 6))]
    return sum(any(segment_hits_box(a, b, box, -2.0) for a, b in segs) for box in near)


#: bends tried for a bond that would cross a label: control point offsets across the bond,
#: in units of its length, smallest first
_BENDS = tuple(sorted((s * k / 20 for k in range(5, 41) for s in (1, -1)), key=abs))


def _bond_shape(e, tail, head, shift: float, avoid: list[Box]) -> BondShape:
    (ax, ay), (bx, by) = _anchor(tail), _anchor(head)
    ux, uy = _unit(bx - ax, by - ay)
    nx_, ny_ = uy, -ux                      # left of the direction of travel (y down)
    ax, ay, bx, by = ax + shift * nx_, ay + shift * ny_, bx + shift * nx_, by + shift * ny_
    # a bond that would run through another label bends round it (a quadratic curve)
    others = [b for b in avoid if b is not tail.box and b is not head.box]
    ctrl: Optional[Point] = None
    if _crossed((ax, ay), None, (bx, by), others):
        L = math.hypot(bx - ax, by - ay)
        mid = ((ax + bx) / 2, (ay + by) / 2)
        best = None
        # bends across the bond's middle first, then control points moved along it too
        for along in (0.0, -0.3, 0.3):
            for k in _BENDS:
                c = (mid[0] + k * L * nx_ + along * L * ux, mid[1] + k * L * ny_ + along * L * uy)
                hits = _crossed((ax, ay), c, (bx, by), others)
                if best is None or hits < best[0]:
                    best = (hits, c)
                if hits == 0:
                    break
            if best is not None and best[0] == 0:
                break
        if best is not None and best[0] < _crossed((ax, ay), None, (bx, by), others):
            ctrl = best[1]
    u0 = _unit(ctrl[0] - ax, ctrl[1] - ay) if ctrl else (ux, uy)
    u1 = _unit(bx - ctrl[0], by - ctrl[1]) if ctrl else (ux, uy)
    d0 = _clip(ax, ay, tail.box, *u0)
    d1 = _clip(bx, by, head.box, -u1[0], -u1[1])
    start = (ax + d0 * u0[0], ay + d0 * u0[1])
    end = (bx - d1 * u1[0], by - d1 * u1[1])
    n0, n1 = (u0[1], -u0[0]), (u1[1], -u1[0])
    blen, bside = BARB
    barb = (end[0] - blen * u1[0] + bside * n1[0], end[1] - blen * u1[1] + bside * n1[1])
    stroke = None
    if e.stroke_end is not None:
        (px, py), n = (end, n1) if e.stroke_at_head else (start, n0)
        stroke = ((px - STROKE * n[0], py - STROKE * n[1]),
                  (px + STROKE * n[0], py + STROKE * n[1]))
    number_at = _number_position(str(e.number), start, ctrl, end, avoid)
    ports = []
    for port, pt, u, sgn in ((e.tail_port, start, u0, 1.0), (e.head_port, end, u1, -1.0)):
        if port:
            w = text_width(port, NOTE_FONT)
            off = 6 + w / 2 * abs(u[0]) + NOTE_FONT / 2 * abs(u[1])
            n = (u[1], -u[0])
            ports.append((port, (pt[0] + sgn * u[0] * off + n[0] * 9,
                                 pt[1] + sgn * u[1] * off + n[1] * 9)))
    tail_end = e.tail if not e.tail_port else f"{e.tail}.{e.tail_port}"
    head_end = e.head if not e.head_port else f"{e.head}.{e.head_port}"
    return BondShape(e.number, tail_end, head_end, start, end, barb, stroke, e.stroke_end,
                     number_at, e.loop, tuple(ports), ctrl)


def _number_position(text: str, start: Point, ctrl: Optional[Point], end: Point,
                     avoid: list[Box]) -> Point:
    """Beside the bond, opposite the barb; moved along it or across if on a label."""
    w = text_width(text, NUMBER_FONT)
    h = NUMBER_FONT
    first = None
    for t in (0.5, 0.35, 0.65):
        px, py = bezier(start, ctrl, end, t)
        q = bezier(start, ctrl, end, t + 0.01)
        ux, uy = _unit(q[0] - px, q[1] - py)
        n = (uy, -ux)
        # distance from the line to the centre of the number's box, across the bond
        across = NUMBER_OFFSET + abs(n[0]) * w / 2 + abs(n[1]) * h / 2
        for side in (-1.0, 1.0):
            mx, my = px + side * across * n[0], py + side * across * n[1]
            box = (mx - w / 2, my - h / 2, w, h)
            if first is None:
                first = (mx, my)
            if not any(_hit(box, b) for b in avoid):
                return mx, my
    return first  # type: ignore[return-value]


def _place_numbers(bonds: list[BondShape], avoid: list[Box]) -> list[BondShape]:
    """Bond numbers moved off every label, every other bond and the numbers placed before.

    Candidates: along the bond at 0.5, 0.35, 0.65, 0.2, 0.8 of its length,
    opposite the barb first, then the barb's side, at the usual distance and
    farther; the first free one wins, else the number stays where it was.
    """
    lines = [list(zip(pts, pts[1:])) for pts in (polyline(b) for b in bonds)]
    spans = [_span(b) for b in bonds]
    placed: list[Box] = []
    out = []
    for k, b in enumerate(bonds):
        text = str(b.number)
        w, h = text_width(text, NUMBER_FONT), NUMBER_FONT
        chosen = None
        for extra in (0.0, 6.0, 12.0):
            for t in (0.5, 0.35, 0.65, 0.2, 0.8):
                px, py = bezier(b.start, b.control, b.end, t)
                q = bezier(b.start, b.control, b.end, min(t + 0.01, 1.0))
                ux, uy = _unit(q[0] - px, q[1] - py)
                n = (uy, -ux)
                across = NUMBER_OFFSET + extra + abs(n[0]) * w / 2 + abs(n[1]) * h / 2
                for side in (-1.0, 1.0):
                    mx, my = px + side * across * n[0], py + side * across * n[1]
                    box = (mx - w / 2 - 1, my - h / 2 - 1, w + 2, h + 2)
                    if any(_hit(box, a) for a in avoid) or any(_hit(box, a) for a in placed):
                        continue
                    if any(segment_hits_box(p0, p1, box) for j, segs in enumerate(lines)
                           if j != k and _hit(box, spans[j]) for p0, p1 in segs):
                        continue
                    chosen = (mx, my)
                    break
                if chosen:
                    break
            if chosen:
                break
        at = chosen or b.number_at
        placed.append((at[0] - w / 2, at[1] - h / 2, w, h))
        out.append(replace(b, number_at=at))
    return out


def _span(b: BondShape, margin: float = 2.0) -> Box:
    """A box round a bond's drawn line, ``margin`` px wider on every side."""
    pts = polyline(b)
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    return (min(xs) - margin, min(ys) - margin, max(xs) - min(xs) + 2 * margin,
            max(ys) - min(ys) + 2 * margin)


def _hit(a: Box, b: Box) -> bool:
    return a[0] < b[0] + b[2] and b[0] < a[0] + a[2] and a[1] < b[1] + b[3] and b[1] < a[1] + a[3]
