"""Symbolic transfer functions of linear (descriptor) state-space models.

Thin facade over :mod:`bondgraph.tf`; see there for the algorithms.

Examples
--------
>>> import sympy as sp
>>> from bondgraph.transfer import transfer_function
>>> J, b = sp.symbols("J b", positive=True)
>>> G = transfer_function([[-b/J]], [[1/J]], [[1]], 0, input_names=["T"],
...                       output_names=["omega"])
>>> G.expr, G.subs({"J": 2, "b": 0.5}).poles()
(1/(J*(s + b/J)), array([-0.25]))
"""

from .tf import *  # noqa: F401,F403
from .tf import __all__  # noqa: F401
