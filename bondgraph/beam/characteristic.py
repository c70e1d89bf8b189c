"""Characteristic (frequency) equations of uniform Euler–Bernoulli beams.

All equations are written in the dimensionless eigenvalue ``lam = beta*L``
with ``beta**4 = rhoA*omega**2/EI`` and the dimensionless ratios

* ``mu  = M_t/(rhoA*L)``        tip mass over beam mass (``mass_ratio``),
* ``j   = J_t/(rhoA*L**3)``     tip rotary inertia (``inertia_ratio``),
* ``eta = J_h/(n_arms*rhoA*L**3)`` hub inertia per arm (``hub_ratio``),
* ``rho = r/L``                 hub radius (``radius_ratio``).

Classical (unscaled) forms, as returned symbolically by
:func:`characteristic_expression` / :func:`hub_characteristic_expression`::

    clamped-free + tip:  F(lam) = 1 + cos cosh + mu*lam*(cos sinh - sin cosh)
                                  - j*lam**3*(sin cosh + cos sinh)
                                  + mu*j*lam**4*(1 - cos cosh)
    pinned-free + tip:   P(lam) with rho = 0 (below); P = sin cosh - cos sinh
                         without tip, i.e. tan(lam) = tanh(lam)
    hub-beam (clamped to a free hub of inertia J_h at radius r):
                         H(lam) = eta*lam**3*F(lam) + P(lam), with
    P = (sin cosh - cos sinh) + 2 lam (rho + mu) sin sinh
        + lam**2 (rho**2 + 2 mu rho)(sin cosh + cos sinh)
        + 2 lam**3 (mu rho**2 + j) cos cosh - j lam**4 (2 rho + mu)(sin cosh - cos sinh)
        - 2 j lam**5 (mu rho + rho**2) sin sinh - j mu rho**2 lam**6 (sin cosh + cos sinh)

(``cos = cos(lam)`` etc.).  ``H`` is the determinant of the 4x4 boundary
condition matrix divided by ``2*lam**7``; the factor ``lam**10`` that was
removed holds the rigid-body root ``lam = 0``.  Limits: ``eta -> oo`` gives
the clamped-free equation ``F``; ``eta = rho = 0`` gives pinned-free.  With
``rho = mu = j = 0``, ``H = 0`` is the slewing-link equation of Barbieri &
Özgüner (1988), ``eta*lam**3*(1 + cos cosh) + sin cosh - cos sinh = 0``.

Numerically every function is divided by ``cosh(lam)`` (``sech`` computed
as ``2 exp(-lam)/(1 + exp(-2 lam))``), e.g. clamped-free becomes
``cos(lam) + sech(lam) = 0``, which never overflows.  Roots are bracketed by
a sign scan (geometric grid on ``[1e-3, 1]``, step ``pi/256`` above) and
polished by :func:`scipy.optimize.brentq` to ``~1e-15``.  Roots closer to each
other than the grid step (none occur for these problems) or below ``1e-3``
(``mu > 3e12``) would be missed.
"""

from __future__ import annotations

import math

import numpy as np
import sympy
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from .._support.sympify import as_expr
from ._validation import BeamParameterError, check_choice, check_float, check_int

__all__ = [
    "BOUNDARIES",
    "characteristic_function",
    "hub_characteristic_function",
    "beam_eigenvalues",
    "hub_beam_eigenvalues",
    "characteristic_expression",
    "hub_characteristic_expression",
]

#: Boundary conditions accepted by :func:`beam_eigenvalues` and ``modal_beam``.
BOUNDARIES: tuple[str, ...] = ("clamped-free", "pinned-free")

_LAM_MIN = 1e-3
_STEP = math.pi / 256


def _trig(lam: NDArray) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """``cos, sin, tanh, sech`` of ``lam >= 0`` without overflow."""
    e2 = np.exp(-2.0 * lam)
    return np.cos(lam), np.sin(lam), (1.0 - e2) / (1.0 + e2), 2.0 * np.exp(-lam) / (1.0 + e2)


def _f_clamped(lam: NDArray, mu: float, j: float) -> NDArray:
    c, s, t, sech = _trig(lam)
    return (sech + c + mu * lam * (c * t - s) - j * lam**3 * (s + c * t)
            + mu * j * lam**4 * (sech - c))


def _p_hub(lam: NDArray, rho: float, mu: float, j: float) -> NDArray:
    c, s, t, _ = _trig(lam)
    return ((s - c * t) + 2 * lam * (rho + mu) * s * t
            + lam**2 * (rho**2 + 2 * mu * rho) * (s + c * t)
            + 2 * lam**3 * (mu * rho**2 + j) * c
            - j * lam**4 * (2 * rho + mu) * (s - c * t)
            - 2 * j * lam**5 * (mu * rho + rho**2) * s * t
            - j * mu * rho**2 * lam**6 * (s + c * t))


def characteristic_function(boundary: str, betaL: ArrayLike, *, mass_ratio: float = 0.0,
                            inertia_ratio: float = 0.0) -> NDArray:
    """Evaluate the overflow-free characteristic function (divided by ``cosh``).

    Parameters
    ----------
    boundary : {"clamped-free", "pinned-free"}
        Root / tip conditions (a tip mass or rotary inertia may sit at the free end).
    betaL : array_like
        Dimensionless eigenvalue(s) ``beta*L >= 0``.
    mass_ratio, inertia_ratio : float, keyword-only
        ``M_t/(rhoA L)`` and ``J_t/(rhoA L**3)``.

    Returns
    -------
    numpy.ndarray
        ``F(lam)/cosh(lam)`` (clamped-free) or ``P(lam)/cosh(lam)`` (pinned-free).

    Examples
    --------
    >>> import numpy as np
    >>> from bondgraph.beam import characteristic_function
    >>> float(np.round(characteristic_function("clamped-free", 1.8751040687), 9))
    0.0
    >>> float(characteristic_function("clamped-free", 1000.0))  # no overflow
    0.5623790762907029
    """
    check_choice(boundary, "boundary", BOUNDARIES)
    mu = check_float(mass_ratio, "mass_ratio", allow_zero=True)
    j = check_float(inertia_ratio, "inertia_ratio", allow_zero=True)
    lam = np.asarray(betaL, dtype=float)
    if boundary == "clamped-free":
        return _f_clamped(lam, mu, j)
    return _p_hub(lam, 0.0, mu, j)


def hub_characteristic_function(betaL: ArrayLike, *, hub_ratio: float, radius_ratio: float = 0.0,
                                mass_ratio: float = 0.0, inertia_ratio: float = 0.0) -> NDArray:
    """Evaluate ``H(lam)/cosh(lam)`` of a beam clamped to a free rigid hub.

    Parameters
    ----------
    betaL : array_like
        Dimensionless eigenvalue(s) ``beta*L >= 0``.
    hub_ratio : float, keyword-only
        ``eta = J_h/(n_arms*rhoA*L**3)`` (hub inertia shared by ``n_arms``
        identical arms deforming symmetrically).
    radius_ratio, mass_ratio, inertia_ratio : float, keyword-only
        ``r/L``, ``M_t/(rhoA L)``, ``J_t/(rhoA L**3)``.

    Returns
    -------
    numpy.ndarray

    Examples
    --------
    >>> from bondgraph.beam import hub_characteristic_function
    >>> float(hub_characteristic_function(1.0, hub_ratio=0.0))  # pinned-free limit
    0.4299799062092971
    """
    eta = check_float(hub_ratio, "hub_ratio", allow_zero=True)
    rho = check_float(radius_ratio, "radius_ratio", allow_zero=True)
    mu = check_float(mass_ratio, "mass_ratio", allow_zero=True)
    j = check_float(inertia_ratio, "inertia_ratio", allow_zero=True)
    lam = np.asarray(betaL, dtype=float)
    return eta * lam**3 * _f_clamped(lam, mu, j) + _p_hub(lam, rho, mu, j)


def _roots(func, n: int) -> tuple[float, ...]:
    """First ``n`` positive roots of ``func`` by sign scan + brentq."""
    roots: list[float] = []
    grid = np.concatenate([np.geomspace(_LAM_MIN, 1.0, 64, endpoint=False),
                           np.arange(1.0, (n + 3) * math.pi, _STEP)])
    while True:
        vals = func(grid)
        if not np.all(np.isfinite(vals)):  # pragma: no cover - defensive
            raise BeamParameterError("n_modes: characteristic function is not finite on the "
                                     "search grid; expected fewer modes or smaller ratios")
        hits = np.nonzero((vals[:-1] == 0.0) | (vals[:-1] * vals[1:] < 0.0))[0]
        for k in hits:
            if vals[k] == 0.0:
                roots.append(float(grid[k]))
            else:
                roots.append(float(brentq(lambda z: float(func(np.float64(z))),
                                          grid[k], grid[k + 1], xtol=1e-15,
                                          rtol=4 * np.finfo(float).eps, maxiter=200)))
            if len(roots) == n:
                return tuple(roots)
        top = grid[-1]
        grid = np.arange(top, top + (n - len(roots) + 3) * math.pi, _STEP)


def beam_eigenvalues(boundary: str, n_modes: int, *, mass_ratio: float = 0.0,
                     inertia_ratio: float = 0.0) -> tuple[float, ...]:
    """First ``n_modes`` flexible eigenvalues ``beta_i*L`` of a uniform beam.

    Parameters
    ----------
    boundary : {"clamped-free", "pinned-free"}
        Root condition (clamped: ``w = w' = 0``; pinned: ``w = w'' = 0``) and a
        free tip, optionally carrying a point mass and rotary inertia.
    n_modes : int
        Number of flexible modes (>= 1).  The pinned-free rigid-body root
        ``beta*L = 0`` (shape ``phi = x``) is never included.
    mass_ratio, inertia_ratio : float, keyword-only
        ``M_t/(rhoA L)`` and ``J_t/(rhoA L**3)`` (default 0).

    Returns
    -------
    tuple of float
        Increasing roots, accurate to about ``1e-14``.

    Examples
    --------
    >>> from bondgraph.beam import beam_eigenvalues
    >>> [round(v, 6) for v in beam_eigenvalues("clamped-free", 3)]
    [1.875104, 4.694091, 7.854757]
    >>> [round(v, 6) for v in beam_eigenvalues("pinned-free", 3)]
    [3.926602, 7.068583, 10.210176]
    """
    check_choice(boundary, "boundary", BOUNDARIES)
    n = check_int(n_modes, "n_modes")
    mu = check_float(mass_ratio, "mass_ratio", allow_zero=True)
    j = check_float(inertia_ratio, "inertia_ratio", allow_zero=True)
    if boundary == "clamped-free":
        return _roots(lambda z: _f_clamped(z, mu, j), n)
    return _roots(lambda z: _p_hub(z, 0.0, mu, j), n)


def hub_beam_eigenvalues(n_modes: int, *, hub_ratio: float, radius_ratio: float = 0.0,
                         mass_ratio: float = 0.0, inertia_ratio: float = 0.0) -> tuple[float, ...]:
    """Flexible eigenvalues ``beta_i*L`` of the free hub + clamped beam system.

    These are the "unconstrained" (system) modes of a slewing beam; the
    rigid-body root ``0`` is excluded.

    Parameters
    ----------
    n_modes : int
        Number of flexible modes (>= 1).
    hub_ratio : float, keyword-only
        ``J_h/(n_arms*rhoA*L**3)``; 0 with ``radius_ratio = 0`` is pinned-free.
    radius_ratio, mass_ratio, inertia_ratio : float, keyword-only
        ``r/L``, ``M_t/(rhoA L)``, ``J_t/(rhoA L**3)``.

    Returns
    -------
    tuple of float

    Examples
    --------
    >>> from bondgraph.beam import hub_beam_eigenvalues
    >>> [round(v, 4) for v in hub_beam_eigenvalues(2, hub_ratio=1.0)]
    [2.01, 4.7038]
    """
    n = check_int(n_modes, "n_modes")
    eta = check_float(hub_ratio, "hub_ratio", allow_zero=True)
    rho = check_float(radius_ratio, "radius_ratio", allow_zero=True)
    mu = check_float(mass_ratio, "mass_ratio", allow_zero=True)
    j = check_float(inertia_ratio, "inertia_ratio", allow_zero=True)
    return _roots(lambda z: eta * z**3 * _f_clamped(z, mu, j) + _p_hub(z, rho, mu, j), n)


BETA_L = sympy.Symbol("betaL", positive=True)


def _sym_parts(lam: sympy.Symbol):
    return sympy.cos(lam), sympy.sin(lam), sympy.cosh(lam), sympy.sinh(lam)


def characteristic_expression(boundary: str, *, mass_ratio: object = 0,
                              inertia_ratio: object = 0) -> sympy.Expr:
    """Classical (unscaled) characteristic expression in ``betaL`` as sympy.

    The ratios may be numbers or sympy symbols.  Zeros of the expression in
    ``betaL > 0`` are the flexible eigenvalues.

    Parameters
    ----------
    boundary : {"clamped-free", "pinned-free"}
    mass_ratio, inertia_ratio : number or sympy.Expr, keyword-only
        ``M_t/(rhoA L)`` and ``J_t/(rhoA L**3)``.

    Returns
    -------
    sympy.Expr
        In the positive symbol ``betaL``.

    Examples
    --------
    >>> from bondgraph.beam import characteristic_expression
    >>> characteristic_expression("clamped-free")
    cos(betaL)*cosh(betaL) + 1
    >>> characteristic_expression("pinned-free")
    sin(betaL)*cosh(betaL) - cos(betaL)*sinh(betaL)
    """
    check_choice(boundary, "boundary", BOUNDARIES)
    mu = as_expr(mass_ratio, what="mass_ratio", error=BeamParameterError)
    j = as_expr(inertia_ratio, what="inertia_ratio", error=BeamParameterError)
    lam = BETA_L
    c, s, ch, sh = _sym_parts(lam)
    if boundary == "clamped-free":
        return (1 + c * ch + mu * lam * (c * sh - s * ch) - j * lam**3 * (s * ch + c * sh)
                + mu * j * lam**4 * (1 - c * ch))
    return _sym_p(0, mu, j)


def _sym_p(rho, mu, j) -> sympy.Expr:
    lam = BETA_L
    c, s, ch, sh = _sym_parts(lam)
    return ((s * ch - c * sh) + 2 * lam * (rho + mu) * s * sh
            + lam**2 * (rho**2 + 2 * mu * rho) * (s * ch + c * sh)
            + 2 * lam**3 * (mu * rho**2 + j) * c * ch
            - j * lam**4 * (2 * rho + mu) * (s * ch - c * sh)
            - 2 * j * lam**5 * (mu * rho + rho**2) * s * sh
            - j * mu * rho**2 * lam**6 * (s * ch + c * sh))


def hub_characteristic_expression(*, hub_ratio: object, radius_ratio: object = 0,
                                  mass_ratio: object = 0, inertia_ratio: object = 0) -> sympy.Expr:
    """Classical characteristic expression ``H(betaL)`` of the hub + beam system.

    Parameters
    ----------
    hub_ratio, radius_ratio, mass_ratio, inertia_ratio : number or sympy.Expr
        ``J_h/(n_arms rhoA L**3)``, ``r/L``, ``M_t/(rhoA L)``, ``J_t/(rhoA L**3)``.

    Returns
    -------
    sympy.Expr

    Examples
    --------
    >>> import sympy
    >>> from bondgraph.beam import hub_characteristic_expression
    >>> eta = sympy.Symbol("eta")
    >>> hub_characteristic_expression(hub_ratio=eta)
    betaL**3*eta*(cos(betaL)*cosh(betaL) + 1) + sin(betaL)*cosh(betaL) - cos(betaL)*sinh(betaL)
    """
    eta = as_expr(hub_ratio, what="hub_ratio", error=BeamParameterError)
    rho = as_expr(radius_ratio, what="radius_ratio", error=BeamParameterError)
    mu = as_expr(mass_ratio, what="mass_ratio", error=BeamParameterError)
    j = as_expr(inertia_ratio, what="inertia_ratio", error=BeamParameterError)
    f = characteristic_expression("clamped-free", mass_ratio=mu, inertia_ratio=j)
    return eta * BETA_L**3 * f + _sym_p(rho, mu, j)
