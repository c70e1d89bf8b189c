"""Checks on a drawn scene: bonds through labels, bond crossings, printed size.

A :class:`~bondgraph.drawing.scene.Scene` is in px (``y`` down).  These
functions read only its coordinates, so they check what the SVG, PNG and
TikZ writers draw:

* :func:`bonds_through_labels` -- every (bond, label) pair where the bond's
  line or curve passes through a label box other than its own two ends'
  (a bond number's box counts as a label: a bond must not run over another
  bond's number either);
* :func:`bond_crossings` -- pairs of bonds whose lines cross (sharing an end
  is not a crossing);
* :func:`printed_size` -- the figure's width and height in cm when its
  labels are printed at ``font_pt`` points.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.drawing.scene import build_scene
>>> from bondgraph.drawing.source import diagram
>>> g = bg.BondGraph("rl")
>>> g.add(bg.Se("V"), bg.One("j"), bg.R("R"), bg.I("L"))
>>> for t, h in [("V", "j"), ("j", "R"), ("j", "L")]: _ = g.connect(t, h)
>>> sc = build_scene(diagram(g))
>>> bonds_through_labels(sc), bond_crossings(sc)
([], [])
"""

from __future__ import annotations

import math

from typing import Any

from .primitives import FONT, NUMBER_FONT, cross_segments, polyline, segment_hits_box, text_width

Scene = Any     # a bondgraph.drawing.scene.Scene (measured, not built, here)

__all__ = ["bonds_through_labels", "bond_crossings", "printed_size", "CM_PER_PT"]

#: centimetres per TeX point
CM_PER_PT = 2.54 / 72.27


def _number_boxes(scene: Scene):
    out = {}
    for b in scene.bonds:
        if b.number_at is None:
            continue
        w = text_width(str(b.number), NUMBER_FONT)
        x, y = b.number_at
        out[b.number] = (x - w / 2, y - NUMBER_FONT / 2, w, NUMBER_FONT)
    return out


def bonds_through_labels(scene: Scene, *, tolerance: float = 1.0) -> list[tuple[int, str]]:
    """``(bond number, label)`` pairs where a bond crosses a label or another bond's number.

    A label is an element or junction box (named by its node) or a bond
    number (named ``'#N'``); a bond's own end boxes and its own number do not
    count.  Boxes are shrunk by ``tolerance`` px, so grazing an edge is not
    a crossing.
    """
    found = []
    numbers = _number_boxes(scene)
    names = {lb.name for lb in scene.labels}
    for b in scene.bonds:
        own = {_end_node(b.tail, names), _end_node(b.head, names)}
        pts = polyline(b)
        segs = list(zip(pts, pts[1:]))
        x0, x1 = min(p[0] for p in pts) - 1, max(p[0] for p in pts) + 1
        y0, y1 = min(p[1] for p in pts) - 1, max(p[1] for p in pts) + 1

        def near(box) -> bool:        # the box reaches the bond's extent at all
            return box[0] < x1 and x0 < box[0] + box[2] and box[1] < y1 and y0 < box[1] + box[3]

        for lb in scene.labels:
            if lb.name in own or not near(lb.box):
                continue
            if any(segment_hits_box(p, q, lb.box, tolerance) for p, q in segs):
                found.append((b.number, lb.name))
        for num, box in numbers.items():
            if num == b.number or not near(box):
                continue
            if any(segment_hits_box(p, q, box, tolerance) for p, q in segs):
                found.append((b.number, f"#{num}"))
    return found


def _end_node(end: str, names: set) -> str:
    """The node of a bond end (``'motor.shaft'`` is port ``shaft`` of node ``motor``)."""
    if end in names:
        return end
    head, _, _ = end.rpartition(".")
    return head if head in names else end


def bond_crossings(scene: Scene) -> list[tuple[int, int]]:
    """Pairs of bond numbers whose drawn lines cross (bonds sharing a node excluded)."""
    names = {lb.name for lb in scene.labels}
    shapes = [(b.number, {_end_node(b.tail, names), _end_node(b.head, names)}, polyline(b))
              for b in scene.bonds]
    out = []
    for i, (na, ea, pa) in enumerate(shapes):
        for nb, eb, pb in shapes[i + 1:]:
            if ea & eb:
                continue
            if any(cross_segments(p, q, r, s) for p, q in zip(pa, pa[1:]) for r, s in zip(pb, pb[1:])):
                out.append((na, nb))
    return out


def printed_size(scene: Scene, *, font_pt: float = 8.0) -> tuple[float, float]:
    """``(width, height)`` in cm of ``scene`` printed with its labels at ``font_pt`` points.

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.drawing.scene import build_scene
    >>> from bondgraph.drawing.source import diagram
    >>> g = bg.BondGraph("r"); g.add(bg.Se("V"), bg.R("R")); _ = g.connect("V", "R")
    >>> w, h = printed_size(build_scene(diagram(g)), font_pt=8.0)
    >>> 0 < w < 5 and 0 < h < 3
    True
    """
    if not (isinstance(font_pt, (int, float)) and math.isfinite(font_pt) and font_pt > 0):
        from .source import DrawingError
        raise DrawingError(f"font_pt must be a positive number of points; got {font_pt!r}")
    scale = font_pt / FONT * CM_PER_PT
    return scene.width * scale, scene.height * scale
