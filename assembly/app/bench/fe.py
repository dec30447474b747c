"""Benchmark: meshing + assembly time, peak memory and h-convergence of the components.

Usage (wired as ``flexgear bench fe``)::

    python -m assembly.app.bench.fe                       # quick: 3 sizes, finest ~60k DOFs
    python -m assembly.app.bench.fe --target-dofs 300000  # README table: 3 sizes, finest ~300k DOFs (P2)

Frequencies are computed for cases up to ``--max-modal-dofs`` (default 120k):
the sparse Cholesky of K - sigma M dominates above that (CHOLMOD on the
system BLAS).

Each case runs in a fresh process (spawned) with an empty temporary mesh cache,
so that "mesh" is a real gmsh run and "peak RSS" (ru_maxrss after assembly)
is the case's own.  The first six elastic free-free frequencies (Hz) give the
h-convergence.  Output: a markdown table on stdout.
"""
from __future__ import annotations

import argparse
import logging
import multiprocessing as mp
import resource
import tempfile
import time

import numpy as np

log = logging.getLogger(__name__)

COMPONENTS = ("pinion", "wheel", "carrier")


def _params(component: str):
    from fe_components import reference as ref

    return {"pinion": ref.PINION_INVOLUTE, "wheel": ref.WHEEL_SMOOTH, "carrier": ref.CARRIER}[component]


def _coarse_size(component: str) -> float:
    from fe_components import reference as ref

    key = {"pinion": "pinion_involute", "wheel": "wheel_smooth", "carrier": "carrier"}[component]
    return ref.CASES[key][1].size


def _run_case(component: str, size: float, order: int, n_modes: int, max_modal_dofs: int, queue) -> None:
    import meshio  # noqa: F401  warm imports, so that the timings below exclude module loading
    import skfem.io.meshio  # noqa: F401

    from cms.eigen import count_rigid_modes, free_free_shift, lowest_modes
    from fe_components.fe_model import build_component
    from fe_components.gmsh_session import gmsh_module
    from fe_components.meshing import MeshOptions
    gmsh_module()

    with tempfile.TemporaryDirectory() as cache:
        model = build_component(_params(component), options=MeshOptions(size=size, order=order), cache_dir=cache)
    model.K  # K and M are assembled on first use: assemble them here, inside the timed assembly
    rss_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: kB
    freqs, t_modes = [], float("nan")
    if n_modes > 0 and model.n_dofs <= max_modal_dofs:
        t0 = time.perf_counter()
        f = lowest_modes(model.K, model.M, 6 + n_modes, sigma=free_free_shift(model.K, model.M)).frequencies_hz
        t_modes = time.perf_counter() - t0
        n_rigid = count_rigid_modes(f)
        if n_rigid != 6:
            log.warning("%s h=%g: %d rigid-body modes (expected 6)", component, size, n_rigid)
        freqs = [float(x) for x in f[6:]]
    queue.put(dict(component=component, size=size, nodes=model.n_nodes, dofs=model.n_dofs,
                   t_mesh=model.timings["mesh"], t_asm=model.timings["assembly"] + model.timings["matrices"], rss_mb=rss_mb,
                   t_modes=t_modes, freqs=freqs))


def run_case(component: str, size: float, order: int = 2, n_modes: int = 6, max_modal_dofs: int = 10**9) -> dict:
    """Mesh + assemble (+ modes) one case in a spawned process; returns its measurements."""
    ctx = mp.get_context("spawn")
    q = ctx.Queue()
    p = ctx.Process(target=_run_case, args=(component, size, order, n_modes, max_modal_dofs, q))
    p.start()
    res = q.get()
    p.join()
    return res


def probe_dofs(component: str, size: float, order: int) -> int:
    """DOFs of the mesh of ``component`` at ``size`` (gmsh run only, no assembly)."""
    from fe_components.meshing import MeshOptions, ensure_mesh, read_mesh

    with tempfile.TemporaryDirectory() as cache:
        raw = read_mesh(ensure_mesh(_params(component), MeshOptions(size=size, order=order), cache))
    return 3 * len(raw.points)


def size_for_dofs(component: str, target: int, order: int, rtol: float = 0.15, max_iter: int = 5) -> float:
    """Mesh size [m] giving about ``target`` DOFs (secant-like updates assuming DOFs ~ h^-3)."""
    h = _coarse_size(component)
    for _ in range(max_iter):
        n = probe_dofs(component, h, order)
        if abs(n / target - 1) < rtol:
            break
        h *= (n / target) ** (1.0 / 3.0)
    return h


def sizes_for(component: str, target_dofs: int, levels: int, order: int) -> list[float]:
    """Mesh sizes [m], geometric from the reference (committed-mesh) size to the size giving ~target_dofs."""
    h0 = _coarse_size(component)
    h1 = size_for_dofs(component, target_dofs, order)
    if h1 >= h0 or levels < 2:
        return [min(h0, h1)]
    return [float(h) for h in h0 * (h1 / h0) ** (np.arange(levels) / (levels - 1))]


HEADER = ("| component | mesh size [mm] | nodes | DOFs | mesh [s] | assembly [s] | mesh+asm [s] "
          "| peak RSS [MB] | modes [s] | first six elastic frequencies [Hz] |\n" + "|" + "---|" * 10)


def format_row(r: dict) -> str:
    f = ", ".join(f"{x:.1f}" for x in r["freqs"]) if r["freqs"] else "-"
    return (f"| {r['component']} | {1e3 * r['size']:.2f} | {r['nodes']} | {r['dofs']} | {r['t_mesh']:.2f} "
            f"| {r['t_asm']:.2f} | {r['t_mesh'] + r['t_asm']:.2f} | {r['rss_mb']:.0f} "
            f"| {r['t_modes']:.1f} | {f} |")


def format_table(rows: list[dict]) -> str:
    return "\n".join([HEADER] + [format_row(r) for r in rows])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="flexgear bench fe", description=__doc__.split("\n")[0])
    ap.add_argument("--components", nargs="+", choices=COMPONENTS, default=list(COMPONENTS))
    ap.add_argument("--target-dofs", type=int, default=60000,
                    help="DOFs of the finest level (README table: 300000)")
    ap.add_argument("--levels", type=int, default=3, help="number of mesh sizes per component")
    ap.add_argument("--order", type=int, choices=(1, 2), default=2)
    ap.add_argument("--modes", type=int, default=6, help="elastic modes per case (0: skip the eigen solve)")
    ap.add_argument("--max-modal-dofs", type=int, default=120000,
                    help="skip the eigen solve above this many DOFs (sparse Cholesky time and memory)")
    args = ap.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    print(HEADER, flush=True)  # benchmark table output, one row per finished case
    for comp in args.components:
        for h in sizes_for(comp, args.target_dofs, args.levels, args.order):
            print(format_row(run_case(comp, h, args.order, args.modes, args.max_modal_dofs)), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
