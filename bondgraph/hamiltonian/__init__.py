r"""Port-Hamiltonian form of a derived model.

A bond graph in integral causality is a port-Hamiltonian system: the
storage elements give the Hamiltonian ``H(x)`` (the stored energy) and its
gradient, the co-energy variables ``z = grad H`` (the flow of each I, the
effort of each C); the junction structure, transformers and gyrators give a
skew-symmetric ``J``; the R elements give a symmetric positive semi-definite
``R``; the sources give the input matrix ``G``:

.. math::

    \dot x = (J - R)\,\nabla H(x) + (G - P)\,u, \qquad
    y = (G + P)^T \nabla H(x) + (S - N)\,u .

``P``, ``S`` and ``N`` are zero unless a collocated output depends on an
input directly (a feedthrough ``D = S - N``: a source meeting an R element
without storage in between, or two sources joined through a gyrator, which
gives a skew ``N``); the conventions are those
of pymor's ``PHLTIModel`` (``Q`` is the Hessian of a quadratic ``H``), with
``W = [[R, P], [P^T, S]]`` symmetric positive semi-definite and ``N``
skew-symmetric for a passive model.

Outputs
-------
The outputs ``y`` of the port-Hamiltonian form are the *collocated* outputs,
one per input, power-conjugate to it: for an ``Se`` the flow out of the
source, for an ``Sf`` the effort on its bond, so that ``y^T u`` is the power
the sources deliver and

.. math::

    \frac{dH}{dt} = -w^T W w + y^T u, \qquad w = (\nabla H, u) .

They are named ``f_<source>`` and ``e_<source>`` (:attr:`PortHamiltonian.output_names`).
They are *not* the model's own outputs, which may be anything the user asked
for (a displacement, a sensor combination); those stay on the
:class:`~bondgraph.model.Model`.

Method
------
The state equations and collocated outputs are derived (with the model's own
causality) and their coefficients in the co-energy variables are read off:
``x' = F z + B u``, ``y = C_z z + D u`` with ``F = (df/dx) (d^2H/dx^2)^{-1}``.
Then ``J = (F - F^T)/2``, ``R = -(F + F^T)/2``, ``G = (B + C_z^T)/2``,
``P = (C_z^T - B)/2``, ``S = (D + D^T)/2``, ``N = (D^T - D)/2``.  The
rebuilt ``x'`` is checked symbolically against the model's ``rhs``.

The elements say what they store and why they would prevent the form
(:mod:`bondgraph.elements.protocol`, "Energy"): a one-port I or C its ``p`` or ``q``
and ``int phi``; a multiport field (:mod:`bondgraph.elements.fields`) its momenta and
displacements and ``H = p^T M^-1 p / 2`` (``IField``), ``q^T K q / 2``
(``CField``), ``x^T Q x / 2`` (``ICField``) or its energy function; an
``RField`` adds its resistance matrix to ``R``; a source names its collocated
output.  A nonlinear field with a coupled energy is accepted when ``J - R``
comes out constant (``F = (df/dx) (d^2H/dx^2)^{-1}``).

Only the storage states enter: integrator states that a displacement or
momentum output added (``model.integrators``) are not stored energy and are
left out (:attr:`PortHamiltonian.states` is ``model.states[:model.storage_states]``).

Derivative causality
--------------------
Storage elements in derivative causality store energy too: ``H`` is the
energy of *all* storage elements, written in the remaining (independent)
states.  Two inertias ``J1``, ``J2`` rigidly joined give the state ``p_J1``
and ``H = (J1 + J2) p_J1**2 / (2 J1**2)`` -- the energy ``p**2/(2 (J1 + J2))``
of the effective inertia with total momentum ``p = (J1 + J2)/J1 * p_J1``.
The reduced form is then again port-Hamiltonian (with power-conserving
two-ports ``F = E^{-1} F_0 E^{-T}``, a congruence of the descriptor form, so
``R`` stays positive semi-definite), with a non-diagonal ``Q`` in general.
Storage in derivative causality must be linear.

What is refused
---------------
:class:`PortHamiltonianError` (a :class:`~bondgraph.errors.NonlinearModelError`,
hence a :class:`~bondgraph.errors.BondGraphError` and ``ValueError``), naming
the element: nonlinear or modulated R, MTF/MGY, sources with ``value=``
(constant loads, time functions, modulated sources: not ports), storage laws
that use signals or time, storage in derivative causality with a nonlinear
law (a nonlinear field with a port in derivative causality), a nonlinear
``RField``, a storage law whose energy ``sympy.integrate`` cannot find, a
source whose derivative enters (a flow source driving an inertia directly).

Transformers and gyrators with ``efficiency`` other than 1 are accepted and
listed in :attr:`PortHamiltonian.nonconservative`: such a two-port (a
one-quadrant data-sheet model) does not conserve power, so the decomposition
is exact but ``W`` need not be positive semi-definite (see
:meth:`PortHamiltonian.is_passive`; the FLEXCAM model of ``models/`` with the
SRV-02 data-sheet efficiencies is not passive in this sense, and is with
efficiencies 1).

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("msd")
>>> v = bg.One("v")
>>> g.add(bg.Se("F"), v, bg.I("m"), bg.R("b"), bg.C("c"))
>>> for t, h in [("F", v), (v, "m"), (v, "b"), (v, "c")]: _ = g.connect(t, h)
>>> ph = port_hamiltonian(bg.derive(g))
>>> ph.H
p_m**2/(2*m) + q_c**2/(2*c)
>>> ph.J, ph.R, ph.G
(Matrix([
[0, -1],
[1,  0]]), Matrix([
[b, 0],
[0, 0]]), Matrix([
[1],
[0]]))
>>> ph.gradient, ph.output_names, ph.outputs()
((p_m/m, q_c/c), ('f_F',), (p_m/m,))
"""

from .form import PortHamiltonian, energy, port_hamiltonian
from .parts import PortHamiltonianError

__all__ = ["PortHamiltonian", "PortHamiltonianError", "port_hamiltonian", "energy"]

PortHamiltonianError.__module__ = __name__   # tracebacks name it where users import it
