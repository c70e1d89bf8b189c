"""Old module paths of the package, served with a :class:`DeprecationWarning`.

The package was reorganised into stage folders (issue 21).  For one release
``import bondgraph.protocol`` (and the other paths of :data:`MOVED`) still
works: it warns, naming the new path, and returns the module that now holds
those names.  The finder is installed by ``import bondgraph``; it only
answers for the names below, so it costs nothing on any other import.

Examples
--------
>>> import sys, warnings, bondgraph
>>> _ = sys.modules.pop("bondgraph.statespace", None)     # as in a fresh interpreter
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     from bondgraph.statespace import SymbolicStateSpace
>>> SymbolicStateSpace is bondgraph.SymbolicStateSpace
True
>>> str(caught[0].message)
'bondgraph.statespace is deprecated; import from bondgraph.linear.statespace'
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys

from .warn import warn_user

__all__ = ["MOVED", "install"]

#: old module path -> the module that now holds its public names
MOVED = {
    "bondgraph.protocol": "bondgraph.elements.protocol",
    "bondgraph.junctions": "bondgraph.elements",
    "bondgraph.fields": "bondgraph.elements.fields",
    "bondgraph.values": "bondgraph._support.sympify",
    "bondgraph.files": "bondgraph._support.files",
    "bondgraph.operating": "bondgraph.linear.operating",
    "bondgraph.statespace": "bondgraph.linear.statespace",
    "bondgraph.transfer": "bondgraph.tf",
    "bondgraph.loops": "bondgraph.equations.loops",
    "bondgraph.integrators": "bondgraph.equations.integrators",
    "bondgraph.control": "bondgraph.numeric.control",
    "bondgraph.plots": "bondgraph.drawing.plots",
}


class _Loader(importlib.abc.Loader):
    def __init__(self, new: str) -> None:
        self.new = new

    def create_module(self, spec):
        return importlib.import_module(self.new)

    def exec_module(self, module) -> None:
        pass


class _MovedFinder(importlib.abc.MetaPathFinder):
    """Answers ``find_spec`` for the old paths only: warns and hands out the new module."""

    def find_spec(self, fullname, path, target=None):
        new = MOVED.get(fullname)
        if new is None:
            return None
        warn_user(f"{fullname} is deprecated; import from {new}", DeprecationWarning)
        return importlib.machinery.ModuleSpec(fullname, _Loader(new))


def install() -> None:
    """Put the finder on :data:`sys.meta_path` once (after the standard finders)."""
    if not any(isinstance(f, _MovedFinder) for f in sys.meta_path):
        sys.meta_path.append(_MovedFinder())
