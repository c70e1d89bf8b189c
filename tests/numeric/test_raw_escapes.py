"""Issue 23, item 13 (audit P09, S19, T16): raw exceptions now name the culprit."""

import pytest
import sympy

import bondgraph as bg
from bondgraph.numeric import NumericError


def _msd(m=None):
    g = bg.BondGraph("msd")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m", m), bg.R("b"), bg.C("c"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "c")]:
        g.connect(t, h)
    return g


def test_undefined_function_refused_at_compile():
    """P09: NameError from the generated code at plant()."""
    model = bg.derive(_msd(sympy.Function("g")(sympy.Symbol("k", positive=True))))
    with pytest.raises(NumericError, match=r"model 'msd': g\(k\) calls an undefined sympy Function"):
        bg.compile_plant(model)


def test_derivative_output_refused_before_simulating():
    """S19: a ValueError from sympy's printer inside simulate."""
    model = bg.derive(_msd(), outputs={"a": sympy.Derivative(bg.flow("m"), bg.t)})
    with pytest.raises(NumericError, match=r"model 'msd': Derivative\(p_m/m, t\) is a symbolic derivative"):
        bg.simulate(model, {"m": 1.0, "b": 1.0, "c": 1.0}, (0, 1), u=[1.0])


def test_subnormal_parameter_overflow_named():
    """T16: OverflowError from the exact evaluation of the coefficients."""
    G = bg.derive(_msd(), outputs={"x": bg.displacement("c")}).transfer_function("F", "x")
    with pytest.raises(bg.ParameterValueError, match=r"beyond the range of a float at .*m = 1e-320"):
        G.subs({"m": 1e-320, "b": 1.0, "c": 1.0})
    # x/F = 1 / (m s^2 + b s + 1/c) by Newton, at ordinary values
    H = G.subs({"m": 2.0, "b": 6.0, "c": 0.25})
    import numpy as np
    assert np.polyval(H.num, 1j) / np.polyval(H.den, 1j) == pytest.approx(1 / (-2.0 + 6.0j + 4.0))
