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
import math
import signal
import sys
from contextlib import nullcontext
from pathlib import Path

from .. import arguments as check
from .args import (
    SCENE_HELP,
    Parser,
    add_campbell,
    add_coupling,
    add_export,
    add_frf,
    add_part,
    add_run,
    add_runup,
    add_simulate,
    add_study,
    api_flags,
    at_least,
    check_options,
    parse_modes,
    scene_file,
    with_flags,
)
from .errors import Terminated, UsageError, user_errors

log = logging.getLogger("flexgear")

BENCHMARKS = {"fe": "assembly.app.bench.fe", "cms": "assembly.app.bench.cms", "flex": "assembly.app.bench.flex",
              "drivetrain": "assembly.app.bench.drivetrain", "frf": "assembly.app.bench.frf",
              "transient": "assembly.app.bench.transient", "study": "assembly.app.bench.study",
              "part": "assembly.app.bench.part", "stream": "assembly.app.bench.stream",
              "turbine": "assembly.app.bench.turbine", "runup": "assembly.app.bench.runup",
              "quick": "assembly.app.bench.quick"}


def _raise_terminated(signum, frame):
    """SIGTERM handler: unwind like Ctrl-C."""
    raise Terminated()


def holding_out(args):
    """``--out`` checked and locked for the whole computation that fills it
    (:func:`assembly.app.output.hold_output`); nothing without ``--out``."""
    from .output import hold_output
    return hold_output(args.out) if args.out is not None else nullcontext()


def cmd_modes(args) -> int:
    from ..analysis.modal import solve_modes
    from ..model.assemble import assemble
    from ..scene.schema import load_scene
    from .report.tables import modes_json, modes_table

    scene = load_scene(scene_file(args))
    res = solve_modes(assemble(scene, dense=True))     # a small rigid model: no SciPy import
    if args.json:
        _print_json(modes_json(res))
    else:
        print(modes_table(res, title=f"{scene.name}  ({args.scene})", all_modes=args.all))
    return 0


def cmd_compare(args) -> int:
    from ..analysis.compare import compare
    from ..scene.schema import load_scene
    from .report.tables import comparison_table

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
    from ..analysis.reactions import static_report
    from ..analysis.static import solve_static_cases
    from ..errors import SceneError
    from ..model.assemble import assemble
    from ..scene.schema import load_scene
    from .report.static_tables import static_json, static_text

    scene = load_scene(scene_file(args))
    if not scene.load_cases():
        raise SceneError("loads", [], "the scene has no load case: add a [load] table or [[loads]] tables")
    model = assemble(scene)
    reports = [static_report(st) for st in solve_static_cases(model)]
    if args.json:
        _print_json(static_json(scene.name, reports, model))
    else:
        print(static_text(reports, title=f"{scene.name}  ({args.scene})", model=model))
    return 0


def cmd_run(args) -> int:
    """``flexgear run``: the whole pipeline into ``--out``."""
    from .progress import Progress
    from .report.pipeline import RunOptions, run_pipeline, skipped_text

    n, numbers = parse_modes(args.modes)
    opts = RunOptions(n_modes=RunOptions.n_modes if n is None else n, mode_numbers=numbers,
                      compare=not args.no_compare, images=not args.no_images)
    ctx = run_pipeline(scene_file(args), args.out, opts, Progress(enabled=False if args.quiet else None))
    if ctx.skipped and not args.quiet:
        print(f"flexgear: {skipped_text(ctx)}", file=sys.stderr)
    if not args.quiet:
        n_img = sum(1 for p, _ in ctx.files if p.endswith(".png"))
        anims = f", {len(ctx.animations)} animations" if ctx.animations else ""
        print(f"{ctx.scene.name}: {len(ctx.result.frequencies_hz)} modes, {n_img} images{anims} -> "
              f"{ctx.out_dir / 'index.html'} ({ctx.timings['total']:.1f} s)")
    return 0


def cmd_study(args) -> int:
    """``flexgear study``: every variant of a study file, on a local Dask cluster (default),
    an existing one (``--scheduler``) or in this process (``--serial``), into ``--out``."""
    import time

    from fe_components.meshing import default_cache_dir

    from .progress import Progress
    from .study.engine import run_study
    from .study.file import read_study
    from .study.out import study_to_dir

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


def cmd_export_elastodyn(args) -> int:
    """``flexgear export elastodyn``: the two-mass drivetrain as an ElastoDyn fragment, to
    ``--out`` (atomically, with a summary on stdout) or to stdout."""
    from ..analysis.two_mass import two_mass
    from ..scene.schema import load_scene
    from .export.elastodyn import fragment_text, write_fragment
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
    from .export.superelement import run
    return run(args)


def cmd_campbell(args) -> int:
    """``flexgear campbell``: natural frequencies, excitation orders and their crossings over
    a speed range of the reference body (rpm): a table, ``--json``, or files in ``--out``."""
    from ..dynamics.campbell import campbell
    from ..scene.schema import load_scene
    from .report.campbell import campbell_json, campbell_to_dir, crossings_text

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
    from .report.frf import frequencies, frf_json, frf_to_dir, summary_text

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


def cmd_runup(args) -> int:
    """``flexgear runup``: :func:`cmd_simulate` of the scene with the run-up's drive
    (:mod:`assembly.dynamics.runup`), its length from the speed range, rate and settling time."""
    from ..dynamics.runup import runup_length, runup_simulation
    from ..scene.tables import with_simulation

    flags = {"speed_range": "--speed-range", "rate": "--rate", "settle": "--settle", "bandwidth": "--bandwidth",
             "body": "--body", "track": "--track"}
    with api_flags(flags):
        args.t_end = runup_length(args.speed_range, args.rate, args.settle)
    args.speed = None

    def prepare(scene):
        if args.track is not None:
            with api_flags(flags):
                check.one_of("track", args.track, [b.name for b in scene.expanded().bodies])
        ref = args.track or args.body or next((b.name for b in scene.bodies if b.role == "rotor"), None)
        if ref is not None and args.output is not None and f"speed:{ref}" not in args.output:
            args.output = [*args.output, f"speed:{ref}"]            # the order analysis tracks it
        with api_flags(flags):
            return with_simulation(scene, runup_simulation(scene, args.speed_range, args.rate, args.body,
                                                           args.bandwidth, args.settle, args.track))
    return cmd_simulate(args, prepare, lambda r, scene, work: runup_report(r, scene, work, args.track))


def runup_report(r, scene, work, track=None):
    """(file names, sections of index.html) of a run-up's order analysis (:mod:`assembly.app.report.runup`,
    :func:`assembly.dynamics.runup_orders.run_orders`): every load tracked against the recorded
    speed of ``track`` (default the reference) over the ramp, the passages with the model's modes
    -- a record too short for it is said on the page, the run kept (the life tables of the ramp
    are the run's own, :mod:`assembly.app.report.life`)."""
    from ..dynamics.runup_orders import run_orders
    from ..errors import SceneError
    from .report.page import Section, link, para
    from .report.runup import runup_files

    try:
        got = run_orders(r, scene, track)
    except SceneError as exc:
        log.warning("orders of the run-up not tracked: %s", exc)
        return [], [Section("Orders of the run-up", para(f"Orders of the run-up not tracked: {exc}"), "Orders")]
    if got is None:
        return [], []
    ref, _, ro, modes = got
    top = max((o for o in ro.orders.values()), default=1.0) * abs(r.outputs[f"speed:{ref}"]).max() / (2 * math.pi)
    files = runup_files(ro, work, scene.name, [f for f, _ in modes], 1.1 * top, ref)
    return files, [Section("Orders of the run-up", f"<p>{link('orders.html', 'Orders of the run-up')}: "
                                                   f"{len(ro.passages)} resonance passages ({link('passages.csv')})."
                                                   "</p>", "Orders")]


def cmd_simulate(args, prepare=None, report=None) -> int:
    """``flexgear simulate``: time-domain run: a summary, ``--json`` or files in ``--out``; a
    run that stops keeps its partial result (:func:`_stopped`) and exits with 1. With ``--out``
    and no ``--json`` the histories stream into the staged folder as the run goes, and the
    summary alone (neither) keeps only the statistics: memory flat in ``--t-end``
    (:mod:`assembly.app.report.simulate`). ``--json`` prints every step, so it holds them."""
    from ..dynamics.simulate import simulate
    from ..dynamics.transient import Diverged, check_history
    from ..scene.schema import load_scene
    from .output import staged_output, writing
    from .progress import Progress
    from .report.simulate import H5_PARTIAL, sim_files, sim_to_dir, summary_text

    flags = {"dt": "--dt", "t_end": "--t-end"}
    # a run-up's order analysis reads the whole histories: they stay in memory
    stream = args.out is not None and not args.json and report is None
    summary_only = args.out is None and not args.json and report is None
    with api_flags(flags):          # the run's length against memory, before the scene is read
        n_steps = check_history(args.dt, args.t_end, len(args.output or []), streaming=stream or summary_only)
    window = getattr(args, "window", None)
    if window is not None:
        with api_flags({"window": "--window"}):
            t0 = check.number("window", window[0], "s", ge=0.0)
            t1 = check.number("window", window[1], "s")
            if not (t0 < t1 <= args.t_end):
                raise check.refuse("window", list(window), f"must lie in the record, 0 <= T0 < T1 <= {args.t_end:g} s")
    path = scene_file(args)
    scene = load_scene(path)
    if prepare is not None:
        scene = prepare(scene)
    progress = Progress(enabled=False if args.quiet or args.json else None)
    with holding_out(args), (staged_output(Path(args.out)) if stream else nullcontext()) as work:
        with (writing(Path(args.out), work, "simulation results") if stream else nullcontext()):
            stopped = None
            with progress.bar(f"{scene.name}: simulate", total=n_steps, unit="step") as bar:
                def tick(step, total, t):
                    bar.update(step - bar.n)
                    bar.set_postfix_str(f"t = {t:.4g} s", refresh=False)
                try:
                    with api_flags(flags):
                        r = simulate(scene, args.t_end, args.dt, args.output, base_dir=Path(path).parent,
                                     speed=args.speed, progress=tick, full_fe=args.unreduced,
                                     history=work / H5_PARTIAL if stream else None, arrays=not summary_only)
                except Diverged as exc:
                    stopped = exc
            if stopped is not None:
                return _stopped(args, stopped, scene.name, path, work)
            extra = None if report is None else (lambda w: report(r, scene, w))
            to_dir = (lambda: sim_files(r, work, scene.name, path, window)) if stream else (
                lambda: sim_to_dir(r, args.out, scene.name, path, window, extra))
            return _emit(args, to_dir, r.as_json, f"{scene.name}: {r.steps} steps, {len(r.statistics)} outputs",
                         lambda: summary_text(r, scene.name), indent=None)


def cmd_coupling(args) -> int:
    """``flexgear coupling``: the coupled run against the one-way runs
    (:func:`assembly.dynamics.coupling.compare_coupling`): the verdicts, ``--json`` or the files
    of :mod:`assembly.app.report.coupling` in ``--out``."""
    from ..dynamics.coupling import compare_coupling
    from ..scene.schema import load_scene
    from .output import check_output_dir, staged_output, writing
    from .report.coupling import coupling_files, coupling_json

    path = scene_file(args)
    scene = load_scene(path)
    with holding_out(args):
        with api_flags({"dt": "--dt", "t_end": "--t-end", "tooth_force": "--tooth-force",
                        "bearing_axial": "--bearing-axial", "t_skip": "--skip", "segment": "--segment"}):
            c = compare_coupling(scene, args.t_end, args.dt, args.tooth_force, args.bearing_axial,
                                 Path(path).parent, args.skip, args.segment, fidelity=args.fidelity)

        def to_dir():
            out = Path(args.out).absolute()
            check_output_dir(out)
            with staged_output(out) as work, writing(out, work, "coupling results"):
                coupling_files(c, work, scene.name, scene.band)
        return _emit(args, to_dir, lambda: coupling_json(c, scene.name),
                     f"{scene.name}: coupled against one-way, {len(c.peaks)} peaks", lambda: "\n".join(c.verdicts))


def _stopped(args, exc, scene_name: str, path: str, work=None) -> int:
    """A run that stopped (``exc``: :class:`~assembly.dynamics.transient.Diverged`): its
    partial result into ``--out`` as a complete one would go, marked partial
    (:func:`~assembly.app.report.simulate.sim_to_dir`; into the staged folder ``work`` where
    it streamed), else nowhere; ``--json`` or, without ``--out``, the summary on stdout; the
    reason in one line on stderr; exit code 1."""
    from .output import OutputDirError
    from .report.simulate import h5_name, sim_files, sim_to_dir, summary_text

    p = exc.partial
    kept = "is not kept: give --out DIR to keep it"
    if work is not None:            # streamed: an error writing the rest is the command's (exit 2)
        sim_files(p, work, scene_name, path)
        kept = f"is in {Path(args.out) / h5_name(p)} (marked partial)"
    elif args.out is not None:
        try:
            sim_to_dir(p, args.out, scene_name, path)
            kept = f"is in {Path(args.out) / h5_name(p)} (marked partial)"
        except OutputDirError as err:
            kept = f"could not be written: {err}"
    if args.json:
        _print_json(p.as_json(), None)
    elif args.out is None:
        print(summary_text(p, scene_name))
    print(f"flexgear: error: run stopped: {exc}; the partial result (to t = {p.t_last_s:.6g} s) {kept}",
          file=sys.stderr)
    return 1


def cmd_part(args) -> int:
    """``flexgear part``: one part checked alone (mass properties, free-free modes, interfaces)."""
    from .report.part import run
    return run(args)


def cmd_demo(args) -> int:
    from ..analysis.modal import solve_modes
    from ..model.assemble import assemble
    from ..scene.schema import load_scene, shipped_scenes
    from .report.tables import modes_table

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


def main(argv=None) -> int:
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as exc:                  # --help (0) or a usage error (2), already printed
        return int(exc.code or 0)
    level = logging.WARNING if args.verbose == 0 else (logging.INFO if args.verbose == 1 else logging.DEBUG)
    logging.basicConfig(level=level, format="%(levelname)s %(name)s: %(message)s")
    # scikit-fem logs each form it assembles at INFO (40 lines a flexible body): -vv shows them
    logging.getLogger("skfem").setLevel(level if args.verbose >= 2 else max(level, logging.WARNING))
    from .signals import signal_handler

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


def build_parser() -> argparse.ArgumentParser:
    p = Parser(prog="flexgear", description="Gearbox and drivetrain dynamics (SI units).")
    p.add_argument("-v", "--verbose", action="count", default=0, help="log progress (-vv: debug, and scikit-fem's assembly lines)")
    p.add_argument("--cache-dir", metavar="DIR", default=None,
                   help="folder of generated meshes and reductions (flexible bodies; default $FLEXGEAR_CACHE_DIR, "
                        "else $XDG_CACHE_HOME/flexgear or ~/.cache/flexgear)")
    sub = p.add_subparsers(dest="cmd", required=True)
    add_run(sub, cmd_run)
    add_study(sub, cmd_study)
    add_campbell(sub, cmd_campbell)
    add_frf(sub, cmd_frf)
    add_simulate(sub, cmd_simulate)
    add_runup(sub, cmd_runup)
    add_coupling(sub, cmd_coupling)
    add_export(sub, cmd_export_elastodyn, cmd_export_superelement)
    add_part(sub, cmd_part)
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
    c.set_defaults(func=cmd_compare, check=lambda a: at_least(a.modes, "--modes", 0))
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


if __name__ == "__main__":
    sys.exit(main())
