"""Benchmark of ``flexgear runup``: one run-up through the command line, its wall time split into
the simulation, the order analysis, the life tables and the pictures, and its peak memory.

    python -m assembly.app.bench.runup [runup arguments]

runs ``flexgear runup`` with the arguments given (a scene and its flags; flags alone, such as
``--out DIR``, are added to :data:`DEFAULT`: the NREL 5 MW through its operating range,
docs/benchmarks.md "Run-up of the 5 MW") in this process, with a
timer around each part, and prints a markdown table: steps, simulated seconds, wall seconds of
each part, peak resident memory (``ru_maxrss``: the interpreter and imports included). The parts
are timed by wrapping the functions the command calls (module attributes, looked up at call
time), so the command runs unchanged:

* simulation: :func:`assembly.dynamics.simulate.simulate` (assembly, start, integration);
* history file: ``simulation.h5`` (:func:`assembly.app.report.simulate.write_h5`);
* spectra: the simulation's spectra and envelopes computed for its pictures (the rest of
  :func:`assembly.app.report.simulate.sim_files`);
* simulation images: ``trace_NN``, ``spectrum_NN``, ``spectrum_low_NN``, ``spectrogram_NN``;
* life: the life tables counted (:func:`assembly.dynamics.life_tables.life_result`: every
  output's rainflow, DELs, LDD and LRD, every bearing's L10 and every gear's damage: the default
  scene rates them all with placeholder ratings, :func:`rated_scene`), and their files
  (:func:`assembly.app.report.life.life_files`);
* orders: :func:`assembly.dynamics.runup_orders.runup_orders` (order maps, cuts, passages);
* order images: ``orders_NN.png``, ``passages.csv``, ``orders.html``
  (:func:`assembly.app.report.runup.runup_files`);
* run-up report, other: the model's modes for the passages, the excitation orders.

Beside them, from the run's ``summary.json``: its steps, simulated seconds, outputs and the
integration's own wall time and steps per second (``info``).
"""
from __future__ import annotations

import functools
import importlib
import json
import resource
import sys
import tempfile
import time
from pathlib import Path

#: Outputs of the default run: the main-shaft torque, every mesh force, every bearing force.
MESHES = ("stage3", *(f"stage{s}.{m}" for s in (1, 2) for p in range(3) for m in (f"sun-planet{p}",
                                                                                    f"planet{p}-ring")))
BEARINGS = ("INP-A", "INP-B", "PLC-A", "PLC-B", "IMS-PLC-A", "IMS-PLC-B", "IMS-A", "IMS-B", "IMS-C", "HS-A", "HS-B",
            "HS-C", "generator bearings", *(f"stage{s}.planet{p}.bearing" for s in (1, 2) for p in range(3)))
#: The default run (docs/benchmarks.md, "Run-up of the 5 MW"); ``--out`` is added if missing.
DEFAULT = ["nrel5mw_transient", "--speed-range", "6.9", "12.1", "--rate", "0.2", "--dt", "2.5e-5", "--settle", "2",
           "--track", "generator", "--output", "torque:main_shaft",
           *(a for m in MESHES for a in ("--output", f"force:{m}")),
           *(a for b in BEARINGS for a in ("--output", f"force:{b}"))]

#: Placeholder ratings of the default run's life tables (not published for this gearbox: they
#: time the tables of every bearing and gear, they rate nothing): C (N) and p of every bearing,
#: T_ref (N m), N_ref and the slope of every gear.
BEARING_RATING = (1.0e7, 10.0 / 3.0)
GEAR_RATING = (1.0e5, 3.0e6, 6.2)


def rated_scene(folder: Path, scene: str = "nrel5mw_transient") -> Path:
    """A variant of the shipped ``scene`` written into ``folder`` whose ``[simulation.life]`` rates
    every bearing with a spring in both radial directions and both gears of every mesh
    (:data:`BEARING_RATING`, :data:`GEAR_RATING`: placeholders)."""
    from ...dynamics.frf_channels import bearing_directions
    from ...model.assemble import assemble
    from ...scene.schema import load_scene, resolve_scene_path

    model = assemble(load_scene(scene))
    c, p = BEARING_RATING
    t_ref, n_ref, k = GEAR_RATING
    bearings = [f'{{ bearing = "{el.name}", rating = {c:g}, exponent = {p!r} }}' for el in model.elements
                if el.kind == "bearing" and {"x", "y"} <= set(bearing_directions(model, el))]
    gears = [f'{{ mesh = "{m.name}", gear = "{g}", torque_ref = {t_ref:g}, cycles_ref = {n_ref:g}, slope = {k:g} }}'
             for m in model.scene.meshes for g in (m.gear1, m.gear2)]
    path = Path(folder) / f"{scene}_rated.toml"
    path.write_text(f'extends = "{resolve_scene_path(scene).as_posix()}"\n'
                    f'name = "{scene}, every bearing and gear rated"\n'
                    f'[set."simulation.life"]\nbearings = [{", ".join(bearings)}]\ngears = [{", ".join(gears)}]\n',
                    encoding="utf-8")
    return path


#: (module, function, part) timed.
PARTS = (("assembly.dynamics.simulate", "simulate", "simulation"),
         ("assembly.dynamics.simulate", "life_result", "life"),
         ("assembly.app.report.life", "life_files", "life files"),
         ("assembly.app.report.simulate", "write_h5", "history file"),
         ("assembly.app.report.simulate", "sim_files", "_sim_files"),
         ("assembly.app.plots", "plot_time_trace", "simulation images"),
         ("assembly.app.plots", "plot_spectrum", "simulation images"),
         ("assembly.app.plots", "plot_spectrogram", "simulation images"),
         ("assembly.dynamics.runup_orders", "runup_orders", "orders"),
         ("assembly.app.report.runup", "runup_files", "order images"),
         ("assembly.app.cli", "runup_report", "_report"))


def timed(parts: dict) -> list:
    """Wrap the functions of :data:`PARTS`, adding their wall seconds to ``parts``; returns
    (module, name, function) of the originals, for :func:`untimed`."""
    originals = []
    for mod, name, part in PARTS:
        m = importlib.import_module(mod)
        f = getattr(m, name)
        originals.append((m, name, f))

        def wrapper(*a, _f=f, _part=part, **k):
            t0 = time.perf_counter()
            try:
                return _f(*a, **k)
            finally:
                parts[_part] = parts.get(_part, 0.0) + time.perf_counter() - t0
        setattr(m, name, functools.wraps(f)(wrapper))
    return originals


def untimed(originals: list) -> None:
    """Put back the functions :func:`timed` wrapped."""
    for m, name, f in reversed(originals):
        setattr(m, name, f)


def main(argv=None) -> int:
    from ..cli import main as cli_main

    argv = list(argv or [])
    args = argv if argv and not argv[0].startswith("-") else [*DEFAULT, *argv]     # flags alone: added to DEFAULT
    if "--out" not in args:
        args += ["--out", "runup-bench"]
    parts: dict = {}
    with tempfile.TemporaryDirectory() as tmp:
        if args[0] == DEFAULT[0]:                   # the default scene: every bearing and gear rated
            args = [str(rated_scene(Path(tmp), args[0])), *args[1:]]
        originals = timed(parts)
        t0 = time.perf_counter()
        try:
            rc = cli_main(["runup", *args, "--quiet"])
        finally:
            untimed(originals)
        wall = time.perf_counter() - t0
    parts["simulation"] = parts.get("simulation", 0.0) - parts.get("life", 0.0)     # the life tables apart
    # sim_files holds the pictures, the history file and the run-up's report: the rest is the spectra
    parts["spectra"] = parts.pop("_sim_files", 0.0) - sum(parts.get(k, 0.0) for k in
                                                           ("history file", "simulation images", "_report"))
    report = parts.pop("_report", 0.0)
    parts["run-up report, other"] = report - sum(parts.get(k, 0.0) for k in ("orders", "order images"))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    out = Path(args[args.index("--out") + 1])
    if (out / "summary.json").exists():
        s = json.loads((out / "summary.json").read_text())
        info = s.get("info", {})
        print(f"{s.get('steps')} steps, {s.get('t_end_s')} s simulated, {len(s.get('outputs', {}))} outputs; "
              f"integration {info.get('wall_s', float('nan')):.1f} s, {info.get('steps_per_s', float('nan')):.0f} "
              f"steps/s; warnings: {s.get('warnings')}\n")
    print("| part | wall [s] |\n|---|---|")
    for k, v in parts.items():
        print(f"| {k} | {v:.1f} |")
    print(f"| total (command) | {wall:.1f} |\n\npeak RSS {peak:.0f} MB; exit {rc}")
    return rc


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
