"""The house: the pipeline's stages import only the stages before them, and nothing circles.

Every import of the package is read from the source (function-level and
``TYPE_CHECKING`` imports included).  A module of stage *k* may import
modules of stages ``<= k`` only; the modules after the last stage (the
consumers of a model: export, code generation, drawing, the command line,
...) may import any stage but must not form an import circle among
themselves.  No private name (and no private module) is imported across a
subpackage boundary: ``_support`` is the package's shared infrastructure and
the one exception.
"""

from __future__ import annotations

import ast
from pathlib import Path

import networkx as nx
import pytest

import bondgraph

PACKAGE = Path(bondgraph.__file__).resolve().parent

#: the pipeline in order; a stage is a top-level module or subpackage of bondgraph
STAGES = ["errors", "signals", "_support", "parameters", "elements", "graph", "flatten",
          "causality", "equations", "tf", "linear", "numeric", "hamiltonian", "model"]


def _modules() -> dict[str, Path]:
    out = {}
    for path in PACKAGE.rglob("*.py"):
        parts = list(path.relative_to(PACKAGE).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(["bondgraph", *parts])] = path
    return out


MODULES = _modules()


def _imports(name: str, path: Path) -> list[tuple[str, tuple[str, ...], int]]:
    """``(target module, imported names, line)`` of every package import in a module."""
    is_pkg = path.name == "__init__.py"
    package = name.split(".") if is_pkg else name.split(".")[:-1]
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else []
            target = ".".join(base + (node.module.split(".") if node.module else []))
            if not target.startswith("bondgraph"):
                continue
            names = tuple(a.name for a in node.names)
            subs = [f"{target}.{n}" for n in names if f"{target}.{n}" in MODULES]
            if subs and not node.module and node.level:
                found += [(s, (), node.lineno) for s in subs]
            else:
                found.append((target, names, node.lineno))
        elif isinstance(node, ast.Import):
            found += [(a.name, (), node.lineno) for a in node.names if a.name.startswith("bondgraph")]
    return found


def _stage(module: str) -> int:
    parts = module.split(".")
    top = parts[1] if len(parts) > 1 else ""
    return STAGES.index(top) if top in STAGES else len(STAGES)


def test_every_stage_exists():
    tops = {m.split(".")[1] for m in MODULES if m.count(".")}
    assert set(STAGES) <= tops


def test_no_import_from_an_earlier_stage_of_a_later_one():
    bad = []
    for name, path in MODULES.items():
        for target, _, line in _imports(name, path):
            if _stage(target) > _stage(name):
                bad.append(f"{name}:{line} imports {target}")
    assert not bad, "\n".join(bad)


def test_no_import_circle():
    graph = nx.DiGraph()
    for name, path in MODULES.items():
        graph.add_node(name)
        for target, _, _ in _imports(name, path):
            while target not in MODULES:          # `from pkg.mod import name`: the module
                target = target.rsplit(".", 1)[0]
            if target != name:
                graph.add_edge(name, target)
    circles = [sorted(c) for c in nx.strongly_connected_components(graph) if len(c) > 1]
    assert not circles, circles


def _private(part: str) -> bool:
    return part.startswith("_") and not part.startswith("__")


def test_no_private_name_crosses_a_subpackage_boundary():
    bad = []
    for name, path in MODULES.items():
        home = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        for target, names, line in _imports(name, path):
            parts = target.split(".")
            common = 0
            while common < min(len(home), len(parts)) and home[common] == parts[common]:
                common += 1
            outside = parts[common:]
            if common == len(home) and len(outside) <= 1:
                continue                          # the importer's own package
            if outside[:1] == ["_support"]:
                outside = outside[1:]
            if any(_private(p) for p in outside):
                bad.append(f"{name}:{line} imports the private module {target}")
            elif any(_private(n) for n in names):
                bad.append(f"{name}:{line} imports private {', '.join(names)} from {target}")
    assert not bad, "\n".join(bad)


def test_the_top_of_the_package_is_small():
    entries = [p.name for p in PACKAGE.iterdir() if p.name != "__pycache__"]
    assert len(entries) <= 30, sorted(entries)


@pytest.mark.parametrize("name", sorted(MODULES))
def test_no_module_over_700_lines(name):
    assert len(MODULES[name].read_text().splitlines()) <= 700
