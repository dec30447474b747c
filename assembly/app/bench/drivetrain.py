"""Benchmark (not a test): a whole drivetrain scene, rigid and with flexible bodies.

``flexgear bench drivetrain [--scene nrel5mw_flexible.toml] [--rigid-scene nrel5mw.toml]
[--repeat 2]`` prints two Markdown tables (times in s, peak resident memory in MB):

- rigid: load + assemble + all modes of the rigid scene and of its torsional variant with
  a warm mesh cache (each component's mass properties come from the mass-property cache,
  assembly.model.mass_cache: no mesh is read);
- flexible: the scene with flexible bodies, cold (every cache folder a fresh temporary
  one: meshing, FE assembly, coupling, Craig-Bampton reduction, assembly, modes) and warm
  (the same caches again, nothing memoised in the process: the reductions are read back),
  FE and reduced DOFs per flexible body and of the assembled model, and the error against
  the unreduced model (``assemble(scene, full_fe=True)``: every FE DOF, its lowest modes by
  the sparse shift-invert solve), its in-band modes paired by MAC with the reduced ones.

Every run is repeated ``--repeat`` times and each time is printed; the machine (cores this
process may use, load average) and the sparse backend are printed with the tables.
"""
from __future__ import annotations

import argparse
import contextlib
import os
import resource
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from ...analysis.classify import pair_modes
from ...analysis.modal import solve_modes
from ...model.assemble import assemble
from ...model.components import CacheDirs, forget_fe_models
from ...scene.schema import load_scene
from ...scene.tables import with_fidelity

#: Modes of the unreduced model solved beyond the reduced model's in-band count: the reduced
#: frequencies bound the full ones from above (Rayleigh-Ritz), so the full model has at
#: least as many in band; the solve is repeated with twice the count until its highest
#: mode lies above the band.
EXTRA_MODES = 10


def peak_rss_mb() -> float:
    """Peak resident memory of this process so far (MB; Linux reports kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def machine() -> str:
    """Cores this process may use, load average and the sparse backend, in one line."""
    from cms.linsolve import default_backend
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    return f"{cores} cores, load average {load} (1, 5, 15 min), sparse backend {default_backend()}"


@contextlib.contextmanager
def fresh_caches():
    """CacheDirs in a new temporary folder (meshes in it, reductions in its ``cms``), also
    named by FLEXGEAR_CACHE_DIR for the block, so nothing reads an older cache."""
    from fe_components.meshing import cache_root
    with tempfile.TemporaryDirectory(prefix="flexgear-bench-") as folder, cache_root(folder):
        yield CacheDirs(Path(folder), Path(folder) / "cms")


def timed_solve(scene_name: str, caches: CacheDirs | None = None, fidelity: str | None = None):
    """(seconds, modal result) of load + assemble + all modes, nothing memoised in the process."""
    forget_fe_models()
    t0 = time.perf_counter()
    scene = load_scene(scene_name)
    if fidelity is not None:
        scene = with_fidelity(scene, fidelity)
    r = solve_modes(assemble(scene, caches=caches, source=scene))
    return time.perf_counter() - t0, r


def rigid_rows(scene_name: str, repeat: int) -> list:
    """Rows of the rigid table: the scene as given and its torsional variant, warm."""
    timed_solve(scene_name)                       # warms the mesh and mass-property caches
    rows = []
    for fidelity in ("rigid", "torsional"):
        runs = [timed_solve(scene_name, fidelity=fidelity) for _ in range(repeat)]
        r = runs[0][1]
        rows.append(dict(scene=scene_name, fidelity=fidelity, dofs=int(r.model.K.shape[0]),
                         n_modes=len(r.frequencies_hz), times_s=[t for t, _ in runs]))
    return rows


def full_fe_modes(scene, caches: CacheDirs, n_modes: int):
    """(model, modes, build s, solve s) of the unreduced model: at least ``n_modes`` modes
    and enough that the highest lies above the band (the count doubles until it does)."""
    forget_fe_models()
    t0 = time.perf_counter()
    model = assemble(scene, full_fe=True, caches=caches, source=scene)
    t_build = time.perf_counter() - t0
    n = n_modes
    while True:
        r = solve_modes(model, n_modes=n, check=False)
        if r.frequencies_hz[-1] > scene.band or n >= model.K.shape[0] - 1:
            return model, r, t_build, time.perf_counter() - t0 - t_build
        n *= 2


def in_band_error(reduced, full, band_hz: float) -> dict:
    """Reduced elastic modes below ``band_hz`` paired by MAC with the full model's: their
    count, the largest relative frequency error and the smallest MAC of the pairs."""
    pairs = {i: (j, mac) for i, j, mac in pair_modes(reduced, full)}
    f_red, f_full = reduced.frequencies_hz, full.frequencies_hz
    idx = [i for i in range(reduced.n_rigid, len(f_red)) if f_red[i] < band_hz]
    err = [abs(f_red[i] / f_full[pairs[i][0]] - 1) for i in idx if i in pairs]
    macs = [pairs[i][1] for i in idx if i in pairs]
    return dict(n_in_band=len(idx), n_paired=len(err), max_rel_err=max(err, default=float("nan")),
                min_mac=min(macs, default=float("nan")))


def flexible_row(scene_name: str, repeat: int) -> dict:
    """The flexible table's row: cold and warm times (``repeat`` runs each: each cold run in
    fresh cache folders, followed by a warm one on them), sizes, in-band error against the
    unreduced model (built from the last run's cached meshes: FE assembly and coupling
    included, meshing not), peak memory (after the reduced runs; after the full FE one)."""
    cold, warm = [], []
    for k in range(repeat):
        with fresh_caches() as caches:
            t, reduced = timed_solve(scene_name, caches)
            cold.append(t)
            warm.append(timed_solve(scene_name, caches)[0])
            rss_reduced = peak_rss_mb()
            if k == repeat - 1:                   # the reference, from the meshes cached here
                scene = load_scene(scene_name)
                n_band = int(np.sum(reduced.frequencies_hz < scene.band))
                full_model, full, t_build, t_solve = full_fe_modes(scene, caches, n_band + EXTRA_MODES)
    m = reduced.model
    flex = [b for b in m.bodies if getattr(m.bodies[b], "flexible", False)]
    return dict(scene=scene_name, band_hz=scene.band, dofs=int(m.K.shape[0]),
                bodies={b: (int(full_model.bodies[b].ndof), int(m.bodies[b].ndof)) for b in flex},
                cold_s=cold, warm_s=warm, full_dofs=int(full_model.K.shape[0]), full_build_s=t_build,
                full_solve_s=t_solve, full_n_modes=len(full.frequencies_hz), full_residual=full.max_residual,
                peak_rss_reduced_mb=rss_reduced, peak_rss_mb=peak_rss_mb(),
                **in_band_error(reduced, full, scene.band))


def _times(ts) -> str:
    return ", ".join(f"{t:.3g}" for t in ts)


def print_rigid(rows, out=None) -> None:
    out = sys.stdout if out is None else out
    print("| scene | fidelity | DOFs | modes | load + assemble + all modes, warm [s] |", file=out)
    print("|---|---|---|---|---|", file=out)
    for r in rows:
        print(f"| {r['scene']} | {r['fidelity']} | {r['dofs']} | {r['n_modes']} | {_times(r['times_s'])} |",
              file=out)


def print_flexible(row, out=None) -> None:
    out = sys.stdout if out is None else out
    bodies = "; ".join(f"{b} {fe} -> {red}" for b, (fe, red) in row["bodies"].items())
    print("| scene | flexible bodies: coupled FE -> reduced DOFs | model DOFs | cold [s] | warm [s] | full FE DOFs "
          "| full FE build + solve [s] | full FE modes (max residual) | in-band modes (paired) | max in-band freq. error [%] | min MAC "
          "| peak RSS reduced / with full FE [MB] |", file=out)
    print("|---|---|---|---|---|---|---|---|---|---|---|---|", file=out)
    print(f"| {row['scene']} | {bodies} | {row['dofs']} | {_times(row['cold_s'])} | {_times(row['warm_s'])} "
          f"| {row['full_dofs']} | {row['full_build_s']:.1f} + {row['full_solve_s']:.1f} "
          f"| {row['full_n_modes']} ({row['full_residual']:.1e}) "
          f"| {row['n_in_band']} ({row['n_paired']}) | {100 * row['max_rel_err']:.2g} | {row['min_mac']:.4f} "
          f"| {row['peak_rss_reduced_mb']:.0f} / {row['peak_rss_mb']:.0f} |", file=out)


def main(argv=None, out=None) -> int:
    out = sys.stdout if out is None else out
    p = argparse.ArgumentParser(prog="flexgear bench drivetrain", description=__doc__.split("\n")[0])
    p.add_argument("--scene", default="nrel5mw_flexible.toml", help="scene with flexible bodies ('' to skip)")
    p.add_argument("--rigid-scene", default="nrel5mw.toml",
                   help="rigid scene timed warm, with its torsional variant ('' to skip)")
    p.add_argument("--repeat", type=int, default=2, help="runs of every timing (each printed)")
    a = p.parse_args(argv)
    if a.repeat < 1:
        p.error("--repeat must be >= 1")
    print(f"machine: {machine()}", file=out)
    if a.rigid_scene:
        print_rigid(rigid_rows(a.rigid_scene, a.repeat), out)
        print(file=out)
    if a.scene:
        print_flexible(flexible_row(a.scene, a.repeat), out)
    print(f"machine after: {machine()}", file=out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
