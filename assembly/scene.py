"""Scene data types: bodies, bearings, gear meshes, shafts, fixed DOFs, planetary stages,
flexible-body options and the static load case. Data only: the rules a scene must obey
live in :mod:`assembly.validate`, the stage builder in :mod:`assembly.planetary`.

All quantities SI: metres, kilograms, newtons, seconds, radians. Stiffnesses: translational
N/m, rotational N m/rad. ``math.inf`` for a bearing stiffness means "rigid": that relative
DOF is constrained exactly instead of being modelled as a huge spring.

A body's six DOFs are ``x, y, z, rx, ry, rz`` in its local axes (``z`` = rotation axis),
measured relative to its reference frame (the housing, or another body: planets live in
the carrier's frame). Constructing a :class:`Scene` validates it once and raises
:class:`~assembly.errors.SceneError` naming the field path and value; scenes derived
from a valid one by a change that cannot invalidate it (:func:`derive`) skip that check.
"""
from __future__ import annotations

import contextvars
import dataclasses
import math
from dataclasses import dataclass, field
from typing import Literal, Optional

import numpy as np

from fe_components.material import STEEL, Material

HOUSING = "housing"
DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")
Fidelity = Literal["torsional", "rigid", "flexible"]
Vec3 = tuple[float, float, float]
Support = Literal["bearing", "fixed", "floating"]


def angle(default=dataclasses.MISSING):
    """Field holding an angle in radians (TOML may give ``<name>_deg`` instead)."""
    return field(default=default, metadata={"angle": True})


@dataclass(frozen=True)
class FlexOptions:
    """How a component body is meshed and reduced.

    ``mesh_size`` (m; default from the component's thinnest wall), ``order`` (2 = P2
    tetrahedra), ``n_modes`` or ``cutoff_hz`` (Hz) of fixed-interface modes (default:
    CUTOFF_FACTOR x the scene's band), ``couplings`` {interface: 'rbe2'|'rbe3'},
    ``residual_vectors`` (default on): add the static response of the interior to the
    inertia of the interface motion (``cms.craig_bampton``), which carries the
    quasi-static part of every truncated mode for one more block solve.
    """

    mesh_size: Optional[float] = None
    order: Literal[1, 2] = 2
    n_modes: Optional[int] = None
    cutoff_hz: Optional[float] = None
    couplings: Optional[dict] = None
    material: Material = STEEL
    residual_vectors: bool = True


@dataclass(frozen=True)
class Body:
    """A body. Inertia about its centre of mass, local axes.

    Give ``mass`` and either ``polar_inertia`` (about the rotation axis, kg m^2) with
    optional ``transverse_inertia`` (default polar/2, a thin disc), or a full 3x3
    ``inertia_tensor`` in the body's local axes (x, y, axis) -- or instead a ``component``
    table (fe_components: pinion, wheel, carrier, cylinder), whose mesh then gives mass and
    inertia at every fidelity; ``position`` is then where the component's local origin sits
    (its local z along ``axis``). ``fidelity = "flexible"`` needs a component; ``flex``
    says how it is meshed and reduced.
    """

    name: str
    mass: Optional[float] = None
    polar_inertia: Optional[float] = None
    transverse_inertia: Optional[float] = None
    inertia_tensor: Optional[tuple[Vec3, Vec3, Vec3]] = None
    position: Vec3 = (0.0, 0.0, 0.0)
    axis: Vec3 = (0.0, 0.0, 1.0)
    frame: str = HOUSING
    fidelity: Fidelity = "rigid"
    stage: Optional[str] = None
    role: Optional[str] = None
    component: Optional[dict] = None
    flex: Optional[FlexOptions] = None

    def inertia_local(self) -> np.ndarray:
        """3x3 inertia tensor about the centre of mass in local axes (kg m^2)."""
        if self.inertia_tensor is not None:
            return np.asarray(self.inertia_tensor, float)
        jt = self.transverse_inertia if self.transverse_inertia is not None else self.polar_inertia / 2
        return np.diag([jt, jt, self.polar_inertia])


@dataclass(frozen=True)
class Bearing:
    """Diagonal 6x6 spring diag(k_radial, k_radial, k_axial, k_tilt, k_tilt, k_torsion).

    Acts on the motion of ``body`` relative to ``frame`` (default: the body's own reference
    frame) at ``position`` (default: the body's position, or the master node of
    ``interface`` for a body with a component), in the body's axes.
    Translational stiffness N/m, rotational N m/rad; ``inf`` constrains that direction.
    """

    body: str
    k_radial: float
    k_axial: float
    k_tilt: float
    k_torsion: float = 0.0
    frame: Optional[str] = None
    position: Optional[Vec3] = None
    name: Optional[str] = None
    interface: Optional[str] = None
    frame_interface: Optional[str] = None

    #: The field behind each entry of :meth:`diagonal` (local x, y, z, rx, ry, rz).
    FIELDS = ("k_radial", "k_radial", "k_axial", "k_tilt", "k_tilt", "k_torsion")

    def diagonal(self) -> np.ndarray:
        return np.array([getattr(self, f) for f in self.FIELDS], float)


@dataclass(frozen=True)
class GearMesh:
    """Linear spring along the line of action between two parallel-axis gears.

    ``base_radius`` (m) is negative for an internal (ring) gear. ``pressure_angle`` is the
    transverse operating pressure angle (rad, > 0); ``helix_angle`` (rad) is positive when
    the teeth of gear 1 are turned left. ``drive_sign`` (+1/-1) picks the loaded flank: the
    sense of rotation of gear 1 about its axis that closes the mesh with gear 2 held.
    The centre distance between the gear centres must equal (r1 + r2)/cos(pressure_angle).
    ``center1``/``center2`` default to the bodies' positions (the gear's mid-face centre).
    ``contact_point``: 'pitch' (default; one shared point, no strain under common rigid
    motion) or 'tangent' (each gear's base-circle tangent point, the convention of the
    published Kahraman/Peeters helical-pair table; see :func:`assembly.elements.gear_mesh`).
    """

    gear1: str
    gear2: str
    stiffness: float
    base_radius1: float
    base_radius2: float
    pressure_angle: float = angle()
    helix_angle: float = angle(0.0)
    drive_sign: int = 1
    name: Optional[str] = None
    center1: Optional[Vec3] = None
    center2: Optional[Vec3] = None
    contact_point: Literal["pitch", "tangent"] = "pitch"
    interface1: Optional[str] = None
    interface2: Optional[str] = None


@dataclass(frozen=True)
class Shaft:
    """Shaft spring between two bodies: torsion (N m/rad), optional bending (N m/rad),
    axial and shear (N/m), acting on their relative motion at ``position`` (default: midway)
    in the axes of ``body1``."""

    body1: str
    body2: str
    k_torsion: float
    k_bending: float = 0.0
    k_axial: float = 0.0
    k_shear: float = 0.0
    position: Optional[Vec3] = None
    name: Optional[str] = None
    interface1: Optional[str] = None
    interface2: Optional[str] = None

    #: The field behind each entry of :meth:`diagonal` (local x, y, z, rx, ry, rz).
    FIELDS = ("k_shear", "k_shear", "k_axial", "k_bending", "k_bending", "k_torsion")

    def diagonal(self) -> np.ndarray:
        return np.array([getattr(self, f) for f in self.FIELDS], float)


@dataclass(frozen=True)
class Fixed:
    """DOFs of ``body`` (local names x, y, z, rx, ry, rz) held at zero relative to its frame."""

    body: str
    dofs: tuple[str, ...] = DOF_NAMES


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
class LoadCase:
    """Rated-torque load case: ``torque`` (N m) about ``input``'s axis, reacted by holding
    ``output`` against rotation. ``input_interface`` names where the torque enters a
    flexible (component) body, e.g. its coupling seat."""

    input: str
    output: str
    torque: float
    input_interface: Optional[str] = None
    name: str = "rated torque"


#: True while :func:`derive` builds a scene from an already validated one.
_TRUSTED = contextvars.ContextVar("flexgear_trusted_scene", default=False)


@dataclass(frozen=True)
class Scene:
    """A drivetrain: bodies and the springs that join them (SI units throughout).

    ``stages`` holds planetary-stage descriptions; :meth:`expanded` turns each into bodies,
    bearings and meshes. ``band_hz``: the frequency band of interest (Hz), which sets the
    Craig-Bampton cutoff of flexible bodies. Construction validates everything
    (``SceneError`` on bad input).
    """

    name: str = "scene"
    description: str = ""
    bodies: tuple[Body, ...] = ()
    bearings: tuple[Bearing, ...] = ()
    meshes: tuple[GearMesh, ...] = ()
    shafts: tuple[Shaft, ...] = ()
    fixed: tuple[Fixed, ...] = ()
    stages: tuple[PlanetaryStage, ...] = ()
    band_hz: Optional[float] = None
    load: Optional[LoadCase] = None

    def __post_init__(self):
        if not _TRUSTED.get():
            from .validate import validate_scene  # validate reads these types: import when used
            validate_scene(self)

    def expanded(self) -> "Scene":
        """The same scene with every planetary stage expanded into plain elements (computed
        once per scene)."""
        if not self.stages:
            return self
        cached = self.__dict__.get("_expanded")
        if cached is None:
            from .planetary import expand_stages  # the builder reads these types
            cached = derive(self, **expand_stages(self), stages=())
            object.__setattr__(self, "_expanded", cached)
        return cached

    def body(self, name: str) -> Body:
        for b in self.expanded().bodies:
            if b.name == name:
                return b
        raise KeyError(name)


def derive(scene: Scene, **changes) -> Scene:
    """``dataclasses.replace(scene, **changes)`` without validating again: for changes
    that keep a validated scene valid (expanding stages, making a near-rigid bearing
    direction exact, holding a DOF of a body). Anything a user could get wrong goes
    through the constructor instead."""
    token = _TRUSTED.set(True)
    try:
        return dataclasses.replace(scene, **changes)
    finally:
        _TRUSTED.reset(token)


def with_fidelity(scene: Scene, fidelity: str, bodies=None) -> Scene:
    """Copy of ``scene`` (stages expanded) with ``bodies`` (default all) at ``fidelity``."""
    sc = scene.expanded()
    new = tuple(dataclasses.replace(b, fidelity=fidelity) if bodies is None or b.name in bodies else b
                for b in sc.bodies)
    return dataclasses.replace(sc, bodies=new)


def scale_bearings(scene: Scene, factor: float, directions=("k_radial", "k_axial", "k_tilt")) -> Scene:
    """Copy of ``scene`` (stages expanded) with the named bearing stiffnesses times ``factor``."""
    sc = scene.expanded()
    new = tuple(dataclasses.replace(b, **{d: getattr(b, d) * factor for d in directions})
                for b in sc.bearings)
    return dataclasses.replace(sc, bearings=new)
