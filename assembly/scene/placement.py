"""Bodies placed by gear meshes at the working centre distance.

A mesh with ``place = "gear2"`` (or ``"gear1"``) puts that gear where the other one's
teeth reach: its gear centre (the ``gear_mesh`` interface master of a component, else its
position) at the other gear's centre plus or minus ``a_w d``, with
``a_w = |r_b1 + r_b2| / cos(alpha_wt)`` from the mesh's (derived or typed) numbers and
``d = cos(theta) e1 + sin(theta) e2`` the direction of the line of centres from gear 1 to
gear 2 in gear 1's axes (:func:`assembly.mechanics.kinematics.axis_frame` of its axis; ``theta`` the
mesh's ``centre_line_angle``, rad, default 0). The placed body's ``position`` follows from
its gear centre (a pinion component's gear sits ``gear_center`` along its axis).

Rules: a body is placed by at most one mesh; placements are made in dependency order and a
cycle (a places b, b places a) is refused; only the scene's own bodies can be placed (stage
members sit where their stage puts them); a placing mesh takes the gear centres from the
bodies (no ``center1``/``center2``). A placed body may still give ``position``: it must then
agree (1e-9 m relative to a_w), so a resolved scene resolves to itself. Bodies neither given
nor placed sit at the origin.

A planetary stage with ``coaxial_with`` is placed after the bodies, on the named body's axis
line to the last bit (:func:`place_stages`): its centre is computed from the body's position
and axis, which a typed centre repeats only to its printed digits.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from fe_components.errors import GeometryError

from ..errors import SceneError
from ..mechanics.kinematics import axis_frame
from .schema import keep_degrees

#: A typed position of a placed body must agree to this fraction of the centre distance.
POSITION_AGREEMENT = 1e-9
ORIGIN = (0.0, 0.0, 0.0)


def _gear_offset(body, interface, path: str) -> np.ndarray:
    """Global vector from the body's position to its gear centre (0 for a plain body)."""
    if body.component is None:
        return np.zeros(3)
    from .attach import local_masters
    try:
        masters = local_masters(body.component)
    except GeometryError as err:  # a carrier without its pins
        raise SceneError(f"{path}.component.{err.parameter}", err.value, err.reason) from None
    name = interface or "gear_mesh"
    if name not in masters:
        raise SceneError(f"{path}.component", name, f"no such interface; have {sorted(masters)}")
    return axis_frame(body.axis) @ masters[name]


def place_bodies(bodies: tuple, meshes: tuple) -> tuple:
    """``bodies`` with the positions the placing meshes give (and the origin for a body
    with neither position nor placement)."""
    index = {b.name: i for i, b in enumerate(bodies)}
    placed_by = {}
    for i, m in enumerate(meshes):
        if m.place is None:
            continue
        target = getattr(m, m.place)
        if target not in index:
            raise SceneError(f"meshes[{i}].place", m.place, f"{target!r} is not one of the scene's bodies "
                                                            f"(stage members sit where their stage puts them)")
        if target in placed_by:
            raise SceneError(f"meshes[{i}].place", m.place,
                             f"{target!r} is already placed by meshes[{placed_by[target]}]: place a body once")
        for f in ("center1", "center2"):
            if getattr(m, f) is not None:
                raise SceneError(f"meshes[{i}].{f}", list(getattr(m, f)),
                                 "a placing mesh takes the gear centres from the bodies; remove it")
        placed_by[target] = i
    bodies = list(bodies)
    pending = dict(placed_by)
    while pending:
        ready = [(t, i) for t, i in pending.items() if _other(meshes[i], t) not in pending]
        if not ready:
            i = max(pending.values())   # the mesh that closed the cycle, in file order
            chain = " -> ".join(f"meshes[{j}] places {t!r}" for t, j in pending.items())
            raise SceneError(f"meshes[{i}].place", meshes[i].place, f"placements form a cycle ({chain})")
        for target, i in ready:
            k = index[target]
            bodies[k] = _placed(bodies, index, meshes[i], i, target, k)
            del pending[target]
    return tuple(b if b.position is not None else keep_degrees(b, dataclasses.replace(b, position=ORIGIN))
                 for b in bodies)


def _other(m, target: str) -> str:
    return m.gear1 if target == m.gear2 else m.gear2


def _placed(bodies, index, m, i: int, target: str, k: int):
    """The body ``target`` (``bodies[k]``) at the place mesh ``m`` (``meshes[i]``) gives it."""
    other = _other(m, target)
    if other not in index:
        raise SceneError(f"meshes[{i}].place", m.place, f"the other gear {other!r} is not one of the scene's "
                                                        f"bodies; place {other!r} instead")
    ob, tb = bodies[index[other]], bodies[k]
    o_pos = np.asarray(ob.position if ob.position is not None else ORIGIN, float)
    path_o, path_t = f"bodies[{index[other]}]", f"bodies[{k}]"
    if_o, if_t = (m.interface1, m.interface2) if other == m.gear1 else (m.interface2, m.interface1)
    c_other = o_pos + _gear_offset(ob, if_o, path_o)
    a_w = abs(m.base_radius1 + m.base_radius2) / math.cos(m.pressure_angle)
    g1 = ob if other == m.gear1 else tb
    E = axis_frame(g1.axis)
    d = math.cos(m.centre_line_angle) * E[:, 0] + math.sin(m.centre_line_angle) * E[:, 1]
    # round-off of cos/sin (cos(pi/2) = 6e-17) would put a gear 5e-17 m off the line it is
    # meant to lie on: a lever arm that couples its turning to springs which must not see it
    d[np.abs(d) < 4 * np.finfo(float).eps] = 0.0
    c_target = c_other + (a_w * d if target == m.gear2 else -a_w * d)
    pos = c_target - _gear_offset(tb, if_t, path_t)
    if tb.position is not None:
        if np.linalg.norm(np.asarray(tb.position, float) - pos) > POSITION_AGREEMENT * a_w:
            raise SceneError(f"{path_t}.position", list(tb.position),
                             f"differs from {[float(f'{v:.12g}') for v in pos]} m where meshes[{i}] places "
                             f"{target!r} (centre distance {a_w:.9g} m): leave position out or remove place")
        return tb
    return keep_degrees(tb, dataclasses.replace(tb, position=tuple(float(v) for v in pos)))


def place_stages(stages: tuple, bodies: tuple) -> tuple:
    """``stages`` with their centres resolved: a stage with ``coaxial_with`` sits on that
    body's axis line exactly -- centre = the body's position + ``axial_offset`` (m, default
    0) along the body's unit axis, axis = the body's axis (in the stage's own sense) -- and
    keeps no ``coaxial_with``, so the resolved scene resolves to itself; a stage without it
    keeps its ``center`` (default the origin). ``bodies``: the scene's own bodies, placed.
    The body is one of ``bodies`` or the sun, ring or carrier of a stage written before."""
    from .shafts import AXIS_TOLERANCE
    by_name = {b.name: (b.position, b.axis) for b in bodies}
    out = []
    for i, st in enumerate(stages):
        path = f"stages[{i}]"
        if st.coaxial_with is None:
            if st.axial_offset is not None:
                raise SceneError(f"{path}.axial_offset", st.axial_offset, "measured along the axis of the body "
                                                                          "named by coaxial_with: give coaxial_with "
                                                                          "too, or give center instead")
            center = st.center if st.center is not None else ORIGIN
            out.append(keep_degrees(st, dataclasses.replace(st, center=center)))
        else:
            out.append(_coaxial(st, path, by_name, AXIS_TOLERANCE))
        for role in ("sun", "ring", "carrier"):
            by_name[f"{st.name}.{role}"] = (out[-1].center, out[-1].axis)
    return tuple(out)


def _coaxial(st, path: str, by_name: dict, tolerance: float):
    """Stage ``st`` (at scene path ``path``) on the axis of the body its ``coaxial_with``
    names (``by_name``: body name -> (position, axis) of the bodies it may name)."""
    name = st.coaxial_with
    if st.center is not None:
        raise SceneError(f"{path}.center", list(st.center),
                         f"the stage sits on the axis of {name!r} (coaxial_with): leave center out and give its "
                         f"distance along that axis as axial_offset (m)")
    if name not in by_name:
        raise SceneError(f"{path}.coaxial_with", name, "must name one of the scene's bodies or the sun, ring or "
                                                        "carrier of a stage written before this one")
    position, axis = by_name[name]
    e = axis_frame(axis)[:, 2]
    a = axis_frame(st.axis)[:, 2]
    angle = math.asin(min(1.0, float(np.linalg.norm(np.cross(a, e)))))
    if angle > tolerance:
        raise SceneError(f"{path}.axis", list(st.axis),
                         f"{angle:.3g} rad off the axis {list(axis)} of {name!r} (coaxial_with): the stage shares "
                         f"that axis (either sense, tolerance {tolerance:g} rad); give axis = {list(axis)}")
    # the body's own axis tuple (or its exact negative): the members' frames then turn about
    # the very line the body turns about, not a line 1 ulp beside it
    same = float(a @ e) > 0
    new_axis = tuple(float(x) for x in axis) if same else tuple(-float(x) for x in axis)
    d = st.axial_offset or 0.0
    center = tuple(float(p + d * x) for p, x in zip(position, e))
    return keep_degrees(st, dataclasses.replace(st, center=center, axis=new_axis, coaxial_with=None,
                                                axial_offset=None))
