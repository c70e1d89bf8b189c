"""No call in the package can run text (issue 12).

A static check over the package source (every ``sympify`` strict, no
``parse_expr``/``eval``/``exec``/``sympy.S(...)``), then the calls that used
to parse strings, each given a payload that would create a marker file if it
ran, and a model whose parameter symbol is named like Python code, compiled
and simulated numerically.
"""

import ast
from pathlib import Path

import numpy as np
import pytest
import sympy

import bondgraph as bg
from bondgraph.beam import characteristic_expression, hub_characteristic_expression
from bondgraph.tf import SymbolicTF, state_space_latex, transfer_function

PACKAGE = Path(bg.__file__).resolve().parent
#: builtins and sympy entry points that run or parse text into expressions (``compile``
#: only syntax-checks generated code, it runs nothing)
FORBIDDEN_NAMES = {"eval", "exec", "__import__", "parse_expr", "S"}
FORBIDDEN_ATTRS = {"parse_expr", "S", "eval", "exec", "parse_latex", "parse_mathematica"}


def _calls(tree):
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            f = node.func
            if isinstance(f, ast.Attribute):
                yield f.attr, f.attr in FORBIDDEN_ATTRS, node
            else:
                name = getattr(f, "id", None)
                yield name, name in FORBIDDEN_NAMES, node


@pytest.mark.parametrize("path", sorted(PACKAGE.rglob("*.py")), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_source_never_parses_text(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for name, forbidden, node in _calls(tree):
        where = f"{path.relative_to(PACKAGE)}:{node.lineno}"
        assert not forbidden, f"{where}: call of {name}()"
        if name == "sympify":
            strict = [k for k in node.keywords if k.arg == "strict"]
            assert strict and isinstance(strict[0].value, ast.Constant) and strict[0].value.value is True, \
                f"{where}: sympify without strict=True parses strings"


@pytest.fixture
def marker(tmp_path):
    path = tmp_path / "INJECTED"
    yield path
    assert not path.exists(), "injected text ran"


def payload(marker):
    return f"__import__('pathlib').Path({str(marker)!r}).touch()"


def test_transfer_function_D_text_refused(marker):
    with pytest.raises(bg.BondGraphError, match=r"D: .*string .*text is never parsed"):
        transfer_function([[-1]], [[1]], [[1]], D=payload(marker))
    with pytest.raises(bg.BondGraphError, match=r"D: .*string"):
        transfer_function([[-1]], [[1]], [[1]], D=[[payload(marker)]])
    with pytest.raises(bg.BondGraphError, match=r"A: .*string"):
        transfer_function([[payload(marker)]], [[1]], [[1]])


def test_from_expr_text_refused(marker):
    with pytest.raises(bg.BondGraphError, match=r"expr: .*string .*never parsed"):
        SymbolicTF.from_expr(payload(marker))


@pytest.mark.parametrize("arg", ["mass_ratio", "inertia_ratio"])
def test_beam_characteristic_text_refused(marker, arg):
    with pytest.raises(bg.BondGraphError, match=f"{arg}: .*string"):
        characteristic_expression("clamped-free", **{arg: payload(marker)})


@pytest.mark.parametrize("arg", ["hub_ratio", "radius_ratio", "mass_ratio", "inertia_ratio"])
def test_hub_characteristic_text_refused(marker, arg):
    kwargs = {"hub_ratio": 1, arg: payload(marker)}
    with pytest.raises(bg.BondGraphError, match=f"{arg}: .*string"):
        hub_characteristic_expression(**kwargs)


def test_latex_matrices_text_refused(marker):
    with pytest.raises(bg.BondGraphError, match=r"B: .*string"):
        state_space_latex([[-1]], [[payload(marker)]])


def test_linearize_point_text_refused(marker):
    g = bg.BondGraph("m")
    g.add(bg.Se("F"), bg.I("m"))
    g.connect("F", "m")
    with pytest.raises(bg.BondGraphError, match=r"state 'p_m': .*string"):
        bg.derive(g).linearize({"p_m": payload(marker)}, {"F": 0})


def test_parameter_values_text_refused(marker):
    g = bg.BondGraph("m")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b")]:
        g.connect(t, h)
    model = bg.derive(g, outputs={"v": bg.flow("m")})
    for call in (bg.compile_plant(model).plant, model.state_space().subs,
                 model.transfer_function().subs):
        with pytest.raises(bg.ParameterValueError, match="text is never parsed"):
            call({"m": payload(marker), "b": 1.0})


def test_element_parameter_text_is_an_identifier_or_refused(marker):
    with pytest.raises(bg.ParameterError):
        bg.R("b", payload(marker))


def test_symbol_named_like_code_is_only_a_name(marker):
    """A sympy Symbol whose name is Python code stays a name through lambdify and simulate.

    x' = -x/tau with tau = 0.5 and x(0) = 1: x(1) = exp(-2) (hand solution).
    """
    tau = sympy.Symbol(payload(marker), positive=True)
    g = bg.BondGraph("decay")
    g.add(bg.One("j"), bg.C("c", 1), bg.R("r", tau))
    g.connect("j", "c")
    g.connect("j", "r")
    model = bg.derive(g)
    assert [p.name for p in model.parameters] == [tau.name]
    P = bg.compile_plant(model).plant({tau: 0.5})
    assert np.allclose(P.A, [[-2.0]])
    res = bg.simulate(model, {tau: 0.5}, t_span=(0.0, 1.0), x0={"q_c": 1.0}, rtol=1e-10, atol=1e-12)
    assert res.x[-1, 0] == pytest.approx(np.exp(-2.0), rel=1e-7)
