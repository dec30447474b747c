"""One planetary stage of a drivetrain as a scene of its own.

Lin & Parker (1999), "Analytical characterization of the unique properties of planetary gear
free vibration", J. Vib. Acoust. 121: the stage's sun, ring and carrier sit on bearings to the
housing (the ring usually held against rotation), the planets on bearings to the carrier. In a
whole drivetrain a member may instead float, or hang on shafts to the next stage; alone, such a
member needs a bearing the caller gives (e.g. the shaft's stiffness with its far end held).
The stage's classes (rotational, translational, planet) can then be checked inside a whole
drivetrain by comparing with the stage alone.
"""
from __future__ import annotations

import dataclasses
import math

from .. import arguments
from ..errors import SceneError
from .schema import convert
from .tables import SPLIT_STIFFNESSES, BearingSpec, Scene, scene_argument
from .validate import check_bearing

ROLES = ("sun", "ring", "carrier")


def stage_alone(scene: Scene, stage_name: str, bearings: dict | None = None, planar: bool = False) -> Scene:
    """The planetary stage ``stage_name`` of ``scene`` as a scene on its own: its sun, ring,
    carrier and planets with their bearings and meshes, nothing else of the scene (no other
    bodies, shafts or load cases). Members supported by a bearing or fixed keep their support;
    ``bearings`` ({"sun" | "ring" | "carrier": a bearing table, the dict of its stiffnesses in
    N/m and N m/rad as in TOML}) puts the named members on the given bearing to the housing
    instead, and must hold one for every floating member. ``planar``: every bearing of the stage (members' and planets') rigid axially and
    in tilt (``inf``), Lin & Parker's planar model. SceneError naming the field otherwise."""
    scene_argument("scene", scene)
    arguments.flag("planar", planar)
    stages = scene.as_given("stages")
    names = [st.name for st in stages]
    i = names.index(arguments.one_of("stage_name", stage_name, names, "planetary stage"))
    given = dict(arguments.optional(arguments.table, "bearings", bearings) or {})
    for role, b in given.items():
        if role not in ROLES:
            raise SceneError("bearings", role, f"a stage member is one of {list(ROLES)}")
        # a member's bearing table, as in TOML: {"k_radial": ..., "k_axial": ..., ...}
        given[role] = convert(BearingSpec, b, f"bearings.{role}", strict=True)
        check_bearing(given[role], f"bearings.{role}")
    st = stages[i]
    held = _planar if planar else (lambda b: b)
    changes = {"planets": dataclasses.replace(st.planets, bearing=held(st.planets.bearing))}
    for role in ROLES:
        m = getattr(st, role)
        if role in given:
            m = dataclasses.replace(m, support="bearing", bearing=given[role])
        elif m.support == "floating":
            raise SceneError(f"stages[{i}].{role}.support", m.support,
                             f"the stage alone has no shaft or other stage to hold its {role}: "
                             f"give bearings={{'{role}': {{'k_radial': ..., 'k_axial': ..., 'k_tilt': ...}}}}")
        changes[role] = dataclasses.replace(m, bearing=held(m.bearing)) if m.support == "bearing" else m
    if st.coaxial_with is not None:   # the body it is coaxial with stays behind: keep where it put it
        placed = scene.stages[i]
        changes.update(center=placed.center, axis=placed.axis, coaxial_with=None, axial_offset=None)
    return Scene(name=f"stage {stage_name} alone", description=f"stage {stage_name} of {scene.name}", stages=(dataclasses.replace(st, **changes),),
                 band_hz=scene.band_hz, fidelity=scene.fidelity)


def _planar(b: BearingSpec) -> BearingSpec:
    """``b`` rigid axially and in tilt (both tilt directions, given as one or per direction)."""
    tilt = {f: math.inf for f in SPLIT_STIFFNESSES["k_tilt"]} if b.k_tilt is None else {"k_tilt": math.inf}
    return dataclasses.replace(b, k_axial=math.inf, **tilt)
