"""The README is the door: the two commands, a first model that runs, a feature table
linking to the guide, where to read on; everything else lives in the guide.

The README once held the reference manual, the verification report and the
performance tables (64 kB); they moved to ``docs/guide/`` and
:func:`test_moved_facts_live_in_the_guide` keeps a sample of each moved section's
facts where it went.
"""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
GUIDE = ROOT / "docs" / "guide"
#: what .ci/run runs, verbatim: set up + main job, set up + the whole test suite
COMMANDS = [
    'python3 -m venv .venv && . .venv/bin/activate && pip install -q -e . && '
    'python models/flexcam.py --out out',
    'python3 -m venv .venv && . .venv/bin/activate && pip install -q -e ".[test]" && '
    'python -m pytest -q -n 2 --nbmake notebooks tests bondgraph',
]


def _text() -> str:
    return README.read_text(encoding="utf-8")


def test_readme_python_blocks_run(capsys):
    blocks = re.findall(r"```python\n(.*?)```", _text(), flags=re.S)
    assert blocks
    for code in blocks:
        namespace: dict = {}
        exec(compile(code, str(README), "exec"), namespace)
    out = capsys.readouterr().out
    assert "dp_La/dt" in out
    # the comment under print(G.expr) is what it prints: omega/V of the DC motor by hand,
    # (La s + Ra)(J s + b) + K^2 in the denominator
    assert "K/(J*La*s**2 + K**2 + Ra*b + s*(J*Ra + La*b))" in out
    assert "print(G.expr)                # K/(J*La*s**2 + K**2 + Ra*b + s*(J*Ra + La*b))" in _text()


def test_readme_opens_with_the_two_commands_ci_runs():
    text = _text()
    first = re.search(r"```(\w*)\n(.*?)```", text, flags=re.S)
    assert first.group(1) == "bash", "the README's first block must be the bash block .ci/run reads"
    lines = [line for line in first.group(2).splitlines() if line.strip()]
    assert lines == COMMANDS
    assert text.index("```bash") < text.index("## ")          # before any section


def test_readme_is_a_door():
    assert README.stat().st_size <= 15_000
    headings = re.findall(r"^## (.+)$", _text(), flags=re.M)
    assert headings == ["A first model", "What it does", "Where to read on"]


def _slug(heading: str) -> str:
    """GitHub's (and MyST's) anchor of a Markdown heading."""
    text = re.sub(r"[`*_]", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def _links(text: str) -> list[str]:
    return [t for t in re.findall(r"\]\(([^)\s]+)\)", text) if not re.match(r"\w+:", t)]


def test_readme_links_resolve():
    links = _links(_text())
    assert links
    for link in links:
        path, _, anchor = link.partition("#")
        target = (ROOT / path).resolve()
        assert target.exists(), link
        if anchor:
            headings = re.findall(r"^#+ (.+)$", target.read_text(encoding="utf-8"), flags=re.M)
            assert anchor in {_slug(h) for h in headings}, link


def test_feature_table_links_every_capability_to_a_page_of_the_site():
    table = [line for line in _text().splitlines() if line.startswith("| ")][1:]   # no header
    features = {row.split("|")[1].strip(): row for row in table}
    for feature in ("state equations", "causality", "transfer functions", "numeric plants",
                    "switched models", "nonlinear and implicit models",
                    "thermal and chemical domains", "units", "structural analysis",
                    "code generation and FMUs", "identification", "parameter studies",
                    "drawing", "verification", "performance"):
        assert feature in features, feature
        assert "](docs/guide/" in features[feature], feature
    index = (ROOT / "docs" / "index.md").read_text(encoding="utf-8")
    for link in _links(_text()):
        if link.startswith("docs/guide/") and link.endswith(".md"):
            assert f"guide/{Path(link).stem}\n" in index, f"{link} is not in the site's toctree"


#: a sample of each section that left the README, at its new place
MOVED = {
    "conventions.md": ["`sympify` runs strictly in the whole package",
                       "(the load inertia of another\n  variant",
                       'bg.TF("gear", 1/N)', "SCAP backtracks on\n  a conflict"],
    "pipeline.md": ["tests/house/test_layering.py", "position outputs as state combinations"],
    "elements.md": ["port-Hamiltonian form | `energy_signals`", "an open\ndifferential",
                    "the first failing parameter\nset"],
    "models.md": ["`two_tanks.py`", "difference <= 8e-15", "05_control"],
    "domains.md": ["| chemical |", "Wegscheider", "bondgraph tf models/two_tanks.py --output q_out"],
    "switched.md": ["tan(w t) = -w R C", "Middlebrook and Cuk", "4.99999 V", "3.125 mV",
                    "240 modes, 140"],
    "getting-started.md": ["exits with status 2", "OPTIONAL_MODULES", "sigma=-0.1+2j"],
    "operating-points.md": ["upright.json", "[[-b/J, +m g l], [1/J, 0]]"],
    "numeric.md": ["A_indptr", "load_npz"],
    "studies.md": ["pickle", "dask-jobqueue"],
    "drawing.md": ["texlive-pictures", "0 bond crossings", "15.2 x 36.4 cm"],
    "energy.md": ["PHLTIModel", "nonconservative"],
    "verification.md": ["17,831 agree", "--n 20000 --seed 0 --jobs 2 --timeout 30 --orders 1",
                        "4922   98.44", "seeds 9168, 17243, 18398"],
    "performance.md": ["LOOP_TERM_BUDGET", "bench_chain.py --large", "99998    0.60    11.63",
                       "chain10        20      30", "102,400 bounded", "absence of state `nominal`"],
}


def test_moved_facts_live_in_the_guide():
    for page, facts in MOVED.items():
        text = (GUIDE / page).read_text(encoding="utf-8")
        for fact in facts:
            assert fact in text, f"{page}: {fact!r}"
