"""Write a :class:`~bondgraph.drawing.scene.Scene` as a TikZ picture (LaTeX).

The picture uses the scene's own coordinates: the ``tikzpicture`` is opened
with ``x=0.75pt, y=-0.75pt`` (one scene px is 0.75 pt, as for SVG at 96
dpi, and ``y`` points down), so every shape sits where the SVG and PNG put
it.  Text takes the document's fonts (``\\small`` labels, ``\\scriptsize``
bond numbers), so a figure ``\\input`` into a paper matches its text.

:func:`scene_to_tikz` gives either a whole document that ``pdflatex`` or
``lualatex`` compiles on its own (the ``article`` class and
``tikz``, nothing else: Debian's ``texlive-latex-base`` and
``texlive-pictures``; the page is cropped to the picture, as the
``standalone`` class would, which Debian ships only in
``texlive-latex-extra``), or, with ``standalone=False``, the bare
``tikzpicture`` for ``\\input``.

Every text that reaches LaTeX goes through :func:`tex_escape`: the ten
special characters of LaTeX are escaped (and ``<``, ``>``, ``|``, ``"``,
which the default font encoding prints as other glyphs), characters LaTeX cannot be
relied on to typeset (control characters, anything outside printable ASCII)
are refused with a :class:`~bondgraph.drawing.DrawingError` naming
the text.  Each bond's shapes carry a comment ``% bond N: tail -> head``,
and its causal stroke the comment ``% stroke N at END`` (checked by tests).

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.drawing.scene import build_scene
>>> from bondgraph.drawing.source import diagram
>>> g = bg.BondGraph("r"); g.add(bg.Se("V_in"), bg.R("R")); _ = g.connect("V_in", "R")
>>> tex = scene_to_tikz(build_scene(diagram(g)), standalone=False)
>>> tex.splitlines()[0]
'% bond graph r, drawn by bondgraph'
>>> "Se:V\\\\_in" in tex and "\\\\end{tikzpicture}" in tex
True
"""

from __future__ import annotations

import math
import re
from typing import Optional

from .scene import COLORS, FONT, NOTE_FONT, NUMBER_FONT, TITLE_FONT, BondShape, Label, Scene, text_width
from .source import DrawingError

__all__ = ["scene_to_tikz", "tex_escape"]

PT_PER_PX = 0.75   # one scene px in TeX points (CSS px at 96 dpi)

#: LaTeX's special characters and what typesets each in any font encoding
_SPECIAL = {
    "\\": r"\textbackslash{}", "{": r"\{", "}": r"\}", "$": r"\$", "&": r"\&", "#": r"\#",
    "%": r"\%", "_": r"\_", "^": r"\^{}", "~": r"\~{}", "<": r"\textless{}",
    ">": r"\textgreater{}", "|": r"\textbar{}", '"': "''",
}

_COLOR_NAMES = {  # scene colour -> name defined inside the picture
    COLORS["ink"]: "bondgraphink", COLORS["number"]: "bondgraphnumber",
    COLORS["derivative"]: "bondgraphderivative", COLORS["derivative_fill"]: "bondgraphderivativefill",
    COLORS["loop"]: "bondgraphloop", COLORS["sub"]: "bondgraphsub",
    COLORS["sub_fill"]: "bondgraphsubfill", COLORS["title"]: "bondgraphtitle",
}


def tex_escape(text: str, what: str = "text") -> str:
    """``text`` as LaTeX source that typesets it literally.

    Parameters
    ----------
    text : str
        Any text (a name, a label).
    what : str
        What the text is, for the error message (``"label of element 'R1'"``).

    Returns
    -------
    str

    Raises
    ------
    DrawingError
        For a character LaTeX cannot be relied on to typeset: a control
        character or one outside printable ASCII (the message names it and
        ``what``).

    Examples
    --------
    >>> print(tex_escape("a_b%c{d}\\\\e^f~g&h#i$"))
    a\\_b\\%c\\{d\\}\\textbackslash{}e\\^{}f\\~{}g\\&h\\#i\\$
    >>> tex_escape("Ω", "name of element 'x'")
    Traceback (most recent call last):
    ...
    bondgraph.drawing.DrawingError: TikZ output: the name of element 'x' 'Ω' has the character 'Ω' (U+03A9), which LaTeX cannot be relied on to typeset; only printable ASCII is written to LaTeX (rename it, or draw SVG/PNG)
    """
    out = []
    for ch in text:
        if not (" " <= ch <= "~"):
            raise DrawingError(
                f"TikZ output: the {what} {text!r} has the character {ch!r} (U+{ord(ch):04X}), "
                "which LaTeX cannot be relied on to typeset; only printable ASCII is written to "
                "LaTeX (rename it, or draw SVG/PNG)")
        out.append(_SPECIAL.get(ch, ch))
    return "".join(out)


def _f(v: float) -> str:
    """A coordinate: two decimals, no trailing zeros, never ``-0``."""
    s = f"{v:.2f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _p(pt) -> str:
    return f"({_f(pt[0])},{_f(pt[1])})"


def _color(c: str) -> str:
    return _COLOR_NAMES[c]


def _bond(b: BondShape, numbers: bool = True) -> list[str]:
    tail, head = tex_escape(b.tail, "bond end"), tex_escape(b.head, "bond end")
    style = "bondgraph loop" if b.loop else "bondgraph bond"
    out = [f"% bond {b.number}: {tail} -> {head}"]
    if b.control is None:
        line = f"{_p(b.start)} -- {_p(b.end)}"
    else:   # the scene's quadratic Bezier curve as TikZ's cubic one
        (x0, y0), (cx, cy), (x1, y1) = b.start, b.control, b.end
        c1 = (x0 + 2 / 3 * (cx - x0), y0 + 2 / 3 * (cy - y0))
        c2 = (x1 + 2 / 3 * (cx - x1), y1 + 2 / 3 * (cy - y1))
        line = f"{_p(b.start)} .. controls {_p(c1)} and {_p(c2)} .. {_p(b.end)}"
    out.append(f"\\draw[{style}] {line} -- {_p(b.barb)};")
    if b.stroke is not None:
        end = tex_escape(b.stroke_end or "", "bond end")
        out.append(f"\\draw[{style}, bondgraph stroke] {_p(b.stroke[0])} -- {_p(b.stroke[1])};"
                   f" % stroke {b.number} at {end}")
    if numbers:
        out.append(f"\\node[bondgraph number] at {_p(b.number_at)} {{{b.number}}};")
    for port, at in b.ports:
        out.append(f"\\node[bondgraph port] at {_p(at)} {{{tex_escape(port, 'port name')}}};")
    return out


_SAFE_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_.]*\Z")


def latex_label(text: str) -> Optional[str]:
    r"""``'I:m_1'`` as ``'I:$m_{1}$'`` (the name through :func:`bondgraph._labels.latex_name`).

    Only a ``KIND:name`` label whose name is letters, digits, ``_`` and
    ``.`` is turned into math; anything else gives None (the caller then
    writes the escaped text), so no character of a name reaches LaTeX
    unescaped.

    Examples
    --------
    >>> latex_label("I:m_1"), latex_label("R:link.b_2"), latex_label("1"), latex_label("R:a$b")
    ('I:$m_{1}$', 'R:$\\mathrm{link}.b_{2}$', None, None)
    """
    from .._support.labels import latex_name

    kind, sep, name = text.partition(":")
    if not sep or not _SAFE_NAME.match(name) or not re.fullmatch(r"[A-Za-z]+", kind):
        return None
    return f"{kind}:${latex_name(name)}$"


def _label(lb: Label, latex: bool = False, unit: float = PT_PER_PX) -> list[str]:
    what = f"element {lb.name!r}"
    text = (latex and latex_label(lb.text)) or tex_escape(lb.text, f"label of {what}")
    x, y, w, h = lb.box
    out = [f"% element {tex_escape(lb.name, 'element name')}"]
    font = "bondgraph boldfont" if lb.role in ("junction", "sub") else "bondgraph labelfont"
    color = _color(lb.color)
    if lb.role == "sub" or lb.derivative:
        fill, draw, r = (("bondgraphsubfill", "bondgraphsub", 6) if lb.role == "sub" else
                         ("bondgraphderivativefill", "bondgraphderivative", 3))
        width = 1.5 if lb.role == "sub" else 1.2
        out.append(f"\\filldraw[fill={fill}, draw={draw}, line width={_f(width * PT_PER_PX)}pt, "
                   f"rounded corners={_f(r * PT_PER_PX)}pt] {_p((x, y))} rectangle "
                   f"{_p((x + w, y + h))};")
        out.append(f"\\node[bondgraph text, {font}, text={color}] at {_p((lb.x, lb.y))} "
                   f"{{{text}}};")
    else:
        out.append(f"\\node[bondgraph label, {font}, text={color}] (bondgraphlabel) at "
                   f"{_p((lb.x, lb.y))} {{{text}}};")
    if lb.note:
        note = _fit(tex_escape(lb.note, f"name of {what}"), text_width(lb.note, NOTE_FONT) * unit)
        if lb.role == "sub" or lb.derivative:
            out.append(f"\\node[bondgraph note] at {_p(lb.note_at)} {{{note}}};")
        else:
            # right after the main text as the document's font sets it (as in the SVG: 1 px
            # after it, FONT * 0.32 px lower), not where DejaVu Sans would end it
            dx = _f(unit - 1.0)
            dy = _f((lb.note_at[1] - lb.y) * unit)
            out.append(f"\\node[bondgraph note] at "
                       f"([xshift={dx}pt, yshift=-{dy}pt]bondgraphlabel.east) "
                       f"{{{note}}};")
    return out


def _fit(tex: str, width_pt: float) -> str:
    """``tex`` shrunk to ``width_pt`` where the document's font sets it wider than the SVG's
    (Computer Modern's small optical sizes are wider than DejaVu Sans at 5 pt): a junction's
    name then stays clear of the bonds beside it."""
    w = _f(width_pt)
    return f"\\sbox0{{{tex}}}\\ifdim\\wd0>{w}pt\\resizebox{{{w}pt}}{{!}}{{\\usebox0}}\\else\\usebox0\\fi"


def _fonts(font_pt: Optional[float]) -> dict[str, str]:
    """The picture's fonts: the document's (``\\small`` labels...) or sizes scaled to ``font_pt``."""
    if font_pt is None:
        return {"label": r"\small", "number": r"\scriptsize", "note": r"\tiny", "title": r"\footnotesize"}

    def size(px: float) -> str:
        pt = font_pt * px / FONT
        return f"\\fontsize{{{_f(pt)}pt}}{{{_f(1.2 * pt)}pt}}\\selectfont"
    return {"label": size(FONT), "number": size(NUMBER_FONT), "note": size(NOTE_FONT),
            "title": size(TITLE_FONT)}


def _picture(scene: Scene, font_pt: Optional[float] = None) -> list[str]:
    name = tex_escape(scene.name, "graph name")
    unit = PT_PER_PX if font_pt is None else font_pt / FONT
    fonts = _fonts(font_pt)
    lw = 1.3 * unit
    out = [
        f"% bond graph {name}, drawn by bondgraph",
        f"% coordinates in px of the SVG drawing: x right, y down; 1 px = {_f(unit)} pt",
        f"\\begin{{tikzpicture}}[x={_f(unit)}pt, y=-{_f(unit)}pt, line cap=round, line join=round,",
        f"  bondgraph bond/.style={{draw=bondgraphink, line width={_f(lw)}pt}},",
        f"  bondgraph loop/.style={{draw=bondgraphloop, line width={_f(2 * unit)}pt}},",
        f"  bondgraph stroke/.style={{line width={_f(2 * unit)}pt}},",
        "  bondgraph text/.style={inner sep=0.5pt},",
        "  bondgraph label/.style={bondgraph text, fill=white, fill opacity=0.85, text opacity=1},",
        "  bondgraph number/.style={inner sep=0.6pt, fill=white, fill opacity=0.8, text opacity=1,",
        f"    text=bondgraphnumber, font={fonts['number']}}},",
        f"  bondgraph note/.style={{anchor=west, inner sep=0.5pt, text=bondgraphnumber, font={fonts['note']}}},",
        "  bondgraph port/.style={inner sep=0.5pt, fill=white, fill opacity=0.8, text opacity=1,",
        f"    text=bondgraphsub, font={fonts['note']}}},",
        f"  bondgraph labelfont/.style={{font={fonts['label']}}},",
        f"  bondgraph boldfont/.style={{font={fonts['label']}\\bfseries}}]",
    ]
    for color, cname in _COLOR_NAMES.items():
        out.append(f"\\definecolor{{{cname}}}{{HTML}}{{{color.lstrip('#').upper()}}}")
    # the canvas, so the picture has the SVG's size and margins
    out.append(f"\\path[use as bounding box] (0,0) rectangle {_p((scene.width, scene.height))};")
    if scene.title:
        out.append(f"\\node[anchor=west, inner sep=0pt, text=bondgraphtitle, font={fonts['title']}] "
                   f"at (16,16) {{{tex_escape(scene.title, 'graph name')}}};")
    for b in scene.bonds:
        out.extend(_bond(b, scene.numbers))
    for lb in scene.labels:
        out.extend(_label(lb, scene.latex, unit))
    if scene.legend:
        x0, y0 = scene.legend_at
        out.append("% legend")
        for i, (entry, text) in enumerate(scene.legend):
            y = y0 + 10 + 18 * i
            if entry == "derivative":
                out.append(f"\\filldraw[fill=bondgraphderivativefill, draw=bondgraphderivative, "
                           f"rounded corners={_f(3 * PT_PER_PX)}pt] {_p((x0, y - 6))} rectangle "
                           f"{_p((x0 + 22, y + 6))};")
            else:
                out.append(f"\\draw[bondgraphloop, line width={_f(2.5 * PT_PER_PX)}pt] "
                           f"{_p((x0, y))} -- {_p((x0 + 22, y))};")
            out.append(f"\\node[anchor=west, inner sep=0pt, font=\\scriptsize] at {_p((x0 + 30, y))} "
                       f"{{{tex_escape(text, 'legend')}}};")
    out.append("\\end{tikzpicture}")
    return out


_DOCUMENT_HEAD = r"""% A document that compiles on its own (pdflatex or lualatex): the
% article class and tikz only; the page is cropped to the picture.
\documentclass{article}
\usepackage{tikz}
\makeatletter
\newsavebox\bondgraph@figure
\newcommand\bondgraph@shipout{%
  \hoffset=-1in \voffset=-1in
  \shipout\hbox{%
    \pgfsys@global@papersize{\the\wd\bondgraph@figure}%
      {\the\dimexpr\ht\bondgraph@figure+\dp\bondgraph@figure\relax}%
    \box\bondgraph@figure}}
\begin{document}
\begin{lrbox}{\bondgraph@figure}%"""

_DOCUMENT_TAIL = r"""\end{lrbox}%
\bondgraph@shipout
\end{document}"""


def scene_to_tikz(scene: Scene, *, standalone: bool = True, font_pt: Optional[float] = None) -> str:
    """TikZ source of a scene.

    Parameters
    ----------
    scene : Scene
        From :func:`~bondgraph.drawing.scene.build_scene`.
    standalone : bool
        True: a whole LaTeX document (``article`` + ``tikz``) whose one page
        is the picture.  False: only the ``tikzpicture`` environment, for
        ``\\input`` into a document that loads ``tikz``.
    font_pt : float, optional
        Print the labels at this size (points) and scale the picture with
        them (one px is ``font_pt / 14`` pt): the size
        :func:`~bondgraph.drawing.geometry.printed_size` gives.  None: the
        document's ``\\small`` labels, one px = 0.75 pt.

    Returns
    -------
    str

    Raises
    ------
    DrawingError
        For a name or label LaTeX cannot typeset (see :func:`tex_escape`).

    Examples
    --------
    >>> import bondgraph as bg
    >>> from bondgraph.drawing.scene import build_scene
    >>> from bondgraph.drawing.source import diagram
    >>> g = bg.BondGraph("r"); g.add(bg.Se("V"), bg.R("R")); _ = g.connect("V", "R")
    >>> doc = scene_to_tikz(build_scene(diagram(g)))
    >>> doc.count("\\\\documentclass{article}"), doc.count("% stroke 1 at R")
    (1, 1)
    """
    if not (math.isfinite(scene.width) and math.isfinite(scene.height)):
        raise DrawingError(f"TikZ output: the drawing of {scene.name!r} has no finite size")
    body = _picture(scene, font_pt)
    if not standalone:
        return "\n".join(body) + "\n"
    return "\n".join([*_DOCUMENT_HEAD.split("\n"), *body, *_DOCUMENT_TAIL.split("\n")]) + "\n"
