"""Drawing primitives: fonts and text widths, Bezier bonds, segment and box intersections.

The scene (:mod:`~bondgraph.drawing.scene`) lays a diagram out with them and
the geometry checks (:mod:`~bondgraph.drawing.geometry`) measure a finished
scene with the same ones, so both agree on what a crossing is.

Examples
--------
>>> from bondgraph.drawing.primitives import cross_segments, segment_hits_box
>>> cross_segments((0, 0), (2, 2), (0, 2), (2, 0)), segment_hits_box((0, 1), (3, 1), (1, 0, 1, 2))
(True, True)
"""

from __future__ import annotations

from functools import lru_cache
from typing import Optional

from .layout import Box

__all__ = ["FONT", "NOTE_FONT", "NUMBER_FONT", "TITLE_FONT", "FONT_FAMILY", "Point", "text_width",
           "bezier", "polyline", "segment_hits_box", "cross_segments"]

FONT = 14.0          # label font size, px
NOTE_FONT = 9.0      # junction names, port names
NUMBER_FONT = 10.0   # bond numbers
TITLE_FONT = 12.0
FONT_FAMILY = "DejaVu Sans"

Point = tuple[float, float]


@lru_cache(maxsize=4096)
def text_width(text: str, size: float, bold: bool = False) -> float:
    """Width in px of ``text`` in DejaVu Sans at ``size`` px (matplotlib's metrics).

    Examples
    --------
    >>> text_width("I:La", 14.0) > text_width("1", 14.0) > 0
    True
    """
    if not text:
        return 0.0
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import TextToPath

    prop = FontProperties(family=FONT_FAMILY, size=size, weight="bold" if bold else "normal")
    w, _, _ = TextToPath().get_text_width_height_descent(text, prop, ismath=False)
    return float(w)


def bezier(p0: Point, c: Optional[Point], p1: Point, t: float) -> Point:
    if c is None:
        return p0[0] + t * (p1[0] - p0[0]), p0[1] + t * (p1[1] - p0[1])
    a, b, d = (1 - t) ** 2, 2 * t * (1 - t), t * t
    return a * p0[0] + b * c[0] + d * p1[0], a * p0[1] + b * c[1] + d * p1[1]


def polyline(b, n: int = 24) -> list[Point]:
    """The drawn line of a bond (anything with ``start``, ``control``, ``end``): its two ends,
    or ``n`` pieces of its curve."""
    if b.control is None:
        return [b.start, b.end]
    return [bezier(b.start, b.control, b.end, k / n) for k in range(n + 1)]


def segment_hits_box(p: Point, q: Point, box: Box, shrink: float = 0.0) -> bool:
    """Whether segment p-q passes through ``box`` shrunk by ``shrink`` on every side (Liang-Barsky)."""
    x0, y0 = box[0] + shrink, box[1] + shrink
    x1, y1 = box[0] + box[2] - shrink, box[1] + box[3] - shrink
    if x0 >= x1 or y0 >= y1:
        return False
    dx, dy = q[0] - p[0], q[1] - p[1]
    t0, t1 = 0.0, 1.0
    for pk, qk in ((-dx, p[0] - x0), (dx, x1 - p[0]), (-dy, p[1] - y0), (dy, y1 - p[1])):
        if pk == 0:
            if qk < 0:
                return False
            continue
        t = qk / pk
        if pk < 0:
            t0 = max(t0, t)
        else:
            t1 = min(t1, t)
        if t0 > t1:
            return False
    return True


def cross_segments(p1: Point, p2: Point, q1: Point, q2: Point) -> bool:
    """Whether segments p1-p2 and q1-q2 cross at a point inside both (touching is not crossing)."""
    def orient(a: Point, b: Point, c: Point) -> int:
        v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        return 0 if abs(v) < 1e-9 else (1 if v > 0 else -1)
    return (orient(p1, p2, q1) * orient(p1, p2, q2) < 0) and (orient(q1, q2, p1) * orient(q1, q2, p2) < 0)
