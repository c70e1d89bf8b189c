"""Issue 23, item 13 (audit C39): a closed standard output exits non-zero, saying so."""

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

MSD = """\
import bondgraph as bg

def model():
    g = bg.BondGraph("msd")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"), bg.C("c"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "c")]:
        g.connect(t, h)
    return bg.ModelDefinition(g, outputs={"x": bg.displacement("c")},
                              parameters={"m": 2.0, "b": 6.0, "c": 0.25})
"""


def test_closed_stdout_exits_1(tmp_path):
    model = tmp_path / "msd.py"
    model.write_text(MSD)
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run(["sh", "-c", f'"{sys.executable}" -m bondgraph equations "{model}" >&-'],
                          capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 1
    assert done.stderr.strip() == "error: standard output was closed before everything was printed"
