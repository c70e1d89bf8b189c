"""``draw()``: a bond graph as SVG text, or an SVG / PNG / TikZ (``.tex``) file.

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("rl")
>>> V, j = bg.Se("V"), bg.One("j")
>>> g.add(V, j, bg.R("R"), bg.I("L"))
>>> for t, h in [(V, j), (j, "R"), (j, "L")]: _ = g.connect(t, h)
>>> svg = draw(g)
>>> "Se:V" in svg and 'class="stroke"' in svg
True
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Optional, Union

from ..errors import BondGraphError
from .scene import build_scene
from .source import Drawable, DrawingError, diagram
from .svg import scene_to_svg
from .tikz import scene_to_tikz

__all__ = ["draw", "repr_svg"]

_FORMATS = ("svg", "png", "tex")


#: the most elements :func:`draw` lays out (a budget: a 100-cell chain, about 400
#: elements, takes half a minute; 1,500 cells took minutes and fit no page)
MAX_DRAW_ELEMENTS = 600


def draw(obj: Drawable, path: Union[str, os.PathLike, None] = None, *,
         fmt: Optional[str] = None, causality: bool = True, expand: bool = True,
         wrap: int = 14, dpi: float = 150.0, standalone: bool = True,
         max_width: Optional[float] = 17.0, font_pt: float = 8.0, title: bool = True,
         prefixes: bool = True, numbers: bool = True, latex: bool = False,
         mode: Any = None) -> str:
    """Draw a bond graph (augmented with causal strokes) as SVG or TikZ, optionally to a file.

    Parameters
    ----------
    obj : BondGraph, AugmentedBondGraph, FlatGraph, Model or SwitchedModel
        What to draw.  A :class:`~bondgraph.BondGraph` gets causality assigned
        when ``causality`` is true; a :class:`~bondgraph.Model` is drawn from
        its ``augmented`` graph; a :class:`bondgraph.hybrid.SwitchedModel` in
        one mode (``mode``), each switch marked ``on`` or ``off``.
    path : str or path-like, optional
        File to write; the format comes from ``fmt`` or else the suffix
        (``.svg``, ``.png`` or ``.tex``).  The file is replaced atomically.
    fmt : {'svg', 'png', 'tex'}, optional
        Output format of ``path`` (without ``path``: ``'tex'`` returns the
        TikZ source).  ``tex`` is a TikZ picture in the same layout (see
        :mod:`bondgraph.drawing.tikz`).
    causality : bool
        Show causal strokes, derivative-causality storage (red) and
        algebraic-loop bonds (orange).
    expand : bool
        Draw sub-models expanded (hierarchical names); False draws each
        sub-model of a :class:`~bondgraph.BondGraph` as one box with its
        ports as bond ends (bond numbers are then the builder's).
    wrap : int
        Longest run of the main chain on one row before it snakes back
        (lowered further when needed to fit ``max_width``).
    dpi : float
        PNG resolution (100 = one pixel per SVG unit).
    standalone : bool
        TikZ only: True writes a document that ``pdflatex`` compiles on its
        own (``article`` + ``tikz``, the page cropped to the picture); False
        writes only the ``tikzpicture``, for ``\\input`` into a document that
        loads ``tikz``.
    max_width : float or None, default 17.0
        Width in cm the figure must fit with its labels printed at
        ``font_pt`` points (17 cm: a two-column page): the main chain wraps
        into shorter rows, else a layered layout is used, whichever fits
        with no bond through a label and the fewest crossings (see
        :func:`~bondgraph.drawing.scene.build_scene`); None keeps ``wrap``.
    font_pt : float, default 8.0
        Label size in points the width is reckoned at; the TikZ picture is
        written at that size (one px = ``font_pt / 14`` pt).
    title : bool
        Print the model's name above the graph.
    prefixes : bool
        Keep sub-model prefixes in labels (``I:link.m_1``); False prints
        ``I:m_1``.
    numbers : bool
        Print the bond numbers.
    latex : bool
        TikZ only: element names as LaTeX math (``I:$m_{1}$``, see
        :func:`~bondgraph.drawing.tikz.latex_label`).
    mode : Mode or mapping with keys ``'on'`` and ``'off'``, optional
        Switched models: the mode whose causal strokes are drawn (default:
        the initial mode, the states the switches are built in).

    Returns
    -------
    str
        The TikZ source for the ``tex`` format, else the SVG text (also when
        a PNG is written).

    Raises
    ------
    DrawingError
        For an unknown format or suffix, ``expand=False`` on a flattened graph,
        more than :data:`MAX_DRAW_ELEMENTS` elements, or (TikZ) a name LaTeX
        cannot typeset.
    CausalityConflictError
        When causality cannot be assigned (draw with ``causality=False``).

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("rc")
    >>> V, n = bg.Se("V"), bg.Zero("n")
    >>> g.add(V, n, bg.R("R"), bg.C("C"))
    >>> for t, h in [(V, n), (n, "R"), (n, "C")]: _ = g.connect(t, h)
    >>> svg = draw(g)
    >>> svg.count('class="stroke"'), "C:C" in svg
    (3, True)
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     _ = draw(g, os.path.join(d, "rc.png"))
    ...     os.path.getsize(os.path.join(d, "rc.png")) > 0
    True
    >>> tikz = draw(g, fmt="tex", standalone=False)
    >>> tikz.count("\\\\begin{tikzpicture}"), "documentclass" in tikz
    (1, False)
    >>> from bondgraph.hybrid import SwitchedModel, library
    >>> svg = draw(SwitchedModel(library.buck()))           # the initial mode: S on, D off
    >>> "buck (D off, S on)" in svg and "CSw:S" in svg
    True
    """
    form = None
    if path is not None:
        form = _format(path, fmt)
    elif fmt is not None and fmt.lower() not in _FORMATS:
        raise DrawingError(f"unknown drawing format {fmt!r}; expected one of {', '.join(_FORMATS)}")
    diag = diagram(obj, causality=causality, expand=expand, mode=mode)
    if len(diag.nodes) > MAX_DRAW_ELEMENTS:
        raise DrawingError(
            f"model {diag.name!r} has {len(diag.nodes):,} elements to draw, more than "
            f"{MAX_DRAW_ELEMENTS:,} (bondgraph.drawing.api.MAX_DRAW_ELEMENTS): its layout would "
            "take minutes and no page could show it legibly; draw a part of it (a sub-model, "
            "or expand=False to show sub-models as boxes), or raise the limit")
    if not prefixes:
        from .labels import without_prefixes
        diag = without_prefixes(diag)
    scene = build_scene(diag, wrap=wrap, title=title, numbers=numbers, max_width=max_width,
                        font_pt=font_pt, latex=latex)
    if (form or (fmt or "").lower().lstrip(".")) == "tex":
        tikz = scene_to_tikz(scene, standalone=standalone, font_pt=font_pt)
        if path is not None:
            _atomic_write(path, lambda f: f.write(tikz.encode("ascii")))
        return tikz
    svg = scene_to_svg(scene)
    if path is not None:
        if form == "svg":
            _atomic_write(path, lambda f: f.write(svg.encode("utf-8")))
        else:
            from .raster import write_png   # matplotlib only when a PNG is asked for
            _atomic_write(path, lambda f: write_png(scene, f, dpi=dpi))
    return svg


def repr_svg(obj: Drawable) -> Optional[str]:
    """SVG for notebooks (``_repr_svg_``): never raises for a bond graph.

    Draws with causality when it can be assigned, else without; a graph with
    open ports (a sub-model on its own) is drawn unexpanded.  Returns None
    when nothing can be drawn, which tells IPython to fall back to text.

    Parameters
    ----------
    obj : BondGraph, AugmentedBondGraph, FlatGraph or Model
        What to draw.

    Returns
    -------
    str or None

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("sub"); g.add(bg.R("R"), bg.Port("p")); _ = g.connect("p", "R")
    >>> "Port:p" in repr_svg(g)
    True
    """
    attempts = ((True, True), (False, True), (False, False))  # (causality, expand)
    for causality, expand in attempts:
        try:
            return draw(obj, causality=causality, expand=expand)
        except BondGraphError:
            continue
    return None


def _format(path, fmt: Optional[str]) -> str:
    if fmt is not None:
        form = fmt.lower().lstrip(".")
        if form not in _FORMATS:
            raise DrawingError(f"unknown drawing format {fmt!r}; expected one of "
                               f"{', '.join(_FORMATS)}")
        return form
    suffix = Path(os.fspath(path)).suffix.lower().lstrip(".")
    if suffix not in _FORMATS:
        raise DrawingError(
            f"cannot tell the drawing format of {os.fspath(path)!r} from its suffix "
            f"{('.' + suffix) if suffix else '(none)'}; use .svg, .png or .tex, or pass "
            "fmt='svg', fmt='png' or fmt='tex'"
        )
    return suffix


def _atomic_write(path, write) -> None:
    """All or nothing, errors naming ``path`` (never the temporary file)."""
    from .._support.files import atomic_write

    atomic_write(path, write)
