"""Scene model: bodies, bearings, gear meshes, shafts, fixed DOFs and planetary stages.

All quantities SI: metres, kilograms, newtons, seconds, radians. Stiffnesses: translational
N/m, rotational N m/rad. ``math.inf`` for a bearing stiffness means "rigid": that relative
DOF is constrained exactly instead of being modelled as a huge spring.

A body's six DOFs are ``x, y, z, rx, ry, rz`` in its local axes (``z`` = rotation axis),
measured relative to its reference frame (the housing, or another body: planets live in
the carrier's frame). Construction validates the whole scene and raises
:class:`~assembly.errors.SceneError` naming the field path and value.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Literal, Optional

import numpy as np

from .errors import SceneError
from .flexible import FlexOptions

HOUSING = "housing"
DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")
Fidelity = Literal["torsional", "rigid", "flexible"]
Vec3 = tuple[float, float, float]


def angle(default=dataclasses.MISSING):
    """Field holding an angle in radians (TOML may give ``<name>_deg`` instead)."""
    return field(default=default, metadata={"angle": True})


def _positive(path, value, what="must be > 0"):
    if not (value > 0):
        raise SceneError(path, value, what)


def _nonneg(path, value):
    if not (value >= 0):
        raise SceneError(path, value, "must be >= 0 (N/m or N m/rad; inf = rigid)")


def _vector(path, value):
    v = np.asarray(value, float)
    if not np.all(np.isfinite(v)):
        raise SceneError(path, list(value), "must be finite")
    return v


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

    def check(self, path: str) -> None:
        if not self.name or self.name == HOUSING or "/" in self.name:
            raise SceneError(f"{path}.name", self.name, "must be a non-empty name other than 'housing'")
        if self.component is not None:
            for f in ("mass", "polar_inertia", "transverse_inertia", "inertia_tensor"):
                if getattr(self, f) is not None:
                    raise SceneError(f"{path}.{f}", getattr(self, f),
                                     "a body with a component takes mass and inertia from its mesh")
            if self.flex is not None:
                self.flex.check(f"{path}.flex")
            _vector(f"{path}.position", self.position)
            return
        if self.fidelity == "flexible":
            raise SceneError(f"{path}.fidelity", self.fidelity,
                             "a flexible body needs a 'component' table (pinion, wheel, carrier, cylinder)")
        if self.flex is not None:
            raise SceneError(f"{path}.flex", "table", "only a body with a component takes flex options")
        if self.mass is None:
            raise SceneError(f"{path}.mass", None, "missing required field (kg)")
        _positive(f"{path}.mass", self.mass, "must be > 0 kg")
        if (self.inertia_tensor is None) == (self.polar_inertia is None):
            raise SceneError(f"{path}.polar_inertia", self.polar_inertia,
                             "give exactly one of polar_inertia or inertia_tensor")
        if self.polar_inertia is not None:
            _positive(f"{path}.polar_inertia", self.polar_inertia, "must be > 0 kg m^2")
            if self.transverse_inertia is not None:
                _positive(f"{path}.transverse_inertia", self.transverse_inertia, "must be > 0 kg m^2")
        else:
            J = np.asarray(self.inertia_tensor, float)
            if not np.allclose(J, J.T, rtol=1e-12, atol=0) or np.linalg.eigvalsh(J).min() <= 0:
                raise SceneError(f"{path}.inertia_tensor", self.inertia_tensor,
                                 "must be symmetric positive definite (kg m^2)")
        _vector(f"{path}.position", self.position)
        a = _vector(f"{path}.axis", self.axis)
        if np.linalg.norm(a) == 0:
            raise SceneError(f"{path}.axis", list(self.axis), "must be a non-zero vector")


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

    def diagonal(self) -> np.ndarray:
        return np.array([self.k_radial, self.k_radial, self.k_axial,
                         self.k_tilt, self.k_tilt, self.k_torsion], float)

    def check(self, path: str) -> None:
        for f in ("k_radial", "k_axial", "k_tilt", "k_torsion"):
            _nonneg(f"{path}.{f}", getattr(self, f))
        if self.position is not None:
            _vector(f"{path}.position", self.position)


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

    def check(self, path: str) -> None:
        if self.gear1 == self.gear2:
            raise SceneError(f"{path}.gear2", self.gear2, "a gear cannot mesh with itself")
        _positive(f"{path}.stiffness", self.stiffness, "must be > 0 N/m")
        if not math.isfinite(self.stiffness):
            raise SceneError(f"{path}.stiffness", self.stiffness, "must be finite")
        for f in ("base_radius1", "base_radius2"):
            v = getattr(self, f)
            if not (math.isfinite(v) and v != 0):
                raise SceneError(f"{path}.{f}", v, "must be a non-zero finite radius in m (negative = internal gear)")
        if self.base_radius1 < 0 and self.base_radius2 < 0:
            raise SceneError(f"{path}.base_radius2", self.base_radius2, "two internal gears cannot mesh")
        if self.base_radius1 + self.base_radius2 == 0:
            raise SceneError(f"{path}.base_radius2", self.base_radius2,
                             "internal and external base radii are equal: zero centre distance")
        if not (0 < self.pressure_angle < math.pi / 2):
            raise SceneError(f"{path}.pressure_angle", self.pressure_angle, "must lie in (0, 90) deg")
        if not (abs(self.helix_angle) < math.pi / 2):
            raise SceneError(f"{path}.helix_angle", self.helix_angle, "|helix angle| must be < 90 deg")
        if self.drive_sign not in (1, -1):
            raise SceneError(f"{path}.drive_sign", self.drive_sign, "must be +1 or -1")


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

    def diagonal(self) -> np.ndarray:
        return np.array([self.k_shear, self.k_shear, self.k_axial,
                         self.k_bending, self.k_bending, self.k_torsion], float)

    def check(self, path: str) -> None:
        if self.body1 == self.body2:
            raise SceneError(f"{path}.body2", self.body2, "a shaft needs two different bodies")
        _positive(f"{path}.k_torsion", self.k_torsion, "must be > 0 N m/rad")
        for f in ("k_torsion", "k_bending", "k_axial", "k_shear"):
            v = getattr(self, f)
            _nonneg(f"{path}.{f}", v)
            if not math.isfinite(v):
                raise SceneError(f"{path}.{f}", v, "must be finite (use a bearing for a rigid joint)")


@dataclass(frozen=True)
class Fixed:
    """DOFs of ``body`` (local names x, y, z, rx, ry, rz) held at zero relative to its frame."""

    body: str
    dofs: tuple[str, ...] = DOF_NAMES

    def check(self, path: str) -> None:
        for i, d in enumerate(self.dofs):
            if d not in DOF_NAMES:
                raise SceneError(f"{path}.dofs[{i}]", d, f"must be one of {list(DOF_NAMES)}")


@dataclass(frozen=True)
class Scene:
    """A drivetrain: bodies and the springs that join them (SI units throughout).

    ``stages`` holds planetary-stage descriptions; :meth:`expanded` turns each into bodies,
    bearings and meshes. Construction validates everything (``SceneError`` on bad input).
    """

    name: str = "scene"
    description: str = ""
    bodies: tuple[Body, ...] = ()
    bearings: tuple[Bearing, ...] = ()
    meshes: tuple[GearMesh, ...] = ()
    shafts: tuple[Shaft, ...] = ()
    fixed: tuple[Fixed, ...] = ()
    stages: tuple["PlanetaryStage", ...] = ()
    band_hz: Optional[float] = None
    load: Optional["LoadCase"] = None

    def __post_init__(self):
        from .validate import validate_scene
        validate_scene(self)

    def expanded(self) -> "Scene":
        """The same scene with every planetary stage expanded into plain elements."""
        from .planetary import expand_stage
        if not self.stages:
            return self
        parts = [expand_stage(st, f"stages[{i}]") for i, st in enumerate(self.stages)]
        return dataclasses.replace(
            self,
            bodies=self.bodies + sum((p.bodies for p in parts), ()),
            bearings=self.bearings + sum((p.bearings for p in parts), ()),
            meshes=self.meshes + sum((p.meshes for p in parts), ()),
            fixed=self.fixed + sum((p.fixed for p in parts), ()),
            stages=(),
        )

    def body(self, name: str) -> Body:
        for b in self.expanded().bodies:
            if b.name == name:
                return b
        raise KeyError(name)


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


from .loads import LoadCase  # noqa: E402  (dataclass used in annotations above)
from .planetary import PlanetaryStage  # noqa: E402  (dataclass used in annotations above)
