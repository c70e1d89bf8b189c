"""Modal description of a uniform Euler–Bernoulli beam (clamped- or pinned-free).

See the package docstring (:mod:`bondgraph.beam`) for the conventions.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _shapes
from ._validation import BeamParameterError, check_choice, check_float, check_int, check_per_mode
from .characteristic import BOUNDARIES, beam_eigenvalues

if TYPE_CHECKING:  # pragma: no cover
    from .symbolic import SymbolicMode

__all__ = ["NORMALIZATIONS", "BeamMode", "ModalBeam", "modal_beam"]

#: Mode-shape normalisations accepted by :func:`modal_beam`.
NORMALIZATIONS: tuple[str, ...] = ("mass", "tip", "length")


def _shape_eval(coef: tuple[float, ...], lam: float, L: float, x: ArrayLike,
                derivative: int) -> float | NDArray:
    if isinstance(derivative, bool) or derivative not in (0, 1, 2, 3, 4):
        raise BeamParameterError(f"derivative: expected 0, 1, 2, 3 or 4, got {derivative!r}")
    xa = np.asarray(x, dtype=float)
    if np.any(xa < -1e-12 * L) or np.any(xa > L * (1 + 1e-12)):
        raise BeamParameterError(f"x: expected positions in [0, L] = [0, {L}], got {x!r}")
    out = _shapes.evaluate(coef, lam, np.clip(xa / L, 0.0, 1.0), derivative) / L**derivative
    return float(out) if out.ndim == 0 else out


def _scale(normalization: str, gen_mass: float, tip: float, int_sq: float) -> tuple[float, float]:
    """``(s, m)``: factor scaling a shape to ``normalization`` and the modal mass it then has.

    ``gen_mass`` is the shape's generalised mass (SI), ``tip`` its tip value
    and ``int_sq`` the integral of its square over ``xi in [0, 1]``.
    """
    if normalization == "mass":
        return 1.0 / math.sqrt(gen_mass), 1.0
    s = 1.0 / tip if normalization == "tip" else 1.0 / math.sqrt(int_sq)
    return s, s**2 * gen_mass


@dataclass(frozen=True)
class BeamMode:
    """One flexible mode of a :class:`ModalBeam` (all quantities in SI units).

    Attributes
    ----------
    number : int
        Mode number, 1 for the fundamental flexible mode.
    betaL : float
        Dimensionless eigenvalue ``beta*L``.
    omega : float
        Natural frequency, rad/s: ``betaL**2 * sqrt(EI/(rhoA L**4))``.
    mass, stiffness, damping : float
        Modal mass ``m``, stiffness ``k = m omega**2`` and damping
        ``c = 2 zeta m omega`` of the coordinate ``eta`` in ``w = phi*eta``.
    damping_ratio : float
        ``zeta`` of this mode.
    root_slope, tip_value, tip_slope : float
        ``phi'(0)``, ``phi(L)``, ``phi'(L)``.
    linear_coupling : float
        ``int rhoA phi dx + M_t phi(L)`` (coupling with a rigid translation).
    angular_coupling : float
        ``int rhoA x phi dx + M_t L phi(L) + J_t phi'(L)`` (coupling with a
        rigid rotation about the root; zero for pinned-free modes).
    L : float
        Beam length.
    coefficients : tuple of 4 floats
        ``phi(x) = c0 cos(bx) + c1 sin(bx) + c2 exp(-bx) + c3 exp(-b(L-x))``.

    Examples
    --------
    >>> from bondgraph.beam import modal_beam
    >>> mode = modal_beam(1.0, 1.0, 1.0, 2).modes[0]
    >>> mode.number, round(mode.betaL, 6), round(mode.omega, 4), mode.mass
    (1, 1.875104, 3.516, 1.0)
    >>> round(mode.tip_value, 6), round(mode.frequency_hz, 4)  # mass-normalised: phi(L) = 2
    (2.0, 0.5596)
    """

    number: int
    betaL: float
    omega: float
    mass: float
    stiffness: float
    damping: float
    damping_ratio: float
    root_slope: float
    tip_value: float
    tip_slope: float
    linear_coupling: float
    angular_coupling: float
    L: float
    coefficients: tuple[float, float, float, float]

    @property
    def frequency_hz(self) -> float:
        """Natural frequency in Hz."""
        return self.omega / (2 * math.pi)

    def shape(self, x: ArrayLike, derivative: int = 0) -> float | NDArray:
        """Mode shape ``phi`` or its ``derivative``-th x-derivative (0..4) at ``x``.

        Examples
        --------
        >>> from bondgraph.beam import modal_beam
        >>> mode = modal_beam(1.0, 1.0, 1.0, 1, normalization="tip").modes[0]
        >>> round(mode.shape(1.0), 12), round(mode.shape(0.0, 1), 12)
        (1.0, 0.0)
        """
        return _shape_eval(self.coefficients, self.betaL, self.L, x, derivative)

    def phi(self, x: ArrayLike) -> float | NDArray:
        """``phi(x)``."""
        return self.shape(x, 0)

    def dphi(self, x: ArrayLike) -> float | NDArray:
        """``phi'(x)`` (slope)."""
        return self.shape(x, 1)

    def d2phi(self, x: ArrayLike) -> float | NDArray:
        """``phi''(x)`` (curvature; bending moment is ``EI phi'' eta``)."""
        return self.shape(x, 2)

    def d3phi(self, x: ArrayLike) -> float | NDArray:
        """``phi'''(x)`` (shear force is ``-EI phi''' eta``)."""
        return self.shape(x, 3)

    def hub_coupling(self, radius: float = 0.0) -> float:
        """``int rhoA (r+x) phi dx + M_t (r+L) phi(L) + J_t phi'(L)`` for hub radius ``r``.

        Examples
        --------
        >>> from bondgraph.beam import modal_beam
        >>> m = modal_beam(1.0, 1.0, 1.0, 1).modes[0]
        >>> abs(m.hub_coupling(0.5) - (m.angular_coupling + 0.5*m.linear_coupling)) < 1e-15
        True
        """
        r = check_float(radius, "radius", allow_zero=True)
        return self.angular_coupling + r * self.linear_coupling


@dataclass(frozen=True)
class ModalBeam:
    """Modal model of a uniform beam; build it with :func:`modal_beam`.

    Attributes
    ----------
    EI, rhoA, L : float
        Bending stiffness (N m^2), mass per length (kg/m), length (m).
    boundary : str
        ``"clamped-free"`` or ``"pinned-free"``.
    n_modes : int
        Number of flexible modes kept.
    tip_mass, tip_inertia : float
        Point mass (kg) and rotary inertia (kg m^2) at ``x = L``.
    normalization : str
        ``"mass"``, ``"tip"`` or ``"length"`` (see :func:`modal_beam`).
    betaL : tuple of float
        Eigenvalues ``beta_i L``.
    modes : tuple of BeamMode
        Per-mode data and shape functions.

    Examples
    --------
    >>> from bondgraph.beam import modal_beam
    >>> b = modal_beam(1.0, 1.0, 1.0, 2, boundary="pinned-free")
    >>> b.n_modes, [round(v, 4) for v in b.betaL], round(b.rigid_inertia, 6)
    (2, [3.9266, 7.0686], 0.333333)
    >>> b.modal_mass.tolist(), len(b.modes)
    ([1.0, 1.0], 2)
    """

    EI: float
    rhoA: float
    L: float
    boundary: str
    n_modes: int
    tip_mass: float
    tip_inertia: float
    normalization: str
    betaL: tuple[float, ...]
    modes: tuple[BeamMode, ...]

    def _col(self, name: str) -> NDArray:
        return np.array([getattr(m, name) for m in self.modes])

    @property
    def omega(self) -> NDArray:
        """Natural frequencies, rad/s."""
        return self._col("omega")

    @property
    def frequency_hz(self) -> NDArray:
        """Natural frequencies, Hz."""
        return self.omega / (2 * math.pi)

    @property
    def modal_mass(self) -> NDArray:
        """Modal masses ``m_i``."""
        return self._col("mass")

    @property
    def modal_stiffness(self) -> NDArray:
        """Modal stiffnesses ``k_i = m_i omega_i**2``."""
        return self._col("stiffness")

    @property
    def modal_damping(self) -> NDArray:
        """Modal damping ``c_i = 2 zeta_i m_i omega_i``."""
        return self._col("damping")

    @property
    def root_slope(self) -> NDArray:
        """``phi_i'(0)`` (input gain of a torque applied at the root)."""
        return self._col("root_slope")

    @property
    def tip_value(self) -> NDArray:
        """``phi_i(L)``."""
        return self._col("tip_value")

    @property
    def angular_coupling(self) -> NDArray:
        """Rigid-rotation couplings ``int rhoA x phi_i dx + M_t L phi_i(L) + J_t phi_i'(L)``."""
        return self._col("angular_coupling")

    @property
    def linear_coupling(self) -> NDArray:
        """Rigid-translation couplings ``int rhoA phi_i dx + M_t phi_i(L)``."""
        return self._col("linear_coupling")

    @property
    def mass_ratio(self) -> float:
        """``M_t/(rhoA L)``."""
        return self.tip_mass / (self.rhoA * self.L)

    @property
    def inertia_ratio(self) -> float:
        """``J_t/(rhoA L**3)``."""
        return self.tip_inertia / (self.rhoA * self.L**3)

    @property
    def rigid_inertia(self) -> float:
        """Inertia of the beam and tip body about the root: ``rhoA L^3/3 + M_t L^2 + J_t``.

        For ``"pinned-free"`` this is the modal mass of the rigid-body mode
        ``phi_0(x) = x`` (``betaL = 0``), which is not in :attr:`modes`.
        """
        return self.rhoA * self.L**3 / 3 + self.tip_mass * self.L**2 + self.tip_inertia

    def shapes(self, x: ArrayLike, derivative: int = 0) -> NDArray:
        """Array ``(n_modes,) + shape(x)`` of ``phi_i^(derivative)(x)``.

        Examples
        --------
        >>> from bondgraph.beam import modal_beam
        >>> modal_beam(1.0, 1.0, 2.0, 3).shapes([0.0, 2.0]).shape
        (3, 2)
        """
        return np.array([m.shape(x, derivative) for m in self.modes])

    def modal_receptance(self, omega: ArrayLike, *, x_out: float | None = None,
                         x_in: float | None = None) -> complex | NDArray:
        """Modal-sum receptance ``sum phi_i(x_out) phi_i(x_in) / (k_i - w^2 m_i + j w c_i)``.

        Deflection at ``x_out`` per unit transverse force at ``x_in`` (both
        default to the tip).  Pinned-free: the rigid-body mode is *not* included.

        Examples
        --------
        >>> from bondgraph.beam import modal_beam
        >>> b = modal_beam(1.0, 1.0, 1.0, 20)
        >>> round(b.modal_receptance(0.0).real, 5)  # static tip compliance L^3/(3 EI)
        0.33333
        """
        xo = self.L if x_out is None else x_out
        xi = self.L if x_in is None else x_in
        w = np.asarray(omega, dtype=float)
        out = np.zeros(w.shape, dtype=complex)
        for m in self.modes:
            out = out + m.shape(xo) * m.shape(xi) / (m.stiffness - w**2 * m.mass
                                                     + 1j * w * m.damping)
        return complex(out) if out.ndim == 0 else out

    def symbolic(self) -> tuple[SymbolicMode, ...]:
        """Sympy expressions of every mode, see :func:`bondgraph.beam.symbolic_modes`."""
        from .symbolic import symbolic_modes

        return symbolic_modes(self)


def _make_mode(number: int, lam: float, *, root: str, EI: float, rhoA: float, L: float,
               mu: float, j: float, normalization: str, zeta: float) -> BeamMode:
    a = _shapes.null_vector(_shapes.root_rows(root, lam) + _shapes.tip_rows(lam, mu=mu, j=j))
    ev = _shapes.evaluate
    if ev(a, lam, 1.0) < 0:
        a = -a
    psi1, dpsi1, dpsi0 = (float(ev(a, lam, x, n)) for x, n in ((1.0, 0), (1.0, 1), (0.0, 1)))
    int_sq = _shapes.integrate(lambda x: ev(a, lam, x) ** 2, lam)
    int_1 = _shapes.integrate(lambda x: ev(a, lam, x), lam)
    int_x = _shapes.integrate(lambda x: x * ev(a, lam, x), lam)
    c = int_sq + mu * psi1**2 + j * dpsi1**2  # generalised mass of psi over rhoA L
    s, mass = _scale(normalization, rhoA * L * c, psi1, int_sq)
    omega = lam**2 * math.sqrt(EI / (rhoA * L**4))
    return BeamMode(
        number=number, betaL=lam, omega=omega, mass=mass, stiffness=mass * omega**2,
        damping=2 * zeta * mass * omega, damping_ratio=zeta,
        root_slope=s * dpsi0 / L, tip_value=s * psi1, tip_slope=s * dpsi1 / L,
        linear_coupling=s * rhoA * L * (int_1 + mu * psi1),
        angular_coupling=s * rhoA * L**2 * (int_x + mu * psi1 + j * dpsi1),
        L=L, coefficients=tuple(float(v) for v in s * a))  # type: ignore[arg-type]


def modal_beam(EI: float, rhoA: float, L: float, n_modes: int, *,
               boundary: str = "clamped-free", tip_mass: float = 0.0, tip_inertia: float = 0.0,
               normalization: str = "mass",
               damping_ratio: float | Sequence[float] = 0.0) -> ModalBeam:
    """Natural modes of a uniform Euler–Bernoulli beam.

    Parameters
    ----------
    EI : float
        Bending stiffness ``E*I`` (N m^2), > 0.
    rhoA : float
        Mass per unit length (kg/m), > 0.
    L : float
        Length (m), > 0.
    n_modes : int
        Number of flexible modes, >= 1.
    boundary : {"clamped-free", "pinned-free"}, keyword-only
        ``"clamped-free"``: cantilever, ``w(0) = w'(0) = 0`` (beam clamped to
        a hub that is held fixed: the *constrained* modes).
        ``"pinned-free"``: ``w(0) = 0``, no root moment ``w''(0) = 0`` (beam
        on a hub of negligible inertia, the FLEXCAM model of Barbosa & Góes).
        The free tip has ``EI w''(L) = J_t omega^2 w'(L)`` and
        ``EI w'''(L) = -M_t omega^2 w(L)``.
    tip_mass, tip_inertia : float, keyword-only
        ``M_t`` (kg) and ``J_t`` (kg m^2) at the tip, >= 0.
    normalization : {"mass", "tip", "length"}, keyword-only
        ``"mass"``: ``int rhoA phi^2 dx + M_t phi(L)^2 + J_t phi'(L)^2 = 1``
        (so ``m_i = 1`` and ``k_i = omega_i^2``);
        ``"tip"``: ``phi(L) = 1`` (dimensionless shape, ``eta`` is the tip deflection);
        ``"length"``: ``int phi^2 dx = L`` (Blevins' dimensionless convention).
        Sign: always ``phi(L) > 0``.
    damping_ratio : float or sequence of float, keyword-only
        Modal damping ratio ``zeta_i`` (one value for all modes or one per mode).

    Returns
    -------
    ModalBeam

    Raises
    ------
    BeamParameterError
        Naming the bad argument and the expected values.

    Examples
    --------
    >>> from bondgraph.beam import modal_beam
    >>> b = modal_beam(1.0, 1.0, 1.0, 3)
    >>> [round(v, 6) for v in b.betaL]
    [1.875104, 4.694091, 7.854757]
    >>> [round(float(w), 4) for w in b.omega]
    [3.516, 22.0345, 61.6972]
    >>> b.modal_mass.tolist()
    [1.0, 1.0, 1.0]
    >>> t = modal_beam(1.0, 1.0, 1.0, 2, normalization="tip")
    >>> [round(float(m), 12) for m in t.modal_mass]  # rhoA L / 4 for every cantilever mode
    [0.25, 0.25]
    """
    EI_ = check_float(EI, "EI")
    rhoA_ = check_float(rhoA, "rhoA")
    L_ = check_float(L, "L")
    n = check_int(n_modes, "n_modes")
    check_choice(boundary, "boundary", BOUNDARIES)
    Mt = check_float(tip_mass, "tip_mass", allow_zero=True)
    Jt = check_float(tip_inertia, "tip_inertia", allow_zero=True)
    check_choice(normalization, "normalization", NORMALIZATIONS)
    zetas = check_per_mode(damping_ratio, "damping_ratio", n)
    mu, j = Mt / (rhoA_ * L_), Jt / (rhoA_ * L_**3)
    lams = beam_eigenvalues(boundary, n, mass_ratio=mu, inertia_ratio=j)
    root = "clamped" if boundary == "clamped-free" else "pinned"
    modes = tuple(_make_mode(i + 1, lam, root=root, EI=EI_, rhoA=rhoA_, L=L_, mu=mu, j=j,
                             normalization=normalization, zeta=zetas[i])
                  for i, lam in enumerate(lams))
    return ModalBeam(EI=EI_, rhoA=rhoA_, L=L_, boundary=boundary, n_modes=n, tip_mass=Mt,
                     tip_inertia=Jt, normalization=normalization, betaL=lams, modes=modes)
