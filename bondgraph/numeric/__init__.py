"""Numeric plants from derived models: evaluation, batches, simulation.

* :func:`compile_plant` / :class:`NumericModel` -- a linear model's
  ``A, B, C, D`` compiled once (monomial entries by numpy, the rest
  lambdified); ``.plant(values)`` gives a
  :class:`NumericStateSpace` (python-control, scipy, eigenvalues, frequency
  response), ``.batch(arrays)`` a :class:`BatchStateSpace` of many plants.
* sparse plants (above :data:`SPARSE_THRESHOLD` states, or ``sparse=True``):
  ``scipy.sparse`` matrices, sparse-LU frequency responses, the eigenvalues
  nearest a target; see :mod:`bondgraph.numeric.sparse`.
* :func:`compile_dynamics` / :func:`simulate` / :func:`to_nonlinear_iosys` --
  nonlinear and time-varying models in time.
* :func:`linear_plant` -- a model linearized at an operating point, at values.
* :mod:`bondgraph.numeric.control` -- small control-design helpers for plants.

Parameter values are a mapping keyed by sympy Symbol or name (``"motor.Ra"``);
all parameters must be given, and nothing else.

Every compiled object pickles (for process pools and Dask): a
:class:`NumericModel` or :class:`NumericDynamics` travels as its model and
expressions and is lambdified again on first use after loading, once per
process (a cache keyed by the expressions), so a round trip gives the same
numbers bit for bit.  A model whose laws call Python functions (sympy
``implemented_function``) cannot be pickled (:class:`NotPicklableError`).

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.numeric import compile_plant
>>> g = bg.BondGraph("dc_motor")
>>> V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
>>> g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
>>> for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
...     _ = g.connect(tail, head)
>>> plant = compile_plant(bg.derive(g, outputs={"omega": bg.flow("J")}))
>>> ss = plant.plant({"Ra": 1.0, "La": 0.5, "K": 0.1, "J": 0.01, "b": 0.1})
>>> ss.A
array([[ -2. , -10. ],
       [  0.2, -10. ]])
>>> ss.to_control().state_labels
['p_La', 'p_J']
"""

from .errors import (DenseConversionError, DenseConversionWarning, ImproperPlantError,
                     NotPicklableError, NumericError, ParameterValueError, SimulationError)
from .resolve import parameter_name, resolve_batch, resolve_parameters
from .plant import (BatchStateSpace, NumericModel, NumericStateSpace, SparseBatchStateSpace,
                    compile_plant, control_labels, numeric_plant)
from .sparse import SPARSE_THRESHOLD, Pattern
from .simulate import (NumericDynamics, SimulationResult, compile_dynamics, simulate,
                       to_nonlinear_iosys)
from .operating import linear_plant
from ._linalg import ChannelResponse, channel_response, sorted_eigenvalues

__all__ = [
    "NumericStateSpace", "BatchStateSpace", "SparseBatchStateSpace", "Pattern",
    "SPARSE_THRESHOLD", "NumericModel", "compile_plant", "numeric_plant",
    "linear_plant", "NumericDynamics", "compile_dynamics", "SimulationResult", "simulate", "to_nonlinear_iosys",
    "ChannelResponse", "channel_response", "sorted_eigenvalues",
    "resolve_parameters", "resolve_batch", "parameter_name", "control_labels",
    "NumericError", "ParameterValueError", "SimulationError", "ImproperPlantError",
    "NotPicklableError", "DenseConversionError", "DenseConversionWarning",
]
