"""Bond-graph elements: frozen values describing each node of a graph.

Conventions
-----------
Every bond has a power direction, from its *tail* to its *head* (the
half-arrow end); ``e*f`` is the power flowing that way.

* ``Se``, ``Sf`` -- effort and flow sources; each is an input ``u`` named after
  the element.  A source's bond normally points away from it.
* ``I`` stores momentum ``p``; a linear I has ``f = p/I``.
* ``C`` stores displacement ``q``; a linear C has ``e = q/C`` (C is a
  compliance; pass ``stiffness=k`` for ``e = k*q``).
* ``R`` dissipates; a linear R has ``e = R*f``.
* One-port laws are written for power flowing *into* the element; a bond
  that points away from an I, C or R flips the sign of its flow.
* ``TF`` with modulus ``n``: ``e1 = n*e2`` and ``f2 = n*f1``, where port 1
  is the bond into the TF and port 2 the bond out of it.
* ``GY`` with modulus ``r``: ``e1 = r*f2`` and ``e2 = r*f1``.
* ``MTF`` and ``MGY`` are the same with a modulus that may depend on
  signals (states, efforts, flows, displacements) and on time :data:`t`.
* ``Zero``: common effort, flows sum to zero (signed by bond direction).
  ``One``: common flow, efforts sum to zero.
* ``Port``: an external port of a graph used as a sub-model.

Parameters default to a positive sympy symbol named after the element (with
its hierarchical path, ``motor.Ra``); a number, a symbol, an expression or an
identifier string may be given instead.

Each class carries its own behaviour through the element protocol
(:mod:`bondgraph.elements.protocol`): port rules, causal rules for SCAP, the
variables it determines and its constitutive relations, its drawing.  The
package's modules: :mod:`~bondgraph.elements.protocol` (the protocol, with
:class:`Bond`), :mod:`~bondgraph.elements.one_ports`,
:mod:`~bondgraph.elements.two_ports`, :mod:`~bondgraph.elements.junctions`
and :mod:`~bondgraph.elements.fields` (multiport fields).

Nonlinear laws are sympy expressions in the element's own variable
(:data:`bondgraph.p`, :data:`~bondgraph.q`, :data:`~bondgraph.e`,
:data:`~bondgraph.f`) or callables taking it.

Examples
--------
>>> from bondgraph import elements
>>> [el.label() for el in (elements.Se("V"), elements.TF("gear", 3), elements.One("w"))]
['Se:V', 'TF:gear', '1:w']
>>> elements.IField("M", [[2, 1], [1, 2]]).bonds
(2, 2)
"""

from .bond import Bond
from .protocol import Element, check_name, drawing_role
from .one_ports import C, I, OnePort, R, Se, Sf
from .two_ports import GY, MGY, MTF, TF, TwoPort
from .junctions import One, Port, Zero
from .fields import CField, Field, FieldError, ICField, IField, RField, StorageField
from .._support.sympify import ParameterLike

__all__ = [
    "Bond", "Element", "OnePort", "TwoPort",
    "Se", "Sf", "I", "C", "R", "TF", "GY", "MTF", "MGY", "Zero", "One", "Port",
    "Field", "StorageField", "IField", "CField", "ICField", "RField", "FieldError",
    "ParameterLike", "check_name", "drawing_role",
]
