"""Sympy expressions for the modes of a :class:`~bondgraph.beam.ModalBeam`.

The expressions are in the symbols ``EI``, ``rhoA``, ``L`` and ``x`` (all
positive).  The dimensionless eigenvalue ``beta_i L`` and the shape
coefficients are numeric constants (``sympy.Float``); they depend only on the
boundary condition and on the dimensionless ratios ``M_t/(rhoA L)`` and
``J_t/(rhoA L^3)``, which are held at the values of the numeric beam.  So
``omega_i = (beta_i L)**2*sqrt(EI/(rhoA*L**4))`` is exact in ``EI, rhoA, L``
for a beam without a tip body, and exact at fixed mass ratios otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import sympy

class _Beam(Protocol):
    """What :func:`symbolic_modes` reads of a :class:`~bondgraph.beam.ModalBeam`."""

    @property
    def modes(self) -> tuple: ...
    @property
    def normalization(self) -> str: ...
    @property
    def rhoA(self) -> float: ...
    @property
    def L(self) -> float: ...

__all__ = ["SymbolicMode", "beam_symbols", "symbolic_modes"]


def beam_symbols() -> tuple[sympy.Symbol, sympy.Symbol, sympy.Symbol, sympy.Symbol]:
    """The positive symbols ``(EI, rhoA, L, x)`` used by :func:`symbolic_modes`.

    Examples
    --------
    >>> from bondgraph.beam import beam_symbols
    >>> beam_symbols()
    (EI, rhoA, L, x)
    """
    return sympy.symbols("EI rhoA L x", positive=True)


@dataclass(frozen=True)
class SymbolicMode:
    """Sympy expressions of one mode (see :func:`symbolic_modes`).

    Attributes
    ----------
    number : int
        Mode number (1 = fundamental flexible mode).
    betaL : sympy.Float
        Dimensionless eigenvalue.
    omega, mass, stiffness, damping : sympy.Expr
        ``omega_i``, ``m_i``, ``k_i = m_i omega_i^2``, ``c_i = 2 zeta_i m_i omega_i``.
    phi : sympy.Expr
        Shape ``phi_i(x)`` in the bounded form
        ``c0 cos(b x) + c1 sin(b x) + c2 exp(-b x) + c3 exp(-b (L - x))``, ``b = betaL/L``.

    Examples
    --------
    >>> from bondgraph.beam import modal_beam, beam_symbols
    >>> EI, rhoA, L, x = beam_symbols()
    >>> mode = modal_beam(1.0, 1.0, 1.0, 1, normalization="tip").symbolic()[0]
    >>> mode.number, round(float(mode.betaL), 6), mode.mass, mode.damping
    (1, 1.875104, 0.25*L*rhoA, 0)
    >>> mode.stiffness.free_symbols == {EI, L}       # k = m omega^2: rhoA cancels
    True
    """

    number: int
    betaL: sympy.Float
    omega: sympy.Expr
    mass: sympy.Expr
    stiffness: sympy.Expr
    damping: sympy.Expr
    phi: sympy.Expr


def symbolic_modes(beam: _Beam) -> tuple[SymbolicMode, ...]:
    """Sympy expressions (in ``EI, rhoA, L, x``) for every mode of ``beam``.

    With ``normalization="mass"`` the shape carries the factor
    ``1/sqrt(rhoA*L)`` and ``m_i = 1``; with ``"tip"`` or ``"length"`` the
    shape is dimensionless and ``m_i = const*rhoA*L``.

    Parameters
    ----------
    beam : ModalBeam

    Returns
    -------
    tuple of SymbolicMode

    Examples
    --------
    >>> import sympy
    >>> from bondgraph.beam import modal_beam, beam_symbols, symbolic_modes
    >>> EI, rhoA, L, x = beam_symbols()
    >>> m1 = symbolic_modes(modal_beam(2.0, 0.5, 1.5, 1, normalization="tip"))[0]
    >>> m1.omega
    3.51601526850015*sqrt(EI)/(L**2*sqrt(rhoA))
    >>> m1.mass
    0.25*L*rhoA
    >>> round(float(m1.phi.subs({L: 1.5, x: 1.5})), 12)
    1.0
    """
    EI, rhoA, L, x = beam_symbols()
    out = []
    for mode in beam.modes:
        lam = sympy.Float(mode.betaL)
        omega = lam**2 * sympy.sqrt(EI / (rhoA * L**4))
        b = lam / L
        basis = (sympy.cos(b * x), sympy.sin(b * x), sympy.exp(-b * x), sympy.exp(-b * (L - x)))
        if beam.normalization == "mass":
            root = (beam.rhoA * beam.L) ** 0.5
            coef = [sympy.Float(c * root) for c in mode.coefficients]
            phi = sum(c * f for c, f in zip(coef, basis)) / sympy.sqrt(rhoA * L)
            mass: sympy.Expr = sympy.Integer(1)
        else:
            coef = [sympy.Float(c) for c in mode.coefficients]
            phi = sum(c * f for c, f in zip(coef, basis))
            mass = sympy.Float(round(mode.mass / (beam.rhoA * beam.L), 14)) * rhoA * L
        zeta = sympy.Float(mode.damping_ratio)
        out.append(SymbolicMode(number=mode.number, betaL=lam, omega=omega, mass=mass,
                                stiffness=mass * omega**2, damping=2 * zeta * mass * omega,
                                phi=phi))
    return tuple(out)
