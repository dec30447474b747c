"""``flexgear`` command line: modes, compare, static, run, study, campbell, frf, simulate, export, part, demo,
reference, bench.

Every subcommand is parsed here; every error the package raises on bad input ends in
:func:`main`'s one handler: a single line on stderr naming the field or file and the
value, exit code 2. SIGTERM unwinds like Ctrl-C (a half-written ``--out`` is removed) and
ends with exit code 143 (128 + 15).
"""
from __future__ import annotations

import argparse
import importlib
import logging
import os
import signal
import sys
from contextlib import contextmanager, nullcontext
from pathlib import Path

log = logging.getLogger("flexgear")

SCENE_HELP = "scene TOML file (or the name of a shipped example)"
BENCHMARKS = {"fe": "assembly.app.bench_fe", "cms": "assembly.app.bench_cms", "flex": "assembly.app.bench_flex",
              "drivetrain": "assembly.app.bench_drivetrain", "frf": "assembly.app.bench_frf",
              "transient": "assembly.app.bench_transient", "study": "assembly.app.bench_study",
              "part": "assembly.app.bench_part"}


OUT_HELP = ("output folder, replaced as a whole when the run succeeds (never half-written); files you "
            "added to an earlier result are carried over")


class UsageError(ValueError):
    """A command-line value the program cannot use (e.g. ``--modes -5``)."""


#: Options checked like scene values before a command reads its scene (:func:`check_options`):
#: numbers (argparse dest -> unit, rule of :func:`assembly.arguments.number`: a real number,
#: finite unless inf is admitted, zero or of magnitude in [1e-100, 1e100], in range), integers
#: (dest -> least, greatest) and names (a non-empty string).
NUMBERS = {"t_end": ("s", {"gt": 0.0}), "dt": ("s", {"gt": 0.0}), "speed": ("rad/s", {}),
           "rated_rpm": ("rpm", {"ge": 0.0}), "speed_range": ("rpm", {"ge": 0.0}), "fmin": ("Hz", {"ge": 0.0}),
           "fmax": ("Hz", {"gt": 0.0}), "modes_hz": ("Hz", {"gt": 0.0, "infinite": "every mode"})}
#: (a local cluster runs one process per worker, one variant at a time each: beyond a few per
#: core they only compete for memory)
INTEGERS = {"points": (2, None), "harmonics": (1, None), "workers": (1, 8 * (os.cpu_count() or 1))}
NAMES = ("reference", "rotor", "generator", "body", "input", "output", "scheduler", "cache_dir")
#: Argument names of the Python API (:mod:`assembly.arguments`) -> the flags that set them: an
#: error the API raises about one of them is printed with the flag.
FLAGS = {"t_end": "--t-end", "dt": "--dt", "speed": "--speed", "outputs": "--output", "input": "--input",
         "reference": "--reference", "speed_range": "--speed-range", "points": "--points",
         "harmonics": "--harmonics", "rotor": "--rotor", "generator": "--generator", "modes_hz": "--modes-hz"}


def check_options(args) -> None:
    """Every numeric and name option given: one SceneError naming the flag and value else."""
    from .. import arguments

    def given(dest):
        v = getattr(args, dest, None)
        return [] if v is None else v if isinstance(v, list) else [v]
    for dest, (unit, rule) in NUMBERS.items():
        for v in given(dest):
            arguments.number(flag_of(dest), v, unit, **rule)
    for dest, (low, high) in INTEGERS.items():
        for v in given(dest):
            arguments.integer(flag_of(dest), v, low, high)
    for dest in NAMES:
        for v in given(dest):
            arguments.text(flag_of(dest), v)


def flag_of(dest: str) -> str:
    return "--" + dest.replace("_", "-")


def with_flags(exc, args):
    """``exc``, a SceneError naming an argument of the Python API, renamed to the flag of the
    command (``args``) that set it; any other error as it is."""
    from ..errors import SceneError
    if not isinstance(exc, SceneError):
        return exc
    flag = FLAGS.get(exc.path.split("[")[0])
    if flag is None or not hasattr(args, flag[2:].replace("-", "_")):
        return exc
    return SceneError(flag, exc.value, exc.reason)


class Terminated(BaseException):
    """SIGTERM arrived; a BaseException like KeyboardInterrupt, so cleanup code runs."""


def _raise_terminated(signum, frame):
    """SIGTERM handler: unwind like Ctrl-C."""
    raise Terminated()


def user_errors() -> tuple:
    """Exception types the package raises on input it cannot use (scene, geometry, meshing,
    coupling, reduction and its cache, eigen solve, output folder, command line): reported
    in one line with exit code 2, never a traceback."""
    from cms.errors import ReductionError
    from fe_components.errors import CouplingError, GeometryError, MeshCacheError, MeshingError

    from ..errors import MechanismError, SceneError, SolverError
    from .output import OutputDirError
    from .pipeline import ModeSelectionError
    return (SceneError, MechanismError, SolverError, OutputDirError, GeometryError, MeshingError, MeshCacheError,
            CouplingError, ReductionError, UsageError, ModeSelectionError)


def _at_least(value: int, flag: str, low: int) -> int:
    if value < low:
        raise UsageError(f"{flag} = {value}: must be >= {low}")
    return value


@contextmanager
def api_flags(flags: dict):
    """A SceneError of an API argument named in ``flags`` (argument -> option, e.g. ``{"t_end":
    "--t-end"}``) becomes a UsageError naming the option: the core names its arguments, the
    command line its options. Other errors pass unchanged."""
    from ..errors import SceneError
    try:
        yield
    except SceneError as exc:
        if exc.path in flags:
            raise UsageError(f"{flags[exc.path]} = {exc.value!r}: {exc.reason}") from None
        raise


def holding_out(args):
    """``--out`` checked and locked for the whole computation that fills it
    (:func:`assembly.app.output.hold_output`); nothing without ``--out``."""
    from .output import hold_output
    return hold_output(args.out) if args.out is not None else nullcontext()


def parse_modes(text: str) -> tuple:
    """``--modes`` of ``run``: ``"N"`` -> (N, None): the first N elastic modes in the band;
    ``"7,9,12-14"`` -> (None, (7, 9, 12, 13, 14)): these modes (1-based, as numbered in the
    mode table; a single mode as ``"7,"`` or ``"7-7"``). UsageError on anything else."""
    text = text.strip()
    if text.isdigit():
        return _at_least(int(text), "--modes", 0), None
    numbers = []
    for part in filter(None, (p.strip() for p in text.split(","))):
        lo, sep, hi = part.partition("-")
        if not lo.isdigit() or (sep and not hi.isdigit()):
            raise UsageError(f"--modes {text}: {part!r} is not a mode number or range (use N, or e.g. 7,9,12-14)")
        a, b = int(lo), int(hi) if sep else int(lo)
        if a < 1 or b < a:
            raise UsageError(f"--modes {text}: {part!r}: mode numbers start at 1 and a range runs upwards")
        numbers += [k for k in range(a, b + 1) if k not in numbers]
    if not numbers:
        raise UsageError(f"--modes {text!r}: no mode numbers (use N, or e.g. 7,9,12-14)")
    return None, tuple(numbers)


def scene_file(args) -> str:
    """The scene file ``args.scene`` names. A bare name may be a file here or a shipped
    example, so the file it resolved to is announced on stderr; a path with a folder part
    is read as given (never a shipped example)."""
    from ..scene.schema import SCENE_DIR, is_bare_name, resolve_scene_path

    path = resolve_scene_path(args.scene)
    if is_bare_name(args.scene) and not getattr(args, "quiet", False):
        shipped = " (shipped example)" if path.parent.resolve() == SCENE_DIR.resolve() else ""
        print(f"flexgear: scene file {path.resolve()}{shipped}", file=sys.stderr)
    return str(path)


def cmd_modes(args) -> int:
    from ..analysis.modal import solve_modes
    from ..model.assemble import assemble
    from ..scene.schema import load_scene
    from .tables import modes_json, modes_table

    scene = load_scene(scene_file(args))
    res = solve_modes(assemble(scene))
    if args.json:
        _print_json(modes_json(res))
    else:
        print(modes_table(res, title=f"{scene.name}  ({args.scene})", all_modes=args.all))
    return 0


def cmd_compare(args) -> int:
    from ..analysis.compare import compare
    from ..scene.schema import load_scene
    from .tables import comparison_table

    scene = load_scene(scene_file(args))
    c = compare(scene, n_rows=args.modes, flexible_components=True)
    if args.json:
        _print_json({"scene": scene.name, "units": {"frequency": "Hz"}, "frequencies_hz": c.frequencies(),
                     "pairs": c.rows, "timings": c.timings})
    else:
        print(f"{scene.name}  ({args.scene})")
        print(comparison_table(c))
    return 0


def cmd_static(args) -> int:
    """``flexgear static``: mesh forces, bearing reactions, shaft loads and checks of
    every load case of the scene."""
    from ..errors import SceneError
    from ..model.assemble import assemble
    from ..analysis.reactions import static_report
    from ..scene.schema import load_scene
    from ..analysis.static import solve_static_cases
    from .static_tables import static_json, static_text

    scene = load_scene(scene_file(args))
    if not scene.load_cases():
        raise SceneError("loads", [], "the scene has no load case: add a [load] table or [[loads]] tables")
    model = assemble(scene)
    reports = [static_report(st) for st in solve_static_cases(scene, None, model=model)]
    if args.json:
        _print_json(static_json(scene.name, reports, model))
    else:
        print(static_text(reports, title=f"{scene.name}  ({args.scene})", model=model))
    return 0


def cmd_run(args) -> int:
    """``flexgear run``: the whole pipeline into ``--out``."""
    from .pipeline import RunOptions, run_pipeline, skipped_text
    from .progress import Progress

    n, numbers = parse_modes(args.modes)
    opts = RunOptions(n_modes=RunOptions.n_modes if n is None else n, mode_numbers=numbers,
                      compare=not args.no_compare, images=not args.no_images)
    ctx = run_pipeline(scene_file(args), args.out, opts, Progress(enabled=False if args.quiet else None))
    if ctx.skipped and not args.quiet:
        print(f"flexgear: {skipped_text(ctx)}", file=sys.stderr)
    if not args.quiet:
        n_img = sum(1 for p, _ in ctx.files if p.endswith(".png"))
        print(f"{ctx.scene.name}: {len(ctx.result.frequencies_hz)} modes, {n_img} images -> "
              f"{ctx.out_dir / 'index.html'} ({ctx.timings['total']:.1f} s)")
    return 0


def cmd_study(args) -> int:
    """``flexgear study``: every variant of a study file, on a local Dask cluster (default),
    an existing one (``--scheduler``) or in this process (``--serial``), into ``--out``."""
    import time

    from fe_components.meshing import default_cache_dir

    from .progress import Progress
    from .study_engine import run_study
    from .study_file import read_study
    from .study_out import study_to_dir

    study = read_study(args.study)
    out = Path(args.out).absolute()
    mode = "serial" if args.serial else "scheduler" if args.scheduler else "local"
    progress = Progress(enabled=False if args.quiet else None)
    t0 = time.perf_counter()
    with holding_out(args):     # a foreign or busy folder refused, and locked, before the (possibly long) study
        with progress.bar(f"{study.name}: {len(study.variants)} variants ({mode})", total=len(study.variants),
                          unit="variant") as bar:
            failed = []

            def tick(row):
                failed.extend([row["variant"]] if row["status"] != "ok" else [])
                bar.update(1)
                bar.set_postfix_str(f"{len(failed)} failed", refresh=False)
            rows = run_study(study, mode, args.scheduler, args.workers, str(default_cache_dir().absolute()), tick)
        info = study_to_dir(study, rows, out, mode, time.perf_counter() - t0)
    if not args.quiet:
        print(f"{study.name}: {info['variants']} variants ({info['failed']} failed) in {info['time_s']:.1f} s "
              f"-> {out / 'index.html'}")
    return 0


def _add_study(sub) -> None:
    p = sub.add_parser("study", help="design study: any scene fields varied (grid, Latin hypercube, random), each "
                                     "variant a modes, compare, frf or simulate run, on a Dask cluster")
    p.add_argument("study", help="study TOML file (or the name of a shipped study: helix_angle, bearing_factor, "
                                 "planet_count)")
    p.add_argument("--out", required=True, help=OUT_HELP + " (study.parquet, study.csv, runs.csv, plots)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS", default=None,
                       help="run on this Dask scheduler (tcp://host:8786); its workers must see the scene and "
                            "cache folders (default: a local cluster, one worker process per core)")
    where.add_argument("--serial", action="store_true", help="run the variants one after the other in this process")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="worker processes of the local cluster (default: one per core)")
    p.add_argument("--quiet", "-q", action="store_true", help="no progress bar, no summary line")
    p.set_defaults(func=cmd_study)


def cmd_export_elastodyn(args) -> int:
    """``flexgear export elastodyn``: the two-mass drivetrain as an ElastoDyn fragment, to
    ``--out`` (atomically, with a summary on stdout) or to stdout."""
    from ..analysis.two_mass import two_mass
    from ..scene.schema import load_scene
    from .elastodyn import fragment_text, write_fragment
    from .output import OutputDirError

    scene = load_scene(scene_file(args))
    tm = two_mass(scene, args.rotor, args.generator)
    if args.out is None:
        sys.stdout.write(fragment_text(tm, scene.name))
        return 0
    try:
        write_fragment(args.out, tm, scene.name)
    except OSError as exc:
        raise OutputDirError(f"--out {args.out}: cannot write: {exc.strerror or exc}") from exc
    f_free, f_locked = tm.frequencies_hz()
    print(f"{scene.name}: GBRatio {tm.gear_ratio:.6g}, GenIner {tm.generator_inertia:.6g} kg m^2, "
          f"DTTorSpr {tm.stiffness:.6g} N m/rad; two-mass {f_free:.4g} Hz free, {f_locked:.4g} Hz generator "
          f"locked -> {args.out}")
    return 0


def cmd_export_superelement(args) -> int:
    """``flexgear export superelement``: a flexible body's superelement as .npz and Nastran DMIG."""
    from .export_superelement import run
    return run(args)


def cmd_campbell(args) -> int:
    """``flexgear campbell``: natural frequencies, excitation orders and their crossings over
    a speed range of the reference body (rpm): a table, ``--json``, or files in ``--out``."""
    from ..dynamics.campbell import campbell
    from ..scene.schema import load_scene
    from .campbell import campbell_json, campbell_to_dir, crossings_text

    path = scene_file(args)
    scene = load_scene(path)
    with holding_out(args):
        with api_flags({"points": "--points", "harmonics": "--harmonics"}):
            c = campbell(scene, args.speed_range, args.reference, args.points, args.gyroscopic, args.harmonics)
        if args.out is not None:
            campbell_to_dir(c, args.out, args.rated_rpm, path)
    if args.json:
        _print_json(campbell_json(c, args.rated_rpm))
    elif args.out is not None:
        print(f"{c.scene}: {len(c.orders)} orders, {len(c.crossings)} crossings -> "
              f"{Path(args.out) / 'campbell.png'}")
    else:
        print(crossings_text(c))
    return 0


def cmd_frf(args) -> int:
    """``flexgear frf``: frequency response from one input to outputs: a summary, ``--json``,
    or files in ``--out``."""
    from ..dynamics.frf import check_frf_size, frequency_response
    from ..model.assemble import assemble
    from ..scene.schema import load_scene
    from .frf import frequencies, frf_json, frf_to_dir, summary_text

    size = {"len(frequency_hz)": "--points"}
    with api_flags(size):
        check_frf_size(args.points, len(args.output))          # before the grid is built
    try:
        f = frequencies(args.fmin, args.fmax, args.points, args.log)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    path = scene_file(args)
    scene = load_scene(path)
    with holding_out(args):
        with api_flags({**size, "modes_hz": "--modes-hz"}):
            r = frequency_response(assemble(scene), args.input, args.output, f, method=args.method,
                                   modes_hz=args.modes_hz)
        if args.json or args.out is not None:        # the summary lists them itself
            for w in r.warnings:
                print(f"flexgear: warning: {w}", file=sys.stderr)
        return _emit(args, lambda: frf_to_dir(r, args.out, scene.name, path, args.log),
                     lambda: frf_json(r, scene.name), f"{scene.name}: FRF from {r.input}, {len(r.outputs)} outputs",
                     lambda: summary_text(r, scene.name))


def _emit(args, to_dir, as_json, done: str, summary, indent: int | None = 1) -> int:
    """An analysis command's output: files in ``--out`` (``to_dir()``), then ``--json``
    (``as_json()`` on stdout), else a line saying where the files are (``done``), else
    ``summary()``."""
    if args.out is not None:
        to_dir()
    if args.json:
        _print_json(as_json(), indent)
    elif args.out is not None:
        print(f"{done} -> {Path(args.out) / 'index.html'}")
    else:
        print(summary())
    return 0


def _print_json(obj, indent: int | None = 1) -> None:
    """One strict JSON object on stdout (:mod:`assembly.app.strict_json`: a non-finite
    number is an error naming it, never a bare NaN)."""
    from .strict_json import dumps
    sys.stdout.write(dumps(obj, indent=indent) + "\n")


def _add_frf(sub) -> None:
    p = sub.add_parser("frf", help="frequency response (damped modes with a residual correction, or a direct "
                                   "solve): shaft torques, mesh and bearing forces, motions, von Mises stress "
                                   "per unit torque or force")
    p.add_argument("scene", help=SCENE_HELP)
    p.add_argument("--input", required=True, metavar="IN",
                   help="torque:BODY[:INTERFACE] (about its axis), force:BODY[:INTERFACE]:x|y|z, "
                        "moment:BODY[:INTERFACE]:x|y|z (global axes) or mesh:MESH (a transmission-error force "
                        "pair along the line of action)")
    p.add_argument("--output", required=True, action="append", metavar="OUT",
                   help="torque:SHAFT, force:MESH, force:BEARING[:x..rz], motion:BODY[:INTERFACE]:x..rz|spin, "
                        "acceleration:BODY[:INTERFACE]:x..rz|spin, stress:BODY:X,Y,Z (von Mises at a point of a "
                        "flexible body, m) (repeat for more); section loads carry their share of every damping")
    p.add_argument("--fmin", type=float, default=0.1, help="lowest frequency, Hz (default 0.1)")
    p.add_argument("--fmax", type=float, default=1000.0, help="highest frequency, Hz (default 1000)")
    p.add_argument("--points", type=int, default=2000, help="frequencies (default 2000)")
    p.add_argument("--log", action="store_true", help="logarithmic frequency spacing (and axis)")
    p.add_argument("--method", choices=("modal", "direct"), default="modal",
                   help="modal: damped-mode superposition (default); direct: one dense solve per frequency "
                        "(the reference)")
    p.add_argument("--modes-hz", type=float, default=None, metavar="HZ",
                   help="modal cutoff, Hz: modes above it enter by their residual flexibility "
                        "(default 30 x --fmax; inf: every mode)")
    _add_out_json(p, "frf.csv, frf.json, bode_NN.png, index.html")
    p.set_defaults(func=cmd_frf)


def cmd_simulate(args) -> int:
    """``flexgear simulate``: time-domain run: a summary, ``--json`` or files in ``--out``; a
    run that stops keeps its partial result (:func:`_stopped`) and exits with 1."""
    from ..dynamics.simulate import simulate
    from ..dynamics.transient import Diverged, check_history
    from ..scene.schema import load_scene
    from .progress import Progress
    from .simulate import sim_to_dir, summary_text

    flags = {"dt": "--dt", "t_end": "--t-end"}
    with api_flags(flags):          # the run's length against memory, before the scene is read
        n_steps = check_history(args.dt, args.t_end, len(args.output or []))
    path = scene_file(args)
    scene = load_scene(path)
    progress = Progress(enabled=False if args.quiet or args.json else None)
    with holding_out(args):
        stopped = None
        with progress.bar(f"{scene.name}: simulate", total=n_steps, unit="step") as bar:
            def tick(step, total, t):
                bar.update(step - bar.n)
                bar.set_postfix_str(f"t = {t:.4g} s", refresh=False)
            try:
                with api_flags(flags):
                    r = simulate(scene, args.t_end, args.dt, args.output, base_dir=Path(path).parent,
                                 speed=args.speed, progress=tick, full_fe=args.unreduced)
            except Diverged as exc:
                stopped = exc
        if stopped is not None:
            return _stopped(args, stopped, scene.name, path)
        return _emit(args, lambda: sim_to_dir(r, args.out, scene.name, path), r.as_json,
                     f"{scene.name}: {len(r.time_s) - 1} steps, {len(r.outputs)} outputs",
                     lambda: summary_text(r, scene.name), indent=None)


def _stopped(args, exc, scene_name: str, path: str) -> int:
    """A run that stopped (``exc``: :class:`~assembly.dynamics.transient.Diverged`): its
    partial result into ``--out`` as a complete one would go, marked partial
    (:func:`~assembly.app.simulate.sim_to_dir`), else nowhere; ``--json`` or, without
    ``--out``, the summary on stdout; the reason in one line on stderr; exit code 1."""
    from .output import OutputDirError
    from .simulate import h5_name, sim_to_dir, summary_text

    p = exc.partial
    kept = "is not kept: give --out DIR to keep it"
    if args.out is not None:
        try:
            sim_to_dir(p, args.out, scene_name, path)
            kept = f"is in {Path(args.out) / h5_name(p)} (marked partial)"
        except OutputDirError as err:
            kept = f"could not be written: {err}"
    if args.json:
        _print_json(p.as_json(), None)
    elif args.out is None:
        print(summary_text(p, scene_name))
    print(f"flexgear: error: run stopped: {exc}; the partial result (to t = {p.time_s[-1]:.6g} s) {kept}",
          file=sys.stderr)
    return 1


def _add_simulate(sub) -> None:
    p = sub.add_parser("simulate", help="time-domain run: implicit integration with angle-driven mesh stiffness, "
                                        "backlash, generator, brake and turbine loads ([simulation] of the scene)")
    p.add_argument("scene", help=SCENE_HELP)
    p.add_argument("--t-end", type=float, required=True, metavar="T", help="end time, s")
    p.add_argument("--dt", type=float, required=True, metavar="DT", help="time step, s")
    p.add_argument("--output", action="append", metavar="OUT",
                   help="as flexgear frf's outputs (torque:SHAFT, force:MESH, force:BEARING[:dir], "
                        "motion:/acceleration:BODY[:INTERFACE]:dof, stress:BODY:X,Y,Z), speed:BODY (rad/s) and "
                        "stress:POINT "
                        "(simulation.points) (repeat for more; default: every named point and nonlinear mesh)")
    p.add_argument("--speed", type=float, default=None, metavar="RAD_S",
                   help="starting speed of the rotor (rad/s; default simulation.speed)")
    p.add_argument("--unreduced", action="store_true",
                   help="integrate every FE DOF of the flexible bodies instead of their reductions (reference)")
    _add_out_json(p, "simulation.h5, trace_NN.png, spectrum_NN.png, summary.json, index.html")
    p.set_defaults(func=cmd_simulate)


def _add_out_json(p, files: str) -> None:
    """``--out DIR`` (writing ``files``), ``--json`` and ``--quiet`` of an analysis command."""
    p.add_argument("--out", default=None, metavar="DIR", help=f"{OUT_HELP} ({files})")
    p.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    p.add_argument("--quiet", "-q", action="store_true", help="do not announce the scene file")


def _add_campbell(sub) -> None:
    p = sub.add_parser("campbell", help="Campbell diagram: natural frequencies, gear-mesh and rotor orders, "
                                        "their crossings over a speed range (Parker's planet phasing rule)")
    p.add_argument("scene", help=SCENE_HELP)
    p.add_argument("--speed-range", nargs=2, type=float, required=True, metavar=("RPM_MIN", "RPM_MAX"),
                   help="speed range of the reference body (rpm)")
    p.add_argument("--reference", default=None, metavar="BODY",
                   help="body whose speed is swept (default: the body of role = \"rotor\")")
    p.add_argument("--points", type=int, default=41, help="speeds sampled (default 41; used with --gyroscopic)")
    p.add_argument("--gyroscopic", action="store_true",
                   help="add each spinning body's gyroscopic coupling (frequencies then depend on speed)")
    p.add_argument("--harmonics", type=int, default=3, metavar="H", help="mesh harmonics 1..H (default 3)")
    p.add_argument("--rated-rpm", type=float, default=None, metavar="RPM", help="mark the rated speed")
    _add_out_json(p, "campbell.png, crossings.csv, campbell.json")
    p.set_defaults(func=cmd_campbell)


def _add_export(sub) -> None:
    p = sub.add_parser("export", help="export to other tools: elastodyn (OpenFAST two-mass drivetrain), "
                                      "superelement (.npz, Nastran DMIG)")
    what = p.add_subparsers(dest="what", required=True)
    e = what.add_parser("elastodyn", help="GBRatio, GenIner, DTTorSpr of the rotor-generator chain "
                                          "(an OpenFAST ElastoDyn input fragment)")
    e.add_argument("scene", help=SCENE_HELP)
    e.add_argument("--out", default=None, metavar="FILE", help="write the fragment to FILE (atomically) "
                                                               "instead of stdout")
    e.add_argument("--rotor", default=None, metavar="NAME", help="rotor body (default: the body of role = \"rotor\")")
    e.add_argument("--generator", default=None, metavar="NAME",
                   help="generator body (default: the body of role = \"generator\")")
    e.add_argument("--quiet", "-q", action="store_true", help="do not announce the scene file")
    e.set_defaults(func=cmd_export_elastodyn)
    s = what.add_parser("superelement", help="a flexible body's reduced K, M and DOF map (local axes): "
                                             "<DIR>/<body>.npz and Nastran DMIG <DIR>/<body>.dmig")
    s.add_argument("scene", help=SCENE_HELP)
    s.add_argument("--body", required=True, metavar="NAME", help="the flexible body (e.g. stage.carrier)")
    s.add_argument("--out", required=True, metavar="DIR", help="folder of the files (created if missing)")
    s.add_argument("--format", default="npz,dmig", metavar="LIST", help="npz, dmig or npz,dmig (default)",
                   type=lambda t: importlib.import_module("assembly.app.export_superelement").parse_formats(t))
    s.add_argument("--quiet", "-q", action="store_true", help="do not announce the scene file")
    s.set_defaults(func=cmd_export_superelement)


def cmd_part(args) -> int:
    """``flexgear part``: one part checked alone (mass properties, free-free modes, interfaces)."""
    from .part import run
    return run(args)


def _add_part(sub) -> None:
    p = sub.add_parser("part", help="check one part alone: mass properties (FE vs CAD), free-free modes, "
                                    "interfaces, what its file held")
    p.add_argument("target", metavar="FILE|SCENE", help="a part file (STEP, BREP, .msh, .inp, .bdf, .med, .vtu, ...) "
                                                        "or a scene with a part-file body")
    p.add_argument("--body", default=None, metavar="NAME", help="SCENE: the body whose part is checked (default: "
                                                                "the only body with a part file)")
    p.add_argument("--units", default=None, metavar="UNIT", help="FILE: length unit of its numbers (m, mm, ...)")
    p.add_argument("--order", type=int, default=None, choices=(1, 2), help="FILE (a mesh): 2 lifts a linear mesh to P2")
    p.add_argument("--axis", default=None, metavar="X,Y,Z", help="FILE: the part's rotation axis in the file's axes "
                                                                 "(--axis=-1,0,0 when it starts with a minus)")
    p.add_argument("--origin", default=None, metavar="X,Y,Z", help="FILE: a point of that axis (m, the file's axes)")
    p.add_argument("--mesh-size", type=float, default=None, metavar="M", help="FILE (CAD): element size (m)")
    p.add_argument("--modes", type=int, default=6, metavar="N", help="elastic modes listed (default 6)")
    p.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    p.add_argument("--quiet", "-q", action="store_true", help="do not announce the scene file")
    p.set_defaults(func=cmd_part, check=lambda a: (_at_least(a.modes, "--modes", 1), a.modes <= 100 or _too_many(a.modes)))


def _too_many(modes: int):
    raise UsageError(f"--modes = {modes}: must be in 1..100")


def cmd_demo(args) -> int:
    from ..analysis.modal import solve_modes
    from ..model.assemble import assemble
    from ..scene.schema import load_scene, shipped_scenes
    from .tables import modes_table

    for p in shipped_scenes():
        scene = load_scene(p)
        print(modes_table(solve_modes(assemble(scene)), title=f"== {scene.name}  ({p.name})"))
        print()
    return 0


def cmd_reference(args) -> int:
    """``flexgear reference``: the scene reference (Markdown) to stdout or ``--out``."""
    from .reference import write_reference

    text = write_reference(args.out)
    if args.out is None:
        sys.stdout.write(text)
    return 0


def cmd_bench(args) -> int:
    names = list(BENCHMARKS) if args.what == "all" else [args.what]
    for name in names:
        rc = importlib.import_module(BENCHMARKS[name]).main(args.rest)
        if rc:
            return rc
    return 0


def _add_run(sub) -> None:
    p = sub.add_parser("run", help="whole pipeline: tables, mode-shape images, plots, index.html")
    p.add_argument("scene", help=SCENE_HELP)
    p.add_argument("--out", required=True, help=OUT_HELP)
    p.add_argument("--modes", default="12", metavar="N|LIST",
                   help="modes drawn (images, modal stresses, VTU): N = the first N elastic modes in the band "
                        "(default 12), or mode numbers as in the table, e.g. 7,9,12-14")
    p.add_argument("--no-compare", action="store_true", help="skip the torsional vs rigid comparison")
    p.add_argument("--no-images", action="store_true",
                   help="skip the mode-shape and stress images (VTU files and tables are still written)")
    p.add_argument("--quiet", "-q", action="store_true", help="no progress bars, no summary line")
    p.set_defaults(func=cmd_run, check=lambda a: parse_modes(a.modes))


class _Parser(argparse.ArgumentParser):
    """argparse with its errors (unknown choice, missing argument) in one line, exit 2, like
    every other user error of the command line (no usage block: ``--help`` has it)."""

    def error(self, message):
        self.exit(2, f"flexgear: error: {self.prog.removeprefix('flexgear').strip() or 'flexgear'}: {message} "
                     f"(see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="flexgear", description="Gearbox and drivetrain dynamics (SI units).")
    p.add_argument("-v", "--verbose", action="count", default=0, help="log progress (-vv: debug)")
    p.add_argument("--cache-dir", metavar="DIR", default=None,
                   help="folder of generated meshes and reductions (flexible bodies; default $FLEXGEAR_CACHE_DIR, "
                        "else $XDG_CACHE_HOME/flexgear or ~/.cache/flexgear)")
    sub = p.add_subparsers(dest="cmd", required=True)
    _add_run(sub)
    _add_study(sub)
    _add_campbell(sub)
    _add_frf(sub)
    _add_simulate(sub)
    _add_export(sub)
    _add_part(sub)
    m = sub.add_parser("modes", help="eigenfrequencies and mode table of a scene")
    m.add_argument("scene", help=SCENE_HELP)
    m.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    m.add_argument("--all", action="store_true", help="list every mode, also those outside the band of interest "
                                                      "(default: up to the display limit, a multiple of band_hz)")
    m.set_defaults(func=cmd_modes)
    c = sub.add_parser("compare", help="torsional, rigid and flexible variants side by side (MAC-paired); "
                                         "flexible: the scene's flexible bodies, else every body with a component")
    c.add_argument("scene", help=SCENE_HELP)
    c.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    c.add_argument("--modes", type=int, default=20, help="rows of the table (default 20)")
    c.set_defaults(func=cmd_compare, check=lambda a: _at_least(a.modes, "--modes", 0))
    s = sub.add_parser("static", help="static load cases: mesh forces, bearing reactions, shaft torques, checks")
    s.add_argument("scene", help=SCENE_HELP)
    s.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    s.set_defaults(func=cmd_static)
    d = sub.add_parser("demo", help="mode tables of the shipped example scenes")
    d.set_defaults(func=cmd_demo)
    r = sub.add_parser("reference", help="scene reference: every TOML key, its unit, range, default (Markdown)")
    r.add_argument("--out", default=None, metavar="FILE", help="write to FILE instead of stdout")
    r.set_defaults(func=cmd_reference)
    b = sub.add_parser("bench", help="benchmarks (print tables; not tests)")
    b.add_argument("what", choices=[*BENCHMARKS, "all"])
    b.add_argument("rest", nargs=argparse.REMAINDER, help="arguments passed to the benchmark")
    b.set_defaults(func=cmd_bench)
    return p


def main(argv=None) -> int:
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as exc:                  # --help (0) or a usage error (2), already printed
        return int(exc.code or 0)
    level = logging.WARNING if args.verbose == 0 else (logging.INFO if args.verbose == 1 else logging.DEBUG)
    logging.basicConfig(level=level, format="%(levelname)s %(name)s: %(message)s")
    from .output import signal_handler

    if args.cache_dir is not None:  # every cache default of this process reads it (CacheDirs)
        from fe_components.meshing import cache_root
        with cache_root(Path(args.cache_dir).expanduser().absolute()):
            return _run(args, signal_handler)
    return _run(args, signal_handler)


def _run(args, signal_handler) -> int:
    """Run the chosen command; every user error ends in one line and exit code 2."""
    try:
        with signal_handler(_raise_terminated, (signal.SIGTERM,)):  # main thread only
            check_options(args)
            if getattr(args, "check", None) is not None:
                args.check(args)
            return args.func(args)
    except user_errors() as exc:
        print(f"flexgear: error: {with_flags(exc, args)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    except Terminated:
        print("flexgear: terminated (SIGTERM)", file=sys.stderr)
        return 128 + signal.SIGTERM
    except BrokenPipeError:  # output piped into e.g. `head`, which stopped reading
        sys.stderr.close()
        return 0


if __name__ == "__main__":
    sys.exit(main())
