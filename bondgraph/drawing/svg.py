"""Write a :class:`~bondgraph.drawing.scene.Scene` as SVG text.

The SVG carries machine-readable attributes so drawings can be checked and
styled: each bond is a ``<g class="bond" data-bond="3" data-tail=... data-head=...>``
holding a ``bond-line`` (a ``<line>``, or a ``<path>`` for a bond bent round
a label), a ``half-arrow`` and, with causality, a
``<line class="stroke" data-bond="3" data-end="J2">`` whose ``data-end`` names
the element at the stroke end; each element is a
``<g class="element" data-name=... data-kind=...>`` with a ``label-box`` rect.

Examples
--------
>>> import xml.etree.ElementTree as ET
>>> import bondgraph as bg
>>> from bondgraph.drawing.scene import build_scene
>>> from bondgraph.drawing.source import diagram
>>> g = bg.BondGraph("r"); g.add(bg.Se("V"), bg.R("R")); _ = g.connect("V", "R")
>>> root = ET.fromstring(scene_to_svg(build_scene(diagram(g))))
>>> root.tag
'{http://www.w3.org/2000/svg}svg'
"""

from __future__ import annotations

from xml.sax.saxutils import escape, quoteattr

from .scene import (COLORS, FONT_FAMILY, NOTE_FONT, NUMBER_FONT, TITLE_FONT, BondShape,
                    Label, Scene, label_font)

__all__ = ["scene_to_svg"]

_FAMILY = f"{FONT_FAMILY}, Arial, Helvetica, sans-serif"


def _f(v: float) -> str:
    return f"{v:.1f}".rstrip("0").rstrip(".") if v != int(v) else str(int(v))


def _attrs(**kw) -> str:
    out = []
    for k, v in kw.items():
        if v is None:
            continue
        if isinstance(v, float):
            v = _f(v)
        out.append(f"{k.rstrip('_').replace('_', '-')}={quoteattr(str(v))}")
    return " ".join(out)


def _text(x: float, y: float, s: str, *, size: float, cls: str, fill: str,
          anchor: str = "middle", weight: str = "normal", halo: bool = False) -> str:
    extra = ' stroke="white" stroke-width="3" stroke-linejoin="round" paint-order="stroke"' \
        if halo else ""
    return (f'<text {_attrs(class_=cls, x=float(x), y=float(y), dy="0.35em")} '
            f'font-size="{_f(size)}" text-anchor="{anchor}" font-weight="{weight}" '
            f'fill="{fill}"{extra}>{escape(s)}</text>')


def _bond(b: BondShape, numbers: bool = True) -> list[str]:
    col = b.color
    width = "2" if b.loop else "1.3"
    (x0, y0), (x1, y1) = b.start, b.end
    data = _attrs(class_="bond", data_bond=b.number, data_tail=b.tail, data_head=b.head,
                  data_loop="1" if b.loop else None)
    out = [f"<g {data}>"]
    paint = f'stroke="{col}" stroke-width="{width}" stroke-linecap="round"'
    if b.control is None:
        coords = _attrs(x1=float(x0), y1=float(y0), x2=float(x1), y2=float(y1))
        out.append(f'<line class="bond-line" {coords} {paint}/>')
    else:
        cx, cy = b.control
        d = f"M {_f(x0)} {_f(y0)} Q {_f(cx)} {_f(cy)} {_f(x1)} {_f(y1)}"
        out.append(f'<path class="bond-line" d="{d}" fill="none" {paint}/>')
    bx, by = b.barb
    out.append(f'<polyline class="half-arrow" points="{_f(x1)},{_f(y1)} {_f(bx)},{_f(by)}" '
               f'fill="none" {paint}/>')
    if b.stroke is not None:
        (sx0, sy0), (sx1, sy1) = b.stroke
        attrs = _attrs(class_="stroke", data_bond=b.number, data_end=b.stroke_end,
                       x1=float(sx0), y1=float(sy0), x2=float(sx1), y2=float(sy1))
        out.append(f'<line {attrs} stroke="{col}" stroke-width="2" stroke-linecap="round"/>')
    if numbers:
        nx_, ny_ = b.number_at
        out.append(_text(nx_, ny_, str(b.number), size=NUMBER_FONT, cls="bond-number",
                         fill=COLORS["number"], halo=True))
    for port, (px, py) in b.ports:
        out.append(_text(px, py, port, size=NOTE_FONT, cls="port-name", fill=COLORS["sub"],
                         halo=True))
    out.append("</g>")
    return out


def _label(lb: Label) -> list[str]:
    x, y, w, h = lb.box
    data = _attrs(class_="element", data_name=lb.name, data_kind=lb.kind,
                  data_causality="derivative" if lb.derivative else None)
    out = [f"<g {data}>"]
    if lb.role == "sub":
        style = f'fill="{COLORS["sub_fill"]}" stroke="{COLORS["sub"]}" stroke-width="1.5" rx="6"'
    elif lb.derivative:
        style = (f'fill="{COLORS["derivative_fill"]}" stroke="{COLORS["derivative"]}" '
                 'stroke-width="1.2" rx="3"')
    else:
        style = 'fill="white" fill-opacity="0.85" stroke="none"'
    box = _attrs(class_="label-box", x=float(x), y=float(y), width=float(w), height=float(h))
    out.append(f"<rect {box} {style}/>")
    size, bold = label_font(lb.role)
    out.append(_text(lb.x, lb.y, lb.text, size=size, cls="label", fill=lb.color,
                     weight="bold" if bold else "normal"))
    if lb.note:
        nx_, ny_ = lb.note_at
        out.append(_text(nx_, ny_, lb.note, size=NOTE_FONT, cls="note", fill=COLORS["number"],
                         anchor="start"))
    out.append("</g>")
    return out


def scene_to_svg(scene: Scene) -> str:
    """SVG text of a scene.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    str
        A standalone SVG document (no XML declaration, so it can be inlined).

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.drawing.scene import build_scene
    >>> from bondgraph.drawing.source import diagram
    >>> g = bg.BondGraph("r"); g.add(bg.Se("V"), bg.R("R")); _ = g.connect("V", "R")
    >>> svg = scene_to_svg(build_scene(diagram(g)))
    >>> svg.startswith("<svg") and 'data-end="R"' in svg
    True
    """
    W, H = scene.width, scene.height
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{_f(W)}" height="{_f(H)}" '
        f'viewBox="0 0 {_f(W)} {_f(H)}" font-family={quoteattr(_FAMILY)} class="bondgraph" '
        f'data-causal="{int(scene.causal)}">',
        f"<title>{escape('bond graph ' + scene.name)}</title>",
        f'<rect width="{_f(W)}" height="{_f(H)}" fill="white"/>',
    ]
    if scene.title:
        out.append(_text(16.0, 16.0, scene.title, size=TITLE_FONT, cls="title",
                         fill=COLORS["title"], anchor="start"))
    out.append('<g class="bonds">')
    for b in scene.bonds:
        out.extend(_bond(b, scene.numbers))
    out.append("</g>")
    out.append('<g class="elements">')
    for lb in scene.labels:
        out.extend(_label(lb))
    out.append("</g>")
    if scene.legend:
        out.append('<g class="legend">')
        x0, y0 = scene.legend_at
        for i, (entry, text) in enumerate(scene.legend):
            y = y0 + 10 + 18 * i
            if entry == "derivative":
                out.append(f'<rect x="{_f(x0)}" y="{_f(y - 6)}" width="22" height="12" rx="3" '
                           f'fill="{COLORS["derivative_fill"]}" stroke="{COLORS["derivative"]}"/>')
            else:
                out.append(f'<line x1="{_f(x0)}" y1="{_f(y)}" x2="{_f(x0 + 22)}" y2="{_f(y)}" '
                           f'stroke="{COLORS["loop"]}" stroke-width="2.5"/>')
            out.append(_text(x0 + 30, y, text, size=NOTE_FONT + 2, cls="legend-text",
                             fill=COLORS["ink"], anchor="start"))
        out.append("</g>")
    out.append("</svg>")
    return "\n".join(out) + "\n"
