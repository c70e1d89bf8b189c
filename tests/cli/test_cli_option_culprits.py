"""Issue 23, item 13 (audit W07, W15-W18, W21): an option's error names the option, not the model file."""

import contextlib
import io

import pytest

from bondgraph.cli import main

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


def _run(*argv):
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(list(argv))
    return code, err.getvalue().strip()


@pytest.mark.parametrize("option,message", [
    (["--n", "0"], "error: --n must be between 1 and 10,000,000; got 0"),
    (["--n", "1000000000000"], "error: --n must be between 1 and 10,000,000; got 1,000,000,000,000"),
    (["--workers", "0"], "error: --workers must be at least 1; got 0"),
    (["--seed", "-1"], "error: --seed must be at least 0; got -1"),
    (["--chunk-size", "-1"], "error: --chunk-size must be at least 1; got -1"),
], ids=["n-zero", "n-huge", "workers", "seed", "chunk-size"])
def test_sweep_option_errors_name_the_option(tmp_path, option, message):
    pytest.importorskip("pandas")
    model = tmp_path / "msd.py"
    model.write_text(MSD)
    study = tmp_path / "st.toml"
    study.write_text("[sweep]\nm = [1.0, 2.0]\n")
    code, err = _run("sweep", str(model), "--params", str(study), "--metric", "max_real",
                     "-o", str(tmp_path / "o.csv"), *option)
    assert code == 1 and err == message
    assert not (tmp_path / "o.csv").exists()


def test_study_file_option_error_names_the_study_file(tmp_path):
    pytest.importorskip("pandas")
    model = tmp_path / "msd.py"
    model.write_text(MSD)
    study = tmp_path / "st.toml"
    study.write_text("[sweep]\nm = [1.0, 2.0]\n[study]\nn = 0\n")
    code, err = _run("sweep", str(model), "--params", str(study), "--metric", "max_real",
                     "-o", str(tmp_path / "o.csv"))
    assert code == 1
    assert err == f"error: n in the [study] table of '{study}' must be between 1 and 10,000,000; got 0"


def test_memory_error_is_not_blamed_on_the_model_file(tmp_path, monkeypatch):
    """R01c: 'error: model file 'chain.py': MemoryError: MemoryError' after 7.8 GB."""
    import types

    import bondgraph.cli._common as common

    model = tmp_path / "msd.py"
    model.write_text(MSD)

    def exhausted(*a, **k):
        raise MemoryError

    monkeypatch.setattr(common, "_transfer_module",
                        lambda: types.SimpleNamespace(transfer_function=exhausted,
                                                      transfer_matrix=exhausted))
    code, err = _run("tf", str(model))
    assert code == 1 and err.startswith("error: out of memory in 'bondgraph tf'")
    assert "model file" not in err
