"""Quanser SRV-02 servo hub (seed 000, Sec. 3; SRV-02 user manual).

Bond graph
----------
::

    Se:e_in -> 1:i -> GY:km (efficiency eta_m*kt/km) -> 1:w_m -> TF:gear (1/Kg, efficiency eta_g) -> 1:w_l
               |  \\                                      |                                          |   \\
             R:Rm  I:Lm                                 I:Jm                                       R:Beq  [I:J_l | Port:shaft]

* armature: resistance ``Rm``, inductance ``Lm`` (optional);
* motor: back-emf ``km*w_m`` and torque ``eta_m*kt*i`` -- a gyrator of modulus
  ``km`` whose torque side is scaled by ``eta_m*kt/km``;
* gearbox ``Kg`` (14 low gear, 70 high gear) as a transformer ``w_l = w_m/Kg``
  with efficiency ``eta_g`` on the torque, as in Quanser's model;
* motor inertia ``Jm`` on the motor shaft; viscous friction ``Beq`` and any
  load inertia on the output shaft.  With a rigid gear the output-shaft
  inertia is in derivative causality and the engine reduces it to
  ``J_eq = eta_g*Kg**2*Jm + J_l`` (Quanser's equivalent inertia).

Outputs: ``theta`` (output-shaft angle, rad), ``omega`` (rad/s), ``i_m`` (A),
``v_pot = k_pot*theta`` (potentiometer, V) and ``v_tach = k_tach*w_m``
(tachometer on the motor shaft, V).

Which configuration reproduces seed 000 Eq. (3)
-----------------------------------------------
Low gear (``Kg = 14``), no load (``J_l = 0``), ``Lm`` neglected: theta/e_in
takes the form of Eq. (1), ``1/(a s^2 + b s)`` with
``a = Rm*Jm*Kg/(eta_m*kt)`` and ``b = (Rm*Beq + eta_g*eta_m*Kg**2*kt*km)/(eta_g*eta_m*Kg*kt)``,
and with the defaults gives ``375.7/(s (s + 42.54))``: -0.56 % in gain and
+0.33 % in pole against the identified ``377.8/(s (s + 42.4))``.  Adding the
0.0042 kg m^2 link inertia of Table 1 as a rigid load (``load_inertia=True``)
gives ``6.01/(s (s + 0.68))``: the identified model is the bare hub.
"""

from __future__ import annotations

import math

import sympy

import bondgraph as bg

__all__ = ["PARAMETERS", "SYMBOLS", "build", "model"]

_names = "Rm Lm kt km eta_m eta_g Kg Jm Beq J_l k_pot k_tach"
SYMBOLS: dict[str, sympy.Symbol] = {n: sympy.Symbol(n, positive=True) for n in _names.split()}

#: Defaults: seed 000 Table 1 and the SRV-02 manual (low gear).
PARAMETERS: dict[str, float] = {
    "Rm": 2.6,            # ohm
    "Lm": 0.18e-3,        # H
    "kt": 0.00767,        # N m / A
    "km": 0.00767,        # V s / rad
    "eta_m": 0.69,
    "eta_g": 0.90,
    "Kg": 14.0,           # low gear (70 in high gear)
    "Jm": 3.87e-7,        # kg m^2, armature
    "Beq": 1.5e-4,        # N m s / rad, low gear
    "J_l": 0.0042,        # kg m^2, link rigid-body inertia (Table 1), used with load_inertia=True
    "k_pot": 0.0284 * 180.0 / math.pi,    # V/rad (0.0284 V/deg)
    "k_tach": 1.5e-3 * 60.0 / (2 * math.pi),  # V/(rad/s) (1.5 mV/RPM)
}


def build(name: str = "srv02", *, inductance: bool = True, motor_inertia: bool = True,
          load_inertia: bool = False, port: bool = False) -> bg.BondGraph:
    """The SRV-02 hub as a bond graph.

    Parameters
    ----------
    name : str
    inductance : bool
        Keep the armature inductance ``Lm`` (False: neglected, as in Eq. (1)).
    motor_inertia : bool
        Put ``Jm`` on the motor shaft.  A model that accounts for the hub
        inertia elsewhere (the FLEXCAM modal beam) sets this False.
    load_inertia : bool
        Put the rigid load ``J_l`` on the output shaft.
    port : bool
        Expose the output shaft as ``Port('shaft')`` for use as a sub-model.

    Examples
    --------
    >>> g = build(inductance=False)
    >>> sorted(el.name for el in g.elements)
    ['Beq', 'Jm', 'Rm', 'e_in', 'gear', 'i', 'km', 'w_l', 'w_m']
    """
    S = SYMBOLS
    g = bg.BondGraph(name)
    e_in, i, w_m, w_l = bg.Se("e_in"), bg.One("i"), bg.One("w_m"), bg.One("w_l")
    g.add(e_in, i, w_m, w_l, bg.R("Rm", S["Rm"]),
          bg.GY("km", S["km"], efficiency=S["eta_m"] * S["kt"] / S["km"]),
          bg.TF("gear", 1 / S["Kg"], efficiency=S["eta_g"]), bg.R("Beq", S["Beq"]))
    g.connect(e_in, i)
    g.connect(i, "Rm")
    if inductance:
        g.add(bg.I("Lm", S["Lm"]))
        g.connect(i, "Lm")
    g.connect(i, "km")
    g.connect("km", w_m)
    if motor_inertia:
        g.add(bg.I("Jm", S["Jm"]))
        g.connect(w_m, "Jm")
    g.connect(w_m, "gear")
    g.connect("gear", w_l)
    g.connect(w_l, "Beq")
    if load_inertia:
        g.add(bg.I("J_l", S["J_l"]))
        g.connect(w_l, "J_l")
    if port:
        g.add(bg.Port("shaft"))
        g.connect(w_l, "shaft")
    return g


def outputs(prefix: str = "") -> dict[str, sympy.Expr]:
    """The sensor outputs (``prefix`` is the sub-model path, e.g. ``'hub.'``)."""
    S = SYMBOLS
    theta = bg.displacement(prefix + "w_l")
    return {
        "theta": theta,
        "omega": bg.flow(prefix + "w_l"),
        "i_m": bg.flow(prefix + "i"),
        "v_pot": S["k_pot"] * theta,
        "v_tach": S["k_tach"] * bg.flow(prefix + "w_m"),
    }


def model(*, inductance: bool = True, load_inertia: bool = False):
    """Model definition of the SRV-02 hub (the model-file protocol)."""
    from bondgraph.modelfile import ModelDefinition

    return ModelDefinition(
        graph=build(inductance=inductance, load_inertia=load_inertia),
        outputs=outputs(),
        parameters=dict(PARAMETERS),
        description="Quanser SRV-02 servo hub, low gear (seed 000 Sec. 3)",
    )
