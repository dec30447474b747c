"""Benchmark (not a test): the user's own STEP carrier against the built-in carrier.

Usage (wired as ``flexgear bench part``)::

    flexgear bench part                          # element size 0.012 m (the scene's)
    flexgear bench part --size 0.015,0.012,0.008 # several element sizes
    flexgear bench part --quick                  # 0.03 m: a smoke run of a few seconds

The cost of a user's part: STEP import + mesh + assemble + couple + reduce of the carrier with
windows of ``planetary_step_carrier.toml`` (``assembly/scenes/parts/carrier_windows.step``,
six cylinder interface rules), against the same steps for the built-in parametric carrier
(:class:`~fe_components.params.CarrierParams`) of ``planetary_flexible_carrier.toml``, its
pins set by the stage (:func:`assembly.scene.planetary.carrier_pins`): two steel carriers of about
the same size (two 15 mm cheeks of 270 mm, the same seats and bores; 17.9 and 15.8 kg).

Both are built at the same element size (P2), each case in a fresh spawned process with an
empty temporary mesh cache, with the scene's flex options (couplings, material, order) and
the scene's reduction: Craig-Bampton with every fixed-interface mode below
``CB_CUTOFF_FACTOR x band_hz`` (1.5 x 3000 Hz = 4500 Hz), residual vectors on, at most
``MAX_MODES`` modes, called as :func:`assembly.model.flexible._reduce` calls it. One more row
builds the STEP carrier again in a fresh process from the mesh cache its cold row filled:
what the mesh cache saves. The superelement cache of a scene run is not used.

Columns (times in s, wall clock): read/import (``part_geometry``: the OpenCASCADE import
of the STEP file and the interface rules on its faces), mesh (gmsh run and the read of the
mesh file; a cache hit reads the file only), assemble (scikit-fem basis, mass properties,
interface node sets, K and M), couple (RBE2 spiders, K_c and M_c), reduce, total, the modes
kept (fixed-interface modes + residual vectors), peak resident memory of the case's process
(MB) and the first three fixed-interface frequencies (Hz) as a sanity check. Output: a
Markdown table with its footnotes on stdout.
"""
from __future__ import annotations

import argparse
import dataclasses
import importlib
import logging
import multiprocessing as mp
import queue
import resource
import tempfile
import time
import traceback

log = logging.getLogger(__name__)

SCENES = {"step": "planetary_step_carrier.toml", "builtin": "planetary_flexible_carrier.toml"}
LABELS = {"step": "STEP carrier with windows", "step-warm": "STEP carrier, warm mesh cache",
          "builtin": "built-in carrier (CarrierParams)"}
DEFAULT_SIZES = (0.012,)
QUICK_SIZE = 0.03
COLUMNS = ("component", "size [m]", "FE DOFs", "mass [kg]", "read/import [s]", "mesh [s]", "assemble [s]",
           "couple [s]", "reduce [s]", "total [s]", "modes kept", "peak RSS [MB]",
           "f1, f2, f3 fixed-interface [Hz]")


@dataclasses.dataclass(frozen=True)
class Case:
    """One carrier to build: ``params`` (a PartFile or CarrierParams with its pins set),
    the scene's flex options and the Craig-Bampton cutoff (Hz)."""

    kind: str                 # "step" or "builtin"
    params: object
    flex: object              # assembly.scene.tables.FlexOptions
    cutoff_hz: float | None


def load_cases() -> dict[str, Case]:
    """The two carriers as their shipped scenes define them (pins, flex options, cutoff)."""
    from ...scene.cutoffs import cutoff_for
    from ...scene.planetary import carrier_pins
    from ...scene.schema import load_scene
    from ...scene.tables import FlexOptions

    out = {}
    for kind, name in SCENES.items():
        scene = load_scene(name)
        stage = scene.stages[0]
        flex = stage.carrier.flex or FlexOptions()
        out[kind] = Case(kind, carrier_pins(stage, "stages[0]"), flex,
                         cutoff_for(stage.carrier, flex, scene.band))
    return out


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # Linux: kB


#: Modules the timed steps use, imported before the clock starts (and gmsh, through
#: fe_components.gmsh_session).
WARM_IMPORTS = ("meshio", "skfem", "skfem.io.meshio", "skfem.models.elasticity", "scipy.sparse.linalg",
                "cms.craig_bampton", "fe_components.coupling", "fe_components.fe_model", "fe_components.part.cad",
                "fe_components.part.read")


def _warm_imports() -> None:
    """Import every module the timed steps use, so that no time below is module loading."""
    from cms.linsolve import default_backend
    from fe_components.gmsh_session import gmsh_module

    gmsh_module()
    for name in WARM_IMPORTS:
        importlib.import_module(name)
    default_backend()  # imports CHOLMOD when it is there


def build_and_reduce(case: Case, size: float, cache_dir: str) -> dict:
    """Read, mesh, assemble, couple and reduce ``case`` at element size ``size`` (m) with
    the mesh cache ``cache_dir``; the measurements (times in s, wall clock)."""
    from cms.craig_bampton import CraigBamptonReductor
    from fe_components.coupling import couple
    from fe_components.fe_model import build_component
    from fe_components.part.file import PartFile
    from fe_components.part.read import part_geometry

    from ...scene.tables import MAX_MODES

    flex, params = case.flex, case.params
    t = {}
    t0 = time.perf_counter()
    if isinstance(params, PartFile):  # memoised per process: the FE model's interfaces reuse it
        part_geometry(params)
    t["read"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    fe = build_component(params, flex.material, mesh_size=size, order=flex.order, cache_dir=cache_dir)
    t_build = time.perf_counter() - t0
    t0 = time.perf_counter()
    fe.K  # K and M are assembled on first use
    t["mesh"] = fe.timings["mesh"]
    t["assemble"] = t_build - fe.timings["mesh"] + time.perf_counter() - t0

    t0 = time.perf_counter()
    c = couple(fe, dict(flex.couplings or {}))
    c.K_c  # projected on first use, with M_c
    t["couple"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    se = CraigBamptonReductor(
        c.K_c, c.M_c, c.boundary_dofs, n_modes=flex.n_modes, cutoff_hz=case.cutoff_hz, max_modes=MAX_MODES,
        dof_names=c.boundary_names,
        rigid_body_basis=c.rigid_body_basis(fe.center_of_mass), residual_vectors=flex.residual_vectors).reduce()
    t["reduce"] = time.perf_counter() - t0

    n_rv = int(se.metadata.get("n_residual_vectors", 0))
    n_eig = se.n_modes - n_rv
    return dict(dofs=int(fe.n_dofs), coupled_dofs=int(c.K_c.shape[0]), mass=float(fe.mass), times=t,
                total=sum(t.values()), n_modes=n_eig, n_rv=n_rv, rss_mb=_peak_mb(),
                freqs=[float(f) for f in se.mode_frequencies_hz[:min(3, n_eig)]])


def _child(case: Case, size: float, cache_dir: str, queue) -> None:
    try:
        _warm_imports()
        queue.put(build_and_reduce(case, size, cache_dir))
    except Exception:  # as text: not every exception pickles
        queue.put(traceback.format_exc())


def run_case(case: Case, size: float, cache_dir: str) -> dict:
    """:func:`build_and_reduce` in a fresh spawned process (nothing imported or memoised)."""
    ctx = mp.get_context("spawn")
    q = ctx.Queue()
    p = ctx.Process(target=_child, args=(case, size, cache_dir, q))
    p.start()
    try:
        while True:
            try:
                res = q.get(timeout=1.0)
                break
            except queue.Empty:
                if not p.is_alive() and q.empty():  # killed (e.g. out of memory) before it reported
                    raise RuntimeError(f"{case.kind} carrier at {size:g} m: the benchmark process ended "
                                       f"with exit code {p.exitcode} and no result") from None
    finally:
        p.join()
    if isinstance(res, str):
        raise RuntimeError(f"{case.kind} carrier at {size:g} m failed in its process:\n{res}")
    return res


def run(cases: dict[str, Case], sizes, warm: bool = True):
    """Rows of the table (dicts), one per (carrier, size): per size the STEP carrier cold,
    warm (when ``warm``) and the built-in carrier, each case yielded when done."""
    for size in sizes:
        with tempfile.TemporaryDirectory(prefix="flexgear-bench-part-") as cache:
            log.info("STEP carrier, %g m, empty mesh cache", size)
            yield dict(component=LABELS["step"], size=size, **run_case(cases["step"], size, cache))
            if warm:
                log.info("STEP carrier, %g m, warm mesh cache", size)
                yield dict(component=LABELS["step-warm"], size=size, **run_case(cases["step"], size, cache))
        with tempfile.TemporaryDirectory(prefix="flexgear-bench-part-") as cache:
            log.info("built-in carrier, %g m, empty mesh cache", size)
            yield dict(component=LABELS["builtin"], size=size, **run_case(cases["builtin"], size, cache))


HEADER = "| " + " | ".join(COLUMNS) + " |\n|" + "---|" * len(COLUMNS)


def format_row(r: dict) -> str:
    t = r["times"]
    read = f"{t['read']:.2f}" if r["component"] != LABELS["builtin"] else f"{t['read']:.2f} (a)"
    f = ", ".join(f"{x:.0f}" for x in r["freqs"]) or "-"
    cells = [r["component"], f"{r['size']:g}", str(r["dofs"]), f"{r['mass']:.2f}", read, f"{t['mesh']:.2f}",
             f"{t['assemble']:.2f}", f"{t['couple']:.2f}", f"{t['reduce']:.2f}", f"{r['total']:.2f}",
             f"{r['n_modes']} + {r['n_rv']} rv", f"{r['rss_mb']:.0f}", f]
    return "| " + " | ".join(cells) + " |"


def footnotes(cases: dict[str, Case]) -> str:
    from .drivetrain import machine

    cut = cases["step"].cutoff_hz
    return "\n".join([
        "",
        "(a) The built-in carrier reads no file: gmsh builds its solid from the parameters inside "
        "the mesh step, so its read/import is ~0 and its mesh time includes the solid construction.",
        "The STEP carrier's mesh step opens the file in OpenCASCADE again and re-applies the interface "
        "rules in the gmsh session it meshes in (not reused from read/import); a warm mesh cache skips "
        "gmsh but not read/import: the FE interfaces and the CAD mass check need the part's faces.",
        f"Craig-Bampton: every fixed-interface mode below {cut:g} Hz (1.5 x band), plus one residual "
        "vector (rv) per boundary DOF; 6 interfaces x 6 master DOFs. Each row: a fresh spawned "
        "process; cold rows start from an empty mesh cache; peak RSS includes the imports.",
        f"Machine: {machine()}.",
    ])


def size_list(text: str) -> tuple[float, ...]:
    """``--size`` value: comma-separated element sizes in m, each in (0, 1)."""
    try:
        sizes = tuple(float(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: give element sizes in m, e.g. 0.015,0.012,0.008") from None
    if not sizes or not all(0 < s < 1 for s in sizes):
        raise argparse.ArgumentTypeError(f"{text!r}: element sizes must lie in (0, 1) m")
    return sizes


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="flexgear bench part", description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=size_list, default=DEFAULT_SIZES, metavar="LIST",
                    help="element sizes in m, comma-separated (default 0.012, the STEP scene's)")
    ap.add_argument("--quick", action="store_true", help=f"element size {QUICK_SIZE} m only (a smoke run)")
    ap.add_argument("--no-warm", action="store_true", help="skip the warm-mesh-cache row")
    ap.add_argument("-v", "--verbose", action="store_true", help="log each case as it starts")
    args = ap.parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING)
    sizes = (QUICK_SIZE,) if args.quick else args.size
    cases = load_cases()
    print(HEADER, flush=True)  # benchmark table output, one row per finished case
    for row in run(cases, sizes, warm=not args.no_warm):
        print(format_row(row), flush=True)
    print(footnotes(cases), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
