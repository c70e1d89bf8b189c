"""Sphinx configuration of the bondgraph documentation site.

Build (from the repository root)::

    pip install -e ".[docs]"
    sphinx-build -W --keep-going -b html docs docs/_build/html

The API reference is generated at every build from the installed package (see
:func:`write_api_pages`): each public module (no component of its dotted name
starts with ``_``) gets a page listing the names of its ``__all__`` (or, without
one, the classes and functions it defines).  Each object is documented in full
once, on the page of its home module (where it is defined, or the public package
re-exporting it from a private module); the other pages, ``bondgraph`` included,
link there.  The generated ``.rst`` files go to ``docs/api/generated/`` (ignored
by git, rewritten only when they change, stale ones removed), so a new public
module or a new name in an ``__all__`` appears with no edit here.  A module that
needs an optional extra goes in :data:`OPTIONAL_MODULES`.

Math is rendered by MathJax 3 copied into the site (``_static/mathjax``, from the
``sphinx-mathjax-offline`` package): the site loads nothing from the network.  The
landing page's figures (the FLEXCAM augmented bond graph and its Bode diagram) are
drawn at every build by :func:`write_landing_figures` into ``docs/_generated/``
(ignored by git), so they always show what the code draws.

The notebooks of ``notebooks/`` are rendered through the symlink
``docs/notebooks`` and executed at every build by myst-nb (a failing cell fails
the build).
"""

from __future__ import annotations

import importlib
import inspect
import types
import os
import pkgutil
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))
# matplotlib without a display; notebooks inherit it through the kernel's environment
os.environ.setdefault("MPLBACKEND", "Agg")

import bondgraph  # noqa: E402

project = "bondgraph"
author = "the bondgraph authors"
copyright = "the bondgraph authors, BSD-3-Clause"
release = version = bondgraph.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.doctest",
    "sphinx.ext.mathjax",
    # MathJax 3 shipped with the site (copied to _static/mathjax): formulas render offline
    "sphinx-mathjax-offline",
    "numpydoc",
    "myst_nb",
]

source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "**/.ipynb_checkpoints"]
templates_path: list[str] = []

html_theme = "furo"
html_title = f"bondgraph {release}"

# -- API reference ------------------------------------------------------------------------------
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
numpydoc_show_class_members = False   # autodoc documents the members themselves
numpydoc_class_members_toctree = False
numpydoc_attributes_as_param_list = True
numpydoc_xref_param_type = False

#: Modules that need an optional extra: documented when importable, else left out with a note.
OPTIONAL_MODULES = {"bondgraph.study": "study"}
#: Modules never imported: running ``bondgraph.__main__`` starts the command line.
SKIP_MODULES = {"bondgraph.__main__"}

# -- notebooks (myst-nb) -----------------------------------------------------------------------
# Committed notebooks have no outputs: execute every one at each build, in its own folder (the
# first cell finds models/ by walking up from the working directory), and fail the build on error.
nb_execution_mode = "force"
nb_execution_timeout = 300
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_execution_in_temp = False
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_heading_anchors = 3
# the notebooks link to ../models/*.py and ../README.md, files outside the site
suppress_warnings = ["myst.xref_missing"]


def public_modules() -> list[str]:
    """Every public module of the package, sorted; private parts and ``__main__`` left out."""
    names = ["bondgraph"]
    for info in pkgutil.walk_packages(bondgraph.__path__, "bondgraph."):
        if info.name in SKIP_MODULES or any(p.startswith("_") for p in info.name.split(".")):
            continue
        names.append(info.name)
    return sorted(names)


def _heading(text: str) -> str:
    return f"{text}\n{'=' * len(text)}\n"


def _summary(obj: object) -> str:
    """The first sentence line of a class, function or module docstring ('' for data)."""
    if not (inspect.isclass(obj) or inspect.isroutine(obj) or inspect.ismodule(obj)):
        return ""
    doc = inspect.getdoc(obj) or ""
    return doc.strip().split("\n\n")[0].replace("\n", " ")


def _common_parts(a: str, b: str) -> int:
    n = 0
    for x, y in zip(a.split("."), b.split(".")):
        if x != y:
            break
        n += 1
    return n


def exported_names(mod: object) -> list[str]:
    """A module's public names: its ``__all__``, else the classes and functions it defines."""
    names = getattr(mod, "__all__", None)
    if names is not None:
        return list(names)
    return [n for n, obj in vars(mod).items() if not n.startswith("_")
            and (inspect.isclass(obj) or inspect.isfunction(obj))
            and obj.__module__ == mod.__name__]


def _homes(modules: dict[str, object]) -> dict[tuple[int, str], str]:
    """Where each exported object is documented, once: ``(id(obj), name) -> module``.

    A class or function is documented in the public module that defines it; if that module
    is private (``bondgraph.numeric._compile``), in the public module exporting it that shares
    the longest prefix with it, the deepest on a tie (``bondgraph.numeric``).  Data (constants,
    type aliases, signal symbols) go to the deepest module exporting them.
    """
    exporters: dict[tuple[int, str], list[str]] = {}
    objects = {}
    for modname, mod in modules.items():
        for name in exported_names(mod):
            try:
                obj = getattr(mod, name)
            except ImportError:
                continue
            if inspect.ismodule(obj):
                continue
            key = (id(obj), name)
            objects[key] = obj
            exporters.setdefault(key, []).append(modname)
    homes = {}
    for key, mods in exporters.items():
        obj = objects[key]
        defined = getattr(obj, "__module__", None) if (
            inspect.isclass(obj) or inspect.isroutine(obj)) else None
        if defined in mods:
            homes[key] = defined
        else:
            homes[key] = max(sorted(mods), key=lambda m: (_common_parts(m, defined or ""),
                                                          m.count(".")))
    return homes


def _directive(obj: object) -> str:
    if inspect.isclass(obj):
        return "autoclass"
    if inspect.isroutine(obj) or callable(obj) and hasattr(obj, "__wrapped__"):
        return "autofunction"
    return "autodata"


def _module_page(name: str, mod: object, homes: dict[tuple[int, str], str]) -> str:
    exported = exported_names(mod)
    if name == "bondgraph":
        exported = sorted(exported, key=str.lower)
    rows, bodies = [], []
    for member in exported:
        try:
            obj = getattr(mod, member)
        except ImportError:   # bg.sweep without the study extra
            continue
        if inspect.ismodule(obj):
            target = obj.__name__
        else:
            home = homes[(id(obj), member)]
            target = f"{home}.{member}"
            if home == name:
                if isinstance(obj, types.GenericAlias):
                    # a type alias (``tuple[float, float]``) is callable: autodata would try
                    # to format its signature and fail
                    bodies.append(f".. py:data:: {target}\n\n   Type alias of ``{obj}``.\n\n")
                    rows.append(f"   * - :py:obj:`~{target}`\n     - Type alias of ``{obj}``.\n")
                    continue
                options = "   :no-value:\n" if _directive(obj) == "autodata" and not isinstance(
                    obj, (int, float, str, tuple)) else ""
                bodies.append(f".. {_directive(obj)}:: {target}\n{options}\n")
        rows.append(f"   * - :py:obj:`~{target}`\n     - {_summary(obj) or ' '}\n")
    page = _heading(f"``{name}``") + f"\n.. automodule:: {name}\n   :no-members:\n\n"
    if rows:
        page += (".. list-table::\n   :widths: 30 70\n   :class: api-summary\n\n"
                 + "".join(rows) + "\n")
    return page + "".join(bodies)


def write_api_pages(out: Path) -> list[str]:
    """Write one ``.rst`` page per public module into ``out`` (emptied first); return their names.

    Every name of a module's ``__all__`` is listed on its page with a link; it is documented in
    full once, on the page of its home module (see :func:`_homes`).
    """
    out.mkdir(parents=True, exist_ok=True)
    modules = {}
    for name in public_modules():
        try:
            modules[name] = importlib.import_module(name)
        except ImportError as exc:
            extra = next((e for m, e in OPTIONAL_MODULES.items()
                          if name == m or name.startswith(m + ".")), None)
            if extra is None:
                raise
            print(f"[bondgraph docs] {name} left out: needs the '{extra}' extra ({exc})")
    homes = _homes(modules)
    pages = {f"{name}.rst": _module_page(name, mod, homes) for name, mod in modules.items()}
    index = _heading("API reference") + (
        "\nGenerated at build time from the package: a page for every public module (no part "
        "of its name starts with ``_``), listing the names of its ``__all__``; each name is "
        "documented in full on the page of the module that defines it.\n\n"
        ".. toctree::\n   :maxdepth: 1\n\n" + "".join(f"   {n}\n" for n in modules))
    pages["modules.rst"] = index
    for stale in set(p.name for p in out.glob("*.rst")) - set(pages):
        (out / stale).unlink(missing_ok=True)   # a module that no longer exists
    for filename, text in pages.items():
        _write_if_changed(out / filename, text)
    return list(modules)


def _write_if_changed(path: Path, text: str) -> None:
    """Replace ``path`` atomically, and only when its text changes.

    Two builds at once (a test run beside a developer's build) then never see a
    half-written or missing page, and an unchanged page keeps its timestamp so an
    incremental build does not reread it.
    """
    try:
        if path.read_text(encoding="utf-8") == text:
            return
    except FileNotFoundError:
        pass
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)


def write_landing_figures(out: Path) -> None:
    """Draw the landing page's FLEXCAM bond graph (SVG) and Bode diagram (SVG) into ``out``."""
    import io

    import numpy as np

    from bondgraph.drawing.plots import bode

    out.mkdir(parents=True, exist_ok=True)
    flexcam = bondgraph.load_model(ROOT / "models" / "flexcam.py")
    model = flexcam.derive()
    svg = bondgraph.draw(model, fmt="svg")
    _write_if_changed(out / "flexcam.svg", svg)
    G = model.transfer_function("hub.e_in", "y").subs(flexcam.parameters)
    fig = bode(G.to_control(), omega=np.logspace(1, 3.5, 800), hz=True,
               labels=["tip deflection y(L) / e_in"], title="FLEXCAM, paper formulation")
    fig.set_size_inches(6.4, 4.0)
    buffer = io.StringIO()
    fig.savefig(buffer, format="svg", metadata={"Date": None})
    _write_if_changed(out / "flexcam_bode.svg", buffer.getvalue())


write_api_pages(DOCS / "api" / "generated")
write_landing_figures(DOCS / "_generated")
