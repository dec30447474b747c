"""The bodies a scene's fields may name, every field that names one, and the nearest name
to one the scene does not have.

A scene's bodies are its own ``[[bodies]]``, the members each planetary stage makes
(``<stage>.sun``, ``.ring``, ``.carrier`` and ``.planet0`` ... ``.planet<count - 1>``,
:mod:`assembly.scene.planetary`) and the stations of its beam shafts (``<shaft>.<station>``,
:mod:`assembly.scene.shafts`). All of them follow from the tables as written, before any gear
number is derived, any body placed or any stage expanded, so a name that does not exist is
refused before a rule that needs the body reads it (a misspelt ``gear2`` used to surface as
a missing base radius of the other gear).
"""
from __future__ import annotations

import difflib

from .tables import HOUSING

#: Longest list of the scene's bodies an error message spells out (beyond it: the count).
LISTED = 12


def scene_body_names(scene) -> list[str]:
    """Every body name of ``scene`` (its own bodies, stage members, shaft stations), in
    the order the expanded scene holds them."""
    names = [b.name for b in scene.bodies]
    for st in scene.stages:
        names += [f"{st.name}.{role}" for role in ("sun", "ring", "carrier")]
        names += [f"{st.name}.planet{i}" for i in range(st.planets.count)]
    for s in scene.shafts:
        if s.name is not None:
            names += [f"{s.name}.{station.name}" for station in s.stations]
    return names


def body_references(scene):
    """``(path, name, housing allowed)`` of every field of ``scene`` that names a body:
    bodies' and bearings' frames, bearings, meshes, shafts, fixed DOFs, stages placed
    coaxial with a body, the static load cases (input, output, point loads, supports) and
    the ``[turbine]`` table (rotor, generator) and the ``[simulation]`` table (reference, loads,
    generator, brake, stress points, unbalances)."""
    for i, b in enumerate(scene.bodies):
        yield f"bodies[{i}].frame", b.frame, True
    for i, br in enumerate(scene.bearings):
        yield f"bearings[{i}].body", br.body, False
        if br.frame is not None:
            yield f"bearings[{i}].frame", br.frame, True
    for i, m in enumerate(scene.meshes):
        yield f"meshes[{i}].gear1", m.gear1, False
        yield f"meshes[{i}].gear2", m.gear2, False
    for i, s in enumerate(scene.shafts):
        yield f"shafts[{i}].body1", s.body1, False
        yield f"shafts[{i}].body2", s.body2, False
    for i, f in enumerate(scene.fixed):
        yield f"fixed[{i}].body", f.body, False
    for i, st in enumerate(scene.stages):
        if st.coaxial_with is not None:
            yield f"stages[{i}].coaxial_with", st.coaxial_with, False
    for path, lc in scene.load_cases():
        for role in ("input", "output"):
            if getattr(lc, role) is not None:
                yield f"{path}.{role}", getattr(lc, role), False
        for j, pl in enumerate(lc.forces):
            yield f"{path}.forces[{j}].body", pl.body, False
        for j, su in enumerate(lc.supports):
            yield f"{path}.supports[{j}].body", su.body, False
    tb = scene.turbine
    if tb is not None:
        for key in ("rotor", "generator"):
            if getattr(tb, key) is not None:
                yield f"turbine.{key}", getattr(tb, key), False
    sim = scene.simulation
    if sim is None:
        return
    if sim.reference is not None:
        yield "simulation.reference", sim.reference, False
    for j, ld in enumerate(sim.loads):
        yield f"simulation.loads[{j}].body", ld.body, False
    for key in ("generator", "brake"):
        table = getattr(sim, key)
        if table is not None and table.body is not None:
            yield f"simulation.{key}.body", table.body, False
    for j, p in enumerate(sim.points):
        yield f"simulation.points[{j}].body", p.body, False
    for j, u in enumerate(sim.unbalance):
        yield f"simulation.unbalance[{j}].body", u.body, False
    if sim.drive is not None and sim.drive.body is not None:
        yield "simulation.drive.body", sim.drive.body, False


def nearest(name: str, names) -> str | None:
    """The name of ``names`` most like ``name`` (difflib's similarity ratio, ignoring case;
    the first of equals), or None for no names."""
    best, score = None, -1.0
    for n in names:
        r = difflib.SequenceMatcher(None, name.lower(), n.lower()).ratio()
        if r > score:
            best, score = n, r
    return best


def unknown_body_reason(name: str, names: list, housing: bool = False) -> str:
    """Why ``name`` names no body: the nearest name the scene has and, for a short list,
    all of them."""
    have = names + [HOUSING] if housing else names
    if not have:
        return "no body of that name: the scene has no bodies"
    listed = f"the scene's bodies: {', '.join(have)}" if len(have) <= LISTED else f"{len(names)} bodies"
    return f"no body of that name; the nearest is {nearest(name, have)!r} ({listed})"
