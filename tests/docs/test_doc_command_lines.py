"""Every ``bondgraph ...`` command line of the README and the user guide is run.

Command lines with concrete names (``bondgraph tf models/srv02.py --input e_in ...``)
are run with :func:`bondgraph.cli.main` in a scratch directory that sees the
repository's ``models/``, plus the two files the guide names without shipping
them (``pendulum.py``, the pendulum of the operating-points page, and a
``study.toml`` for the sweep).  Templates (``bondgraph tf MODEL --input U
--output Y [--latex]``) are filled in (``MODEL`` -> ``models/srv02.py``, ``U`` ->
``e_in``, the first of ``a|b|c``, the bracketed options kept) and parsed by the
command line's own parser, so an option or format the docs name and the
program does not know fails here.  The guide's first example once named an
input ``Vm`` that srv02 does not have; that cannot come back.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs" / "guide").glob("*.md"))]
#: names a filled-in template uses
FILL = [("MODEL", "models/srv02.py"), ("FILE.svg", "fig.svg"), ("FILE", "p.json"),
        ("OUT", "out.json"), ("U=V", "e_in=1"), ("X=V", "theta=0"), ("U", "e_in"),
        ("Y", "theta")]
TEMPLATE_WORDS = re.compile(r"\b(MODEL|FILE|OUT|U|Y|X=V|U=V)\b|\||\[")

PENDULUM = '''
import sympy
import bondgraph as bg

def model():
    m, g_, l = sympy.symbols("m g l", positive=True)
    gr = bg.BondGraph("pendulum")
    w = bg.One("w")
    gr.add(bg.Se("T"), w, bg.I("J"), bg.R("b"), bg.C("grav", law=m * g_ * l * sympy.sin(bg.q)))
    for t, h in [("T", w), (w, "J"), (w, "b"), (w, "grav")]:
        gr.connect(t, h)
    return bg.ModelDefinition(gr, parameters={"m": 1.0, "g": 9.81, "l": 0.5, "J": 0.25,
                                              "b": 0.1})
'''
STUDY = '[sweep]\nRm = [2.0, 3.0]\nk_cam = [30.0, 50.0]\n[study]\nseed = 1\n'


def command_lines() -> list[tuple[str, str]]:
    """``(page, command)`` for every command line in fenced blocks and inline code."""
    found = []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        block = None
        for line in text.splitlines():
            fence = re.match(r"^\s*```+\s*\{?([\w-]*)\}?", line)
            if fence and block is None:
                block = fence.group(1)
            elif fence and line.strip().strip("`") == "":
                block = None
            elif block is not None and block not in ("python", "pycon") and \
                    re.match(r"^\s*\$?\s*bondgraph\s", line):
                found.append((page.name, re.sub(r"^\s*\$?\s*", "", line).strip()))
        outside = re.sub(r"```.*?```", "", text, flags=re.S)
        for span in re.findall(r"`(bondgraph [^`]+)`", outside):
            found.append((page.name, re.sub(r"\s+", " ", span).strip()))
    return found


COMMANDS = command_lines()
CONCRETE = [(p, c) for p, c in COMMANDS if not TEMPLATE_WORDS.search(c)
            and (len(c.split()) > 2 or c.endswith("--help"))]
TEMPLATES = [(p, c) for p, c in COMMANDS if (p, c) not in CONCRETE]


def test_the_docs_have_command_lines():
    assert len(CONCRETE) >= 6 and len(TEMPLATES) >= 5
    assert any("tf models/srv02.py --input e_in" in c for _, c in CONCRETE)
    # the upright pendulum, whose exported A is checked below, is on the operating-points page
    assert ("operating-points.md", "bondgraph export pendulum.py --trim --guess q_grav=3 -o "
            "upright.json") in CONCRETE


def _fill(command: str) -> list[str]:
    text = command.replace("[", " ").replace("]", " ")
    text = re.sub(r"(\S+?)\|\S+", r"\1", text)
    words = []
    for word in text.split()[1:]:
        for placeholder, value in FILL:
            if word == placeholder or word.startswith(placeholder + "."):
                word = value if word == placeholder or placeholder == "FILE.svg" else \
                    value + word[len(placeholder):]
                break
        words.append(word)
    return words


@pytest.mark.parametrize("page, command", TEMPLATES, ids=[c for _, c in TEMPLATES])
def test_templates_parse(page, command):
    from bondgraph.cli._parser import build_parser

    argv = _fill(command)
    if len(argv) <= 1:          # "bondgraph tf" named in a sentence: the subcommand exists
        with contextlib.redirect_stdout(io.StringIO()), pytest.raises(SystemExit) as info:
            build_parser().parse_args(argv + ["--help"])
        assert info.value.code == 0
        return
    build_parser().parse_args(argv)      # argparse exits (status 2) on an unknown option


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    d = tmp_path_factory.mktemp("docs_cli")
    os.symlink(ROOT / "models", d / "models")
    (d / "pendulum.py").write_text(PENDULUM)
    (d / "study.toml").write_text(STUDY)
    (d / "out").mkdir()
    return d


@pytest.mark.parametrize("page, command", CONCRETE, ids=[c for _, c in CONCRETE])
def test_concrete_command_lines_run(page, command, scratch, monkeypatch):
    from bondgraph.cli import main

    argv = command.split()[1:]
    if "sweep" in argv:
        pytest.importorskip("pandas")
        argv[argv.index("--n") + 1] = "64"      # the docs' 10000 samples: the same command
    monkeypatch.chdir(scratch)
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(argv)
    assert status == 0, f"{page}: {command}\n{err.getvalue()}"
    if "upright.json" in argv:
        # the operating-points page: A = [[-b/J, +m g l], [1/J, 0]] at the upright point
        A = np.array(json.loads((scratch / "upright.json").read_text())["A"], dtype=float)
        assert A == pytest.approx(np.array([[-0.1 / 0.25, 1.0 * 9.81 * 0.5], [1 / 0.25, 0.0]]))
