"""Issue 11, numeric side: minimal realizations and plants export refuses to mislabel."""

import numpy as np
import pytest

import bondgraph as bg
from bondgraph.export import ExportError, export
from bondgraph.numeric import NumericStateSpace
from helpers import connect_all


def test_minimal_realization_drops_a_redundant_integrator():
    """Mass-spring-damper with the position integrated a second time (what the
    engine once built): states p, q, x with x' = p/m duplicates q.  Minimal
    realization: 2 states, and X/F = 1/(m s^2 + b s + k) unchanged."""
    m, b, k = 2.0, 0.5, 8.0
    A = np.array([[-b / m, -k, 0.0], [1 / m, 0.0, 0.0], [1 / m, 0.0, 0.0]])
    B = np.array([[1.0], [0.0], [0.0]])
    C = np.array([[0.0, 0.0, 1.0]])
    plant = NumericStateSpace(A, B, C, [[0.0]], ("p", "q", "x"), ("F",), ("x",))
    ctrb = np.hstack([np.linalg.matrix_power(A, i) @ B for i in range(3)])
    assert np.linalg.matrix_rank(ctrb) == 2
    red = plant.minimal()
    assert red.nstates == 2 and red.input_names == ("F",) and red.output_names == ("x",)
    w = np.array([0.3, 1.0, 2.0, 7.0])
    expected = 1 / (m * (1j * w) ** 2 + b * 1j * w + k)
    assert np.allclose(red.frequency_response(w)[:, 0, 0], expected, rtol=1e-10)


def test_export_refuses_improper_plants(tmp_path):
    """Sf v on a 1-junction with a mass: the source's effort is F = m dv/dt."""
    g = bg.BondGraph("shaker")
    g.add(bg.Sf("v"), bg.One("j"), bg.I("m"), bg.R("b"))
    connect_all(g, [("v", "j"), ("j", "m"), ("j", "b")])
    model = bg.derive(g, outputs={"F": bg.effort(1)})
    plant = bg.compile_plant(model).plant({"m": 2.0, "b": 0.5})
    assert not plant.is_proper
    with pytest.raises(ExportError, match="improper"):
        export(plant, tmp_path / "p.mat")
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(bg.ImproperPlantError):
        plant.to_control()


def test_import_does_not_load_matplotlib():
    """Plotting and PNG output load matplotlib on first use only (a fresh interpreter)."""
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c",
                          "import sys, bondgraph; print('matplotlib' in sys.modules)"],
                         capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
