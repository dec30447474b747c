"""Benchmark (not a test): frequency response of a whole drivetrain, reduced vs naive.

``flexgear bench frf [--scene nrel5mw_flexible.toml] [--points 10000] [--fmin 0.5]
[--fmax 100] [--full-points 2] [--no-full] [--input IN]`` prints one Markdown table (times in s, peak
resident memory in MB: of the process after the reduced rows, then after the unreduced
model) for a unit torque on the generator (``role = "generator"``) to every
internal load of the model: each shaft element's torque, each mesh force, each bearing force
and moment in every direction with a spring or damper (``torque:``/``force:`` outputs of
:mod:`assembly.dynamics.frf_channels`), at ``--points`` frequencies spaced linearly:

- **modal** (default cutoff, 30 x fmax, residual correction) and **modal, every mode**: the
  FRF alone on the solved modes, then with the modal solve (``solve_modes``) included;
- **direct (naive)**: one dense LU of ``K - w^2 M + i w C`` of the reduced model per point;
- **direct, unreduced**: the same per point on the unreduced model (every FE DOF of the
  flexible bodies, ``assemble(full_fe=True)``) with a sparse LU (a dense matrix would need
  n^2 x 16 bytes, printed); ``--full-points`` points are solved and the time per point is
  scaled to all of them. Its outputs at those points give the reduction's own error.

Errors: the largest ``|H - H_ref|`` over the points and outputs, each output relative to its
peak ``max |H_ref|``; reference the direct solve of the same model (reduced rows) and the
unreduced direct solve (last column).
"""
from __future__ import annotations

import argparse
import logging
import sys
import time

import numpy as np

from .drivetrain import machine, peak_rss_mb

log = logging.getLogger(__name__)


def internal_loads(model) -> list[str]:
    """Every shaft torque, mesh force and bearing force output of ``model``."""
    from ...dynamics.frf_channels import bearing_directions
    out = ["torque:" + e.name for e in model.elements if e.kind == "shaft"]
    out += ["force:" + e.name for e in model.elements if e.kind == "mesh"]
    out += ["force:" + e.name for e in model.elements if e.kind == "bearing" and bearing_directions(model, e)]
    return out


def scaled_error(r, ref) -> float:
    """max |H - H_ref| over points and outputs, relative to the largest |H_ref| of any output
    of the same unit (the size of the model's forces, or of its moments): outputs that vanish
    by symmetry (an axial bearing force under a pure torque) are judged by the loads of their
    kind, not by their own round-off."""
    units = {k: ref.units.get(k) or r.units.get(k) for k in ref.outputs}
    peak = {u: max(np.max(np.abs(ref.outputs[k])) for k in ref.outputs if units[k] == u) for u in set(units.values())}
    return max(float(np.max(np.abs(r.outputs[k] - h))) / peak[units[k]] for k, h in ref.outputs.items())


def worst_own_peak(r, ref) -> tuple[str, float, float]:
    """(output, its max |H - H_ref| / its own peak, that peak / the largest of its unit)."""
    err = {k: float(np.max(np.abs(r.outputs[k] - h)) / np.max(np.abs(h))) for k, h in ref.outputs.items()}
    k = max(err, key=err.get)
    unit = r.units.get(k)
    top = max(np.max(np.abs(ref.outputs[j])) for j in ref.outputs if r.units.get(j) == unit)
    return k, err[k], float(np.max(np.abs(ref.outputs[k])) / top)


def _generator(scene) -> str:
    from ...analysis.drivetrain import chain_ends
    return chain_ends(scene)[1]


def direct_unreduced(scene, source: str, outputs: list, f: np.ndarray):
    """(FRF at ``f``, build s, s per point, DOFs) of the unreduced model by a sparse LU per point."""
    import scipy.sparse.linalg as spla

    from ...dynamics.frf import FRF
    from ...dynamics.frf_channels import input_channel, output_channels, output_rows
    from ...model.assemble import assemble
    from ...model.damping import damping_matrix
    t0 = time.perf_counter()
    model = assemble(scene, full_fe=True)
    if scene.damping is not None and (scene.damping.modal or scene.damping.rayleigh_alpha):
        raise ValueError("the unreduced direct solve takes element dampers and Rayleigh beta only")
    K, M = model.K.tocsc(), model.M.tocsc()
    C = damping_matrix(model).tocsc()
    if scene.damping is not None and scene.damping.rayleigh_beta:
        C = C + scene.damping.rayleigh_beta * K
    src = input_channel(model, source)
    outs = [c for name in outputs for c in output_channels(model, name)]
    Ok, Oc = output_rows(outs)
    build = time.perf_counter() - t0
    H = np.empty((len(f), len(outs)), complex)
    t1 = time.perf_counter()
    b = src.k_row.astype(complex)
    resid = 0.0
    for j, fj in enumerate(f):
        w = 2 * np.pi * fj
        A = (K - w * w * M + 1j * w * C).tocsc()
        # SuperLU with a symmetric fill-reducing ordering (the default COLAMD took 488 s and 14 GB
        # per point here, this one, without pivoting, 23 s and 6 GB); the residual below says what it cost
        x = spla.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                      options=dict(SymmetricMode=True)).solve(b)
        resid = max(resid, float(np.linalg.norm(A @ x - b) / np.linalg.norm(b)))
        H[j] = Ok @ x + 1j * w * (Oc @ x)
    per = (time.perf_counter() - t1) / len(f)
    log.info("unreduced direct solve: relative residual %.2e", resid)
    r = FRF(source, f, {c.name: H[:, j] for j, c in enumerate(outs)}, {c.name: c.unit for c in outs}, method="direct")
    return r, build, per, int(K.shape[0]), resid


def main(argv=None, out=None) -> int:
    from ...analysis.modal import solve_modes
    from ...dynamics.frf import MODAL_CUTOFF_FACTOR, frequency_response
    from ...model.assemble import assemble
    from ...scene.schema import load_scene

    out = out or sys.stdout
    p = argparse.ArgumentParser(prog="flexgear bench frf", description=__doc__.split("\n\n")[0])
    p.add_argument("--scene", default="nrel5mw_flexible.toml")
    p.add_argument("--points", type=int, default=10000)
    p.add_argument("--fmin", type=float, default=0.5, help="Hz")
    p.add_argument("--fmax", type=float, default=100.0, help="Hz")
    p.add_argument("--full-points", type=int, default=2, help="points solved on the unreduced model")
    p.add_argument("--no-full", action="store_true", help="skip the unreduced model")
    p.add_argument("--input", default=None, help="input (default torque:GENERATOR, the body of role generator)")
    a = p.parse_args(argv)
    scene = load_scene(a.scene)
    f = np.linspace(a.fmin, a.fmax, a.points)
    source = a.input or f"torque:{_generator(scene)}"
    t0 = time.perf_counter()
    model = assemble(scene)
    t_asm = time.perf_counter() - t0
    outputs = internal_loads(model)
    t0 = time.perf_counter()
    res = solve_modes(model)
    t_modes = time.perf_counter() - t0
    rows = []
    for label, cutoff in ((f"modal, modes to {MODAL_CUTOFF_FACTOR:g} x fmax", MODAL_CUTOFF_FACTOR * a.fmax),
                          ("modal, every mode", np.inf)):
        rows.append((label, cutoff, frequency_response(model, source, outputs, f, result=res, modes_hz=cutoff)))
    t0 = time.perf_counter()
    ref = frequency_response(model, source, outputs, f, method="direct", result=res)
    t_direct = time.perf_counter() - t0
    n_rows = len(rows[0][2].outputs)
    print(f"`flexgear bench frf`: {scene.name}; {source} -> {n_rows} internal loads "
          f"({len(outputs)} names), {a.points} points {a.fmin:g}-{a.fmax:g} Hz; {machine()}", file=out)
    print(f"reduced model {model.K.shape[0]} DOFs, assembled in {t_asm:.2f} s, all {len(res.frequencies_hz)} modes "
          f"in {t_modes:.3f} s (highest {res.frequencies_hz[-1]:.4g} Hz)\n", file=out)
    rss_reduced = peak_rss_mb()                                        # before the unreduced model
    full = None
    if not a.no_full:
        fs = np.linspace(a.fmin, a.fmax, a.full_points + 2)[1:-1]
        full = direct_unreduced(scene, source, outputs, fs)
    print("| method | DOFs | time, FRF only [s] | with the modal solve [s] | error vs direct (reduced) | "
          "error vs unreduced | peak RSS [MB] |", file=out)
    print("|---|---|---|---|---|---|---|", file=out)
    for label, cutoff, r in rows:
        err_full = ""
        if full is not None:                                         # this row's method at the unreduced points
            at = frequency_response(model, source, outputs, full[0].frequency_hz, result=res, modes_hz=cutoff)
            err_full = f"{scaled_error(at, full[0]):.2e} (at {a.full_points} points)"
        print(f"| {label} | {model.K.shape[0]} | {r.time_s:.3f} | {r.time_s + t_modes:.3f} | "
              f"{scaled_error(r, ref):.2e} | {err_full} | {rss_reduced:.0f} |", file=out)
    print(f"| direct (naive): dense LU per point, reduced | {model.K.shape[0]} | {t_direct:.2f} | "
          f"{t_direct:.2f} | reference | | {rss_reduced:.0f} |", file=out)
    if full is not None:
        r_full, build, per, n, resid = full
        print(f"| direct, unreduced: sparse LU per point ({a.full_points} solved, x {a.points}) | {n} | "
              f"{per * a.points:.4g} (= {per:.3g} per point; build {build:.1f}) | | | reference | "
              f"{peak_rss_mb():.0f} |", file=out)
        print(f"\nUnreduced: largest relative residual |A x - b| / |b| of its solves {resid:.1e}. A dense solve "
              f"of the unreduced matrix would need {n * n * 16 / 1e9:.3g} GB for the matrix alone.", file=out)
    k, e, size = worst_own_peak(rows[0][2], ref)
    print(f"\nErrors: largest |H - H_ref| relative to the largest response of the same unit (forces, moments). "
          f"Against each output's own peak the worst is {k}: {e:.2e}, an output {size:.1e} x the size of its "
          "kind (it vanishes by symmetry; its value is round-off of the loads).", file=out)
    speed = t_direct / rows[0][2].time_s
    print(f"\nModal (default cutoff) vs naive dense on the reduced model: {speed:.0f}x faster.", file=out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
