"""Benchmark: building FMUs and simulating them (fmpy) against bg.simulate, 10 s of model time.

Models: FLEXCAM (``models/flexcam.py``, paper form, 6 states) and the
100-cell mass-spring-damper chain of ``bench/bench_chain.py`` (199 states;
every mass 1 kg, spring 100 N/m, damper 0.5 N s/m), each driven by a unit
step of its input from rest.  For each FMI version the table gives the time
to build the FMU (derive excluded: it is shared; C generation, the model
description, compilation with ``cc`` and the archive), the wall time of
fmpy's Model Exchange simulation (CVode, relative tolerance 1e-6) and of its
Co-Simulation (the FMU's fixed-step RK4 at its default ``rk4_step``), and
the wall time of ``bg.simulate`` (scipy RK45 and LSODA, rtol 1e-6, atol
1e-9).  Every run reports 1001 samples (0.01 s apart; the communication
step of Co-Simulation); the median of ``--repeat`` runs is shown (default 3).
The error columns compare the first output of each run with a tight
reference (``bg.simulate``, DOP853, rtol 1e-10, atol 1e-12), relative to
its largest magnitude.

    python bench/bench_fmu.py
    python bench/bench_fmu.py --repeat 1
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

T_END, DT = 10.0, 0.01


def chain(n: int = 100):
    import bondgraph as bg
    from bench_chain import build

    g = build(n)
    model = bg.derive(g, outputs={"v_first": bg.flow("m0"), "v_mid": bg.flow(f"m{n // 2}")})
    values = {}
    for p in model.parameters:
        values[p.name] = {"m": 1.0, "k": 100.0, "b": 0.5}[p.name[0]]
    return model, values


def flexcam():
    import bondgraph as bg

    defn = bg.load_model(HERE.parent / "models" / "flexcam.py")
    model = defn.derive()
    return model, {p.name: defn.parameters[p.name] for p in model.parameters}


def timed(repeat: int, call):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = call()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main(argv: list[str]) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)

    import bondgraph as bg
    from bondgraph.fmu import default_step, export_fmu
    from fmpy import read_model_description, simulate_fmu

    print(f"10 s of model time, {int(T_END / DT) + 1} samples, median of {args.repeat} run(s); seconds\n")
    head = (f"{'model':<9} {'states':>6} {'FMI':>3} {'build':>7} {'FMU ME':>8} {'FMU CS':>8} {'rk4_step':>9} "
            f"{'bg RK45':>8} {'bg LSODA':>8} {'err ME':>8} {'err CS':>8} {'err RK45':>8}")
    print(head)
    print("-" * len(head))
    with tempfile.TemporaryDirectory() as tmp:
        for name, make in (("flexcam", flexcam), ("chain100", chain)):
            model, values = make()
            u_name = model.input_names[0]
            times = np.linspace(0.0, T_END, int(round(T_END / DT)) + 1)
            t_rk, ref = timed(args.repeat, lambda: bg.simulate(model, values, (0.0, T_END), u=[1.0],
                                                               t_eval=times, rtol=1e-6, atol=1e-9))
            t_ls, _ = timed(args.repeat, lambda: bg.simulate(model, values, (0.0, T_END), u=[1.0], t_eval=times,
                                                             method="LSODA", rtol=1e-6, atol=1e-9))
            tight = bg.simulate(model, values, (0.0, T_END), u=[1.0], t_eval=times, method="DOP853",
                                rtol=1e-10, atol=1e-12)
            out = model.output_names[0]
            scale = float(np.max(np.abs(tight[out])))

            def error(t, y):
                return float(np.max(np.abs(np.interp(times, t, y) - tight[out]))) / scale
            h = default_step(model, [values[p.name] for p in model.parameters])
            for fmi in (2, 3):
                path = os.path.join(tmp, f"{name}_{fmi}.fmu")
                t_build, _ = timed(args.repeat, lambda: export_fmu(model, path, fmi=fmi, values=values))
                md = read_model_description(path)

                def sim(kind):
                    return simulate_fmu(path, model_description=md, fmi_type=kind, stop_time=T_END,
                                        output_interval=DT, start_values={u_name: 1.0},
                                        relative_tolerance=1e-6)
                t_me, me = timed(args.repeat, lambda: sim("ModelExchange"))
                t_cs, cs = timed(args.repeat, lambda: sim("CoSimulation"))
                print(f"{name:<9} {len(model.states):>6} {fmi:>3} {t_build:>7.2f} {t_me:>8.2f} {t_cs:>8.2f} "
                      f"{h:>9.0e} {t_rk:>8.2f} {t_ls:>8.2f} {error(me['time'], me[out]):>8.1e} "
                      f"{error(cs['time'], cs[out]):>8.1e} {error(ref.t, ref[out]):>8.1e}")


if __name__ == "__main__":
    main(sys.argv[1:])
