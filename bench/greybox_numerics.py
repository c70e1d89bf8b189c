"""Benchmark: the grey-box fit's numerics, hand-written against scipy.

Issue 13 asked to replace three hand-written pieces of
:mod:`bondgraph.identification` by scipy unless a benchmark shows them needed:

* ``_expm`` (scaling and squaring, [6/6] Padé, numpy) by ``scipy.linalg.expm``;
* ``_discretize`` (the zero/first-order-hold block exponentials of
  ``scipy.signal.cont2discrete``, on ``_expm``) by ``cont2discrete`` itself;
* ``_central_jacobian`` (central differences at the optimum for the
  covariance, after ``least_squares`` ran with forward differences) by
  ``least_squares(jac="3-point")`` and its ``jac`` at the optimum.

Outcome: the Jacobian is now scipy's (equal accuracy, a few more residual
evaluations); ``_expm``/``_discretize`` stay (in
:mod:`bondgraph.identification.sampled`), because ``scipy.linalg.expm`` solves
with LAPACK ``getrs``, which OpenBLAS runs multithreaded even for 3 x 3
matrices: with the cores busy its calls stall (see the latency percentiles in
part 1 and the fit times in part 3; compare a run with
``OPENBLAS_NUM_THREADS=1``).  ``_central_jacobian`` is copied below, as it was.

Problems, the sizes of tests/identification/test_greybox.py and tests/models/test_validation.py:

* SRV-02 hub (2 states, 1 input, dt = 5 ms) and FLEXCAM system formulation with
  3 modes (8 states, dt = 1 ms): exponentials of the zoh (n+1) and foh (n+2)
  block matrices and the discretisations; accuracy against mpmath at 50
  digits (relative max-norm error), time per call (min, median, 90th
  percentile of single calls);
* whole fits, best of ``--repeat``: SRV-02 time-domain ``Jm``, ``Beq`` (8000
  samples, noise), SRV-02 ``k_pot`` (linear in the parameter: the exact OLS
  standard error is known), FLEXCAM frequency-domain ``k_1..k_3`` (Welch FRF
  of 60 s of lsim data), FLEXCAM time-domain ``k_1..k_3`` (first 4 s of the
  same record, first-order hold), and the mass-spring-damper of
  tests/identification/test_greybox.py with 5 % noise; three variants of ``greybox_fit``:
  ``old`` (forward differences, ``_central_jacobian`` at the end, ``_discretize``),
  ``shipped`` (``jac="3-point"``, ``_discretize``) and ``c2d`` (``jac="3-point"``,
  ``cont2discrete``).  Reported: time, residual evaluations (Jacobian ones
  included), largest relative difference of estimates and standard errors
  from ``old``.

Run from the repository root::

    python bench/greybox_numerics.py                          # about 20 s on an idle machine
    python bench/greybox_numerics.py --busy 2                 # with 2 extra processes spinning
    OPENBLAS_NUM_THREADS=1 python bench/greybox_numerics.py --busy 2   # BLAS single threaded
    python bench/greybox_numerics.py --repeat 1               # fits timed once
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import time
from pathlib import Path
from typing import Any, Callable
from unittest import mock

import numpy as np
import scipy.linalg
import scipy.optimize
import scipy.signal

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "models"))

import bondgraph as bg  # noqa: E402
from bondgraph.identification import (FrequencyData, TimeData, estimate_frf,  # noqa: E402
                                      greybox_fit, prbs)
from bondgraph.identification import greybox as greybox_module  # noqa: E402
from bondgraph.identification.sampled import _discretize, _dlsim, _expm  # noqa: E402
from bondgraph.numeric import compile_plant  # noqa: E402


# ----------------------------------------------------------- the hand-written pieces
hand_expm = _expm
hand_discretize = _discretize


def hand_central_jacobian(fun, x, lo, hi, step=1e-5):
    """The former ``greybox._central_jacobian`` (one-sided next to a bound), unchanged."""
    f0 = fun(x)
    J = np.empty((f0.size, x.size))
    for i in range(x.size):
        h = step * max(1.0, abs(float(x[i])))
        up, down = x[i] + h <= hi[i], x[i] - h >= lo[i]
        xp, xm = x.copy(), x.copy()
        if up and down:
            xp[i] += h
            xm[i] -= h
            J[:, i] = (fun(xp) - fun(xm)) / (2 * h)
        elif up:
            xp[i] += h
            J[:, i] = (fun(xp) - f0) / h
        else:
            xm[i] -= h
            J[:, i] = (f0 - fun(xm)) / h
    return J


def scipy_discretize(A, B, C, D, dt, method):
    Ad, Bd, Cd, Dd, _ = scipy.signal.cont2discrete((A, B, C, D), dt, method=method)
    return Ad, Bd, Cd, Dd


# ----------------------------------------------------------- references (mpmath)
def mp_expm(M: np.ndarray):
    import mpmath

    with mpmath.workdps(50):
        return mpmath.expm(mpmath.matrix(M.tolist()))


def mp_to_np(X) -> np.ndarray:
    return np.array(X.tolist(), dtype=float)


def mp_discretize(A, B, C, D, dt, method):
    """Reference discretisation: the same block exponentials, in 50-digit arithmetic."""
    import mpmath

    n, m = B.shape
    with mpmath.workdps(50):
        if method == "zoh":
            M = np.zeros((n + m, n + m))
            M[:n, :n], M[:n, n:] = A * dt, B * dt
            E = mp_to_np(mp_expm(M))
            return E[:n, :n], E[:n, n:], C, D
        M = np.zeros((n + 2 * m, n + 2 * m))
        M[:n, :n], M[:n, n:n + m] = A * dt, B * dt
        M[n:n + m, n + m:] = np.eye(m)
        E = mp_expm(M)
        ms11 = E[:n, :n]
        ms13 = E[:n, n + m:]
        bd = E[:n, n:n + m] - ms13 + ms11 * ms13
        dd = mpmath.matrix(D.tolist()) + mpmath.matrix(C.tolist()) * ms13
        return mp_to_np(ms11), mp_to_np(bd), C, mp_to_np(dd)


def rel_err(X: np.ndarray, ref: np.ndarray) -> float:
    scale = np.max(np.abs(ref))
    return float(np.max(np.abs(X - ref)) / scale) if scale else float(np.max(np.abs(X)))


def latency(f: Callable[[], Any], calls: int = 2000) -> tuple[float, float, float]:
    """Min, median and 90th percentile of single calls, in microseconds."""
    f()
    ts = np.empty(calls)
    for i in range(calls):
        t0 = time.perf_counter()
        f()
        ts[i] = time.perf_counter() - t0
    ts *= 1e6
    return float(ts.min()), float(np.median(ts)), float(np.percentile(ts, 90))


def fmt(lat: tuple[float, float, float]) -> str:
    return "/".join(f"{x:.0f}" for x in lat)


# ----------------------------------------------------------- problems
def hub_problem():
    """SRV-02 hub, as tests/models/test_validation.py: 8000 samples at 200 Hz, noise."""
    import srv02

    model = bg.derive(srv02.build(inductance=False), outputs=srv02.outputs())
    nm = compile_plant(model)
    values = {p.name: srv02.PARAMETERS[p.name] for p in model.parameters}
    plant = nm.plant(values)
    dt = 0.005
    u = prbs(10, clock_divider=4, length=8000)
    i = plant.output_names.index("theta")
    sysd = scipy.signal.cont2discrete((plant.A, plant.B, plant.C[[i]], plant.D[[i]]), dt)
    _, theta, _ = scipy.signal.dlsim(sysd[:4] + (dt,), u)
    y = theta[:, 0] + 2e-4 * np.random.default_rng(2024).standard_normal(u.size)
    return nm, values, plant, u, theta[:, 0], y, dt


def flex_problem():
    """FLEXCAM system formulation, 3 modes, 2 % damping, as tests/models/test_validation.py."""
    import flexcam

    g, outs, params = flexcam.build(3, formulation="system", damping_ratio=0.02)
    model = bg.derive(g, outputs=outs)
    nm = compile_plant(model)
    values = {p.name: params[p.name] for p in model.parameters}
    plant = nm.plant(values)
    rng = np.random.default_rng(5)
    fs, over, n = 1000.0, 4, 60000
    fine = fs * over
    sos = scipy.signal.butter(8, 200.0, fs=fine, output="sos")
    uf = scipy.signal.sosfilt(sos, rng.standard_normal(n * over))
    uf /= uf.std()
    i, j = plant.input_names.index("hub.e_in"), plant.output_names.index("y")
    t_fine = np.arange(uf.size) / fine
    _, yf, _ = scipy.signal.lsim((plant.A, plant.B[:, [i]], plant.C[[j]], plant.D[[j]][:, [i]]),
                                 uf, t_fine, interp=True)
    u, y = uf[::over], yf[::over]
    y = y + 0.02 * y.std() * rng.standard_normal(n)
    frf = estimate_frf(u, y, fs=fs, nperseg=4096)
    return nm, values, plant, u, y, 1.0 / fs, frf


def msd_problem():
    g = bg.BondGraph("msd")
    F, v = bg.Se("F"), bg.One("v")
    g.add(F, v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
    for a, b in [(F, v), (v, "m"), (v, "b"), (v, "k")]:
        g.connect(a, b)
    nm = compile_plant(bg.derive(g, outputs={"x": bg.displacement("k")}))
    dt = 0.05
    u = prbs(7, clock_divider=3)
    A = np.array([[0.0, 1.0], [-4.0, -0.4]])
    sysd = scipy.signal.cont2discrete((A, np.array([[0.0], [1.0]]), np.array([[1.0, 0.0]]),
                                       np.zeros((1, 1))), dt)
    _, y, _ = scipy.signal.dlsim(sysd[:4] + (dt,), u)
    y = y[:, 0] + 0.05 * y.std() * np.random.default_rng(11).standard_normal(u.size)
    return nm, u, y, dt


# ----------------------------------------------------------- the two fit variants
_least_squares = scipy.optimize.least_squares


class Counter:
    def __init__(self):
        self.calls = 0

    def wrap(self, fun):
        def counted(x):
            self.calls += 1
            return fun(x)
        return counted


@contextlib.contextmanager
def variant(name: str, counter: Counter):
    """``greybox_fit`` as shipped, as before issue 13 (``old``) or on ``cont2discrete`` (``c2d``)."""
    if name == "old":
        def ls(fun, x0, *, jac, bounds, **kw):
            fun = counter.wrap(fun)
            sol = _least_squares(fun, x0, bounds=bounds, **kw)       # forward differences
            sol.jac = hand_central_jacobian(fun, sol.x, *bounds)
            return sol
    else:
        def ls(fun, x0, **kw):
            return _least_squares(counter.wrap(fun), x0, **kw)
    disc = scipy_discretize if name == "c2d" else _discretize
    with mock.patch("scipy.optimize.least_squares", ls), \
            mock.patch.object(greybox_module, "_discretize", disc):
        yield


def run_fit(name: str, call: Callable[[], Any], repeat: int):
    best, result, evals = np.inf, None, 0
    for _ in range(repeat):
        counter = Counter()
        with variant(name, counter):
            t0 = time.perf_counter()
            result = call()
            best = min(best, time.perf_counter() - t0)
        evals = counter.calls
    return best, result, evals


def max_rel(a: dict, b: dict) -> float:
    return max(abs(a[k] - b[k]) / abs(b[k]) for k in b)


# ----------------------------------------------------------- main
def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=3, help="timings of each fit (best kept)")
    ap.add_argument("--busy", type=int, default=0, metavar="N",
                    help="keep N extra processes spinning meanwhile (cores busy, as when "
                         "tests or fits run in parallel)")
    args = ap.parse_args(argv)
    with busy_cores(args.busy):
        return run(args)


@contextlib.contextmanager
def busy_cores(n: int):
    """``n`` processes spinning on the CPU for the duration (stopped, by id, at the end)."""
    import multiprocessing

    procs = [multiprocessing.Process(target=_spin, daemon=True) for _ in range(n)]
    for p in procs:
        p.start()
    try:
        yield
    finally:
        for p in procs:
            p.terminate()
            p.join()


def _spin() -> None:
    x = 0
    while True:
        x = (x + 1) % 1000003


def run(args) -> int:
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"numpy {np.__version__}, scipy {scipy.__version__}, {os.cpu_count()} cores, "
          f"load average {load:.1f}, OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', '-')}"
          f", {args.busy} busy processes")

    hub = hub_problem()
    t0 = time.perf_counter()
    flex = flex_problem()
    print(f"(FLEXCAM data: {time.perf_counter() - t0:.1f} s of lsim and Welch)\n")
    plants = {"SRV-02": (hub[2], hub[6]), "FLEXCAM": (flex[2], flex[5])}

    print("1. matrix exponential of the hold block matrix: us per call (min/median/p90), "
          "error vs mpmath")
    print(f"   {'plant/hold':<14}{'size':>5}{'hand _expm':>16}{'scipy expm':>18}"
          f"{'hand err':>10}{'scipy err':>10}")
    for pname, (plant, dt) in plants.items():
        A, B = plant.A, plant.B[:, :1]
        n = A.shape[0]
        for hold, size in (("zoh", n + 1), ("foh", n + 2)):
            M = np.zeros((size, size))
            M[:n, :n], M[:n, n:n + 1] = A * dt, B * dt
            if hold == "foh":
                M[n, n + 1] = 1.0
            ref = mp_to_np(mp_expm(M))
            lh = latency(lambda: hand_expm(M))
            ls_ = latency(lambda: scipy.linalg.expm(M))
            print(f"   {pname + ' ' + hold:<14}{size:>5}{fmt(lh):>16}{fmt(ls_):>18}"
                  f"{rel_err(hand_expm(M), ref):>10.0e}{rel_err(scipy.linalg.expm(M), ref):>10.0e}")

    print("\n2. discretisation (Ad, Bd, Dd): us per call (min/median/p90), worst error vs mpmath")
    print(f"   {'plant/hold':<14}{'_discretize':>16}{'cont2discrete':>18}"
          f"{'hand err':>10}{'scipy err':>10}")
    for pname, (plant, dt) in plants.items():
        A, B, C, D = plant.A, plant.B[:, :1], plant.C[:1], plant.D[:1, :1]
        for hold in ("zoh", "foh"):
            ref = mp_discretize(A, B, C, D, dt, hold)
            eh = max(rel_err(x, r) for x, r in zip(hand_discretize(A, B, C, D, dt, hold), ref))
            es = max(rel_err(x, r) for x, r in zip(scipy_discretize(A, B, C, D, dt, hold), ref))
            lh = latency(lambda: hand_discretize(A, B, C, D, dt, hold), 1000)
            ls_ = latency(lambda: scipy_discretize(A, B, C, D, dt, hold), 1000)
            print(f"   {pname + ' ' + hold:<14}{fmt(lh):>16}{fmt(ls_):>18}{eh:>10.0e}{es:>10.0e}")

    nm, values, plant, u, theta, y, dt = hub
    Ad, Bd, Cd, Dd = hand_discretize(plant.A, plant.B, plant.C[:1], plant.D[:1], dt, "zoh")
    print(f"\n   one SRV-02 residual (8000 samples): model {fmt(latency(lambda: nm.plant(values), 200))}"
          f" us, simulation {fmt(latency(lambda: _dlsim(Ad, Bd, Cd, Dd, u[:, None], None), 200))} us")

    print("\n3. whole fits: s (best of repeats), residual evaluations, max relative difference "
          "from old")
    nmh, values, _, u, theta, y, dt = hub
    nmf, fvalues, _, fu, fy, fdt, frf = flex
    nmm, mu, my, mdt = msd_problem()
    ks = ["link.k_1", "link.k_2", "link.k_3"]
    kstart = {k: f * fvalues[k] for k, f in zip(ks, (0.85, 1.2, 0.9))}
    rng = np.random.default_rng(7)
    y_pot = 1.5 * theta + 0.02 * rng.standard_normal(theta.size)
    fits = {
        "SRV-02 time Jm,Beq": lambda: greybox_fit(
            nmh, TimeData(u, y, dt), free=["Jm", "Beq"], values=values,
            initial={"Jm": 2.0 * values["Jm"], "Beq": 0.5 * values["Beq"]},
            input="e_in", output="theta"),
        "SRV-02 time k_pot": lambda: greybox_fit(
            nmh, TimeData(u, y_pot, dt), free=["k_pot"], values=values, output="v_pot"),
        "FLEXCAM freq k1-3": lambda: greybox_fit(
            nmf, FrequencyData.from_frf(frf, fmin=1.0, fmax=150.0), free=ks, values=fvalues,
            initial=kstart, input="hub.e_in", output="y"),
        "FLEXCAM time k1-3": lambda: greybox_fit(
            nmf, TimeData(fu[:4000], fy[:4000], fdt), free=ks, values=fvalues, initial=kstart,
            input="hub.e_in", output="y", method="foh"),
        "msd time m,b,k": lambda: greybox_fit(
            nmm, TimeData(mu, my, mdt), free=["m", "b", "k"],
            initial={"m": 1.5, "b": 0.2, "k": 3.0}, output="x"),
    }
    names = ("old", "shipped", "c2d")
    print(f"   {'problem':<20}" + "".join(f"{n + ' s':>10}" for n in names)
          + "".join(f"{n + ' ev':>11}" for n in names) + f"{'d est':>9}{'d se':>9}")
    results = {}
    for label, call in fits.items():
        runs = {n: run_fit(n, call, args.repeat) for n in names}
        results[label] = {n: r[1] for n, r in runs.items()}
        old, new = runs["old"][1], runs["shipped"][1]
        print(f"   {label:<20}" + "".join(f"{runs[n][0]:>10.2f}" for n in names)
              + "".join(f"{runs[n][2]:>11d}" for n in names)
              + f"{max_rel(new.estimates, old.estimates):>9.0e}"
              + f"{max_rel(new.std_errors, old.std_errors):>9.0e}")

    # the linear-in-parameter case: standard error by the OLS formula
    r = results["SRV-02 time k_pot"]
    k_ols = theta @ y_pot / (theta @ theta)
    s2 = np.sum((y_pot - k_ols * theta) ** 2) / (theta.size - 1)
    se = np.sqrt(s2 / (theta @ theta))
    print(f"\n   k_pot standard error against the OLS formula ({se:.6e}), relative error: "
          + ", ".join(f"{n} {abs(r[n].std_errors['k_pot'] / se - 1):.0e}" for n in names))
    r = results["SRV-02 time Jm,Beq"]["shipped"]
    print("   SRV-02 (shipped): " + ", ".join(
        f"{k} = {r.estimates[k]:.6g} ± {r.std_errors[k]:.2g} (true {values[k]:.6g})"
        for k in ("Jm", "Beq")))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
