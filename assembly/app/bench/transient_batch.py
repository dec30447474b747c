"""Benchmark table 6 of ``flexgear bench transient``: a batch of 600 s load cases on Dask workers.

It runs the shipped study ``nrel5mw_load_cases`` (analysis ``simulate``: the NREL 5 MW
drivetrain at 50, 75 and 100 % of rated torque, every mesh angle-driven with backlash) on a
local cluster of ``--workers`` worker processes (one thread each; start-up and close inside
the wall time), first with a short ``t_end`` and then with the study's own (600 s, one IEC
61400-1 load case). A variant keeps no history, only its statistics
(:class:`assembly.dynamics.history.Statistics`), so a worker's peak memory should not grow
with ``t_end``. It prints per variant the torque factor, the variant's own run time (the row's
``time_s``), the statistics of the main-shaft torque and of stage 3's mesh force, the contact
losses, and per run the wall time, the workers' peak resident memory (``VmHWM``, read as each
row arrives) and its ratio to the short run's.
"""
from __future__ import annotations

import dataclasses
import math

from .drivetrain import machine
from .study import timed_run

STUDY = "nrel5mw_load_cases"
#: The compiled step's goal for 600 s of the rigid 5 MW drivetrain (minutes, one core) and the
#: memory of a long run against a short one's
GOAL_MINUTES, GOAL_MEMORY_RATIO = 4.0, 1.10


def run_batch(t_end: float, workers: int) -> dict:
    """The study's rows with ``t_end`` on a local cluster, the wall time and the workers' peak
    memory (MB) (:func:`assembly.app.bench.study.timed_run`)."""
    from ..study.file import read_study
    study = read_study(STUDY)
    r = timed_run(dataclasses.replace(study, settings=dict(study.settings, t_end=t_end)), "local", workers, None)
    return {"rows": r["rows"], "wall": r["wall"], "workers": r["pids"], "t_end": t_end,
            "worker_mb": math.nan if r["worker_mb"] is None else r["worker_mb"]}


def batch_table(seconds: float, short: float, workers: int, out) -> None:
    """Print table 6: the load-case study over ``short`` s and ``seconds`` s on ``workers``."""
    print(f"`flexgear bench transient` 6: the load-case study `{STUDY}` (3 variants) on {workers} Dask workers, "
          f"{short:g} s and {seconds:g} s a variant at dt = 1e-4 s; {machine()}\n", file=out)
    print("| t_end [s] | torque factor | status | run [s] | goal [s] | mean main-shaft torque [MN m] | "
          "peak main-shaft torque [MN m] | rms stage-3 mesh force [kN] | peak stage-3 mesh force [kN] | "
          "contact losses |", file=out)
    print("|---|---|---|---|---|---|---|---|---|---|", file=out)
    runs = []
    for t_end in (short, seconds):
        r = run_batch(t_end, workers)
        runs.append(r)
        for row in r["rows"]:
            ok = row["status"] == "ok"
            cell = (lambda k, s: f"{row[k] / s:.4f}") if ok else (lambda k, s: "")
            print(f"| {t_end:g} | {row['torque_factor']:g} | {row['status']} {row.get('error', '')} | "
                  f"{row.get('time_s', math.nan):.1f} | <= {GOAL_MINUTES * 60 * t_end / 600:.3g} | "
                  f"{cell('mean[torque:main_shaft]', 1e6)} | {cell('peak[torque:main_shaft]', 1e6)} | "
                  f"{cell('rms[force:stage3]', 1e3)} | {cell('peak[force:stage3]', 1e3)} | "
                  f"{row.get('contact_losses', '')} |", file=out)
    print("\n| t_end [s] | variants | workers | wall [s] | workers' peak RSS [MB] | / short run | goal |", file=out)
    print("|---|---|---|---|---|---|---|", file=out)
    for r in runs:
        ratio = r["worker_mb"] / runs[0]["worker_mb"]
        print(f"| {r['t_end']:g} | {len(r['rows'])} | {r['workers']} | {r['wall']:.1f} | {r['worker_mb']:.0f} | "
              f"{ratio:.2f} | <= {GOAL_MEMORY_RATIO:.2f} |", file=out)
    print("\nNotes: a row's run time is the variant's own work in its worker (`time_s`: the scene's assembly, the "
          "static start and the integration); the goal is the compiled step's for 600 s on one core, scaled to "
          "t_end. The wall time holds the cluster's start-up and close, and variants wait for a free worker "
          "(3 variants on 2 workers: two rounds).\n", file=out)
