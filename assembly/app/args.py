"""The command line's arguments: the parser of every subcommand and the checks of their
values (a number or a name checked like a scene value, before the command reads its scene;
an error the Python API raises about one of its arguments named by the flag that set it).
"""
from __future__ import annotations

import argparse
import importlib
import os
import sys
from contextlib import contextmanager

from .errors import UsageError

SCENE_HELP = "scene TOML file (or the name of a shipped example)"


OUT_HELP = ("output folder, replaced as a whole when the run succeeds (never half-written); files you "
            "added to an earlier result are carried over")


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


def at_least(value: int, flag: str, low: int) -> int:
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


def parse_modes(text: str) -> tuple:
    """``--modes`` of ``run``: ``"N"`` -> (N, None): the first N elastic modes in the band;
    ``"7,9,12-14"`` -> (None, (7, 9, 12, 13, 14)): these modes (1-based, as numbered in the
    mode table; a single mode as ``"7,"`` or ``"7-7"``). UsageError on anything else."""
    text = text.strip()
    if text.isdigit():
        return at_least(int(text), "--modes", 0), None
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


def add_study(sub, func) -> None:
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
    p.set_defaults(func=func)


def add_frf(sub, func) -> None:
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
    add_out_json(p, "frf.csv, frf.json, bode_NN.png, index.html")
    p.set_defaults(func=func)


def add_simulate(sub, func) -> None:
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
    add_window(p)
    add_out_json(p, "simulation.h5, trace_NN.png, spectrum_NN.png, summary.json, index.html")
    p.set_defaults(func=func)


def add_runup(sub, func) -> None:
    p = sub.add_parser("runup", help="run-up: the drivetrain driven through a speed range at a rate by a "
                                     "speed-controlled drive (flexgear simulate with [simulation.drive])")
    p.add_argument("scene", help=SCENE_HELP)
    p.add_argument("--speed-range", nargs=2, type=float, required=True, metavar=("RPM_FROM", "RPM_TO"),
                   help="speeds of the driven body, rpm")
    p.add_argument("--rate", type=float, required=True, metavar="RPM_S", help="ramp rate, rpm/s")
    p.add_argument("--dt", type=float, required=True, metavar="DT", help="time step, s")
    p.add_argument("--body", default=None, metavar="BODY", help="driven body (default the reference, role rotor)")
    p.add_argument("--bandwidth", type=float, default=10.0, metavar="HZ", help="the drive's servo bandwidth, Hz "
                                                                              "(default 10)")
    p.add_argument("--settle", type=float, default=1.0, metavar="S",
                   help="time held at each end of the range, s (default 1)")
    p.add_argument("--track", default=None, metavar="BODY",
                   help="the shaft whose revolutions count the orders (default the driven body)")
    p.add_argument("--output", action="append", metavar="OUT", help="as flexgear simulate's")
    p.add_argument("--unreduced", action="store_true", help="as flexgear simulate's")
    add_window(p)
    add_out_json(p, "simulation.h5, trace_NN.png, spectrum_NN.png, summary.json, index.html")
    p.set_defaults(func=func)


def add_coupling(sub, func) -> None:
    p = sub.add_parser("coupling", help="the drivetrain coupled in its turbine against one-way (load series from "
                                        "the two-mass drivetrain's turbine run): spectra and where they differ")
    p.add_argument("scene", help=SCENE_HELP + " (with a [turbine] table and its wind)")
    p.add_argument("--t-end", type=float, required=True, metavar="T", help="end time, s")
    p.add_argument("--dt", type=float, required=True, metavar="DT", help="time step, s")
    p.add_argument("--tooth-force", default=None, metavar="OUT",
                   help="tooth force output (default the first mesh's force:MESH)")
    p.add_argument("--bearing-axial", default=None, metavar="OUT",
                   help="bearing load output (default force:BEARING:z of the first bearing with an axial spring)")
    p.add_argument("--skip", type=float, default=None, metavar="T0",
                   help="start left out of the spectra, s (default 10 %% of --t-end)")
    p.add_argument("--segment", type=float, default=10.0, metavar="S",
                   help="Welch segment, s (default 10; frequency resolution 1/S)")
    p.add_argument("--fidelity", choices=("torsional", "rigid", "flexible"), default=None,
                   help="fidelity of the detailed drivetrain (default the scene's)")
    add_out_json(p, "index.html, coupling.json, peaks.csv, spectrum_NN.png")
    p.set_defaults(func=func)


def add_window(p) -> None:
    """``--window T0 T1``: the part of the record the spectra are taken of."""
    p.add_argument("--window", nargs=2, type=float, default=None, metavar=("T0", "T1"),
                   help="the spectra of the record from T0 to T1 s only (start-up transients left out)")


def add_out_json(p, files: str) -> None:
    """``--out DIR`` (writing ``files``), ``--json`` and ``--quiet`` of an analysis command."""
    p.add_argument("--out", default=None, metavar="DIR", help=f"{OUT_HELP} ({files})")
    p.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    p.add_argument("--quiet", "-q", action="store_true", help="do not announce the scene file")


def add_campbell(sub, func) -> None:
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
    add_out_json(p, "campbell.png, crossings.csv, campbell.json, index.html")
    p.set_defaults(func=func)


def add_export(sub, elastodyn, superelement) -> None:
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
    e.set_defaults(func=elastodyn)
    s = what.add_parser("superelement", help="a flexible body's reduced K, M and DOF map (local axes): "
                                             "<DIR>/<body>.npz and Nastran DMIG <DIR>/<body>.dmig")
    s.add_argument("scene", help=SCENE_HELP)
    s.add_argument("--body", required=True, metavar="NAME", help="the flexible body (e.g. stage.carrier)")
    s.add_argument("--out", required=True, metavar="DIR", help="folder of the files (created if missing)")
    s.add_argument("--format", default="npz,dmig", metavar="LIST", help="npz, dmig or npz,dmig (default)",
                   type=lambda t: importlib.import_module("assembly.app.export.superelement").parse_formats(t))
    s.add_argument("--quiet", "-q", action="store_true", help="do not announce the scene file")
    s.set_defaults(func=superelement)


def add_part(sub, func) -> None:
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
    p.set_defaults(func=func, check=lambda a: (at_least(a.modes, "--modes", 1), a.modes <= 100 or too_many(a.modes)))


def too_many(modes: int):
    raise UsageError(f"--modes = {modes}: must be in 1..100")


def add_run(sub, func) -> None:
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
    p.set_defaults(func=func, check=lambda a: parse_modes(a.modes))


class Parser(argparse.ArgumentParser):
    """argparse with its errors (unknown choice, missing argument) in one line, exit 2, like
    every other user error of the command line (no usage block: ``--help`` has it)."""

    def error(self, message):
        self.exit(2, f"flexgear: error: {self.prog.removeprefix('flexgear').strip() or 'flexgear'}: {message} "
                     f"(see {self.prog} --help)\n")


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
