"""Parametric OCC solids of the components and the definitions of their interfaces.

The solids are built with gmsh's OpenCASCADE kernel (``gmsh`` is imported
lazily by the caller, :mod:`fe_components.meshing`, and passed in).  Each
interface is defined *here*, from the parameters: its master-node position and
a geometric selector that picks the CAD surfaces belonging to it right after
the boolean operations; those surfaces become gmsh physical groups, and the
interface node sets are read from the physical groups of the mesh.

Lengths in m, angles in rad, rotation axis = global z.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .involute import flank_half_angle, flank_radii
from .params import CarrierParams, CylinderParams, GearTeeth, PartFile, PinionParams, WheelParams
from .part.read import part_geometry

AXIS = np.array([0.0, 0.0, 1.0])


# ---------------------------------------------------------------- interface definitions
@dataclass(frozen=True)
class SurfaceSelector:
    """Selects CAD surfaces lying on a cylinder or beyond a radius, inside an axial window.

    kind "cylinder": every sample point is at distance ``radius`` from the axis
    through ``center`` (x, y), parallel to z.
    kind "outer": every sample point is at distance >= ``radius`` from the z axis
    and the surface is not a plane z = const (lateral tooth / rim surfaces).
    kind "plane": the surface is the plane z = z_min (= z_max).
    All: the surface's z extent lies inside [z_min, z_max].
    """

    kind: str
    radius: float
    z_min: float
    z_max: float
    center: tuple[float, float] = (0.0, 0.0)

    def matches(self, pts: np.ndarray, zlo: float, zhi: float, tol: float) -> bool:
        if zlo < self.z_min - tol or zhi > self.z_max + tol:
            return False
        d = np.hypot(pts[:, 0] - self.center[0], pts[:, 1] - self.center[1])
        if self.kind == "cylinder":
            return bool(np.all(np.abs(d - self.radius) < tol))
        if self.kind == "outer":
            return bool(np.all(d >= self.radius - tol) and (zhi - zlo) > tol)
        if self.kind == "plane":
            return bool(np.all(np.abs(pts[:, 2] - self.z_min) < tol))
        raise ValueError(self.kind)


@dataclass(frozen=True)
class InterfaceDef:
    """An interface: name, master position (3,) [m], default coupling, surface selectors."""

    name: str
    master: tuple[float, float, float]
    coupling: str
    selectors: tuple[SurfaceSelector, ...]


def _gear_mesh_def(teeth: GearTeeth, z_mid: float) -> InterfaceDef:
    b = teeth.face_width
    r = teeth.inner_limit_radius if teeth.fidelity == "involute" else teeth.outer_radius
    sel = SurfaceSelector("outer", r, z_mid - b / 2, z_mid + b / 2)
    return InterfaceDef("gear_mesh", (0.0, 0.0, z_mid), "rbe3", (sel,))


def interface_defs(params) -> list[InterfaceDef]:
    """Interfaces of a component, in a fixed order (this order is the master order)."""
    if isinstance(params, PinionParams):
        s0, s1, L = params.shaft[0], params.shaft[-1], params.length
        return [
            InterfaceDef("bearing_a", (0.0, 0.0, s0.length / 2), "rbe2",
                         (SurfaceSelector("cylinder", s0.diameter / 2, 0.0, s0.length),)),
            InterfaceDef("bearing_b", (0.0, 0.0, L - s1.length / 2), "rbe2",
                         (SurfaceSelector("cylinder", s1.diameter / 2, L - s1.length, L),)),
            _gear_mesh_def(params.teeth, params.gear_center),
        ]
    if isinstance(params, WheelParams):
        h0, h1 = params.hub_offset - params.hub_length / 2, params.hub_offset + params.hub_length / 2
        return [
            InterfaceDef("bore", (0.0, 0.0, params.hub_offset), "rbe2",
                         (SurfaceSelector("cylinder", params.bore_diameter / 2, h0, h1),)),
            _gear_mesh_def(params.teeth, 0.0),
        ]
    if isinstance(params, CarrierParams):
        params.require_pins()
        s, t = params.cheek_spacing, params.cheek_thickness
        out = []
        for i, a in enumerate(params.planet_angles):
            c = (params.pin_pitch_radius * math.cos(a), params.pin_pitch_radius * math.sin(a))
            sel = SurfaceSelector("cylinder", params.pin_bore_diameter / 2, -s / 2 - t, s / 2 + t, c)
            out.append(InterfaceDef(f"pin_{i}", (c[0], c[1], 0.0), "rbe2", (sel,)))
        za0, za1 = -s / 2 - t - params.seat_a_length, -s / 2 - t
        zb0, zb1 = s / 2 + t, s / 2 + t + params.seat_b_length
        out += [
            InterfaceDef("bearing_a", (0.0, 0.0, (za0 + za1) / 2), "rbe2",
                         (SurfaceSelector("cylinder", params.seat_a_diameter / 2, za0, za1),)),
            InterfaceDef("bearing_b", (0.0, 0.0, (zb0 + zb1) / 2), "rbe2",
                         (SurfaceSelector("cylinder", params.seat_b_diameter / 2, zb0, zb1),)),
            InterfaceDef("output_bore", (0.0, 0.0, (zb0 + zb1) / 2), "rbe2",
                         (SurfaceSelector("cylinder", params.output_bore_diameter / 2, zb0, zb1),)),
        ]
        return out
    if isinstance(params, CylinderParams):
        L = params.length
        return [
            InterfaceDef("end_a", (0.0, 0.0, 0.0), "rbe3", (_end_face(0.0),)),
            InterfaceDef("end_b", (0.0, 0.0, L), "rbe3", (_end_face(L),)),
        ]
    if isinstance(params, PartFile):  # from the file (read once per process), faces found by the rules
        return [InterfaceDef(i.name, tuple(float(x) for x in i.master), i.coupling, ())
                for i in part_geometry(params).interfaces]
    raise TypeError(f"unsupported component parameters: {type(params).__name__}")



def _end_face(z: float) -> SurfaceSelector:
    return SurfaceSelector("plane", 0.0, z, z)


def characteristic_length(params) -> float:
    """A length scale of the part [m] (for geometric tolerances)."""
    if isinstance(params, PinionParams):
        return max(params.length, 2 * params.teeth.tip_radius)
    if isinstance(params, WheelParams):
        return 2 * params.teeth.tip_radius
    if isinstance(params, CarrierParams):
        return params.cheek_diameter
    if isinstance(params, CylinderParams):
        return max(params.length, params.diameter)
    if isinstance(params, PartFile):
        return part_geometry(params).size
    raise TypeError(type(params).__name__)


def _annulus(r_out: float, r_in: float, length: float) -> float:
    return math.pi * (r_out ** 2 - r_in ** 2) * length


def volume_lower_bound(params) -> float:
    """A lower bound of the solid's volume [m^3] from its parameters alone (no meshing):
    the volume of the regions that :func:`build_solid` keeps whatever the boolean details
    (teeth, posts, fillets only add material). Cylinder: exact; pinion: the bored shaft
    steps; wheel: rim (inner rim to root or smooth radius), web less its holes, bored hub
    (three disjoint regions); carrier: the two cheeks less the pin bores and centre hole."""
    p = params
    if isinstance(p, CylinderParams):
        return _annulus(p.diameter / 2, p.bore_diameter / 2, p.length)
    if isinstance(p, PinionParams):
        return sum(_annulus(s.diameter / 2, p.bore_diameter / 2, s.length) for s in p.shaft)
    if isinstance(p, WheelParams):
        t = p.teeth
        rim = _annulus(t.inner_limit_radius, p.rim_inner_diameter / 2, t.face_width)
        web = (_annulus(p.rim_inner_diameter / 2, p.hub_outer_diameter / 2, p.web_thickness)
               - p.n_holes * _annulus(p.hole_diameter / 2, 0.0, p.web_thickness))
        hub = _annulus(p.hub_outer_diameter / 2, p.bore_diameter / 2, p.hub_length)
        return rim + web + hub
    if isinstance(p, CarrierParams):
        t = p.cheek_thickness
        cheek = (_annulus(p.cheek_diameter / 2, p.center_hole_diameter / 2, t)
                 - p.n_planets * _annulus(p.pin_bore_diameter / 2, 0.0, t))
        return 2 * cheek
    if isinstance(p, PartFile):  # the CAD-exact volume, or the straight elements' of a mesh file
        return part_geometry(p).volume
    raise TypeError(type(params).__name__)


# ---------------------------------------------------------------- OCC solids
def _gear_body(occ, teeth: GearTeeth, z0: float, flank_points: int = 7, helix_sections: int = 5) -> tuple[int, int]:
    """Gear body (volume dimTag) between z0 and z0 + face width: smooth annulus or involute teeth."""
    b = teeth.face_width
    if teeth.fidelity == "smooth":
        return (3, occ.addCylinder(0, 0, z0, 0, 0, b, teeth.outer_radius))
    if abs(teeth.helix_angle) < 1e-12:
        wire = _involute_wire(occ, teeth, z0, 0.0, flank_points)
        surf = occ.addPlaneSurface([wire])
        ext = occ.extrude([(2, surf)], 0, 0, b)
        return next(dt for dt in ext if dt[0] == 3)
    # helical: transverse sections rotated along the helix, lofted
    wires = []
    for k in range(helix_sections):
        z = z0 + b * k / (helix_sections - 1)
        phi = (z - z0) * math.tan(teeth.helix_angle) / teeth.pitch_radius
        wires.append(_involute_wire(occ, teeth, z, phi, flank_points))
    out = occ.addThruSections(wires, makeSolid=True, makeRuled=False)
    return next(dt for dt in out if dt[0] == 3)


def _involute_wire(occ, teeth: GearTeeth, z: float, phi0: float, flank_points: int) -> int:
    """Closed curve loop of the full transverse gear outline at height z, rotated by phi0."""
    zt = teeth.n_teeth
    r_b, r_f = teeth.base_radius, teeth.root_radius
    radii = flank_radii(teeth, flank_points)
    theta = flank_half_angle(teeth, radii)
    radial = r_f < r_b  # radial flank extension below the base circle
    centre = occ.addPoint(0, 0, z)

    def pt(r, a):
        return occ.addPoint(r * math.cos(a), r * math.sin(a), z)

    curves: list[int] = []
    first_root_pt = None
    prev_root_pt = None  # end point of the previous root arc (on the root circle)
    for k in range(zt):
        c = phi0 + 2 * math.pi * k / zt
        # right flank (angle c - theta), from root to tip
        right = [pt(r, c - th) for r, th in zip(radii, theta)]
        if radial:
            root_r = pt(r_f, c - theta[0])
            if prev_root_pt is not None:
                curves.append(occ.addCircleArc(prev_root_pt, centre, root_r))
            else:
                first_root_pt = root_r
            curves.append(occ.addLine(root_r, right[0]))
        else:
            if prev_root_pt is not None:
                curves.append(occ.addCircleArc(prev_root_pt, centre, right[0]))
            else:
                first_root_pt = right[0]
        curves.append(occ.addSpline(right))
        left = [pt(r, c + th) for r, th in zip(radii[::-1], theta[::-1])]
        curves.append(occ.addCircleArc(right[-1], centre, left[0]))
        curves.append(occ.addSpline(left))
        if radial:
            root_l = pt(r_f, c + theta[0])
            curves.append(occ.addLine(left[-1], root_l))
            prev_root_pt = root_l
        else:
            prev_root_pt = left[-1]
    curves.append(occ.addCircleArc(prev_root_pt, centre, first_root_pt))
    return occ.addCurveLoop(curves)


def _cyl(occ, x, y, z0, z1, r) -> tuple[int, int]:
    return (3, occ.addCylinder(x, y, z0, 0, 0, z1 - z0, r))


def build_solid(occ, params, flank_points: int = 7, helix_sections: int = 5) -> list[tuple[int, int]]:
    """Create the component's solid in the OCC model; returns its volume dimTags."""
    if isinstance(params, CylinderParams):
        body = [_cyl(occ, 0, 0, 0, params.length, params.diameter / 2)]
        if params.bore_diameter > 0:
            body, _ = occ.cut(body, [_cyl(occ, 0, 0, -params.length, 2 * params.length, params.bore_diameter / 2)])
        return body
    if isinstance(params, PinionParams):
        parts, z = [], 0.0
        for seg in params.shaft:
            parts.append(_cyl(occ, 0, 0, z, z + seg.length, seg.diameter / 2))
            z += seg.length
        gear = _gear_body(occ, params.teeth, params.gear_center - params.teeth.face_width / 2,
                          flank_points, helix_sections)
        body, _ = occ.fuse([gear], parts)
        if params.bore_diameter > 0:
            L = params.length
            body, _ = occ.cut(body, [_cyl(occ, 0, 0, -L, 2 * L, params.bore_diameter / 2)])
        return body
    if isinstance(params, WheelParams):
        t = params.teeth
        b = t.face_width
        gear = _gear_body(occ, t, -b / 2, flank_points, helix_sections)
        L = max(b, params.hub_length) + abs(params.hub_offset) + 1.0
        rim, _ = occ.cut([gear], [_cyl(occ, 0, 0, -L, L, params.rim_inner_diameter / 2)])
        web = _cyl(occ, 0, 0, params.web_offset - params.web_thickness / 2,
                   params.web_offset + params.web_thickness / 2, params.rim_inner_diameter / 2)
        hub = _cyl(occ, 0, 0, params.hub_offset - params.hub_length / 2,
                   params.hub_offset + params.hub_length / 2, params.hub_outer_diameter / 2)
        body, _ = occ.fuse(rim, [web, hub])
        tools = [_cyl(occ, 0, 0, -L, L, params.bore_diameter / 2)]
        rh = params.hole_pitch_radius
        for i in range(params.n_holes):
            a = 2 * math.pi * i / params.n_holes + math.pi / max(params.n_holes, 1)
            tools.append(_cyl(occ, rh * math.cos(a), rh * math.sin(a), -L, L, params.hole_diameter / 2))
        body, _ = occ.cut(body, tools)
        return body
    if isinstance(params, CarrierParams):
        p = params
        p.require_pins()
        s, t = p.cheek_spacing, p.cheek_thickness
        Rc = p.cheek_diameter / 2
        cheek_a = _cyl(occ, 0, 0, -s / 2 - t, -s / 2, Rc)
        cheek_b = _cyl(occ, 0, 0, s / 2, s / 2 + t, Rc)
        parts = [cheek_b]
        rp = p.post_radius_value
        for a in p.post_angles:  # posts overlap half a cheek on each side (robust boolean)
            parts.append(_cyl(occ, rp * math.cos(a), rp * math.sin(a), -s / 2 - t / 2, s / 2 + t / 2, p.post_diameter / 2))
        parts.append(_cyl(occ, 0, 0, -s / 2 - t - p.seat_a_length, -s / 2 - t / 2, p.seat_a_diameter / 2))
        parts.append(_cyl(occ, 0, 0, s / 2 + t / 2, s / 2 + t + p.seat_b_length, p.seat_b_diameter / 2))
        body, _ = occ.fuse([cheek_a], parts)
        Lz = s + 2 * t + p.seat_a_length + p.seat_b_length + 1.0
        tools = []
        for a in p.planet_angles:
            tools.append(_cyl(occ, p.pin_pitch_radius * math.cos(a), p.pin_pitch_radius * math.sin(a),
                              -Lz, Lz, p.pin_bore_diameter / 2))
        tools.append(_cyl(occ, 0, 0, s / 2 + t, Lz, p.output_bore_diameter / 2))
        if p.center_hole_diameter > 0:
            tools.append(_cyl(occ, 0, 0, -Lz, Lz, p.center_hole_diameter / 2))
        body, _ = occ.cut(body, tools)
        return body
    raise TypeError(f"unsupported component parameters: {type(params).__name__}")

