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

import dataclasses
import math

import numpy as np

from fe_components.errors import GeometryError
from fe_components.params import CarrierParams
from fe_components.part.file import PartFile

from ..errors import SceneError
from ..mechanics.kinematics import axis_frame
from .mesh_excitation import stage_variations
from .planet_spacing import planets_field
from .tables import Bearing, Body, Fixed, GearMesh, Member, PlanetaryStage


def carrier_pins(st: PlanetaryStage, path: str) -> CarrierParams:
    """The carrier component of stage ``st`` (scene path ``path``) with its pins at the
    planets: their angles (rad) on the carrier radius (m). A pin check that fails names the
    carrier's field, or the planets' count or angles when the pins follow from those. A
    carrier read from a file (:class:`fe_components.part.file.PartFile`) keeps its own pins,
    which must be where the planets are (:func:`check_part_pins`)."""
    if isinstance(st.carrier.component, PartFile):
        check_part_pins(st, path)
        return st.carrier.component
    try:
        return dataclasses.replace(st.carrier.component, planet_angles=st.planet_angles(),
                                   pin_pitch_radius=st.carrier_radius())
    except GeometryError as err:
        if err.parameter == "planet_angles":   # the planets' own numbers, as the user wrote them
            raise SceneError(*planets_field(st, path), f"the carrier component {err.reason}") from None
        raise SceneError(f"{path}.carrier.component.{err.parameter}", err.value, err.reason) from None


#: A part file's pin master may lie this fraction of the carrier radius from its planet's
#: axis point (the CAD file's coordinate precision is far finer).
PIN_TOLERANCE = 1e-6


def check_part_pins(st: PlanetaryStage, path: str) -> None:
    """Each planet n rides on interface ``pin_n`` of a carrier read from a file: that
    interface must exist and its master be the planet's centre, (R_c cos psi_n, R_c sin
    psi_n, 0) in the carrier's local axes (m)."""
    from fe_components.part.read import part_geometry
    part = st.carrier.component
    where = f"{path}.carrier.component"
    try:
        masters = {i.name: i.master for i in part_geometry(part).interfaces}
    except GeometryError as err:
        raise SceneError(f"{where}.{err.parameter}", err.value, err.reason) from None
    Rc = st.carrier_radius()
    for k, psi in enumerate(st.planet_angles()):
        name = f"pin_{k}"
        want = np.array([Rc * math.cos(psi), Rc * math.sin(psi), 0.0])
        if name not in masters:
            raise SceneError(f"{where}.interfaces", sorted(masters),
                             f"{part.path.name}: no interface {name!r} for planet {k} (the stage has "
                             f"{len(st.planet_angles())} planets: pin_0..pin_{len(st.planet_angles()) - 1})")
        gap = float(np.linalg.norm(masters[name] - want))
        if gap > PIN_TOLERANCE * Rc:
            i, _ = part.rule(name)
            raise SceneError(f"{where}.interfaces[{i}]", name,
                             f"{part.path.name}: the pin's master {np.round(masters[name], 6).tolist()} m is "
                             f"{gap:.4g} m from planet {k}'s centre {np.round(want, 6).tolist()} m (carrier "
                             f"radius {Rc:.6g} m, {math.degrees(psi):.6g} deg): the part does not reach the planet")


def expand_stages(scene) -> dict:
    """Bodies, bearings, meshes and fixed DOFs of ``scene`` with every planetary stage
    expanded (the scene's own elements first, then each stage's in order)."""
    parts = [expand_stage(st, f"stages[{i}]") for i, st in enumerate(scene.stages)]
    return {key: getattr(scene, key) + sum((p[key] for p in parts), ())
            for key in ("bodies", "bearings", "meshes", "fixed")}


def expand_stage(st: PlanetaryStage, path: str = "stage") -> dict:
    """Bodies, bearings, meshes and fixed DOFs of one planetary stage (``path``: its scene
    path, for errors)."""
    E = axis_frame(st.axis)
    c = np.asarray(st.center if st.center is not None else (0.0, 0.0, 0.0), float)
    Rc = st.carrier_radius()
    n = st.name
    bodies, bearings, fixed, meshes = [], [], [], []

    def central(role: str, m: Member):
        bname = f"{n}.{role}"
        comp = None
        if m.component is not None:
            comp = carrier_pins(st, path)
        bodies.append(Body(name=bname, mass=m.mass, polar_inertia=m.polar_inertia,
                           transverse_inertia=m.transverse_inertia, position=tuple(c),
                           axis=tuple(E[:, 2]), fidelity=m.fidelity, stage=n, role=role,
                           component=comp, flex=m.flex))
        if m.support == "bearing":
            b = m.bearing
            bearings.append(Bearing(body=bname, **b.stiffnesses(), **b.dampings(), name=f"{bname}.bearing",
                                    interface=m.bearing_interface if comp is not None else None))
        elif m.support == "fixed":
            fixed.append(Fixed(body=bname))
        return bname

    sun = central("sun", st.sun)
    ring = central("ring", st.ring)
    carrier = central("carrier", st.carrier)
    pl = st.planets
    for i, psi in enumerate(st.planet_angles()):
        var_sun, var_ring = stage_variations(st, path, psi)
        pos = c + Rc * (math.cos(psi) * E[:, 0] + math.sin(psi) * E[:, 1])
        pname = f"{n}.planet{i}"
        bodies.append(Body(name=pname, mass=pl.mass, polar_inertia=pl.polar_inertia,
                           transverse_inertia=pl.transverse_inertia, position=tuple(pos),
                           axis=tuple(E[:, 2]), frame=carrier, fidelity=pl.fidelity,
                           stage=n, role="planet"))
        b = pl.bearing
        # the planet's bearing axes: x radial, y tangential (the planet's axes are E's)
        bearings.append(Bearing(body=pname, **b.stiffnesses(), **b.dampings(), name=f"{pname}.bearing", radial_angle=psi,
                                frame_interface=f"pin_{i}" if st.carrier.component is not None else None))
        # Sun closes its mesh turning in +drive_sign; the planet it pushes turns the other
        # way and so closes the ring mesh turning in -drive_sign.
        meshes.append(GearMesh(gear1=sun, gear2=pname, stiffness=st.k_mesh_sun,
                               base_radius1=st.sun.base_radius, base_radius2=pl.base_radius,
                               pressure_angle=st.pressure_angle_sun, helix_angle=st.mesh_helix_angle(),
                               drive_sign=st.drive_sign, name=f"{n}.sun-planet{i}",
                               contact_point=st.contact_point, damping=st.c_mesh_sun,
                               backlash=st.backlash, variation=var_sun))
        meshes.append(GearMesh(gear1=pname, gear2=ring, stiffness=st.k_mesh_ring,
                               base_radius1=pl.base_radius, base_radius2=-st.ring.base_radius,
                               pressure_angle=st.pressure_angle_ring, helix_angle=-st.mesh_helix_angle(),
                               drive_sign=-st.drive_sign, name=f"{n}.planet{i}-ring",
                               contact_point=st.contact_point, damping=st.c_mesh_ring,
                               backlash=st.backlash, variation=var_ring and dataclasses.replace(
                                   var_ring, counting_gear="gear2")))
    return {"bodies": tuple(bodies), "bearings": tuple(bearings), "meshes": tuple(meshes),
            "fixed": tuple(fixed)}
