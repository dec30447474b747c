"""Which modes the run draws as its key pictures (fixed file names, docs/output.md).

* global torsional (``images/global_torsional.png``): the lowest elastic mode of class
  ``rotational`` and scope ``"global"`` (:func:`assembly.analysis.classify.classify_modes`) -- in a
  wind-turbine drivetrain the rotor against the generator;
* stage-local (``images/stage_local.png``): the lowest elastic mode whose scope is a stage,
  taken from the first of these tiers that has one: (1) a planetary stage, class rotational
  or translational (Lin & Parker's in-plane classes); (2) a planetary stage, any class;
  (3) any stage, any class.

Either is None when the scene has no such mode (no picture is drawn then).
"""
from __future__ import annotations

IN_PLANE = ("rotational", "translational")


def global_torsional_mode(infos, n_rigid: int):
    """0-based index of the lowest elastic rotational global mode, or None."""
    return next((mi.index for mi in infos if mi.index >= n_rigid and mi.mode_class == "rotational"
                 and mi.scope == "global"), None)


def stage_local_mode(infos, n_rigid: int, scene):
    """0-based index of the stage-local mode of the module doc's tiers, or None."""
    planetary = {b.stage for b in scene.bodies if b.role == "planet"}
    local = [mi for mi in infos if mi.index >= n_rigid and mi.scope not in (None, "global")]
    tiers = ([mi for mi in local if mi.scope in planetary and mi.mode_class in IN_PLANE],
             [mi for mi in local if mi.scope in planetary], local)
    for tier in tiers:
        if tier:
            return min(tier, key=lambda mi: mi.frequency_hz).index
    return None
