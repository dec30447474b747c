"""Planetary-stage builder: sun, ring, carrier and N planets -> bodies, bearings, meshes.

Geometry (SI): the carrier arm (planet-centre radius) follows from the sun mesh,
``R_c = (r_sun + r_planet) / cos(alpha_sun)`` with base radii r; the ring's base radius must
then satisfy ``(r_ring - r_planet) / cos(alpha_ring) = R_c``. Planets sit at angles ``psi_n``
(rad, measured from the stage's local x axis about its axis) in the carrier's frame and are
supported by bearings to the carrier. One ``drive_sign`` for the stage loads every sun
mesh on the flank that the sun closes when turning in that sense; the planet-ring meshes
are loaded consistently (the planet turns the other way), so on a loaded planet the two
mesh forces have equal tangential and opposite radial components.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, Optional

import numpy as np

from .errors import SceneError
from .geometry import axis_frame
from .flexible import FlexOptions
from .scene import Bearing, Body, Fidelity, Fixed, GearMesh, Vec3, angle

Support = Literal["bearing", "fixed", "floating"]


@dataclass(frozen=True)
class BearingSpec:
    """Stiffnesses of a member's bearing (N/m, N m/rad; ``inf`` = rigid direction)."""

    k_radial: float
    k_axial: float
    k_tilt: float
    k_torsion: float = 0.0


@dataclass(frozen=True)
class Member:
    """Sun, ring or carrier. ``support``: 'bearing' (to the housing, stiffness ``bearing``;
    a ring on a torsional spring is a bearing with k_torsion), 'fixed' (all six DOFs held)
    or 'floating' (no bearing at all). ``base_radius`` (m, positive) for sun and ring.
    The carrier may instead be a ``component`` (fe_components carrier without
    ``planet_angles``/``pin_pitch_radius``: the stage places the pins at its planets) with
    ``flex`` options; its bearing then acts at the component's ``bearing_interface``."""

    mass: Optional[float] = None
    polar_inertia: Optional[float] = None
    transverse_inertia: Optional[float] = None
    base_radius: Optional[float] = None
    support: Support = "bearing"
    bearing: Optional[BearingSpec] = None
    fidelity: Fidelity = "rigid"
    component: Optional[dict] = None
    flex: Optional[FlexOptions] = None
    bearing_interface: str = "bearing_b"


@dataclass(frozen=True)
class Planets:
    """N identical planets at ``angles`` (rad; default equally spaced from 0).
    ``outer_radius`` (m, default the pitch radius) is used for the overlap check."""

    count: int
    mass: float
    polar_inertia: float
    base_radius: float
    bearing: BearingSpec
    transverse_inertia: Optional[float] = None
    angles: Optional[tuple[float, ...]] = angle(None)
    outer_radius: Optional[float] = None
    fidelity: Fidelity = "rigid"


@dataclass(frozen=True)
class PlanetaryStage:
    """A planetary stage. Mesh stiffness N/m; pressure angles transverse, rad."""

    name: str
    sun: Member
    ring: Member
    carrier: Member
    planets: Planets
    k_mesh_sun: float
    k_mesh_ring: float
    pressure_angle_sun: float = angle()
    pressure_angle_ring: float = angle()
    helix_angle: float = angle(0.0)
    drive_sign: int = 1
    center: Vec3 = (0.0, 0.0, 0.0)
    axis: Vec3 = (0.0, 0.0, 1.0)
    contact_point: Literal["pitch", "tangent"] = "pitch"

    def carrier_radius(self) -> float:
        """Planet-centre radius (m) from the sun-planet mesh geometry."""
        return (self.sun.base_radius + self.planets.base_radius) / math.cos(self.pressure_angle_sun)

    def planet_angles(self) -> tuple[float, ...]:
        n = self.planets.count
        if self.planets.angles is not None:
            return tuple(self.planets.angles)
        return tuple(2 * math.pi * i / n for i in range(n))


@dataclass(frozen=True)
class _Parts:
    bodies: tuple
    bearings: tuple
    meshes: tuple
    fixed: tuple


def check_stage(st: PlanetaryStage, path: str) -> None:
    """Geometric and physical consistency of a stage (SceneError on failure)."""
    if not st.name or "." in st.name:
        raise SceneError(f"{path}.name", st.name, "must be a non-empty name without '.'")
    for role in ("sun", "ring", "carrier"):
        m: Member = getattr(st, role)
        p = f"{path}.{role}"
        if m.component is not None:
            if role != "carrier":
                raise SceneError(f"{p}.component", m.component.get("kind"),
                                 "only the carrier of a planetary stage can be a component so far")
            for f in ("planet_angles", "pin_pitch_radius", "n_planets"):
                if f in m.component or f + "_deg" in m.component:
                    raise SceneError(f"{p}.component.{f}", m.component.get(f, m.component.get(f + "_deg")),
                                     "set by the stage from its planets; remove it")
            if m.mass is not None or m.polar_inertia is not None:
                raise SceneError(f"{p}.mass", m.mass, "a component carrier takes mass and inertia from its mesh")
        else:
            if m.fidelity == "flexible":
                raise SceneError(f"{p}.fidelity", m.fidelity, "a flexible member needs a component table")
            if m.mass is None or not m.mass > 0:
                raise SceneError(f"{p}.mass", m.mass, "must be > 0 kg")
            if m.polar_inertia is None or not m.polar_inertia > 0:
                raise SceneError(f"{p}.polar_inertia", m.polar_inertia, "must be > 0 kg m^2")
        if m.support == "bearing" and m.bearing is None:
            raise SceneError(f"{p}.bearing", None, "support = 'bearing' needs a bearing table")
        if m.support != "bearing" and m.bearing is not None:
            raise SceneError(f"{p}.support", m.support, "a bearing table is given but support is not 'bearing'")
    for role in ("sun", "ring"):
        r = getattr(st, role).base_radius
        if r is None or not r > 0:
            raise SceneError(f"{path}.{role}.base_radius", r, "must be > 0 m (give the ring's as positive)")
    pl = st.planets
    if pl.count < 1:
        raise SceneError(f"{path}.planets.count", pl.count, "must be >= 1")
    for f in ("mass", "polar_inertia", "base_radius"):
        if not getattr(pl, f) > 0:
            raise SceneError(f"{path}.planets.{f}", getattr(pl, f), "must be > 0")
    for f in ("k_mesh_sun", "k_mesh_ring"):
        v = getattr(st, f)
        if not (v > 0 and math.isfinite(v)):
            raise SceneError(f"{path}.{f}", v, "must be a finite stiffness > 0 N/m")
    for f in ("pressure_angle_sun", "pressure_angle_ring"):
        if not 0 < getattr(st, f) < math.pi / 2:
            raise SceneError(f"{path}.{f}", getattr(st, f), "must lie in (0, 90) deg")
    if not abs(st.helix_angle) < math.pi / 2:
        raise SceneError(f"{path}.helix_angle", st.helix_angle, "|helix angle| must be < 90 deg")
    if st.drive_sign not in (1, -1):
        raise SceneError(f"{path}.drive_sign", st.drive_sign, "must be +1 or -1")
    if st.ring.base_radius <= pl.base_radius:
        raise SceneError(f"{path}.ring.base_radius", st.ring.base_radius,
                         "must exceed the planet base radius")
    Rc = st.carrier_radius()
    Rc_ring = (st.ring.base_radius - pl.base_radius) / math.cos(st.pressure_angle_ring)
    if abs(Rc_ring - Rc) > 1e-6 * Rc:
        want = pl.base_radius + Rc * math.cos(st.pressure_angle_ring)
        raise SceneError(f"{path}.ring.base_radius", st.ring.base_radius,
                         f"inconsistent with the sun mesh: the planet centre lies at {Rc:.6g} m, "
                         f"which needs a ring base radius of {want:.9g} m")
    if pl.angles is not None and len(pl.angles) != pl.count:
        raise SceneError(f"{path}.planets.angles", list(pl.angles),
                         f"must list exactly planets.count = {pl.count} angles")
    psi = np.sort(np.mod(np.asarray(st.planet_angles()), 2 * math.pi))
    if pl.count > 1:
        gaps = np.diff(np.concatenate([psi, psi[:1] + 2 * math.pi]))
        r_out = pl.outer_radius if pl.outer_radius is not None else pl.base_radius / math.cos(st.pressure_angle_sun)
        chord = 2 * Rc * np.sin(gaps.min() / 2)
        if chord <= 2 * r_out:
            key = "angles" if pl.angles is not None else "count"
            val = list(pl.angles) if pl.angles is not None else pl.count
            raise SceneError(f"{path}.planets.{key}", val,
                             f"planets overlap: closest centres {chord:.4g} m apart, "
                             f"planet outer diameter {2 * r_out:.4g} m")


def expand_stage(st: PlanetaryStage, path: str) -> _Parts:
    """Bodies, bearings, meshes and fixed DOFs of one planetary stage."""
    E = axis_frame(st.axis)
    c = np.asarray(st.center, float)
    Rc = st.carrier_radius()
    n = st.name
    bodies, bearings, fixed, meshes = [], [], [], []

    def central(role: str, m: Member):
        bname = f"{n}.{role}"
        comp = None
        if m.component is not None:
            comp = {**m.component, "planet_angles": list(st.planet_angles()), "pin_pitch_radius": Rc}
        bodies.append(Body(name=bname, mass=m.mass, polar_inertia=m.polar_inertia,
                           transverse_inertia=m.transverse_inertia, position=tuple(c),
                           axis=tuple(E[:, 2]), fidelity=m.fidelity, stage=n, role=role,
                           component=comp, flex=m.flex))
        if m.support == "bearing":
            b = m.bearing
            bearings.append(Bearing(body=bname, k_radial=b.k_radial, k_axial=b.k_axial,
                                    k_tilt=b.k_tilt, k_torsion=b.k_torsion, name=f"{bname}.bearing",
                                    interface=m.bearing_interface if comp is not None else None))
        elif m.support == "fixed":
            fixed.append(Fixed(body=bname))
        return bname

    sun = central("sun", st.sun)
    ring = central("ring", st.ring)
    carrier = central("carrier", st.carrier)
    pl = st.planets
    for i, psi in enumerate(st.planet_angles()):
        pos = c + Rc * (math.cos(psi) * E[:, 0] + math.sin(psi) * E[:, 1])
        pname = f"{n}.planet{i}"
        bodies.append(Body(name=pname, mass=pl.mass, polar_inertia=pl.polar_inertia,
                           transverse_inertia=pl.transverse_inertia, position=tuple(pos),
                           axis=tuple(E[:, 2]), frame=carrier, fidelity=pl.fidelity,
                           stage=n, role="planet"))
        b = pl.bearing
        bearings.append(Bearing(body=pname, k_radial=b.k_radial, k_axial=b.k_axial, k_tilt=b.k_tilt,
                                k_torsion=b.k_torsion, name=f"{pname}.bearing",
                                frame_interface=f"pin_{i}" if st.carrier.component is not None else None))
        # Sun closes its mesh turning in +drive_sign; the planet it pushes turns the other
        # way and so closes the ring mesh turning in -drive_sign.
        meshes.append(GearMesh(gear1=sun, gear2=pname, stiffness=st.k_mesh_sun,
                               base_radius1=st.sun.base_radius, base_radius2=pl.base_radius,
                               pressure_angle=st.pressure_angle_sun, helix_angle=st.helix_angle,
                               drive_sign=st.drive_sign, name=f"{n}.sun-planet{i}",
                               contact_point=st.contact_point))
        meshes.append(GearMesh(gear1=pname, gear2=ring, stiffness=st.k_mesh_ring,
                               base_radius1=pl.base_radius, base_radius2=-st.ring.base_radius,
                               pressure_angle=st.pressure_angle_ring, helix_angle=-st.helix_angle,
                               drive_sign=-st.drive_sign, name=f"{n}.planet{i}-ring",
                               contact_point=st.contact_point))
    return _Parts(tuple(bodies), tuple(bearings), tuple(meshes), tuple(fixed))
