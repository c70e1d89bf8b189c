"""The package type-checks cleanly with mypy under the repository's ``mypy.ini``.

mypy runs in-process (``mypy.api``) from this one test, so under pytest-xdist
it runs once, on one worker.  Its cache goes to a fresh pytest temporary
directory, never into the repository (a cold run takes about 5-10 s).
"""

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def test_mypy_clean(tmp_path_factory):
    pytest.importorskip("mypy")
    from mypy import api

    cache = tmp_path_factory.mktemp("mypy_cache")
    stdout, stderr, status = api.run([
        "--config-file", str(REPO / "mypy.ini"),
        "--cache-dir", str(cache),
        str(REPO / "bondgraph"),
    ])
    assert status == 0, f"mypy exit status {status}:\n{stdout}{stderr}"
