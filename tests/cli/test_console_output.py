"""Console output of the README main job (models/flexcam.py) and of ``bondgraph tf``.

References:

* the width rule of the issue: no line over 100 characters;
* seed 000, Eq. (13): the form ``(a5 s^5 + ... + a0)/(b6 s^6 + ... + b0)`` and
  its printed numbers (copied here from the seed text, not from the model);
* the pinned-free beam's closed form: ``omega_i = (beta_i L)^2 / L^2 sqrt(EI /
  rhoA)`` with ``tan(beta L) = tanh(beta L)`` (roots found here with
  scipy's ``brentq``), so the undamped denominator has ``b0 = prod omega_i^2``
  and ``b4 = sum omega_i^2`` (mass-normalised modes);
* the DC motor by hand: ``omega/V = K / (J La s^2 + (J Ra + La b) s + Ra b +
  K^2)``, monic: ``b1 = (J Ra + La b)/(J La) = 14``, ``b0 = (K^2 + Ra b)/(J
  La) = 41``, ``a0 = K/(J La) = 10`` with Ra 2, La 0.5, K 0.1, J 0.02, b 0.2.
"""

import math
import re
import sys
from pathlib import Path

import pytest
from scipy.optimize import brentq

from bondgraph.cli import main as cli_main

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "models"))
import flexcam  # noqa: E402

# seed 000 Eq. (13) as printed (a5..a0, b6..b0)
EQ13_NUM = {"a5": -3.8e-15, "a4": -4.91e-5, "a3": 3.8e-13, "a2": -0.0117, "a1": 2.28e-12, "a0": -0.85}
EQ13_DEN = {"b6": 1.0, "b5": 1.07e-5, "b4": 320.699, "b3": 0.002999, "b2": 16848.25, "b1": 0.116,
            "b0": 84534.2}


@pytest.fixture(scope="module")
def main_job(tmp_path_factory):
    out = tmp_path_factory.mktemp("out")
    import contextlib
    import io

    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        assert flexcam.main(["--out", str(out)]) == 0
    return buffer.getvalue()


def rows(text):
    """Rows of the coefficient table: name -> its cells (columns are apart by two spaces or more)."""
    found = {}
    for line in text.splitlines():
        if re.match(r"^[ab]\d  ", line):
            cells = tuple(re.split(r" {2,}", line))
            found[cells[0]] = cells
    return found


def test_main_job_lines_fit_100_characters(main_job):
    long = [line for line in main_job.splitlines() if len(line) > 100]
    assert not long, long


def test_main_job_has_every_coefficient_of_eq13_with_the_printed_value_and_ratio(main_job):
    table = rows(main_job)
    assert set(table) == set(EQ13_NUM) | set(EQ13_DEN)
    for name, printed in {**EQ13_NUM, **EQ13_DEN}.items():
        _, power, value, unit, paper, ratio = table[name]
        k = int(name[1])
        assert power == ("1" if k == 0 else "s" if k == 1 else f"s^{k}")
        assert float(paper) == pytest.approx(printed, rel=5e-4)
        if float(value) != 0.0:
            assert float(ratio) == pytest.approx(float(value) / printed, rel=2e-3)
        # units: y in m over e_in in V for a_k, 1/s^(6-k) for b_k (monic denominator)
        if name[0] == "a":
            assert unit == ("m/(V s)" if k == 5 else f"m/(V s^{6 - k})")
        else:
            assert unit == ("1" if k == 6 else "1/s" if k == 5 else f"1/s^{6 - k}")


def _pinned_free_omegas(n=3):
    EI, rhoA, L = flexcam.link_properties()
    roots = [brentq(lambda x: math.tan(x) - math.tanh(x), (i + 1) * math.pi + 1e-6,
                    (i + 1) * math.pi + math.pi / 2 - 1e-6) for i in range(n)]
    return [(r / L) ** 2 * math.sqrt(EI / rhoA) for r in roots]


def test_main_job_denominator_values_follow_from_the_beam_closed_form(main_job):
    table = rows(main_job)
    w = _pinned_free_omegas()
    assert float(table["b0"][2]) == pytest.approx(math.prod(x * x for x in w), rel=1e-3)
    assert float(table["b4"][2]) == pytest.approx(sum(x * x for x in w), rel=1e-3)
    # the symbolic form sits under its row
    assert "= link.k_1*link.k_2*link.k_3/(link.m_1*link.m_2*link.m_3)" in main_job


def test_main_job_pole_table_is_aligned(main_job):
    lines = main_job.splitlines()
    head = next(i for i, line in enumerate(lines) if line.startswith("kind  root"))
    block = [line for line in lines[head:head + 8] if line.startswith(("kind", "pole", "zero"))]
    assert len(block) == 6           # header, three pole pairs, two zero pairs
    starts = [lines[head].index(h) for h in ("wn (rad/s)", "f (Hz)", "zeta")]
    for line in block[1:]:
        for s in starts:
            assert line[s - 2:s] == "  " and line[s] != " "


def test_cli_tf_prints_the_coefficient_table(capsys):
    code = cli_main(["tf", str(REPO / "tests" / "data" / "dc_motor.py"), "-u", "V", "-y", "omega", "--numeric"])
    out = capsys.readouterr().out
    assert code == 0
    assert all(len(line) <= 100 for line in out.splitlines())
    got = {}
    for line in out.splitlines():
        m = re.match(r"^(a\d|b\d)\s+(1|s|s\^\d)\s+(\S+)(?:\s+(\S+))?$", line)
        if m:
            got[m.group(1)] = (float(m.group(3)), m.group(4))
    assert got == {"a0": (10.0, None), "b2": (1.0, "1"), "b1": (14.0, "1/s"), "b0": (41.0, "1/s^2")}
    assert "= (J*Ra + La*b)/(J*La)" in out


def test_cli_tf_of_flexcam_tip_fits_100_characters(capsys):
    code = cli_main(["tf", str(REPO / "models" / "flexcam.py"), "-u", "hub.e_in", "-y", "y", "--numeric"])
    out = capsys.readouterr().out
    assert code == 0
    assert all(len(line) <= 100 for line in out.splitlines())
    assert {m.group(1) for m in re.finditer(r"^(a\d|b\d) ", out, re.M)} == {
        "a4", "a3", "a2", "a1", "a0", "b6", "b5", "b4", "b3", "b2", "b1", "b0"}
