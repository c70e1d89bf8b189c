"""Label options of a drawing: sub-model prefixes left out.

A flattened model names its elements by path (``link.m_1``); a paper's
figure usually shows only the local name (``I:m_1``), the sub-model being
clear from the picture.  :func:`without_prefixes` rewrites a
:class:`~bondgraph.drawing.source.Diagram`'s texts and notes; node names,
bonds and causality are untouched, so the layout and every check are the same.

Examples
--------
>>> from bondgraph.drawing.source import Diagram, Node
>>> d = Diagram("g", (Node("link.m_1", "I", "I:link.m_1"), Node("hub.w", "1", "1", "hub.w")), ())
>>> [(n.text, n.note) for n in without_prefixes(d).nodes]
[('I:m_1', ''), ('1', 'w')]
"""

from __future__ import annotations

from dataclasses import replace

from .source import Diagram

__all__ = ["without_prefixes", "local_name"]


def local_name(name: str) -> str:
    """The last part of a dotted path: ``'link.m_1'`` -> ``'m_1'``.

    Examples
    --------
    >>> local_name("a.b.c"), local_name("R")
    ('c', 'R')
    """
    return name.rpartition(".")[2] or name


def _local_text(text: str) -> str:
    kind, sep, name = text.partition(":")
    if not sep:
        return local_name(text) if "." in text else text
    return f"{kind}:{local_name(name)}"


def without_prefixes(diag: Diagram) -> Diagram:
    """``diag`` with every label's and note's sub-model path left out."""
    nodes = tuple(replace(n, text=_local_text(n.text) if n.role != "sub" else n.text,
                          note=local_name(n.note) if n.note else n.note) for n in diag.nodes)
    return replace(diag, nodes=nodes)
