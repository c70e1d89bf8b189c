"""Benchmark: this package beside its peers on the same N-cell chain, in one run.

The chain is the one of ``bench/bench_chain.py`` (a force on the first mass;
each cell a 1-junction with a mass ``m_i`` and a damper ``b_i`` to ground, a
0-junction with a spring of compliance ``k_i`` between neighbouring masses),
built in each tool with symbolic parameters, bond for bond in the same
directions.  Timed per tool, each size in a fresh process (imports not
counted): model construction, then derivation of the state equations.

* bondgraph (this package): ``build(n)``, ``assign_causality``, ``derive``.
* BondGraphTools (PyPI ``BondGraphTools``): ``bgt.new`` / ``bgt.add`` /
  ``bgt.connect``, then ``model.constitutive_relations`` (the reduced
  relations ``dx_i - f_i(x, u) = 0``).
* bondgraph-pypi (PyPI ``bondgraph``, another project of the same import
  name): ``BondGraph.add(Bond(...))``, then ``get_state_equations()``.

The peers run in their own virtual environment (the name ``bondgraph``
clashes with this package): ``--peer-python`` points at its interpreter;
without it the script makes one in ``--venv`` (default
``/tmp/bondgraph-peers``) with ``pip install BondGraphTools bondgraph`` and
says so when that fails.  A peer run that fails or exceeds ``--timeout``
seconds is reported as such.

Like for like: at 3 cells each tool's state matrix ``A`` at the same
numeric parameter values (``df_i/dx_j`` of its equations, states matched by
element) is compared with this package's ``compile_plant(...).plant(values).A``.

    python bench/bench_peers.py                      # N = 10 50, venv made if needed
    python bench/bench_peers.py 10 50 100 --peer-python /tmp/peers/bin/python
    python bench/bench_peers.py --timeout 120 10

This package's times are the median (by CPU) of 3 fresh processes, each
peer's one process.  "ratio" is the peer's wall time over this package's,
build + derivation;
"CPU ratio" the same for CPU seconds (``time.process_time`` of each process),
steadier on a shared machine.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
PEERS = ("BondGraphTools", "bondgraph-pypi")
CHECK_CELLS = 3


def values(n: int) -> dict[str, float]:
    """Distinct parameter values per cell (masses, dampers, compliances) and the force."""
    out = {}
    for i in range(n):
        out[f"m{i}"] = 1.0 + 0.1 * i
        out[f"b{i}"] = 0.1 + 0.05 * i
        if i:
            out[f"k{i}"] = 0.01 * (1.0 + 0.2 * i)
    return out


# ----------------------------------------------------------------------------- each tool, in its process
def _ours(n: int, check: bool) -> dict:
    sys.path.insert(0, HERE)
    import bondgraph as bg
    from bench_chain import build

    c0, t0 = time.process_time(), time.perf_counter()
    g = build(n)
    t1 = time.perf_counter()
    model = bg.derive(bg.assign_causality(g))
    t2 = time.perf_counter()
    r = {"build": t1 - t0, "derive": t2 - t1, "cpu": time.process_time() - c0,
         "states": len(model.states)}
    if check:
        A = bg.compile_plant(model).plant(values(n)).to_dense().A
        r["elements"] = [s[2:] for s in model.state_names]          # p_m0 -> m0, q_k1 -> k1
        r["A"] = A.tolist()
    return r


def _jacobian(rhs: list, states: list, n: int) -> list:
    import sympy

    subs = {sympy.Symbol(k): v for k, v in values(n).items()}
    J = sympy.Matrix(rhs).jacobian(sympy.Matrix(states)).xreplace(subs)
    return [[float(v) for v in row] for row in J.tolist()]


def _bondgraphtools(n: int, check: bool) -> dict:
    import sympy
    import BondGraphTools as bgt

    S = sympy.Symbol
    c0, t0 = time.process_time(), time.perf_counter()
    model = bgt.new(name=f"chain{n}")
    force = bgt.new("Se", name="F")
    bgt.add(model, force)
    prev = None
    for i in range(n):
        v = bgt.new("1", name=f"v{i}")
        m = bgt.new("I", name=f"m{i}", value=S(f"m{i}"))
        b = bgt.new("R", name=f"b{i}", value=S(f"b{i}"))
        bgt.add(model, v, m, b)
        bgt.connect(v, m)
        bgt.connect(v, b)
        if prev is None:
            bgt.connect(force, v)
        else:
            s = bgt.new("0", name=f"s{i}")
            k = bgt.new("C", name=f"k{i}", value=S(f"k{i}"))
            bgt.add(model, s, k)
            bgt.connect(prev, s)
            bgt.connect(s, v)
            bgt.connect(s, k)
        prev = v
    t1 = time.perf_counter()
    relations = model.constitutive_relations
    t2 = time.perf_counter()
    r = {"build": t1 - t0, "derive": t2 - t1, "cpu": time.process_time() - c0,
         "states": len(model.state_vars)}
    if check:
        names = sorted(model.state_vars, key=lambda x: int(x.split("_")[1]))
        xs = [S(x) for x in names]
        rhs = [None] * len(names)
        for rel in relations:                    # dx_j - f_j(x, u) = 0, one dx_j each
            (j,) = [j for j, x in enumerate(names) if rel.has(S("d" + x))]
            dx = S("d" + names[j])
            assert rel.coeff(dx) == 1
            rhs[j] = dx - rel
        r["elements"] = [model.state_vars[x][0].name for x in names]
        r["A"] = _jacobian(rhs, xs, n)
    return r


def _bondgraph_pypi(n: int, check: bool) -> dict:
    import sympy
    from bondgraph.common import Bond
    from bondgraph.core import BondGraph
    from bondgraph.elements import Element_C, Element_I, Element_R, Source_effort
    from bondgraph.junctions import JunctionEqualEffort, JunctionEqualFlow

    S = sympy.Symbol
    c0, t0 = time.process_time(), time.perf_counter()
    g = BondGraph()
    force = Source_effort("F", S("F"))
    prev = None
    for i in range(n):
        v = JunctionEqualFlow(f"v{i}")
        g.add(Bond(v, Element_I(f"m{i}", S(f"m{i}"), S(f"p_m{i}"))))
        g.add(Bond(v, Element_R(f"b{i}", S(f"b{i}"))))
        if prev is None:
            g.add(Bond(force, v))
        else:
            s = JunctionEqualEffort(f"s{i}")
            g.add(Bond(prev, s))
            g.add(Bond(s, v))
            g.add(Bond(s, Element_C(f"k{i}", S(f"k{i}"), S(f"q_k{i}"))))
        prev = v
    t1 = time.perf_counter()
    eqs = g.get_state_equations()
    t2 = time.perf_counter()
    r = {"build": t1 - t0, "derive": t2 - t1, "cpu": time.process_time() - c0,
         "states": len(eqs)}
    if check:
        states = list(eqs)
        r["elements"] = [s.name[2:] for s in states]
        r["A"] = _jacobian([eqs[s] for s in states], states, n)
    return r


RUNNERS = {"ours": _ours, "BondGraphTools": _bondgraphtools, "bondgraph-pypi": _bondgraph_pypi}


# ----------------------------------------------------------------------------- driver
def _peer_env() -> dict:
    # the peers' own ``bondgraph`` must win: no path of this package's checkout
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)
    return env


def make_venv(path: str) -> tuple[str, str]:
    """``(python, message)``: the peers' interpreter in ``path``, made and installed if absent."""
    python = os.path.join(path, "bin", "python")
    if os.path.exists(python):
        return python, f"peers' venv {path} (already there)"
    try:
        subprocess.run([sys.executable, "-m", "venv", path], check=True, capture_output=True,
                       text=True, timeout=300)
        done = subprocess.run([python, "-m", "pip", "install", "-q", "BondGraphTools", "bondgraph"],
                              capture_output=True, text=True, timeout=1200)
    except (subprocess.SubprocessError, OSError) as exc:
        return "", f"could not make the peers' venv in {path}: {exc}"
    if done.returncode != 0:
        return python, (f"pip install BondGraphTools bondgraph failed in {path}: "
                        f"{done.stderr.strip().splitlines()[-1:]}")
    return python, f"peers' venv {path} made (pip install BondGraphTools bondgraph)"


def run(python: str, tool: str, n: int, check: bool, timeout: float) -> dict:
    """One tool at one size in a fresh process: its result, or ``{"error": text}``."""
    cmd = [python, os.path.abspath(__file__), "--one", tool, str(n)] + (["--check"] if check else [])
    env = None if tool == "ours" else _peer_env()
    cwd = None if tool == "ours" else HERE
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env,
                              cwd=cwd)
    except subprocess.TimeoutExpired:
        return {"error": f"did not finish in {timeout:.0f} s"}
    lines = done.stdout.strip().splitlines()
    if done.returncode != 0 or not lines:
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        return {"error": f"failed: {last}"}
    return json.loads(lines[-1])


def compare(ours: dict, peer: dict) -> str:
    """``"A matches (max |diff| 1e-16)"`` or why not, states matched by element name."""
    if "error" in peer:
        return f"no check: {peer['error']}"
    if peer["states"] != ours["states"]:
        return f"{peer['states']} states against {ours['states']}: not the same model"
    if sorted(peer["elements"]) != sorted(ours["elements"]):
        return f"states of {peer['elements']} against {ours['elements']}"
    at = {e: i for i, e in enumerate(peer["elements"])}
    order = [at[e] for e in ours["elements"]]
    worst = 0.0
    for i, row in enumerate(ours["A"]):
        for j, a in enumerate(row):
            worst = max(worst, abs(a - peer["A"][order[i]][order[j]]))
    scale = max(abs(a) for row in ours["A"] for a in row)
    verdict = "A matches" if worst <= 1e-12 * scale else "A DIFFERS"
    return f"{verdict} ({ours['states']} states, max |diff| {worst:.1e}, max |A| {scale:.1f})"


def main(argv: list[str]) -> None:
    if argv and argv[0] == "--one":
        print(json.dumps(RUNNERS[argv[1]](int(argv[2]), "--check" in argv)))
        return
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("sizes", nargs="*", type=int, default=[10, 50])
    ap.add_argument("--peer-python", help="interpreter of a venv with the peers installed")
    ap.add_argument("--venv", default="/tmp/bondgraph-peers",
                    help="where to make that venv when --peer-python is not given")
    ap.add_argument("--timeout", type=float, default=900.0, help="seconds per peer run")
    args = ap.parse_args(argv)
    if args.peer_python:
        python, note = args.peer_python, f"peers' interpreter {args.peer_python}"
    else:
        python, note = make_venv(args.venv)
    print(note)
    load = os.getloadavg()
    print(f"load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f}; {os.cpu_count()} cores")

    ours_check = run(sys.executable, "ours", CHECK_CELLS, True, args.timeout)
    for tool in PEERS:
        peer = run(python, tool, CHECK_CELLS, True, args.timeout) if python else {
            "error": "not installed"}
        print(f"check at {CHECK_CELLS} cells, {tool}: {compare(ours_check, peer)}")

    print(f"\n{'tool':<16} {'N':>5} {'states':>6} {'build s':>9} {'derive s':>10} "
          f"{'total s':>9} {'CPU s':>8} {'ratio':>8} {'CPU ratio':>9}")
    for n in args.sizes:
        # this package's run is short and noisy on a shared machine: median CPU of 3 processes
        tries = sorted((run(sys.executable, "ours", n, False, args.timeout) for _ in range(3)),
                       key=lambda r: r.get("cpu", float("inf")))
        ours = tries[1]
        rows = [("this package", ours)]
        for tool in PEERS:
            rows.append((tool, run(python, tool, n, False, args.timeout) if python else
                         {"error": "not installed"}))
        base = ours["build"] + ours["derive"] if "error" not in ours else None
        for tool, r in rows:
            if "error" in r:
                print(f"{tool:<16} {n:>5}  {r['error']}")
                continue
            total = r["build"] + r["derive"]
            ratio = f"{total / base:.1f}x" if base else "-"
            cpu_ratio = f"{r['cpu'] / ours['cpu']:.1f}x" if base else "-"
            print(f"{tool:<16} {n:>5} {r['states']:>6} {r['build']:>9.4f} {r['derive']:>10.4f} "
                  f"{total:>9.3f} {r['cpu']:>8.3f} {ratio:>8} {cpu_ratio:>9}")


if __name__ == "__main__":
    main(sys.argv[1:])
