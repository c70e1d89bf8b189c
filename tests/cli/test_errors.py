"""Command-line failures (issue 12): no traceback, a non-zero exit, a message naming the
culprit (path, key, parameter), and no file written.

Every case runs ``main([...])`` in process.  ``outdir`` is a directory of its own for
outputs, so "nothing written" is ``os.listdir(outdir) == []`` (no partial file, no
temporary ``.tmp`` or backup ``.bak`` file).
"""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import bondgraph
import bondgraph.cli as cli
from bondgraph.cli import CLIError, ParamsFileError, load_params, main
from bondgraph.export import ExportError, atomic_write_many, export_json
from bondgraph.modelfile import ModelFileError, load_model
from bondgraph.numeric import NumericStateSpace

DATA = Path(__file__).resolve().parents[1] / "data"
MOTOR = str(DATA / "dc_motor.py")


@pytest.fixture
def outdir(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    return out


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in err and "Traceback" not in out
    return code, out, err


def failed(capsys, *argv, code=1):
    got, out, err = run(capsys, *argv)
    assert got == code, (out, err)
    assert err.startswith("error: ") and err.count("\n") == 1, err
    return err


# ----------------------------------------------------------------------------- params files
HUGE = "9" * 400
PARAMS_CASES = [
    # (file name, content, words the message must hold besides the file's path)
    ("p.json", f'{{"Ra": {HUGE}}}', "parameter 'Ra' is an integer too large for a float (400 digits)"),
    ("p.json", f'{{"Ra": -{"1" * 5000}}}', "parameter 'Ra' is an integer too large for a float (5000 digits)"),
    ("p.toml", f"Ra = {HUGE}\n", "parameter 'Ra' is an integer too large for a float"),
    ("p.json", '{"Ra": 1e400}', "parameter 'Ra' must be finite; got inf"),
    ("p.json", '{"Ra": -Infinity}', "parameter 'Ra' must be finite; got -inf"),
    ("p.json", '{"Ra": NaN}', "parameter 'Ra' must be finite; got nan"),
    ("p.json", '{"Ra": null}', "parameter 'Ra' must be a number; got NoneType None"),
    ("p.json", '{"Ra": "2.0"}', "parameter 'Ra' must be a number; got str '2.0'"),
    ("p.json", '{"Ra": false}', "parameter 'Ra' must be a number; got bool False"),
    ("p.json", '{"Ra": [2.0]}', "parameter 'Ra' must be a number; got list [2.0]"),
    ("p.json", '{"motor": {"Ra": {}, "La": "x"}}', "parameter 'motor.La' must be a number"),
    ("p.toml", 'Ra = 1979-05-27\n', "parameter 'Ra' must be a number; got date"),
    ("p.toml", 'Ra = nan\n', "parameter 'Ra' must be finite"),
    ("p.json", '{"Ra": 1, "Ra": 2}', "the key 'Ra' appears twice in one object"),
    ("p.json", '{"motor": {"Ra": 1, "La": 2, "Ra": 1}}', "the key 'Ra' appears twice in one object"),
    ("p.json", '{"motor.Ra": 1, "motor": {"Ra": 1}}', "parameter 'motor.Ra' is given twice"),
    ("p.toml", 'Ra = 1\nRa = 2\n', "is not valid TOML: Cannot overwrite a value"),
    ("p.json", '{"a":' * 5000 + "1" + "}" * 5000, "is nested too deeply to be read"),
    ("p.toml", "Ra = " + "[" * 5000 + "]" * 5000 + "\n", "is nested too deeply to be read"),
    ("p.json", b'{"Ra": 1.0, "\xff": 2}', "is not UTF-8 text"),
    ("p.json", "", "is not valid JSON"),
    ("p.json", "[]", "must hold a mapping of parameter names to numbers; got a list"),
    ("p.json", "3", "must hold a mapping of parameter names to numbers; got a int"),
]


@pytest.mark.parametrize("name, content, words", PARAMS_CASES,
                         ids=[f"{k}-{c[2][:28]}" for k, c in enumerate(PARAMS_CASES)])
@pytest.mark.parametrize("command", ["export-json", "export-c", "tf"])
def test_bad_params_file(tmp_path, outdir, capsys, name, content, words, command):
    path = tmp_path / name
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content)
    argv = {"export-json": ["export", MOTOR, "-o", outdir / "m.json"],
            "export-c": ["export", MOTOR, "-o", outdir / "m.c"],
            "tf": ["tf", MOTOR, "-u", "V", "-y", "omega", "--numeric"]}[command]
    err = failed(capsys, *argv, "--params", path)
    assert words in err and f"'{path}'" in err
    assert os.listdir(outdir) == []


def test_deep_but_readable_params_need_no_recursion(tmp_path):
    # 900 levels: the JSON parser copes; the flattening must not recurse
    path = tmp_path / "deep.json"
    path.write_text('{"a":' * 900 + "1" + "}" * 900)
    assert load_params(path) == {".".join(["a"] * 900): 1.0}


def test_params_errors_are_package_errors(tmp_path):
    path = tmp_path / "p.json"
    path.write_text('{"Ra": 1, "Ra": 2}')
    with pytest.raises(ParamsFileError) as info:
        load_params(path)
    assert isinstance(info.value, bondgraph.BondGraphError) and isinstance(info.value, ValueError)
    with pytest.raises(ParamsFileError, match="NUL character"):
        load_params("p\0.json")
    with pytest.raises(ParamsFileError, match=f"cannot read params file '{tmp_path}.json'"):
        (tmp_path.parent / f"{tmp_path.name}.json").mkdir()
        load_params(f"{tmp_path}.json")


# ----------------------------------------------------------------------------- model files
EXITING = [
    ("import sys\nsys.exit(0)\n", "called sys.exit(0) while being imported"),
    ("import sys\nsys.exit(2)\n", "called sys.exit(2) while being imported"),
    ("raise SystemExit\n", "called sys.exit(None) while being imported"),
    ("raise SystemExit('bye')\n", "called sys.exit('bye') while being imported"),
    ("import sys\ndef model():\n    sys.exit(0)\n", "called sys.exit(0) in model()"),
    ("class Stop(BaseException):\n    pass\nraise Stop('x')\n", "raised Stop while being imported: x"),
    ("def model():\n    raise GeneratorExit\n", "raised GeneratorExit in model()"),
    ("raise RuntimeError('boom')\n", "raised RuntimeError while being imported: boom"),
    ("def model():\n    return 1 / 0\n", "model() raised ZeroDivisionError: division by zero"),
    ("class E(Exception):\n    def __str__(self):\n        raise ValueError\nraise E()\n",
     "raised E while being imported: <E whose message cannot be shown>"),
    ("def f():\n    return f()\nf()\n", "raised RecursionError while being imported"),
    ("def model(:\n", "has a syntax error at line 1"),
    (b"x = '\xff'\n", "has a syntax error"),
    ("x = 1\n", "defines no function model()"),
    ("model = 3\n", "model is a int, not a function"),
    ("def model(n):\n    return n\n", "model() raised TypeError"),
    ("import bondgraph as bg\ndef model():\n    return bg.BondGraph('g')\n", "model() returned BondGraph"),
    ("from bondgraph.modelfile import ModelDefinition\ndef model():\n    return ModelDefinition('g')\n",
     "model() failed: ModelDefinition.graph must be a bondgraph.BondGraph; got str"),
    ("import bondgraph as bg\nfrom bondgraph.modelfile import ModelDefinition\ndef model():\n"
     "    g = bg.BondGraph('m'); g.add(bg.Se('F'), bg.I('m')); g.connect('F', 'm')\n"
     "    return ModelDefinition(g, {}, {'m': 10 ** 400})\n",
     "default value of parameter 'm' must be a finite real number"),
    ("import bondgraph as bg\nfrom bondgraph.modelfile import ModelDefinition\ndef model():\n"
     "    g = bg.BondGraph('m'); g.add(bg.Se('F'), bg.One('v'), bg.I('m'), bg.R('b', 2 + 1j))\n"
     "    g.connect('F', 'v'); g.connect('v', 'm'); g.connect('v', 'b')\n"
     "    return ModelDefinition(g, {'v': bg.flow('m')}, {'m': 1.0})\n", "complex"),
]


@pytest.mark.parametrize("source, words", EXITING, ids=[w[:30] for _, w in EXITING])
@pytest.mark.parametrize("command", ["equations", "export", "draw"])
def test_model_file_that_exits_or_raises(tmp_path, outdir, capsys, source, words, command):
    path = tmp_path / "bad_model.py"
    if isinstance(source, bytes):
        path.write_bytes(source)
    else:
        path.write_text(source)
    extra = {"export": ["-o", outdir / "m.json"], "draw": ["-o", outdir / "m.svg"]}.get(command, [])
    err = failed(capsys, command, path, *extra)
    assert words in err and f"'{path}'" in err
    assert os.listdir(outdir) == []


@pytest.mark.parametrize("source", ["raise KeyboardInterrupt\n", "def model():\n    raise KeyboardInterrupt\n"])
def test_model_file_interrupted(tmp_path, outdir, capsys, source):
    path = tmp_path / "ctrl_c.py"
    path.write_text(source)
    err = failed(capsys, "export", path, "-o", outdir / "m.json", code=130)
    assert f"model file '{path}' was interrupted" in err
    assert os.listdir(outdir) == []
    with pytest.raises(KeyboardInterrupt, match="was interrupted"):     # the library keeps the interrupt
        load_model(path)


def test_model_file_exit_is_a_model_file_error(tmp_path):
    path = tmp_path / "exits.py"
    path.write_text("import sys\nsys.exit(0)\n")
    with pytest.raises(ModelFileError, match="sys.exit") as info:
        load_model(path)
    assert isinstance(info.value, bondgraph.BondGraphError)
    assert not any(name.startswith("_bondgraph_model_exits") for name in sys.modules)


@pytest.mark.parametrize("make, words", [
    (lambda d: d, "is not a file"),
    (lambda d: "no\0such.py", "NUL character"),
    (lambda d: d / ("x" * 300 + ".py"), "cannot read model file"),
    (lambda d: d / "nothere" / "m.py", "does not exist")], ids=["directory", "nul", "too-long", "missing"])
def test_model_path_kinds(tmp_path, outdir, capsys, make, words):
    model = make(tmp_path)
    err = failed(capsys, "export", model, "-o", outdir / "m.json")
    assert words in err and (repr(str(model)) in err or f"'{model}'" in err)
    assert os.listdir(outdir) == []


# ----------------------------------------------------------------------------- outputs
def test_output_may_not_replace_an_input(tmp_path, capsys):
    model = tmp_path / "motor.py"
    model.write_text(Path(MOTOR).read_text())
    params = tmp_path / "p.json"
    params.write_text('{"Ra": 2.0}')
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    err = failed(capsys, "export", model, "-o", model)
    assert f"output '{model}' is the model file" in err
    err = failed(capsys, "export", model, "--params", params, "-f", "json", "-o", params)
    assert f"output '{params}' is the params file" in err
    err = failed(capsys, "draw", model, "-f", "svg", "-o", model)
    assert "is the model file" in err
    err = failed(capsys, "export", model, "-o", tmp_path / "." / "motor.py")
    assert "is the model file" in err
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before


def test_output_suffix_checked_before_any_work(tmp_path, outdir, capsys, monkeypatch):
    monkeypatch.setattr(cli._common, "_load_definition", lambda path: pytest.fail("the model was loaded"))
    assert f"C output '{outdir / 'm.txt'}' must end in .c" in failed(
        capsys, "export", MOTOR, "-f", "c", "-o", outdir / "m.txt")
    assert "Python output" in failed(capsys, "export", MOTOR, "-f", "py", "-o", outdir / "m.txt")
    assert "MATLAB output" in failed(capsys, "export", MOTOR, "-f", "m", "-o", outdir / "m.py")
    assert "cannot tell the drawing format" in failed(capsys, "draw", MOTOR, "-o", outdir / "m.jpg")
    assert os.listdir(outdir) == []


def fail_on_call(number, real=os.replace):
    """An ``os.replace`` that raises PermissionError on its ``number``-th call."""
    calls = []

    def replace(src, dst, *args, **kwargs):
        calls.append((os.fspath(src), os.fspath(dst)))
        if len(calls) == number:
            raise PermissionError(13, "Permission denied", os.fspath(src), None, os.fspath(dst))
        return real(src, dst, *args, **kwargs)
    return replace, calls


@pytest.mark.parametrize("suffix", ["svg", "png"])
def test_draw_error_names_the_target_not_the_temporary(outdir, capsys, monkeypatch, suffix):
    replace, calls = fail_on_call(1)
    monkeypatch.setattr(os, "replace", replace)
    target = outdir / f"m.{suffix}"
    err = failed(capsys, "draw", MOTOR, "-o", target)
    assert calls and calls[0][1] == str(target)
    assert f"cannot write '{target}': Permission denied" in err and ".tmp" not in err
    assert os.listdir(outdir) == []


def test_draw_to_missing_directory_names_it(tmp_path, capsys):
    target = tmp_path / "nodir" / "m.svg"
    assert f"cannot write '{target}'" in failed(capsys, "draw", MOTOR, "-o", target)
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("old", [True, False], ids=["replacing", "new"])
def test_c_pair_is_all_or_nothing(outdir, capsys, monkeypatch, old):
    if old:
        (outdir / "m.c").write_text("old c")
        (outdir / "m.h").write_text("old h")
    replace, calls = fail_on_call(2)          # the .c is renamed, the .h fails
    monkeypatch.setattr(os, "replace", replace)
    err = failed(capsys, "export", MOTOR, "-o", outdir / "m.c")
    assert f"cannot write '{outdir / 'm.h'}': Permission denied" in err
    assert [Path(dst).name for _, dst in calls[:2]] == ["m.c", "m.h"]
    if old:
        assert (outdir / "m.c").read_text() == "old c" and (outdir / "m.h").read_text() == "old h"
        assert sorted(os.listdir(outdir)) == ["m.c", "m.h"]
    else:
        assert os.listdir(outdir) == []
    monkeypatch.undo()
    assert run(capsys, "export", MOTOR, "-o", outdir / "m.c")[0] == 0       # and it works unpatched
    assert "#include \"m.h\"" in (outdir / "m.c").read_text() and sorted(os.listdir(outdir)) == ["m.c", "m.h"]


def test_atomic_write_many_rolls_back_every_renamed_file(tmp_path, monkeypatch):
    for name in ("a", "b"):
        (tmp_path / name).write_text(f"old {name}")
    replace, _ = fail_on_call(3)
    monkeypatch.setattr(os, "replace", replace)
    items = [(tmp_path / n, lambda fh, n=n: fh.write(f"new {n}")) for n in ("a", "b", "c")]
    with pytest.raises(ExportError, match=f"cannot write '{tmp_path / 'c'}'") as info:
        atomic_write_many(items, binary=False)
    assert info.value.filename == str(tmp_path / "c")
    assert {p.name: p.read_text() for p in tmp_path.iterdir()} == {"a": "old a", "b": "old b"}


def test_atomic_write_many_says_when_the_roll_back_fails(tmp_path, monkeypatch):
    real = os.replace
    calls = []

    def replace(src, dst):                   # first rename works, every later one fails
        calls.append(dst)
        if len(calls) > 1:
            raise OSError(5, "Input/output error")
        return real(src, dst)
    monkeypatch.setattr(os, "replace", replace)
    (tmp_path / "a").write_text("old a")
    items = [(tmp_path / n, lambda fh, n=n: fh.write(f"new {n}")) for n in ("a", "b")]
    with pytest.raises(ExportError, match=f"these files are new: {tmp_path / 'a'}"):
        atomic_write_many(items, binary=False)
    assert sorted(os.listdir(tmp_path)) == ["a"]              # no temporary or backup file


def test_atomic_write_many_interrupted_between_renames(tmp_path, monkeypatch):
    real = os.replace
    calls = []

    def replace(src, dst):
        calls.append(dst)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(src, dst)
    monkeypatch.setattr(os, "replace", replace)
    items = [(tmp_path / n, lambda fh, n=n: fh.write(n)) for n in ("a", "b")]
    with pytest.raises(KeyboardInterrupt):
        atomic_write_many(items, binary=False)
    assert os.listdir(tmp_path) == []


def test_atomic_write_many_refuses_one_target_twice(tmp_path):
    with pytest.raises(ExportError, match="twice"):
        atomic_write_many([(tmp_path / "a", lambda fh: None), (tmp_path / "." / "a", lambda fh: None)])
    assert os.listdir(tmp_path) == []


def test_writer_interrupted_leaves_no_temporary(tmp_path):
    def interrupted(fh):
        fh.write(b"part")
        raise KeyboardInterrupt
    with pytest.raises(KeyboardInterrupt):
        atomic_write_many([(tmp_path / "a", interrupted)])
    assert os.listdir(tmp_path) == []


def test_json_export_refuses_complex_and_non_finite_values(outdir):
    plant = NumericStateSpace([[-1.0]], [[1.0]], [[2.0]], [[0.0]], ("x",), ("u",), ("y",), {"k": 1.0}, "p")
    object.__setattr__(plant, "parameters", {"k": 1 + 2j})      # what a careless caller could build
    with pytest.raises(ExportError, match=r"parameter 'k' must be a number; got complex") as info:
        export_json(plant, outdir / "p.json")
    assert str(outdir / "p.json") in str(info.value)
    inf = NumericStateSpace([[-1.0]], [[np.inf]], [[2.0]], [[0.0]], ("x",), ("u",), ("y",))
    with pytest.raises(ExportError, match=r"B\[0, 0\] is inf"):
        export_json(inf, outdir / "p.json")
    assert os.listdir(outdir) == []


# ----------------------------------------------------------------------------- exit statuses
def test_usage_errors_exit_2(outdir, capsys):
    code, _, err = run(capsys, "export", MOTOR, "-f", "m", "--name", "x", "-o", outdir / "m.m")
    assert code == 2 and "--name only applies to --format c" in err
    code, _, err = run(capsys, "export", MOTOR, "--name", "x", "-o", outdir / "m.json")
    assert code == 2 and "--name only applies to --format c" in err
    code, _, err = run(capsys, "tf", MOTOR, "--params", outdir / "p.json")
    assert code == 2 and "--params is used only with --numeric" in err
    assert os.listdir(outdir) == []


def test_unexpected_exception_is_reported_without_traceback(capsys, monkeypatch):
    def boom(*args, **kwargs):
        raise RuntimeError("something inside broke")
    monkeypatch.setattr(cli._common, "_load_definition", boom)
    err = failed(capsys, "equations", MOTOR)
    assert err == f"error: model file '{MOTOR}': RuntimeError: something inside broke\n"


def test_errors_name_the_model_file_when_nothing_else(capsys):
    err = failed(capsys, "tf", MOTOR, "-u", "V", "-y", "nope")
    assert err.startswith(f"error: model file '{MOTOR}': the model has no output named 'nope'")


def test_broken_pipe_exits_1(capsys, monkeypatch):
    def closed(*args, **kwargs):
        raise BrokenPipeError(32, "Broken pipe")
    monkeypatch.setattr(cli._parser, "cmd_equations", closed)   # build_parser looks it up when called
    assert "standard output was closed" in failed(capsys, "equations", MOTOR)


def test_package_errors_derive_from_bondgraph_error():
    for cls in (CLIError, ParamsFileError, ExportError, ModelFileError):
        assert issubclass(cls, bondgraph.BondGraphError)


def test_module_runs_as_script(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "bondgraph.cli", "export", MOTOR, "--params",
                           str(tmp_path / "p.json"), "-o", str(tmp_path / "m.json")],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1 and proc.stderr.startswith("error: params file ")
    assert "Traceback" not in proc.stderr and os.listdir(tmp_path) == []



def test_roll_back_without_hard_links_uses_a_copy(tmp_path, monkeypatch):
    def no_links(*args, **kwargs):
        raise PermissionError(1, "Operation not permitted")
    monkeypatch.setattr(os, "link", no_links)
    (tmp_path / "a").write_text("old a")
    replace, _ = fail_on_call(2)
    monkeypatch.setattr(os, "replace", replace)
    items = [(tmp_path / n, lambda fh, n=n: fh.write(f"new {n}")) for n in ("a", "b")]
    with pytest.raises(ExportError, match="cannot write .*b'"):
        atomic_write_many(items, binary=False)
    assert {p.name: p.read_text() for p in tmp_path.iterdir()} == {"a": "old a"}
