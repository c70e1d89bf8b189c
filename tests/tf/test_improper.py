"""Issue 11, item 9: transfer functions of models with input derivatives.

With zero initial conditions, ``x' = A x + B u + B1 u'`` and
``y = C x + D u + D1 u'`` give ``G(s) = C (sE - A)^-1 (B + s B1) + D + s D1``.
Every expected value below is derived by hand (Newton's law in the Laplace
domain) in the docstring of its test; numeric checks use the hand formulas
at numbers, never the code under test.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import bondgraph as bg
from bondgraph.model import Model
from bondgraph.numeric import ImproperPlantError, NumericError

s = sp.Symbol("s")
m, b, mw, mb, ks, bs, L, a, M, k = sp.symbols("m b mw mb ks bs L a M k", positive=True)


def same(e1, e2) -> bool:
    """Equal as rational functions of s and the parameters."""
    return sp.cancel(sp.together(e1 - e2)) == 0


def entry(G):
    return G.expr.subs(G.s, s)


# ------------------------------------------------------------------- models
def shaker(outputs):
    """Velocity source vr on a 1-junction with a mass m and a damper b."""
    g = bg.BondGraph("shaker")
    g.add(bg.Sf("vr"), bg.One("j"), bg.I("m"), bg.R("b"))
    for t, h in [("vr", "j"), ("j", "m"), ("j", "b")]:
        g.connect(t, h)
    return bg.derive(g, outputs=outputs)


def rigid_tyre_quarter_car(outputs):
    """Road velocity vr imposed on the wheel mass mw (rigid tyre); suspension
    spring ks and damper bs in parallel (1-junction of the relative velocity)
    between the wheel and the body mass mb.  Bond 1: source -> wheel junction."""
    g = bg.BondGraph("qc")
    vr, wh, ns, sj, bo = bg.Sf("vr"), bg.One("wh"), bg.Zero("ns"), bg.One("sj"), bg.One("bo")
    g.add(vr, wh, ns, sj, bo, bg.I("mw"), bg.C("ks", stiffness="ks"), bg.R("bs"), bg.I("mb"))
    for t, h in [(vr, wh), (wh, "mw"), (wh, ns), (ns, sj), (sj, "ks"), (sj, "bs"),
                 (ns, bo), (bo, "mb")]:
        g.connect(t, h)
    return bg.derive(g, outputs=outputs)


# ------------------------------------------------------------------- shaker
def test_shaker_source_force_is_improper():
    """F = m vr' + b vr  =>  F/vr = m s + b (D = b, D1 = m); the mass moves with vr: v/vr = 1."""
    model = shaker({"F": bg.effort(1), "v": bg.flow("m")})
    G = model.transfer_function("vr", "F")
    assert same(entry(G), m * s + b)
    assert not G.is_proper and G.num.degree() == 1 and G.den.degree() == 0
    assert str(G) == "F/vr = m*s + b"
    assert G.to_latex() == r"\frac{F(s)}{vr(s)} = m s + b"
    Gv = model.transfer_function("vr", "v")
    assert same(entry(Gv), 1) and Gv.is_proper
    T = model.transfer_matrix()
    assert same(T.expr[0, 0].subs(T.s, s), m * s + b) and same(T.expr[1, 0].subs(T.s, s), 1)
    # numbers: m = 2, b = 3 -> G(jw) = 3 + 2jw
    N = G.subs({"m": 2.0, "b": 3.0})
    assert N(2j) == pytest.approx(3 + 4j)
    assert N.zeros() == pytest.approx([-1.5])
    sys = G.to_control({"m": 2.0, "b": 3.0})   # python-control holds improper TFs
    assert complex(sys(2j)) == pytest.approx(3 + 4j)
    assert sys.input_labels == ["vr"] and sys.output_labels == ["F"]


def test_shaker_state_space_error_points_to_transfer_function():
    model = shaker({"F": bg.effort(1)})
    with pytest.raises(bg.NonlinearModelError,
                       match=r"depends on dvr/dt.*transfer_function\(\) and transfer_matrix\(\)"):
        model.state_space()


def test_shaker_numeric_plant():
    """No state; y = b vr + m vr': frequency response b + j w m; to_control refused."""
    plant = bg.compile_plant(shaker({"F": bg.effort(1)})).plant({"m": 2.0, "b": 3.0})
    assert not plant.is_proper
    w = np.array([0.0, 1.0, 10.0])
    H = plant.frequency_response(w)[:, 0, 0]
    assert H == pytest.approx(3.0 + 2.0j * w)
    for conv in (plant.to_control, plant.to_scipy, plant.to_tf):
        with pytest.raises(ImproperPlantError, match="improper") as err:
            conv()
        assert isinstance(err.value, bg.BondGraphError) and isinstance(err.value, NumericError)


# -------------------------------------------------------------- quarter car
def _qc_hand():
    """Suspension compression x: x' = vr - vb; body: mb vb' = ks x + bs (vr - vb).

    Laplace: Vb/Vr = (bs s + ks)/(mb s^2 + bs s + ks)                  (proper)
    Source force F = mw vr' + ks x + bs (vr - vb) = mw s Vr + mb s Vb:
        F/Vr = mw s + mb s (bs s + ks)/(mb s^2 + bs s + ks)            (improper)
    Momentum of bond 1, h = integral of F: H/Vr = F/(s Vr)             (proper)
    Momentum of the wheel (derivative causality): pw = mw vr:  mw      (constant)
    """
    q = mb * s**2 + bs * s + ks
    vb = (bs * s + ks) / q
    F = mw * s + mb * s * (bs * s + ks) / q
    return {"v_body": vb, "F": F, "H": F / s, "pw": mw}


OUTS = {"v_body": bg.flow("mb"), "F": bg.effort(1), "H": bg.momentum(1), "pw": bg.momentum("mw")}


def test_quarter_car_every_entry_against_hand_formulas():
    hand = _qc_hand()
    model = rigid_tyre_quarter_car(OUTS)
    T = model.transfer_matrix()
    for i, name in enumerate(OUTS):
        G = model.transfer_function("vr", name)
        assert same(entry(G), hand[name]), name
        assert same(T.expr[i, 0].subs(T.s, s), hand[name]), name
        assert same(entry(T[name, "vr"]), hand[name]), name
    assert not model.transfer_function("vr", "F").is_proper
    assert model.transfer_function("vr", "v_body").is_proper
    assert model.transfer_function("vr", "H").is_proper


def test_quarter_car_proper_entry_unchanged_by_improper_outputs():
    """v_body/vr comes out exactly as from the model without the improper outputs."""
    alone = rigid_tyre_quarter_car({"v_body": bg.flow("mb")}).transfer_function("vr", "v_body")
    mixed = rigid_tyre_quarter_car(OUTS).transfer_function("vr", "v_body")
    assert (mixed.num_coeffs, mixed.den_coeffs) == (alone.num_coeffs, alone.den_coeffs)
    assert alone.den_coeffs == (1, bs / mb, ks / mb)


def test_quarter_car_numeric_plant_frequency_response():
    vals = {"mw": 40.0, "mb": 300.0, "ks": 2.0e4, "bs": 1.5e3}
    hand = _qc_hand()
    w = np.array([0.3, 2.0, 8.0, 30.0])
    sub = {sp.Symbol(n, positive=True): v for n, v in vals.items()}
    want = np.array([[complex(hand[n].subs(sub).subs(s, 1j * wi)) for n in OUTS] for wi in w])
    compiled = bg.compile_plant(rigid_tyre_quarter_car(OUTS))
    plant = compiled.plant(vals)
    assert plant.frequency_response(w)[:, :, 0] == pytest.approx(want, rel=1e-9)
    assert not plant.is_proper
    batch = compiled.batch({**vals, "mw": [40.0, 40.0]})
    assert batch.frequency_response(w)[1, :, :, 0] == pytest.approx(want, rel=1e-9)
    assert batch[0].frequency_response(w)[:, :, 0] == pytest.approx(want, rel=1e-9)
    # the proper outputs alone give an ordinary python-control plant
    proper = bg.compile_plant(rigid_tyre_quarter_car(
        {"v_body": OUTS["v_body"], "H": OUTS["H"]})).plant(vals)
    assert proper.is_proper
    sys = proper.to_control()
    for wi, row in zip(w, want):
        assert np.asarray(sys(1j * wi)).ravel() == pytest.approx([row[0], row[2]], rel=1e-9)


# ------------------------------------------- input derivative inside the rhs
def test_sf_on_zero_junction_with_inertia():
    """Sf u on a 0-junction with only an I: the I's flow is u (derivative
    causality), its effort L u', its momentum L u.  Outputs: e1 = L u'
    (E/U = L s), momentum of bond 1 h = integral of e1 = L u (H/U = L),
    momentum of L: L u (L)."""
    g = bg.BondGraph("z")
    g.add(bg.Sf("u"), bg.Zero("z"), bg.I("L"))
    g.connect("u", "z")
    g.connect("z", "L")
    model = bg.derive(g, outputs={"e": bg.effort(1), "h": bg.momentum(1), "pL": bg.momentum("L")})
    for name, want in (("e", L * s), ("h", L), ("pL", L)):
        assert same(entry(model.transfer_function("u", name)), want), name
    plant = bg.compile_plant(model).plant({"L": 0.5})
    w = np.array([1.0, 3.0])
    H = plant.frequency_response(w)[:, :, 0]
    assert H == pytest.approx(np.array([[0.5j * wi, 0.5, 0.5] for wi in w]))


def _hand_model(rhs, outs, ud, descriptor=None, states=None):
    x = sp.Symbol("x", real=True)
    u = sp.Symbol("u", real=True)
    return Model(name="hand", augmented=None, states=states or (x,), inputs=(u,),
                 output_names=tuple(f"y{i}" for i in range(len(outs))), rhs=tuple(rhs),
                 output_exprs=tuple(outs), input_derivatives=tuple(ud), descriptor=descriptor,
                 storage_states=1)


def test_hand_model_first_derivative_in_rhs():
    """x' = -a x + u', y0 = x, y1 = x - u + a u'.

    s X = -a X + s U  =>  X/U = s/(s + a);  Y1/U = s/(s + a) - 1 + a s.
    Numeric plant: z = x - u, z' = -a z - a u, y0 = z + u: s/(s+a) again, proper
    (to_control works, DC gain 0)."""
    x, u, du = sp.Symbol("x", real=True), sp.Symbol("u", real=True), sp.Symbol("du/dt", real=True)
    model = _hand_model([-a * x + du], [x, x - u + a * du], [du])
    assert same(entry(model.transfer_function("u", "y0")), s / (s + a))
    assert same(entry(model.transfer_function("u", "y1")), s / (s + a) - 1 + a * s)
    plant = bg.compile_plant(_hand_model([-a * x + du], [x], [du])).plant({"a": 2.0})
    assert plant.is_proper
    assert plant.state_shift[0] == pytest.approx(np.array([[1.0]]))
    assert plant.B == pytest.approx(np.array([[-2.0]])) and plant.D == pytest.approx(np.array([[1.0]]))
    w = np.array([0.0, 1.0, 5.0])
    assert plant.frequency_response(w)[:, 0, 0] == pytest.approx(1j * w / (1j * w + 2.0))
    assert float(plant.to_control().dcgain()) == pytest.approx(0.0, abs=1e-12)


def test_hand_model_second_derivative():
    """x' = -a x + u'', y = x:  X/U = s^2/(s + a) (improper)."""
    x, u = sp.Symbol("x", real=True), sp.Symbol("u", real=True)
    d2u = sp.Symbol("d2u/dt2", real=True)
    model = _hand_model([-a * x + d2u], [x], [d2u])
    G = model.transfer_function("u", "y0")
    assert same(entry(G), s**2 / (s + a)) and not G.is_proper
    plant = bg.compile_plant(model).plant({"a": 2.0})
    w = np.array([0.5, 1.0, 5.0])
    assert plant.frequency_response(w)[:, 0, 0] == pytest.approx((1j * w)**2 / (1j * w + 2.0))


def test_hand_descriptor_with_input_derivative():
    """M x' = -k x + u' (descriptor E = [[M]]), y = x:  X/U = s/(M s + k),
    from the descriptor form and from the explicit one alike."""
    x, du = sp.Symbol("x", real=True), sp.Symbol("du/dt", real=True)
    model = _hand_model([(-k * x + du) / M], [x], [du],
                        descriptor=(sp.ImmutableMatrix([[M]]), (-k * x + du,)))
    for desc in (None, True, False):
        assert same(entry(model.transfer_function("u", "y0", descriptor=desc)), s / (M * s + k))
    assert same(model.transfer_matrix().expr[0, 0].subs(sp.Symbol("s"), s), s / (M * s + k))
    with pytest.raises(bg.NonlinearModelError, match="transfer_function"):
        model.descriptor_form()


def test_input_derivative_must_be_linear():
    """u * u' has no transfer function: refused, naming the variable."""
    x, u, du = sp.Symbol("x", real=True), sp.Symbol("u", real=True), sp.Symbol("du/dt", real=True)
    model = _hand_model([-a * x + u * du], [x], [du])
    with pytest.raises(bg.NonlinearModelError, match="nonlinear"):
        model.transfer_function("u", "y0")
