"""compile_plant's numpy evaluation of monomial entries against sympy evaluation of the same entries.

The reference is independent of the compiler: every entry of the model's
symbolic ``A, B, C, D`` (and ``D_derivatives``, ``state_shift``) is evaluated
by sympy (``xreplace`` of the parameter values as 30-digit Floats, then
``evalf(30)``), and the compiled plant must agree to 1e-13 relative (times
the entry's condition number where a sum cancels: with random signs,
``R1*R2 - R1*R3`` is only known to its terms' rounding, whatever evaluates
it).  Checked
on random graphs of ``tests/verification/generator.py`` (positive values,
then random signs, one parameter set and batches), on every model of
``models/``, and on zero parameters (a non-finite entry is refused exactly
when sympy's value is infinite or undefined).
"""

from __future__ import annotations

import random
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.numeric._monomials import classify, compile_entries
from bondgraph.numeric.plant import _reduced_form

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "models"))

from verification import generator as gen  # noqa: E402

RTOL = 1e-13


def _value_and_condition(ex, sub) -> tuple:
    """``(value, kappa)``: ``ex`` at ``sub`` by sympy (30 digits) and a relative condition
    number: 1 for a monomial, ``sum |t_i| / |sum t_i|`` for a sum (cancellation), the
    largest of its factors' for a product or power."""
    if ex.is_Add:
        parts = [_value_and_condition(t, sub) for t in ex.args]
        total = sum(v for v, _ in parts)
        mags = sum(abs(v) * k for v, k in parts)
        return total, (mags / abs(total) if total != 0 else sympy.oo)
    if ex.is_Mul or ex.is_Pow:
        parts = [_value_and_condition(a, sub) for a in (ex.args if ex.is_Mul else (ex.base,))]
        return sympy.N(ex.xreplace(sub), 30), max(k for _, k in parts)
    return sympy.N(ex.xreplace(sub), 30), 1


def reference(model, values: dict) -> list[tuple[np.ndarray, np.ndarray]]:
    """Each matrix of the plant evaluated by sympy at ``values`` (name -> float), dense, with
    the tolerance of each entry: ``RTOL * |value| * kappa`` (see :func:`_value_and_condition`)."""
    mats, _ = _reduced_form(model)
    sub = {p: sympy.Float(values[p.name], 30) for p in model.parameters}
    out = []
    for M in mats:
        A, T = np.zeros(M.shape), np.zeros(M.shape)
        for (i, j), ex in M.todok().items():
            v, kappa = _value_and_condition(ex, sub)
            A[i, j] = float(v) if v.is_finite else np.nan
            T[i, j] = RTOL * abs(A[i, j]) * float(kappa)
        out.append((A, T))
    return out


def compiled(plant) -> list[np.ndarray]:
    dense = lambda M: M.toarray() if hasattr(M, "toarray") else np.asarray(M)  # noqa: E731
    return [dense(M) for M in (plant.A, plant.B, plant.C, plant.D, *plant.D_derivatives,
                               *plant.state_shift)]


def assert_close(got: list, want: list, where: str) -> None:
    assert len(got) == len(want), where
    for k, (g, (w, tol)) in enumerate(zip(got, want)):
        err = np.abs(g - w)
        assert np.all(err <= tol), (where, k, float((err / np.maximum(tol, 1e-300)).max()))


def random_values(model, rng: random.Random, signs: bool) -> dict:
    return {p.name: rng.uniform(0.3, 3.0) * (rng.choice((-1, 1)) if signs else 1)
            for p in model.parameters}


GRAPH_SEEDS = range(96)


@pytest.mark.parametrize("chunk", range(4))
def test_random_graphs_agree_with_sympy(chunk):
    checked = 0
    for seed in GRAPH_SEEDS[chunk::4]:
        g = gen.generate(seed)
        bgg, outputs, _ = gen.build(g, seed)
        try:
            model = bg.derive(bgg, outputs=outputs)
            nm = bg.compile_plant(model)
        except bg.BondGraphError:
            continue                  # ill-posed graphs are refused before compilation
        rng = random.Random(seed)
        for signs in (False, True):
            vals = random_values(model, rng, signs)
            try:
                plant = nm.plant(vals)
            except bg.BondGraphError:
                continue              # a singular algebraic loop at these values
            assert_close(compiled(plant), reference(model, vals), f"seed {seed} signs {signs}")
        checked += 1
        if not model.parameters:
            continue
        sets = [random_values(model, rng, True) for _ in range(3)]
        try:
            batch = nm.batch({k: [s[k] for s in sets] for k in sets[0]}, sparse=False)
        except (bg.BondGraphError, IndexError):
            continue
        for r, vals in enumerate(sets):
            assert_close(compiled(batch[r]), reference(model, vals), f"seed {seed} batch {r}")
    assert checked >= 10


def _models():
    import appendages
    import flexcam
    import srv02

    defs = [("srv02", srv02.model()), ("srv02-L0", srv02.model(inductance=False)),
            ("flexcam-paper", flexcam.model(n_modes=3)),
            ("flexcam-system", flexcam.model(n_modes=3, formulation="system",
                                             damping_ratio=0.01)),
            ("appendages", appendages.model(n_modes=2)),
            ("appendages-paper", appendages.model(n_modes=2, formulation="paper"))]
    return defs


@pytest.mark.parametrize("name, defn", _models(), ids=lambda x: x if isinstance(x, str) else "")
def test_models_agree_with_sympy(name, defn):
    model = bg.derive(defn.graph, outputs=defn.outputs)
    nm = bg.compile_plant(model)
    rng = random.Random(name)
    given = {k: float(v) for k, v in defn.parameters.items()}
    vals = {p.name: given.get(p.name, rng.uniform(0.5, 2.0)) for p in model.parameters}
    assert_close(compiled(nm.plant(vals)), reference(model, vals), name)
    signed = {k: v * rng.choice((-1, 1)) for k, v in vals.items()}
    try:
        plant = nm.plant(signed)
    except bg.BondGraphError:
        return
    assert_close(compiled(plant), reference(model, signed), name + " signed")


def test_zero_parameter_refused_exactly_where_sympy_is_infinite():
    g = bg.BondGraph("msd")
    F, v = bg.Se("F"), bg.One("v")
    # active elements: their signs are not checked by the elements' rules, so the zeros
    # reach the compiled entries, whose own check is tested here
    g.add(F, v, bg.I("m", "m", active=True), bg.R("b"), bg.C("k", stiffness="k", active=True))
    for t, h in [(F, v), (v, "m"), (v, "b"), (v, "k")]:
        g.connect(t, h)
    model = bg.derive(g, outputs={"x": bg.displacement("k")})
    nm = bg.compile_plant(model)
    # b = 0, k = 0: every entry finite (A = [[0, -0], [1/m, 0]] up to signs)
    vals = {"m": 2.0, "b": 0.0, "k": 0.0}
    assert_close(compiled(nm.plant(vals)), reference(model, vals), "b = k = 0")
    with pytest.raises(bg.BondGraphError, match="m = 0"):
        nm.plant({"m": 0.0, "b": 1.0, "k": 1.0})              # -b/m, 1/m: infinite


def test_classes_and_duplicates():
    x, y, z = sympy.symbols("x y z")
    index = {x: 0, y: 1, z: 2}
    assert classify(sympy.Rational(-3, 7) * x**3 / (y * z**2), index) == (
        "monomial", (-3 / 7, (0, 0, 0), (1, 2, 2)))
    assert classify(x / y - 2 * z, index)[0] == "sum"
    for general in (sympy.sqrt(x), x**sympy.Rational(1, 3), (x + y) / z, sympy.exp(x) * y,
                    x * sympy.I, x * sympy.Symbol("unknown")):
        assert classify(general, index)[0] == "general", general
    ce = compile_entries([x, y, z], [x / y, (x + y) / z, x / y, (x + y) / z, 2 * x + y])
    assert ce.counts == {"monomial": 2, "sum": 1, "general": 2}
    assert len(ce.general._exprs) == 1                          # one distinct general entry
    cols = [np.float64(-2.0), np.float64(4.0), np.float64(-0.5)]
    # by hand: -0.5, (2)/(-0.5) = -4, -0.5, -4, 0
    assert ce.evaluate(cols, None).tolist() == [-0.5, -4.0, -0.5, -4.0, 0.0]
    batch = ce.evaluate([np.array([-2.0, 1.0]), np.array([4.0, 1.0]), np.array([-0.5, 2.0])], 2)
    assert batch.tolist() == [[-0.5, -4.0, -0.5, -4.0, 0.0], [1.0, 1.0, 1.0, 1.0, 3.0]]
