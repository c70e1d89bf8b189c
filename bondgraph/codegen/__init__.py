"""Code generation from a model's symbolic equations: C, MATLAB/Octave, Python.

Each generator renames the model's symbols to identifiers of the target
language (``motor.Ra`` -> ``motor_Ra``, avoiding reserved words and
clashes), splits the equations into common subexpressions with
:func:`sympy.cse`, and prints them with sympy's code printers (doubles
printed exactly; a function with no equivalent in the target is an error,
never silently left in the code).  Arrays are in the model's order: states,
inputs and outputs as derived, parameters sorted by name
(``Model.parameters``).

* :func:`generate_c` / :func:`write_c` -- a ``.c``/``.h`` pair with
  ``NAME_derivatives``, ``NAME_outputs``, ``NAME_step_euler`` and
  ``NAME_step_rk4``.
* :func:`generate_matlab` / :func:`write_matlab` -- ``[xdot, y] = NAME(t, x, u, p)``.
* :func:`generate_python` / :func:`write_python` -- a module using only :mod:`math`.
* :func:`generate_switched_c` / :func:`generate_switched_python` /
  :func:`generate_switched_matlab` -- a switched model
  (:mod:`bondgraph.hybrid`): a table of its reachable modes with their
  right-hand sides, outputs, guards and re-initialisations
  (:mod:`bondgraph.codegen.switched`, :mod:`bondgraph.codegen.switched_matlab`).

An implicit model (algebraic unknowns ``z`` with residuals ``0 = g(x, z,
u)``) is generated with a damped Newton iteration on the generated ``dg/dz``,
warm-started from the last ``z``; a failure is a status (C), an
``AlgebraicSolveError`` (Python) or an ``error`` (MATLAB) naming the
unknowns (:mod:`bondgraph.codegen._newton`).

Names never reach the generated text raw.  Function names and the C prefix
must be identifiers (matched whole, so ``"abc\\n"`` is refused); every other
name (model, states, inputs, outputs, parameters -- a parameter may be any
sympy Symbol) is escaped for the place it lands in: C string literals with
octal escapes and no trigraphs, Python :func:`ascii` literals, MATLAB char
arrays (``''`` doubled, else built from UTF-8 bytes), and comments and
docstrings that show it on one line of printable ASCII, with no ``*/`` or
triple quote that could end them.  The generated files are ASCII.  Only a name no
escape can carry (a NUL character, a lone surrogate) is refused, with a
:class:`CodegenError` naming it.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.codegen import generate_c
>>> g = bg.BondGraph("servo")
>>> V, i = bg.Se("V"), bg.One("i")
>>> g.add(V, i, bg.I("L", "motor.L"), bg.R("R", "motor_L"))
>>> for tail, head in [(V, i), (i, "L"), (i, "R")]: _ = g.connect(tail, head)
>>> code = generate_c(bg.derive(g, outputs={"i": bg.flow("L")}))
>>> code.identifiers["motor.L"], code.identifiers["motor_L"]
('motor_L_2', 'motor_L')
>>> "#define SERVO_NX 1" in code.header
True
"""

from ._common import CodegenError
from .c import CCode, generate_c, write_c
from .matlab import generate_matlab, write_matlab
from .python import generate_python, write_python
from .switched import (SwitchedCCode, SwitchedExportError, generate_switched_c,
                       generate_switched_python)
from .switched_matlab import generate_switched_matlab

__all__ = ["CodegenError", "CCode", "generate_c", "write_c", "generate_matlab", "write_matlab",
           "generate_python", "write_python", "SwitchedCCode", "SwitchedExportError",
           "generate_switched_c", "generate_switched_python", "generate_switched_matlab"]
