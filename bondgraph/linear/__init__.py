"""Linear forms of derived equations: state space, descriptor form, transfer functions
of a model, symbolic linearization and operating points.

* :mod:`~bondgraph.linear.model_forms` -- :func:`state_space`,
  :func:`descriptor_form`, :func:`transfer_function`,
  :func:`transfer_matrix`, :func:`linearize` (symbolic Jacobians) of a
  :class:`~bondgraph.equations.StateEquations` record;
* :mod:`~bondgraph.linear.statespace` -- :class:`SymbolicStateSpace`;
* :mod:`~bondgraph.linear.operating` -- :func:`equilibrium` (trim) and the
  :class:`Equilibrium` it returns; :mod:`~bondgraph.linear.implicit` -- the
  same for implicit models (``f = 0`` and ``g = 0`` together);
* :mod:`~bondgraph.linear.offsets` -- linear forms of a model with constant
  sources in deviations about its :class:`OperatingPoint`
  (:mod:`~bondgraph.linear.point`), symbolic or numeric;
* :mod:`~bondgraph.linear.forms` -- the linear coefficients behind them.

The numeric plant at an operating point is :func:`bondgraph.numeric.linear_plant`.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph import examples
>>> from bondgraph.equations import derive_equations
>>> from bondgraph.linear import state_space, transfer_function
>>> eqs = derive_equations(examples.rc(), {"vC": bg.effort("C")})
>>> state_space(eqs).C
Matrix([[1/C]])
>>> transfer_function(eqs, "V", "vC", normalize="leading-one-denominator").expr
1/(C*R*s + 1)
"""

from .model_forms import (derivative_form, descriptor_form, deviations, is_linear, laplace_system,
                          linearize,
                          state_space, transfer_function, transfer_matrix)
from .operating import Equilibrium, EquilibriumError
from .implicit import equilibrium
from .statespace import SymbolicStateSpace
from .point import OperatingPoint, OperatingPointError
from .offsets import numeric_operating_point, symbolic_operating_point

__all__ = ["SymbolicStateSpace", "state_space", "is_linear", "descriptor_form", "laplace_system",
           "derivative_form", "transfer_function", "transfer_matrix", "linearize",
           "Equilibrium", "EquilibriumError", "equilibrium", "OperatingPoint",
           "OperatingPointError", "symbolic_operating_point", "numeric_operating_point",
           "deviations"]

EquilibriumError.__module__ = __name__   # tracebacks name it where users import it
OperatingPointError.__module__ = __name__
