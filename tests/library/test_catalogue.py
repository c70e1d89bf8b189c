"""The component catalogue page and its pictures are generated from the library, and current."""

from __future__ import annotations

from pathlib import Path

from bondgraph.library.catalogue import catalogue_markdown, load_all

DOCS = Path(__file__).resolve().parents[2] / "docs"


def test_catalogue_page_is_current_and_every_component_has_its_picture():
    page = (DOCS / "guide" / "library.md").read_text(encoding="utf-8")
    assert page == catalogue_markdown(), (
        "docs/guide/library.md is stale: run python -m bondgraph.library.catalogue docs")
    for key, cls in load_all().items():
        assert f"### {cls.__name__}" in page
        assert (DOCS / "img" / "library" / f"{key}.svg").is_file(), key


def test_catalogue_is_listed_in_the_documentation_index():
    index = (DOCS / "index.md").read_text(encoding="utf-8")
    assert "guide/library" in index and "guide/domains" in index
