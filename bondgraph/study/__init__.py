"""Parameter studies: sweeps and Sobol sensitivity indices of a model's numeric plants.

* :func:`sweep` -- sample the varied parameters (Sobol, Latin hypercube,
  Halton, grid, random, or your points), evaluate metrics of each sample's
  plant, in chunks, vectorised where the metric allows, in this process,
  on a ``concurrent.futures`` executor or on a Dask cluster; a pandas
  ``DataFrame`` with one row per sample.
* :func:`sensitivity` -- first-order and total Sobol indices (SALib).
* :mod:`~bondgraph.study.metrics` -- the built-in metrics (poles, damping,
  gains, bandwidth, step response) and how to write your own.
* :mod:`~bondgraph.study.design` -- parameter ranges and designs.
* ``bondgraph sweep MODEL --params study.toml ...`` -- the command line
  (:mod:`~bondgraph.study.config` reads the study file).

Importing this package needs no optional package; running a study needs the
``study`` extra (pandas, tqdm, SALib, dask[distributed], pyarrow for
parquet), else :class:`MissingDependencyError` names it.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.study import sweep
>>> g = bg.BondGraph("rc")
>>> g.add(bg.Se("V"), bg.One("i"), bg.R("R"), bg.C("C"))
>>> for tail, head in [("V", "i"), ("i", "R"), ("i", "C")]: _ = g.connect(tail, head)
>>> model = bg.derive(g, outputs={"vC": bg.effort("C")})
>>> df = sweep(model, {"R": [1.0, 2.0, 4.0]}, ["max_real", "bandwidth"], values={"C": 1.0},
...            design="grid", progress=False)
>>> df[["R", "max_real"]].to_numpy().tolist()        # the pole -1/(RC)
[[1.0, -1.0], [2.0, -0.5], [4.0, -0.25]]
>>> df["bandwidth"].round(6).tolist()                  # 3 dB: 1/(RC) for 1/(RCs + 1)
[0.997628, 0.498814, 0.249407]
"""

from .deps import MissingDependencyError, StudyError, StudyWarning
from .design import DESIGNS, ParameterSpec, design_points, parameter_specs
from .metrics import BUILTIN, Metric
from .sweep import sensitivity, sweep

__all__ = ["sweep", "sensitivity", "StudyError", "StudyWarning", "MissingDependencyError",
           "DESIGNS", "BUILTIN", "Metric", "ParameterSpec", "parameter_specs", "design_points"]
