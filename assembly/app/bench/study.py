"""Benchmark (not a test): design studies (``flexgear study``) in this process and on a local Dask cluster.

``flexgear bench study [--variants 20] [--vary thickness|cutoff] [--rigid-variants 200]
[--workers 2] [--no-flexible] [--no-rigid] [--quick]`` builds its studies in a temporary
folder (study files written there, read by :func:`assembly.app.study.file.read_study`),
runs each with :func:`assembly.app.study.engine.run_study` ``mode="serial"`` (one variant
after the other in this process) and ``mode="local"`` (a new LocalCluster of ``--workers``
worker processes, one thread each; its start-up and close are inside the wall time), and
prints three Markdown tables (times in s unless marked, memory in MB):

1. **flexible study, cold**: ``--variants`` variants of ``planetary_flexible_carrier`` (the
   Craig-Bampton reduced carrier), analysis ``modes`` (first 10 elastic frequencies), varying
   ``stages[0].carrier.component.cheek_thickness`` 10-20 mm (``--vary thickness``: each
   variant a new mesh, FE model and reduction) or ``stages[0].carrier.flex.cutoff_hz``
   4-12 kHz (``--vary cutoff``: the same mesh, a new reduction each). Each engine gets its
   own fresh cache folder (``cache_dir``), so every reduction is built. Wall time, the sum of
   the rows' own ``time_s``, the speed-up (serial wall / this wall), the variants whose result
   columns are not bitwise those of the serial run, the largest ``|f - f_serial|`` over every
   variant and kept frequency (and relative to f), and how many of the meshes cached by both
   runs differ in content (gmsh's mesh of a component is not bit-reproducible from one run to
   the next: a few node coordinates may differ in their last bits, and the frequencies then
   at round-off level); errors = rows with ``status = "error"``. Sizes: the shipped scene's
   carrier FE DOFs -> reduced DOFs and the model's DOFs (its first variant may differ).
   The local engine starts its workers without the Dask nanny's ``MALLOC_TRIM_THRESHOLD_``
   (:mod:`assembly.app.study.engine`); with it, 2 workers took 0.70x the serial time.
2. **reductions reused, cold vs warm**: the same study run again on each engine's now-warm
   cache folder (new worker processes; in this process the memoised FE models are dropped
   first): per run the reductions built and reused (sums of the rows' ``reductions_built``,
   ``reductions_reused``) and the wall time, cold and warm.
3. **per-variant overhead of the engine**: ``--rigid-variants`` variants of the rigid
   ``lin_parker_n4`` (``stages[0].planets.bearing.k_radial`` 1e7-1e9 N/m, log spaced,
   analysis ``modes``). A row's ``time_s`` is the variant's own work inside
   :func:`assembly.app.study.run.run_variant`; the engine's overhead per variant is

   - serial: ``(wall - sum(time_s)) / n``;
   - local, w workers (w = min(workers, n)): ``(wall - sum(time_s) / w) / n``, "incl.
     start-up": the cluster's start-up and close are in ``wall``; "excl. start-up":
     ``(wall - fixed - sum(time_s) / w) / n`` with ``fixed`` the engine's fixed cost, measured
     separately as the wall time of a 1-variant local study less that variant's ``time_s``
     (cluster start-up, the workers' first imports, close). ``sum(time_s) / w`` is the time of
     a perfectly balanced split: imbalance between workers counts as overhead.

Memory: peak resident memory of this (client) process so far, ``getrusage``, after each run
(the local runs go first, so their figure is the client's own, before any serial run), and
of each worker process (``VmHWM`` of ``/proc/PID/status`` of the row's ``pid``, read when its
row arrives; the largest worker is printed). The machine (cores, load average) is printed
with the tables. The sparse backend is loaded (``machine()``) before any run, so the one BLAS
thread that :func:`assembly.app.study.run.run_variant` holds applies to it in a serial run too.
"""
from __future__ import annotations

import argparse
import logging
import sys
import tempfile
import time
from pathlib import Path

from .drivetrain import machine, peak_rss_mb

log = logging.getLogger(__name__)

FLEX_SCENE = "planetary_flexible_carrier"
RIGID_SCENE = "lin_parker_n4"
#: --vary: the parameter of the flexible study and its range [start, stop] (SI: m, Hz)
VARY = {"thickness": ("stages[0].carrier.component.cheek_thickness", 0.010, 0.020),
        "cutoff": ("stages[0].carrier.flex.cutoff_hz", 4000.0, 12000.0)}
RIGID_PATH, RIGID_RANGE = "stages[0].planets.bearing.k_radial", (1.0e7, 1.0e9)
KEEP_MODES = 10


def study_file(folder: Path, name: str, scene: str, path: str, key: str, start: float, stop: float, n: int):
    """Write and read a ``modes`` study of ``scene`` varying ``path`` (``key`` = range or
    log_range) over n values; the :class:`assembly.app.study.file.Study`."""
    from ..study.file import read_study
    f = Path(folder) / f"{name}.toml"
    f.write_text(f'name = "{name}"\nscene = "{scene}"\nanalysis = "modes"\n\n[keep]\nmodes = {KEEP_MODES}\n\n'
                 f'[[parameters]]\npath = "{path}"\n{key} = [{start!r}, {stop!r}, {n}]\n', encoding="utf-8")
    return read_study(f)


def worker_hwm_mb(pid: int) -> float | None:
    """Peak resident memory (MB) of process ``pid`` so far (Linux ``VmHWM``), None if unreadable."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


def timed_run(study, mode: str, workers: int | None, cache_dir: str | None) -> dict:
    """Run ``study``: its rows, wall time, sums of the run columns and peak memory."""
    from ...model.components import forget_fe_models
    from ..study.engine import run_study
    if mode == "serial":
        forget_fe_models()                           # nothing memoised in this process
    hwm: dict = {}

    def tick(row):
        if mode != "serial" and "pid" in row:
            m = worker_hwm_mb(row["pid"])
            if m is not None:
                hwm[row["pid"]] = max(hwm.get(row["pid"], 0.0), m)
    t0 = time.perf_counter()
    rows = run_study(study, mode=mode, workers=workers, cache_dir=cache_dir, tick=tick)
    wall = time.perf_counter() - t0
    return dict(mode=mode, workers=1 if mode == "serial" else min(workers, len(rows)), rows=rows, wall=wall,
                work=sum(r.get("time_s", 0.0) for r in rows), n=len(rows),
                errors=sum(r["status"] != "ok" for r in rows),
                built=sum(r.get("reductions_built", 0) for r in rows),
                reused=sum(r.get("reductions_reused", 0) for r in rows),
                pids=len({r["pid"] for r in rows if "pid" in r}),
                client_mb=peak_rss_mb(), worker_mb=max(hwm.values(), default=None))


def compare_rows(rows: list, ref: list) -> dict:
    """How ``rows`` differ from ``ref`` (the same variants): ``differ``, the variants with a
    result column (every column but the run columns) not bitwise equal; ``abs``, ``rel``, the
    largest ``|f - f_ref|`` (Hz) and ``|f - f_ref| / f_ref`` over the frequency columns."""
    from ..study.run import RUN_COLUMNS
    out = {"differ": abs(len(rows) - len(ref)), "abs": 0.0, "rel": 0.0}
    for r, q in zip(rows, ref):
        a = {k: v for k, v in r.items() if k not in RUN_COLUMNS}
        b = {k: v for k, v in q.items() if k not in RUN_COLUMNS}
        out["differ"] += a != b
        keys = [k for k in a if k.endswith("_hz") and k in b]
        if set(keys) != {k for k in b if k.endswith("_hz")}:
            out["abs"] = out["rel"] = float("inf")
        for k in keys:
            d = abs(float(a[k]) - float(b[k]))
            out["abs"] = max(out["abs"], d)
            out["rel"] = max(out["rel"], d / abs(float(b[k])) if b[k] else d)
    return out


def same_text(c: dict, n: int) -> str:
    return "identical" if not c["differ"] else f"{c['differ']} of {n} variants differ"


def mesh_hashes(folder) -> dict:
    """{mesh file name: SHA-256 of its content} of the meshes cached in ``folder``."""
    import hashlib
    return {f.name: hashlib.sha256(f.read_bytes()).hexdigest() for f in sorted(Path(folder).glob("*.msh"))}


def unlike(hashes: dict, ref: dict) -> str:
    """``k of n``: the meshes of ``hashes`` also in ``ref`` whose content differs."""
    common = [k for k in hashes if k in ref]
    return f"{sum(hashes[k] != ref[k] for k in common)} of {len(common)}"


def flexible_sizes(scene_name: str, cache_dir: str) -> str:
    """``carrier FE -> reduced DOFs; model DOFs`` of the shipped scene, from the cache at ``cache_dir``."""
    from fe_components.meshing import cache_root

    from ...model.assemble import assemble
    from ...scene.schema import load_scene
    with cache_root(cache_dir):
        m = assemble(load_scene(scene_name))
    flex = [f"{b} {m.bodies[b].info.get('n_full_dofs')} -> {m.bodies[b].ndof}"
            for b in m.bodies if getattr(m.bodies[b], "flexible", False)]
    return f"{'; '.join(flex)}; model {m.K.shape[0]} DOFs"


def _mb(x) -> str:
    return "" if x is None else f"{x:.0f}"


def print_flexible(runs: dict, sizes: str, vary: str, out) -> None:
    serial = runs["serial", "cold"]
    print("| engine | workers (processes) | variants | wall [s] | sum of time_s [s] | speed-up vs serial | "
          "result columns vs serial | max abs diff of frequencies [Hz] (relative) | cached meshes unlike serial's | "
          "errors | client peak RSS [MB] | worker peak RSS, largest [MB] |", file=out)
    print("|---|---|---|---|---|---|---|---|---|---|---|---|", file=out)
    for key, label in ((("serial", "cold"), "serial"), (("local", "cold"), "local")):
        r, mode = runs[key], key[0]
        c = compare_rows(r["rows"], serial["rows"])
        print(f"| {label} | {r['workers']} ({r['pids']}) | {r['n']} | {r['wall']:.2f} | {r['work']:.2f} | "
              f"{serial['wall'] / r['wall']:.2f} | {same_text(c, r['n'])} | {c['abs']:.3g} ({c['rel']:.1e}) | "
              f"{unlike(r['meshes'], serial['meshes'])} | "
              f"{r['errors']} | {_mb(r['client_mb'])} | {_mb(r['worker_mb']) if mode != 'serial' else '(client)'} |",
              file=out)
    print(f"\nScene {FLEX_SCENE} as shipped: {sizes}. Varied: {VARY[vary][0]}.", file=out)
    print("Cached meshes unlike serial's: the meshes of the same name (same component parameters) in this run's "
          "cache folder whose content (SHA-256) differs from the serial run's; a mesh from the committed reference "
          "meshes (meshes/ref) is not in either folder. Results depend on the mesh's every bit.", file=out)


def print_reuse(runs: dict, out) -> None:
    print("| engine | workers | variants | reductions built, cold | reused, cold | wall cold [s] | "
          "reductions built, warm | reused, warm | wall warm [s] | cold / warm |", file=out)
    print("|---|---|---|---|---|---|---|---|---|---|", file=out)
    for mode in ("serial", "local"):
        c, w = runs[mode, "cold"], runs[mode, "warm"]
        print(f"| {mode} | {c['workers']} | {c['n']} | {c['built']} | {c['reused']} | {c['wall']:.2f} | "
              f"{w['built']} | {w['reused']} | {w['wall']:.2f} | {c['wall'] / w['wall']:.1f} |", file=out)


def print_overhead(runs: dict, fixed: float, out) -> None:
    print("| engine | workers | variants | wall [s] | sum of time_s [s] | mean time_s [ms] | "
          "overhead per variant, incl. start-up [ms] | excl. start-up [ms] | engine fixed cost [s] | "
          "speed-up vs serial | errors | worker peak RSS, largest [MB] |", file=out)
    print("|---|---|---|---|---|---|---|---|---|---|---|---|", file=out)
    serial = runs["serial"]
    for mode in ("serial", "local"):
        r = runs[mode]
        incl = (r["wall"] - r["work"] / r["workers"]) / r["n"]
        f = fixed if mode == "local" else 0.0
        excl = (r["wall"] - f - r["work"] / r["workers"]) / r["n"]
        print(f"| {mode} | {r['workers']} | {r['n']} | {r['wall']:.2f} | {r['work']:.2f} | "
              f"{1e3 * r['work'] / r['n']:.1f} | {1e3 * incl:.1f} | {1e3 * excl:.1f} | "
              f"{f'{fixed:.2f}' if mode == 'local' else '0'} | {serial['wall'] / r['wall']:.2f} | {r['errors']} | "
              f"{_mb(r['worker_mb']) if mode != 'serial' else '(client)'} |", file=out)
    c = compare_rows(runs["local"]["rows"], serial["rows"])
    print(f"\nResult columns, local vs serial: {same_text(c, serial['n'])} "
          f"(max abs diff of frequencies {c['abs']:.3g} Hz). Engine fixed cost: wall of a 1-variant local study "
          f"less its time_s.", file=out)


def main(argv=None, out=None) -> int:
    out = sys.stdout if out is None else out
    p = argparse.ArgumentParser(prog="flexgear bench study", description=__doc__.split("\n\n")[0])
    p.add_argument("--variants", type=int, default=20, help="variants of the flexible study")
    p.add_argument("--vary", choices=sorted(VARY), default="thickness",
                   help="the flexible study's parameter: carrier cheek thickness (new mesh + reduction) or "
                        "the carrier's cutoff_hz (new reduction)")
    p.add_argument("--rigid-variants", type=int, default=200, help="variants of the rigid (overhead) study")
    p.add_argument("--workers", type=int, default=2, help="worker processes of the local cluster")
    p.add_argument("--no-flexible", action="store_true", help="skip the flexible study (tables 1 and 2)")
    p.add_argument("--no-rigid", action="store_true", help="skip the rigid study (table 3)")
    p.add_argument("--quick", action="store_true", help="small sizes: 4 flexible, 20 rigid variants")
    a = p.parse_args(argv)
    if a.quick:
        a.variants, a.rigid_variants = 4, 20
    if a.variants < 1 or a.rigid_variants < 1 or a.workers < 1:
        p.error("--variants, --rigid-variants and --workers must be >= 1")
    print(f"`flexgear bench study`: {a.workers} workers; {machine()}", file=out)
    with tempfile.TemporaryDirectory(prefix="flexgear-bench-study-") as tmp:
        tmp = Path(tmp)
        rigid = None
        if not a.no_rigid:                # first: the client's peak RSS is not yet the serial flexible run's
            study = study_file(tmp, "rigid", RIGID_SCENE, RIGID_PATH, "log_range", *RIGID_RANGE, a.rigid_variants)
            one = study_file(tmp, "one", RIGID_SCENE, RIGID_PATH, "log_range", RIGID_RANGE[0], RIGID_RANGE[0], 1)
            r1 = timed_run(one, "local", a.workers, None)
            fixed = r1["wall"] - r1["work"]
            rigid = {"local": timed_run(study, "local", a.workers, None),
                     "serial": timed_run(study, "serial", None, None)}
        if not a.no_flexible:
            path, lo, hi = VARY[a.vary]
            study = study_file(tmp, "flexible", FLEX_SCENE, path, "range", lo, hi, a.variants)
            runs, caches = {}, {}
            for mode in ("local", "serial"):               # local first: the client's own memory
                caches[mode] = str(tmp / f"cache-{mode}")
                for state in ("cold", "warm"):
                    runs[mode, state] = timed_run(study, mode, a.workers, caches[mode])
                runs[mode, "cold"]["meshes"] = mesh_hashes(caches[mode])
            sizes = flexible_sizes(FLEX_SCENE, caches["serial"])
            print(f"\nFlexible study: {a.variants} variants of {FLEX_SCENE}, modes (first {KEEP_MODES}), cold caches",
                  file=out)
            print_flexible(runs, sizes, a.vary, out)
            print("\nReductions reused, cold vs warm (the same caches again)", file=out)
            print_reuse(runs, out)
        if rigid is not None:
            print(f"\nPer-variant overhead: {a.rigid_variants} variants of {RIGID_SCENE} (rigid), modes "
                  f"(first {KEEP_MODES}), {RIGID_PATH} log spaced {RIGID_RANGE[0]:g}-{RIGID_RANGE[1]:g}", file=out)
            print_overhead(rigid, fixed, out)
    print(f"\nmachine after: {machine()}", file=out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
