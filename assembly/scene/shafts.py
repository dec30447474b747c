"""Beam shafts (``[[shafts]]`` with ``diameter``): where they run, their stations as
bodies, and their chain of Timoshenko elements.

A beam shaft runs from body1's attachment point ``p1`` (its position, or ``interface1``'s
master node on a component body) to body2's ``p2``; length ``L = |p2 - p1|`` (m), axis
``(p2 - p1) / L``, which must be parallel to body1's axis. Each station sits ``at`` metres
from ``p1`` and becomes a rigid body ``<shaft name>.<station name>`` (the scene's default
fidelity, never flexible) carrying the lumped half masses of its two elements
(:func:`assembly.mechanics.beam.node_mass`); the half masses at the end bodies stay with the first and
last elements (``Element.mass``), since an end body may be a meshed component.
"""
from __future__ import annotations

import json

import numpy as np

from fe_components.sizes import SHAFT_DIAMETER, SLENDERNESS, unit_hint

from ..errors import SceneError
from ..mechanics.beam import node_mass, section
from ..mechanics.kinematics import unit
from .attach import global_masters, interface_point
from .tables import HOUSING, Body, Shaft

#: Largest angle (rad) between a beam shaft's axis and body1's axis that counts as parallel.
AXIS_TOLERANCE = 1e-6
#: Shortest element of a beam shaft, relative to its length: stations closer than this to
#: each other or to an end are refused (an element of zero length has no stiffness matrix).
MIN_SPACING = 1e-9


def station_body(s: Shaft, station) -> str:
    """Name of the body a station becomes: ``<shaft name>.<station name>``."""
    return f"{s.name}.{station.name}"


def shafts_expanded(scene) -> bool:
    """Whether every station of every beam shaft of ``scene`` is a body already."""
    names = {b.name for b in scene.bodies}
    return all(station_body(s, st) in names for s in scene.shafts for st in s.stations)


def _ends(s: Shaft, i: int, by_name: dict, masters: dict):
    """(body1, body2, p1, p2, interface1, interface2) of shaft ``i``."""
    path = f"shafts[{i}]"
    bodies = []
    for key in ("body1", "body2"):
        name = getattr(s, key)
        if name not in by_name:
            raise SceneError(f"{path}.{key}", name, "no body of that name")
        bodies.append(by_name[name])
    b1, b2 = bodies
    p1, i1 = _end_point(s, 1, b1, masters, path)
    p2, i2 = _end_point(s, 2, b2, masters, path)
    return b1, b2, p1, p2, i1, i2


def _end_point(s: Shaft, k: int, body, masters: dict, path: str):
    """(global point, interface) where end ``k`` (1 or 2) of beam shaft ``s`` attaches: its
    ``position<k>`` on a body without a component (a rigid arm to the body), else the body's
    attachment point (:func:`assembly.scene.attach.interface_point`)."""
    given = getattr(s, f"position{k}")
    if given is not None and body.component is not None:
        raise SceneError(f"{path}.position{k}", list(given), f"body {body.name!r} is a component: "
                                                            f"name its interface (interface{k}) instead")
    p, iface = interface_point(body, getattr(s, f"interface{k}"), masters, f"{path}.interface{k}")
    return (np.asarray(given, float) if given is not None else p), iface


def shaft_line(s: Shaft, i: int, by_name: dict, masters: dict):
    """(p1, p2, length in m, unit axis) of beam shaft ``i``; SceneError for a shaft of zero
    length or not along body1's axis (:func:`check_along_axis`)."""
    b1, b2, p1, p2, _, _ = _ends(s, i, by_name, masters)
    d = p2 - p1
    length = float(np.linalg.norm(d))
    if length == 0.0:
        raise SceneError(f"shafts[{i}].body2", s.body2, f"attaches at the same point as body1 {s.body1!r} "
                                                        f"({p1.tolist()} m): a shaft of zero length")
    check_along_axis(s, i, b1, b2, p1, p2)
    return p1, p2, length, d / length


def check_slenderness(s: Shaft, i: int, length: float) -> None:
    """A beam shaft ``length`` (m) long is at most SLENDERNESS diameters long: beyond, its
    diameter is in the wrong unit (:mod:`fe_components.sizes`)."""
    if length > SLENDERNESS * s.diameter:
        raise SceneError(f"shafts[{i}].diameter", s.diameter,
                         f"the shaft is {length / s.diameter:.4g} diameters long ({length:.6g} m between its ends): "
                         f"a drive shaft is 1 to 50, at most {SLENDERNESS:g}; a length in the wrong unit"
                         f"{unit_hint(s.diameter, length / SLENDERNESS, SHAFT_DIAMETER.hi)}")


def shaft_ends(s: Shaft, i: int, by_name: dict, masters: dict):
    """(body1, body2, p1, p2) of shaft ``i``: the bodies and the global points (m) where
    its ends attach (a spring shaft: the bodies' attachment points, not ``position``,
    where its springs act)."""
    return _ends(s, i, by_name, masters)[:4]


def check_along_axis(s: Shaft, i: int, b1, b2, p1, p2) -> None:
    """A shaft runs along body1's axis: the line from body1's attachment point ``p1`` to
    body2's ``p2`` (m, global) lies within AXIS_TOLERANCE rad of body1's axis -- body2's
    point at most AXIS_TOLERANCE x the shaft's length off body1's axis line (a spring shaft:
    x the larger of its length and its coordinates' magnitude, so that a coupling of two
    coincident points is judged too). A beam shaft's axis is that line; a spring
    shaft's springs act between the two points, so an offset is a lever arm that turns the
    bodies' common rotation into shear: a stiffness against the drivetrain's free rotation
    that no real shaft has (the quill of two_stage_quill.toml 5 mm off: a 1.2 Hz mode).
    SceneError at ``shafts[i].body2`` naming the shaft, both bodies and the offset (m); when
    a planetary stage puts one of them there, how to place it on the other's axis."""
    p1, p2 = np.asarray(p1, float), np.asarray(p2, float)
    d = p2 - p1
    length = float(np.linalg.norm(d))
    a1 = unit(b1.axis)
    offset = float(np.linalg.norm(d - (d @ a1) * a1))
    # the offset allowed: AXIS_TOLERANCE rad over the shaft's length; a spring shaft of
    # (nearly) no length, a coupling, is held to that fraction of its coordinates' size
    # (its two points then agree to their rounding, not to nothing)
    reach = length if s.is_beam else max(length, float(np.abs(np.concatenate([p1, p2])).max()))
    if offset <= AXIS_TOLERANCE * reach:
        return
    angle = float(np.arcsin(min(1.0, offset / length)))
    kind = "beam" if s.is_beam else "spring"
    name = f" {s.name!r}" if s.name else ""
    raise SceneError(f"shafts[{i}].body2", s.body2,
                     f"the {kind} shaft{name} from {s.body1!r} at {p1.tolist()} m to {s.body2!r} at {p2.tolist()} m "
                     f"runs {angle:.3g} rad off body1's axis {list(b1.axis)}: {s.body2!r} attaches {offset:.3g} m off "
                     f"the axis line of {s.body1!r}; a shaft runs along it (tolerance {AXIS_TOLERANCE:g} rad, "
                     f"{AXIS_TOLERANCE * reach:.3g} m over {reach:.6g} m){stage_fix(b1, b2)}")


def stage_fix(b1, b2) -> str:
    """``"; stage 's' places 's.sun': ..."``: how to put the planetary stage that placed
    one of two joined bodies on the other's axis exactly (``coaxial_with``), or ""."""
    member, other = (b2, b1) if b2.role in ("sun", "ring", "carrier") else (b1, b2)
    if member.role not in ("sun", "ring", "carrier") or member.stage == other.stage:
        return ""
    e = unit(other.axis)
    along = float((np.asarray(member.position, float) - np.asarray(other.position, float)) @ e)
    return (f"; stage {member.stage!r} places {member.name!r}: put the stage on the axis of {other.name!r} "
            f"exactly with coaxial_with = {json.dumps(other.name)}, axial_offset = {along:.9g} (m) in place of "
            f"its center")


def ordered_stations(s: Shaft, i: int, length: float) -> list:
    """(index as written, station) sorted by ``at``; SceneError for a station not strictly
    inside (0, ``length``) or two at the same place (closer than MIN_SPACING x length)."""
    gap = MIN_SPACING * length
    for j, st in enumerate(s.stations):
        if not gap <= st.at <= length - gap:
            raise SceneError(f"shafts[{i}].stations[{j}].at", st.at,
                             f"must lie strictly inside the shaft, between 0 and its length L = {length:.9g} m "
                             f"(the distance between its attachment points): a shaft shorter than its "
                             f"bearing span?")
    order = sorted(enumerate(s.stations), key=lambda js: js[1].at)
    for (k, a), (j, b) in zip(order, order[1:]):
        if b.at - a.at < gap:
            raise SceneError(f"shafts[{i}].stations[{max(j, k)}].at", s.stations[max(j, k)].at,
                             f"same place as stations[{min(j, k)}].at = {s.stations[min(j, k)].at!r} m")
    return order


def _masters_of(*bodies) -> dict:
    return {b.name: global_masters(b) for b in bodies if b.component is not None}


def expand_shafts(scene) -> tuple:
    """The station bodies of every beam shaft of ``scene`` (stages expanded), in shaft
    order and in each shaft by ``at``."""
    by_name = {b.name: b for b in scene.bodies}
    fidelity = scene.fidelity if scene.fidelity in ("rigid", "torsional") else "rigid"
    out = []
    for i, s in enumerate(scene.shafts):
        if not s.stations:
            continue
        masters = _masters_of(*(by_name[n] for n in (s.body1, s.body2) if n in by_name))
        p1, _, length, e = shaft_line(s, i, by_name, masters)
        order = ordered_stations(s, i, length)
        ats = [0.0] + [st.at for _, st in order] + [length]
        sec = section(s.diameter, s.bore_diameter, s.material.nu)
        rho = s.material.rho
        for n, (_, st) in enumerate(order, start=1):
            # its two halves: node_mass of an element as long as both together (local axes)
            M = node_mass(ats[n + 1] - ats[n - 1], sec, rho, np.eye(3))
            out.append(Body(name=station_body(s, st), mass=float(M[0, 0]), polar_inertia=float(M[5, 5]),
                            transverse_inertia=float(M[3, 3]), position=tuple((p1 + st.at * e).tolist()),
                            axis=tuple(e.tolist()), frame=HOUSING, fidelity=fidelity, stage=s.stage,
                            role="station"))
    return tuple(out)


def beam_nodes(s: Shaft, i: int, by_name: dict, masters: dict) -> list:
    """Nodes of beam shaft ``i`` in order along it: (body, global point in m, interface or
    None, label) for body1's point, the stations by ``at``, body2's point. Consecutive
    nodes bound one element, named ``<shaft>:<label a>-<label b>`` (:func:`beam_elements`)."""
    _, _, p1, p2, i1, i2 = _ends(s, i, by_name, masters)
    _, _, length, e = shaft_line(s, i, by_name, masters)
    order = ordered_stations(s, i, length)
    nodes = [(s.body1, p1, i1, s.body1)]
    nodes += [(station_body(s, st), p1 + st.at * e, None, st.name) for _, st in order]
    nodes += [(s.body2, p2, i2, s.body2)]
    return nodes
