"""Start-up time of the command line: ``bondgraph --help`` and each command's imports.

Each figure is the median wall time of ``--runs`` fresh Python processes (no
warm module cache inside a process; the OS file cache is warm after the
first run).  Targets (issue 35, on a quiet machine): ``bondgraph --help``
under 0.3 s, each command's imports under 0.6 s.

* ``python (baseline)``: ``python -c pass``, the interpreter alone;
* ``bondgraph --help``: ``python -m bondgraph --help``;
* ``import bondgraph``: the package (its names are bound on first use);
* ``<command> imports``: the modules the command loads before its work
  (``equations``: the model file machinery; ``tf``: and the transfer
  functions; ``export``: and the plants, exports and code generators; ...);
* ``equations dc_motor.py``: a whole command on a small model.

Run from the repository root::

    python bench/bench_cli_startup.py [--runs 7] [--importtime] [--root OTHER_CHECKOUT]

``--root`` times another checkout of the package (to compare before and after).

``--importtime`` adds the ten slowest imports of ``bondgraph --help`` and of
``equations`` (``python -X importtime``, cumulative microseconds).  The load
average is printed: on a busy machine the numbers scale with it.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MOTOR = str(ROOT / "tests" / "data" / "dc_motor.py")

#: command -> the modules it imports before doing its work (see bondgraph/cli/_commands.py)
COMMAND_IMPORTS = {
    "equations": ["bondgraph.cli", "bondgraph.modelfile"],
    "tf": ["bondgraph.cli", "bondgraph.modelfile", "bondgraph.tf"],
    "export": ["bondgraph.cli", "bondgraph.modelfile", "bondgraph.export", "bondgraph.numeric",
               "bondgraph.codegen"],
    "draw": ["bondgraph.cli", "bondgraph.modelfile", "bondgraph.drawing"],
    "simulate": ["bondgraph.cli", "bondgraph.modelfile", "bondgraph.numeric.simulate",
                 "scipy.integrate"],
    "sweep": ["bondgraph.cli", "bondgraph.modelfile", "bondgraph.study"],
}


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def _set_root(path: str) -> None:
    global ROOT, MOTOR
    ROOT = Path(path).resolve()
    MOTOR = str(ROOT / "tests" / "data" / "dc_motor.py")


def timed(argv: list[str], runs: int) -> float:
    """Median wall time of ``runs`` fresh processes (one untimed run first)."""
    env = _env()
    # run in the checkout: its package, not one in the caller's directory, is imported
    subprocess.run(argv, env=env, capture_output=True, check=True, cwd=ROOT)
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run(argv, env=env, capture_output=True, check=True, cwd=ROOT)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def slowest_imports(argv: list[str], n: int = 10) -> list[tuple[int, str]]:
    """The ``n`` largest cumulative import times (us) of ``python -X importtime argv``."""
    out = subprocess.run([sys.executable, "-X", "importtime", *argv], env=_env(), cwd=ROOT,
                         capture_output=True, text=True, check=True).stderr
    rows = []
    for line in out.splitlines():
        if line.startswith("import time:") and "|" in line and "cumulative" not in line:
            _, cumulative, name = line.split("|")
            rows.append((int(cumulative), name.rstrip()))
    return sorted(rows, reverse=True)[:n]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=7, help="processes per figure (median)")
    ap.add_argument("--importtime", action="store_true", help="also the slowest imports")
    ap.add_argument("--root", help="time this checkout instead (default: this repository)")
    args = ap.parse_args(argv)
    if args.root:
        _set_root(args.root)
    py = sys.executable
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"python {sys.version.split()[0]}, {os.cpu_count()} CPUs, load average {load:.2f}, "
          f"median of {args.runs} runs, {ROOT}")
    rows = [("python (baseline)", [py, "-c", "pass"], None),
            ("bondgraph --help", [py, "-m", "bondgraph", "--help"], 0.3),
            ("import bondgraph", [py, "-c", "import bondgraph"], None)]
    for command, modules in COMMAND_IMPORTS.items():
        rows.append((f"{command} imports", [py, "-c", "import " + ", ".join(modules)], 0.6))
    rows.append(("equations dc_motor.py", [py, "-m", "bondgraph", "equations", MOTOR], None))
    for label, cmd, target in rows:
        t = timed(cmd, args.runs)
        goal = f"   (target < {target:.1f} s quiet)" if target else ""
        print(f"{label:24s} {t:7.3f} s{goal}")
    if args.importtime:
        for label, cmd in (("--help", ["-m", "bondgraph", "--help"]),
                           ("equations", ["-m", "bondgraph", "equations", MOTOR])):
            print(f"\nslowest imports of {label} (cumulative ms):")
            for us, name in slowest_imports(cmd):
                print(f"  {us / 1000:8.1f}  {name.strip()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
