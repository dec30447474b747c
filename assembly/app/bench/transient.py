"""Benchmark (not a test): time-domain runs (``flexgear simulate``), their cost and the reduction's error.

``flexgear bench transient [--steps 5000] [--repeat 20000] [--seconds 10] [--no-flexible]
[--t-end 0.05] [--dt DT] [--no-full] [--tables 1,2,3,4]`` prints Markdown tables (times in s
unless marked, peak resident memory in MB): 1-3 below, 4 beside Exudyn
(:mod:`~assembly.app.bench.transient_peer`), 5 a 600 s run through the command line
(:mod:`~assembly.app.bench.transient_long`), 6 a batch of 600 s load cases on Dask workers
(:mod:`~assembly.app.bench.transient_batch`); 5 and 6 run on demand only:

1. **per-step cost** on the shipped ``nrel5mw_transient`` (126 DOFs, 13 meshes with the
   stiffness driven by the gear angle and 0.40 mm backlash: rank 26) and its flexible
   variant (stage 1 and 2 carriers and the stage-3 wheel flexible, 322 DOFs), dt = 1e-4 s,
   ``--steps`` steps from the static start, one BLAS thread: the step time
   (``(wall_s - factor_s) / steps`` of the run's ``info``) of the compiled step
   (numba; after a run that compiles it) and of the Python step, against one dense
   back-substitution of the same size measured in the same run (``Solver(A0).solve(b)``, the
   kept inverse times a vector, median of 5 blocks of ``--repeat``); the ratio, and the step's
   goals (at most 12x / 5x that back-substitution, 30 / 60 us); then ``--estimate`` s of each
   scene compiled and the 600 s run it extrapolates to (goals: 4 and 7 minutes);
2. **``--seconds`` of the drivetrain** (same scenes and settings, dt = 1e-4 s): wall time of
   ``simulate`` (model assembled before), steps/s, contact-loss events, mean main-shaft
   torque (``torque:main_shaft``, its rotor-side element) against the rated rotor torque;
3. **reduced vs unreduced** on ``hs_parallel_stage``: the scene's ``[load]`` torque (500 N m
   in at the pinion's ``bearing_a``) stepped on from rest over one dt, reacted by the
   torque on the output body that leaves the rigid-body mode unloaded, ``--t-end`` s at
   ``--dt`` (default: 10 steps per period at the band's top, the largest dt that resolves
   the band), the Craig-Bampton model and the unreduced one (``full_fe=True``, sparse LU);
   error of the reduced mesh-force histories: RMS and peak of the difference over those of
   the unreduced force, raw and low-passed to the band (FFT, both histories).
"""
from __future__ import annotations

import argparse
import logging
import math
import os
import statistics
import sys
import time

import numpy as np
from threadpoolctl import threadpool_limits

from .drivetrain import machine, peak_rss_mb
from .rated import BACKLASH, DT_5MW, GENERATOR_TORQUE, RATIO, STEP, rated_5mw
from .transient_batch import batch_table
from .transient_long import long_table
from .transient_peer import peer_table

log = logging.getLogger(__name__)

def bare_solve(model, scene, dt: float, repeat: int) -> tuple[float, float, str]:
    """(s per solve with the run's constant factorisation, s per solve + products with K, C
    and M, solver kind), built as ``simulate`` builds them."""
    from ...analysis.modal import SMALL_DENSE
    from ...dynamics.integrators import Solver, effective_matrix
    from ...dynamics.run_model import model_matrices, scheme_of
    from ...scene.time_domain import Simulation
    n = model.K.shape[0]
    M, K, C, _ = model_matrices(model)
    solver = Solver(effective_matrix(M, C, K, dt, scheme_of(scene.simulation or Simulation())))
    b = np.random.default_rng(0).standard_normal(n)

    def step_algebra():
        return solver.solve(b), K @ b, C @ b, M @ b

    out = []
    with threadpool_limits(1 if n <= SMALL_DENSE else None):
        for fn in (lambda: solver.solve(b), step_algebra):
            blocks = []
            for _ in range(5):
                t0 = time.perf_counter()
                for _ in range(repeat):
                    fn()
                blocks.append((time.perf_counter() - t0) / repeat)
            out.append(statistics.median(blocks))
    return out[0], out[1], solver.kind


def timed(model, t_end: float, dt: float, outputs, **kw):
    """(result, simulate() wall s, s per step between the first and last progress calls)."""
    from ...dynamics.simulate import simulate
    marks = []
    t0 = time.perf_counter()
    r = simulate(model, t_end, dt, outputs, progress=lambda i, n, t: marks.append((i, time.perf_counter())), **kw)
    wall = time.perf_counter() - t0
    (i0, t0), (i1, t1) = marks[0], marks[-1]
    return r, wall, (t1 - t0) / max(i1 - i0, 1)


def rms(x) -> float:
    return float(np.sqrt(np.mean(np.square(x))))


def low_pass(x: np.ndarray, dt: float, f_hz: float) -> np.ndarray:
    X = np.fft.rfft(x)
    X[np.fft.rfftfreq(len(x), dt) > f_hz] = 0.0
    return np.fft.irfft(X, len(x))


def step_scene(name: str, dt: float, rho_inf: float = 1.0):
    """The scene with its ``[load]`` torque stepped on over one dt, reacted on its output body
    so that the rigid-body mode is not loaded, integrated by generalized-alpha with
    ``rho_inf``; (scene, input torque, output torque)."""
    from ...analysis.load_cases import single_rigid_mode
    from ...model.assemble import assemble
    from ...model.probes import spin_row
    from ...scene.schema import load_scene
    scene = load_scene(name)
    ld = scene.load
    model = assemble(scene)
    phi = single_rigid_mode(model)[0][:, 0]
    t_out = -ld.torque * (spin_row(model, ld.input) @ phi) / (spin_row(model, ld.output) @ phi)
    loads = [{"body": b, "interface": i, "value": 0.0, "end_value": v, "t_start": 0.0, "t_end": dt}
             for b, i, v in ((ld.input, ld.input_interface, ld.torque), (ld.output, ld.output_interface, t_out))]
    loads = [{k: v for k, v in x.items() if v is not None} for x in loads]
    sim = {"static_start": False, "loads": loads, "scheme": "generalized-alpha", "rho_inf": rho_inf}
    return scene.with_values({"simulation": sim}), ld.torque, t_out


def main(argv=None, out=None) -> int:
    from ...model.assemble import assemble

    out = out or sys.stdout
    p = argparse.ArgumentParser(prog="flexgear bench transient", description=__doc__.split("\n\n")[0])
    p.add_argument("--steps", type=int, default=5000, help="steps of the per-step runs (table 1)")
    p.add_argument("--repeat", type=int, default=20000, help="bare solves a timing block (table 1)")
    p.add_argument("--seconds", type=float, default=10.0, help="simulated time of table 2 (s)")
    p.add_argument("--estimate", type=float, default=10.0,
                   help="table 1: simulated time of the compiled run that estimates 600 s (s; 0: none)")
    p.add_argument("--no-flexible", action="store_true", help="tables 1, 2: nrel5mw only")
    p.add_argument("--t-end", type=float, default=0.05, help="table 3: simulated time (s)")
    p.add_argument("--dt", type=float, default=None, help="table 3: time step (s; default 1 / (10 band_hz))")
    p.add_argument("--no-full", action="store_true", help="table 3: skip the unreduced model")
    p.add_argument("--rho-inf", type=float, default=0.6,
                   help="table 3: generalized-alpha spectral radius of both runs (default 0.6: damps what dt "
                        "cannot resolve, the unreduced model's modes far above the band)")
    p.add_argument("--cutoff-factor", type=float, default=3.0,
                   help="table 3: the reduced bodies keep their fixed-interface modes up to this x the band "
                        "(default 3; the scene's default is 1.5)")
    p.add_argument("--peer-seconds", type=float, default=1.0, help="table 4: simulated time beside Exudyn (s)")
    p.add_argument("--long-seconds", type=float, default=600.0,
                   help="table 5: the long run (s; default 600, one IEC 61400-1 load case)")
    p.add_argument("--short-seconds", type=float, default=10.0, help="table 5: the short run it is compared with (s)")
    p.add_argument("--batch-seconds", type=float, default=600.0,
                   help="table 6: simulated time of each load case of the batch (s; default 600)")
    p.add_argument("--workers", type=int, default=2, help="table 6: Dask worker processes (default 2)")
    p.add_argument("--tables", default="1,2,3,4", help="which tables to print (default 1,2,3,4; 5 and 6 run 600 s "
                                                        "cases and take tens of minutes)")
    a = p.parse_args(argv)
    tables = {int(x) for x in a.tables.split(",") if x.strip()}
    names = (["nrel5mw"] + ([] if a.no_flexible else ["nrel5mw_flexible"])) if 2 in tables else []
    cases = {}
    for name in names:
        scene = rated_5mw(name)
        t0 = time.perf_counter()
        cases[name] = (scene, assemble(scene), time.perf_counter() - t0)

    if 1 in tables:
        _per_step(cases, a, out)
    if 2 in tables:
        _drivetrain(cases, a, out)
    if 3 in tables:
        _reduced_vs_unreduced(a, out)
    flex = [] if a.no_flexible else ["nrel5mw_flexible"]
    if 4 in tables:
        peer_table(["nrel5mw", *flex], DT_5MW, a.peer_seconds, out)
    if 5 in tables:
        long_table(["nrel5mw", *flex], a.long_seconds, a.short_seconds, DT_5MW, out)
    if 6 in tables:
        batch_table(a.batch_seconds, a.short_seconds, a.workers, out)
    return 0


def transient_scenes(flexible: bool = True) -> dict:
    """{name: scene}: the shipped ``nrel5mw_transient`` and its flexible variant (the bodies
    ``nrel5mw_flexible`` makes flexible)."""
    from ...scene.schema import load_scene
    scene = load_scene("nrel5mw_transient")
    out = {"nrel5mw_transient": scene}
    if flexible:
        out["nrel5mw_transient, flexible"] = scene.with_values({f: "flexible" for f in FLEXIBLE})
    return out


#: The bodies of nrel5mw_flexible.toml that are flexible
FLEXIBLE = ("stages.stage1.carrier.fidelity", "stages.stage2.carrier.fidelity", "bodies.wheel.fidelity")
#: The compiled step's goals per step at 126 and 322 DOFs: x one back-substitution, and us
GOALS = {126: (12.0, 30.0), 322: (5.0, 60.0)}
#: Interleaved rounds of the compiled step's timing (table 1)
ROUNDS = 5
#: The compiled step's goals for 600 s at dt = 1e-4 s (min), rigid and flexible
GOALS_600 = {126: 4.0, 322: 7.0}


def step_time(model, steps: int, compiled: bool) -> tuple[float, dict]:
    """(s per step, run info) of ``steps`` steps of 1e-4 s on the compiled or the Python step."""
    from ...dynamics import jit
    from ...dynamics.simulate import simulate
    saved = jit.ENABLED
    jit.ENABLED = compiled
    try:
        r = simulate(model, steps * DT_5MW, DT_5MW)
    finally:
        jit.ENABLED = saved
    i = r.info
    if i["compiled"] is not compiled:
        raise RuntimeError(f"the run took the {'compiled' if i['compiled'] else 'Python'} step")
    return (i["wall_s"] - i["factor_s"]) / i["steps"], i


def _per_step(cases, a, out) -> None:
    from ...dynamics import jit
    from ...model.assemble import assemble
    if not jit.COMPILED:
        print("`flexgear bench transient` 1: numba is not installed (make installs the speed extra); the compiled "
              "step is not measured.\n", file=out)
    load0 = os.getloadavg()
    rows, long_rows = [], []
    with threadpool_limits(1):
        for name, scene in transient_scenes(not a.no_flexible).items():
            model = assemble(scene)
            n = model.K.shape[0]
            python, pinfo = step_time(model, a.steps, False)
            if jit.COMPILED:
                step_time(model, 10, True)                      # compiles (or loads numba's cache)
                # rounds of a run and a back-substitution block, interleaved so that both see the
                # machine alike (a shared machine's speed drifts by some 10 % over a minute); the
                # medians of the step, the back-substitution and their ratio
                rounds = []
                for _ in range(ROUNDS):
                    c = step_time(model, a.steps, True)[0]
                    b, _, kind = bare_solve(model, scene, DT_5MW, a.repeat)
                    rounds.append((c, b, c / b))
                compiled, solve, ratio = (statistics.median(x) for x in zip(*rounds))
            else:
                compiled, ratio = math.nan, math.nan
                solve, _, kind = bare_solve(model, scene, DT_5MW, a.repeat)
            rows.append((name, n, pinfo["rank"], pinfo["mean_iterations"], kind, compiled, python, solve, ratio))
            if jit.COMPILED and a.estimate > 0:
                from ...dynamics.simulate import simulate
                t0 = time.perf_counter()
                r = simulate(model, a.estimate, DT_5MW)
                wall = time.perf_counter() - t0
                long_rows.append((name, n, a.estimate, wall, r.info["mean_iterations"], r.info["losses_total"],
                                  wall * 600.0 / a.estimate / 60.0))
    load1 = os.getloadavg()
    print(f"`flexgear bench transient` 1: per-step cost against one back-substitution, one thread; {machine()}\n",
          file=out)
    print("| scene | DOFs | rank m | Newton iterations / step | solver | compiled step [us] | Python step [us] | "
          "back-substitution [us] | compiled / back-substitution | goal | Python / back-substitution | holds |",
          file=out)
    print("|---|---|---|---|---|---|---|---|---|---|---|---|", file=out)
    for name, n, m, its, kind, c, p, solve, r in rows:
        goal, us = GOALS.get(n, (math.nan, math.nan))
        holds = "yes" if r <= goal and c * 1e6 <= us else ("no" if c == c else "")
        print(f"| {name} | {n} | {m} | {its:.2f} | {kind} | {c * 1e6:.1f} | {p * 1e6:.1f} | {solve * 1e6:.2f} | "
              f"{r:.1f} | <= {goal:g}x, <= {us:g} us | {p / solve:.0f} | {holds} |", file=out)
    print(f"\nNotes: {a.steps} steps of {DT_5MW:g} s from the static start; step time from the run's info (wall_s "
          "less factor_s). Back-substitution: one `Solver(A0).solve(b)` of the run's effective matrix (the kept "
          f"inverse times a vector), median of 5 blocks of {a.repeat}. The compiled step: {ROUNDS} rounds of a run "
          "and a back-substitution measurement, interleaved; the medians of the step, the back-substitution and "
          "their ratio (the Python step: one run). Load average (1, 5, 15 min) "
          f"{', '.join(f'{x:.2f}' for x in load0)} before, {', '.join(f'{x:.2f}' for x in load1)} after; "
          "the absolute goals hold at load below 1.\n", file=out)
    if long_rows:
        print("| scene | DOFs | simulated [s] | simulate, compiled [s] | Newton iterations / step | contact losses | "
              "600 s estimate [min] | goal [min] |", file=out)
        print("|---|---|---|---|---|---|---|---|", file=out)
        for name, n, secs, wall, its, losses, est in long_rows:
            print(f"| {name} | {n} | {secs:g} | {wall:.1f} | {its:.2f} | {losses} | {est:.1f} | "
                  f"< {GOALS_600.get(n, math.nan):g} |", file=out)
        print("\nNotes: the whole `simulate` call (static start, setup, integration; the model assembled before), "
              "x 600 / simulated seconds.\n", file=out)


def _drivetrain(cases, a, out) -> None:
    rated = GENERATOR_TORQUE * RATIO
    print(f"`flexgear bench transient` 2: {a.seconds:g} s of the 5 MW drivetrain at dt = {DT_5MW:g} s; "
          f"{machine()}\n", file=out)
    print("| scene | DOFs | assemble [s] | steps | simulate [s] | steps/s | Newton iterations / step | "
          "contact losses | mean torque:main_shaft [N m] | / rated | min, max [N m] |", file=out)
    print("|---|---|---|---|---|---|---|---|---|---|---|", file=out)
    for name, (scene, model, t_asm) in cases.items():
        r, wall, _ = timed(model, a.seconds, DT_5MW, ["torque:main_shaft"])
        i, tq = r.info, r.outputs["torque:main_shaft"]
        print(f"| {name} | {i['dofs']} | {t_asm:.2f} | {i['steps']} | {wall:.1f} | {i['steps'] / wall:.0f} | "
              f"{i['mean_iterations']:.2f} | {i['losses_total']} | {tq.mean():.6g} | {tq.mean() / rated:.4f} | "
              f"{tq.min():.4g}, {tq.max():.4g} |", file=out)
    print(f"\nNotes: rated rotor torque {GENERATOR_TORQUE:.2f} x {RATIO:g} = {rated:.6g} N m; the goal is "
          f"{a.seconds:g} s simulated in under 30 s of wall time. simulate [s]: the whole call with the model "
          "assembled before (setup, static start, integration); steps/s over that call. Contact losses: steps at "
          "whose end a mesh in contact lost it, summed over the meshes.\n", file=out)


def _reduced_vs_unreduced(a, out) -> None:
    from ...dynamics.run_checks import STEPS_PER_PERIOD
    from ...model.assemble import assemble
    from ...scene.schema import load_scene
    sname = "hs_parallel_stage"
    band = load_scene(sname).band
    dt = a.dt or 1.0 / (STEPS_PER_PERIOD * band)
    scene, t_in, t_out = step_scene(sname, dt, a.rho_inf)
    flexible = [i for i, b in enumerate(scene.bodies) if b.fidelity == "flexible"]
    scene = scene.with_values({f"bodies[{i}].flex.cutoff_hz": a.cutoff_factor * band for i in flexible})
    meshes = ["force:" + (m.name or f"{m.gear1}-{m.gear2}") for m in scene.meshes]
    runs = [("reduced (Craig-Bampton)", False)] + ([] if a.no_full else [("unreduced (full_fe)", True)])
    res = []
    for label, full in runs:
        r, wall, per = timed(scene, a.t_end, dt, meshes, full_fe=full)
        model = assemble(scene, full_fe=full)
        bare = bare_solve(model, scene, dt, 20 if full else a.repeat)[0]
        del model
        res.append((label, r, wall, per, peak_rss_mb(), bare))
        log.info("%s: %.1f s", label, wall)
    print(f"`flexgear bench transient` 3: {sname}, torque step, reduced vs unreduced; {machine()}\n", file=out)
    print("| model | DOFs | solver | simulate [s] | factorisations [s] | step [ms] | bare solve [ms] | step / bare "
          "solve | speed-up (simulate; step) | error RMS | error peak | in band: RMS | in band: peak | peak RSS [MB] |",
          file=out)
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|", file=out)
    ref = res[-1][1] if len(res) > 1 else None
    for label, r, wall, per, rss, bare in res:
        i, cols = r.info, ["", "", "", "", ""]
        if ref is not None and r is not ref:
            d = [r.outputs[k] - ref.outputs[k] for k in meshes]
            lp = [(low_pass(x, dt, band), low_pass(ref.outputs[k], dt, band)) for x, k in zip(d, meshes)]
            cols = [f"{res[1][2] / wall:.0f}x; {res[1][3] / per:.0f}x",
                    f"{max(rms(x) / rms(ref.outputs[k]) for x, k in zip(d, meshes)):.2%}",
                    f"{max(np.abs(x).max() / np.abs(ref.outputs[k]).max() for x, k in zip(d, meshes)):.2%}",
                    f"{max(rms(x) / rms(y) for x, y in lp):.2%}",
                    f"{max(np.abs(x).max() / np.abs(y).max() for x, y in lp):.2%}"]
        elif r is ref:
            cols = ["", "reference", "", "", ""]
        print(f"| {label} | {i['dofs']} | {i['solver']} | {wall:.2f} | {i['factor_s']:.3g} | {per * 1e3:.3g} | "
              f"{bare * 1e3:.3g} | {per / bare:.1f} | " + " | ".join(cols) + f" | {rss:.0f} |", file=out)
    f0 = res[0][1].outputs[meshes[0]]
    print(f"\nNotes: {a.t_end:g} s at dt = {dt:.4g} s ({round(a.t_end / dt)} steps, {1 / (dt * band):.1f} per period "
          f"at the band's top {band:g} Hz), reduced bodies' cutoff {a.cutoff_factor:g} x the band, "
          f"generalized-alpha rho_inf = {a.rho_inf:g} (both models), no "
          f"damping in the scene, from rest; "
          f"{t_in:g} N m on {scene.load.input}:{scene.load.input_interface} and {t_out:.6g} N m on "
          f"{scene.load.output} ramped from 0 over one dt. Outputs {', '.join(meshes)} (reduced: mean "
          f"{f0.mean():.5g} N, peak {np.abs(f0).max():.5g} N). simulate [s]: the whole call with assembly; "
          "factorisations: the effective matrix's and M's (for the starting acceleration); step: time between "
          "the first and last progress calls per step; bare solve: one solve with the effective matrix's "
          "factorisation. Errors: of the reduced "
          "history against the unreduced, RMS (peak) of the difference over the RMS (peak) of the unreduced "
          "force; in band: both histories low-passed to the band by FFT first. Goals: speed-up >= 100x, "
          "error <= 0.5 % RMS.", file=out)


if __name__ == "__main__":
    raise SystemExit(main())
