"""Benchmark table 5 of ``flexgear bench transient``: a design load case's length (IEC 61400-1:
600 s a case) through the command line, with its files.

Each row runs ``flexgear simulate SCENE --t-end T --dt 1e-4 --out DIR`` in a child process on
the rated NREL 5 MW scene of :func:`assembly.app.bench.rated.rated_5mw` (every mesh
angle-driven with backlash; written to a temporary TOML file), one BLAS thread, recording the
main-shaft torque, the generator speed and every nonlinear mesh force (the run's default
outputs plus two). It prints the child's wall time, its peak resident memory (``ru_maxrss``
of the child: the interpreter and imports included), the time ``--out`` took to write the
files (the run manifest's ``time_s``) and, for the longer run, the ratio of its peak memory
to the shorter run's: a run whose histories stream keeps it near 1.
"""
from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .rated import rated_5mw

#: The issue's goals for 600 s at dt = 1e-4 s: wall minutes (rigid, flexible), peak memory GB,
#: the long run's peak memory over the short run's, and the seconds writing may take.
GOAL_MINUTES = {"nrel5mw": 4.0, "nrel5mw_flexible": 7.0}
GOAL_PEAK_GB, GOAL_MEMORY_RATIO, GOAL_WRITE_S = 1.0, 1.10, 30.0


def run_cli(scene_file: Path, t_end: float, dt: float, out_dir: Path) -> dict:
    """Wall s, peak RSS MB and writing s of one ``flexgear simulate`` child (module notes)."""
    from ..output import MANIFEST
    cmd = [sys.executable, "-m", "assembly.app.cli", "simulate", str(scene_file), "--t-end", repr(t_end),
           "--dt", repr(dt), "--out", str(out_dir), "--quiet",
           "--output", "torque:main_shaft", "--output", "speed:generator"]
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    code = os.waitstatus_to_exitcode(status)
    err = proc.stderr.read().decode(errors="replace").strip().splitlines() if proc.stderr else []
    manifest = out_dir / MANIFEST
    write_s = json.loads(manifest.read_text()).get("time_s") if manifest.exists() else None
    return {"code": code, "wall_s": wall, "peak_mb": usage.ru_maxrss / 1024.0, "write_s": write_s,
            "error": err[-1] if code and err else ""}


def long_table(names, seconds: float, short: float, dt: float, out) -> None:
    """Print table 5 for the scenes ``names``: ``short`` s and ``seconds`` s of each."""
    from ...scene.save import save_scene
    print(f"`flexgear bench transient` 5: `flexgear simulate --out` over {short:g} s and {seconds:g} s at dt = "
          f"{dt:g} s, one thread\n", file=out)
    print("| scene | simulated [s] | exit | wall [s] | goal wall [s] | peak RSS [MB] | / short run | goal | "
          "writing [s] | goal |", file=out)
    print("|---|---|---|---|---|---|---|---|---|---|", file=out)
    with tempfile.TemporaryDirectory(prefix="flexgear-bench-long-") as tmp:
        for name in names:
            scene_file = Path(tmp) / f"{name}_rated.toml"
            save_scene(rated_5mw(name), scene_file)
            peak_short = None
            for t_end in (short, seconds):
                r = run_cli(scene_file, t_end, dt, Path(tmp) / f"{name}_{t_end:g}")
                # the goals are the long run's (a short run's time is mostly start-up: imports, assembly)
                goal_wall = GOAL_MINUTES.get(name, float("nan")) * 60 * t_end / 600.0   # scaled from 600 s
                ratio = r["peak_mb"] / peak_short if peak_short else None
                peak_short = peak_short or r["peak_mb"]
                shown = "" if ratio is None else f"{ratio:.2f}"
                goal = f"<= {GOAL_PEAK_GB * 1024:.0f} MB" + ("" if ratio is None else f", <= {GOAL_MEMORY_RATIO:.2f}")
                write = "" if r["write_s"] is None else f"{r['write_s']:.1f}"
                wall_goal = f"<= {goal_wall:.3g}" if t_end == seconds else ""
                print(f"| {name} | {t_end:g} | {r['code']} | {r['wall_s']:.1f} | {wall_goal} | "
                      f"{r['peak_mb']:.0f} | {shown} | {goal} | {write} | <= {GOAL_WRITE_S:g} |", file=out)
                if r["code"]:
                    print(f"\n{name} {t_end:g} s: exit {r['code']}: {r['error']}\n", file=out)
    print(f"\nThe wall goal is the long run's, scaled to its length from 600 s; peak RSS of the child (ru_maxrss). "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB in this process.\n", file=out)
