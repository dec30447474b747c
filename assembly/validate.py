"""Whole-scene checks: names, references, frames, connectivity (SceneError with paths)."""
from __future__ import annotations

import math

import numpy as np

from .attach import bearing_point, component_masters, mesh_centers, shaft_points
from .errors import SceneError
from .geometry import unit


def _unique(items, path, attr="name"):
    seen = {}
    for i, it in enumerate(items):
        name = getattr(it, attr)
        if name is None:
            continue
        if name in seen:
            raise SceneError(f"{path}[{i}].{attr}", name, f"duplicate of {path}[{seen[name]}].{attr}")
        seen[name] = i


def validate_scene(scene) -> None:
    from .planetary import check_stage
    from .scene import HOUSING

    for i, st in enumerate(scene.stages):
        check_stage(st, f"stages[{i}]")
    _unique(scene.stages, "stages")
    for i, b in enumerate(scene.bodies):
        b.check(f"bodies[{i}]")
    for i, b in enumerate(scene.bearings):
        b.check(f"bearings[{i}]")
    for i, m in enumerate(scene.meshes):
        m.check(f"meshes[{i}]")
    for i, s in enumerate(scene.shafts):
        s.check(f"shafts[{i}]")
    for i, f in enumerate(scene.fixed):
        f.check(f"fixed[{i}]")
    if scene.band_hz is not None and not scene.band_hz > 0:
        raise SceneError("band_hz", scene.band_hz, "must be > 0 Hz")

    sc = scene.expanded()
    # Where did each expanded body come from (for error paths)?
    origin = {b.name: f"bodies[{i}]" for i, b in enumerate(scene.bodies)}
    for i, st in enumerate(scene.stages):
        for b in sc.bodies:
            if b.stage == st.name and b.name not in origin:
                origin[b.name] = f"stages[{i}]"
    names = {}
    for i, b in enumerate(sc.bodies):
        if b.name in names:
            raise SceneError(f"{origin.get(b.name, f'bodies[{i}]')}.name", b.name, "duplicate body name")
        names[b.name] = b
    if not names:
        raise SceneError("bodies", [], "a scene needs at least one body")

    def ref(path, name, allow_housing=False):
        if allow_housing and name == HOUSING:
            return
        if name not in names:
            raise SceneError(path, name, "no body of that name" + (" (or 'housing')" if allow_housing else ""))

    for i, b in enumerate(scene.bodies):
        ref(f"bodies[{i}].frame", b.frame, allow_housing=True)
    # Frames must form a tree rooted at the housing.
    for b in sc.bodies:
        seen, cur = {b.name}, b.frame
        while cur != HOUSING:
            if cur in seen:
                raise SceneError(f"{origin[b.name]}.frame", b.frame, "reference frames form a cycle")
            seen.add(cur)
            cur = names[cur].frame
    for i, br in enumerate(scene.bearings):
        ref(f"bearings[{i}].body", br.body)
        if br.frame is not None:
            ref(f"bearings[{i}].frame", br.frame, allow_housing=True)
            if br.frame == br.body:
                raise SceneError(f"bearings[{i}].frame", br.frame, "a bearing cannot join a body to itself")
    for i, m in enumerate(scene.meshes):
        ref(f"meshes[{i}].gear1", m.gear1)
        ref(f"meshes[{i}].gear2", m.gear2)
    for i, s in enumerate(scene.shafts):
        ref(f"shafts[{i}].body1", s.body1)
        ref(f"shafts[{i}].body2", s.body2)
    for i, f in enumerate(scene.fixed):
        ref(f"fixed[{i}].body", f.body)

    masters = component_masters(sc, origin)
    for b in sc.bodies:
        if b.fidelity == "flexible" and b.frame != HOUSING:
            raise SceneError(f"{origin[b.name]}.frame", b.frame, "a flexible body must live in the housing frame")
    for i, br in enumerate(sc.bearings):
        p = f"bearings[{i}]" if i < len(scene.bearings) else origin[br.body] + " bearing"
        bearing_point(br, names[br.body], masters, p)
    for i, s in enumerate(sc.shafts):
        shaft_points(s, names[s.body1], names[s.body2], masters, f"shafts[{i}]")
    for f in sc.fixed:
        if names[f.body].fidelity == "flexible":
            raise SceneError(f"{origin[f.body]}.fidelity", "flexible",
                             "fixed DOFs act on rigid bodies; hold a flexible body by a rigid bearing")

    # Infinite bearing stiffness is modelled as a constraint: only for a bearing acting at
    # the body's own position relative to its own frame.
    all_bearings = list(enumerate(scene.bearings)) + [(None, b) for b in sc.bearings[len(scene.bearings):]]
    for i, br in all_bearings:
        body = names[br.body]
        p = f"bearings[{i}]" if i is not None else origin[br.body] + " bearing"
        if np.any(np.isinf(br.diagonal())):
            if body.fidelity == "flexible" or body.component is not None:
                raise SceneError(f"{p}.k_radial", br.k_radial, "infinite stiffness is only supported for "
                                 "plain rigid bodies; give a component body a finite bearing")
            own_frame = br.frame is None or br.frame == body.frame
            at_body = br.position is None or np.allclose(br.position, body.position, rtol=0, atol=1e-12)
            if not (own_frame and at_body):
                raise SceneError(f"{p}.k_radial", br.k_radial,
                                 "infinite (rigid) stiffness is only supported for a bearing at the "
                                 "body's position to its own frame")

    for i, m in enumerate(sc.meshes):
        p = f"meshes[{i}]" if i < len(scene.meshes) else origin[m.gear1]
        b1, b2 = names[m.gear1], names[m.gear2]
        a1, a2 = unit(b1.axis), unit(b2.axis)
        if abs(abs(a1 @ a2) - 1) > 1e-9:
            raise SceneError(f"{p}.gear2", m.gear2, "gear axes are not parallel (only parallel-axis meshes)")
        c1, c2, _, _ = mesh_centers(m, b1, b2, masters, p)
        d = c2 - c1
        C = np.linalg.norm(d - (d @ a1) * a1)
        C_want = abs(m.base_radius1 + m.base_radius2) / math.cos(m.pressure_angle)
        if abs(C - C_want) > 1e-6 * C_want:
            raise SceneError(f"{p}.pressure_angle", m.pressure_angle,
                             f"centre distance {C:.9g} m between {m.gear1} and {m.gear2} does not "
                             f"match |r1 + r2|/cos(pressure_angle) = {C_want:.9g} m")

    if scene.load is not None:
        scene.load.check("load", names)

    # Every body must be connected to something.
    linked = set()
    for br in sc.bearings:
        linked.add(br.body)
        other = br.frame or names[br.body].frame
        if other != HOUSING:
            linked.add(other)
    for m in sc.meshes:
        linked.update((m.gear1, m.gear2))
    for s in sc.shafts:
        linked.update((s.body1, s.body2))
    for f in sc.fixed:
        linked.add(f.body)
    for b in sc.bodies:
        if b.name not in linked:
            raise SceneError(f"{origin[b.name]}.name", b.name,
                             "body is connected to nothing (no bearing, mesh, shaft or fixed DOF)")
