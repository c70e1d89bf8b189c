"""The catalogue: checks, pictures and the documentation page of every element and component.

:func:`check_component` is the sub-model check every library component
passes (its declared ports are its ports, each port's domain is declared, it
has a law, a reference and a drawing label, and it draws);
:func:`component_svg` draws a component's inside with its ports as labelled
terminals; :func:`element_classes` lists every public element class (the
generic elements, the switches, the chemical and thermal elements, the
structural ``SS``); :func:`write_catalogue` writes ``docs/guide/library.md``
(the elements, the library's components and the switched graphs of
:mod:`bondgraph.hybrid.library`) and one SVG per component
(``docs/img/library/``), generated from the classes (run
``python -m bondgraph.library.catalogue docs``).

Examples
--------
>>> from bondgraph.library.mechanical import Gear
>>> check_component(Gear)
'mechanical.Gear: ports a, b (rotation, rotation)'
>>> "Port:a" in component_svg(Gear("gear"))
True
>>> switches = [cls.__name__ for cls in element_classes()["bondgraph.hybrid"]]
>>> {"Switch", "Diode", "ControlledSwitch", "SwitchedZero", "SwitchedOne"} <= set(switches)
True
"""

from __future__ import annotations

import importlib
import inspect
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, Optional, Union

from ..errors import ModelStructureError
from ..graph import BondGraph
from ..elements.protocol import Element
from ._component import CATALOGUE, Component

__all__ = ["DOMAINS", "ELEMENT_MODULES", "check_component", "component_svg", "catalogue_markdown",
           "write_catalogue", "load_all", "element_classes"]

#: the library's modules, in catalogue order
MODULES = ("electrical", "mechanical", "hydraulic", "thermal", "electromechanical")
#: the public modules whose ``__all__`` holds element classes, in catalogue order
ELEMENT_MODULES = ("bondgraph.elements", "bondgraph.hybrid", "bondgraph.library.chemical",
                   "bondgraph.library.thermal", "bondgraph.structure")
#: the domains a component port may have
DOMAINS = ("electrical", "translation", "rotation", "hydraulic", "thermal", "thermal (entropy)",
           "chemical")


def load_all() -> dict[str, type[Component]]:
    """Import every library module and return the catalogue (qualified name -> class)."""
    for mod in MODULES:
        importlib.import_module(f"{__package__}.{mod}")
    return dict(CATALOGUE)


def element_classes() -> dict[str, list[type[Element]]]:
    """Every concrete element class exported by the modules of :data:`ELEMENT_MODULES`.

    A class is concrete when it declares its own ``kind`` (its drawing label);
    base classes (``Element``, ``OnePort``, ``SwitchElement``, ...) are left out.

    Returns
    -------
    dict of str to list of type
        ``{module: [element classes in the order of its __all__]}``.

    Examples
    --------
    >>> [cls.__name__ for cls in element_classes()["bondgraph.elements"]][:5]
    ['Se', 'Sf', 'I', 'C', 'R']
    """
    found: dict[str, list[type[Element]]] = {}
    for modname in ELEMENT_MODULES:
        module = importlib.import_module(modname)
        found[modname] = [obj for obj in (getattr(module, n) for n in module.__all__)
                          if inspect.isclass(obj) and issubclass(obj, Element)
                          and obj is not Element and "kind" in vars(obj)]
    return found


def _signature(cls: type) -> str:
    """``Name(name, parameter=None, *, value=None)``: the constructor without annotations."""
    parts, star = [], False
    for p in inspect.signature(cls).parameters.values():
        if p.kind is inspect.Parameter.KEYWORD_ONLY and not star:
            parts.append("*")
            star = True
        parts.append(p.name if p.default is inspect.Parameter.empty else f"{p.name}={p.default!r}")
    return f"{cls.__name__}({', '.join(parts)})"


def _first_paragraph(obj: object) -> str:
    return (inspect.getdoc(obj) or "").split("\n\n")[0].replace("\n", " ").strip()


def _elements_markdown() -> list[str]:
    """The catalogue's element section: one table per module of :data:`ELEMENT_MODULES`."""
    lines = ["## Elements", "",
             "The element classes, from the generic elements to the switches and the "
             "domain elements: each is one node of a graph, added with `g.add` and "
             "connected by its name.  *Drawn as* is its label's prefix (`Se:F`) and its "
             "role in a drawing.", ""]
    for modname, classes in element_classes().items():
        module = importlib.import_module(modname)
        lines += [f"### `{modname}`", "", _first_paragraph(module).split(". ")[0].rstrip(".")
                  + ".", "", "| element | drawn as | constructor | what |", "|---|---|---|---|"]
        for cls in classes:
            what = _first_paragraph(cls).replace("|", "\\|")
            lines.append(f"| `{cls.__name__}` | `{cls.kind}` ({cls.drawing_role}) | "
                         f"`{_signature(cls)}` | {what} |")
        lines.append("")
    return lines


def _switched_graphs_markdown() -> list[str]:
    """The catalogue's section on the switched graphs of :mod:`bondgraph.hybrid.library`."""
    hybrid_library = importlib.import_module("bondgraph.hybrid.library")
    lines = ["## Switched graphs", "", "`bondgraph.hybrid.library`", "",
             "Functions returning a fresh switched bond graph with its switches in their "
             "initial state, for `bondgraph.hybrid.SwitchedModel` (see {doc}`switched`).", "", "| function | what |", "|---|---|"]
    for name in hybrid_library.__all__:
        what = _first_paragraph(getattr(hybrid_library, name)).replace("|", "\\|")
        lines.append(f"| `{name}()` | {what} |")
    return lines + [""]


@dataclass(frozen=True, eq=False)
class _Terminal(Element):
    """A component's port drawn as a terminal (drawing only)."""

    kind: ClassVar[str] = "Port"
    drawing_role: ClassVar[str] = "source"


def _display(comp: BondGraph) -> BondGraph:
    """A copy of ``comp`` whose ports are terminals, so it can be drawn on its own."""
    g = BondGraph(comp.name)
    g.add(*(_Terminal(el.name) if el.name in comp.ports else el for el in comp.elements))
    for b in comp.bonds:
        g.connect(b.tail, b.head)
    return g


def component_svg(comp: BondGraph) -> str:
    """The SVG drawing of a component's inside (no causality), ports as ``Port:<name>``."""
    from ..drawing import draw

    return draw(_display(comp), causality=False)


def _qualified(cls: type[Component]) -> str:
    return f"{cls.__module__.rsplit('.', 1)[-1]}.{cls.__name__}"


def check_component(cls: type[Component], comp: Optional[Component] = None) -> str:
    """Check one component class (built with its defaults unless ``comp`` is given).

    Raises
    ------
    ModelStructureError
        Naming the component and what is missing or inconsistent.
    """
    name = _qualified(cls)
    comp = cls("c") if comp is None else comp
    problems = []
    if comp.ports != tuple(comp.port_names):
        problems.append(f"ports {comp.ports} differ from the declared {comp.port_names}")
    for port in comp.ports:
        dom = comp.port_domains.get(port)
        if dom not in DOMAINS:
            problems.append(f"port {port!r} has domain {dom!r}; expected one of {DOMAINS}")
    for attr in ("law", "reference", "symbol", "domain"):
        if not getattr(cls, attr):
            problems.append(f"no {attr}")
    if not (cls.__doc__ or "").strip() or "Examples" not in (cls.__doc__ or ""):
        problems.append("no docstring with Examples")
    if problems:
        raise ModelStructureError(f"component {name}: " + "; ".join(problems))
    if "<svg" not in component_svg(comp):
        raise ModelStructureError(f"component {name}: its drawing is empty")
    doms = ", ".join(comp.port_domains[p] for p in comp.ports)
    return f"{name}: ports {', '.join(comp.ports)} ({doms})"


def catalogue_markdown(pictures: str = "../img/library") -> str:
    """The catalogue page (Markdown, MyST), one section per module and component."""
    load_all()
    lines = ["# Catalogue: elements and components", "",
             "Generated from the classes of `bondgraph.elements`, `bondgraph.hybrid` and "
             "`bondgraph.library` by `python -m bondgraph.library.catalogue docs`; do not "
             "edit by hand.", ""]
    lines += _elements_markdown()
    lines += ["## Components", "",
             "Each component is a sub-model: add it to a graph and connect its ports as "
             "`'name.port'`. Parameters not given default to the positive symbol "
             "`<name>_<parameter>`. The chemical domain (`bondgraph.library.chemical`) is "
             "elements (above) and a reaction-network builder rather than components; see "
             "its module documentation.", "",
             "```pycon", ">>> from bondgraph.library.mechanical import Gear",
             ">>> Gear(\"gb\", ratio=14)[\"n\"].modulus      # an N:1 reduction is TF(1/N)",
             "1/14", "```", ""]
    by_module: dict[str, list[type[Component]]] = {}
    for key, cls in CATALOGUE.items():
        by_module.setdefault(key.split(".")[0], []).append(cls)
    for mod in MODULES:
        module = sys.modules[f"{__package__}.{mod}"]
        lines += [f"### {mod.capitalize()}", "", f"`bondgraph.library.{mod}`", ""]
        first = (module.__doc__ or "").strip().split("\n\n")[0]
        lines += [first, ""]
        for cls in by_module.get(mod, []):
            comp = cls("c")
            ports = ", ".join(f"`{p}` ({comp.port_domains[p]})" for p in comp.ports)
            summary = (cls.__doc__ or "").strip().split("\n")[0]
            lines += [f"#### {cls.__name__}", "", summary, "",
                      f"- **Law**: `{cls.law}`", f"- **Ports**: {ports}",
                      f"- **Drawing label**: `{cls.symbol}`", f"- **Source**: {cls.reference}", "",
                      f"![{cls.__name__}]({pictures}/{mod}.{cls.__name__}.svg)", ""]
    lines += _switched_graphs_markdown()
    return "\n".join(lines).rstrip("\n") + "\n"


def write_catalogue(directory: Union[str, os.PathLike]) -> list[Path]:
    """Write ``guide/library.md`` and ``img/library/<module>.<Component>.svg`` under the
    documentation ``directory``.

    Every file is written to a temporary name and renamed, so a failure
    leaves no half-written page.

    Raises
    ------
    ModelStructureError
        ``directory`` (or a folder under it) is an existing file.
    """
    if not isinstance(directory, (str, os.PathLike)) or isinstance(directory, bytes):
        raise ModelStructureError(f"write_catalogue: directory must be a path (str or "
                                  f"os.PathLike); got {type(directory).__name__}")
    out = Path(directory)
    for part in (out, out / "img", out / "img" / "library", out / "guide"):
        if part.exists() and not part.is_dir():
            raise ModelStructureError(f"write_catalogue: {str(part)!r} is a file, not a "
                                      "directory; give the documentation directory "
                                      "(the catalogue goes to guide/ and img/library/ under it)")
    pics = out / "img" / "library"
    pics.mkdir(parents=True, exist_ok=True)
    written = []
    for key, cls in load_all().items():
        written.append(_atomic(pics / f"{key}.svg", component_svg(cls("c"))))
    (out / "guide").mkdir(parents=True, exist_ok=True)
    written.append(_atomic(out / "guide" / "library.md", catalogue_markdown()))
    return written


def _atomic(path: Path, text: str) -> Path:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)
    return path


if __name__ == "__main__":      # pragma: no cover - the docs build step
    for p in write_catalogue(sys.argv[1] if len(sys.argv) > 1 else "docs"):
        print(p)
