"""Drawings of bond graphs: augmented bond graphs with causal strokes, as SVG, PNG or TikZ.

:func:`draw` lays a graph out from its structure (the longest junction chain
left to right, one-port elements around their junctions), and draws each
bond with its half-arrow, its number and its causal stroke.  Storage elements
in derivative causality are shown in red, algebraic-loop bonds in orange.
PNG files are rendered with matplotlib from the same geometry, and ``.tex``
files are TikZ pictures (a document pdflatex compiles, or the bare
``tikzpicture`` for ``\\input``).  Importing this package registers the
Jupyter display (``_repr_svg_``) of bond graphs and models.

The pipeline, one module each: :mod:`.source` (what to draw) ->
:mod:`.layout` (grid cells: the comb) and :mod:`.layered` (grid cells: a layered,
Sugiyama-style layout, tried when the comb does not fit the width or crosses
bonds) -> :mod:`.scene` (geometry in px) ->
:mod:`.svg` / :mod:`.raster` / :mod:`.tikz` (output); :mod:`.api` holds :func:`draw`.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.drawing import draw
>>> g = bg.BondGraph("dc_motor")
>>> V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
>>> g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
>>> for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
...     _ = g.connect(tail, head)
>>> svg = draw(g)
>>> all(s in svg for s in ("Se:V", "I:La", "GY:K", "R:b"))
True
"""

from .api import draw, repr_svg
from .layout import boxes_overlap, grid_layout, overlapping_pairs
from .scene import BondShape, Label, Scene, build_scene
from .source import Diagram, DrawingError, Edge, Node, diagram
from .svg import scene_to_svg
from .tikz import scene_to_tikz


def _repr_svg_(self):
    """SVG of the bond graph for Jupyter (registered by :mod:`bondgraph.drawing`)."""
    return repr_svg(self)


def _register_displays() -> None:
    """Give the core classes their Jupyter display (``_repr_svg_``).

    The core modules (``graph``, ``causality``, ``model``) do not import the
    drawing package; importing it (``import bondgraph`` does) registers the
    display on :class:`~bondgraph.BondGraph`,
    :class:`~bondgraph.AugmentedBondGraph` and :class:`~bondgraph.Model`.
    """
    from ..causality import AugmentedBondGraph
    from ..graph import BondGraph
    from ..model import Model

    for cls in (BondGraph, AugmentedBondGraph, Model):
        setattr(cls, "_repr_svg_", _repr_svg_)


_register_displays()


def __getattr__(name: str):
    """``scene_figure`` and ``write_png`` load matplotlib: imported on first use only."""
    if name in ("scene_figure", "write_png"):
        from . import raster
        return getattr(raster, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

__all__ = [
    "draw", "repr_svg", "DrawingError",
    "diagram", "Diagram", "Node", "Edge",
    "grid_layout", "boxes_overlap", "overlapping_pairs",
    "build_scene", "Scene", "Label", "BondShape",
    "scene_to_svg", "scene_to_tikz", "scene_figure", "write_png",
]

DrawingError.__module__ = __name__   # tracebacks name it where users import it
