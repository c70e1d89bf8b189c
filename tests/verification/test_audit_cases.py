"""The shared hostile-input audit (``../shared/audit/turn4/cases``, issue 36): a quick subset in CI.

Each case runs in its own process under the audit's own runner (``run_cases.py``, which
classifies it: refused-well, accepted-right, SILENTLY-WRONG, raw-exception, hang, ...); the
subset here (units, chemistry, thermal and the component library) must print ``bad=0``.
The whole set (about 4 minutes on 2 cores) is a bench run:
``python ../shared/audit/turn4/cases/run_cases.py ../shared/audit/turn4/cases -v``.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT.parent / "shared" / "audit" / "turn4" / "cases"
#: groups that run in about a minute together and need no file of the project by path
QUICK = ("C_chemical", "D_thermal_library", "E_units")


@pytest.mark.skipif(not (CASES / "run_cases.py").is_file(),
                    reason=f"the shared audit cases are not beside the project ({CASES})")
def test_quick_audit_groups_print_bad_zero(tmp_path):
    root = tmp_path / "cases"
    root.mkdir()
    for group in QUICK:
        (root / group).symlink_to(CASES / group)
    for helper in CASES.glob("_*.py"):
        (root / helper.name).symlink_to(helper)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    done = subprocess.run([sys.executable, str(CASES / "run_cases.py"), str(root),
                           "--python", sys.executable, "--jobs", "1", "-v"],
                          cwd=ROOT, capture_output=True, text=True, timeout=900, env=env)
    found = re.findall(r"\bbad=(\d+)", done.stdout)
    assert found, done.stdout[-3000:] + done.stderr[-2000:]
    assert int(found[-1]) == 0, done.stdout[-6000:]
