"""Benchmark: fully symbolic transfer functions from state-space matrices.

Models (built as sympy matrices here, independent of the engine core):

- ``dc_motor``: armature current and speed, omega/V (2 states, 5 symbols);
- ``hub_beam``: DC-motor hub (inductance neglected) with 3 modal beam modes,
  tip deflection / voltage (8 states: theta, omega, 3 x (eta_i, eta_i'));
- ``hub_beam_E``: the same hub and 3 modes coupled through a full mass
  matrix, in descriptor form ``E x' = A x + B u`` (8 states, E not diagonal);
- ``chain7``: 7 masses with springs and dampers to the previous mass (the
  first to ground), force on mass 1, position of mass 7 (14 states, 21 symbols);
  ``chain5`` .. ``chain10``: the same with 5 .. 10 masses (10 .. 20 states);
- ``bgchain10``: the bond-graph chain of ``bench/bench_chain.py`` with 10 cells
  (dampers to ground, springs between masses), force to last-mass velocity
  (19 states, 29 symbols), from ``Model.state_space()``.

Each configuration runs in a fresh process (``subprocess``); the time is the
``transfer_function`` call only (imports excluded, reported separately), the
memory the process's peak resident set (``resource.getrusage``, imports
included), the size of the answer the number of terms of the numerator and
denominator coefficients (a fraction's numerator and denominator both count).

    python bench/bench_tf.py             # fast path (method auto) + references
    python bench/bench_tf.py --chains    # only the chain sizes (10 .. 20 states)
    python bench/bench_tf.py --slow      # also Berkowitz on the 14-state chain
    python bench/bench_tf.py --json      # machine-readable rows
    python bench/bench_tf.py --modes 3 9    # hub_beam with 3 .. 9 modes
    python bench/bench_tf.py --flexcam 3 14 # FLEXCAM's tip deflection, 3 .. 14 modes

``--modes`` runs the fully symbolic hub + modal beam (``hub_beam(n)``: 2 + 2n
states, 5 + 5n symbols, an answer 3.2x larger per mode) from the first to the
last number of modes, each in a fresh process, with the default term budget
(``max_terms``), in the columns of ``--flexcam``.

``--flexcam FIRST LAST`` runs issue 28's FLEXCAM series: the tip deflection
``y / hub.e_in`` of ``models/flexcam.py`` (paper formulation; ``--system`` for
the system formulation), derived by the engine and fully symbolic (2n states,
7 + 4n symbols at n modes), each number of modes in a fresh process.  The
``transfer_function`` call returns without sympy objects; the rows give its CPU
and wall seconds and the process's peak memory before and after it, then the
CPU seconds and peak memory once the sympy Polys are built (first access of
``num``/``den``), the answer's terms and the CPU microseconds per answer term.
``--chains`` and the default table report the same columns (``seconds`` is the
call's wall time; ``peak MB`` includes the sympy Polys).

    python bench/bench_tf.py --flexcam 3 14
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def dc_motor():
    import sympy as sp

    La, Ra, J, b, K = sp.symbols("L_a R_a J b K", positive=True)
    A = sp.Matrix([[-Ra / La, -K / La], [K / J, -b / J]])
    B = sp.Matrix([1 / La, 0])
    C = sp.Matrix([[0, 1]])
    return A, B, C, sp.zeros(1, 1)


def hub_beam(modes: int = 3):
    """Hub angle/rate plus ``modes`` x (eta_i, eta_i'), as in the seed paper."""
    import sympy as sp

    J, b, K, R, Lb = sp.symbols("J b K R L_b", positive=True)
    m = sp.symbols(f"m1:{modes + 1}", positive=True)
    k = sp.symbols(f"k1:{modes + 1}", positive=True)
    c = sp.symbols(f"c1:{modes + 1}", positive=True)
    g = sp.symbols(f"g1:{modes + 1}", positive=True)   # phi_i'(0): torque -> mode
    h = sp.symbols(f"h1:{modes + 1}", positive=True)   # phi_i(L): mode -> tip
    n = 2 + 2 * modes
    A = sp.zeros(n, n)
    B = sp.zeros(n, 1)
    C = sp.zeros(1, n)
    # tau = K/R (V - K omega)
    A[0, 1] = 1
    A[1, 1] = -(b + K**2 / R) / J
    B[1, 0] = K / (R * J)
    C[0, 0] = Lb
    for i in range(modes):
        e, v = 2 + 2 * i, 3 + 2 * i
        A[e, v] = 1
        A[v, e] = -k[i] / m[i]
        A[v, v] = -c[i] / m[i]
        A[v, 1] = -g[i] * K**2 / (R * m[i])
        B[v, 0] = g[i] * K / (R * m[i])
        C[0, e] = h[i]
    return A, B, C, sp.zeros(1, 1)


def hub_beam_descriptor(modes: int = 3):
    """Hub and modes coupled through a full mass matrix, descriptor form.

    ``M q'' + Cd q' + K q = e_1 tau``, ``q = (theta, eta_1..)``, with
    ``M = [[J_t, d^T], [d, diag(m)]]``; states ``(q, q')``, ``E = diag(I, M)``.
    """
    import sympy as sp

    Jt, b, K, R, Lb = sp.symbols("J_t b K R L_b", positive=True)
    m = sp.symbols(f"m1:{modes + 1}", positive=True)
    k = sp.symbols(f"k1:{modes + 1}", positive=True)
    c = sp.symbols(f"c1:{modes + 1}", positive=True)
    d = sp.symbols(f"d1:{modes + 1}", positive=True)
    h = sp.symbols(f"h1:{modes + 1}", positive=True)
    nq = 1 + modes
    M = sp.zeros(nq, nq)
    M[0, 0] = Jt
    for i in range(modes):
        M[0, 1 + i] = M[1 + i, 0] = d[i]
        M[1 + i, 1 + i] = m[i]
    Cd = sp.diag(b + K**2 / R, *c)
    Kq = sp.diag(0, *k)
    E = sp.diag(sp.eye(nq), M)
    A = sp.zeros(2 * nq, 2 * nq)
    A[:nq, nq:] = sp.eye(nq)
    A[nq:, :nq] = -Kq
    A[nq:, nq:] = -Cd
    B = sp.zeros(2 * nq, 1)
    B[nq, 0] = K / R
    C = sp.zeros(1, 2 * nq)
    C[0, 0] = Lb
    for i in range(modes):
        C[0, 1 + i] = h[i]
    return A, B, C, sp.zeros(1, 1), E


def chain(nmass: int = 7):
    import sympy as sp

    m = sp.symbols(f"m1:{nmass + 1}", positive=True)
    k = sp.symbols(f"k1:{nmass + 1}", positive=True)
    b = sp.symbols(f"b1:{nmass + 1}", positive=True)
    n = 2 * nmass
    A = sp.zeros(n, n)
    for i in range(nmass):
        A[2 * i, 2 * i + 1] = 1
    for link in range(nmass):            # link i joins mass i-1 (ground for i=0) and i
        lo, hi = link - 1, link
        for mass, sign in ((hi, 1), (lo, -1)):
            if mass < 0:
                continue
            r = 2 * mass + 1
            A[r, 2 * hi] -= sign * k[link] / m[mass]
            A[r, 2 * hi + 1] -= sign * b[link] / m[mass]
            if lo >= 0:
                A[r, 2 * lo] += sign * k[link] / m[mass]
                A[r, 2 * lo + 1] += sign * b[link] / m[mass]
    B = sp.zeros(n, 1)
    B[1, 0] = 1 / m[0]
    C = sp.zeros(1, n)
    C[0, n - 2] = 1
    return A, B, C, sp.zeros(1, 1)


def bond_graph_chain(cells: int = 10):
    """Force to last-mass velocity of ``bench/bench_chain.py``'s chain."""
    import bondgraph as bg

    sys.path.insert(0, str(ROOT / "bench"))
    from bench_chain import build

    model = bg.derive(build(cells), outputs={"v": bg.flow(f"m{cells - 1}")})
    ss = model.state_space()
    return ss.A, ss.B, ss.C, ss.D


def flexcam(modes: int = 3, formulation: str = "paper"):
    """FLEXCAM's tip deflection ``y / hub.e_in`` (``models/flexcam.py``, fully symbolic)."""
    import bondgraph as bg

    sys.path.insert(0, str(ROOT / "models"))
    import flexcam as fc

    g, outputs, _ = fc.build(modes, formulation=formulation)
    model = bg.derive(g, outputs=outputs)
    ss = model.state_space()
    i, j = ss.output_names.index("y"), ss.input_names.index("hub.e_in")
    return ss.A, ss.B[:, j], ss.C[i, :], ss.D[i:i + 1, j:j + 1]


CHAINS = ("chain5", "chain7", "chain8", "chain9", "chain10", "bgchain10")
MODELS = {"dc_motor": dc_motor, "hub_beam": hub_beam, "hub_beam_E": hub_beam_descriptor,
          "chain7": chain, "bgchain10": bond_graph_chain,
          **{f"chain{n}": (lambda n=n: chain(n)) for n in (5, 8, 9, 10)}}


def _model(name: str):
    for prefix, form in (("flexcam_sys", "system"), ("flexcam", "paper")):
        if name.startswith(prefix) and name[len(prefix):].isdigit():
            return flexcam(int(name[len(prefix):]), form)
    if name.startswith("hub_beam") and name[len("hub_beam"):].isdigit():
        return hub_beam(int(name[len("hub_beam"):]))
    return MODELS[name]()


def answer_terms(P) -> int:
    """Terms of a Poly's coefficients (polynomials, fractions or numbers)."""
    total = 0
    for c in P.rep.to_list():
        if hasattr(c, "numer") and hasattr(c, "denom"):
            total += len(c.numer) + (len(c.denom) if c.denom != 1 else 0)
        elif isinstance(c, dict):
            total += len(c)
        else:
            total += bool(c)
    return total


def run_one(model: str, method: str, normalize: str) -> dict:
    t0 = time.perf_counter()
    import sympy  # noqa: F401  (part of the import time)
    from sympy.external.gmpy import GROUND_TYPES

    sys.path.insert(0, str(ROOT))
    from bondgraph.tf import transfer_function
    from bondgraph.tf._algebra import backend_name

    t_import = time.perf_counter() - t0
    A, B, C, D, *rest = _model(model)
    E = rest[0] if rest else None
    syms = set()
    for M in (A, B, C, D) + tuple(rest):
        syms |= M.free_symbols
    import resource

    from bondgraph.tf.errors import TermBudgetError

    def peak_mb() -> float:
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

    base_mb = peak_mb()
    t1, c1 = time.perf_counter(), time.process_time()
    try:
        G = transfer_function(A, B, C, D, E=E, method=method, normalize=normalize)
    except TermBudgetError as exc:
        return {"model": model, "states": A.shape[0], "symbols": len(syms), "method": method,
                "seconds": time.perf_counter() - t1, "cpu": time.process_time() - c1,
                "note": "refused: " + str(exc)[:160], "peak_mb": peak_mb()}
    seconds, cpu = time.perf_counter() - t1, time.process_time() - c1
    tf_mb = peak_mb()
    # the sympy Polys, built on first access (what printing or coefficients ask for)
    t2, c2 = time.perf_counter(), time.process_time()
    num, den = G.num, G.den
    sympy_seconds, sympy_cpu = time.perf_counter() - t2, time.process_time() - c2
    return {"model": model, "states": A.shape[0], "symbols": len(syms), "method": method,
            "backend": "sympy-DomainMatrix" if method == "berkowitz" else backend_name(),
            "ground_types": GROUND_TYPES, "normalize": normalize, "seconds": seconds,
            "cpu": cpu, "sympy_seconds": sympy_seconds, "sympy_cpu": sympy_cpu,
            "import_seconds": t_import, "order": G.order, "base_mb": base_mb, "tf_mb": tf_mb,
            "peak_mb": peak_mb(), "num_terms": answer_terms(num), "den_terms": answer_terms(den)}


def spawn(model: str, method: str, env_extra: dict, normalize: str = "monic",
          timeout: float = 900) -> dict:
    env = dict(os.environ, **env_extra)
    cmd = [sys.executable, __file__, "--one", model, "--method", method,
           "--normalize", normalize]
    try:
        out = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout,
                             check=True)
    except subprocess.TimeoutExpired:
        return {"model": model, "method": method, "seconds": float("inf"),
                "note": f"timeout {timeout}s", **env_extra}
    except subprocess.CalledProcessError as exc:  # pragma: no cover
        return {"model": model, "method": method, "seconds": float("nan"),
                "note": exc.stderr.strip().splitlines()[-1], **env_extra}
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--one", help=argparse.SUPPRESS)
    ap.add_argument("--method", default="auto", help=argparse.SUPPRESS)
    ap.add_argument("--normalize", default="monic", help=argparse.SUPPRESS)
    ap.add_argument("--slow", action="store_true",
                    help="also Berkowitz (DomainMatrix.charpoly) on the 14-state chain")
    ap.add_argument("--json", action="store_true", help="print JSON rows")
    ap.add_argument("--chains", action="store_true",
                    help="only the chains of 10 .. 20 states (both normalizations)")
    ap.add_argument("--modes", nargs=2, type=int, metavar=("FIRST", "LAST"),
                    help="hub_beam (5 symbols a mode) with FIRST .. LAST modes")
    ap.add_argument("--flexcam", nargs=2, type=int, metavar=("FIRST", "LAST"),
                    help="FLEXCAM's tip deflection (models/flexcam.py, paper form, fully "
                         "symbolic) with FIRST .. LAST modes")
    ap.add_argument("--system", action="store_true",
                    help="with --flexcam: the system formulation instead of the paper's")
    args = ap.parse_args(argv)
    if args.flexcam:
        return _series("flexcam_sys" if args.system else "flexcam", *args.flexcam)
    if args.modes:
        return _series("hub_beam", *args.modes)
    if args.one:
        print(json.dumps(run_one(args.one, args.method, args.normalize)))
        return 0
    configs = []
    chains = [(m, "auto", {"SYMPY_GROUND_TYPES": "flint"}, norm) for m in CHAINS
              for norm in ("monic", "as-derived")]
    if args.chains:
        return _print(chains, args.json)
    for model in ("dc_motor", "hub_beam", "hub_beam_E", "chain7"):
        configs.append((model, "auto", {"SYMPY_GROUND_TYPES": "flint"}))
        configs.append((model, "auto", {"SYMPY_GROUND_TYPES": "python"}))
    for model in ("dc_motor", "hub_beam") + (("chain7",) if args.slow else ()):
        configs.append((model, "berkowitz", {"SYMPY_GROUND_TYPES": "flint"}))
        configs.append((model, "berkowitz", {"SYMPY_GROUND_TYPES": "python"}))
    for model in ("dc_motor", "hub_beam", "chain7"):
        configs.append((model, "auto", {"BONDGRAPH_TF_BACKEND": "sympy",
                                        "SYMPY_GROUND_TYPES": "flint"}))
    return _print([c + ("monic",) for c in configs] + chains, args.json)


def _series(prefix: str, first: int, last: int) -> int:
    """One row per number of modes, each in a fresh process: the ``transfer_function``
    call (CPU and wall seconds, peak resident MB of the process), then the sympy Polys
    built on first access (CPU seconds, peak MB), the answer's terms and the CPU time
    per answer term of the call and of call plus sympy."""
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}; "
          f"'base' is the process before the call (imports, model, derivation)")
    print(f"{'modes':>5} {'states':>6} {'symbols':>7} {'tf cpu s':>8} {'tf wall':>7} "
          f"{'base MB':>7} {'tf MB':>6} {'sympy s':>7} {'peak MB':>7} {'num terms':>9} "
          f"{'den terms':>9} {'us/term':>7} {'+sympy':>7}")
    for n in range(first, last + 1):
        r = spawn(f"{prefix}{n}", "auto", {"SYMPY_GROUND_TYPES": "flint"}, timeout=1800)
        if "num_terms" not in r:
            print(f"{n:>5} {r.get('states', ''):>6} {r.get('symbols', ''):>7} "
                  f"{r.get('cpu', float('nan')):>8.3f} {r['seconds']:>7.3f}  "
                  f"{r.get('note', '')}", flush=True)
            continue
        terms = r["num_terms"] + r["den_terms"]
        print(f"{n:>5} {r['states']:>6} {r['symbols']:>7} {r['cpu']:>8.3f} "
              f"{r['seconds']:>7.3f} {r['base_mb']:>7.0f} {r['tf_mb']:>6.0f} "
              f"{r['sympy_cpu']:>7.3f} {r['peak_mb']:>7.0f} {r['num_terms']:>9} "
              f"{r['den_terms']:>9} {1e6 * r['cpu'] / terms:>7.1f} "
              f"{1e6 * (r['cpu'] + r['sympy_cpu']) / terms:>7.1f}", flush=True)
    return 0


def _print(configs, as_json: bool) -> int:
    rows = [spawn(model, method, env, normalize) for model, method, env, normalize in configs]
    if as_json:
        for r in rows:
            print(json.dumps(r))
        return 0
    head = f"{'model':<10} {'states':>6} {'symbols':>7}  {'method':<10} {'ring arithmetic':<19} " \
           f"{'ground':<7} {'normalize':<10} {'seconds':>8} {'sympy s':>8} {'tf MB':>6} " \
           f"{'peak MB':>8} {'num terms':>9} {'den terms':>9}  {'import s':>8}"
    print(head)
    print("-" * len(head))
    for r in rows:
        print(f"{r['model']:<10} {r.get('states', ''):>6} {r.get('symbols', ''):>7}  "
              f"{r['method']:<10} {r.get('backend', r.get('BONDGRAPH_TF_BACKEND', '')):<19} "
              f"{r.get('ground_types', r.get('SYMPY_GROUND_TYPES', '')):<7} "
              f"{r.get('normalize', ''):<10} {r['seconds']:>8.3f} "
              f"{r.get('sympy_seconds', float('nan')):>8.3f} {r.get('tf_mb', float('nan')):>6.0f} "
              f"{r.get('peak_mb', float('nan')):>8.0f} {r.get('num_terms', ''):>9} "
              f"{r.get('den_terms', ''):>9}  {r.get('import_seconds', float('nan')):>8.2f}"
              + (f"  {r['note']}" if "note" in r else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
