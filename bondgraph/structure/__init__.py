"""What the graph knows: structural analyses of a linear bond-graph model.

Each analysis reads a derived :class:`bondgraph.Model` (its augmented bond
graph and its linear form) and returns a frozen result that explains itself
(``print(result)``): the causal paths, the elements involved, and the
generic (almost-all-parameter-values) answer.

* :func:`controllability`, :func:`observability` -- causal paths from the
  inputs / to the outputs, the structural and generic rank of ``[A B]`` and
  ``[A; C]``, the states lost and why (:mod:`bondgraph.structure.reach`);
* :func:`zero_structure` -- relative degree from the shortest causal path,
  number of finite zeros, the zeros; :func:`collocated` (:mod:`bondgraph.structure.zeros`);
* :func:`infinite_zeros` -- the orders of the infinite zeros of a MIMO
  selection from disjoint causal paths and from the Markov parameters
  (:mod:`bondgraph.structure.mimo`);
* :func:`identifiability` -- which parameters, and which of their products,
  a transfer function determines (:mod:`bondgraph.structure.identifiable`);
* :func:`invert` -- the input for an output trajectory, with the relative
  degree and minimum-phase conditions (:mod:`bondgraph.structure.inversion`);
  :func:`bicausal_graph` -- the bicausal bond graph of the inversion, the
  source-sensor pair and the split strokes (:mod:`bondgraph.structure.bicausal`);
* :func:`sensor_placement`, :func:`position_sweep` -- which modes a sensor on
  a modal beam observes, the nodes, where a sensor turns a pair
  non-minimum-phase (:mod:`bondgraph.structure.placement`);
* :func:`fault_signatures` -- analytical redundancy relations, the fault
  signature matrix, residuals on data (:mod:`bondgraph.structure.faults`).
"""

from ._generic import StructureError
from .bicausal import Bicausal, bicausal_graph
from .derivative import SS, DerivativeCausality, derivative_causality
from .mimo import InfiniteZeros, infinite_zeros
from .inversion import Inversion, invert
from .placement import PositionSweep, SensorPlacement, position_sweep, sensor_placement
from .reach import Reachability, controllability, observability
from .faults import FaultDiagnosis, fault_signatures
from .identifiable import (Identifiability, IdentifiabilityWarning, identifiability,
                           tf_coefficients)
from .zeros import ZeroStructure, collocated, zero_structure

__all__ = ["StructureError", "Reachability", "controllability", "observability",
           "SS", "DerivativeCausality", "derivative_causality",
           "ZeroStructure", "zero_structure", "collocated", "InfiniteZeros", "infinite_zeros",
           "Identifiability", "identifiability", "tf_coefficients", "IdentifiabilityWarning",
           "Inversion", "invert", "Bicausal", "bicausal_graph",
           "SensorPlacement", "sensor_placement", "PositionSweep", "position_sweep",
           "FaultDiagnosis", "fault_signatures"]
