"""A study cannot be hung by a metric that never returns, nor lost by a worker that dies
(issue 23): the samples concerned carry an error, the others their values (the hand result
sqrt(k/m))."""

import os
import time

import numpy as np
import pytest

pd = pytest.importorskip("pandas")

import bondgraph as bg
from bondgraph.study import StudyError, sweep


def msd():
    g = bg.BondGraph("msd")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "k")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"x": bg.displacement("k")})


def stalls(ss):
    """sqrt(k/m) (the natural frequency, by hand), but never returns for k > 8."""
    if ss.parameters["k"] > 8.0:
        time.sleep(3600)
    return float(np.sqrt(ss.parameters["k"] / ss.parameters["m"]))


def dies(ss):
    """sqrt(k/m), but the worker process exits for k > 8 (as a segfault would end it)."""
    if ss.parameters["k"] > 8.0:
        os._exit(1)
    return float(np.sqrt(ss.parameters["k"] / ss.parameters["m"]))


STUDY = dict(parameters={"k": [1.0, 4.0, 9.0, 16.0]}, values={"m": 1.0, "b": 0.5}, n=4,
             design="grid", chunk_size=1, progress=False)


def test_timeout_must_be_positive():
    with pytest.raises(StudyError, match="timeout must be a positive number"):
        sweep(msd(), metric=stalls, timeout=0, **STUDY)


@pytest.fixture
def client():        # one cluster per test: a stalled worker keeps sleeping
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as c:
        yield c


def test_a_metric_that_never_returns_times_out_on_dask(client):
    with pytest.warns(bg.study.StudyWarning, match="2 of 4 samples failed"):
        df = sweep(msd(), metric={"wn": stalls}, executor=client, timeout=8.0, **STUDY)
    by_k = df.set_index("k")
    for k in (1.0, 4.0):
        assert by_k.loc[k, "wn"] == pytest.approx(np.sqrt(k))
        assert pd.isna(by_k.loc[k, "error"])
    for k in (9.0, 16.0):
        assert np.isnan(by_k.loc[k, "wn"])
        assert "timeout of 8 s" in by_k.loc[k, "error"]


def test_a_worker_that_dies_marks_its_samples_and_the_study_returns(client):
    """The dead worker's samples carry the error; samples Dask lost with it (their tasks
    "already forgotten") carry it too; every other sample has its value."""
    with pytest.warns(bg.study.StudyWarning, match="samples failed"):
        df = sweep(msd(), metric={"wn": dies}, executor=client, **STUDY)
    by_k = df.set_index("k")
    for k in (9.0, 16.0):
        assert np.isnan(by_k.loc[k, "wn"])
        assert "worker running these samples died" in by_k.loc[k, "error"]
    for k in (1.0, 4.0):
        if pd.isna(by_k.loc[k, "error"]):
            assert by_k.loc[k, "wn"] == pytest.approx(np.sqrt(k))
        else:
            assert "worker running these samples died" in by_k.loc[k, "error"]
