"""``flexgear`` command line: modes, demo, bench.

Bad input ends in one line on stderr naming the scene path and value, exit code 2.
"""
from __future__ import annotations

import argparse
import json
import logging
import sys

log = logging.getLogger("flexgear")


def _user_errors():
    from .errors import MechanismError, SceneError
    from .pipeline import OutputDirError
    errs = [SceneError, MechanismError, OutputDirError]
    try:
        from fe_components.errors import GeometryError
        errs.append(GeometryError)
    except ImportError:
        pass
    try:
        from cms.errors import ReductionError
        errs.append(ReductionError)
    except ImportError:
        pass
    return tuple(errs)


def cmd_modes(args) -> int:
    from .modal import solve_modes
    from .model import assemble
    from .report import modes_json, modes_table
    from .toml_io import load_scene

    scene = load_scene(args.scene)
    res = solve_modes(assemble(scene))
    if args.json:
        json.dump(modes_json(res), sys.stdout, indent=1)
        sys.stdout.write("\n")
    else:
        print(modes_table(res, title=f"{scene.name}  ({args.scene})"))
    return 0


def cmd_compare(args) -> int:
    from .compare import compare, comparison_table
    from .toml_io import load_scene

    scene = load_scene(args.scene)
    c = compare(scene, n_rows=args.modes)
    if args.json:
        json.dump({"scene": scene.name, "units": {"frequency": "Hz"}, "frequencies_hz": c.frequencies(),
                   "pairs": c.rows, "timings": c.timings}, sys.stdout, indent=1)
        sys.stdout.write("\n")
    else:
        print(f"{scene.name}  ({args.scene})")
        print(comparison_table(c))
    return 0


def cmd_demo(args) -> int:
    from .modal import solve_modes
    from .model import assemble
    from .report import modes_table
    from .toml_io import load_scene, shipped_scenes

    for p in shipped_scenes():
        scene = load_scene(p)
        print(modes_table(solve_modes(assemble(scene)), title=f"== {scene.name}  ({p.name})"))
        print()
    return 0


def cmd_bench(args) -> int:
    import importlib
    targets = {"fe": "fe_components.bench", "cms": "cms.bench", "flex": "assembly.bench_flex"}
    names = list(targets) if args.what == "all" else [args.what]
    for name in names:
        mod = importlib.import_module(targets[name])
        rc = mod.main(args.rest)
        if rc:
            return rc
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="flexgear", description="Gearbox and drivetrain dynamics (SI units).")
    p.add_argument("-v", "--verbose", action="count", default=0, help="log progress (-vv: debug)")
    sub = p.add_subparsers(dest="cmd", required=True)
    from .pipeline import add_run_parser
    from .sweep import add_sweep_parser
    add_run_parser(sub)
    add_sweep_parser(sub)
    m = sub.add_parser("modes", help="eigenfrequencies and mode table of a scene")
    m.add_argument("scene", help="scene TOML file (or the name of a shipped example)")
    m.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    m.set_defaults(func=cmd_modes)
    c = sub.add_parser("compare", help="torsional, rigid and flexible variants side by side (MAC-paired)")
    c.add_argument("scene", help="scene TOML file (or the name of a shipped example)")
    c.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    c.add_argument("--modes", type=int, default=20, help="rows of the table (default 20)")
    c.set_defaults(func=cmd_compare)
    d = sub.add_parser("demo", help="run the shipped example scenes")
    d.add_argument("--out", default="results", help="output folder")
    d.set_defaults(func=cmd_demo)
    b = sub.add_parser("bench", help="benchmarks (print tables; not tests)")
    b.add_argument("what", choices=["fe", "cms", "flex", "all"])
    b.add_argument("rest", nargs=argparse.REMAINDER, help="arguments passed to the benchmark")
    b.set_defaults(func=cmd_bench)
    return p


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    level = logging.WARNING if args.verbose == 0 else (logging.INFO if args.verbose == 1 else logging.DEBUG)
    logging.basicConfig(level=level, format="%(levelname)s %(name)s: %(message)s")
    try:
        return args.func(args)
    except _user_errors() as exc:
        print(f"flexgear: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
