r"""``Model.to_latex`` and ``Model.equations`` (issue 14): expected strings written
by hand from the DC-motor equations ``La di/dt = V - Ra i - K omega``,
``J domega/dt = K i - b omega`` in the momenta ``p_La = La i``, ``p_J = J omega``;
the LaTeX compiles with pdflatex where it is installed."""

import shutil
import subprocess

import pytest
import sympy

import bondgraph as bg


def dc_motor():
    g = bg.BondGraph("dc")
    i, w = bg.One("i"), bg.One("w")
    g.add(bg.Se("V"), i, bg.R("Ra"), bg.I("La"), bg.GY("K"), w, bg.I("J"), bg.R("b"))
    for t, h in [("V", i), (i, "Ra"), (i, "La"), (i, "K"), ("K", w), (w, "J"), (w, "b")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"omega": bg.flow("J")})


def hierarchical():
    sub = bg.BondGraph("motor")
    sub.add(bg.Se("V"), bg.One("i"), bg.R("Ra"), bg.I("La"), bg.Port("shaft"))
    for t, h in [("V", "i"), ("i", "Ra"), ("i", "La"), ("i", "shaft")]:
        sub.connect(t, h)
    top = bg.BondGraph("top")
    top.add(sub, bg.One("w"), bg.R("b"))
    top.connect("motor.shaft", "w")
    top.connect("w", "b")
    return bg.derive(top, outputs={"i": bg.flow("motor.La")})


DC_LATEX = "\n".join([
    r"\begin{aligned}",
    r"\dot{p}_{La} &= V - \frac{Ra p_{La}}{La} - \frac{K p_{J}}{J} \\",
    r"\dot{p}_{J} &= \frac{K p_{La}}{La} - \frac{b p_{J}}{J} \\",
    r"\omega &= \frac{p_{J}}{J}",
    r"\end{aligned}"])


def test_dc_motor_latex():
    assert dc_motor().to_latex() == DC_LATEX


def test_hierarchical_names_are_upright_paths():
    # La i' = V - (Ra + b) i: one state, the motor's inductor momentum
    text = hierarchical().to_latex()
    assert text.splitlines()[1].startswith(r"\dot{p}_{\mathrm{motor}.La} &= ")
    assert r"\mathrm{motor}.V" in text and r"\mathrm{motor}.Ra" in text


def test_matrices_appended_for_a_linear_model():
    text = dc_motor().to_latex(matrices=True)
    assert text.startswith(DC_LATEX) and r"\left[\begin{matrix}" in text


def test_equations_are_derivatives_in_time():
    eqs = dc_motor().equations
    p_La, p_J = sympy.symbols("p_La p_J", real=True)
    assert eqs[0].lhs == sympy.Derivative(p_La, bg.t, evaluate=False)
    assert eqs[1].lhs == sympy.Derivative(p_J, bg.t, evaluate=False)
    assert sympy.latex(eqs[0].lhs) == r"\frac{d}{d t} p_{La}"


@pytest.mark.parametrize("build", [dc_motor, hierarchical])
def test_latex_compiles(tmp_path, build):
    if shutil.which("pdflatex") is None:
        pytest.skip("pdflatex not installed (Debian: texlive-latex-base); .ci/run installs it")
    doc = "\n".join([r"\documentclass{article}", r"\usepackage{amsmath}", r"\begin{document}",
                     r"\begin{equation}", build().to_latex(matrices=build is dc_motor),
                     r"\end{equation}", r"\end{document}"])
    (tmp_path / "m.tex").write_text(doc)
    run = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "m.tex"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout[-2000:]
    assert (tmp_path / "m.pdf").stat().st_size > 1000


def test_state_space_print_aligns_matrix_rows():
    # every row of a printed matrix starts in the column after "A = "
    text = str(dc_motor().state_space())
    a_rows = [ln for ln in text.splitlines() if ln.startswith("A = ") or
              (ln.startswith("    [") and not ln.startswith("     "))]
    assert a_rows and all(ln[4] == "[" for ln in a_rows)
    assert sum(ln.startswith("A = ") for ln in text.splitlines()) == 1


def test_pole_zero_table_html():
    from bondgraph.tf.tables import pole_zero_table
    html = pole_zero_table([1.0, 0.0], [1.0, 3.0, 2.0])._repr_html_()   # s/((s+1)(s+2))
    assert html.startswith("<table>") and html.count("<tr>") == 4
    assert "<td>zero</td><td>0</td>" in html
