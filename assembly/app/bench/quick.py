"""Benchmark (not a test): how quickly the two everyday commands answer.

``flexgear bench quick [--repeat 9] [--run-repeat 3] [--only modes|run]`` times, each in a
fresh process with the interpreter running this one (``python -m assembly.app.cli``):

- ``flexgear modes kahraman_beta20``: a 12-DOF scene, goal under 0.3 s: the process start,
  the imports and the solve, nothing cached but what Python caches;
- ``flexgear run hs_parallel_stage.toml --out TMP`` (``make run``), goal under 8 s, with a
  warm cache (one run first, not timed, fills the mesh and superelement caches).

Each command runs once untimed, then ``N`` times; the table gives the median, the fastest
and the slowest wall time (s), the median CPU time (user + system, s: what the command
itself costs, less swayed by other work than the wall time; above the wall time when it
runs threads), the goal, median / goal, and the 1-minute load average after the command's
runs (the machine's other work slows every figure: read them with the load).
The first line names the cores, the load average before, whether Python writes bytecode
caches (``PYTHONDONTWRITEBYTECODE``) and how many of the package's modules have an up-to-date
one (``make setup`` compiles them all): a module without one is compiled again at every
start, about 0.1 s of the small command in all.
"""
from __future__ import annotations

import argparse
import importlib.util
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .drivetrain import machine

#: (name, arguments of ``flexgear``, goal in s); ``{out}`` is a fresh output folder.
COMMANDS = (("modes", ("modes", "kahraman_beta20"), 0.3),
            ("run", ("run", "hs_parallel_stage.toml", "--out", "{out}"), 8.0))


def timed(args: tuple, folder: Path, k: int) -> tuple[float, float]:
    """(wall time, CPU time user + system) in s of ``flexgear *args`` in a fresh process;
    SystemExit if it fails."""
    argv = [a.format(out=folder / f"out{k}") for a in args]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "assembly.app.cli", *argv], stdout=subprocess.DEVNULL,
                       stderr=subprocess.PIPE, text=True)
    dt = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode:
        raise SystemExit(f"flexgear {' '.join(argv)} failed ({p.returncode}): {p.stderr.strip()[-500:]}")
    return dt, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def row(name: str, args: tuple, goal: float, n: int, folder: Path) -> dict:
    """One warm-up run, then ``n`` timed runs of one command: its figures."""
    timed(args, folder, 0)
    runs = [timed(args, folder, k + 1) for k in range(n)]
    times = [w for w, _ in runs]
    med = statistics.median(times)
    return {"command": "flexgear " + " ".join(a.replace("{out}", "TMP") for a in args), "runs": n,
            "median_s": med, "min_s": min(times), "max_s": max(times), "cpu_s": statistics.median(c for _, c in runs),
            "goal_s": goal, "ratio": med / goal, "load_1min": os.getloadavg()[0]}


def bytecode_note() -> str:
    """Whether Python writes bytecode caches, and how many of the package's modules have an
    up-to-date one (``make setup`` compiles them: with them, caches off costs nothing)."""
    off = sys.dont_write_bytecode or bool(os.environ.get("PYTHONDONTWRITEBYTECODE"))
    src = [p for p in (Path(__file__).resolve().parents[2]).rglob("*.py")]
    fresh = 0
    for p in src:
        c = Path(importlib.util.cache_from_source(str(p)))
        fresh += c.exists() and c.stat().st_mtime >= p.stat().st_mtime
    state = "bytecode caches off (PYTHONDONTWRITEBYTECODE)" if off else "bytecode caches on"
    return f"{state}, {fresh} of {len(src)} modules of assembly compiled"


def main(argv=None, out=None) -> int:
    out = out or sys.stdout
    ap = argparse.ArgumentParser(prog="flexgear bench quick", description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=9, help="timed runs of the modes command (default 9)")
    ap.add_argument("--run-repeat", type=int, default=3, help="timed runs of the run command (default 3)")
    ap.add_argument("--only", choices=[c[0] for c in COMMANDS], help="time one command only")
    a = ap.parse_args(argv)
    if a.repeat < 1 or a.run_repeat < 1:
        ap.error("--repeat and --run-repeat must be >= 1")
    print(f"# how quickly flexgear answers\n\n{machine()}; {bytecode_note()}\n", file=out)
    print("| command | runs | median [s] | fastest [s] | slowest [s] | CPU median [s] | goal [s] | median / goal | "
          "load average (1 min) |", file=out)
    print("|---|---|---|---|---|---|---|---|---|", file=out, flush=True)
    with tempfile.TemporaryDirectory(prefix="flexgear-bench-quick-") as tmp:
        for name, args, goal in COMMANDS:
            if a.only not in (None, name):
                continue
            r = row(name, args, goal, a.repeat if name == "modes" else a.run_repeat, Path(tmp))
            print(f"| {r['command']} | {r['runs']} | {r['median_s']:.2f} | {r['min_s']:.2f} | {r['max_s']:.2f} | "
                  f"{r['cpu_s']:.2f} | {r['goal_s']:g} | {r['ratio']:.2f} | {r['load_1min']:.2f} |",
                  file=out, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
