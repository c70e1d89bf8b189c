"""Issue 23, item 9 (audit N13, N21, N26, I07, I10, X09): numpy never parses a user's text.

``np.asarray(["1", "2"], dtype=float)`` turns strings into numbers; every
entry point that converts a user's array now accepts only integer or float
dtypes and names the argument otherwise.
"""

import numpy as np
import pytest

import bondgraph as bg
from bondgraph.identification import IdentificationError, arx
from bondgraph.numeric import NumericError, NumericStateSpace


def _msd():
    g = bg.BondGraph("msd")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"), bg.C("c"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "c")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"x": bg.displacement("c")})


@pytest.fixture(scope="module")
def compiled():
    return bg.compile_plant(_msd())


def test_batch_refuses_text_arrays(compiled):
    """N13: batch({"m": ["1", "2"]}) ran at m = 1 and 2."""
    with pytest.raises(bg.ParameterValueError, match=r"'m'|m must be finite real numbers.*<U1"):
        compiled.batch({"m": ["1", "2"], "b": 6.0, "c": 0.25})


def test_batch_still_takes_numbers(compiled):
    """The A matrix of the mass-spring-damper by hand: d/dt (p, q) = (-b/m p - q/c, p/m)."""
    batch = compiled.batch({"m": [1, 2.0], "b": 6.0, "c": 0.25})
    for k, m in enumerate((1.0, 2.0)):
        A = batch.A[k]
        A = A.toarray() if hasattr(A, "toarray") else np.asarray(A)
        np.testing.assert_allclose(sorted(np.linalg.eigvals(A), key=np.real),
                                   sorted(np.roots([m, 6.0, 4.0]), key=np.real))


@pytest.mark.parametrize("omega", ["10", ["1", "10"], np.array([b"10"]), [None], [1j]],
                         ids=["str", "list-of-str", "bytes", "object", "complex"])
def test_frequency_response_refuses_non_numbers(compiled, omega):
    """N21: frequency_response("10") was evaluated at 10 rad/s."""
    plant = compiled.plant({"m": 2.0, "b": 6.0, "c": 0.25})
    with pytest.raises(NumericError, match="omega holds"):
        plant.frequency_response(omega)
    with pytest.raises(NumericError, match="omega holds"):
        compiled.batch({"m": [1.0, 2.0], "b": 6.0, "c": 0.25}).frequency_response(omega)


def test_frequency_response_value_by_hand(compiled):
    """x/F of m s^2 + b s + 1/c at w = 2: 1 / (1/c - m w^2 + j b w)."""
    plant = compiled.plant({"m": 2.0, "b": 6.0, "c": 0.25})
    H = plant.frequency_response([2])[0, 0, 0]
    assert H == pytest.approx(1.0 / (4.0 - 2.0 * 4.0 + 6.0j * 2.0))


@pytest.mark.parametrize("A", [[["1"]], [[1j]], [[None]]], ids=["text", "complex", "object"])
def test_state_space_matrices_must_be_real_numbers(A):
    """N26: a complex A raised a raw TypeError; text was parsed."""
    with pytest.raises(NumericError, match="state-space matrix A holds"):
        NumericStateSpace(A, [[1.0]], [[1.0]], [[0.0]], ("x",), ("u",), ("y",))


def test_arx_refuses_text_and_complex():
    """I10 (strings parsed and fitted), I07 (complex y cast to real)."""
    rng = np.random.default_rng(0)
    u = rng.standard_normal(200)
    y = np.zeros(200)
    for k in range(1, 200):
        y[k] = 0.5 * y[k - 1] + u[k - 1]
    fit = arx(y, u, na=1, nb=1)
    # y[k] = 0.5 y[k-1] + u[k-1] exactly: A = 1 - 0.5 q^-1, B = q^-1
    np.testing.assert_allclose(fit.a, [1.0, -0.5], atol=1e-9)
    with pytest.raises(IdentificationError, match="u: expected an array of real numbers; it holds text"):
        arx(y, [str(v) for v in u], na=1, nb=1)
    with pytest.raises(IdentificationError, match="y: expected an array of real numbers; it holds complex"):
        arx(y + 1j, u, na=1, nb=1)
