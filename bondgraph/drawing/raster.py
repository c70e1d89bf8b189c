"""Draw a :class:`~bondgraph.drawing.scene.Scene` with matplotlib (for PNG).

The geometry is the scene's, in px, drawn onto a ``matplotlib.figure.Figure``
whose axes span the whole canvas with ``y`` pointing down, so the PNG matches
the SVG.  No pyplot state is used.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.drawing.scene import build_scene
>>> from bondgraph.drawing.source import diagram
>>> g = bg.BondGraph("r"); g.add(bg.Se("V"), bg.R("R")); _ = g.connect("V", "R")
>>> fig = scene_figure(build_scene(diagram(g)))
>>> len(fig.axes)
1
"""

from __future__ import annotations

from typing import BinaryIO, Union

from matplotlib import patheffects
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import FancyBboxPatch, PathPatch, Rectangle
from matplotlib.path import Path as MplPath

from .scene import (COLORS, FONT_FAMILY, NOTE_FONT, NUMBER_FONT, TITLE_FONT, Scene,
                    label_font)

__all__ = ["scene_figure", "write_png"]

_PX = 100.0  # figure dpi at scale 1: one scene px is one image px


def scene_figure(scene: Scene) -> Figure:
    """A matplotlib Figure showing the scene (1 px of the scene = 1/100 inch).

    Parameters
    ----------
    scene : Scene
        From :func:`~bondgraph.drawing.scene.build_scene`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.drawing.scene import build_scene
    >>> from bondgraph.drawing.source import diagram
    >>> g = bg.BondGraph("r"); g.add(bg.Se("V"), bg.R("R")); _ = g.connect("V", "R")
    >>> scene_figure(build_scene(diagram(g))).get_size_inches().round(2).tolist()[0] > 0
    True
    """
    W, H = scene.width, scene.height
    fig = Figure(figsize=(W / _PX, H / _PX), dpi=_PX)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(0, W)
    ax.set_ylim(H, 0)
    ax.set_axis_off()
    pt = 72.0 / _PX  # font size: px -> pt
    halo = [patheffects.withStroke(linewidth=3, foreground="white")]

    def text(x, y, s, *, size, color, ha="center", weight="normal", effects=None, z=5):
        ax.text(x, y, s, fontsize=size * pt, color=color, ha=ha, va="center_baseline",
                family=FONT_FAMILY, fontweight=weight, path_effects=effects, zorder=z)

    if scene.title:
        text(16.0, 16.0, scene.title, size=TITLE_FONT, color=COLORS["title"], ha="left")
    for b in scene.bonds:
        lw = (2.0 if b.loop else 1.3) * pt
        col = b.color
        (x0, y0), (x1, y1) = b.start, b.end
        if b.control is None:
            ax.add_line(Line2D([x0, x1], [y0, y1], color=col, lw=lw, solid_capstyle="round",
                               zorder=2))
        else:
            curve = MplPath([(x0, y0), b.control, (x1, y1)],
                            [MplPath.MOVETO, MplPath.CURVE3, MplPath.CURVE3])
            ax.add_patch(PathPatch(curve, facecolor="none", edgecolor=col, lw=lw,
                                   capstyle="round", zorder=2))
        ax.add_line(Line2D([x1, b.barb[0]], [y1, b.barb[1]], color=col, lw=lw,
                           solid_capstyle="round", zorder=2))
        if b.stroke is not None:
            (sx0, sy0), (sx1, sy1) = b.stroke
            ax.add_line(Line2D([sx0, sx1], [sy0, sy1], color=col, lw=2 * pt,
                               solid_capstyle="round", zorder=2))
        if scene.numbers:
            text(*b.number_at, str(b.number), size=NUMBER_FONT, color=COLORS["number"],
                 effects=halo, z=3)
        for port, (px, py) in b.ports:
            text(px, py, port, size=NOTE_FONT, color=COLORS["sub"], effects=halo, z=3)
    for lb in scene.labels:
        x, y, w, h = lb.box
        if lb.role == "sub":
            ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle="round,pad=0,rounding_size=6",
                                        facecolor=COLORS["sub_fill"], edgecolor=COLORS["sub"],
                                        lw=1.5 * pt, zorder=4))
        elif lb.derivative:
            ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle="round,pad=0,rounding_size=3",
                                        facecolor=COLORS["derivative_fill"],
                                        edgecolor=COLORS["derivative"], lw=1.2 * pt, zorder=4))
        else:
            ax.add_patch(Rectangle((x, y), w, h, facecolor="white", edgecolor="none",
                                   alpha=0.85, zorder=4))
        size, bold = label_font(lb.role)
        text(lb.x, lb.y, lb.text, size=size, color=lb.color, weight="bold" if bold else "normal")
        if lb.note:
            text(*lb.note_at, lb.note, size=NOTE_FONT, color=COLORS["number"], ha="left")
    x0, y0 = scene.legend_at
    for i, (entry, s) in enumerate(scene.legend):
        y = y0 + 10 + 18 * i
        if entry == "derivative":
            ax.add_patch(FancyBboxPatch((x0, y - 6), 22, 12, boxstyle="round,pad=0,rounding_size=3",
                                        facecolor=COLORS["derivative_fill"],
                                        edgecolor=COLORS["derivative"], lw=pt, zorder=4))
        else:
            ax.add_line(Line2D([x0, x0 + 22], [y, y], color=COLORS["loop"], lw=2.5 * pt))
        text(x0 + 30, y, s, size=NOTE_FONT + 2, color=COLORS["ink"], ha="left")
    return fig


def write_png(scene: Scene, target: Union[str, BinaryIO], *, dpi: float = 150.0) -> None:
    """Render the scene to PNG (``dpi=100`` gives one image pixel per scene px).

    Parameters
    ----------
    scene : Scene
        From :func:`~bondgraph.drawing.scene.build_scene`.
    target : str or binary file object
        Where to write the PNG.
    dpi : float
        Resolution of the image.

    Examples
    --------
    >>> import io
    >>> import bondgraph as bg
    >>> from bondgraph.drawing.scene import build_scene
    >>> from bondgraph.drawing.source import diagram
    >>> g = bg.BondGraph("r"); g.add(bg.Se("V"), bg.R("R")); _ = g.connect("V", "R")
    >>> buf = io.BytesIO(); write_png(build_scene(diagram(g)), buf)
    >>> buf.getvalue()[:8] == b"\\x89PNG\\r\\n\\x1a\\n"
    True
    """
    fig = scene_figure(scene)
    fig.savefig(target, format="png", dpi=dpi, facecolor="white")
