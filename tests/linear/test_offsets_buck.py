"""The averaged buck converter with the source voltage an input: control-to-output and
line-to-output transfer functions from one averaged model.

Hand derivation (state-space averaging, continuous conduction), written here.
Inductor current ``i = p_L/L``, capacitor voltage ``v = q_C/C``, duty ``d``,
source voltage ``Vg``, load ``R``:

    L i' = d Vg - v,        C v' = i - v/R,        vo = v.

The product ``d Vg`` makes the model nonlinear in its inputs.  Equilibrium at
``(d, Vg) = (D0, Vg0)``: ``v0 = D0 Vg0``, ``i0 = v0/R``.  In deviations
``L di' = Vg0 dd + D0 dVg - dv``, ``C dv' = di - dv/R``; eliminating
``di = (C s + 1/R) dv``:

    dv (L C s^2 + (L/R) s + 1) = Vg0 dd + D0 dVg,

so ``vo/d = Vg0/(L C s^2 + (L/R) s + 1)`` and ``vo/vg = D0/(L C s^2 + (L/R) s + 1)``.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.hybrid import Mode, SwitchedModel
from bondgraph.hybrid.errors import ModeError
from bondgraph.hybrid.library import buck

L, C, R = sympy.symbols("L C R", positive=True)
s = sympy.Symbol("s")
ACTIVE, PASSIVE = Mode(on={"S"}, off={"D"}), Mode(on={"D"}, off={"S"})


@pytest.fixture(scope="module")
def averaged():
    sm = SwitchedModel(buck(), outputs={"vo": bg.effort("C")})
    return sm.average("d", active=ACTIVE, passive=PASSIVE, inputs=("Vin",))


def den():
    return L * C * s**2 + (L / R) * s + 1


def same(a, b) -> bool:
    return sympy.simplify(a - b) == 0


def test_both_transfer_functions_from_one_model(averaged):
    assert averaged.input_names == ("Vin", "d")
    Gd = averaged.transfer_function("d", "vo")
    Gv = averaged.transfer_function("Vin", "vo")
    d0, Vg0 = Gd.operating_point.inputs["d"], Gd.operating_point.inputs["Vin"]
    assert (d0.name, Vg0.name) == ("d0", "Vin0")
    assert same(Gd.expr, Vg0 / den())
    assert same(Gv.expr, d0 / den())
    op = Gv.operating_point
    assert same(op.outputs["vo"], d0 * Vg0)
    assert same(op.states["p_L"], L * d0 * Vg0 / R)          # L i0
    assert same(op.states["q_C"], C * d0 * Vg0)              # C v0


def test_at_a_symbolic_point_of_the_users_symbols(averaged):
    D0, Vg0 = sympy.symbols("D0 Vg0", positive=True)
    G = averaged.transfer_matrix(at={"d": D0, "Vin": Vg0})
    assert same(G["vo", "d"].expr, Vg0 / den())
    assert same(G["vo", "Vin"].expr, D0 / den())
    assert G.operating_point.inputs == {"Vin": Vg0, "d": D0}


def test_point_check_with_plain_symbols_simplifies(averaged):
    # the user's Symbol("C") without assumptions is the model's positive C: -C + C cancels
    Lp, Cp, Rp, d0, V0 = sympy.symbols("L C R d0 V0")
    good = averaged.linearize({"p_L": Lp * V0 * d0 / Rp, "q_C": Cp * V0 * d0},
                              {"d": d0, "Vin": V0})
    assert good.B == sympy.Matrix([[d0, V0], [0, 0]])
    with pytest.raises(bg.NonlinearModelError) as err:
        averaged.linearize({"p_L": Lp * V0 * d0 / Rp, "q_C": 2 * Cp * V0 * d0},
                           {"d": d0, "Vin": V0})
    text = str(err.value)
    assert "-C + C" not in text and "dp_L/dt = -V0*d0" in text


def test_numeric_plant_at_the_operating_point(averaged):
    values = {"L": 1e-4, "C": 1e-4, "R": 5.0, "T": 1e-5, "duty": 0.5}
    plant = averaged.linearize(values=values, u0={"d": 0.4, "Vin": 12.0})
    np.testing.assert_allclose(plant.B, [[0.4, 12.0], [0.0, 0.0]], rtol=1e-12)
    assert plant.operating_point.outputs["vo"] == pytest.approx(4.8, rel=1e-12)
    w = np.array([0.0, 1e3, 1e4])
    H = plant.frequency_response(w)[:, 0, 1]                   # vo/d
    Lv, Cv, Rv = 1e-4, 1e-4, 5.0
    np.testing.assert_allclose(H, 12.0 / (Lv * Cv * (1j * w)**2 + (Lv / Rv) * 1j * w + 1),
                               rtol=1e-9)


def test_inputs_must_name_constant_sources():
    sm = SwitchedModel(buck(), outputs={"vo": bg.effort("C")})
    with pytest.raises(ModeError, match="'L' is not a source"):
        sm.average("d", active=ACTIVE, passive=PASSIVE, inputs=("L",))
    with pytest.raises(ModeError, match="sequence of source names"):
        sm.average("d", active=ACTIVE, passive=PASSIVE, inputs="Vin")
