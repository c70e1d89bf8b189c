"""Issue 16, items 3-4: parameter sweeps, Sobol indices, the ``sweep`` command, the extra.

Hand derivations.  The mass-spring-damper ``m x'' + b x' + k x = F`` has
poles ``s^2 + (b/m) s + k/m = 0``: natural frequency ``wn = sqrt(k/m)`` and
damping ratio ``zeta = b / (2 sqrt(m k))`` (both poles, when ``zeta < 1``);
``x/F`` has DC gain ``1/k``.  For ``Y = a X1 + c X2`` with independent
``X1, X2`` uniform on one interval, ``Var Y = (a^2 + c^2) Var X`` and the
first-order (= total) Sobol indices are ``a^2/(a^2 + c^2)`` and
``c^2/(a^2 + c^2)``.
"""

from __future__ import annotations

import math
import subprocess
import sys
from concurrent.futures import ProcessPoolExecutor

import control
import numpy as np
import pytest
import scipy.stats

import bondgraph as bg
from bondgraph.cli import main
from bondgraph.study import (MissingDependencyError, StudyError, StudyWarning, design_points,
                             parameter_specs, sensitivity, sweep)
from bondgraph.study import metrics as M

pd = pytest.importorskip("pandas")

MSD = {"m": 1.0, "b": 0.4, "k": 4.0}
RANGES = {"b": (0.1, 1.0), "k": (1.0, 9.0)}


def msd():
    g = bg.BondGraph("msd")
    F, v = bg.Se("F"), bg.One("v")
    g.add(F, v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
    for tail, head in [(F, v), (v, "m"), (v, "b"), (v, "k")]:
        g.connect(tail, head)
    return bg.derive(g, outputs={"x": bg.displacement("k"), "v": bg.flow("m")})


@pytest.fixture(scope="module")
def plant_model():
    return bg.compile_plant(msd())


def quiet_sweep(*args, **kwargs):
    kwargs.setdefault("progress", False)
    return sweep(*args, **kwargs)


# ------------------------------------------------------------------ designs
@pytest.mark.parametrize("design", ["sobol", "lhs", "halton", "random", "grid"])
def test_design_samples_lie_inside_the_bounds(design):
    specs = parameter_specs({"a": (-2.0, 3.0), "b": (1e-3, 1e-2), "c": [5.0, 7.0, 11.0]})
    X, name = design_points(specs, design, 200, seed=4)
    assert name == design and X.shape[1] == 3
    assert ((X[:, 0] >= -2.0) & (X[:, 0] <= 3.0)).all()
    assert ((X[:, 1] >= 1e-3) & (X[:, 1] <= 1e-2)).all()
    assert set(X[:, 2].tolist()) <= {5.0, 7.0, 11.0}
    if design == "grid":              # 3 values x k^2 <= 200: k = 8, endpoints included
        assert X.shape[0] == 3 * 8 * 8 and X[:, 0].min() == -2.0 and X[:, 0].max() == 3.0
    else:
        assert X.shape[0] == 200 and np.unique(X[:, 0]).size == 200
        assert len(set(X[:, 2].tolist())) == 3


def test_distributions_arrays_and_seeds():
    specs = parameter_specs({"k": scipy.stats.norm(10.0, 0.5), "b": (0.0, 1.0)})
    X1, _ = design_points(specs, "sobol", 256, seed=7)
    X2, _ = design_points(specs, "sobol", 256, seed=7)
    X3, _ = design_points(specs, "sobol", 256, seed=8)
    assert np.array_equal(X1, X2) and not np.array_equal(X1, X3)
    assert abs(X1[:, 0].mean() - 10.0) < 0.05 and abs(X1[:, 0].std() - 0.5) < 0.05
    unit = np.array([[0.0, 0.25], [0.5, 1.0]])
    X, name = design_points(parameter_specs({"m": (1.0, 3.0), "k": [1.0, 2.0]}), unit, None, seed=0)
    assert name == "array" and X.tolist() == [[1.0, 1.0], [2.0, 2.0]]


@pytest.mark.parametrize("parameters, message", [
    ({"b": (1.0, 2.0, 3.0)}, "tuple .lo, hi. of two numbers"),
    ({"b": (2.0, 1.0)}, "lo < hi"),
    ({"b": (0.0, float("nan"))}, "finite"),
    ({"b": "0..1"}, "bounds .lo, hi. as a tuple"),
    ({"b": []}, "non-empty"),
    ({}, "at least one"),
])
def test_bad_ranges_are_refused_naming_the_parameter(parameters, message):
    with pytest.raises(StudyError, match=message):
        parameter_specs(parameters)


def test_bad_designs_are_refused():
    specs = parameter_specs(RANGES)
    with pytest.raises(StudyError, match="did you mean 'sobol'"):
        design_points(specs, "sobel", 8, seed=0)
    with pytest.raises(StudyError, match="unit hypercube"):
        design_points(specs, np.array([[0.5, 1.5]]), None, seed=0)
    with pytest.raises(StudyError, match="shape"):
        design_points(specs, np.zeros((4, 3)), None, seed=0)
    with pytest.raises(StudyError, match="positive integer"):
        design_points(specs, "lhs", 0, seed=0)


# ------------------------------------------------------------------ metrics against hand derivations
def test_min_damping_is_the_hand_derived_ratio(plant_model):
    """zeta = b/(2 sqrt(m k)); here every sample is underdamped (b <= 1, m k >= 1)."""
    df = quiet_sweep(plant_model, {"b": (0.1, 1.0), "k": (1.0, 9.0), "m": [1.0, 2.0]},
                     ["min_damping", "max_real", "dc_gain"], output="x", n=16, seed=3)
    m, b, k = df["m"].to_numpy(), df["b"].to_numpy(), df["k"].to_numpy()
    assert np.allclose(df["min_damping"], b / (2 * np.sqrt(m * k)), rtol=1e-12)
    assert np.allclose(df["max_real"], -b / (2 * m), rtol=1e-12)        # Re p = -b/(2m)
    assert np.allclose(df["dc_gain"], 1 / k, rtol=1e-12)
    assert df["error"].isna().all() and df.attrs["failed"] == 0


def test_channel_metrics_agree_with_python_control(plant_model):
    values = [{"m": 1.0, "b": 0.2, "k": 4.0}, {"m": 2.0, "b": 1.5, "k": 1.0},
              {"m": 0.5, "b": 0.05, "k": 30.0}]
    metrics = M.resolve_metrics(["peak_gain", "bandwidth", "step"], ("F",), ("x", "v"), output="x")
    for v in values:
        ss = plant_model.plant(v)
        sys_x = control.ss(ss.A, ss.B, ss.C[[0]], ss.D[[0]])
        peak, w_peak, bw, over, settle = [x for m in metrics for x in m.plant(ss)]
        zeta, wn = v["b"] / (2 * math.sqrt(v["m"] * v["k"])), math.sqrt(v["k"] / v["m"])
        if zeta < 1 / math.sqrt(2):      # resonance peak 1/(k 2 zeta sqrt(1 - zeta^2)) at wn sqrt(1 - 2 zeta^2)
            assert peak == pytest.approx(1 / (v["k"] * 2 * zeta * math.sqrt(1 - zeta**2)), rel=1e-9)
            assert w_peak == pytest.approx(wn * math.sqrt(1 - 2 * zeta**2), rel=1e-5)
        else:                            # no resonance: the peak is the DC gain at w = 0
            assert (peak, w_peak) == (pytest.approx(1 / v["k"], rel=1e-12), 0.0)
        assert bw == pytest.approx(control.bandwidth(sys_x), rel=1e-9)
        info = control.step_info(sys_x)
        assert (over, settle) == (pytest.approx(info["Overshoot"]), pytest.approx(info["SettlingTime"]))


def test_metric_choices_are_checked(plant_model):
    with pytest.raises(StudyError, match=r"2 outputs \(x, v\); choose one with dc_gain\(output=...\)"):
        quiet_sweep(plant_model, RANGES, "dc_gain", values={"m": 1.0}, n=4)
    with pytest.raises(StudyError, match="did you mean 'min_damping'"):
        quiet_sweep(plant_model, RANGES, "min_damp", values={"m": 1.0}, n=4)
    with pytest.raises(StudyError, match="no output named 'y'"):
        quiet_sweep(plant_model, RANGES, M.dc_gain(output="y"), values={"m": 1.0}, n=4)
    with pytest.raises(StudyError, match="name of a parameter"):
        quiet_sweep(plant_model, RANGES, {"k": lambda ss: 1.0}, values={"m": 1.0}, n=4)


def test_parameter_names_follow_the_package_policy(plant_model):
    with pytest.raises(bg.ParameterValueError, match="did you mean 'k'"):
        quiet_sweep(plant_model, {"kk": (1.0, 2.0)}, "min_damping", values=MSD, n=4)
    with pytest.raises(bg.ParameterValueError, match="unknown parameter 'mm'"):
        quiet_sweep(plant_model, RANGES, "min_damping", values={"mm": 1.0}, n=4)
    with pytest.raises(bg.MissingValueError, match="no value for m"):
        quiet_sweep(plant_model, RANGES, "min_damping", n=4)
    # a varied parameter may have a nominal value: the study's value wins
    df = quiet_sweep(plant_model, {"k": [4.0, 16.0]}, "min_damping", values=MSD, design="grid")
    assert np.allclose(df["min_damping"], [0.1, 0.05])


# ------------------------------------------------------------------ failures, executors
def fragile(ss):
    """A user metric that fails for the stiffest samples."""
    if ss.parameters["k"] > 5.0:
        raise RuntimeError("too stiff for this metric")
    return ss.parameters["k"] * 2.0


def test_failing_samples_are_recorded_and_the_study_goes_on(plant_model):
    with pytest.warns(StudyWarning, match=r"2 of 6 samples failed.*I:m\b.*\bm = 0"):
        df = quiet_sweep(plant_model, {"m": [0.0, 1.0, 2.0], "k": [4.0, 9.0]}, "min_damping",
                         values={"b": 0.4}, design="grid")
    bad = df["m"] == 0.0
    assert df.loc[bad, "error"].str.contains("ParameterValueError").all()
    assert df.loc[bad, "min_damping"].isna().all()
    assert df.loc[~bad, "error"].isna().all()
    good = df[~bad]
    assert np.allclose(good["min_damping"], 0.4 / (2 * np.sqrt(good["m"] * good["k"])))
    assert df.attrs["failed"] == 2
    with pytest.warns(StudyWarning, match="3 of 6"):
        df = quiet_sweep(plant_model, {"k": [1.0, 3.0, 4.0, 6.0, 7.0, 8.0]},
                         ["min_damping", fragile], values=MSD, design="grid")
    assert df["fragile"].tolist()[:3] == [2.0, 6.0, 8.0] and df["fragile"][3:].isna().all()
    assert df["error"][3:].str.contains("metric fragile: RuntimeError: too stiff").all()
    assert df["min_damping"].notna().all()          # the other metric still ran


EXECUTOR_STUDY = dict(parameters={"b": (0.1, 1.0), "k": (1.0, 9.0)}, values={"m": 1.0}, n=64,
                      seed=11, design="lhs", chunk_size=10, output="x")


def test_a_process_pool_gives_the_identical_frame(plant_model):
    metrics = ["min_damping", "peak_gain", "bandwidth", "settling_time"]     # the last plant by plant
    local = quiet_sweep(plant_model, metric=metrics, **EXECUTOR_STUDY)
    with ProcessPoolExecutor(2) as pool:
        pooled = quiet_sweep(plant_model, metric=metrics, executor=pool, **EXECUTOR_STUDY)
        with pytest.raises(StudyError, match="could not run on the executor.*module level"):
            quiet_sweep(plant_model, metric=lambda ss: 1.0, executor=pool, **EXECUTOR_STUDY)
    pd.testing.assert_frame_equal(local, pooled)
    assert local.attrs == pooled.attrs and local.attrs["seed"] == 11


def test_a_dask_cluster_gives_the_identical_frame(plant_model):
    distributed = pytest.importorskip("distributed")
    metrics = ["min_damping", "peak_gain", "bandwidth"]        # (workers need not import control)
    local = quiet_sweep(plant_model, metric=metrics, **EXECUTOR_STUDY)
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        clustered = quiet_sweep(plant_model, metric=metrics, executor=client, **EXECUTOR_STUDY)
    pd.testing.assert_frame_equal(local, clustered)
    assert local.attrs == clustered.attrs


def test_a_fresh_seed_is_recorded_and_reproduces(plant_model):
    df = quiet_sweep(plant_model, RANGES, "min_damping", values=MSD, n=8)
    again = quiet_sweep(plant_model, RANGES, "min_damping", values=MSD, n=8, seed=df.attrs["seed"])
    pd.testing.assert_frame_equal(df, again)
    with pytest.raises(StudyError, match="executor"):
        quiet_sweep(plant_model, RANGES, "min_damping", values=MSD, n=8, executor=object())


def test_progress_bar_goes_to_stderr(plant_model, capsys):
    sweep(plant_model, RANGES, "min_damping", values=MSD, n=8, progress=True)
    assert "sweep msd" in capsys.readouterr().err


# ------------------------------------------------------------------ Sobol indices
def additive(ss):
    """Y = 1 b + 2 k: S1(b) = 1/5, S1(k) = 4/5."""
    return 1.0 * ss.parameters["b"] + 2.0 * ss.parameters["k"]


def test_sobol_indices_of_an_additive_function(plant_model):
    si = sensitivity(plant_model, {"b": (0.0, 1.0), "k": (0.0, 1.0)}, additive, values={"m": 1.0},
                     n=1024, seed=2, progress=False).set_index("parameter")
    exact = {"b": 0.2, "k": 0.8}
    for name, value in exact.items():
        row = si.loc[name]
        assert abs(row["S1"] - value) <= row["S1_conf"], (name, row.to_dict())
        assert abs(row["ST"] - value) <= row["ST_conf"], (name, row.to_dict())
        assert row["S1_conf"] < 0.1
    assert si.attrs["samples"] == 1024 * 4 and si.attrs["design"] == "saltelli"


def test_sensitivity_needs_every_sample(plant_model):
    with pytest.raises(StudyError, match="Sobol indices need every sample"):
        sensitivity(plant_model, {"m": [0.0, 1.0]}, "min_damping", values=MSD, n=8, seed=0,
                    progress=False)


# ------------------------------------------------------------------ the extra
def test_core_imports_without_the_study_packages():
    code = ("import sys\n"
            "for name in ('pandas', 'dask', 'distributed', 'SALib', 'tqdm', 'pyarrow'):\n"
            "    sys.modules[name] = None\n"
            "import bondgraph, bondgraph.study, bondgraph.cli\n"
            "from bondgraph.study import sweep, MissingDependencyError\n"
            "try:\n"
            "    sweep(None, {'a': (0, 1)}, 'min_damping')\n"
            "except MissingDependencyError as exc:\n"
            "    print(exc)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert "sweep() needs the package 'pandas'" in out.stdout
    assert 'pip install "bondgraph[study]"' in out.stdout


def test_missing_salib_is_named(plant_model, monkeypatch):
    monkeypatch.setitem(sys.modules, "SALib", None)
    with pytest.raises(MissingDependencyError, match="SALib") as info:
        sensitivity(plant_model, RANGES, "min_damping", values=MSD, n=8)
    assert isinstance(info.value, bg.BondGraphError) and isinstance(info.value, ImportError)


# ------------------------------------------------------------------ command line
MODEL_FILE = '''\
import bondgraph as bg
from bondgraph.modelfile import ModelDefinition

def model():
    g = bg.BondGraph("msd")
    F, v = bg.Se("F"), bg.One("v")
    g.add(F, v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
    for tail, head in [(F, v), (v, "m"), (v, "b"), (v, "k")]:
        g.connect(tail, head)
    return ModelDefinition(g, {"x": bg.displacement("k")}, {"m": 1.0, "b": 0.4, "k": 4.0})
'''


@pytest.fixture
def study_dir(tmp_path):
    (tmp_path / "msd.py").write_text(MODEL_FILE)
    (tmp_path / "study.toml").write_text(
        '[sweep]\nb = [0.1, 1.0]\nk = { values = [1.0, 4.0] }\n[values]\nm = 2.0\n'
        '[study]\nseed = 5\n')
    return tmp_path


def test_cli_sweep_writes_the_table(study_dir, capsys):
    out = study_dir / "results.csv"
    code = main(["sweep", str(study_dir / "msd.py"), "--params", str(study_dir / "study.toml"),
                 "--n", "32", "--design", "sobol", "--metric", "min_damping", "--metric", "dc_gain",
                 "-o", str(out)])
    assert code == 0, capsys.readouterr().err
    assert "wrote" in capsys.readouterr().out
    df = pd.read_csv(out)
    assert list(df.columns) == ["b", "k", "min_damping", "dc_gain", "error"] and len(df) == 32
    assert np.allclose(df["min_damping"], df["b"] / (2 * np.sqrt(2.0 * df["k"])))
    assert np.allclose(df["dc_gain"], 1 / df["k"])
    pq = study_dir / "results.parquet"
    if pytest.importorskip("pyarrow"):
        assert main(["sweep", str(study_dir / "msd.py"), "--params", str(study_dir / "study.toml"),
                     "--n", "32", "--metric", "min_damping", "--metric", "dc_gain",
                     "-o", str(pq)]) == 0
        back = pd.read_parquet(pq)
        pd.testing.assert_frame_equal(back[["b", "k", "min_damping"]], df[["b", "k", "min_damping"]])
        assert back.attrs["seed"] == 5 and back.attrs["design"] == "sobol"


@pytest.mark.parametrize("study, argv, message", [
    ('[sweep]\nkk = [1, 2]\n', [], "study file '.*study.toml'.*unknown parameter 'kk' .did you mean 'k'"),
    ('[sweep]\nk = [1, 2, 3]\n', [], "bounds \\[lo, hi\\]; got 3 values"),
    ('[sweep]\nk = { distribution = "nope" }\n', [], "not a scipy.stats distribution"),
    ('[values]\nm = 1\n', [], "has no \\[sweep\\] table"),
    ('[sweep]\nk = [1, 2]\n', ["--design", "grid", "--n", "0"], "--n must be between 1 and 10,000,000"),
    ('[sweep]\nk = [1, 2]\n[study]\nmetric = "nope"\n', None, "unknown metric 'nope'"),
])
def test_cli_sweep_errors_leave_no_file(study_dir, capsys, study, argv, message):
    (study_dir / "study.toml").write_text(study)
    out = study_dir / "results.csv"
    args = ["sweep", str(study_dir / "msd.py"), "--params", str(study_dir / "study.toml"),
            "-o", str(out)] + (["--metric", "min_damping"] + argv if argv is not None else [])
    assert main(args) == 1
    err = capsys.readouterr().err
    assert err.startswith("error: ") and err.count("\n") == 1
    assert pytest.importorskip("re").search(message, err), err
    assert list(study_dir.iterdir()) == sorted(study_dir.iterdir()) and not out.exists()
    assert sorted(p.name for p in study_dir.iterdir()) == ["msd.py", "study.toml"]


def test_cli_sweep_needs_a_table_suffix(study_dir, capsys):
    assert main(["sweep", str(study_dir / "msd.py"), "--params", str(study_dir / "study.toml"),
                 "--metric", "min_damping", "-o", str(study_dir / "out.txt")]) == 1
    assert "use a .csv or .parquet file name" in capsys.readouterr().err
