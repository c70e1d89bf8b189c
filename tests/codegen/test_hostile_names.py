"""Hostile names through the code generators: no name runs, every generated file builds and agrees.

Every name of :func:`corpus` (quotes, comment markers, triple quotes,
backslashes, newlines, ``%``, braces, non-ASCII letters, an emoji, bidi
marks, keywords of C, Python and MATLAB, identifiers the generated code uses
itself, 300 characters, trigraphs) is the name of a parameter Symbol of one
small model: a mass, a cubic spring and one resistor per name, weighted
``(k + 1) / n`` so that a name read in the wrong place changes the numbers.
The names the element and graph checks accept are element and graph names
too; the others must be refused with a ``BondGraphError`` naming them.  The
model's own name is a payload as well (a ``Model`` is a plain dataclass, so
codegen must not trust it).

The payloads try to create ``<tmp>/INJECTED``: C through a constructor
function, Python through ``open`` / ``__import__``, MATLAB through
``fclose(fopen(...))``.  The C must compile with ``-std=c99 -Wall -Wextra
-Werror`` and a driver must agree with the model's sympy equations; the
Python must import and agree; the MATLAB must run in Octave and agree; the
name tables must hold the names byte for byte; the marker must not exist.
The same goes through ``bondgraph export``.
"""

import ast
import dataclasses
import importlib.util
import inspect
import shutil
import subprocess
import textwrap

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.cli import main as cli_main
from bondgraph.codegen import (CodegenError, generate_c, generate_matlab, generate_python, write_c,
                               write_matlab, write_python)
from bondgraph.codegen._common import shown
from bondgraph.codegen.c import c_comment, c_string
from bondgraph.codegen.matlab import m_comment, m_string
from bondgraph.codegen.python import py_docstring
from bondgraph.signals import t as T

CC = shutil.which("cc") or shutil.which("gcc")
OCTAVE = shutil.which("octave-cli") or shutil.which("octave")
CFLAGS = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"]
RTOL = 1e-12


def corpus(marker):
    """Hostile names; the payloads among them try to create the file ``marker``."""
    m = str(marker)
    return [
        # quotes and string / comment delimiters of the three languages
        "it's", 'say "hi"', "a'b\"c", '""', "''", "/*", "*/", "//", "a*/b/*c",
        f'*/\n#include <stdlib.h>\n__attribute__((constructor)) static void inj(void) '
        f'{{ system("touch {m}"); }}\n/*',
        f'"}}; __attribute__((constructor)) static void inj2(void) {{ system("touch {m}"); }} '
        f'static const char *z[] = {{"',
        f'"""\nopen({m!r}, "w").close()\n"""',
        f"'''\n__import__('os').system('touch {m}')\n'''",
        f"'), open({m!r}, 'w'), ('",
        f"\nfclose(fopen('{m}', 'w'));\n%",
        f"'); fclose(fopen('{m}', 'w')); x = ('",
        # backslashes, escapes and control characters
        "back\\slash", "trailing\\", "\\n literally", "\\x41\\101\\", "new\nline", "carriage\rreturn",
        "crlf\r\n", "tab\tbed", "bell\a", "\x1b[31mred",
        # format strings, braces, MATLAB block comments and continuations
        "%d %s %%", "{}", "{0}", "%{", "%}", "...", "a...b", "", " ", "1st",
        # non-ASCII: accents, Greek, emoji, bidi marks, combining accent
        "é", "Ωμέγα", "😀", "\u200f", "\u202e", "e\u0301",
        # keywords and identifiers of the generated code itself
        "int", "return", "lambda", "end", "function", "def", "class", "NULL", "xdot", "NAME", "math",
        "M_PI", "HOSTILE_NX", "PLANT_NP", "__LINE__", "_Bool", "_", "tmp0", "nargin", "zeros",
        "native2unicode", "p", "y",
        # long, and trigraphs (C99 turns ??/ into a backslash, even in comments)
        "L" * 300, "é" * 150, "??/", "??=", "??'", "a??/", '"??/"',
    ]


def hostile_graph(names, graph_name="hostile", element_names=()):
    """Mass ``m``, cubic spring, one resistor per name in ``names`` on one 1-junction.

    Resistor ``k`` has resistance ``(k + 1)/n * Symbol(names[k])``; its element
    name is the k-th of ``element_names`` if given, else ``r<k>``.
    """
    g = bg.BondGraph(graph_name)
    F, v = bg.Se("double"), bg.One("switch")
    k1, k3 = sympy.Symbol("k", positive=True), sympy.Symbol(names[0], positive=True)
    g.add(F, v, bg.I("endfunction", "m"), bg.C("endwhile", law=k1 * bg.q + k3 * bg.q**3))
    g.connect(F, v)
    g.connect(v, "endfunction")
    g.connect(v, "endwhile")
    for k, name in enumerate(names):
        ename = element_names[k] if k < len(element_names) else f"r{k}"
        g.add(bg.R(ename, sympy.Rational(k + 1, len(names)) * sympy.Symbol(name, positive=True)))
        g.connect(v, ename)
    return g


OUTPUTS = {"é": bg.flow("endfunction"), "lambda": bg.effort("endwhile"), "Ωmega": bg.effort("r0")}


def accepted_element_names(names):
    """The names bg.R accepts; every other one must be refused naming it."""
    ok = []
    for name in names:
        try:
            bg.R(name)
        except bg.BondGraphError as exc:
            assert repr(name) in str(exc), (name, str(exc))
        else:
            ok.append(name)
    return ok


def build(marker):
    """The hostile model, its model name a payload (C comment, Python docstring, MATLAB line)."""
    names = corpus(marker)
    elements = [n if n in accepted_element_names(names) else f"r{k}" for k, n in enumerate(names)]
    elements[0] = "r0"      # the output Omega reads R:r0
    model = bg.derive(hostile_graph(names, element_names=elements), outputs=OUTPUTS)
    hostile_name = "\n".join(names[9:16])
    return dataclasses.replace(model, name=hostile_name), names


def samples(model, count=3, seed=1):
    rng = np.random.default_rng(seed)
    n, m, k = len(model.states), len(model.inputs), len(model.parameters)
    return [(float(rng.uniform(-2, 2)), rng.uniform(-1, 1, n), rng.uniform(-1, 1, m), rng.uniform(0.5, 2, k))
            for _ in range(count)]


def reference(model, t, x, u, p):
    """``x'`` and ``y`` from the model's sympy equations, substituted and evaluated to 30 digits."""
    subs = {T: t, **dict(zip(model.states, x)), **dict(zip(model.inputs, u)),
            **dict(zip(model.parameters, p))}
    subs = {s: sympy.Float(float(v), 30) for s, v in subs.items()}
    ev = [float(ex.xreplace(subs).evalf(30)) for ex in model.rhs + model.output_exprs]
    n = len(model.states)
    return np.array(ev[:n]), np.array(ev[n:])


def close(got, want):
    np.testing.assert_allclose(got, want, rtol=RTOL, atol=RTOL * max(1.0, float(np.max(np.abs(want)))))


def expected_numbers(model, points):
    return np.concatenate([np.concatenate(reference(model, *pt)) for pt in points])


# ----------------------------------------------------------------------------- names refused
@pytest.mark.parametrize("name", ["m\n", "g\n", "a*/b", "it's", "return", "lambda", "é", "", "a.b", "1st",
                                  "x\r", "\u200f"])
def test_graph_and_element_checks_refuse_naming_the_name(name):
    for make in (bg.BondGraph, bg.I, bg.R, bg.Se):
        with pytest.raises(bg.BondGraphError) as info:
            make(name)
        assert repr(name) in str(info.value)


def test_unwritable_names_are_refused_naming_them():
    for bad in ("nul\x00byte", "lone\ud800surrogate"):
        model = bg.derive(hostile_graph(["ok", bad]), outputs=OUTPUTS)
        for gen in (generate_c, generate_python, generate_matlab):
            with pytest.raises(CodegenError) as info:
                gen(model)
            assert repr(bad) in str(info.value) and "parameter name" in str(info.value)
    model = bg.derive(hostile_graph(["ok"]), outputs=OUTPUTS)
    with pytest.raises(CodegenError, match="model name"):
        generate_python(dataclasses.replace(model, name="a\x00"))


@pytest.mark.parametrize("prefix", ["abc\n", "a*/b", "é", "int", "_Abc", "__x", "", "a b"])
def test_c_prefix_and_matlab_function_name_match_whole(prefix):
    model = bg.derive(hostile_graph(["ok"]), outputs=OUTPUTS)
    with pytest.raises(CodegenError) as info:
        generate_c(model, name=prefix)
    assert repr(prefix) in str(info.value)
    if prefix not in ("int", "_Abc", "__x"):      # MATLAB allows these three, C does not
        with pytest.raises(CodegenError) as info:
            generate_matlab(model, name=prefix)
        assert repr(prefix) in str(info.value)
    for header in ('a".h', "a\n.h", "x*/.h", "dir/a.h", "??/.h"):
        with pytest.raises(CodegenError, match="header file name"):
            generate_c(model, name="plant", header_file=header)


def test_accepted_graph_names_reach_every_generator(tmp_path):
    names = corpus(tmp_path / "INJECTED")
    for name in names:
        try:
            g = hostile_graph(["ok"], graph_name=name)
        except bg.BondGraphError as exc:
            assert repr(name) in str(exc)
            continue
        model = bg.derive(g, outputs=OUTPUTS)
        ns = {}
        exec(generate_python(model), ns)
        assert ns["NAME"] == name
        for gen in (generate_c, generate_matlab):
            try:
                gen(model)
            except CodegenError as exc:       # a reserved word of that language, named
                assert repr(name) in str(exc) and "reserved word" in str(exc)


# ----------------------------------------------------------------------------- escapes, on random text
ALPHABET = ['"', "'", "\\", "*", "/", "?", "%", "{", "}", ".", "a", "Z", "_", "0", " ", "\n", "\r", "\t",
            "\x1b", "\x7f", "\xe9", "\u03a9", "\u200f", "\U0001f600"]


def random_texts(count=3000, seed=5):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        yield "".join(rng.choice(ALPHABET, size=int(rng.integers(0, 10))))


def test_escapes_hold_for_random_text():
    for text in random_texts():
        for view in (c_comment(text), m_comment(text), shown(text)):
            assert view.isascii() and view.isprintable(), (text, view)     # one line, no control
        assert not any(bad in c_comment(text) for bad in ("*/", "/*", "??")), text
        literal = c_string(text)
        assert literal.isascii() and literal.isprintable() and "??" not in literal
        lines = text.split("\n")
        doc = py_docstring(lines)
        assert doc.isascii() and len(ast.parse(doc).body) == 1 and ast.literal_eval(doc) == text


# ----------------------------------------------------------------------------- C
C_DRIVER = r"""
#include <stdio.h>
#include "plant.h"

static const double T[] = {%(t)s};
static const double X[][PLANT_NX] = {%(x)s};
static const double U[][PLANT_NU] = {%(u)s};
static const double P[][PLANT_NP] = {%(p)s};

static void names(const char *const *list)
{
    int i;
    for (i = 0; list[i] != NULL; ++i) {
        const unsigned char *c = (const unsigned char *)list[i];
        printf("N:");
        while (*c) printf("%%02x", *c++);
        printf("\n");
    }
}

int main(void)
{
    double xdot[PLANT_NX], y[PLANT_NY];
    int s, i;
    for (s = 0; s < (int)(sizeof T / sizeof T[0]); ++s) {
        plant_derivatives(T[s], X[s], U[s], P[s], xdot);
        plant_outputs(T[s], X[s], U[s], P[s], y);
        for (i = 0; i < PLANT_NX; ++i) printf("%%.17g\n", xdot[i]);
        for (i = 0; i < PLANT_NY; ++i) printf("%%.17g\n", y[i]);
    }
    names(plant_state_names);
    names(plant_input_names);
    names(plant_output_names);
    names(plant_parameter_names);
    for (i = 0; i < PLANT_NP; ++i) printf("D:%%.17g\n", plant_default_parameters[i]);
    return 0;
}
"""


def c_array(rows):
    return ", ".join("{" + ", ".join(repr(float(v)) for v in row) + "}" for row in rows)


def run_c(model, src, tmp_path, points):
    """Compile ``src`` (and its header) and a driver; the driver's numbers, names and defaults."""
    subprocess.run([CC, *CFLAGS, "-c", "-o", str(tmp_path / "plant.o"), str(src)], check=True,
                   capture_output=True, text=True, cwd=tmp_path)
    driver = tmp_path / "driver.c"
    driver.write_text(C_DRIVER % {"t": ", ".join(repr(pt[0]) for pt in points),
                                  "x": c_array(pt[1] for pt in points), "u": c_array(pt[2] for pt in points),
                                  "p": c_array(pt[3] for pt in points)})
    exe = tmp_path / "driver"
    subprocess.run([CC, *CFLAGS, "-o", str(exe), str(driver), str(tmp_path / "plant.o"), "-lm"], check=True,
                   capture_output=True, text=True, cwd=tmp_path)
    lines = subprocess.run([str(exe)], check=True, capture_output=True, text=True, cwd=tmp_path).stdout.splitlines()
    numbers = np.array([float(ln) for ln in lines if not ln.startswith(("N:", "D:"))])
    names = [bytes.fromhex(ln[2:]).decode("utf-8") for ln in lines if ln.startswith("N:")]
    defaults = [float(ln[2:]) for ln in lines if ln.startswith("D:")]
    return numbers, names, defaults


@pytest.mark.skipif(CC is None, reason="no C compiler (cc) on PATH")
def test_c_string_round_trips_random_text_through_the_compiler(tmp_path):
    texts = list(random_texts(count=500, seed=6))
    src = tmp_path / "strings.c"
    src.write_text("#include <stdio.h>\n"
                   "/* " + " ".join(c_comment(t) for t in texts) + " */\n"
                   "static const char *const S[] = {" + ", ".join(c_string(t) for t in texts) + ", NULL};\n"
                   "int main(void)\n{\n    int i;\n    for (i = 0; S[i] != NULL; ++i) {\n"
                   "        const unsigned char *c = (const unsigned char *)S[i];\n"
                   "        printf(\"N:\");\n        while (*c) printf(\"%02x\", *c++);\n"
                   "        printf(\"\\n\");\n    }\n    return 0;\n}\n", encoding="ascii")
    exe = tmp_path / "strings"
    subprocess.run([CC, *CFLAGS, "-o", str(exe), str(src)], check=True, capture_output=True, text=True)
    out = subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout.splitlines()
    assert [bytes.fromhex(line[2:]).decode("utf-8") for line in out] == texts


def all_names(model):
    return list(model.state_names + model.input_names + model.output_names) + [p.name for p in model.parameters]


@pytest.mark.skipif(CC is None, reason="no C compiler (cc) on PATH")
def test_c_compiles_agrees_and_runs_no_payload(tmp_path):
    marker = tmp_path / "INJECTED"
    model, names = build(marker)
    assert sorted(p.name for p in model.parameters) == sorted(set(names) | {"k", "m"})   # each one once
    defaults = {p.name: 1.0 + k / 8 for k, p in enumerate(model.parameters)}
    src, hdr = write_c(model, tmp_path / "plant.c", name="plant", defaults=defaults)
    for text in (src.read_text(encoding="ascii"), hdr.read_text(encoding="ascii")):
        assert "??" not in text and "\r" not in text        # no trigraph, one kind of line end
    points = samples(model)
    numbers, got_names, got_defaults = run_c(model, src, tmp_path, points)
    close(numbers, expected_numbers(model, points))
    assert got_names == all_names(model)
    assert got_defaults == list(defaults.values())
    assert not marker.exists()


# ----------------------------------------------------------------------------- Python
def import_file(path, name):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def check_python_module(path, model, marker, defaults=None):
    text = path.read_text(encoding="ascii")
    top = ast.parse(text).body
    kinds = [type(node).__name__ for node in top]
    assert kinds == ["Expr", "Import"] + ["Assign"] * 6 + ["FunctionDef"] * 3, kinds
    mod = import_file(path, f"hostile_{path.stem}")
    assert not marker.exists()
    assert mod.NAME == model.name
    assert (mod.STATE_NAMES, mod.INPUT_NAMES, mod.OUTPUT_NAMES) == (
        model.state_names, model.input_names, model.output_names)
    assert mod.PARAMETER_NAMES == tuple(p.name for p in model.parameters)
    assert mod.DEFAULT_PARAMETERS == defaults
    for pt in samples(model, seed=2):
        t, x, u, p = pt
        xdot, y = reference(model, *pt)
        close(mod.derivatives(t, list(x), list(u), list(p)), xdot)
        close(mod.outputs(t, list(x), list(u), dict(zip(mod.PARAMETER_NAMES, p))), y)
    assert not marker.exists()
    return mod


def test_python_imports_agrees_and_runs_no_payload(tmp_path):
    marker = tmp_path / "INJECTED"
    model, names = build(marker)
    defaults = {p.name: 1.0 + k / 8 for k, p in enumerate(model.parameters)}
    path = write_python(model, tmp_path / "plant.py", defaults=defaults)
    mod = check_python_module(path, model, marker, defaults)
    doc = mod.__doc__.splitlines()         # one printable line per name, each name shown escaped
    assert all(ch.isascii() and ch.isprintable() for line in doc for ch in line)
    rows = [line for line in doc if line.startswith("    p[")]
    assert len(rows) == len(model.parameters)
    for k, (row, par) in enumerate(zip(rows, model.parameters)):
        assert row.startswith(f"    p[{k}]  {shown(par.name)}")


# ----------------------------------------------------------------------------- MATLAB / Octave
def octave(script, cwd):
    """Run ``script`` in one Octave process; its stdout."""
    if OCTAVE is None:
        pytest.skip("octave not installed: neither octave-cli nor octave is on PATH")
    out = subprocess.run([OCTAVE, "--no-gui", "--quiet", "--norc", "--no-history", "--eval", script],
                         cwd=cwd, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    return out.stdout


def m_vector(values):
    return "[" + "; ".join(repr(float(v)) for v in values) + "]"


def octave_eval_script(fname, points):
    lines = [f"info = {fname}();",
             "fields = {'states', 'inputs', 'outputs', 'parameters'};",
             "for f = 1:numel(fields)",
             "  c = info.(fields{f});",
             "  for i = 1:numel(c), printf('N:%s\\n', sprintf('%02x', double(c{i}))); end",
             "end",
             "printf('M:%s\\n', sprintf('%02x', double(info.name)));",
             "printf('D:%.17g\\n', info.defaults);"]
    for t, x, u, p in points:
        lines.append(f"[xd, y] = {fname}({t!r}, {m_vector(x)}, {m_vector(u)}, {m_vector(p)});")
        lines.append("printf('%.17g\\n', [xd; y]);")
    return "\n".join(lines)


def parse_octave(stdout):
    lines = stdout.splitlines()
    numbers = np.array([float(ln) for ln in lines if ln[:2] not in ("N:", "M:", "D:")])
    names = [bytes.fromhex(ln[2:]).decode("utf-8") for ln in lines if ln.startswith("N:")]
    model_name = [bytes.fromhex(ln[2:]).decode("utf-8") for ln in lines if ln.startswith("M:")]
    defaults = [float(ln[2:]) for ln in lines if ln.startswith("D:")]
    return numbers, names, model_name[0], defaults


def check_matlab_run(path, model, marker, defaults, tmp_path):
    text = path.read_text(encoding="ascii")
    assert "\r" not in text
    points = samples(model, seed=3)
    numbers, names, model_name, got_defaults = parse_octave(octave(octave_eval_script(path.stem, points),
                                                                   tmp_path))
    close(numbers, expected_numbers(model, points))
    assert names == all_names(model) and model_name == model.name
    assert got_defaults == list(defaults.values())
    assert not marker.exists()


def test_m_string_round_trips_random_text_in_octave(tmp_path):
    texts = list(random_texts(count=300, seed=7))
    script = ("c = {" + ", ...\n".join(m_string(t) for t in texts) + "};\n"
              "for i = 1:numel(c), printf('N:%s\\n', sprintf('%02x', double(c{i}))); end")
    out = octave(script, tmp_path).splitlines()
    assert [bytes.fromhex(line[2:]).decode("utf-8") for line in out] == texts


def test_matlab_runs_in_octave_agrees_and_runs_no_payload(tmp_path):
    marker = tmp_path / "INJECTED"
    model, names = build(marker)
    defaults = {p.name: 1.0 + k / 8 for k, p in enumerate(model.parameters)}
    path = write_matlab(model, tmp_path / "plant.m", defaults=defaults)
    lines = path.read_text(encoding="ascii").splitlines()
    help_end = next(i for i, ln in enumerate(lines) if not ln.startswith("%") and i > 0)
    assert lines[help_end] == "if nargin == 0"        # no name broke out of the help text
    check_matlab_run(path, model, marker, defaults, tmp_path)


# ----------------------------------------------------------------------------- bondgraph export
MODEL_FILE = '''\
"""Hostile names for bondgraph export (written by tests/codegen/test_hostile_names.py)."""
import sympy
import bondgraph as bg
from bondgraph.modelfile import ModelDefinition

NAMES = {names}
OUTPUTS = {{"\\xe9": bg.flow("endfunction"), "lambda": bg.effort("endwhile"),
           "\\u03a9mega": bg.effort("r0")}}


{source}

def model():
    g = hostile_graph(NAMES)
    values = {{name: 1.0 + k / 8 for k, name in enumerate(sorted(set(NAMES) | {{"k", "m"}}))}}
    return ModelDefinition(graph=g, outputs=OUTPUTS, parameters=values)
'''


def write_model_file(tmp_path, marker):
    names = corpus(marker)
    path = tmp_path / "hostile_model.py"
    path.write_text(MODEL_FILE.format(names=ascii(names), source=textwrap.dedent(inspect.getsource(hostile_graph))),
                    encoding="ascii")
    model = bg.derive(hostile_graph(names), outputs=OUTPUTS)
    defaults = {p.name: 1.0 + k / 8 for k, p in enumerate(model.parameters)}
    return path, model, defaults


def test_cli_export_of_hostile_names(tmp_path, capsys):
    marker = tmp_path / "INJECTED"
    path, model, defaults = write_model_file(tmp_path, marker)
    assert cli_main(["export", str(path), "-o", str(tmp_path / "plant.py")]) == 0
    check_python_module(tmp_path / "plant.py", model, marker, defaults)
    assert cli_main(["export", str(path), "-o", str(tmp_path / "plant.c"), "--name", "plant"]) == 0
    if CC is not None:
        points = samples(model)
        numbers, names, got_defaults = run_c(model, tmp_path / "plant.c", tmp_path, points)
        close(numbers, expected_numbers(model, points))
        assert names == all_names(model) and got_defaults == list(defaults.values())
    assert cli_main(["export", str(path), "-o", str(tmp_path / "plant.m")]) == 0
    capsys.readouterr()
    for bad in ("abc\n", "a*/b", "int"):
        assert cli_main(["export", str(path), "-o", str(tmp_path / "bad.c"), "--name", bad]) == 1
        assert repr(bad) in capsys.readouterr().err
    assert not (tmp_path / "bad.c").exists() and not (tmp_path / "bad.h").exists()
    assert not marker.exists()
    if OCTAVE is not None:
        check_matlab_run(tmp_path / "plant.m", model, marker, defaults, tmp_path)
