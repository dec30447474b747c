"""The run report's frequency response: from a unit torque on the generator (the body of
``role = "generator"``) to the section torque at each planetary stage's sun output (every
shaft element attached to ``<stage>.sun``) and at the high-speed pinion (the shaft element
attached to the fastest body with teeth, by the speed ratios of the rigid-body mode), on
``FMIN_HZ`` - ``FMAX_HZ`` log spaced. Written as ``frf.csv`` and ``images/frf_generator.png``
(Bode, undamped natural frequencies dotted). Scenes without both roles or without stages
get none; undamped scenes a note (their FRF is infinite at every natural frequency).
"""
from __future__ import annotations

import logging

import numpy as np

from ...analysis.drivetrain import chain_ends, speed_ratios
from ...dynamics.frf import frequency_response
from ...errors import MechanismError
from ...model.damping import has_damping
from .frf import write_csv

log = logging.getLogger(__name__)

FMIN_HZ, FMAX_HZ, POINTS = 1.0, 1000.0, 400   # Hz, Hz, log-spaced points
IMAGE = "images/frf_generator.png"


def has_roles(scene) -> bool:
    """Whether ``scene``'s ``[[bodies]]`` have both roles "rotor" and "generator"."""
    roles = {b.role for b in scene.bodies}
    return {"rotor", "generator"} <= roles


def report_outputs(model, stages, rotor: str) -> list[str]:
    """``torque:SHAFT`` outputs: the shaft elements at each stage's sun, then the one at the
    fastest toothed body (|omega / omega_rotor| largest) that has a shaft; no repeats."""
    shafts = [el for el in model.elements if el.kind == "shaft"]
    names = [el.name for st in stages for el in shafts if f"{st.name}.sun" in el.bodies]
    toothed = {b for el in model.elements if el.kind == "mesh" for b in el.bodies}
    ratio = speed_ratios(model, rotor)
    for b in sorted(toothed, key=lambda b: -abs(ratio[b])):
        at = [el.name for el in shafts if b in el.bodies]
        if at:
            names.append(at[0])
            break
    return ["torque:" + n for n in dict.fromkeys(names)]


def step_frf(ctx, bar) -> None:
    """Pipeline step (:mod:`assembly.app.report.pipeline`): the FRF files and picture, or a note."""
    from ..plots import plot_bode

    sc = ctx.scene
    if not (sc.stages and has_roles(sc)):
        return
    if not has_damping(sc):
        ctx.notes.append(f"no frequency response ({IMAGE}, frf.csv): the scene has no damping")
        return
    rotor, generator = chain_ends(sc)
    try:
        outputs = report_outputs(ctx.model, sc.stages, rotor)
    except MechanismError as e:
        ctx.notes.append(f"no frequency response ({IMAGE}, frf.csv): {e}")
        return
    if not outputs:
        ctx.notes.append(f"no frequency response ({IMAGE}, frf.csv): no shaft carries the rotor's torque")
        return
    f = np.geomspace(FMIN_HZ, FMAX_HZ, POINTS)
    r = frequency_response(ctx.model, f"torque:{generator}", outputs, f)
    write_csv(r, ctx.add_file("frf.csv", f"frequency response from torque:{generator} to {', '.join(outputs)}: "
                                         "real, imaginary, magnitude, phase per Hz (CSV)"))
    plot_bode(f, r.outputs, ctx.add_file(IMAGE, "Bode plot of frf.csv (PNG)"),
              title=f"{sc.name}: torque:{generator} -> shaft torques", ylabel=r.units[outputs[0]],
              natural_hz=r.natural_hz, logx=True)
    ctx.plots.append((IMAGE, f"frequency response from a unit torque on {generator} to the shaft torques "
                             f"{', '.join(outputs)} ({FMIN_HZ:g}-{FMAX_HZ:g} Hz, {POINTS} points log; "
                             "dotted: undamped natural frequencies)"))
    log.info("run FRF: %d outputs in %.2f s", len(outputs), r.time_s)
