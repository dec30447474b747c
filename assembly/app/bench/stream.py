"""Benchmark (not a test): memory and time of ``flexgear simulate --out`` as the run lengthens,
histories streamed to HDF5 (:mod:`assembly.dynamics.history`).

``flexgear bench stream [--scene nrel5mw_transient] [--t-end 10 60] [--dt 1e-4]`` runs, for
each ``--t-end``, ``flexgear simulate SCENE --t-end T --dt DT --out TMP -q`` (the scene's
own outputs: every named stress point and nonlinear mesh force) in a fresh process and prints
one Markdown table: steps, wall time of the process, steps/s of the run, the time to write
the summary and pictures (``sim_files``: the history is written during the run), the
process's peak resident memory (MB, ``getrusage``), its ratio to the first length's, and the
HDF5 file's size. The goal: 600 s within 10 % of 10 s and under 1 GB.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .drivetrain import machine

CHILD = ("import resource, sys\nfrom assembly.app.cli import main\nrc = main(sys.argv[1:])\n"
         "print('MAXRSS_KB', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, file=sys.stderr)\nsys.exit(rc)\n")


def one(scene: str, t_end: float, dt: float, folder: Path) -> dict:
    """One ``flexgear simulate --out`` in a fresh process: its figures."""
    out = folder / f"t{t_end:g}"
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-c", CHILD, "simulate", scene, "--t-end", str(t_end), "--dt", str(dt),
                        "--out", str(out), "-q"], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    rss = [ln for ln in p.stderr.splitlines() if ln.startswith("MAXRSS_KB")]
    if p.returncode or not rss:
        raise SystemExit(f"flexgear simulate --t-end {t_end:g} failed ({p.returncode}): {p.stderr.strip()[-500:]}")
    summary = json.loads((out / "summary.json").read_text())
    manifest = json.loads((out / "flexgear_run.json").read_text())
    h5 = out / "simulation.h5"
    return {"t_end": t_end, "steps": summary["steps"], "wall_s": wall, "steps_per_s": summary["info"]["steps_per_s"],
            "write_s": manifest["time_s"], "rss_mb": int(rss[0].split()[1]) / 1024,
            "h5_mb": h5.stat().st_size / 2 ** 20, "outputs": len(summary["outputs"])}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="flexgear bench stream", description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default="nrel5mw_transient")
    ap.add_argument("--t-end", type=float, nargs="+", default=[10.0, 60.0])
    ap.add_argument("--dt", type=float, default=1e-4)
    a = ap.parse_args(argv)
    print(f"# flexgear simulate --out, streamed histories: {a.scene}, dt = {a.dt:g} s\n\n{machine()}\n")
    print("| t_end [s] | steps | outputs | wall [s] | steps/s | summary + pictures [s] | peak RSS [MB] | "
          "RSS / first | simulation.h5 [MB] |")
    print("|---|---|---|---|---|---|---|---|---|")
    first = None
    with tempfile.TemporaryDirectory(prefix="flexgear-bench-stream-") as tmp:
        for t_end in a.t_end:
            r = one(a.scene, t_end, a.dt, Path(tmp))
            first = first or r["rss_mb"]
            print(f"| {t_end:g} | {r['steps']} | {r['outputs']} | {r['wall_s']:.1f} | {r['steps_per_s']:.0f} | "
                  f"{r['write_s']:.2f} | {r['rss_mb']:.0f} | {r['rss_mb'] / first:.3f} | {r['h5_mb']:.0f} |",
                  flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
