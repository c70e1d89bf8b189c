"""Quanser FLEXCAM: SRV-02 hub driving a flexible link (seed 000, Sec. 4).

Two formulations, both bond graphs built from the SRV-02 sub-model
(``models/srv02.py``, armature inductance neglected as in seed 000 Eq. (1))
and the modal beam fragment (:mod:`bondgraph.beam.fragment`):

``"paper"`` -- seed 000 Eqs. (7)-(13) as printed: the link's pinned-free
    flexible modes (Eq. 12), each driven by the hub torque through the root
    slope ``phi_i'(0)`` (Eq. 11), tip deflection ``y(L) = sum phi_i(L) eta_i``
    (Eq. 8).  With ``n`` modes and the motor inertia left out of the motor
    (the pinned-free expansion has no hub inertia), ``y(L)/e_in`` is of order
    ``2n``: the 6th-order Eq. (13) for three modes.  The motor's back-emf and
    ``Beq`` reach the modes through the hub velocity ``sum phi_i'(0) eta_i'``.
``"system"`` -- the physically complete model: exact unconstrained modes of
    the hub (reflected motor inertia ``eta_g*Kg**2*Jm``) carrying the link,
    rigid-body mode included, so the hub angle and the tip deflection seen by
    the hub-mounted camera are both outputs.

Link data (seed 000 Table 1): length 0.425 m, height 0.02 m, thickness
0.8 mm, mass 0.06 kg (so rhoA = 0.1412 kg/m).  The table gives no material;
we take spring steel, E = 200 GPa (a FLEXCAM/FLEXGAGE link is steel), giving
EI = 0.1707 N m^2.  The camera gain is 0.39 V/cm.

What the model gives against the paper (see notebooks/02_flexcam.ipynb):
pinned-free flexible frequencies 14.9, 48.4, 101.0 Hz against the printed
0.38, 1.23, 2.55 Hz.  The printed frequencies are in the pinned-free ratios
(1 : 3.24 : 6.76) but would need EI = 1.1e-4 N m^2, which a 0.8 mm x 20 mm
strip cannot have; the printed numbers cannot follow from the printed
parameters, and no parameter is tuned here to hit them.
"""

from __future__ import annotations

import sys
from pathlib import Path

import sympy

import bondgraph as bg
from bondgraph.beam import hub_beam_modes, modal_beam
from bondgraph.beam.fragment import ModalFragment, beam_fragment

sys.path.insert(0, str(Path(__file__).resolve().parent))
import srv02  # noqa: E402

__all__ = ["LINK", "PARAMETERS", "build", "model", "main"]

#: Link of seed 000 Table 1, with the material we assume (spring steel).
LINK = {
    "length": 0.425, "height": 0.02, "thickness": 0.8e-3, "mass": 0.06,
    "E": 200e9, "camera_gain": 0.39e2,  # V/m (0.39 V/cm)
}


def link_properties(link: dict = LINK) -> tuple[float, float, float]:
    """``(EI, rhoA, L)`` of the link."""
    I = link["height"] * link["thickness"] ** 3 / 12
    return link["E"] * I, link["mass"] / link["length"], link["length"]


PARAMETERS: dict[str, float] = dict(srv02.PARAMETERS, k_cam=LINK["camera_gain"])


def build(n_modes: int = 3, *, formulation: str = "paper", damping_ratio: float = 0.0,
          inductance: bool = False) -> tuple[bg.BondGraph, dict, dict]:
    """FLEXCAM bond graph, its outputs and default parameter values.

    Parameters
    ----------
    n_modes : int
        Flexible modes of the link.
    formulation : {"paper", "system"}
    damping_ratio : float
        Modal damping ratio of every flexible mode (0: undamped, as printed).
    inductance : bool
        Keep the armature inductance.

    Returns
    -------
    graph : BondGraph
    outputs : dict
    parameters : dict of str to float

    Examples
    --------
    >>> g, outs, params = build()
    >>> sorted(outs)
    ['theta', 'v_cam', 'y']
    """
    if formulation not in ("paper", "system"):
        raise ValueError(f"formulation must be 'paper' or 'system', got {formulation!r}")
    EI, rhoA, L = link_properties()
    P = srv02.PARAMETERS
    if formulation == "paper":
        beam = modal_beam(EI, rhoA, L, n_modes, boundary="pinned-free")
        frag = beam_fragment(beam, name="link", rigid=False, damping_ratio=damping_ratio)
    else:
        J_hub = P["eta_g"] * P["Kg"] ** 2 * P["Jm"]
        beam = hub_beam_modes(EI, rhoA, L, n_modes, hub_inertia=J_hub)
        frag = beam_fragment(beam, name="link", rigid=True, damping_ratio=damping_ratio)
    hub = srv02.build("hub", inductance=inductance, motor_inertia=False, port=True)
    g = bg.BondGraph(f"flexcam_{formulation}")
    g.add(hub, frag.graph)
    g.connect("hub.shaft", "link.hub")
    outputs = _outputs(frag, formulation)
    params = dict(PARAMETERS)
    params.update(frag.values)
    return g, outputs, params


def _outputs(frag: ModalFragment, formulation: str) -> dict:
    k_cam = sympy.Symbol("k_cam", positive=True)
    if formulation == "paper":
        y = frag.tip_deflection("link.")
    else:
        y = frag.tip_deflection("link.", relative=True)    # what the hub camera sees
    return {"y": y, "v_cam": k_cam * y, "theta": bg.displacement("hub.w_l")}


def model(*, n_modes: int = 3, formulation: str = "paper", damping_ratio: float = 0.0):
    """Model definition (the model-file protocol)."""
    from bondgraph.modelfile import ModelDefinition

    g, outputs, params = build(n_modes, formulation=formulation, damping_ratio=damping_ratio)
    return ModelDefinition(graph=g, outputs=outputs, parameters=params,
                           description=f"FLEXCAM hub + flexible link ({formulation} formulation)")


#: Seed 000 Eq. (13) as printed (numerator a5..a0, denominator b6..b0).
PRINTED_NUM = (-3.8e-15, -4.91e-5, 3.8e-13, -0.0117, 2.28e-12, -0.85)
PRINTED_DEN = (1.0, 1.07e-5, 320.699, 0.002999, 16848.25, 0.116, 84534.2)
PRINTED_FREQ_HZ = (0.38, 1.23, 2.55)


def paper_transfer_function(n_modes: int = 3):
    """Derived model, symbolic ``y(L)/e_in`` and its numeric form (paper formulation)."""
    g, outputs, params = build(n_modes, formulation="paper")
    mdl = bg.derive(g, outputs=outputs)
    G = mdl.transfer_function("hub.e_in", "y")
    values = {p: params[p.name] for p in mdl.parameters}
    return mdl, G, G.subs(values), params


#: width of the main job's console output (characters)
WIDTH = 100


def _printer(width: int):
    """``say(text, indent=2)``: print ``text`` wrapped at ``width``, continuation lines indented."""
    import textwrap

    def say(text: str, indent: int = 2) -> None:
        print(textwrap.fill(text, width, subsequent_indent=" " * indent, break_long_words=False,
                            break_on_hyphens=False))
    return say


def main(argv: list[str] | None = None) -> int:
    """Print the symbolic and numeric FLEXCAM transfer function, write numeric ABCD."""
    import argparse

    from bondgraph.export import export
    from bondgraph.numeric import compile_plant
    from bondgraph.tf.coefficients import coefficient_table

    ap = argparse.ArgumentParser(description=main.__doc__)
    ap.add_argument("--out", default="out", help="directory for flexcam_abcd.npz/.mat")
    ap.add_argument("--modes", type=int, default=3, help="flexible modes of the link")
    args = ap.parse_args(argv)

    mdl, G, Gn, params = paper_transfer_function(args.modes)
    values = {p.name: params[p.name] for p in mdl.parameters}
    say = _printer(WIDTH)
    say(f"FLEXCAM (seed 000, Eqs. 7-13): {len(mdl.states)} states: {', '.join(mdl.state_names)}")
    print()
    say("Symbolic G(s) = Y(L,s)/E_in(s) = (a5 s^5 + ... + a0)/(b6 s^6 + ... + b0), the form of "
        "Eq. (13). value: Table 1 parameters, steel link (E = 200 GPa); paper: Eq. (13) as "
        "printed; ratio = value/paper; under each row its symbolic coefficient.")
    print()
    table = coefficient_table(G, values, printed_num=PRINTED_NUM, printed_den=PRINTED_DEN,
                              printed_label="paper (Eq. 13)", output_unit="m", input_unit="V")
    print(table.format(WIDTH))
    print()
    say("with the modal symbols (pinned-free link modes, mass-normalised):")
    for name in sorted(v for v in params if v.startswith("link.")):
        print(f"  {name} = {params[name]:.6g}")
    print()
    say("Numeric (Table 1 parameters, steel link E = 200 GPa):")
    print(Gn)
    print()
    say(f"Poles, zeros and frequencies (cf. paper Table 2: "
        f"{', '.join(f'{f:g}' for f in PRINTED_FREQ_HZ)} Hz):")
    print(Gn.table())
    print()
    say("The printed frequencies cannot follow from Table 1's link (they would need "
        "EI = 1.1e-4 N m^2); see models/flexcam.py and notebooks/02_flexcam.ipynb.")

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    plant = compile_plant(mdl).plant({p.name: params[p.name] for p in mdl.parameters})
    for suffix in ("npz", "mat"):
        export(plant, out / f"flexcam_abcd.{suffix}")
    print()
    say(f"A ({plant.A.shape[0]}x{plant.A.shape[1]}), B, C, D written to "
        f"{out / 'flexcam_abcd.npz'} and {out / 'flexcam_abcd.mat'}")
    say("states : " + ", ".join(plant.state_names), indent=9)
    say("inputs : " + ", ".join(plant.input_names), indent=9)
    say("outputs: " + ", ".join(plant.output_names), indent=9)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
