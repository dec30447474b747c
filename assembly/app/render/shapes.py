"""Drawn solids of the bodies of an assembled drivetrain (pure numpy; no pyvista).

Every body is drawn where it is, as a solid of its geometry (:class:`BodyShape`):

* a gear (a body taking part in gear meshes) is a toothed disc of its pitch radius
  ``|base_radius| / cos(pressure_angle)``; an internal gear (ring) is a toothed annulus;
* any other body is the equivalent solid cylinder of its mass properties,
  ``r = sqrt(2 J_polar / m)`` (capped: :func:`plain_radius_cap`); a body that carries others
  in its frame (a planet carrier) is drawn as a plate just behind the bodies it carries, so
  it does not hide them; a beam shaft's station is a collar on the shaft;
* the face width follows from the transverse inertia of a solid cylinder,
  ``J_t = m (3 r^2 + L^2) / 12``, where that gives a real length, else a fixed fraction of
  the radius (:func:`width_from_inertia`).

A mode shape moves a rigid or torsional body's solid rigidly (:func:`rigid_part`,
:func:`rigid_displacement`); torsional bodies need nothing special: their mode shape only
holds the spin. :func:`assembly_size` (the bounding-box diagonal of the undeformed solids)
sizes the views, the springs and the drawn deformation.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Face width (fraction of the radius) when the inertia gives no real length: a gear or
#: plain body, a plate (planet carrier).
WIDTH_FRACTION = 0.35
PLATE_WIDTH_FRACTION = 0.12
#: Smallest gear of the scene gets this many teeth (drawing only).
MIN_TEETH = 18
#: A gearless scene caps a plain body's drawn radius at this fraction of the spread of the
#: body positions (m): :func:`plain_radius_cap`.
CAP_LENGTH_FRACTION = 0.25
#: A beam shaft's station (bearing seat) is drawn as a collar of this many shaft radii,
#: as wide as its radius.
COLLAR_RADIUS = 1.3


@dataclass(frozen=True)
class BodyShape:
    """Drawn solid of one body: an annulus between ``r_inner`` and ``r_outer`` (m) of
    axial ``width`` (m), centred ``axial_offset`` (m) along the axis from ``position``.
    ``teeth`` > 0 puts that many teeth on the outer (external gear) or inner (internal
    gear) rim. ``kind``: 'gear', 'ring', 'plate' or 'cylinder'."""

    name: str
    kind: str
    position: np.ndarray
    axes: np.ndarray
    r_inner: float
    r_outer: float
    width: float
    axial_offset: float = 0.0
    teeth: int = 0
    tooth_height: float = 0.0
    equivalent_radius: float = 0.0   # m: sqrt(2 J / m) of a plain body drawn smaller (capped)

    @property
    def face_center_front(self) -> np.ndarray:
        return self.position + self.axes[:, 2] * (self.axial_offset + self.width / 2)

    @property
    def face_center_back(self) -> np.ndarray:
        return self.position + self.axes[:, 2] * (self.axial_offset - self.width / 2)


def pitch_radii(scene) -> dict:
    """Signed pitch radius (m) of every gear from the meshes it takes part in
    (``|base_radius| / cos(pressure_angle)``; negative = internal gear)."""
    out = {}
    for m in scene.meshes:
        for g, rb in ((m.gear1, m.base_radius1), (m.gear2, m.base_radius2)):
            r = rb / math.cos(m.pressure_angle)
            if g not in out or abs(r) > abs(out[g]):
                out[g] = r
    return out


def _local_inertia(bm) -> np.ndarray:
    """Inertia (kg m^2) about the centre of mass in the body's local axes (x, y, axis),
    from the assembled body model (rigid or flexible: both carry mass, inertia, axes)."""
    R = np.asarray(bm.axes, float)
    return R.T @ np.asarray(bm.inertia, float) @ R


class _MassProps:
    """Mass properties of an assembled body model, shaped like a scene Body for sizing."""

    def __init__(self, bm):
        self.mass = float(bm.mass)
        self._J = _local_inertia(bm)

    def inertia_local(self):
        return self._J


def width_from_inertia(body, radius: float, fraction: float) -> float:
    """Face width L from the body's inertia, ``fraction * radius`` when that gives no real
    length. Any axisymmetric body whose mass is spread evenly along its axis has
    ``J_t = J_p / 2 + m L^2 / 12`` (a solid cylinder: ``m (3 r^2 + L^2) / 12``; a thin
    ring likewise), so ``L = sqrt(12 (J_t - J_p / 2) / m)``."""
    J = body.inertia_local()
    jt = 0.5 * (J[0, 0] + J[1, 1])
    L2 = 12.0 * (jt - 0.5 * J[2, 2]) / body.mass
    if L2 > (0.02 * radius) ** 2:
        return float(math.sqrt(L2))
    return fraction * radius


def plain_radius_cap(scene, rp: dict) -> float:
    """Largest drawn radius (m) of a body without gear geometry: the largest pitch radius of
    the scene's gears, or without gears :data:`CAP_LENGTH_FRACTION` of the spread of the
    body positions (inf for a scene of coincident bodies). A lumped rotor's equivalent
    solid cylinder (``sqrt(2 J / m)``: 26 m for the NREL 5 MW rotor) would hide the
    drivetrain; a hub of the size of the largest gear does not."""
    if rp:
        return max(abs(r) for r in rp.values())
    P = np.array([b.position for b in scene.bodies if b.position is not None], float).reshape(-1, 3)
    spread = float(np.linalg.norm(np.ptp(P, axis=0))) if len(P) > 1 else 0.0
    return CAP_LENGTH_FRACTION * spread if spread > 0 else math.inf


def _station_shaft_radii(scene) -> dict:
    """Station body name -> outer radius (m) of its beam shaft."""
    from ...scene.shafts import station_body
    return {station_body(s, st): 0.5 * s.diameter for s in scene.shafts if s.is_beam for st in s.stations}


def body_shapes(model) -> dict:
    """:class:`BodyShape` of every body of an assembled model (name -> shape). A beam
    shaft's station is a collar on the shaft (:data:`COLLAR_RADIUS`); a plain body's radius
    is capped by :func:`plain_radius_cap` (``equivalent_radius`` keeps the uncapped one)."""
    sc = model.scene
    by_name = {b.name: b for b in sc.bodies}
    rp = pitch_radii(sc)
    gear_r = [abs(r) for r in rp.values()]
    module = 2.0 * min(gear_r) / MIN_TEETH if gear_r else 0.0
    cap = plain_radius_cap(sc, rp)
    collars = _station_shaft_radii(sc)
    children = {}
    for b in sc.bodies:
        if b.frame in by_name:
            children.setdefault(b.frame, []).append(b.name)
    shapes = {}
    # Gears and plain bodies first; plates (bodies carrying others) need their children.
    for b in sc.bodies:
        bm = model.bodies[b.name]
        mp = _MassProps(bm)
        if b.name in children and b.name not in rp:
            continue
        if b.name in rp:
            r = rp[b.name]
            n_teeth = max(6, int(round(2 * abs(r) / module)))
            h = 1.1 * module
            face = getattr(getattr(b, "teeth", None), "face_width", None)    # the teeth's own width
            if r < 0 or b.role == "ring":
                r = abs(r)
                width = face or width_from_inertia(mp, r, WIDTH_FRACTION * 0.6)
                shapes[b.name] = BodyShape(b.name, "ring", bm.position, bm.axes, r, r * 1.18 + h,
                                           width, 0.0, n_teeth, h)
            else:
                width = face or width_from_inertia(mp, r, WIDTH_FRACTION)
                shapes[b.name] = BodyShape(b.name, "gear", bm.position, bm.axes, 0.22 * r, r,
                                           width, 0.0, n_teeth, h)
        elif b.name in collars:
            r = COLLAR_RADIUS * collars[b.name]
            shapes[b.name] = BodyShape(b.name, "cylinder", bm.position, bm.axes, 0.0, r, r)
        else:
            r = math.sqrt(2.0 * mp.inertia_local()[2, 2] / mp.mass)
            width = width_from_inertia(mp, min(r, cap), WIDTH_FRACTION)
            if r > cap:
                width = min(width, 2.0 * WIDTH_FRACTION * cap)
            shapes[b.name] = BodyShape(b.name, "cylinder", bm.position, bm.axes, 0.0, min(r, cap), width,
                                       equivalent_radius=r if r > cap else 0.0)
    for name, kids in children.items():
        if name in shapes:
            continue
        bm = model.bodies[name]
        mp = _MassProps(bm)
        r = math.sqrt(2.0 * mp.inertia_local()[2, 2] / mp.mass)
        width = width_from_inertia(mp, r, PLATE_WIDTH_FRACTION)
        width = min(width, PLATE_WIDTH_FRACTION * r * 2)
        # Behind the carried bodies: their rearmost face, a small gap, then the plate.
        ax = bm.axes[:, 2]
        back = min(((shapes[k].face_center_back - bm.position) @ ax) for k in kids if k in shapes)
        offset = back - 0.15 * width - width / 2
        shapes[name] = BodyShape(name, "plate", bm.position, bm.axes, 0.12 * r, r, width, offset)
    return shapes


def _profile(shape: BodyShape, n_theta: int):
    """Angles and (inner, outer) radii around the body (teeth on one rim)."""
    th = np.linspace(0.0, 2 * np.pi, n_theta, endpoint=False)
    r_in = np.full(n_theta, shape.r_inner)
    r_out = np.full(n_theta, shape.r_outer)
    if shape.teeth:
        # Trapezoidal teeth: tanh-flattened cosine, tooth height h centred on the pitch circle.
        t = np.tanh(2.5 * np.cos(shape.teeth * th)) / np.tanh(2.5)
        if shape.kind == "ring":
            r_in = shape.r_inner - 0.5 * shape.tooth_height * t
        else:
            r_out = shape.r_outer + 0.5 * shape.tooth_height * t
    return th, r_in, r_out


def solid_surface(shape: BodyShape, n_radial: int = 3):
    """Triangulated closed surface of ``shape`` in global coordinates: (points, faces)
    with faces as an (n, 3) index array."""
    n_theta = max(96, 10 * shape.teeth) if shape.teeth else 96
    th, r_in, r_out = _profile(shape, n_theta)
    c, s = np.cos(th), np.sin(th)
    ring_r = [r_in + (r_out - r_in) * k / n_radial for k in range(n_radial + 1)]
    zs = (shape.axial_offset - shape.width / 2, shape.axial_offset + shape.width / 2)
    pts, faces = [], []

    def add_ring(r, z):
        start = len(pts)
        for j in range(n_theta):
            pts.append((r[j] * c[j], r[j] * s[j], z))
        return start

    def strip(a, b, flip):
        for j in range(n_theta):
            j1 = (j + 1) % n_theta
            q = (a + j, a + j1, b + j1, b + j)
            if flip:
                q = q[::-1]
            faces.append((q[0], q[1], q[2]))
            faces.append((q[0], q[2], q[3]))

    # End faces: concentric rings from inner to outer rim at each z.
    for zi, z in enumerate(zs):
        idx = [add_ring(r, z) for r in ring_r]
        for k in range(n_radial):
            strip(idx[k], idx[k + 1], flip=(zi == 0))
        if zi == 0:
            in0, out0 = idx[0], idx[-1]
        else:
            in1, out1 = idx[0], idx[-1]
    strip(out0, out1, flip=True)   # outer wall
    if shape.r_inner > 0 or shape.teeth and shape.kind == "ring":
        strip(in0, in1, flip=False)  # inner wall (bore)
    P = np.asarray(pts, float)
    P = shape.position + P @ shape.axes.T
    return P, np.asarray(faces, int)


def rigid_displacement(shape6: np.ndarray, origin: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Displacement of ``points`` (n, 3) under the small rigid motion [u, theta] at ``origin``."""
    u, th = shape6[:3], shape6[3:6]
    return u[None, :] + np.cross(th[None, :], points - origin[None, :])


def rigid_part(body_model, shape) -> np.ndarray:
    """6-vector [u, theta] (global axes, at the body's position) of a body's mode shape:
    the shape itself for a rigid/torsional body, the rigid-equivalent motion
    (``rigid_motion``) for a flexible body without its own drawing."""
    z = np.asarray(shape, float)
    if z.shape[0] == 6:
        return z
    rm = getattr(body_model, "rigid_motion", None)
    if rm is None:
        raise TypeError(f"cannot draw body {getattr(body_model, 'name', '?')!r}: "
                        f"{z.shape[0]} DOFs and no rigid_motion")
    return np.asarray(rm(z), float)


def index_mark(shape: BodyShape) -> np.ndarray:
    """Two points of a radial index line on the body's free face (along local x), so that
    a rotation about the axis shows against the ghost."""
    face = shape.face_center_back if shape.kind == "plate" else shape.face_center_front
    ax = shape.axes[:, 2] * (-1 if shape.kind == "plate" else 1)
    lift = ax * 0.01 * shape.width
    r0 = shape.r_inner if shape.r_inner > 0 else 0.0
    r1 = shape.r_outer - (0.5 * shape.tooth_height if shape.kind == "gear" else 0.0)
    e1 = shape.axes[:, 0]
    return np.array([face + lift + r0 * e1, face + lift + r1 * e1])


def assembly_bounds(shapes: dict) -> tuple[np.ndarray, np.ndarray]:
    """Axis-aligned bounding box (m) of the undeformed bodies."""
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for s in shapes.values():
        ax = s.axes
        r = s.r_outer + (0.5 * s.tooth_height if s.kind == "gear" else 0.0)
        for z in (s.axial_offset - s.width / 2, s.axial_offset + s.width / 2):
            c = s.position + ax[:, 2] * z
            for e in (ax[:, 0], ax[:, 1]):
                lo = np.minimum(lo, np.minimum(c - r * e, c + r * e))
                hi = np.maximum(hi, np.maximum(c - r * e, c + r * e))
    return lo, hi


def assembly_size(shapes: dict) -> float:
    """Bounding-box diagonal (m) of the undeformed bodies."""
    lo, hi = assembly_bounds(shapes)
    return float(np.linalg.norm(hi - lo))
