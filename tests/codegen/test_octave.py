"""Generated MATLAB run in GNU Octave, and exported ``.mat`` files loaded in it.

Each test starts one Octave process (it starts slowly) that evaluates the
generated function at random states, inputs and parameters -- as a vector
and as a struct of parameters -- reads ``info = NAME()``, and prints every
number with 17 significant digits.  The expected values come from the
package's own numeric path (:func:`bondgraph.numeric.compile_dynamics`,
numpy lambdified from the sympy equations), never from generated code, and
must agree to 1e-12 relative.  Models: the DC motor, Duffing oscillator
(pi, dotted names, a name clash) and cos(t) lever of ``test_codegen``, a
pendulum with sin, exp, sqrt, tanh and abs in its laws, the SRV-02 hub and
FLEXCAM (both formulations) from ``models/``.  Where Octave is not installed the tests skip and say so.
"""

import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.cli import main as cli_main
from bondgraph.codegen import write_matlab
from bondgraph.modelfile import load_model
from bondgraph.numeric import compile_dynamics, simulate
sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_codegen import dc_motor, duffing, lever   # linear; nonlinear with pi and dotted names; cos(t)

MODELS_DIR = Path(__file__).resolve().parents[2] / "models"
OCTAVE = shutil.which("octave-cli") or shutil.which("octave")
RTOL = 1e-12


def octave(script, cwd):
    """Run ``script`` in one Octave process in ``cwd``; its stdout (skips where Octave is absent)."""
    if OCTAVE is None:
        pytest.skip("octave not installed: neither octave-cli nor octave is on PATH "
                    "(.ci/run installs it with apt-get)")
    out = subprocess.run([OCTAVE, "--no-gui", "--quiet", "--norc", "--no-history", "--eval", script],
                         cwd=cwd, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, f"octave failed:\n{out.stderr}"
    return out.stdout


def close(got, want, rtol=RTOL):
    got, want = np.asarray(got, float), np.asarray(want, float)
    assert got.shape == want.shape
    np.testing.assert_allclose(got, want, rtol=rtol, atol=rtol * max(1.0, float(np.max(np.abs(want)))))


# ----------------------------------------------------------------------------- models
def pendulum():
    """Torque-driven pendulum: gravity sin(q) and a softened spring, drag |f| f, tanh friction."""
    mgl, k, c, d = (sympy.Symbol(n, positive=True) for n in ("arm.mgl", "spring.k", "drag.c", "drag.d"))
    g = bg.BondGraph("pendulum")
    tau, w = bg.Se("tau"), bg.One("w")
    g.add(tau, w, bg.I("J", "arm.J"),
          bg.C("grav", law=mgl * sympy.sin(bg.q) + k * bg.q * sympy.exp(-bg.q**2)),
          bg.R("drag", law=c * bg.f * abs(bg.f) + d * sympy.tanh(bg.f) * sympy.sqrt(1 + bg.f**2)))
    for tail, head in [(tau, w), (w, "J"), (w, "grav"), (w, "drag")]:
        g.connect(tail, head)
    return bg.derive(g, outputs={"angle": bg.displacement("grav"), "drag_torque": bg.effort("drag")})


def from_file(stem, **options):
    def make():
        if options:
            sys.path.insert(0, str(MODELS_DIR))
            try:
                module = __import__(stem)
            finally:
                sys.path.remove(str(MODELS_DIR))
            defn = module.model(**options)
        else:
            defn = load_model(MODELS_DIR / f"{stem}.py")
        model = defn.derive()
        return model, {p.name: defn.parameters[p.name] for p in model.parameters}
    return make


def no_defaults(build):
    return lambda: (build(), None)


MODELS = {"dc_motor": no_defaults(dc_motor), "duffing": no_defaults(duffing), "lever": no_defaults(lever),
          "pendulum": no_defaults(pendulum), "srv02": from_file("srv02"), "flexcam": from_file("flexcam"),
          "flexcam_system": from_file("flexcam", formulation="system")}


def samples(model, defaults, seed, count=4):
    """Random (t, x, u, p); parameters around the defaults where the model file has them."""
    rng = np.random.default_rng(seed)
    n, m, k = len(model.states), len(model.inputs), len(model.parameters)
    base = np.ones(k) if defaults is None else np.array(list(defaults.values()))
    return [(float(rng.uniform(-3, 3)), rng.uniform(-2, 2, n), rng.uniform(-2, 2, m),
             base * rng.uniform(0.5, 2.0, k)) for _ in range(count)]


def m_vector(values):
    return "[" + "; ".join(repr(float(v)) for v in values) + "]"


def struct_fields(text):
    """The struct fields standing for the parameters, in order, read from the generated file."""
    found = re.search(r"^  p = \[(.*)\];$", text, re.M)
    return [] if found is None else [f.strip()[2:] for f in found.group(1).split(";")]


# ----------------------------------------------------------------------------- generated functions
@pytest.mark.parametrize("case", list(MODELS))
def test_generated_matlab_agrees_with_numeric_rhs_in_octave(case, tmp_path):
    model, defaults = MODELS[case]()
    fname = f"{case}_ode"
    path = write_matlab(model, tmp_path / f"{fname}.m", defaults=defaults)
    fields = struct_fields(path.read_text())
    assert len(fields) == len(model.parameters)
    points = samples(model, defaults, seed=len(case))
    script = [f"info = {fname}();",
              "printf('%s\\n', info.name, info.states{:}, info.inputs{:}, info.outputs{:}, info.parameters{:});",
              "if ~isempty(info.defaults), printf('D %.17g\\n', info.defaults); end"]
    for t, x, u, p in points:
        script += [f"[xd, y] = {fname}({t!r}, {m_vector(x)}, {m_vector(u)}, {m_vector(p)});",
                   "printf('V %.17g\\n', [xd; y]);"]
    t, x, u, p = points[0]      # the same point with the parameters as a struct
    script.append("s = struct();")
    script += [f"s.{f} = {float(v)!r};" for f, v in zip(fields, p)]
    script += [f"[xd, y] = {fname}({t!r}, {m_vector(x)}, {m_vector(u)}, s);", "printf('S %.17g\\n', [xd; y]);"]
    lines = octave("\n".join(script), tmp_path).splitlines()

    dyn = compile_dynamics(model)
    assert dyn.parameter_names == tuple(q.name for q in model.parameters)
    want = np.concatenate([np.concatenate([dyn.derivatives(*pt), dyn.outputs(*pt)]) for pt in points])
    close([float(ln[2:]) for ln in lines if ln.startswith("V ")], want)
    by_struct = [float(ln[2:]) for ln in lines if ln.startswith("S ")]
    assert by_struct == [float(ln[2:]) for ln in lines if ln.startswith("V ")][:len(by_struct)]
    names = [ln for ln in lines if not ln.startswith(("V ", "S ", "D "))]
    assert names == [model.name, *model.state_names, *model.input_names, *model.output_names,
                     *(q.name for q in model.parameters)]
    assert [float(ln[2:]) for ln in lines if ln.startswith("D ")] == list((defaults or {}).values())


def test_generated_matlab_integrates_with_ode45_like_simulate(tmp_path):
    """``ode45(@(t, x) NAME(t, x, u, p), ...)`` as the module docstring promises, against solve_ivp."""
    model = pendulum()
    write_matlab(model, tmp_path / "pend.m")
    values = {"arm.J": 0.5, "arm.mgl": 2.0, "drag.c": 0.3, "drag.d": 0.1, "spring.k": 1.5}
    p = [values[q.name] for q in model.parameters]
    script = ("opts = odeset('RelTol', 1e-10, 'AbsTol', 1e-12);"
              f"[tt, xx] = ode45(@(t, x) pend(t, x, 0.7, {m_vector(p)}), [0 2], [0.4; -0.3], opts);"
              "printf('%.17g\\n', xx(end, :));")
    got = [float(v) for v in octave(script, tmp_path).split()]
    res = simulate(model, values, (0.0, 2.0), x0=[0.4, -0.3], u=[0.7], t_eval=[2.0], rtol=1e-11, atol=1e-13)
    want = [res[name][-1] for name in model.state_names]
    close(got, want, rtol=1e-7)


# ----------------------------------------------------------------------------- exported .mat
def test_exported_mat_loads_in_octave_with_abcd_and_names(tmp_path, capsys):
    out = tmp_path / "flexcam.mat"
    assert cli_main(["export", str(MODELS_DIR / "flexcam.py"), "-o", str(out)]) == 0
    capsys.readouterr()
    plant = load_model(MODELS_DIR / "flexcam.py").plant()
    script = ("S = load('flexcam.mat');"
              "for v = {'A', 'B', 'C', 'D'}, M = S.(v{1}); printf('%s %d %d\\n', v{1}, rows(M), columns(M));"
              " printf('%.17g\\n', M.'); end;"
              "for v = {'state_names', 'input_names', 'output_names', 'parameter_names'}, c = S.(v{1});"
              " printf('%s %d\\n', v{1}, numel(c)); printf('%s\\n', c{:}); end;"
              "printf('model_name %s\\n', S.model_name);"
              "printf('%.17g\\n', S.parameter_values);")
    lines = octave(script, tmp_path).splitlines()
    pos = 0
    for label, M in (("A", plant.A), ("B", plant.B), ("C", plant.C), ("D", plant.D)):
        assert lines[pos] == f"{label} {M.shape[0]} {M.shape[1]}"
        got = np.array([float(v) for v in lines[pos + 1:pos + 1 + M.size]]).reshape(M.shape)
        assert np.array_equal(got, M)           # doubles written and read back exactly
        pos += 1 + M.size
    for label, names in (("state_names", plant.state_names), ("input_names", plant.input_names),
                         ("output_names", plant.output_names), ("parameter_names", list(plant.parameters))):
        assert lines[pos] == f"{label} {len(names)}"
        assert lines[pos + 1:pos + 1 + len(names)] == list(names)
        pos += 1 + len(names)
    assert lines[pos] == f"model_name {plant.name}"
    assert [float(v) for v in lines[pos + 1:]] == list(plant.parameters.values())
