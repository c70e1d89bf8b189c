"""One parameter policy for every call that takes values (issue 12).

Expected numbers are hand derivations: the mass-spring-damper
``m x'' + b x' + x/c = F`` (poles of ``m s^2 + b s + 1/c``; ``C`` takes a
compliance), the pendulum
linearized at the horizontal, the SRV-02 armature pole ``-Rm/Lm``.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.numeric.errors import ParameterValueError as NumericPVE
from bondgraph.tf.errors import MissingValueError as TfMissing
from bondgraph.tf.errors import ParameterValueError as TfPVE

MODELS = Path(__file__).resolve().parents[2] / "models"


def msd():
    g = bg.BondGraph("msd")
    v = bg.One("v")
    g.add(bg.Se("F"), v, bg.I("m"), bg.R("b"), bg.C("c"))
    for t, h in [("F", v), (v, "m"), (v, "b"), (v, "c")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"x": bg.displacement("c")})


VALUES = {"m": 2.0, "b": 6.0, "c": 0.25}   # 2 s^2 + 6 s + 4 = 2 (s + 1)(s + 2)


def test_one_error_class():
    assert NumericPVE is bg.ParameterValueError is TfPVE
    assert TfMissing is bg.MissingValueError
    assert issubclass(bg.MissingValueError, bg.ParameterValueError)
    assert issubclass(bg.ParameterValueError, bg.BondGraphError)
    assert issubclass(bg.ParameterValueError, ValueError)


def every_call(model):
    """Each call of the package that takes parameter values, as name -> callable(values)."""
    plant = bg.compile_plant(model)
    G = model.transfer_function("F", "x")
    T = model.transfer_matrix()
    ss = model.state_space()
    return {
        "plant": plant.plant,
        "batch": plant.batch,
        "numeric_plant": lambda v: bg.numeric_plant(model, v),
        "SymbolicTF.subs": G.subs,
        "TransferMatrix.subs": T.subs,
        "SymbolicStateSpace.subs": lambda v: ss.subs(v, partial=False),
        "SymbolicTF.poles": G.poles,
    }


@pytest.mark.parametrize("call", list(every_call(msd())))
def test_misspelled_name_is_an_error_listing_valid_names(call):
    fn = every_call(msd())[call]
    with pytest.raises(bg.ParameterValueError) as info:
        fn({"m": 2.0, "bb": 6.0, "c": 0.25})
    msg = str(info.value)
    assert "unknown parameter 'bb' (did you mean 'b'?)" in msg, msg
    assert "Valid names: b, c, m" in msg, msg
    assert info.value.unknown == ("bb",)


@pytest.mark.parametrize("call", list(every_call(msd())))
def test_missing_value_is_an_error(call):
    fn = every_call(msd())[call]
    with pytest.raises(bg.MissingValueError, match="missing c"):
        fn({"m": 2.0, "b": 6.0})


@pytest.mark.parametrize("bad, words", [
    ("4", r"str '4' \(text is never parsed\)"), (float("nan"), "got nan"), (math.inf, "got inf"),
    (2j, "complex"), (True, "bool"), (10 ** 400, "too large"), (sympy.zoo, "got zoo"),
    (sympy.I, "got I")])
@pytest.mark.parametrize("call", ["plant", "SymbolicTF.subs", "TransferMatrix.subs",
                                  "SymbolicStateSpace.subs"])
def test_bad_value_names_the_parameter(call, bad, words):
    fn = every_call(msd())[call]
    with pytest.raises(bg.ParameterValueError, match=f"parameter 'c'.*{words}"):
        fn({**VALUES, "c": bad})


def test_same_numbers_through_every_call():
    model = msd()
    calls = every_call(model)
    want = np.array([-2.0, -1.0])          # roots of 2 s^2 + 6 s + 4
    assert np.allclose(np.sort(np.linalg.eigvals(calls["plant"](VALUES).A)), want)
    assert np.allclose(np.sort(np.linalg.eigvals(calls["batch"](VALUES).A[0])), want)
    assert np.allclose(np.sort(calls["SymbolicTF.poles"](VALUES).real), want)
    assert calls["SymbolicTF.subs"](VALUES).den == (1.0, 3.0, 2.0)
    A = calls["SymbolicStateSpace.subs"](VALUES).A
    assert sorted(complex(e).real for e in A.eigenvals(multiple=True)) == [-2, -1]


def test_partial_substitution_keeps_the_rest_symbolic():
    model = msd()
    b, c = sympy.symbols("b c", positive=True)
    ss = model.state_space().subs({"m": 2})
    assert {p.name for p in ss.parameters} == {"b", "c"}
    G = model.transfer_function("F", "x", normalize="as-derived").subs({"m": 2}, partial=True)
    s = G.s
    # X/F = 1/(m s^2 + b s + 1/c) with m = 2
    assert sympy.simplify(G.expr - 1 / (2 * s**2 + b * s + 1 / c)) == 0
    N = G.subs({"b": 6, "c": 0.25})
    assert np.allclose(np.array(N.den) / N.den[0], [1.0, 3.0, 2.0])
    with pytest.raises(bg.MissingValueError, match="missing b, c"):
        model.state_space().subs({"m": 2}, partial=False)


def test_definition_parameter_unused_by_derived_form_is_accepted():
    """models/srv02.py declares J_l (the load of another variant): accepted everywhere."""
    sys.path.insert(0, str(MODELS))
    try:
        import srv02
    finally:
        sys.path.remove(str(MODELS))
    d = srv02.model()
    values = dict(d.parameters)
    assert "J_l" in values
    model = d.derive()
    assert "J_l" not in {p.name for p in model.parameters}
    assert "J_l" in model.known_parameters
    P = bg.compile_plant(model).plant(values)
    # the armature equation Lm di/dt = V - Rm i - ... gives the entry -Rm/Lm
    assert np.isclose(P.A[0, 0], -values["Rm"] / values["Lm"])
    model.transfer_function(0, 0).subs(values)
    model.state_space().subs(values)
    bg.compile_plant(model).batch(values)
    res = bg.simulate(model, values, (0.0, 1e-3))   # zero input, zero state: stays at rest
    assert np.all(res.x == 0.0)
    with pytest.raises(bg.ParameterValueError, match="unknown parameter 'J_ll'"):
        bg.simulate(model, {**values, "J_ll": 1.0}, (0.0, 1e-3))
    with pytest.raises(bg.ParameterValueError, match="unknown parameter 'J_ll'"):
        bg.compile_plant(model).plant({**values, "J_ll": 1.0})


def test_parameter_dropped_by_linearization_is_accepted():
    """Pendulum at the horizontal: A no longer holds m, g, l; their values are accepted."""
    m, g_, l = sympy.symbols("m g l", positive=True)
    g = bg.BondGraph("pendulum")
    w = bg.One("w")
    g.add(bg.Se("T"), w, bg.I("J"), bg.R("b"), bg.C("grav", law=m * g_ * l * sympy.sin(bg.q)))
    for t, h in [("T", w), (w, "J"), (w, "b"), (w, "grav")]:
        g.connect(t, h)
    model = bg.derive(g)
    lin = model.linearize({"p_J": 0, "q_grav": sympy.pi / 2}, {"T": m * g_ * l})
    assert {p.name for p in lin.parameters} == {"J", "b"}
    vals = {"m": 1.0, "g": 9.81, "l": 0.5, "J": 2.0, "b": 0.1}
    A = lin.subs(vals).A
    # J theta'' = T - b theta' - m g l sin(theta); d/dtheta sin at pi/2 is 0
    assert A == sympy.Matrix([[sympy.Rational(-1, 20), 0], [sympy.Rational(1, 2), 0]])
    with pytest.raises(bg.ParameterValueError, match="unknown parameter 'mm'"):
        lin.subs({**vals, "mm": 1.0})


def test_keys_may_be_symbols_or_names_but_not_twice():
    model = msd()
    m = next(p for p in model.parameters if p.name == "m")
    plant = bg.compile_plant(model)
    assert np.allclose(plant.plant({m: 2.0, "b": 6.0, "c": 0.25}).A, plant.plant(VALUES).A)
    with pytest.raises(bg.ParameterValueError, match="'m' is given twice"):
        plant.plant({m: 2.0, "m": 2.0, "b": 6.0, "c": 0.25})
    with pytest.raises(bg.ParameterValueError, match="keys must be sympy Symbols or their names"):
        plant.plant({1: 2.0, "b": 6.0, "c": 0.25})
    with pytest.raises(bg.ParameterValueError, match="must be a mapping"):
        plant.plant([2.0, 6.0, 4.0])


def test_zero_divisor_value_names_the_element():
    plant = bg.compile_plant(msd())
    with pytest.raises(bg.ParameterValueError, match=r"I:m: its mass \(inertance\) m = 0 must be positive"):
        plant.plant({**VALUES, "m": 0.0})


def test_negative_values_are_refused_unless_active():
    """A negative damper is refused by default; an active one (active=True) gives the
    unstable poles of 2 s^2 - 6 s + 4."""
    with pytest.raises(bg.ParameterValueError, match=r"R:b: its resistance b = -6 must not be negative"):
        bg.compile_plant(msd()).plant({**VALUES, "b": -6.0})
    g = bg.BondGraph("msd")
    v = bg.One("v")
    g.add(bg.Se("F"), v, bg.I("m"), bg.R("b", "b", active=True), bg.C("c"))
    for t, h in [("F", v), (v, "m"), (v, "b"), (v, "c")]:
        g.connect(t, h)
    P = bg.compile_plant(bg.derive(g)).plant({**VALUES, "b": -6.0})
    assert np.allclose(np.sort(np.linalg.eigvals(P.A).real), [1.0, 2.0])


def test_codegen_defaults_follow_the_policy():
    from bondgraph.codegen import generate_python

    model = msd()
    ns: dict = {}
    exec(generate_python(model, defaults=VALUES), ns)
    assert dict(ns["DEFAULT_PARAMETERS"]) == VALUES
    with pytest.raises(bg.ParameterValueError, match=r"unknown parameter 'bb' \(did you mean 'b'\?\)"):
        generate_python(model, defaults={**VALUES, "bb": 1.0})
    with pytest.raises(bg.MissingValueError, match="missing c"):
        generate_python(model, defaults={"m": 2.0, "b": 6.0})
