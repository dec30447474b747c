"""Benchmark (not a test): the cost of the turbine in the loop per time step.

``flexgear bench turbine [--t-end 60] [--dt 0.00625]`` runs ``nrel5mw_turbine`` (60 s of IEC
class B turbulence at 16 m/s, ROSCO called every sample, the rotor's aerodynamics on the
surface, gravity) with the gearbox bodies rigid and with the flexible carriers and wheel of
``nrel5mw_flexible``, and beside each the same drivetrain, model and step without the turbine
(the rated rotor torque and generator torque held constant, as ``nrel5mw_transient`` drives it
without its mesh laws): the time per step of both, their ratio (the coupling's cost), the
controller's calls, and whether the compiled step ran. Wall times are whole runs (the wind
generated, the deck read, the model's start); the time per step is the integration's alone.
Prints one Markdown table.
"""
from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from .drivetrain import machine

#: The turbine of nrel5mw_turbine.toml, on another drivetrain (``extends``).
TURBINE = """
[set]
band_hz = 15.0
[set.damping]
class_ratios = {{ rotational = 0.05 }}
[set.simulation]
speed = 1.2671
{tables}
"""
WITH = """[set.turbine]
openfast = "rosco"
tilt_deg = 5.0
gravity = true
pitch_deg = 12.01
wind = { speed = 16.0, turbulence = "B", seed = 1 }
"""
# the rated operating point of nrel5mw_transient.toml: rotor torque = generator torque x ratio
WITHOUT = """[set.simulation.generator]
torque = 43093.55
[[set.simulation.loads]]
body = "rotor"
value = 4.152243e6
"""


def scene_file(folder: Path, base: str, turbine: bool) -> Path:
    f = folder / f"{base}_{'turbine' if turbine else 'alone'}.toml"
    f.write_text(f'extends = "{base}.toml"\nname = "{base} {"in its turbine" if turbine else "alone"}"\n'
                 + TURBINE.format(tables=WITH if turbine else WITHOUT).replace("{{", "{").replace("}}", "}"))
    return f


def one(path: Path, t_end: float, dt: float) -> dict:
    from ...dynamics.simulate import simulate
    from ...model.assemble import assemble
    from ...scene.schema import load_scene
    scene = load_scene(path)
    model = assemble(scene)
    t0 = time.perf_counter()
    r = simulate(model, t_end, dt, arrays=False, base_dir=path.parent)
    wall = time.perf_counter() - t0
    # per step: the integration's own time (the wind's generation, the deck, the controller's
    # loading and the static start are in the run's wall time, not in it)
    return {"dofs": r.info["dofs"], "steps": r.steps, "wall_s": wall, "us_per_step": 1e6 * r.info["wall_s"] / r.steps,
            "compiled": r.info.get("compiled"), "calls": r.info.get("controller_calls", 0)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="flexgear bench turbine", description=__doc__.split("\n\n")[0])
    ap.add_argument("--t-end", type=float, default=60.0)
    ap.add_argument("--dt", type=float, default=0.00625)
    ap.add_argument("--bases", nargs="+", default=["nrel5mw", "nrel5mw_flexible"])
    a = ap.parse_args(argv)
    print(f"# The turbine in the loop: {a.t_end:g} s at dt = {a.dt:g} s\n\n{machine()}\n")
    print("| drivetrain | DOFs | steps | with turbine [s] | us/step | compiled | controller calls | "
          "without [s] | us/step | compiled | ratio |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory(prefix="flexgear-bench-turbine-") as tmp:
        for base in a.bases:
            w = one(scene_file(Path(tmp), base, True), a.t_end, a.dt)
            o = one(scene_file(Path(tmp), base, False), a.t_end, a.dt)
            print(f"| {base} | {w['dofs']} | {w['steps']} | {w['wall_s']:.2f} | {w['us_per_step']:.1f} | "
                  f"{w['compiled']} | {w['calls']} | {o['wall_s']:.2f} | {o['us_per_step']:.1f} | {o['compiled']} | "
                  f"{w['us_per_step'] / o['us_per_step']:.2f} |", flush=True)
    return 0
