"""``bondgraph tf MODEL --input U --output Y --numeric`` for every output of every model in
models/: the parameter policy (a value the definition knows but this output does not use is
accepted; an unknown name is refused listing the valid ones).

Before the fix every output of srv02.py failed with "unknown parameter 'k_pot'": the model
file's defaults for the sensor gains were refused for outputs that do not use them.
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import pytest

import bondgraph as bg
from bondgraph.cli import main
from bondgraph.cli._switched import mode_text, switched_of
from bondgraph.modelfile import load_model

MODELS = sorted((Path(__file__).resolve().parents[2] / "models").glob("*.py"))


def _signals(path: Path):
    definition = load_model(str(path))
    model = bg.derive(definition.graph, outputs=definition.outputs)
    return [(u, y) for u in model.input_names for y in model.output_names]


def _mode(path: Path) -> list[str]:
    """``--mode`` with the built mode for a switched model file (tf refuses it without one)."""
    sm = switched_of(load_model(str(path)))
    return [] if sm is None else ["--mode", mode_text(sm, sm.initial)]


CASES = [(path, u, y) for path in MODELS for u, y in _signals(path)]


def _run(*argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(list(argv))
    return status, out.getvalue(), err.getvalue()


def test_every_model_is_covered():
    assert {p.name for p in MODELS} >= {"srv02.py", "flexcam.py", "appendages.py"}
    assert len(CASES) >= 12


@pytest.mark.parametrize("path, u, y", CASES, ids=[f"{p.stem}:{y}" for p, _, y in CASES])
def test_numeric_tf_of_every_output(path, u, y):
    status, out, err = _run("tf", str(path), "--input", u, "--output", y, "--numeric", *_mode(path))
    assert status == 0, err
    assert out.startswith(f"{y}/{u} =")
    assert "error" not in err


def test_params_file_value_for_an_unused_parameter_is_accepted(tmp_path):
    """k_pot is a parameter of srv02's v_pot output only; theta does not use it."""
    params = tmp_path / "p.json"
    params.write_text('{"k_pot": 2.0, "Rm": 2.6}')
    srv02 = next(p for p in MODELS if p.name == "srv02.py")
    status, out, err = _run("tf", str(srv02), "--input", "e_in", "--output", "theta",
                            "--numeric", "--params", str(params))
    assert status == 0, err


def test_params_file_with_an_unknown_name_is_refused(tmp_path):
    params = tmp_path / "p.json"
    params.write_text('{"k_pott": 2.0}')
    srv02 = next(p for p in MODELS if p.name == "srv02.py")
    status, out, err = _run("tf", str(srv02), "--input", "e_in", "--output", "theta",
                            "--numeric", "--params", str(params))
    assert status != 0
    assert "k_pott" in err and "k_pot" in err.split("k_pott", 1)[1]


def test_zero_transfer_function_needs_no_values():
    """The open clutch: w2 does not respond to tau at all, G = 0 (Newton: nothing couples the
    two inertias).  A parameter left in the polynomial domain after the cancellation
    (J2) once made the numeric form ask for a value it does not use."""
    clutch = next(p for p in MODELS if p.name == "clutch.py")
    status, out, err = _run("tf", str(clutch), "--input", "tau", "--output", "w2", "--numeric",
                            "--mode", "on=K")
    assert status == 0, err
    assert out.startswith("w2/tau = 0")
