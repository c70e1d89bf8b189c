"""Beam(s) clamped to a free rigid hub: unconstrained (system) modes.

Geometry (Soares, Góes & Souza, Eq. 1): the hub (inertia ``J_h``, angle
``theta``) carries ``n_arms`` identical beams clamped at radius ``r``; ``x``
runs from the beam root (``0``) to the tip (``L``).  ``w(x, t)`` is the
*absolute* transverse deflection ``(r + x) theta + y(x, t)``, with ``y`` the
elastic deflection in the hub frame.  Linear theory, no centrifugal
stiffening; all arms deform alike (for two opposite arms this is the
antisymmetric family driven by a hub torque).

Exact model: ``EI w'''' + rhoA w_tt = 0`` with ::

    w(0) = r theta,  w'(0) = theta                       (clamp on the hub)
    J_h theta_tt = tau + n_arms (EI w''(0) - r EI w'''(0))  (hub equation)
    EI w''(L) = -J_t w'_tt(L),  EI w'''(L) = M_t w_tt(L)  (tip body)

whose frequency equation is ``H(beta L) = 0`` of
:mod:`bondgraph.beam.characteristic`.  :func:`hub_beam_modes` returns those
modes; :func:`hub_assumed_modes` builds the Rayleigh–Ritz (assumed-modes)
model ``M q'' + C q' + K q = B tau`` with ``q = [theta, eta_1..eta_n]`` from a
:class:`~bondgraph.beam.ModalBeam` basis, which converges to them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import eigh

from . import _shapes
from ._validation import BeamParameterError, check_choice, check_float, check_int
from .characteristic import hub_beam_eigenvalues
from .modal import NORMALIZATIONS, ModalBeam, _scale, _shape_eval

__all__ = ["HubMode", "HubBeamModes", "hub_beam_modes", "AssumedModesModel",
           "hub_assumed_modes"]

_OUTPUTS = ("hub", "tip")


@dataclass(frozen=True)
class HubMode:
    """One flexible (unconstrained) mode of the hub + beam system.

    Attributes
    ----------
    number : int
        Mode number (1 = first flexible mode; the rigid-body mode is excluded).
    betaL, omega : float
        Eigenvalue ``beta L`` and natural frequency (rad/s).
    mass : float
        Modal mass ``J_h Theta^2 + n_arms (int rhoA w^2 dx + M_t w(L)^2 + J_t w'(L)^2)``.
    hub_angle : float
        ``Theta = w'(0)``: hub rotation of the mode (torque input gain).
    tip_value : float
        Absolute tip deflection ``w(L)`` (positive by convention).
    L : float
        Beam length.
    coefficients : tuple of 4 floats
        ``w(x) = c0 cos(bx) + c1 sin(bx) + c2 exp(-bx) + c3 exp(-b(L-x))``.

    Examples
    --------
    >>> from bondgraph.beam import hub_beam_modes
    >>> mode = hub_beam_modes(1.0, 1.0, 1.0, 2, hub_inertia=1.0).modes[0]
    >>> mode.number, round(mode.betaL, 4), round(mode.omega, 4), round(mode.hub_angle, 6)
    (1, 2.01, 4.0401, -0.490086)
    >>> abs(mode.shape(1.0) - mode.tip_value) < 1e-12
    True
    """

    number: int
    betaL: float
    omega: float
    mass: float
    hub_angle: float
    tip_value: float
    L: float
    coefficients: tuple[float, float, float, float]

    @property
    def frequency_hz(self) -> float:
        """Natural frequency in Hz."""
        return self.omega / (2 * math.pi)

    def shape(self, x: ArrayLike, derivative: int = 0) -> float | NDArray:
        """Absolute deflection shape ``w(x)`` or an x-derivative (0..4)."""
        return _shape_eval(self.coefficients, self.betaL, self.L, x, derivative)


@dataclass(frozen=True)
class HubBeamModes:
    """Exact unconstrained modes of a hub with ``n_arms`` clamped beams.

    Built by :func:`hub_beam_modes`; attributes mirror its arguments plus
    ``betaL`` and ``modes`` (tuple of :class:`HubMode`).

    Examples
    --------
    >>> from bondgraph.beam import hub_beam_modes
    >>> s = hub_beam_modes(1.0, 1.0, 1.0, 2, hub_inertia=1.0)
    >>> s.n_modes, round(s.total_inertia, 6), [round(float(w), 4) for w in s.omega]
    (2, 1.333333, [4.0401, 22.1257])
    """

    EI: float
    rhoA: float
    L: float
    n_modes: int
    hub_inertia: float
    hub_radius: float
    n_arms: int
    tip_mass: float
    tip_inertia: float
    normalization: str
    betaL: tuple[float, ...]
    modes: tuple[HubMode, ...]

    @property
    def omega(self) -> NDArray:
        """Flexible natural frequencies, rad/s."""
        return np.array([m.omega for m in self.modes])

    @property
    def frequency_hz(self) -> NDArray:
        """Flexible natural frequencies, Hz."""
        return self.omega / (2 * math.pi)

    @property
    def total_inertia(self) -> float:
        """Rigid-body inertia ``J_h + n (rhoA((r+L)^3 - r^3)/3 + M_t (r+L)^2 + J_t)``."""
        r, L = self.hub_radius, self.L
        return self.hub_inertia + self.n_arms * (
            self.rhoA * ((r + L) ** 3 - r**3) / 3 + self.tip_mass * (r + L) ** 2
            + self.tip_inertia)

    def torque_receptance(self, omega: ArrayLike, *, output: str = "hub") -> complex | NDArray:
        """Undamped hub-torque receptance from the exact modes (rigid mode included).

        ``output="hub"``: hub angle per torque,
        ``-1/(J_tot w^2) + sum Theta_i^2/(m_i (w_i^2 - w^2))``;
        ``output="tip"``: absolute tip deflection per torque (``(r+L)`` and
        ``Theta_i w_i(L)`` in the numerators).

        Examples
        --------
        >>> from bondgraph.beam import hub_beam_modes
        >>> s = hub_beam_modes(1.0, 1.0, 1.0, 30, hub_inertia=100.0)
        >>> round(-1/(1e-6*s.torque_receptance(1e-3).real), 6)  # ~ J_tot = 100 + 1/3
        100.333333
        """
        check_choice(output, "output", _OUTPUTS)
        w2 = np.asarray(omega, dtype=float) ** 2
        if np.any(w2 == 0):
            raise BeamParameterError("omega: expected nonzero frequencies (rigid-body pole at 0)")
        lever = 1.0 if output == "hub" else self.hub_radius + self.L
        out = -lever / (self.total_inertia * w2) + 0j
        for m in self.modes:
            gain = m.hub_angle if output == "hub" else m.tip_value
            out = out + m.hub_angle * gain / (m.mass * (m.omega**2 - w2))
        return complex(out) if np.ndim(out) == 0 else out


def hub_beam_modes(EI: float, rhoA: float, L: float, n_modes: int, *, hub_inertia: float,
                   hub_radius: float = 0.0, n_arms: int = 1, tip_mass: float = 0.0,
                   tip_inertia: float = 0.0, normalization: str = "mass") -> HubBeamModes:
    """Exact unconstrained modes of a free hub carrying clamped beams.

    Parameters
    ----------
    EI, rhoA, L : float
        Beam bending stiffness, mass per length and length (> 0).
    n_modes : int
        Number of flexible modes (>= 1).
    hub_inertia : float, keyword-only
        ``J_h`` (kg m^2) of the rigid hub alone, >= 0.
    hub_radius : float, keyword-only
        ``r``: distance from the rotation axis to the beam root, >= 0.
    n_arms : int, keyword-only
        Number of identical arms deforming alike (each takes ``J_h/n_arms``).
    tip_mass, tip_inertia : float, keyword-only
        Tip body of each arm.
    normalization : {"mass", "tip", "length"}, keyword-only
        As in :func:`~bondgraph.beam.modal_beam`, with the mass including
        ``J_h Theta^2`` and all arms; ``"tip"`` sets ``w(L) = 1`` (absolute).

    Returns
    -------
    HubBeamModes

    Examples
    --------
    >>> from bondgraph.beam import hub_beam_modes
    >>> s = hub_beam_modes(1.0, 1.0, 1.0, 2, hub_inertia=1.0)
    >>> [round(v, 4) for v in s.betaL]
    [2.01, 4.7038]
    """
    EI_, rhoA_, L_ = check_float(EI, "EI"), check_float(rhoA, "rhoA"), check_float(L, "L")
    n = check_int(n_modes, "n_modes")
    Jh = check_float(hub_inertia, "hub_inertia", allow_zero=True)
    r = check_float(hub_radius, "hub_radius", allow_zero=True)
    arms = check_int(n_arms, "n_arms")
    Mt = check_float(tip_mass, "tip_mass", allow_zero=True)
    Jt = check_float(tip_inertia, "tip_inertia", allow_zero=True)
    check_choice(normalization, "normalization", NORMALIZATIONS)
    eta, rho = Jh / (arms * rhoA_ * L_**3), r / L_
    mu, j = Mt / (rhoA_ * L_), Jt / (rhoA_ * L_**3)
    lams = hub_beam_eigenvalues(n, hub_ratio=eta, radius_ratio=rho, mass_ratio=mu,
                                inertia_ratio=j)
    ev = _shapes.evaluate
    modes = []
    for k, lam in enumerate(lams):
        a = _shapes.null_vector(_shapes.root_rows("hub", lam, rho=rho, eta=eta)
                                + _shapes.tip_rows(lam, mu=mu, j=j))
        psi1, dpsi1, dpsi0 = (float(ev(a, lam, x, d)) for x, d in ((1.0, 0), (1.0, 1), (0.0, 1)))
        sign = psi1 if abs(psi1) > 1e-9 * np.max(np.abs(a)) else dpsi0
        if sign < 0:
            a, psi1, dpsi1, dpsi0 = -a, -psi1, -dpsi1, -dpsi0
        int_sq = _shapes.integrate(lambda x: ev(a, lam, x) ** 2, lam)
        c = eta * dpsi0**2 + int_sq + mu * psi1**2 + j * dpsi1**2
        s, mass = _scale(normalization, arms * rhoA_ * L_ * c, psi1, int_sq)
        modes.append(HubMode(
            number=k + 1, betaL=lam, omega=lam**2 * math.sqrt(EI_ / (rhoA_ * L_**4)), mass=mass,
            hub_angle=s * dpsi0 / L_, tip_value=s * psi1, L=L_,
            coefficients=tuple(float(v) for v in s * a)))  # type: ignore[arg-type]
    return HubBeamModes(EI=EI_, rhoA=rhoA_, L=L_, n_modes=n, hub_inertia=Jh, hub_radius=r,
                        n_arms=arms, tip_mass=Mt, tip_inertia=Jt, normalization=normalization,
                        betaL=lams, modes=tuple(modes))


@dataclass(frozen=True)
class AssumedModesModel:
    """Rayleigh–Ritz hub + beam model ``M q'' + C q' + K q = B tau``.

    ``q = (theta, eta_1, ..., eta_n)``: ``theta`` is the angle of the frame in
    which the beam modes are measured, ``w(x) = (r + x) theta + sum phi_i(x) eta_i``;
    the hub angle is ``theta + sum phi_i'(0) eta_i`` (equal to ``theta`` for
    clamped-free modes).  Matrices are stored as nested tuples; use
    :meth:`matrices` for arrays.

    Attributes
    ----------
    coordinates : tuple of str
        ``("theta", "eta1", ...)``.
    mass_matrix, damping_matrix, stiffness_matrix : tuple of tuples
    torque_input : tuple of float
        ``B`` for a hub torque (also the hub-angle output row).
    tip_output : tuple of float
        Row giving the absolute tip deflection ``w(L)``.

    Examples
    --------
    >>> from bondgraph.beam import modal_beam, hub_assumed_modes
    >>> model = hub_assumed_modes(modal_beam(1.0, 1.0, 1.0, 2), hub_inertia=1.0)
    >>> M, C, K = model.matrices()
    >>> M.shape, model.torque_input, [round(v, 6) for v in model.tip_output]
    ((3, 3), (1.0, 0.0, 0.0), [1.0, 2.0, 2.0])
    >>> round(float(M[0, 0]), 6)          # J_h + rhoA L^3/3
    1.333333
    """

    coordinates: tuple[str, ...]
    mass_matrix: tuple[tuple[float, ...], ...]
    damping_matrix: tuple[tuple[float, ...], ...]
    stiffness_matrix: tuple[tuple[float, ...], ...]
    torque_input: tuple[float, ...]
    tip_output: tuple[float, ...]

    def matrices(self) -> tuple[NDArray, NDArray, NDArray]:
        """``(M, C, K)`` as numpy arrays."""
        return (np.array(self.mass_matrix), np.array(self.damping_matrix),
                np.array(self.stiffness_matrix))

    def frequencies(self) -> NDArray:
        """Flexible natural frequencies (rad/s), rigid-body mode removed.

        Examples
        --------
        >>> from bondgraph.beam import modal_beam, hub_assumed_modes
        >>> model = hub_assumed_modes(modal_beam(1.0, 1.0, 1.0, 8), hub_inertia=1.0)
        >>> [round(float(w) ** 0.5, 3) for w in model.frequencies()[:2]]  # sqrt(omega) = betaL
        [2.01, 4.704]
        """
        M, _, K = self.matrices()
        w2 = eigh(K, M, eigvals_only=True)
        return np.sqrt(np.clip(np.sort(w2)[1:], 0.0, None))

    def receptance(self, omega: ArrayLike, *, output: str = "hub") -> complex | NDArray:
        """Torque receptance ``c (K - w^2 M + j w C)^-1 B`` (``output`` "hub" or "tip")."""
        check_choice(output, "output", _OUTPUTS)
        M, C, K = self.matrices()
        B = np.array(self.torque_input)
        row = B if output == "hub" else np.array(self.tip_output)
        w = np.asarray(omega, dtype=float)
        vals = [row @ np.linalg.solve(K - wk**2 * M + 1j * wk * C, B) for wk in w.ravel()]
        out = np.array(vals, dtype=complex).reshape(w.shape)
        return complex(out) if out.ndim == 0 else out


def hub_assumed_modes(beam: ModalBeam, *, hub_inertia: float, hub_radius: float = 0.0,
                      n_arms: int = 1) -> AssumedModesModel:
    """Assumed-modes model of a free hub carrying ``n_arms`` copies of ``beam``.

    ``M = J_h e e^T + n_arms M_b``, with ``e = (1, phi_1'(0), ...)`` and the
    per-arm beam block ::

        M_b = [[I_r,  h^T      ],   I_r = int rhoA (r+x)^2 dx + M_t (r+L)^2 + J_t
               [h,    diag(m_i)]]   h_i = BeamMode.hub_coupling(r)

    ``K = n_arms diag(0, k_i)``, ``C = n_arms diag(0, c_i)``, ``B = e``.

    Parameters
    ----------
    beam : ModalBeam
        Basis: ``"clamped-free"`` modes (any ``r``, tip body allowed) or
        ``"pinned-free"`` modes (then ``hub_radius`` must be 0; the root slope
        ``phi_i'(0)`` adds to the hub angle, Barbosa & Góes Eq. 5).
    hub_inertia : float, keyword-only
        ``J_h`` >= 0.
    hub_radius : float, keyword-only
        ``r`` >= 0.
    n_arms : int, keyword-only
        Identical arms deforming alike.

    Returns
    -------
    AssumedModesModel

    Examples
    --------
    >>> from bondgraph.beam import modal_beam, hub_assumed_modes
    >>> model = hub_assumed_modes(modal_beam(1.0, 1.0, 1.0, 2), hub_inertia=1.0)
    >>> model.coordinates
    ('theta', 'eta1', 'eta2')
    """
    if not isinstance(beam, ModalBeam):
        raise BeamParameterError(f"beam: expected a ModalBeam, got {type(beam).__name__}")
    Jh = check_float(hub_inertia, "hub_inertia", allow_zero=True)
    r = check_float(hub_radius, "hub_radius", allow_zero=True)
    arms = check_int(n_arms, "n_arms")
    if beam.boundary == "pinned-free" and r != 0.0:
        raise BeamParameterError(
            f"hub_radius: expected 0 with a pinned-free basis (pin on the hub axis), got {r}; "
            "use a clamped-free basis for a beam root off the axis")
    n = beam.n_modes
    e = np.concatenate([[1.0], beam.root_slope if beam.boundary == "pinned-free"
                        else np.zeros(n)])
    L = beam.L
    Mb = np.zeros((n + 1, n + 1))
    Mb[0, 0] = (beam.rhoA * ((r + L) ** 3 - r**3) / 3 + beam.tip_mass * (r + L) ** 2
                + beam.tip_inertia)
    h = np.array([m.hub_coupling(r) for m in beam.modes])
    Mb[0, 1:] = Mb[1:, 0] = h
    Mb[1:, 1:] = np.diag(beam.modal_mass)
    M = Jh * np.outer(e, e) + arms * Mb
    K = arms * np.diag(np.concatenate([[0.0], beam.modal_stiffness]))
    C = arms * np.diag(np.concatenate([[0.0], beam.modal_damping]))

    def tup(a: NDArray) -> tuple[tuple[float, ...], ...]:
        return tuple(tuple(float(v) for v in row) for row in a)

    return AssumedModesModel(
        coordinates=("theta",) + tuple(f"eta{i + 1}" for i in range(n)),
        mass_matrix=tup(M), damping_matrix=tup(C), stiffness_matrix=tup(K),
        torque_input=tuple(float(v) for v in e),
        tip_output=tuple(float(v) for v in np.concatenate([[r + L], beam.tip_value])))
