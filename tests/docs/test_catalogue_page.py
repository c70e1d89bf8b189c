"""The catalogue page lists every public element and component class of the package.

The classes are found here independently of the generator: every public module
of the package (no part of its dotted name starts with ``_``) is imported and
its ``__all__`` searched for element classes that declare their own drawing
label (``kind``) and for library components that declare their own law.  A new
element or component in any public module must appear on the page; the page
itself must be what the generator writes (``tests/library/test_catalogue.py``).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
from pathlib import Path

import bondgraph
from bondgraph.elements import Element
from bondgraph.library._component import Component

PAGE = Path(__file__).resolve().parents[2] / "docs" / "guide" / "library.md"
#: need an optional extra, or start the command line
SKIP = {"bondgraph.__main__", "bondgraph.study"}


def _public_classes() -> tuple[set[type], set[type]]:
    elements, components = set(), set()
    for info in pkgutil.walk_packages(bondgraph.__path__, "bondgraph."):
        name = info.name
        if any(part.startswith("_") for part in name.split(".")) or \
                any(name == s or name.startswith(s + ".") for s in SKIP):
            continue
        module = importlib.import_module(name)
        for obj in vars(module).values():
            if not inspect.isclass(obj) or obj.__name__.startswith("_"):
                continue
            public = obj.__name__ in getattr(module, "__all__", ()) or obj.__module__ == name
            if public and issubclass(obj, Element) and obj is not Element and "kind" in vars(obj):
                elements.add(obj)
            if public and issubclass(obj, Component) and "law" in vars(obj):
                components.add(obj)
    return elements, components


def test_every_public_element_and_component_is_on_the_catalogue_page():
    page = PAGE.read_text(encoding="utf-8")
    elements, components = _public_classes()
    names = {cls.__name__ for cls in elements}
    # the ones a newcomer missed (issue 35), and the generic kinds
    assert {"Diode", "Switch", "ControlledSwitch", "SwitchedZero", "SwitchedOne", "RS",
            "Se", "Sf", "I", "C", "R", "TF", "GY", "MTF", "MGY", "Zero", "One", "Port",
            "IField", "CField", "ICField", "RField", "Ce", "Re"} <= names
    missing = sorted(cls.__name__ for cls in elements
                     if f"| `{cls.__name__}` | `{cls.kind}` (" not in page)
    assert not missing, f"elements missing from the catalogue: {missing}"
    assert len(components) >= 40
    missing = sorted(cls.__name__ for cls in components if f"#### {cls.__name__}\n" not in page)
    assert not missing, f"components missing from the catalogue: {missing}"
    for graph in ("rectifier", "buck", "clutch", "end_stop", "bounce"):
        assert f"| `{graph}()` |" in page
