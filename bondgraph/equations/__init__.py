"""Equations: the state equations of an augmented bond graph, as a frozen record.

* :func:`derive_equations` -- bond variables computed once each in causal
  order; algebraic loops solved exactly over the parameters' rational
  functions (:mod:`~bondgraph.equations.loops`); derivative causality kept
  as a descriptor form and solved; displacement and momentum outputs as
  state combinations or integrator states
  (:mod:`~bondgraph.equations.integrators`).
* :class:`StateEquations` -- the record every later stage reads (linear
  forms, transfer functions, numeric plants, the port-Hamiltonian form);
  :class:`bondgraph.Model` is this record with the verbs attached, and
  :func:`bondgraph.derive` returns one.

Examples
--------
>>> from bondgraph import examples
>>> from bondgraph.equations import derive_equations
>>> derive_equations(examples.mass_spring_damper()).rhs
(F - b*p_m/m - k*q_k, p_m/m)
"""

from .derive import derive_equations
from .loops import SingularLoopError
from .record import StateEquations

__all__ = ["derive_equations", "StateEquations", "SingularLoopError"]
