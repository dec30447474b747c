"""Where each part of an expanded scene came from: the table path a user wrote, for messages.

A scene's stages and beam shafts expand into bodies, bearings and meshes of their own
(:meth:`assembly.scene.tables.Scene.expanded`); an error about one of those names the table that
made it -- ``stages[0].planets``, ``shafts[1].stations[0]``, ``stages[0].variation_ring`` --
never an internal name the user did not write.
"""
from __future__ import annotations

from .shafts import station_body

#: A stage member's role -> the table of the stage that describes it.
_STAGE_TABLE = {"sun": "sun", "ring": "ring", "carrier": "carrier", "planet": "planets"}


def body_origins(scene, expanded) -> dict:
    """Body name -> the path of the table that made it: ``bodies[i]``, a shaft's station
    (``shafts[i].stations[j]``), or the member table of the stage (``stages[i].sun``,
    ``.ring``, ``.carrier``, ``.planets``)."""
    origin = {b.name: f"bodies[{i}]" for i, b in enumerate(scene.bodies)}
    for i, s in enumerate(scene.shafts):
        for j, st in enumerate(s.stations):
            origin.setdefault(station_body(s, st), f"shafts[{i}].stations[{j}]")
    for i, st in enumerate(scene.stages):
        for b in expanded.bodies:
            if b.stage == st.name and b.name not in origin:
                origin[b.name] = f"stages[{i}].{_STAGE_TABLE[b.role]}"
    return origin


def element_paths(scene, expanded, key: str, origin: dict, attr: str):
    """(path, item) of every bearing or mesh of the expanded scene: ``key[i]`` for the
    user's own tables; for a stage's, the bearing table of its member
    (``stages[0].planets.bearing``) or the stage itself (a mesh: ``stages[0]``)."""
    own = len(getattr(scene, key))
    for i, item in enumerate(getattr(expanded, key)):
        if i < own:
            yield f"{key}[{i}]", item
        else:
            member = origin[getattr(item, attr)]
            yield (f"{member}.bearing" if key == "bearings" else member.split(".")[0]), item


def stage_mesh_side(expanded, mesh) -> str:
    """"ring" for a stage's planet-ring mesh, else "sun" (its sun-planet mesh): the side whose
    ``variation_<side>`` and contact ratio belong to it, read from the roles of its gears."""
    roles = {b.name: b.role for b in expanded.bodies}
    return "ring" if "ring" in (roles.get(mesh.gear1), roles.get(mesh.gear2)) else "sun"
