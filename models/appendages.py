"""Hub on a gas bearing with two flexible aluminium appendages (seeds 001/002).

Model
-----
A rigid hub (``I_hub``, radius ``r``) carries two identical aluminium beams
clamped at its rim, each with an optional tip mass (the accelerometer, whose
mass the paper does not list; default 0).  The hub turns freely (gas
bearing); a brushless motor applies the torque ``tau``.  The arms are taken
to deform alike (antisymmetric about the axis), as the paper assumes, so one
set of modal coordinates describes both.

Reading of the equations (seed 001 Eqs. 15-20)
----------------------------------------------
The extracted Eqs. (11), (13) and (17) are partly garbled, and taken
literally the mass matrix of Eq. (16) is lower-triangular (not symmetric):
its coupling column ``I_j`` multiplies ``theta''`` in the modal rows but
nothing couples ``eta_j''`` back into the hub row, so the printed ``M, K``
just return the ``omega_j`` put into ``K``.  We use the symmetric reading
that the kinetic energy of Eq. (7) gives directly: Rayleigh-Ritz with ``n`` clamped-free
assumed modes, ``q = (theta, eta_1..eta_n)``::

    M = [[I_T, h^T], [h, diag(m_i)]] (x2 arms, + I_hub),  K = diag(0, k_i) (x2 arms),
    F = (tau, 0, ..., 0),
    I_T = I_hub + 2 (rhoA ((r+L)^3 - r^3)/3 + m_t (r+L)^2),
    h_i = int rhoA (r+x) phi_i dx + m_t (r+L) phi_i(L).

Eq. (18) puts ``phi_j'(0) tau`` on the modal rows; for clamped-free modes
``phi_j'(0) = 0``, so the torque acts on ``theta`` only, as in our ``F``.
The coupled ``M, K`` are diagonalised (system modes: one rigid, ``n``
flexible), and each system mode becomes a 1-junction with I and C in the
bond graph (:func:`bondgraph.beam.fragment.modal_fragment`); the hub torque
reaches mode ``i`` through a TF of modulus ``1/Theta_i`` (``Theta_i`` = hub
rotation of the mode).

Paper form
----------
``build(formulation="paper")`` writes the model as the paper writes it
(Eqs. 15-17): the generalised coordinates ``q = (theta, eta_1..eta_n)``
each have a 1-junction (``hub``, ``eta_1``, ...), the coupled mass matrix
``M`` above is one inertia field ``IF:M`` on all of them (``p = M q'``, the
rigid rotation coupled to every mode through ``h_j``), the modal stiffness
``diag(k_j)`` one compliance field ``CF:K`` on the modal junctions, and the
torque drives the hub junction.  Its parameters are the entries ``I_T``,
``h_j``, ``m_j``, ``k_j`` (values from the Rayleigh-Ritz integrals).  It has
the same eigenvalues and sensor transfer functions as the diagonalised
(``"system"``) form, which needs no field.

Sensors (Eqs. 21-26): integrated tip accelerometer ``e_ac = G_a ((r+L) theta +
y(L))`` (the paper writes ``L theta``; the tip of an arm clamped at radius
``r`` is at ``r + L``), potentiometer ``e_p = G_p theta``, strain gauge at
``x_1``, ``e_s = (e/2) y''(x_1)`` (``e`` = beam thickness), tachometer
``e_t = G_t theta'``.  Gains default to 1 (the paper does not list them).

Against the paper (Table 2: analytical 12.51, 31.11, 62.86 Hz; experimental
12.0, 33.25, 59.5 Hz): Table 1's parameters give 4.78, 22.36, 61.65 Hz for the
coupled hub + arms (converged in n, and equal to the exact unconstrained
modes).  Only the third mode agrees.  The first flexible frequency of this
hub carrying these arms lies between the clamped-arm value (3.50 Hz, hub
held still) and the massless-hub value (12.94 Hz with r = 0.09 m);
12.51 Hz would need a hub inertia of 0.0057 kg m^2 instead of 0.767 (and
the other two printed frequencies would need other inertias, 0.026 and
0.11 kg m^2).  No parameter is tuned here.
"""

from __future__ import annotations

import numpy as np
import sympy
from scipy.linalg import eigh

import bondgraph as bg
from bondgraph.beam import hub_assumed_modes, modal_beam
from bondgraph.beam.fragment import ModeData, modal_fragment

__all__ = ["TABLE1", "PARAMETERS", "FORMULATIONS", "build", "build_paper", "model",
           "system_modes"]

#: ``formulation=`` of :func:`build`: diagonalised system modes, or the paper's coupled M, K
FORMULATIONS = ("system", "paper")

#: Seed 001 Table 1.
TABLE1 = {
    "rho": 2.7950e3,        # kg/m^3
    "E": 6.8900e10,         # N/m^2
    "thickness": 4.1200e-3,  # m ("beams width" E_b: the bending thickness e)
    "height": 8.0780e-2,    # m
    "L": 9.7150e-1,         # m
    "A": 3.3281e-4,         # m^2
    "I": 4.7070e-10,        # m^4
    "I_b": 2.8430e-1,       # kg m^2, one beam about its root (= rhoA L^3/3)
    "I_hub": 7.6749e-1,     # kg m^2
    "r": 9.0000e-2,         # m
}

GAINS = {"G_a": 1.0, "G_p": 1.0, "G_t": 1.0}
PARAMETERS = dict(GAINS)


def system_modes(n_modes: int = 3, *, tip_mass: float = 0.0):
    """Rayleigh-Ritz model and its mass-normalised system modes.

    Returns ``(beam, rr, w2, Phi)``: the clamped-free basis, the assumed-modes
    model, squared frequencies (ascending, rigid mode first) and mode matrix.

    Examples
    --------
    >>> _, _, w2, _ = system_modes(6)
    >>> [round(float(np.sqrt(w)) / (2 * np.pi), 2) for w in w2[1:4]]
    [4.78, 22.36, 61.65]
    """
    T = TABLE1
    beam = modal_beam(T["E"] * T["I"], T["rho"] * T["A"], T["L"], n_modes,
                      boundary="clamped-free", tip_mass=tip_mass)
    rr = hub_assumed_modes(beam, hub_inertia=T["I_hub"], hub_radius=T["r"], n_arms=2)
    M, _, K = rr.matrices()
    w2, Phi = eigh(K, M)
    w2[0] = 0.0
    return beam, rr, w2, Phi


def build(n_modes: int = 3, *, tip_mass: float = 0.0, strain_position: float = 0.05,
          damping_ratio: float = 0.0, n_system_modes: int | None = None,
          formulation: str = "system"):
    """Bond graph, outputs and parameter values of the hub with two appendages.

    Parameters
    ----------
    n_modes : int
        Assumed (clamped-free) modes per arm in the Rayleigh-Ritz basis.
    formulation : {"system", "paper"}
        ``"system"``: the coupled ``M, K`` diagonalised into system modes, one
        I and one C per mode; ``"paper"``: ``M`` as an inertia field and ``K``
        as a compliance field on the coordinates (theta, eta_j), as in the
        paper's Eqs. (15-17) (:func:`build_paper`).
    tip_mass : float
        Tip mass of each arm (kg).
    strain_position : float
        ``x_1``: distance of the strain gauge from the beam root (m).
    damping_ratio : float
        Modal damping ratio of the flexible system modes.
    n_system_modes : int, optional
        Flexible system modes kept in the bond graph (default: all ``n_modes``).

    Examples
    --------
    >>> g, outs, params = build(3)
    >>> sorted(outs)
    ['e_ac', 'e_p', 'e_s', 'e_t']
    """
    if formulation not in FORMULATIONS:
        raise ValueError(f"formulation must be 'system' or 'paper', got {formulation!r}")
    if formulation == "paper":
        if n_system_modes is not None:
            raise ValueError("n_system_modes truncates the system modes of the 'system' "
                             "formulation; the 'paper' formulation keeps every assumed mode")
        return build_paper(n_modes, tip_mass=tip_mass, strain_position=strain_position,
                           damping_ratio=damping_ratio)
    beam, rr, w2, Phi = system_modes(n_modes, tip_mass=tip_mass)
    keep = n_modes if n_system_modes is None else n_system_modes
    tip_row = np.array(rr.tip_output)
    d2 = np.array([m.shape(strain_position, 2) for m in beam.modes])
    e_half = TABLE1["thickness"] / 2
    data, strain = [], []
    for i in range(1, keep + 1):
        w = float(np.sqrt(w2[i]))
        data.append(ModeData(1.0, w2[i], 2 * damping_ratio * w, Phi[0, i], tip_row @ Phi[:, i]))
        strain.append(e_half * float(d2 @ Phi[1:, i]))
    g0 = Phi[0, 0]
    frag = modal_fragment(data, name="arms", rigid_inertia=1.0 / g0**2,
                          length=TABLE1["r"] + TABLE1["L"])
    g = bg.BondGraph("appendages")
    tau, hub = bg.Se("tau"), bg.One("hub")
    g.add(tau, hub, frag.graph)
    g.connect(tau, hub)
    g.connect(hub, "arms.hub")
    Ga, Gp, Gt = (sympy.Symbol(n, positive=True) for n in ("G_a", "G_p", "G_t"))
    params = dict(PARAMETERS)
    params.update(frag.values)
    eps = []
    for i, s_i in enumerate(strain, start=1):
        sym = sympy.Symbol(f"arms.s_{i}", real=True)
        params[sym.name] = s_i
        eps.append(sym * bg.displacement(f"arms.k_{i}"))
    theta = bg.displacement("hub")
    # absolute tip deflection = (r + L) theta + deflection relative to the hub, so that the
    # hub angle is the only integrator (no second, redundant rigid-body displacement state)
    tip = (TABLE1["r"] + TABLE1["L"]) * theta + frag.tip_deflection("arms.", relative=True)
    outputs = {
        "e_ac": Ga * tip,
        "e_p": Gp * theta,
        "e_s": sympy.Add(*eps),
        "e_t": Gt * bg.flow("hub"),
    }
    return g, outputs, params


def build_paper(n_modes: int = 3, *, tip_mass: float = 0.0, strain_position: float = 0.05,
                damping_ratio: float = 0.0):
    """The paper form: coupled ``M`` as ``IF:M``, modal ``K`` as ``CF:K`` (Eqs. 15-17).

    Port 1 of ``IF:M`` is the hub rotation ``theta``, port ``j + 1`` the modal
    coordinate ``eta_j`` (port ``j`` of ``CF:K``).  ``damping_ratio`` adds the
    modal damping of the system modes as a resistive field ``RF:D`` on all
    the coordinates (``D = M Phi diag(2 zeta w) Phi^T M``, the system form's
    damping written in these coordinates).

    Examples
    --------
    >>> g, outs, params = build_paper(3)
    >>> sorted(el.label() for el in g.elements if el.kind in ("IF", "CF"))
    ['CF:K', 'IF:M']
    >>> round(params["I_T"], 4), sorted(outs)
    (1.5088, ['e_ac', 'e_p', 'e_s', 'e_t'])
    """
    beam, rr, w2, Phi = system_modes(n_modes, tip_mass=tip_mass)
    M_num, _, K_num = rr.matrices()
    n = n_modes
    sym = lambda name: sympy.Symbol(name, positive=True)    # noqa: E731
    h = [sympy.Symbol(f"h_{j}", real=True) for j in range(1, n + 1)]   # couplings: any sign
    m = [sym(f"m_{j}") for j in range(1, n + 1)]
    k = [sym(f"k_{j}") for j in range(1, n + 1)]
    M = sympy.zeros(n + 1, n + 1)
    M[0, 0] = sym("I_T")
    for j in range(n):
        M[0, j + 1] = M[j + 1, 0] = h[j]
        M[j + 1, j + 1] = m[j]
    params = dict(PARAMETERS, I_T=float(M_num[0, 0]))
    for j in range(n):
        params.update({h[j].name: float(M_num[0, j + 1]), m[j].name: float(M_num[j + 1, j + 1]),
                       k[j].name: float(K_num[j + 1, j + 1])})
    g = bg.BondGraph("appendages_paper")
    coords = [bg.One("hub")] + [bg.One(f"eta_{j}") for j in range(1, n + 1)]
    g.add(bg.Se("tau"), *coords, bg.IField("M", M), bg.CField("K", stiffness=sympy.diag(*k)))
    g.connect("tau", "hub")
    for c in coords:
        g.connect(c, "M")
    for c in coords[1:]:
        g.connect(c, "K")
    if damping_ratio:
        w = np.sqrt(np.clip(w2, 0.0, None))
        D = M_num @ Phi @ np.diag(2 * damping_ratio * w) @ Phi.T @ M_num
        g.add(bg.RField("D", ((D + D.T) / 2).tolist()))
        for c in coords:
            g.connect(c, "D")
    Ga, Gp, Gt = (sympy.Symbol(name, positive=True) for name in ("G_a", "G_p", "G_t"))
    eta = [bg.displacement("K", port=j) for j in range(1, n + 1)]
    theta = bg.displacement("hub")
    tip = rr.tip_output
    d2 = [mode.shape(strain_position, 2) for mode in beam.modes]
    e_half = TABLE1["thickness"] / 2
    outputs = {
        "e_ac": Ga * (tip[0] * theta + sympy.Add(*[tip[j + 1] * eta[j] for j in range(n)])),
        "e_p": Gp * theta,
        "e_s": sympy.Add(*[e_half * float(d2[j]) * eta[j] for j in range(n)]),
        "e_t": Gt * bg.flow("hub"),
    }
    return g, outputs, params


def model(*, n_modes: int = 3, tip_mass: float = 0.0, formulation: str = "system"):
    """Model definition (the model-file protocol)."""
    from bondgraph.modelfile import ModelDefinition

    g, outputs, params = build(n_modes, tip_mass=tip_mass, formulation=formulation)
    return ModelDefinition(graph=g, outputs=outputs, parameters=params,
                           description="Hub on gas bearing with two flexible appendages (seed 001"
                           f", {formulation} formulation)")
