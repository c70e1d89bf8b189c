"""Issue 23 item 6: the options of ``equilibrium`` / ``--trim`` are checked, never a raw error.

Reproducers from the audit (../shared/audit/scripts/eq.py): ``tol=nan`` returned a
non-equilibrium of ``q^2 = -1``; a zero inertia raised ``KeyError: 'ComplexInfinity'``;
a ``fixed`` set leaving more equations than unknowns raised scipy's ``ValueError``;
a list as ``guess`` a ``TypeError``.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import bondgraph as bg
from bondgraph.linear import EquilibriumError

V = {"m": 1.0, "b": 1.0}


def duffing(law):
    g = bg.BondGraph("d")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"), bg.C("k", law=law))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "k")]:
        g.connect(t, h)
    return bg.derive(g)


@pytest.mark.parametrize("tol", [float("nan"), float("inf"), -1, 0, "1e-9", True, None])
def test_tol_must_be_a_finite_positive_number(tol):
    with pytest.raises(EquilibriumError, match=r"tol: expected a finite number > 0"):
        duffing(bg.q ** 2).equilibrium(V, {"F": -1.0}, tol=tol)


def test_no_equilibrium_is_not_hidden_by_a_loose_tolerance():
    with pytest.raises(EquilibriumError, match="no equilibrium found"):
        duffing(bg.q ** 2).equilibrium(V, {"F": -1.0}, tol=1e-3)


@pytest.mark.parametrize("exact", [True, False])
def test_zero_inertia_names_the_element(exact):
    # the mass's own rule refuses it before the equations are evaluated
    with pytest.raises(bg.ParameterValueError, match=r"I:m: its mass \(inertance\) m = 0 must be positive"):
        duffing(bg.q ** 3).equilibrium({"m": 0.0, "b": 1.0}, {"F": 0.0}, exact=exact)


def test_fixed_value_no_equilibrium_allows():
    """p_m = 1 makes dq/dt = p/m = 1: 2 equations, 1 free state, no solution."""
    with pytest.raises(EquilibriumError,
                       match=r"with p_m fixed, 2 equations remain for 1 free state.*q_k"):
        duffing(bg.q ** 3).equilibrium(V, {"F": 1.0}, fixed={"p_m": 1.0})


def test_fixed_value_an_equilibrium_allows():
    """p_m = 0 is the equilibrium's: q^3 = F = 8 gives q = 2 with 2 equations for 1 state."""
    eq = duffing(bg.q ** 3).equilibrium(V, {"F": 8.0}, fixed={"p_m": 0.0})
    assert eq.states["q_k"] == pytest.approx(2.0, rel=1e-10)


@pytest.mark.parametrize("option", ["inputs", "guess", "fixed"])
def test_options_must_be_mappings(option):
    kwargs = {"inputs": {"F": 1.0}}
    kwargs[option] = [0, 1]
    inputs = kwargs.pop("inputs")
    with pytest.raises(EquilibriumError, match=rf"{option}: expected a mapping"):
        duffing(bg.q ** 3).equilibrium(V, inputs, **kwargs)


def test_unknown_function_in_a_law_is_named():
    import sympy
    with pytest.raises(bg.NonlinearModelError, match="numpy and scipy cannot evaluate"):
        duffing(bg.q + sympy.Function("h")(bg.q)).equilibrium(V, {"F": 1.0})


def test_exact_solver_has_a_degree_budget():
    """q^(10^6) = 1 is not sent to sympy.solve (it never returned); numerics find q = 1."""
    eq = duffing(bg.q ** (10 ** 6)).equilibrium(V, {"F": 1.0}, guess={"q_k": 1.0000001})
    assert eq.method == "numeric" and eq.states["q_k"] == pytest.approx(1.0, rel=1e-9)


PEND = '''
import sympy
import bondgraph as bg

def model():
    m, g_, l = sympy.symbols("m g l", positive=True)
    gr = bg.BondGraph("pend")
    gr.add(bg.Se("T"), bg.One("w"), bg.I("J"), bg.R("b"),
           bg.C("grav", law=-m * g_ * l * sympy.sin(bg.q)))
    for t, h in [("T", "w"), ("w", "J"), ("w", "b"), ("w", "grav")]:
        gr.connect(t, h)
    return bg.ModelDefinition(gr, outputs={"theta": bg.displacement("grav")},
                              parameters={"m": 1.0, "g": 9.81, "l": 0.5, "J": 0.25, "b": 0.1})
'''


def _cli(tmp_path: Path, monkeypatch, capsys, *args: str) -> tuple[int, str]:
    """The command line's ``main`` in this process (the same code path as the console script)."""
    from bondgraph.cli import main

    (tmp_path / "pend.py").write_text(PEND)
    monkeypatch.chdir(tmp_path)
    status = main(list(args))
    return status, capsys.readouterr().err


def test_cli_trim_zero_inertia_blames_the_params_file(tmp_path, monkeypatch, capsys):
    (tmp_path / "j0.json").write_text('{"J": 0.0, "b": 0.1, "m": 1, "g": 9.81, "l": 0.5}')
    status, err = _cli(tmp_path, monkeypatch, capsys, "export", "pend.py", "--trim", "--params",
                       "j0.json", "-o", "o.json")
    assert status == 1 and "Traceback" not in err
    assert "params file 'j0.json'" in err and "I:J: its mass (inertance) J = 0 must be positive" in err
    assert "ComplexInfinity" not in err
    assert not (tmp_path / "o.json").exists()


def test_cli_trim_contradicting_fix(tmp_path, monkeypatch, capsys):
    status, err = _cli(tmp_path, monkeypatch, capsys, "export", "pend.py", "--trim", "--fix",
                       "p_J=1", "-o", "o.json")
    assert status == 1 and "Traceback" not in err
    assert "--trim" in err and "with p_J fixed" in err
    assert "changed size" not in err
    assert not (tmp_path / "o.json").exists()
