"""Benchmark: sparse numeric plants of a chain of N mass-spring-damper cells.

For each N, in a fresh process: causality + derivation (+ ``state_space()``),
``compile_plant``, ``.plant(values)`` (sparse above the threshold) and a
100-point frequency response, each timed, and the process's peak resident
memory (``resource.getrusage(RUSAGE_SELF).ru_maxrss``) after each step.  The
chain is the one of ``bench/bench_chain.py`` (imported from it).

    python bench/bench_sparse.py                  # N = 1000 5000 20000
    python bench/bench_sparse.py 1000 5000        # chosen sizes
    python bench/bench_sparse.py --dense 500      # force dense plants (for comparison)
    python bench/bench_sparse.py --symengine 1000 5000
    python bench/bench_sparse.py --lu 5000        # column orderings of the sparse LU
    python bench/bench_sparse.py --compare 1000 5000 20000   # compile: numpy classes vs lambdify
    python bench/bench_sparse.py 100000           # end to end, peak memory
    python bench/bench_sparse.py --scale          # CPU per step, N = 1000 5000 20000 100000

``--scale`` reports CPU seconds per step (build, causality + derivation +
``state_space()``, ``compile_plant``, ``.plant``, 100-point response), the
derivation's microseconds per bond (flat when it grows linearly), the wall
time of the whole chain and the peak resident memory.

``--compare`` compiles the same model twice in one process, alternating,
median of 3 (fewer at 20,000 cells): as ``compile_plant`` does (monomials
and sums of monomials evaluated by numpy, :mod:`bondgraph.numeric._monomials`)
and with every entry sent to ``sympy.lambdify`` (the classifier patched to
answer "general": the path before), and reports both times, the classes of
the entries and the largest relative difference of the plant values.

``--symengine`` measures ``compile_plant`` end to end with its lambdify step
done by ``sympy.lambdify(..., cse=True)`` (what it uses) and by
``symengine.Lambdify(..., backend="lambda", cse=True)`` (conversion of the
sympy expressions included), alternating, median of 3, and the largest
relative difference of the plant values the two compute.  Needs ``pip
install symengine``.  Measured with symengine 0.15 (2 cores shared with
other jobs): 1,000 cells 2.49 s -> 1.02 s (2.4x), 5,000 cells 15.8 s ->
7.5 s (2.1x; 1.5x in an earlier run under heavier load), identical values
(relative difference 0).  That is below the 3x end to end at 5,000 cells
that adopting it as an optional accelerator called for, so
``compile_plant`` keeps ``sympy.lambdify``.

``--lu`` times the 100 sparse LU factorizations and solves of a frequency
response three ways: COLAMD ordering at every frequency, no ordering
(``permc_spec="NATURAL"`` on the model's state order), and the ordering of
the first factorization reused on the pre-permuted structure (what
``NumericStateSpace.frequency_response`` does, :class:`ShiftedSolver`).

Timings on a shared machine are noisy: take the median of a few runs.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def _rss_mb() -> float:
    # ru_maxrss is in kilobytes on Linux
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _values(nm) -> dict:
    # masses 1, dampers 0.1, springs 100 (stiffness), the same at every cell
    out = {}
    for name in nm.parameter_names:
        out[name] = {"m": 1.0, "b": 0.1, "k": 0.01}.get(name[0], 1.0)
    return out


def one(n: int, sparse) -> dict:
    import numpy as np

    import bondgraph as bg
    from bench_chain import build

    r: dict = {"N": n}
    c0 = time.process_time()
    t0 = time.perf_counter()
    g = build(n)
    r["build_cpu"] = time.process_time() - c0
    aug = bg.assign_causality(g)
    model = bg.derive(aug, outputs={"v_last": bg.flow(f"m{n - 1}")})
    model.state_space()
    t1 = time.perf_counter()
    c1 = time.process_time()
    r["derive"], r["rss_derive"] = t1 - t0, _rss_mb()
    r["derive_cpu"], r["bonds"] = c1 - c0 - r["build_cpu"], len(aug.flat.bonds)
    nm = bg.compile_plant(model, sparse=sparse)
    t2 = time.perf_counter()
    c2 = time.process_time()
    r["compile_cpu"] = c2 - c1
    r["compile"], r["rss_compile"] = t2 - t1, _rss_mb()
    ss = nm.plant(_values(nm))
    t3 = time.perf_counter()
    c3 = time.process_time()
    r["plant"], r["rss_plant"], r["plant_cpu"] = t3 - t2, _rss_mb(), c3 - c2
    H = ss.frequency_response(np.logspace(-3, 1, 100))
    t4 = time.perf_counter()
    r["response"], r["rss_response"] = t4 - t3, _rss_mb()
    r["cpu_total"] = time.process_time() - c0
    r["response_cpu"] = r["cpu_total"] - (c3 - c0)
    r["states"], r["sparse"] = ss.nstates, ss.is_sparse
    r["nnz_A"] = int(ss.A.nnz) if ss.is_sparse else int(np.count_nonzero(ss.A))
    assert H.shape == (100, 1, 1) and np.isfinite(H).all()
    return r


def symengine_one(n: int, repeats: int = 3) -> dict:
    import statistics

    import numpy as np
    import symengine

    import bondgraph as bg
    from bench_chain import build
    from bondgraph.numeric import _compile

    model = bg.derive(bg.assign_causality(build(n)), outputs={"v_last": bg.flow(f"m{n - 1}")})
    model.state_space()
    sympy_lambdify = _compile.lambdify_cse

    def symengine_lambdify(args, exprs):
        fn = symengine.Lambdify([symengine.sympify(a) for a in args],
                                [symengine.sympify(e) for e in exprs], backend="lambda", cse=True)
        return lambda *values: fn(np.array(values, dtype=float)).ravel()

    times: dict = {"sympy": [], "symengine": []}
    plants = {}
    for _ in range(repeats):                  # alternate, so that both see the same load
        for label, lambdify in (("sympy", sympy_lambdify), ("symengine", symengine_lambdify)):
            _compile.lambdify_cse = lambdify
            try:
                t0 = time.perf_counter()
                nm = bg.compile_plant(model)
                times[label].append(time.perf_counter() - t0)
            finally:
                _compile.lambdify_cse = sympy_lambdify
            plants[label] = nm.plant(_values(nm)).A.data
    a, b = plants["sympy"], plants["symengine"]
    rel = float(np.max(np.abs(a - b) / np.maximum(np.abs(a), 1e-300)))
    sy, se = statistics.median(times["sympy"]), statistics.median(times["symengine"])
    return {"N": n, "exprs": len(nm._fn.general._exprs), "compile_plant": sy,
            "compile_plant_with_symengine": se, "max_rel_diff": rel}


def lu_one(n: int) -> dict:
    import numpy as np
    import scipy.sparse
    import scipy.sparse.linalg

    import bondgraph as bg
    from bench_chain import build
    from bondgraph.numeric.sparse import Pattern, ShiftedSolver

    model = bg.derive(bg.assign_causality(build(n)), outputs={"v_last": bg.flow(f"m{n - 1}")})
    nm = bg.compile_plant(model, sparse=True)
    ss = nm.plant(_values(nm))
    A, b = ss.A, ss.B.toarray().astype(complex)
    w = np.logspace(-3, 1, 100)
    eye = scipy.sparse.eye_array(A.shape[0], format="csc")
    r = {"N": n, "states": A.shape[0]}
    for spec in ("COLAMD", "NATURAL"):
        t0 = time.perf_counter()
        for wk in w:
            scipy.sparse.linalg.splu((1j * wk * eye - A).tocsc(), permc_spec=spec).solve(b)
        r[spec] = time.perf_counter() - t0
    t0 = time.perf_counter()
    solver = ShiftedSolver(Pattern(A.shape, A.indptr, A.indices))
    for wk in w:
        solver.solve(A.data, 1j * wk, b)
    r["reused"] = time.perf_counter() - t0
    return r


def compare_one(n: int) -> dict:
    import statistics

    import numpy as np

    import bondgraph as bg
    from bench_chain import build
    from bondgraph.numeric import _monomials

    model = bg.derive(bg.assign_causality(build(n)), outputs={"v_last": bg.flow(f"m{n - 1}")})
    model.state_space()
    classify = _monomials.classify
    times: dict = {"numpy": [], "lambdify": []}
    values = {}
    repeats = 3 if n <= 5000 else 1
    for _ in range(repeats):
        for label in ("numpy", "lambdify"):
            if label == "lambdify":
                _monomials.classify = lambda ex, index: ("general", None)
            try:
                t0 = time.perf_counter()
                nm = bg.compile_plant(model, sparse=True)
                times[label].append(time.perf_counter() - t0)
            finally:
                _monomials.classify = classify
            t0 = time.perf_counter()
            values[label] = nm.plant(_values(nm)).A.data
            times.setdefault(label + "_plant", []).append(time.perf_counter() - t0)
            if label == "numpy":
                counts = dict(nm._fn.counts)
    a, b = values["numpy"], values["lambdify"]
    rel = float(np.max(np.abs(a - b) / np.maximum(np.abs(a), 1e-300)))
    med = {k: statistics.median(v) for k, v in times.items()}
    return {"N": n, "counts": counts, **med, "max_rel_diff": rel, "repeats": repeats}


def _run(args: list[str]) -> dict:
    out = subprocess.run([sys.executable, __file__, *args], check=True, capture_output=True,
                         text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def scale(sizes: list[int]) -> None:
    """CPU seconds of each step, end to end, each size in a fresh process; "us/bond" is
    causality + derivation + ``state_space()`` per bond (flat when linear)."""
    load = os.getloadavg()
    print(f"load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f} at the start")
    print(f"{'N':>7} {'bonds':>7} {'build':>7} {'derive':>8} {'us/bond':>8} {'compile':>8} "
          f"{'plant':>7} {'FRF100':>7} {'total CPU s':>11} {'wall s':>8} {'peak MB':>8}")
    for n in sizes:
        r = _run(["--one", str(n), "auto"])
        wall = r["derive"] + r["compile"] + r["plant"] + r["response"]
        print(f"{n:>7} {r['bonds']:>7} {r['build_cpu']:>7.2f} {r['derive_cpu']:>8.2f} "
              f"{1e6 * r['derive_cpu'] / r['bonds']:>8.1f} {r['compile_cpu']:>8.2f} "
              f"{r['plant_cpu']:>7.2f} {r['response_cpu']:>7.2f} {r['cpu_total']:>11.2f} "
              f"{wall:>8.2f} {r['rss_response']:>8.0f}")
    load = os.getloadavg()
    print(f"load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f} at the end")


def main(argv: list[str]) -> None:
    if argv and argv[0] == "--one":
        sparse = {"auto": None, "dense": False, "sparse": True}[argv[2]]
        print(json.dumps(one(int(argv[1]), sparse)))
        return
    if argv and argv[0] == "--symengine-one":
        print(json.dumps(symengine_one(int(argv[1]))))
        return
    if argv and argv[0] == "--compare-one":
        print(json.dumps(compare_one(int(argv[1]))))
        return
    if argv and argv[0] == "--compare":
        print(f"{'N':>6} {'monomial':>8} {'sum':>5} {'general':>7} {'numpy s':>8} "
              f"{'lambdify s':>10} {'speed-up':>8} {'plant s':>8} {'(lambdify)':>10} "
              f"{'max rel diff':>12}")
        for n in [int(a) for a in argv[1:]] or [1000, 5000]:
            r = _run(["--compare-one", str(n)])
            c = r["counts"]
            print(f"{n:>6} {c['monomial']:>8} {c['sum']:>5} {c['general']:>7} "
                  f"{r['numpy']:>8.3f} {r['lambdify']:>10.3f} "
                  f"{r['lambdify'] / r['numpy']:>7.1f}x {r['numpy_plant']:>8.3f} "
                  f"{r['lambdify_plant']:>10.3f} {r['max_rel_diff']:>12.1e}")
        return
    if argv and argv[0] == "--lu-one":
        print(json.dumps(lu_one(int(argv[1]))))
        return
    if argv and argv[0] == "--lu":
        print(f"{'N':>6} {'states':>6} {'COLAMD each s':>14} {'NATURAL s':>10} {'reused s':>9}")
        for n in [int(a) for a in argv[1:]] or [5000]:
            r = _run(["--lu-one", str(n)])
            print(f"{n:>6} {r['states']:>6} {r['COLAMD']:>14.3f} {r['NATURAL']:>10.3f} "
                  f"{r['reused']:>9.3f}")
        return
    if argv and argv[0] == "--symengine":
        sizes = [int(a) for a in argv[1:]] or [1000, 5000]
        print(f"{'N':>6} {'exprs':>6} {'sympy.lambdify s':>17} {'symengine s':>12} {'speed-up':>9} "
              f"{'max rel diff':>13}   (compile_plant end to end, median of 3)")
        for n in sizes:
            r = _run(["--symengine-one", str(n)])
            print(f"{n:>6} {r['exprs']:>6} {r['compile_plant']:>17.3f} "
                  f"{r['compile_plant_with_symengine']:>12.3f} "
                  f"{r['compile_plant'] / r['compile_plant_with_symengine']:>8.2f}x "
                  f"{r['max_rel_diff']:>13.1e}")
        return
    if argv and argv[0] == "--scale":
        scale([int(a) for a in argv[1:]] or [1000, 5000, 20000, 100000])
        return
    mode = "auto"
    if argv and argv[0] in ("--dense", "--sparse"):
        mode, argv = argv[0][2:], argv[1:]
    sizes = [int(a) for a in argv] or [1000, 5000, 20000]
    print(f"{'N':>6} {'states':>6} {'sparse':>6} {'nnz A':>7} {'derive s':>9} {'compile s':>9} "
          f"{'plant s':>8} {'FRF100 s':>9} {'peak MB':>8} {'total s':>8} {'compile CPU s':>13} "
          f"{'total CPU s':>11} (peak MB after derive / compile / plant)")
    for n in sizes:
        r = _run(["--one", str(n), mode])
        print(f"{n:>6} {r['states']:>6} {str(r['sparse']):>6} {r['nnz_A']:>7} "
              f"{r['derive']:>9.3f} {r['compile']:>9.3f} {r['plant']:>8.3f} "
              f"{r['response']:>9.3f} {r['rss_response']:>8.0f} "
              f"{r['derive'] + r['compile'] + r['plant'] + r['response']:>8.2f} "
              f"{r['compile_cpu']:>13.3f} {r['cpu_total']:>11.2f} "
              f"({r['rss_derive']:.0f} / {r['rss_compile']:.0f} / {r['rss_plant']:.0f})")


if __name__ == "__main__":
    main(sys.argv[1:])
