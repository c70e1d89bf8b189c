r"""Modal numerics of uniform Euler–Bernoulli beams (for modal bond-graph fragments).

What is here
------------
* :func:`modal_beam` -> :class:`ModalBeam`: eigenvalues ``beta_i L``, natural
  frequencies, modal masses / stiffnesses / damping, root slopes, tip values,
  rigid-body couplings and shape functions ``phi_i, phi_i', phi_i'', phi_i'''``
  of a ``"clamped-free"`` or ``"pinned-free"`` beam, optionally with a tip
  mass ``M_t`` and tip rotary inertia ``J_t``;
* :func:`symbolic_modes` (or :meth:`ModalBeam.symbolic`): the same as sympy
  expressions in ``EI, rhoA, L, x``;
* :func:`hub_beam_modes`: exact *unconstrained* (system) modes of a free hub
  of inertia ``J_h`` with beams clamped at radius ``r``;
  :func:`hub_assumed_modes`: the Rayleigh–Ritz (assumed-modes) model of the
  same system, built from a :class:`ModalBeam` basis;
* :mod:`~bondgraph.beam.characteristic`: the frequency equations (stable
  numeric forms, classical sympy forms) and their roots.

Conventions
-----------
* ``x`` runs from the root (``0``) to the free tip (``L``); ``w(x, t)`` is the
  transverse deflection, ``EI w'''' + rhoA w_tt = 0`` (no shear deformation,
  rotary inertia of the section or axial/centrifugal stiffening).
* Bending moment ``M = EI w''`` and shear force ``V = -EI w'''``
  (so a static tip force ``F`` in ``+w`` gives ``EI w'''(L) = -F`` and a tip
  moment ``C`` turning towards ``+w'`` gives ``EI w''(L) = C``).
* Tip body at ``x = L`` (Hamilton's principle with kinetic energy
  ``M_t w_t(L)^2/2 + J_t w'_t(L)^2/2``), harmonic ``e^{j omega t}``::

      EI w'''(L) = -M_t omega^2 w(L),    EI w''(L) = +J_t omega^2 w'(L).

* Root: *clamped* ``w = w' = 0`` (cantilever on a fixed hub: "constrained"
  modes); *pinned* ``w = w'' = 0`` (beam on a hub of negligible inertia:
  Barbosa & Góes, FLEXCAM, Eqs. 7–12).  The pinned-free beam also has the
  rigid-body mode ``phi_0 = x`` at ``beta L = 0``, which is *not* in
  ``ModalBeam.modes``; its modal mass is :attr:`ModalBeam.rigid_inertia`, and
  every flexible pinned-free mode is mass-orthogonal to it
  (``angular_coupling = 0``).  To couple a hub of finite inertia use
  :func:`hub_beam_modes` or :func:`hub_assumed_modes`.
* ``omega_i = (beta_i L)^2 sqrt(EI/(rhoA L^4))``; ``k_i = m_i omega_i^2``;
  ``c_i = 2 zeta_i m_i omega_i``.
* Orthogonality (mass operator including the tip body)::

      int_0^L rhoA phi_i phi_j dx + M_t phi_i(L) phi_j(L) + J_t phi_i'(L) phi_j'(L)
          = m_i delta_ij,      int_0^L EI phi_i'' phi_j'' dx = k_i delta_ij.

* Normalisation (``normalization=``): ``"mass"`` (``m_i = 1``, default),
  ``"tip"`` (``phi_i(L) = 1``) or ``"length"`` (``int phi_i^2 dx = L``, the
  dimensionless convention of Blevins).  The sign is fixed by ``phi_i(L) > 0``.
* Shapes are evaluated in the bounded basis
  ``cos(bx), sin(bx), exp(-bx), exp(-b(L-x))`` (never ``cosh - cos`` of huge
  numbers), so high modes are accurate; frequency equations are divided by
  ``cosh(beta L)`` (e.g. clamped-free ``cos(beta L) + 1/cosh(beta L) = 0``).
* Modal equation of a force distribution ``f(x, t)``:
  ``m_i eta_i'' + c_i eta_i' + k_i eta_i = int phi_i f dx``; a root torque
  ``tau`` enters with gain ``phi_i'(0)`` (:attr:`BeamMode.root_slope`), a tip
  force with ``phi_i(L)`` (:attr:`BeamMode.tip_value`).
* Rigid/flexible couplings (for assumed-modes mass matrices of a hub):
  ``linear_coupling = int rhoA phi dx + M_t phi(L)``,
  ``angular_coupling = int rhoA x phi dx + M_t L phi(L) + J_t phi'(L)`` and
  ``hub_coupling(r) = angular_coupling + r * linear_coupling``.

Characteristic equations (``lam = beta L``, ``mu = M_t/(rhoA L)``,
``j = J_t/(rhoA L^3)``)::

    clamped-free:  1 + cos lam cosh lam = 0                          (1.8751, 4.6941, 7.8548)
    + tip body:    1 + cos cosh + mu lam (cos sinh - sin cosh)
                   - j lam^3 (sin cosh + cos sinh) + mu j lam^4 (1 - cos cosh) = 0
    pinned-free:   tan lam = tanh lam                                (0, 3.9266, 7.0686, 10.2102)

and for the hub, see :mod:`bondgraph.beam.characteristic`.

References
----------
* L. Meirovitch, *Analytical Methods in Vibrations*, Macmillan, 1967 (ch. 5);
  *Fundamentals of Vibrations*, McGraw-Hill, 2001.
* R. D. Blevins, *Formulas for Natural Frequency and Mode Shape*, Van
  Nostrand Reinhold, 1979, Table 8-1.
* E. Barbieri, Ü. Özgüner, "Unconstrained and constrained mode expansions for a
  flexible slewing link", J. Dyn. Sys. Meas. Control 110 (1988) 416–421.
* E. G. Barbosa, L. C. S. Góes, FLEXCAM paper (seed 000), Eqs. 7–12;
  A. M. S. Soares, L. C. S. Góes, L. C. G. Souza (seed 001), Eqs. 1–18.

Examples
--------
>>> from bondgraph.beam import modal_beam
>>> beam = modal_beam(EI=2.0, rhoA=0.5, L=1.2, n_modes=3, boundary="pinned-free")
>>> [round(v, 4) for v in beam.betaL]
[3.9266, 7.0686, 10.2102]
>>> m = beam.modes[0]
>>> [abs(v) < 1e-12 for v in (m.phi(0.0), m.d2phi(0.0), m.angular_coupling)]
[True, True, True]
"""

from ._validation import BeamParameterError
from .characteristic import (
    BOUNDARIES,
    beam_eigenvalues,
    characteristic_expression,
    characteristic_function,
    hub_beam_eigenvalues,
    hub_characteristic_expression,
    hub_characteristic_function,
)
from .hub import AssumedModesModel, HubBeamModes, HubMode, hub_assumed_modes, hub_beam_modes
from .modal import NORMALIZATIONS, BeamMode, ModalBeam, modal_beam
from .symbolic import SymbolicMode, beam_symbols, symbolic_modes

__all__ = [
    "BeamParameterError",
    "BOUNDARIES", "NORMALIZATIONS",
    "beam_eigenvalues", "hub_beam_eigenvalues",
    "characteristic_function", "hub_characteristic_function",
    "characteristic_expression", "hub_characteristic_expression",
    "BeamMode", "ModalBeam", "modal_beam",
    "SymbolicMode", "beam_symbols", "symbolic_modes",
    "HubMode", "HubBeamModes", "hub_beam_modes",
    "AssumedModesModel", "hub_assumed_modes",
]
