"""Benchmark (not a test): reduced flexible assemblies against the unreduced full-FE model.

For each demo scene: the full-FE reference (every FE DOF of every flexible body in one
sparse eigenproblem), then Craig-Bampton reductions with a given number of fixed-interface
modes per body, or with the cutoff at a multiple of the scene's band. Columns: modes per
body, coupled DOFs, max and mean relative error of the first 20 elastic coupled
frequencies (and of those inside the band), time to reduce (fresh cache), time to solve,
cold and warm-cache totals vs full-FE time, a design study of bearing variants, peak memory. ``flexgear bench flex [--scene S] [--modes 0,4,8,...]
[--factors 1,1.5,2,3]``.
"""
from __future__ import annotations

import argparse
import contextlib
import dataclasses
import resource
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from ...analysis.modal import solve_modes
from ...model.assemble import assemble, build_body_models
from ...model.components import CacheDirs, forget_fe_models
from ...scene.cutoffs import CB_CUTOFF_FACTOR
from ...scene.schema import load_scene
from ...scene.tables import FlexOptions, scale_bearings


def with_flex_options(scene, **kw):
    """``scene`` expanded, each flexible body's FlexOptions replaced by ``kw`` (n_modes,
    cutoff_hz, residual_vectors): the reduction settings a bench row varies."""
    sc = scene.expanded()
    bodies = []
    for b in sc.bodies:
        if b.fidelity == "flexible":
            b = dataclasses.replace(b, flex=dataclasses.replace(b.flex or FlexOptions(), **kw))
        bodies.append(b)
    return dataclasses.replace(sc, bodies=tuple(bodies))


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


@contextlib.contextmanager
def empty_superelement_cache():
    """Cache folders whose superelement folder is fresh (temporary) for the block's
    duration; meshes stay in the default cache."""
    with tempfile.TemporaryDirectory() as folder:
        yield CacheDirs(superelements=Path(folder))


def _variants(scene, n: int):
    """``n`` bearing-stiffness variants (all bearings x 0.25 ... x 4, log-spaced): the kind
    of design study (Peeters Fig. 11a) that changes springs and leaves every body alone."""
    return [scale_bearings(scene, float(f)) for f in np.logspace(np.log10(0.25), np.log10(4.0), n)]


@dataclasses.dataclass(frozen=True)
class FullFE:
    """A scene's full-FE reference: its modes (``n_cmp + 12`` of them), DOFs, and the times
    [s] to build the model (FE assembly included) and to build and solve it."""
    modes: object
    dofs: int
    build_s: float
    total_s: float


def full_fe_reference(scene, n_cmp: int = 20) -> FullFE:
    """The full-FE reference :func:`run` compares against, from FE models assembled afresh."""
    forget_fe_models()
    t0 = time.perf_counter()
    full_model = assemble(scene, full_fe=True)
    t_build = time.perf_counter() - t0
    ref = solve_modes(full_model, n_modes=n_cmp + 12)
    return FullFE(ref, int(full_model.K.shape[0]), t_build, time.perf_counter() - t0)


def run(scene_name: str, modes, factors, n_cmp: int = 20, n_variants: int = 10, out=sys.stdout,
        plain_modes=(), plain_factors=(), reference: FullFE | None = None) -> list:
    """Benchmark one scene; prints a table and returns its rows (dicts, times in s).

    Every time includes the component FE assembly from the on-disk mesh cache (the FE
    models are forgotten before each cold case), so full FE and reduced start equal:
    - ``cold``: empty superelement cache: FE assembly, coupling, reduction, assembly, solve;
    - ``warm``: the same scene again with its reductions in the cache (no FE needed);
    - ``study``: ``n_variants`` bearing-stiffness variants at the default cutoff: full FE
      assembles its FE models once and re-solves every variant; the reduced model reduces
      once (cold) and solves every variant from the cache.
    ``reference``: the scene's :func:`full_fe_reference` with this ``n_cmp`` when already
    solved (a test's); else it is solved here.
    """

    scene = load_scene(scene_name)
    band = scene.band
    full = reference if reference is not None else full_fe_reference(scene, n_cmp)
    ref, t_build, t_full = full.modes, full.build_s, full.total_s
    f_ref = ref.frequencies_hz[ref.n_rigid:ref.n_rigid + n_cmp]
    in_band = f_ref < band
    rows = []
    print(f"\n{scene.name}: full FE {full.dofs} DOFs, build {t_build:.1f} s (FE assembly "
          f"included), solve {t_full - t_build:.1f} s, total {t_full:.1f} s, max residual "
          f"{ref.max_residual:.1e}; band {band:.0f} Hz ({int(in_band.sum())} of the first {n_cmp} "
          f"elastic modes inside)", file=out)
    print(f"{'selection':>14} {'DOFs':>6} {'max err %':>9} {'mean err %':>10} {'band max %':>10} "
          f"{'reduce s':>8} {'solve s':>7} {'cold s':>7} {'speed-up':>8} {'warm s':>7} {'speed-up':>8} "
          f"{'peak MB':>8}", file=out)
    cases = ([("n_modes", m, True) for m in modes] + [("cutoff", f, True) for f in factors]
             + [("n_modes", m, False) for m in plain_modes] + [("cutoff", f, False) for f in plain_factors])
    for kind, val, rv in cases:
        with empty_superelement_cache() as caches:
            sc = with_flex_options(scene, n_modes=val, cutoff_hz=None, residual_vectors=rv) \
                if kind == "n_modes" else \
                with_flex_options(scene, n_modes=None, cutoff_hz=val * band, residual_vectors=rv)
            forget_fe_models()
            t1 = time.perf_counter()
            bodies = build_body_models(sc.expanded(), caches=caches)
            t_red = time.perf_counter() - t1
            m = assemble(sc, bodies=bodies)
            r = solve_modes(m)
            t_tot = time.perf_counter() - t1
            forget_fe_models()
            t2 = time.perf_counter()
            r_warm = solve_modes(assemble(sc, bodies=build_body_models(sc.expanded(), caches=caches)))
            t_warm = time.perf_counter() - t2
            assert np.allclose(r_warm.frequencies_hz, r.frequencies_hz, rtol=1e-9, atol=1e-6)
        f = r.frequencies_hz[r.n_rigid:r.n_rigid + n_cmp]
        k = min(len(f), len(f_ref))
        err = np.abs(f[:k] / f_ref[:k] - 1) * 100
        band_err = err[in_band[:k]].max() if in_band[:k].any() else float("nan")
        label = (f"{val} modes" if kind == "n_modes" else f"cutoff {val:g}xband") + (" +rv" if rv else " plain")
        row = dict(scene=scene.name, selection=label, dofs=int(m.K.shape[0]), max_err_pct=float(err.max()),
                   mean_err_pct=float(err.mean()), band_max_err_pct=float(band_err), reduce_s=t_red,
                   solve_s=r.solve_time_s, total_s=t_tot, warm_s=t_warm, full_fe_s=t_full,
                   peak_mb=_peak_mb())
        rows.append(row)
        print(f"{label:>14} {row['dofs']:>6} {row['max_err_pct']:>9.3f} {row['mean_err_pct']:>10.3f} "
              f"{row['band_max_err_pct']:>10.3f} {t_red:>8.1f} {r.solve_time_s:>7.3f} {t_tot:>7.1f} "
              f"{t_full / t_tot:>7.1f}x {t_warm:>7.2f} {t_full / t_warm:>7.0f}x {row['peak_mb']:>8.0f}",
              file=out)
        out.flush()
    if n_variants:
        rows.append(_study(scene, band, n_variants, CB_CUTOFF_FACTOR, n_cmp, out))
    return rows


def _study(scene, band, n, factor, n_cmp, out) -> dict:
    """Design study: ``n`` bearing variants, full FE vs reduced (default cutoff)."""
    variants = _variants(scene, n)
    forget_fe_models()
    t0 = time.perf_counter()
    ref = []
    for v in variants:   # keep the frequencies only: ten full-FE results held 3 GB
        r = solve_modes(assemble(v, full_fe=True), n_modes=n_cmp + 12)
        ref.append(r.frequencies_hz[r.n_rigid:r.n_rigid + n_cmp])
    t_full = time.perf_counter() - t0
    errs = []
    with empty_superelement_cache() as caches:
        forget_fe_models()
        t1 = time.perf_counter()
        for v, f0 in zip(variants, ref):
            sc = with_flex_options(v, n_modes=None, cutoff_hz=factor * band)
            r = solve_modes(assemble(sc, bodies=build_body_models(sc.expanded(), caches=caches)))
            f = r.frequencies_hz[r.n_rigid:r.n_rigid + n_cmp]
            k = min(len(f), len(f0))
            sel = f0[:k] < band
            if sel.any():
                errs.append(float(np.max(np.abs(f[:k][sel] / f0[:k][sel] - 1)) * 100))
        t_red = time.perf_counter() - t1
    row = dict(scene=scene.name, selection=f"study: {n} bearing variants", dofs=0, max_err_pct=float("nan"),
               mean_err_pct=float("nan"), band_max_err_pct=max(errs) if errs else float("nan"),
               reduce_s=float("nan"), solve_s=float("nan"), total_s=t_red, warm_s=float("nan"),
               full_fe_s=t_full, peak_mb=_peak_mb())
    print(f"design study, {n} bearing-stiffness variants (x0.25 ... x4), cutoff {factor:g} x band: "
          f"full FE {t_full:.1f} s, reduced {t_red:.1f} s (one reduction, then the cache): "
          f"{t_full / t_red:.1f}x; max error in band over all variants {row['band_max_err_pct']:.3f} %",
          file=out)
    out.flush()
    return row


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="flexgear bench flex", description=__doc__.split("\n")[0])
    p.add_argument("--scene", action="append", help="scene(s) (default: both flexible demo scenes)")
    p.add_argument("--modes", default="0,4,8,16,32", help="fixed-interface modes per body to try")
    p.add_argument("--factors", default="1,1.5,2,4", help="cutoff factors (x band), residual vectors on")
    p.add_argument("--plain-modes", default="0,8,32",
                   help="fixed-interface modes per body for plain Craig-Bampton (no residual vectors)")
    p.add_argument("--plain-factors", default="1.5,4",
                   help="cutoff factors (x band) for plain Craig-Bampton (no residual vectors)")
    p.add_argument("--variants", type=int, default=10,
                   help="bearing-stiffness variants in the design-study row (0: skip)")
    p.add_argument("--out", help="folder for speed_vs_error.png and speed_vs_error.csv")
    a = p.parse_args(argv)
    scenes = a.scene or ["hs_parallel_stage.toml", "planetary_flexible_carrier.toml"]
    modes = [int(x) for x in a.modes.split(",") if x]
    factors = [float(x) for x in a.factors.split(",") if x]
    plain = [float(x) for x in a.plain_factors.split(",") if x]
    plain_modes = [int(x) for x in a.plain_modes.split(",") if x]
    rows = []
    for s in scenes:
        rows += run(s, modes, factors, n_variants=a.variants, plain_modes=plain_modes, plain_factors=plain)
    if a.out:
        write_plot(rows, a.out)
    return 0


def write_plot(rows: list, out_dir) -> None:
    """Speed vs error of the flexible model against mode count (PNG) and the rows (CSV)."""
    import csv
    import os

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "speed_vs_error.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for scene in dict.fromkeys(r["scene"] for r in rows):
        for tag, style in ((" +rv", "o-"), (" plain", "s--")):
            rs = [r for r in rows if r["scene"] == scene and r["selection"].endswith("modes" + tag)]
            if not rs:
                continue
            n = [int(r["selection"].split()[0]) for r in rs]
            axes[0].semilogy(n, [max(r["band_max_err_pct"], 1e-6) for r in rs], style, label=scene + tag)
            axes[1].loglog([r["total_s"] for r in rs], [max(r["max_err_pct"], 1e-6) for r in rs], style,
                           label=scene + tag)
            axes[1].axvline(rs[0]["full_fe_s"], ls=":", color=axes[1].lines[-1].get_color())
    axes[0].axhline(0.5, ls="--", color="k", lw=0.8)
    axes[0].set(xlabel="fixed-interface modes per flexible body", ylabel="max error in band vs full FE [%]",
                title="accuracy against mode count")
    axes[1].set(xlabel="time to reduce + solve [s] (dotted: full FE)", ylabel="max error, first 20 modes [%]",
                title="speed vs error")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    tmp = out / ".speed_vs_error.png.tmp"
    fig.savefig(tmp, dpi=120, format="png")
    plt.close(fig)
    os.replace(tmp, out / "speed_vs_error.png")


if __name__ == "__main__":
    sys.exit(main())
