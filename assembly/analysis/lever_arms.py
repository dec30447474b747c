"""Bodies joined across a hair between their axes, and the field that put them there.

A shaft, or a bearing between two bodies, joins bodies that turn about parallel axes. When
those axis lines lie a hair apart -- more than the round-off of the coordinates
(:data:`assembly.mechanics.nullity.DROP_RTOL`), less than the alignment tolerance of a shaft
(:data:`assembly.scene.shafts.AXIS_TOLERANCE` of the model's size) -- their common rotation strains
the element's translational springs by the offset times the angle: a lever arm, and a
stiffness k delta^2 against a rotation that is free with the axes joined. The structure
then has one rigid-body mode less, and its place is taken by an "elastic" mode of
k delta^2 (1e-9 m on the quill of two_stage_quill.toml: 5e-7 Hz) that no eigen solve
resolves. :func:`hair_error` finds such an offset when a solve fails that way
(:mod:`assembly.analysis.resolution`): it counts the rigid-body modes again with each offset
removed (the moved body's motion taken at the element's point shifted by the offset) and,
when that restores a mode, names the field that placed the body -- a planetary stage's
``center`` -- with the offset and how to put the body on the axis exactly.
"""
from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

from ..errors import SceneError
from ..mechanics.nullity import coordinate_scale, rigid_body_count
from ..scene.shafts import AXIS_TOLERANCE

#: Stage members that sit at the stage's centre.
CENTRAL = ("sun", "ring", "carrier")


@dataclass(frozen=True)
class HairOffset:
    """Element ``index`` of a model joins ``moved``, whose axis line lies ``offset`` (m,
    normal to the axis) from the axis line of ``fixed``."""

    index: int
    fixed: str
    moved: str
    offset: np.ndarray

    @property
    def distance(self) -> float:
        return float(np.linalg.norm(self.offset))


def axis_line(bm) -> tuple[np.ndarray, np.ndarray]:
    """(a point, the unit direction) of the line a body model turns about: a rigid body's
    axis point, a flexible body's component origin, along its axis."""
    point = getattr(bm, "axis_point", None)
    if point is None:
        point = bm.origin
    return np.asarray(point, float), np.asarray(bm.axes, float)[:, 2]


def hair_offsets(model) -> list[HairOffset]:
    """The two-body elements of ``model`` with a translational spring whose bodies turn
    about parallel axes (AXIS_TOLERANCE) a hair apart: more than nothing, at most
    AXIS_TOLERANCE times the larger of their distance along the axis and the coordinates'
    magnitude. The moved body is the member of a planetary stage where one is (its stage's
    centre is typed; a body placed by a mesh or a coaxial stage is exact), else the second."""
    by_name = {b.name: b for b in model.scene.bodies}
    out = []
    for i, el in enumerate(model.elements):
        if len(el.bodies) != 2 or None in el.bodies or el.bodies[0] == el.bodies[1]:
            continue
        if not np.any(np.abs(el.B[el.k > 0][:, [0, 1, 2, 6, 7, 8]]).sum(axis=1) > 0):
            continue                           # no translational spring: no lever arm
        a, b = el.bodies
        if by_name[a].role in CENTRAL and by_name[b].role not in CENTRAL:
            a, b = b, a
        pa, ea = axis_line(model.bodies[a])
        pb, eb = axis_line(model.bodies[b])
        if np.linalg.norm(np.cross(ea, eb)) > AXIS_TOLERANCE:
            continue
        d = pb - pa
        off = d - (d @ ea) * ea
        dist = float(np.linalg.norm(off))
        if 0.0 < dist <= AXIS_TOLERANCE * max(abs(float(d @ ea)), coordinate_scale(model, el)):
            out.append(HairOffset(i, a, b, off))
    return out


def rigid_modes_without(model, hairs) -> int:
    """Rigid-body modes of ``model`` with the offsets ``hairs`` removed: each moved body's
    motion taken at its element's point shifted by the offset, as if its axis lay on the
    fixed body's."""
    ops = {}
    for h in hairs:
        el = model.elements[h.index]
        ops[h.index] = model.attachment_operator(el, {h.moved: np.asarray(el.point, float) + h.offset})
    return rigid_body_count(model, ops)


def hair_error(model, n_zero: int, why: str, paths) -> SceneError | None:
    """SceneError naming the field that puts a body a hair off the axis of a body it is
    joined to, when removing that offset restores a rigid-body mode the structure lacks
    (``n_zero`` counted; ``why``: what went wrong in the solve; ``paths``: the model's
    :class:`assembly.analysis.resolution.ScenePaths`); None when no such offset explains it."""
    hairs = hair_offsets(model)
    if not hairs or rigid_modes_without(model, hairs) <= n_zero:
        return None
    h = next((h for h in hairs if rigid_modes_without(model, [h]) > n_zero), max(hairs, key=lambda h: h.distance))
    el = model.elements[h.index]
    el_path = paths.elements[el.item][0]
    # a common rotation theta moves the two attachments apart by theta e x offset: the rows
    # that see that tangential motion hold the rotation with k (b.t)^2 offset^2
    t = np.cross(axis_line(model.bodies[h.fixed])[1], h.offset / h.distance)
    seen = {j: float(el.B[j, :3] @ t) ** 2 for j in np.flatnonzero(el.k > 0)}
    rows = [j for j, w in seen.items() if w > 1e-12 * max(seen.values())]
    d = h.distance
    k_eff = sum(float(el.k[j]) * seen[j] for j in rows) * d * d
    fields = ", ".join(sorted({el.fields[j] for j in rows})) if el.fields else "stiffness"
    fixed_path = paths.bodies[h.fixed][0]
    lever = (f"to which {el_path} ({el.name}) joins {h.moved!r}: a lever arm that turns their common rotation "
             f"into strain of its {fields}, a stiffness of {k_eff:.3g} N m/rad against a rotation that is free "
             f"with the axes joined (the structure has {n_zero} rigid-body modes, {n_zero + 1} with them joined), "
             f"so {why}")
    path, value = paths.bodies[h.moved][0], paths.bodies[h.moved][1]
    if path.startswith("stages[") and value.role in CENTRAL:
        k = int(path[len("stages["):path.index("]")])
        src = model.source if model.source is not None else model.scene
        given = src.as_given("stages")[k]
        e = axis_line(model.bodies[h.fixed])[1]
        along = float((np.asarray(value.position, float) - axis_line(model.bodies[h.fixed])[0]) @ e)
        fix = (f"put the stage on that axis exactly: coaxial_with = {json.dumps(h.fixed)}, axial_offset = "
               f"{along:.9g} (m) in place of its center")
        where = ("stages[%d].center" % k, list(given.center) if given.center is not None else None)
        if given.coaxial_with is not None:
            where = (f"stages[{k}].coaxial_with", given.coaxial_with)
        return SceneError(*where, f"stage {given.name!r} sits {d:.3g} m off the axis of {h.fixed!r} "
                                  f"({fixed_path}), {lever}; {fix}")
    pos = list(value.position) if value.position is not None else None
    return SceneError(f"{path}.position", pos, f"{h.moved!r} sits {d:.3g} m off the axis of {h.fixed!r} "
                                               f"({fixed_path}), {lever}; put it on that axis exactly")
