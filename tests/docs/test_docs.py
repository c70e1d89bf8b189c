"""The documentation site builds with warnings as errors, and its examples run.

``test_site_builds`` runs ``sphinx-build -W --keep-going -b html docs <tmp>``
in a subprocess (the API reference generated from the docstrings, the user
guide, the notebooks executed by myst-nb) and looks at a few pages.  It
is one test on purpose: under ``pytest -n 2`` a fixture shared by several
tests would build the site once per worker.

``test_guide_examples`` runs the ``>>>`` examples of every Markdown page of
the guide as doctests, so the guide cannot drift from the code; the expected
outputs in the pages are hand results (or printed forms checked against
them), never produced by running this test.
"""

from __future__ import annotations

import doctest
import importlib.util
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
PAGES = sorted([DOCS / "index.md", *(DOCS / "guide").glob("*.md")])
#: pages whose examples need an optional extra
NEEDS = {"studies.md": "pandas"}


def _examples(path: Path) -> str:
    """The page with everything outside its ```python / ```pycon blocks blanked.

    Line numbers are kept, so a failure points at the page's own line; the
    closing fence becomes a blank line, which ends an example's expected output.
    """
    kept, block = [], None
    for line in path.read_text(encoding="utf-8").splitlines():
        fence = re.match(r"^\s*```+\s*\{?([\w-]*)\}?", line)
        if fence and block is None:
            block = fence.group(1)
            kept.append("")
        elif fence and line.strip().strip("`") == "":
            block = None
            kept.append("")
        else:
            kept.append(line if block in ("python", "pycon") else "")
    return "\n".join(kept) + "\n"


def _sphinx_missing() -> str | None:
    for module in ("sphinx", "numpydoc", "myst_nb", "furo", "sphinx-mathjax-offline"):
        if importlib.util.find_spec(module) is None:
            return f"{module} is not installed (pip install -e '.[docs]')"
    return None


def test_examples_reader_keeps_only_python_blocks(tmp_path):
    page = tmp_path / "p.md"
    page.write_text("text >>> 1\n```bash\n>>> 2\n```\n```python\n>>> 1 + 1\n2\n```\n>>> 3\n")
    test = doctest.DocTestParser().get_doctest(_examples(page), {}, "p", str(page), 0)
    assert [e.source for e in test.examples] == ["1 + 1\n"]
    assert [e.want for e in test.examples] == ["2\n"]
    assert test.examples[0].lineno == 5


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_guide_examples(page, monkeypatch):
    if page.name in NEEDS:
        pytest.importorskip(NEEDS[page.name], reason=f"{page.name} needs the study extra")
    monkeypatch.chdir(ROOT)          # models.md loads models/srv02.py from the repository root
    test = doctest.DocTestParser().get_doctest(_examples(page), {}, page.name, str(page), 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    out: list[str] = []
    runner.run(test, out=out.append)
    assert runner.failures == 0, "".join(out)
    if page.parent.name == "guide" and page.name not in ("verification.md", "performance.md"):
        assert test.examples, f"{page.name}: no runnable example"


def test_site_builds(tmp_path):
    missing = _sphinx_missing()
    if missing:
        pytest.skip(missing)
    out = tmp_path / "html"       # myst-nb keeps executed notebooks beside it, in tmp_path
    start = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
         str(DOCS), str(out)],
        cwd=ROOT, capture_output=True, text=True, timeout=900)
    seconds = time.perf_counter() - start
    assert proc.returncode == 0, f"sphinx-build failed:\n{proc.stdout[-4000:]}\n{proc.stderr[-8000:]}"
    print(f"documentation site built in {seconds:.1f} s")

    # the API reference: BondGraph and derive_equations documented once, at their home modules, with the
    # numpydoc sections rendered; the top-level page links every name of bondgraph.__all__
    graph = (out / "api" / "generated" / "bondgraph.graph.html").read_text(encoding="utf-8")
    assert 'id="bondgraph.graph.BondGraph"' in graph
    equations = (out / "api" / "generated" / "bondgraph.equations.derive.html").read_text(
        encoding="utf-8")
    assert 'id="bondgraph.equations.derive.derive_equations"' in equations
    assert "Parameters" in equations and "Examples" in equations
    top = (out / "api" / "generated" / "bondgraph.html").read_text(encoding="utf-8")
    import bondgraph

    for name in ("BondGraph", "derive", "Model", "compile_plant", "simulate", "draw"):
        assert name in bondgraph.__all__
        assert re.search(rf'href="[^"]*#bondgraph\.(?:\w+\.)*{name}"', top), name
    for module in ("tf", "numeric", "identification", "codegen", "export", "hamiltonian",
                   "elements.protocol", "linear.operating", "beam", "fmu", "errors", "hybrid",
                   "library", "structure", "equations"):
        assert (out / "api" / "generated" / f"bondgraph.{module}.html").is_file(), module

    # a notebook page with executed outputs: the SRV-02 hub's printed transfer function and
    # the figures the notebooks draw, embedded as images
    hub = (out / "notebooks" / "01_srv02_hub.html").read_text(encoding="utf-8")
    outputs = " ".join(re.findall(r'class="cell_output[^"]*">(.*?)</div>\s*</div>', hub, re.S))
    # theta/e_in of the hub, Eq. (1) configuration: 375.7/(s (s + 42.54)) (the models page's table)
    assert "375.7" in outputs and "42.54" in outputs
    assert re.search(r'<img [^>]*src="../_images/\w+\.png"', hub), "no figure in 01_srv02_hub"
    for name in ("01_srv02_hub", "02_flexcam", "03_appendages", "04_identification", "05_control"):
        page = (out / "notebooks" / f"{name}.html").read_text(encoding="utf-8")
        assert "cell_output" in page, f"{name}: no executed output"
    assert any((out / "_images").glob("*.png")), "no notebook figure rendered"

    # the guide and the generated bad-input catalogue
    assert (out / "guide" / "causality.html").is_file()
    assert "derivative causality" in (out / "guide" / "causality.html").read_text(encoding="utf-8")
    assert "bad-input catalogue" in (out / "errors.html").read_text(encoding="utf-8")
    _check_offline(out)

    # the landing page: the three-line example, the FLEXCAM bond graph and its Bode diagram
    index = (out / "index.html").read_text(encoding="utf-8")
    assert "load_model" in index and "transfer_function" in index
    for name in ("flexcam.svg", "flexcam_bode.svg"):
        assert re.search(rf'<img [^>]*src="_images/{name}"', index), name
        assert (out / "_images" / name).is_file(), name
    # the notebooks open on the physics: the set-up cell is collapsed (myst-nb's hide-input)
    for name in ("01_srv02_hub", "02_flexcam", "03_appendages", "04_identification", "05_control"):
        page = (out / "notebooks" / f"{name}.html").read_text(encoding="utf-8")
        assert "tag_hide-input" in page, name


#: a <script src=...> or <link href=...> to another host (http:, https: or protocol-relative)
_EXTERNAL = re.compile(r'<(?:script|link)\b[^>]*\b(?:src|href)\s*=\s*["\']?(?:https?:)?//', re.I)


def _check_offline(out: Path) -> None:
    """Nothing of the site comes from the network, and its own MathJax renders its math."""
    pages = sorted(out.rglob("*.html"))
    bad = [(p.relative_to(out), m.group(0)) for p in pages
           for m in _EXTERNAL.finditer(p.read_text(encoding="utf-8"))]
    assert not bad, bad[:5]
    for css in out.rglob("*.css"):
        text = css.read_text(encoding="utf-8", errors="replace")
        assert not re.search(r"(@import|url\()\s*[\"']?(https?:)?//", text), css
    mathjax = out / "_static" / "mathjax"
    assert (mathjax / "tex-chtml.js").is_file()
    assert any((mathjax / "output" / "chtml" / "fonts" / "woff-v2").glob("*.woff"))
    page = (out / "guide" / "transfer-functions.html").read_text(encoding="utf-8")
    assert 'src="../_static/mathjax/tex-chtml.js' in page
    formulas = re.findall(r'class="math notranslate nohighlight">\s*\\[\[(](.*?)\\[\])]', page, re.S)
    assert formulas, "no math on the transfer-functions page"
    node = shutil.which("node")
    if node is None:
        return
    import html

    script = ("const [dir, tex] = process.argv.slice(1);"
              "require(dir + '/node-main.js').init({loader: {paths: {mathjax: dir},"
              " load: ['input/tex', 'output/chtml', 'adaptors/liteDOM']}})"
              ".then((MJ) => console.log(MJ.startup.adaptor.outerHTML(MJ.tex2chtml(tex))))"
              ".catch((e) => { console.error(e.message); process.exit(1); });")
    tex = html.unescape(formulas[0])
    done = subprocess.run([node, "-e", script, str(mathjax), tex], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("<mjx-container") and "<mjx-merror" not in done.stdout, done.stdout[:500]
