"""MTT's Hybrid/Bounce example reproduced: a ball with air resistance bouncing on a springy ground.

MTT (examples/Hybrid/Bounce): m = 1, r = 1 (linear air resistance), k_g = 100 (ground
stiffness, acting while the height h < 0), gravity 9.81, released at rest from h = 10,
simulated over 10 time units.  The reference here is an independent two-state ODE
m h'' = -m g - r h' - k_g h [h < 0], integrated piecewise with its own events.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import bondgraph as bg
from bondgraph.hybrid import SwitchedModel, library, simulate

M, RA, KG, G, H0, T_END = 1.0, 1.0, 100.0, 9.81, 10.0, 10.0


def reference():
    """Crossings of h = 0 and a dense h(t), by an independent piecewise integration."""
    def flight(t, y):
        return [y[1], -G - RA * y[1] / M]

    def contact(t, y):
        return [y[1], -G - RA * y[1] / M - KG * y[0] / M]

    def land(t, y):             # flight ends when h falls through 0
        return y[0]
    land.terminal, land.direction = True, -1

    def leave(t, y):            # contact ends when h rises through 0
        return y[0]
    leave.terminal, leave.direction = True, 1

    t, y, rhs = 0.0, [H0, 0.0], flight
    times, pieces = [], []
    while t < T_END:
        sol = solve_ivp(rhs, (t, T_END), y, events=land if rhs is flight else leave,
                        rtol=1e-11, atol=1e-12, dense_output=True)
        pieces.append((t, sol.t[-1], sol.sol))
        if sol.status != 1:
            break
        t, y = sol.t_events[0][0], sol.y_events[0][0]
        times.append(t)
        rhs = contact if rhs is flight else flight
    def h(tt):
        for a, b, f in pieces:
            if a <= tt <= b:
                return f(tt)[0]
        raise ValueError(tt)
    return np.array(times), h


def test_bounce_matches_mtt_example():
    sm = SwitchedModel(library.bounce(), outputs={"h": bg.displacement("ball")})
    grid = np.linspace(0, T_END, 201)
    res = simulate(sm, (0, T_END), {"h": H0}, values={"m": M, "r": RA, "k_g": KG, "g": G},
                   t_eval=grid)
    times, h = reference()
    got = res.event_times("ground")
    assert len(got) == len(times) >= 10
    np.testing.assert_allclose(got, times, rtol=0, atol=1e-6)
    sel = np.isin(res.t, grid)
    np.testing.assert_allclose(res.outputs["h"][sel], [h(t) for t in res.t[sel]], atol=1e-5)
    # the first landing: free fall with linear drag, by hand  h(t) = H0 - (g m/r) t + (g m^2/r^2)(1 - e^{-r t/m})
    t1 = got[0]
    assert H0 - G * M / RA * t1 + G * M ** 2 / RA ** 2 * (1 - np.exp(-RA * t1 / M)) == pytest.approx(0, abs=1e-8)
    # the bounces die out: each apex lower than the one before
    apex = [res.outputs["h"][(res.t > a) & (res.t < b)].max() for a, b in zip(got[1::2], got[2::2])]
    assert all(x > y for x, y in zip(apex, apex[1:]))
