"""Benchmark: generated code and FMUs of an implicit model (issue 29).

The diode circuit of ``tests/codegen/test_implicit_codegen.py`` (a 5 V source,
a 1 kOhm resistor and a diode ``i = Is (exp(v/Vt) - 1)`` in series charging a
1 uF capacitor; the loop current is the algebraic unknown):

* C, timed inside a compiled driver (``cc -O2``): ``NAME_derivatives`` along a
  slowly varying state (the warm start from the previous call) and at
  random states with ``z`` reset to 0 each time (cold starts, forward and
  reverse bias); then 5,000 ``NAME_step_rk4`` steps over 5 ms and the error
  of the final state against ``bg.simulate`` (DOP853, rtol 1e-12);
* the same evaluations through ``bondgraph.numeric.compile_dynamics`` and
  through the generated Python module;
* the FMU (FMI 2, Model Exchange, fmpy's CVode at rtol 1e-8) against
  ``bg.simulate`` (RK45, rtol 1e-8), wall time of each run.

    python bench/bench_implicit_codegen.py
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

DRIVER = r"""
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "diode_rc.h"

int main(void)
{
    double p[4] = {1e-6, 1e-12, 1e3, 0.025};      /* C, Is, R, Vt */
    double x[1], u[1] = {5.0}, z[1] = {0.0}, xdot[1], sum = 0.0;
    long k, n = 1000000, bad = 0;
    clock_t t0;
    t0 = clock();
    for (k = 0; k < n; ++k) {                      /* warm: q moves by 5e-12 per call */
        x[0] = 5e-6 * (double)k / (double)n;
        bad += diode_rc_derivatives(0.0, x, u, p, z, xdot) != 0;
        sum += xdot[0];
    }
    printf("warm %.3f %ld %.17g\n", (double)(clock() - t0) / CLOCKS_PER_SEC / n * 1e9, bad, sum);
    srand(1);
    t0 = clock();
    for (k = 0; k < n / 10; ++k) {                 /* cold: V - q/C uniform in [-1, 4] V */
        x[0] = 1e-6 * (5.0 - (-1.0 + 5.0 * rand() / (double)RAND_MAX));
        z[0] = 0.0;
        bad += diode_rc_derivatives(0.0, x, u, p, z, xdot) != 0;
        sum += xdot[0];
    }
    printf("cold %.3f %ld %.17g\n", (double)(clock() - t0) / CLOCKS_PER_SEC / (n / 10) * 1e9, bad, sum);
    x[0] = 0.0; z[0] = 0.0;
    t0 = clock();
    for (k = 0; k < 5000; ++k) bad += diode_rc_step_rk4(k * 1e-6, 1e-6, x, u, p, z) != 0;
    printf("rk4 %.3f %ld %.17g\n", (double)(clock() - t0) / CLOCKS_PER_SEC * 1e3, bad, x[0]);
    return 0;
}
"""


def main() -> None:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "codegen"))
    import bondgraph as bg
    from bondgraph.codegen import generate_python, write_c
    from test_implicit_codegen import diode_rc

    model = diode_rc()
    values = {"C": 1e-6, "Is": 1e-12, "R": 1e3, "Vt": 0.025}
    ref = bg.simulate(model, values, (0.0, 5e-3), {"q_C": 0.0}, u=[5.0], method="DOP853",
                      rtol=1e-12, atol=1e-18, t_eval=[5e-3])
    q_ref = float(ref["q_C"][-1])
    cc = shutil.which("cc") or shutil.which("gcc")
    with tempfile.TemporaryDirectory() as d:
        src, _ = write_c(model, Path(d, "diode_rc.c"))
        Path(d, "driver.c").write_text(DRIVER)
        exe = Path(d, "bench")
        subprocess.run([cc, "-O2", "-std=c99", "-I", d, "-o", str(exe), str(src), str(Path(d, "driver.c")),
                        "-lm"], check=True)
        lines = subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout.split("\n")
    rows = {ln.split()[0]: ln.split()[1:] for ln in lines if ln}
    print(f"C derivatives, warm start      : {float(rows['warm'][0]):8.1f} ns/call  "
          f"(failures {rows['warm'][1]})")
    print(f"C derivatives, cold start z = 0: {float(rows['cold'][0]):8.1f} ns/call  "
          f"(failures {rows['cold'][1]})")
    q_c = float(rows["rk4"][2])
    print(f"C RK4, 5000 steps of 1 us      : {float(rows['rk4'][0]):8.3f} ms; q_C(5 ms) relative error "
          f"{abs(q_c - q_ref) / abs(q_ref):.2e} against simulate (DOP853)")

    dyn = bg.numeric.compile_dynamics(model)
    p = dyn.parameter_vector(values)
    ns: dict = {}
    exec(generate_python(model), ns)
    qs = np.linspace(0.0, 5e-6, 2000)
    for label, fn in (("compile_dynamics", lambda q: dyn.derivatives(0.0, [q], [5.0], p)),
                      ("generated Python", lambda q: ns["derivatives"](0.0, [q], [5.0], list(p)))):
        t0 = time.perf_counter()
        for q in qs:
            fn(q)
        print(f"{label:17s} warm start    : {(time.perf_counter() - t0) / qs.size * 1e6:8.1f} us/call")

    try:
        from fmpy import simulate_fmu

        from bondgraph.fmu import export_fmu
    except ImportError:     # pragma: no cover
        print("fmpy not installed: no FMU timing")
        return
    with tempfile.TemporaryDirectory() as d:
        t0 = time.perf_counter()
        path = export_fmu(model, Path(d, "diode_rc.fmu"), fmi=2, values=values)
        t_build = time.perf_counter() - t0
        t0 = time.perf_counter()
        res = simulate_fmu(str(path), fmi_type="ModelExchange", stop_time=5e-3, output_interval=5e-5,
                           start_values={"V": 5.0}, relative_tolerance=1e-8)
        t_fmu = time.perf_counter() - t0
    t0 = time.perf_counter()
    sim = bg.simulate(model, values, (0.0, 5e-3), {"q_C": 0.0}, u=[5.0], rtol=1e-8, atol=1e-16,
                      t_eval=res["time"])
    t_sim = time.perf_counter() - t0
    err = np.max(np.abs(res["i"] - sim["i"])) / np.max(np.abs(sim["i"]))
    print(f"FMU build (FMI 2, compiled)    : {t_build:8.2f} s")
    print(f"FMU Model Exchange, 5 ms       : {t_fmu:8.3f} s   bg.simulate: {t_sim:.3f} s   "
          f"max relative difference of i: {err:.1e}")


if __name__ == "__main__":
    main()
