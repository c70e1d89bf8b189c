"""Runs the bad-input catalogue of ``tests/bad_inputs.py`` (issue 12).

Each case: the error class (derived from ``BondGraphError``), a message that
names the culprit (the case's regular expression), and nothing written in
the output directory.  ``docs/errors.md`` must be the catalogue rendered.
"""

import warnings
from pathlib import Path

import pytest

import bondgraph as bg

from bad_inputs import CASES, Dirs, generate, run

ROOT = Path(__file__).resolve().parents[2]


def test_catalogue_has_at_least_60_cases():
    assert len(CASES) >= 60
    assert len({c.id for c in CASES}) == len(CASES)


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_case(case, tmp_path):
    dirs = Dirs(tmp_path / "in", tmp_path / "out")
    dirs.inp.mkdir()
    dirs.out.mkdir()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bg.BondGraphWarning)
        with pytest.raises(case.error, match=case.match) as info:
            case.call(dirs)
    assert isinstance(info.value, bg.BondGraphError)
    assert sorted(p.name for p in dirs.out.rglob("*")) == [], "a file was written"
    assert run(case, dirs)  # the page generator sees the same error


def test_docs_errors_page_is_the_catalogue():
    page = ROOT / "docs" / "errors.md"
    assert page.read_text(encoding="utf-8") == generate(), (
        "docs/errors.md is out of date: python tests/bad_inputs.py docs/errors.md")
