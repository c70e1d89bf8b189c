"""A bounded fuzz test of the command line (issue 12).

Random argument lists (sub-commands, options, junk tokens, random paths, missing
files, directories given as files, outputs under a file or in a missing or locked
directory), malformed model files (syntax errors, exceptions, ``sys.exit``,
``KeyboardInterrupt``, no ``model``, a ``model`` that is not a function or returns
no definition, random bytes) and params files (random JSON with ``NaN`` and
``Infinity`` literals, deep nesting, huge integers, duplicate keys, non-UTF-8 bytes,
empty files, random TOML) are run through ``main(argv)`` in process, and a few
through the installed console script.  For each run:

* no traceback on stdout or stderr;
* the exit status is 0, 1 (``error: ...`` on stderr), 2 (usage) or 130 (the model
  file raised ``KeyboardInterrupt``); a bad model or params file is never 0;
* on failure the output directory is exactly as before (no partial, temporary or
  backup file, an old output file untouched); on success only the outputs are new;
* a run that must succeed (the DC motor model, good values, a good path) does.

Hypothesis runs a fixed number of examples, derandomized (a fixed seed), with no
example database; the file runs in well under 30 s.
"""

import contextlib
import io
import itertools
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, event, given, settings
from hypothesis import strategies as st

from bondgraph.cli import main

DATA = Path(__file__).resolve().parents[1] / "data"
MOTOR_PARAMS = ["Ra", "La", "K", "J", "b"]
EXAMPLES = 200

BAD_MODELS = {
    "syntax": "def model(:\n",
    "raise": "raise ValueError('bad model')\n",
    "raise_in_model": "def model():\n    raise RuntimeError('no')\n",
    "exit_import": "import sys\nsys.exit({code})\n",
    "exit_model": "import sys\ndef model():\n    sys.exit({code})\n",
    "system_exit": "raise SystemExit\n",
    "keyboard": "raise KeyboardInterrupt\n",
    "base_exception": "class Stop(BaseException):\n    pass\nraise Stop()\n",
    "no_model": "x = 1\n",
    "not_callable": "model = {'a': 1}\n",
    "needs_argument": "def model(n):\n    return n\n",
    "non_definition": "import bondgraph as bg\ndef model():\n    return bg.BondGraph('g')\n",
    "bad_definition": "from bondgraph.modelfile import ModelDefinition\ndef model():\n"
                      "    return ModelDefinition(graph=42)\n",
    "bad_default": (DATA / "dc_motor.py").read_text().replace('"Ra": 2.0', '"Ra": 10 ** 400'),
    "empty": "",
}
GOOD_MODELS = {"motor": DATA / "dc_motor.py", "duffing": DATA / "duffing.py"}
SUFFIXES = [".json", ".mat", ".npz", ".c", ".m", ".py", ".svg", ".png", ".txt", ""]
EXPORT_SUFFIXES = {".json", ".mat", ".npz", ".c", ".m", ".py"}
DRAW_SUFFIXES = {".svg", ".png"}
VALID_OPTIONS = {
    "equations": {"flags": ["--latex"], "formats": []},
    "tf": {"flags": ["--latex", "--numeric", "-u", "-y"], "formats": []},
    "export": {"flags": ["--name"], "formats": ["json", "mat", "npz", "c", "m", "py"]},
    "draw": {"flags": ["--no-causality"], "formats": ["svg", "png"]},
}
ALL_FLAGS = ["--latex", "--numeric", "--no-causality", "-u", "-y", "--name"]
ALL_FORMATS = ["json", "mat", "npz", "c", "m", "py", "svg", "png", "xml"]
JUNK = ["--bogus", "-o", "--params", "", "-", "--", "x", "--format", "-f", "png", "--latex", "tf"]

json_leaf = (st.none() | st.booleans() | st.integers() | st.floats(allow_nan=True, allow_infinity=True)
             | st.text(max_size=4))
json_value = st.recursive(json_leaf, lambda kids: st.lists(kids, max_size=3)
                          | st.dictionaries(st.text(max_size=4), kids, max_size=3), max_leaves=8)
good_values = st.dictionaries(st.sampled_from(MOTOR_PARAMS),
                              st.floats(min_value=0.05, max_value=50.0), max_size=5)
path_text = st.text(st.characters(blacklist_categories=("Cs",), blacklist_characters="/"),
                    min_size=1, max_size=10).filter(lambda s: s not in (".", ".."))

_counter = itertools.count()


@pytest.fixture(scope="module")
def workspace(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz")


def snapshot(root):
    """Every path below ``root``: file contents, ``None`` for directories."""
    out = {}
    for folder, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if d != "__pycache__"]      # Python's, when a model is imported
        for d in dirs:
            out[os.path.relpath(os.path.join(folder, d), root)] = None
        for f in files:
            path = os.path.join(folder, f)
            with open(path, "rb") as fh:
                out[os.path.relpath(path, root)] = fh.read()
    return out


def draw_model(data, folder):
    """(path, kind, good): a model file of a random kind."""
    kind = data.draw(st.sampled_from(["motor"] * 12 + ["duffing"] * 4 + list(BAD_MODELS)
                                     + ["bytes", "missing", "directory", "txt", "nul", "random"]))
    if kind in GOOD_MODELS:
        return str(GOOD_MODELS[kind]), kind, True
    path = folder / "model.py"
    if kind in BAD_MODELS:
        code = data.draw(st.sampled_from(["0", "1", "2", "None", "'bye'", "255", "-1"]))
        path.write_text(BAD_MODELS[kind].replace("{code}", code))
    elif kind == "bytes":
        path.write_bytes(data.draw(st.binary(max_size=40)))
    elif kind == "missing":
        path = folder / "nothere.py"
    elif kind == "directory":
        path = folder / "adir.py"
        path.mkdir()
    elif kind == "txt":
        path = folder / "model.txt"
        path.write_text((DATA / "dc_motor.py").read_text())
    elif kind == "nul":
        return str(folder / "mo\0del.py"), kind, False
    else:
        path = folder / data.draw(path_text)
    return str(path), kind, False


def leaves(value, prefix=""):
    """(dotted name, value) of every non-mapping value, as the params loader flattens them."""
    for key, item in value.items():
        if isinstance(item, dict):
            yield from leaves(item, f"{prefix}{key}.")
        else:
            yield f"{prefix}{key}", item


def is_bad_json_params(value):
    """True when the loader must refuse ``value``: not a mapping, or a leaf that is not a
    finite real number for one of the DC motor's parameters."""
    if not isinstance(value, dict):
        return True
    return any(name not in MOTOR_PARAMS or isinstance(item, bool) or not isinstance(item, (int, float))
               or abs(item) == float("inf") or item != item for name, item in leaves(value))


def draw_params(data, folder):
    """(path, verdict): a params file of a random kind; verdict is good, bad or unknown."""
    kind = data.draw(st.sampled_from(["good", "good", "good_toml", "random_json", "huge_int", "deep",
                                      "duplicate", "bytes", "empty", "missing", "directory", "yaml",
                                      "random_toml", "unknown_name"]))
    path = folder / ("p.toml" if "toml" in kind else "p.json")
    verdict = "bad"
    if kind == "good":
        path.write_text(json.dumps(data.draw(good_values)))
        verdict = "good"
    elif kind == "good_toml":
        path.write_text("".join(f"{k} = {v!r}\n" for k, v in data.draw(good_values).items()))
        verdict = "good"
    elif kind == "random_json":
        value = data.draw(json_value)
        path.write_text(json.dumps(value, allow_nan=True))     # NaN, Infinity literals
        verdict = "bad" if is_bad_json_params(value) else "unknown"     # {} or {"b": 0.0}: may work
    elif kind == "huge_int":
        digits = data.draw(st.integers(min_value=309, max_value=6000))
        path.write_text(f'{{"{data.draw(st.sampled_from(MOTOR_PARAMS))}": {"7" * digits}}}')
    elif kind == "deep":
        depth = data.draw(st.integers(min_value=800, max_value=5000))
        path.write_text('{"Ra":' * depth + "1" + "}" * depth)
    elif kind == "duplicate":
        key = data.draw(st.sampled_from(MOTOR_PARAMS))
        inner = f'"{key}": 1.0, "{key}": 2.0'
        path.write_text(data.draw(st.sampled_from([f"{{{inner}}}", f'{{"motor": {{{inner}}}}}'])))
    elif kind == "bytes":
        path.write_bytes(b'{"Ra": "' + data.draw(st.binary(min_size=1, max_size=8)).replace(b'"', b"") +
                         b'\xff"}')
    elif kind == "empty":
        path.write_text("")
    elif kind == "missing":
        path = folder / "absent.json"
    elif kind == "directory":
        path = folder / "pdir.json"
        path.mkdir()
    elif kind == "yaml":
        path = folder / "p.yaml"
        path.write_text("Ra: 1\n")
    elif kind == "random_toml":
        path.write_text(data.draw(st.text(max_size=30)) + "\nx = 1\n")
    else:
        path.write_text('{"Rx": 1.0}')
    return str(path), verdict


def draw_output(data, outdir, model):
    """(output path, kind, model path): an output of a random kind, the directories it needs made.

    Kind ``model``: the output is the model file itself (a copy in ``outdir``), which must
    be refused; the model path returned is then that copy.
    """
    kind = data.draw(st.sampled_from(["fresh"] * 4 + ["old"] * 2 + ["missing_dir", "file_parent", "is_dir",
                                                                    "locked", "random", "model"]))
    suffix = data.draw(st.sampled_from(SUFFIXES))
    if kind in ("fresh", "old"):
        path = outdir / f"out{suffix}"
        if kind == "old":
            path.write_bytes(b"old")
            if suffix == ".c":
                path.with_suffix(".h").write_bytes(b"old h")
    elif kind == "missing_dir":
        path = outdir / "nodir" / f"out{suffix}"
    elif kind == "file_parent":
        (outdir / "afile").write_text("x")
        path = outdir / "afile" / f"out{suffix}"
    elif kind == "is_dir":
        path = outdir / f"adir{suffix}"
        path.mkdir()
    elif kind == "locked":
        (outdir / "locked").mkdir()
        path = outdir / "locked" / f"out{suffix}"
        (outdir / "locked").chmod(0o500)      # root writes anyway: then it may succeed
    elif kind == "random":
        path = outdir / (data.draw(path_text) + suffix)
    else:
        path = outdir / "model.py"
        if "\0" not in model and os.path.isfile(model):
            shutil.copy(model, path)
        model = str(path)
    return str(path), kind, model


def run_main(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def check(code, out, err, *, must_fail, must_succeed, before, after, argv):
    where = f"argv={argv!r}\nstdout={out!r}\nstderr={err!r}"
    assert "Traceback" not in err and "Traceback" not in out, where
    assert code in (0, 1, 2, 130), where
    if code == 1 or code == 130:
        assert err and err.splitlines()[-1].startswith("error: "), where
    if code == 2:
        assert "usage:" in err or "error:" in err, where
    if must_fail:
        assert code != 0, where
    if must_succeed:
        assert code == 0, where
    if code != 0:
        assert after == before, f"files changed by a failed run\n{where}"
    else:
        new = [p for p in after if p not in before]
        assert not [p for p in new if os.path.basename(p).startswith(".")], f"temporary left\n{where}"


@settings(max_examples=EXAMPLES, derandomize=True, database=None, deadline=None,
          suppress_health_check=list(HealthCheck), phases=(Phase.explicit, Phase.generate, Phase.shrink))
@given(data=st.data())
def test_fuzz_main_in_process(workspace, data):
    case = workspace / f"case{next(_counter)}"
    inputs, outdir = case / "in", case / "out"
    inputs.mkdir(parents=True)
    outdir.mkdir()
    command = data.draw(st.sampled_from(["equations", "tf", "tf", "export", "export", "export", "draw",
                                         "draw", "bogus"]))
    model, model_kind, model_good = draw_model(data, inputs)
    output = out_kind = None
    if command in ("export", "draw"):
        output, out_kind, model = draw_output(data, outdir, model)
    argv = [command, model]
    if output is not None and data.draw(st.integers(0, 19)) > 0:
        argv += ["-o", output]
    params = "none"
    # mostly where --params is an option (export; tf with --numeric); sometimes anywhere
    if data.draw(st.integers(0, 9)) < (6 if command in ("export", "tf") else 1):
        path, params = draw_params(data, inputs)
        argv += ["--params", path]
    valid = VALID_OPTIONS.get(command, VALID_OPTIONS["export"])
    flags = []
    if data.draw(st.integers(0, 2)) == 0:
        pool = valid["flags"] if data.draw(st.integers(0, 7)) else ALL_FLAGS
        flags = data.draw(st.lists(st.sampled_from(pool), min_size=1, max_size=min(2, len(pool)), unique=True))
    if command == "tf" and "--params" in argv and data.draw(st.integers(0, 3)):
        flags = list(dict.fromkeys(flags + ["--numeric"]))
    for flag in flags:
        argv += [flag] if flag in ("--latex", "--numeric", "--no-causality") else \
            [flag, data.draw(st.sampled_from(["V", "omega", "i", "F", "x", "nope", "m", "bad name"]))]
    fmt = None
    if data.draw(st.integers(0, 3)) == 0:
        fmt = data.draw(st.sampled_from(valid["formats"] if valid["formats"] and data.draw(st.integers(0, 7))
                                        else ALL_FORMATS))
        argv += ["--format", fmt]
    junk = data.draw(st.lists(st.sampled_from(JUNK), min_size=1, max_size=2)) \
        if data.draw(st.integers(0, 9)) == 0 else []
    for token in junk:
        argv.insert(data.draw(st.integers(0, len(argv))), token)

    suffix = Path(output).suffix if output else ""
    plain = not junk and fmt is None and not flags
    must_succeed = plain and model_kind == "motor" and out_kind in ("fresh", "old") and "-o" in argv and (
        (command == "export" and suffix in EXPORT_SUFFIXES and params in ("none", "good"))
        or (command == "draw" and suffix in DRAW_SUFFIXES and params == "none"))
    if command == "equations" and model_good and params == "none" and not junk and fmt is None \
            and set(flags) <= {"--latex"}:
        must_succeed = True
    must_fail = not model_good or params == "bad" or out_kind == "model" or command == "bogus"

    before = snapshot(outdir)
    code, out, err = run_main(argv)
    if out_kind == "locked":
        (outdir / "locked").chmod(0o700)
    after = snapshot(outdir)
    check(code, out, err, must_fail=must_fail, must_succeed=must_succeed, before=before, after=after,
          argv=argv)
    event(f"exit {code}")                    # pytest --hypothesis-show-statistics lists them
    event(f"{command}: {'must succeed' if must_succeed else 'must fail' if must_fail else 'either'}")
    if code == 130:                          # only the model file that raises KeyboardInterrupt
        assert model_kind == "keyboard", argv
    if code == 0 and command in ("export", "draw"):
        assert os.path.isfile(output) and os.path.getsize(output) > 0
    shutil.rmtree(case, ignore_errors=True)


SCRIPT_CASES = [
    # (model source or None for the DC motor, params text or None, output name, expected exit status)
    (None, None, "m.json", 0),
    (None, '{"Ra": 1.0, "Ra": ' + "9" * 400 + "}", "m.c", 1),
    ("import sys\nsys.exit(0)\n", None, "m.json", 1),
    ("raise KeyboardInterrupt\n", None, "m.svg", 130),
]


def test_fuzz_console_script(tmp_path):
    """A few cases through a real process: exit status, stderr, files (run two at a time)."""
    script = Path(sys.executable).with_name("bondgraph")
    prefix = [str(script)] if script.exists() else [sys.executable, "-m", "bondgraph.cli"]
    runs = []
    for k, (source, params, name, expected) in enumerate(SCRIPT_CASES):
        case = tmp_path / f"case{k}"
        (case / "out").mkdir(parents=True)
        model = DATA / "dc_motor.py"
        if source is not None:
            model = case / "model.py"
            model.write_text(source)
        command = "draw" if name.endswith(".svg") else "export"
        argv = prefix + [command, str(model), "-o", str(case / "out" / name)]
        if params is not None:
            (case / "p.json").write_text(params)
            argv += ["--params", str(case / "p.json")]
        runs.append((argv, case, name, expected))
    results = []
    for pair in (runs[i:i + 2] for i in range(0, len(runs), 2)):
        procs = [subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                 for argv, *_ in pair]
        results += [(p.communicate(timeout=120), p.returncode) for p in procs]
    for (argv, case, name, expected), ((out, err), code) in zip(runs, results):
        where = f"argv={argv!r}\nstderr={err!r}"
        assert code == expected, where
        assert "Traceback" not in err and "Traceback" not in out, where
        listing = sorted(os.listdir(case / "out"))
        if expected == 0:
            assert listing == [name] and err == "", where
        else:
            assert err.startswith("error: ") and listing == [], where
            assert str(case) in err, where           # names the model or params file
