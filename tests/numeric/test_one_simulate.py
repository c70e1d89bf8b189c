"""One ``bondgraph.simulate`` for smooth, implicit and switched models, one result protocol.

Hand references:

* a mass m pushed by a constant force F from rest: p_m = F t, v = F t / m;
* an RL circuit (E = 1 V, R = 1 ohm, L = 1 H) whose switch opens at t = 1 s:
  i = 1 - e^{-t} before, 0 after (the ideal switch takes the current to zero).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import bondgraph as bg
from bondgraph import hybrid
from bondgraph.errors import ParameterValueError
from bondgraph.numeric.errors import NumericError
from bondgraph.numeric.result import TimeResponse


def mass():
    g = bg.BondGraph("mass")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"))
    g.connect("F", "v"); g.connect("v", "m")
    return bg.derive(g, outputs={"vel": bg.flow("m")})


def rl_switch():
    g = bg.BondGraph("rl")
    g.add(bg.Se("E"), bg.One("i"), bg.R("R"), bg.I("L"),
          hybrid.ControlledSwitch("S", gate=1 - bg.t, on=True))
    for a, b in [("E", "i"), ("i", "R"), ("i", "L"), ("i", "S")]:
        g.connect(a, b)
    return hybrid.SwitchedModel(g, outputs={"i": bg.flow("L")})


GRID = [0.0, 0.5, 1.5, 2.0]


def test_smooth_result_by_name_and_as_a_table():
    res = bg.simulate(mass(), {"m": 2.0}, (0.0, 2.0), u={"F": 3.0}, t_eval=GRID, rtol=1e-10, atol=1e-12)
    assert isinstance(res, TimeResponse) and res.events == ()
    assert res.names == ("vel", "p_m", "F")
    t = np.array(GRID)
    np.testing.assert_allclose(res["vel"], 3.0 * t / 2.0, atol=1e-9)
    np.testing.assert_allclose(res["p_m"], 3.0 * t, atol=1e-9)
    np.testing.assert_allclose(res["F"], 3.0)
    assert "vel" in res and "nope" not in res
    with pytest.raises(KeyError, match="no output, state or input named 'nope'.*outputs: vel"):
        res["nope"]
    pd = pytest.importorskip("pandas")
    df = res.to_dataframe()
    assert isinstance(df, pd.DataFrame) and list(df.columns) == ["vel", "p_m", "F"]
    assert df.index.name == "t" and df.loc[2.0, "vel"] == pytest.approx(3.0)
    assert list(res.to_dataframe("vel").columns) == ["vel"]


def test_switched_result_by_name_with_inputs_and_modes():
    res = bg.simulate(rl_switch(), {"R": 1.0, "L": 1.0}, (0.0, 2.0), u={"E": 1.0}, t_eval=GRID)
    assert isinstance(res, TimeResponse) and isinstance(res, hybrid.SwitchedResult)
    assert res.names == ("i", "p_L", "E")
    assert [round(e.time, 9) for e in res.events] == [1.0]
    before = res.mode_index == 0                    # S on, until the gate 1 - t falls through 0
    np.testing.assert_allclose(res["i"][before], 1 - np.exp(-res.t[before]), atol=1e-8)
    np.testing.assert_allclose(res["i"][~before], 0.0, atol=1e-9)
    np.testing.assert_allclose(res["E"], 1.0)
    pytest.importorskip("pandas")
    df = res.to_dataframe(["i"])
    assert list(df.columns) == ["i", "mode"]
    assert df["mode"].iloc[0] == "S on" and df["mode"].iloc[-1] == "S off"


def test_input_histories_follow_a_function_of_time():
    res = bg.simulate(rl_switch(), {"R": 1.0, "L": 1.0}, (0.0, 2.0), u={"E": lambda t: 2.0 * t},
                      t_eval=GRID)
    np.testing.assert_allclose(res["E"], 2.0 * res.t)


def test_plot_draws_the_chosen_signals_and_the_events():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res = bg.simulate(rl_switch(), {"R": 1.0, "L": 1.0}, (0.0, 2.0), u={"E": 1.0})
    ax = res.plot()
    labels = [line.get_label() for line in ax.get_lines()]
    assert labels == ["i", "events"]
    assert ax.get_xlabel() == "t [s]"
    with pytest.raises(KeyError):
        res.plot("nope")
    plt.close("all")


def test_old_switched_call_forms_warn_and_give_the_same_run():
    sm, values = rl_switch(), {"R": 1.0, "L": 1.0}
    new = bg.simulate(sm, values, (0.0, 2.0), u={"E": 1.0}, t_eval=GRID)
    with pytest.warns(DeprecationWarning, match="bondgraph.simulate"):
        old = hybrid.simulate(sm, (0.0, 2.0), values=values, inputs={"E": 1.0}, t_eval=GRID)
    with pytest.warns(DeprecationWarning, match="bondgraph.simulate"):
        meth = sm.simulate((0.0, 2.0), None, values=values, inputs={"E": 1.0}, t_eval=GRID)
    for res in (old, meth):
        np.testing.assert_array_equal(res["i"], new["i"])
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # the one form does not warn
        hybrid.simulate(sm, values, (0.0, 2.0), u={"E": 1.0}, t_eval=GRID)
        sm.simulate(values, (0.0, 2.0), u={"E": 1.0}, t_eval=GRID)


def test_event_options_go_to_switched_models_only():
    with pytest.raises(NumericError, match="max_events apply to switched models"):
        bg.simulate(mass(), {"m": 1.0}, (0.0, 1.0), max_events=3)
    with pytest.raises(hybrid.EventBudgetError):
        bg.simulate(rl_switch(), {"R": 1.0, "L": 1.0}, (0.0, 2.0), u={"E": 1.0}, max_events=0)


@pytest.mark.parametrize("switched", [False, True], ids=["smooth", "switched"])
def test_an_input_given_as_a_parameter_is_named_as_an_input(switched):
    if switched:
        call = lambda: bg.simulate(rl_switch(), {"R": 1.0, "L": 1.0, "E": 1.0}, (0.0, 1.0))
    else:
        call = lambda: bg.simulate(mass(), {"m": 1.0, "F": 2.0}, (0.0, 1.0))
    with pytest.raises(ParameterValueError) as info:
        call()
    text = str(info.value)
    assert "is an input of the model, not a parameter" in text and "unknown parameter" not in text


def test_plant_names_an_input_given_as_a_parameter():
    with pytest.raises(ParameterValueError, match="'F' is an input of the model"):
        bg.compile_plant(mass()).plant({"m": 1.0, "F": 2.0})
    assert math.isclose(bg.compile_plant(mass()).plant({"m": 2.0}).C[0, 0], 0.5)
