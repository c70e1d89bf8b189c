r"""Multiport fields: :class:`IField`, :class:`CField`, :class:`ICField`, :class:`RField`.

A field is one element with ``n`` ports (``n`` bonds, in the order they are
connected) whose constitutive law couples the ports: a mass matrix from
finite elements or a multibody model, a stiffness matrix, a coupled
resistance, a kinetic or potential energy function.

Conventions
-----------
Port ``k`` (1-based) is the ``k``-th bond of the field.  As for one-port
elements, the law holds for power flowing *into* the field: a bond that
points away from it flips the sign of its flow.  On each port the field
stores an *energy variable* ``x_k`` -- a momentum ``p`` on an inertial
(I-like) port, a displacement ``q`` on a compliant (C-like) port -- with
``dp_k/dt = e_k`` and ``dq_k/dt = f_k``; its *co-energy variable* ``z_k`` is
the port's flow (I port) or effort (C port), ``z = grad H(x)``.

* ``IField(name, mass)``: ``p = M f`` (``H = p^T M^-1 p / 2``), or
  ``energy=T(p_1..p_n)`` with ``f = dT/dp``.
* ``CField(name, stiffness=K)``: ``e = K q``; ``compliance=C``: ``q = C e``;
  or ``energy=V(q_1..q_n)`` with ``e = dV/dq``.
* ``ICField(name, kinds="IIC", matrix=Q)``: ``z = Q x`` with ``x`` the
  momenta of its I ports and displacements of its C ports in port order,
  ``Q`` the Hessian of ``H``; or ``energy=H(x)``.
* ``RField(name, resistance)``: ``e = R f``; or ``law=(e_1(f), ..., e_n(f))``.

With ``energy=`` (or ``law=``) give ``variables=``: the sympy symbols, one
per port in port order, in which the function is written.

States and names
----------------
A port in integral causality (effort in on an I port, flow in on a C port,
preferred on every port) gives the state ``p_<name>_<k>`` or
``q_<name>_<k>``: ``p_M_1, p_M_2`` for ``IField("M", ...)``.  Those names
must not clash with another element's states (an I named ``M_1`` would
also be ``p_M_1``: derivation refuses the clash).

A port in derivative causality (driven by a flow source, rigidly joined to
another inertia) keeps its momentum or displacement as an algebraic
function of the others.  Linear fields are solved symbolically (a Schur
complement: for ``p = M f`` with ports ``a`` integral and ``b`` driven,
``f_a = M_aa^-1 (p_a - M_ab f_b)``); a nonlinear law is inverted on those
ports only, and :class:`FieldError` names the field and its ports when it
cannot be.  An :class:`RField` takes either causality on each port.

Signals
-------
``bg.flow("M")`` is ambiguous for a field and refused; name the port:
``bg.flow("M", port=1)``, ``bg.effort("K", port=2)``,
``bg.momentum("M", port=1)`` (the state ``p_M_1``),
``bg.displacement("K", port=2)`` (``q_K_2``).

Checks
------
Matrix size against the bonds (at ``connect`` and when flattened), symmetry
(symbolically) and positive definiteness (numerically, when the entries are
numbers; :meth:`StorageField.check_values` at given parameter values) raise
:class:`FieldError` naming the field and the matrix.

Examples
--------
Two masses coupled through their mass matrix, each pushed by a force:

>>> import sympy, bondgraph as bg
>>> m1, m2, m12 = sympy.symbols("m1 m2 m12", positive=True)
>>> g = bg.BondGraph("pair")
>>> g.add(bg.Se("F1"), bg.Se("F2"), bg.IField("M", [[m1, m12], [m12, m2]]))
>>> _ = g.connect("F1", "M"); _ = g.connect("F2", "M")
>>> model = bg.derive(g, outputs={"v1": bg.flow("M", port=1)})
>>> model.state_names, model.rhs
(('p_M_1', 'p_M_2'), (F1, F2))
>>> sympy.factor(model.output_exprs[0])
(-m12*p_M_2 + m2*p_M_1)/(m1*m2 - m12**2)
"""

from .algebra import FieldError
from .base import Field
from .resistive import RField
from .storage import CField, ICField, IField, StorageField

__all__ = ["FieldError", "Field", "StorageField", "IField", "CField", "ICField", "RField"]
