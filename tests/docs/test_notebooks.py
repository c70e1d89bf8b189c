"""The example notebooks are present, well formed and committed without outputs.

They are executed by ``pytest --nbmake notebooks``; this only checks the files.
"""

import json
from pathlib import Path

import pytest

NOTEBOOKS = Path(__file__).resolve().parents[2] / "notebooks"
NAMES = ("01_srv02_hub", "02_flexcam", "03_appendages", "04_identification", "05_control",
         "06_structure")


def _load(name):
    return json.loads((NOTEBOOKS / f"{name}.ipynb").read_text(encoding="utf-8"))


@pytest.mark.parametrize("name", NAMES)
def test_notebook_is_valid_and_clean(name):
    nb = _load(name)
    assert nb["nbformat"] == 4
    cells = nb["cells"]
    assert cells and cells[0]["cell_type"] == "markdown"
    assert "".join(cells[0]["source"]).startswith("# ")
    code = [c for c in cells if c["cell_type"] == "code"]
    assert code, f"{name}: no code cell"
    for c in code:
        assert c["outputs"] == [], f"{name}: committed with outputs; clear them"
        assert c["execution_count"] is None, f"{name}: committed with execution counts"


@pytest.mark.parametrize("name", NAMES)
def test_notebook_finds_models_without_file_path(name):
    # nbmake runs a notebook with its own folder as working directory; the first code cell
    # must locate models/ from there (no __file__ in a notebook) and not write bytecode
    setup = "".join(next(c for c in _load(name)["cells"] if c["cell_type"] == "code")["source"])
    assert "find_models" in setup and "dont_write_bytecode" in setup
