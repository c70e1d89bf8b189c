"""What the command line imports before it works (no timings here: bench/bench_cli_startup.py).

``bondgraph --help`` must not load sympy, numpy, scipy or the engine: the parser and the
package's front are plain Python.  ``import bondgraph`` binds its names on first use, and
building a graph loads no scipy (numeric plants, exports and drawings load when used).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HEAVY = ("sympy", "numpy", "scipy", "networkx", "matplotlib", "pandas", "bondgraph.model")


def loaded_after(code: str) -> dict[str, bool]:
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    probe = (f"import sys, json, io, contextlib\n{code}\n"
             f"print(json.dumps({{m: m in sys.modules for m in {HEAVY!r}}}))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=env,
                         check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("argv", [["--help"], ["--version"], ["simulate", "--help"],
                                  ["sweep", "--help"], ["export", "--help"]],
                         ids=lambda a: " ".join(a))
def test_help_loads_no_engine(argv):
    code = ("from bondgraph.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            f"    assert main({argv!r}) == 0\n")
    assert not any(loaded_after(code).values())


def test_building_a_graph_loads_no_scipy():
    loaded = loaded_after("import bondgraph as bg\ng = bg.BondGraph('x')\ng.add(bg.Se('V'))")
    assert loaded["sympy"] and not loaded["scipy"] and not loaded["matplotlib"]
