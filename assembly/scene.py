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

Every number field declares its unit and range here (:func:`fe_components.fields.quantity`:
finite, of physical magnitude, in range), every name field its rule (:func:`name_field`);
:mod:`assembly.schema` checks both, the same way for a TOML table and for dataclasses
built in Python, before any other rule compares or combines them.
"""
from __future__ import annotations

import contextvars
import dataclasses
import math
from dataclasses import dataclass, field
from typing import Literal, Optional, get_args

import numpy as np

from fe_components.fields import quantity
from fe_components.material import STEEL, Material
from fe_components.params import MAX_PLANETS, ComponentParams, GearTeeth

from .errors import SceneError

HOUSING = "housing"
#: Band of interest (Hz) when a scene does not give ``band_hz``.
DEFAULT_BAND_HZ = 3000.0
#: Tables, plots, images and modal stresses show the modes up to this multiple of the band
#: (:attr:`Scene.display_limit_hz`); modes above it are flagged "outside the band". Matches
#: the default Craig-Bampton cutoff factor (assembly.flexible.CUTOFF_FACTOR), so with default
#: reductions every mode shown lies below every flexible body's cutoff.
DISPLAY_BAND_FACTOR = 1.5
DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")
Fidelity = Literal["torsional", "rigid", "flexible"]
Vec3 = tuple[float, float, float]
Support = Literal["bearing", "fixed", "floating"]
#: Most fixed-interface modes one flexible body may keep (``flex.n_modes``, or the modes
#: below its cutoff): a superelement of a few hundred modes already resolves a band far
#: above any drivetrain excitation, while the modes of a cutoff without bound (every
#: interior mode of a 50k-DOF mesh: 2.4 GB, many minutes) exhaust the machine.
MAX_MODES = 500
#: Longest name (characters) of a body, stage, bearing, mesh, shaft, load case or scene:
#: names become parts of output file names.
MAX_NAME_LENGTH = 64
_HALF_PI = math.pi / 2


def angle(default=dataclasses.MISSING, **rule):
    """Field holding an angle in radians (TOML may give ``<name>_deg`` instead)."""
    return quantity("rad", default, angle=True, **rule)


def name_field(default=dataclasses.MISSING):
    """Field holding a name: non-empty, at most MAX_NAME_LENGTH characters, no control
    characters and no path separators (names become parts of file names)."""
    return field(default=default, metadata={"name": True})


def stiffness(unit: str, default=dataclasses.MISSING):
    """A bearing stiffness (N/m or N m/rad): >= 0, ``inf`` = rigid."""
    return quantity(unit, default, ge=0.0, inf_ok=True)


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

    mesh_size: Optional[float] = quantity("m", None, gt=0.0)
    order: Literal[1, 2] = 2
    n_modes: Optional[int] = quantity("", None, integer=True, ge=0, le=MAX_MODES,
                                      hint="0 = Guyan; at most MAX_MODES")
    cutoff_hz: Optional[float] = quantity("Hz", None, gt=0.0)
    couplings: Optional[dict] = None
    material: Material = STEEL
    residual_vectors: bool = True


@dataclass(frozen=True)
class Body:
    """A body. Inertia about its centre of mass, local axes.

    Give ``mass`` and either ``polar_inertia`` (about the rotation axis, kg m^2) with
    optional ``transverse_inertia`` (default polar/2, a thin disc), or a full 3x3
    ``inertia_tensor`` in the body's local axes (x, y, axis) -- or instead a ``component``
    (:class:`fe_components.params.PinionParams`, ``WheelParams``, ``CarrierParams`` or
    ``CylinderParams``; a scene file gives a table with ``kind``, converted once by
    :mod:`assembly.schema`, as is a plain dict given in Python), whose mesh then gives mass
    and inertia at every fidelity; ``position`` is then where the component's local origin
    sits (its local z along ``axis``). A carrier body needs its ``planet_angles`` and
    ``pin_pitch_radius``. ``fidelity = "flexible"`` needs a component; ``flex``
    says how it is meshed and reduced. ``fidelity`` left out: the scene's ``fidelity``
    (default "rigid").

    A gear body may carry its ``teeth`` (:class:`fe_components.params.GearTeeth`, ISO 21771:
    ``n_teeth``, ``normal_module``, ``pressure_angle``, ``face_width``, ``helix_angle``,
    ``profile_shift``, ...; angles may be given in degrees under ``<name>_deg``), or its
    component's ``teeth`` serve; giving both, they must be equal (one definition). A mesh
    between gears with teeth then derives base radii, working pressure angle and helix
    (:mod:`assembly.gear_data`). ``internal = true``: the teeth are internal (a ring gear;
    ``teeth.n_teeth`` stays positive). ``position`` (m) left out: (0, 0, 0), or where a mesh
    with ``place`` puts the body (:mod:`assembly.placement`).
    """

    name: str = name_field()
    mass: Optional[float] = quantity("kg", None, gt=0.0)
    polar_inertia: Optional[float] = quantity("kg m^2", None, gt=0.0)
    transverse_inertia: Optional[float] = quantity("kg m^2", None, gt=0.0)
    inertia_tensor: Optional[tuple[Vec3, Vec3, Vec3]] = quantity("kg m^2", None)
    position: Optional[Vec3] = quantity("m", None)
    axis: Vec3 = quantity("", (0.0, 0.0, 1.0))
    frame: str = HOUSING
    fidelity: Optional[Fidelity] = None
    stage: Optional[str] = None
    role: Optional[str] = None
    component: Optional[ComponentParams] = None
    flex: Optional[FlexOptions] = None
    teeth: Optional[GearTeeth] = None
    internal: bool = False

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
    k_radial: float = stiffness("N/m")
    k_axial: float = stiffness("N/m")
    k_tilt: float = stiffness("N m/rad")
    k_torsion: float = stiffness("N m/rad", 0.0)
    frame: Optional[str] = None
    position: Optional[Vec3] = quantity("m", None)
    name: Optional[str] = name_field(None)
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
    transverse operating pressure angle (rad, > 0); ``helix_angle`` (rad) is the line of
    action's inclination to the transverse plane (the base helix angle), positive when gear 1
    is left-hand (from teeth: minus gear 1's signed base helix angle, see
    :func:`assembly.gear_data.mesh_helix`). ``drive_sign`` (+1/-1) picks the loaded flank: the
    sense of rotation of gear 1 about its axis that closes the mesh with gear 2 held.
    The centre distance between the gear centres must equal (r1 + r2)/cos(pressure_angle).
    ``center1``/``center2`` default to the bodies' positions (the gear's mid-face centre).
    ``contact_point``: 'pitch' (default; one shared point, no strain under common rigid
    motion) or 'tangent' (each gear's base-circle tangent point, the convention of the
    published Kahraman/Peeters helical-pair table; see :func:`assembly.elements.gear_mesh`).

    From teeth: when both gears carry teeth (``Body.teeth`` or their component's), leave
    out ``base_radius1/2``, ``pressure_angle`` and ``helix_angle``: they are derived (ISO
    21771, :mod:`assembly.gear_data`): base radii ``z m_n cos(alpha_t) / (2 cos beta)``
    (negative for the gear whose body says ``internal``), the working transverse pressure
    angle from the profile shifts, and gear 1's helix angle. Numbers given as well must
    agree with the teeth (relative 1e-6), else the scene is refused naming both. A gear with
    teeth meshing a gear without: its base radius, if typed, must agree with its teeth.
    ``place`` ("gear1" or "gear2") puts that gear at the working centre distance from the
    other, along ``centre_line_angle`` (rad, in the other gear's axes from its local x;
    default 0) -- see :mod:`assembly.placement`.
    """

    gear1: str
    gear2: str
    stiffness: float = quantity("N/m", gt=0.0)
    base_radius1: Optional[float] = quantity("m", None, nonzero=True, hint="negative = internal gear")
    base_radius2: Optional[float] = quantity("m", None, nonzero=True, hint="negative = internal gear")
    pressure_angle: Optional[float] = angle(None, gt=0.0, lt=_HALF_PI)
    helix_angle: Optional[float] = angle(None, abs_lt=_HALF_PI)
    drive_sign: int = 1
    name: Optional[str] = name_field(None)
    center1: Optional[Vec3] = quantity("m", None)
    center2: Optional[Vec3] = quantity("m", None)
    contact_point: Literal["pitch", "tangent"] = "pitch"
    interface1: Optional[str] = None
    interface2: Optional[str] = None
    place: Optional[Literal["gear1", "gear2"]] = None
    centre_line_angle: float = angle(0.0, abs_lt=4 * math.pi)


@dataclass(frozen=True)
class Shaft:
    """Shaft spring between two bodies: torsion (N m/rad), optional bending (N m/rad),
    axial and shear (N/m), acting on their relative motion at ``position`` (default: midway)
    in the axes of ``body1``."""

    body1: str
    body2: str
    k_torsion: float = quantity("N m/rad", gt=0.0)
    k_bending: float = quantity("N m/rad", 0.0, ge=0.0)
    k_axial: float = quantity("N/m", 0.0, ge=0.0)
    k_shear: float = quantity("N/m", 0.0, ge=0.0)
    position: Optional[Vec3] = quantity("m", None)
    name: Optional[str] = name_field(None)
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

    k_radial: float = stiffness("N/m")
    k_axial: float = stiffness("N/m")
    k_tilt: float = stiffness("N m/rad")
    k_torsion: float = stiffness("N m/rad", 0.0)


@dataclass(frozen=True)
class Member:
    """Sun, ring or carrier. ``support``: 'bearing' (to the housing, stiffness ``bearing``;
    a ring on a torsional spring is a bearing with k_torsion), 'fixed' (all six DOFs held)
    or 'floating' (no bearing at all). ``base_radius`` (m, positive) for sun and ring.
    The carrier may instead be a ``component`` (a :class:`fe_components.params.CarrierParams`,
    or a table / dict of ``kind = "carrier"``, without ``planet_angles``/``pin_pitch_radius``:
    the stage places the pins at its planets) with
    ``flex`` options; its bearing then acts at the component's ``bearing_interface``.
    ``teeth`` (number of teeth, sun and ring) and ``profile_shift`` (ISO 21771 x, the
    ring's as given in ISO's convention) replace ``base_radius`` when the stage gives
    ``normal_module`` (see :class:`PlanetaryStage`). ``fidelity`` left out: the scene's."""

    mass: Optional[float] = quantity("kg", None, gt=0.0)
    polar_inertia: Optional[float] = quantity("kg m^2", None, gt=0.0)
    transverse_inertia: Optional[float] = quantity("kg m^2", None, gt=0.0)
    base_radius: Optional[float] = quantity("m", None, gt=0.0, hint="give the ring's as positive")
    support: Support = "bearing"
    bearing: Optional[BearingSpec] = None
    fidelity: Optional[Fidelity] = None
    component: Optional[ComponentParams] = None
    flex: Optional[FlexOptions] = None
    bearing_interface: str = "bearing_b"
    teeth: Optional[int] = quantity("", None, integer=True, ge=3)
    profile_shift: float = quantity("", 0.0, gt=-1.0, lt=1.0)


@dataclass(frozen=True)
class Planets:
    """N identical planets at ``angles`` (rad; default equally spaced from 0).
    ``outer_radius`` (m, default the pitch radius) is used for the overlap check.
    ``teeth`` and ``profile_shift`` (ISO 21771) replace ``base_radius`` when the stage gives
    ``normal_module``. ``fidelity`` left out: the scene's."""

    count: int = quantity("", integer=True, ge=1, le=MAX_PLANETS)
    mass: float = quantity("kg", gt=0.0)
    polar_inertia: float = quantity("kg m^2", gt=0.0)
    bearing: BearingSpec = field()
    base_radius: Optional[float] = quantity("m", None, gt=0.0)
    transverse_inertia: Optional[float] = quantity("kg m^2", None, gt=0.0)
    angles: Optional[tuple[float, ...]] = angle(None)
    outer_radius: Optional[float] = quantity("m", None, gt=0.0)
    fidelity: Optional[Fidelity] = None
    teeth: Optional[int] = quantity("", None, integer=True, ge=3)
    profile_shift: float = quantity("", 0.0, gt=-1.0, lt=1.0)


@dataclass(frozen=True)
class PlanetaryStage:
    """A planetary stage. Mesh stiffness N/m; pressure angles transverse, rad.

    From teeth: ``normal_module`` (m), ``normal_pressure_angle`` (rad, or ``_deg``) and
    ``helix_angle`` (the sun's, rad) with ``teeth`` and ``profile_shift`` on ``sun``,
    ``planets`` and ``ring`` derive the base radii, both working pressure angles and the
    carrier radius (:func:`assembly.gear_data.stage_from_teeth`, ISO 21771): the carrier
    radius is the sun-planet working centre distance; the planet-ring one must agree to
    :data:`assembly.gear_data.RING_CENTRE_TOLERANCE` normal modules, and the ring mesh works
    at the carrier radius (``cos(alpha_ring) = (r_b,ring - r_b,planet) / R_c``). Typed base
    radii and pressure angles given as well must agree (relative 1e-6).

    ``helix_angle`` is therefore read two ways (:meth:`mesh_helix_angle`): without
    ``normal_module`` it is the sun-planet meshes' line-of-action helix, as
    ``[[meshes]].helix_angle``; with it, the sun teeth's reference helix angle (> 0 right
    hand, as ``GearTeeth.helix_angle``), and the meshes take the signed base helix angle.
    """

    name: str = name_field()
    sun: Member = field()
    ring: Member = field()
    carrier: Member = field()
    planets: Planets = field()
    k_mesh_sun: float = quantity("N/m", gt=0.0)
    k_mesh_ring: float = quantity("N/m", gt=0.0)
    pressure_angle_sun: Optional[float] = angle(None, gt=0.0, lt=_HALF_PI)
    pressure_angle_ring: Optional[float] = angle(None, gt=0.0, lt=_HALF_PI)
    helix_angle: float = angle(0.0, abs_lt=_HALF_PI)
    normal_module: Optional[float] = quantity("m", None, gt=0.0)
    normal_pressure_angle: Optional[float] = angle(None, gt=0.0, lt=math.radians(45))
    drive_sign: int = 1
    center: Vec3 = quantity("m", (0.0, 0.0, 0.0))
    axis: Vec3 = quantity("", (0.0, 0.0, 1.0))
    contact_point: Literal["pitch", "tangent"] = "pitch"

    def carrier_radius(self) -> float:
        """Planet-centre radius (m) from the sun-planet mesh geometry."""
        return (self.sun.base_radius + self.planets.base_radius) / math.cos(self.pressure_angle_sun)

    def mesh_helix_angle(self) -> float:
        """Line-of-action helix (rad) of the sun-planet meshes (the planet-ring meshes take
        its negative): ``helix_angle`` as typed, or from the sun's teeth minus their base
        helix angle (:func:`assembly.gear_data.mesh_helix`)."""
        if self.normal_module is None:
            return self.helix_angle
        from fe_components.gear_pair import base_helix_angle
        return -base_helix_angle(self.normal_pressure_angle, self.helix_angle)

    def planet_angles(self) -> tuple[float, ...]:
        n = self.planets.count
        if self.planets.angles is not None:
            return tuple(self.planets.angles)
        return tuple(2 * math.pi * i / n for i in range(n))


@dataclass(frozen=True)
class LoadCase:
    """Static load case: ``torque`` (N m) about ``input``'s axis, reacted by holding
    ``output`` against rotation about its own axis (relative to the housing).
    ``input_interface`` / ``output_interface`` name where the torque enters / where the
    output is held on a component body (e.g. its coupling seat): the interface's master
    node. A scene gives one ``[load]`` or a list ``[[loads]]`` (not both; names unique);
    see docs/static.md."""

    input: str
    output: str
    torque: float = quantity("N m", nonzero=True)
    input_interface: Optional[str] = None
    output_interface: Optional[str] = None
    name: str = name_field("rated torque")


#: True while :func:`derive` builds a scene from an already validated one.
_TRUSTED = contextvars.ContextVar("flexgear_trusted_scene", default=False)


@dataclass(frozen=True)
class Scene:
    """A drivetrain: bodies and the springs that join them (SI units throughout).

    ``stages`` holds planetary-stage descriptions; :meth:`expanded` turns each into bodies,
    bearings and meshes. ``band_hz``: the frequency band of interest (Hz), which sets the
    Craig-Bampton cutoff of flexible bodies. ``fidelity``: the default fidelity of every
    body, stage member and planets table that does not give its own (default "rigid").
    Construction first derives the gear numbers from teeth and places the bodies meshes
    place (:func:`assembly.gear_data.resolve`), then validates everything (``SceneError``
    on bad input); the scene then holds the derived numbers.
    """

    name: str = name_field("scene")
    description: str = ""
    bodies: tuple[Body, ...] = ()
    bearings: tuple[Bearing, ...] = ()
    meshes: tuple[GearMesh, ...] = ()
    shafts: tuple[Shaft, ...] = ()
    fixed: tuple[Fixed, ...] = ()
    stages: tuple[PlanetaryStage, ...] = ()
    band_hz: Optional[float] = quantity("Hz", None, gt=0.0)
    load: Optional[LoadCase] = None
    loads: tuple[LoadCase, ...] = ()
    fidelity: Optional[Fidelity] = None

    def __post_init__(self):
        for f in ("bodies", "bearings", "meshes", "shafts", "fixed", "stages", "loads"):
            if isinstance(getattr(self, f), list):  # Python callers may pass lists
                object.__setattr__(self, f, tuple(getattr(self, f)))
        if not _TRUSTED.get():
            # these read the types defined here: import when used
            from .gear_data import resolve
            from .schema import checked_fields
            from .validate import validate_scene
            # types and ranges before anything derives from them; a component given as a
            # table (dict) becomes its parameter object here, once
            for key, value in checked_fields(self).items():
                object.__setattr__(self, key, value)
            resolved = resolve(self)
            # what the user wrote, before numbers derived from teeth and the scene's default
            # fidelity were filled in: editing and saving work on it (see :meth:`as_given`)
            object.__setattr__(self, "_given", {key: getattr(self, key) for key in resolved})
            for key, value in resolved.items():
                object.__setattr__(self, key, value)
            validate_scene(self)

    def as_given(self, field_name: str):
        """Field ``field_name`` as the user gave it: for bodies, meshes and stages, before
        gear numbers were derived from teeth, bodies placed by meshes and the scene's default
        fidelity filled in (a changed tooth count then derives new numbers instead of
        contradicting the old ones)."""
        return self.__dict__.get("_given", {}).get(field_name, getattr(self, field_name))

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

    def load_cases(self) -> tuple[tuple[str, LoadCase], ...]:
        """(scene path, load case) of every static load case: ``[load]`` or ``[[loads]]``."""
        if self.load is not None:
            return (("load", self.load),)
        return tuple((f"loads[{i}]", lc) for i, lc in enumerate(self.loads))

    @property
    def band(self) -> float:
        """The band of interest (Hz): ``band_hz``, or DEFAULT_BAND_HZ when not given."""
        return self.band_hz or DEFAULT_BAND_HZ

    def get_value(self, path: str):
        """The value at a scene path such as ``"bearings[2].k_radial"`` (:func:`assembly.edit.get_value`)."""
        from .edit import get_value
        return get_value(self, path)

    def with_value(self, path: str, value) -> "Scene":
        """New validated scene with the field at ``path`` (e.g. ``"shafts.quill.k_torsion"``,
        ``"meshes[0].helix_angle_deg"``) set to ``value`` (:func:`assembly.edit.with_value`)."""
        from .edit import with_value
        return with_value(self, path, value)

    def with_values(self, changes: dict) -> "Scene":
        """New scene with every ``{path: value}`` set, validated once (:func:`assembly.edit.with_values`)."""
        from .edit import with_values
        return with_values(self, changes)

    @property
    def display_limit_hz(self) -> float:
        """Highest frequency (Hz) shown by default: DISPLAY_BAND_FACTOR x the band."""
        return DISPLAY_BAND_FACTOR * self.band

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
    """Copy of ``scene`` with ``bodies`` (names in the expanded scene, or one name; default
    all) at ``fidelity``. Planetary stages stay stages -- the chosen members, or all the
    planets, take the fidelity -- so an error of the new scene names the table the user
    wrote; only a choice that splits the planets of one stage expands the scene."""
    allowed = get_args(Fidelity)
    if not isinstance(fidelity, str) or fidelity not in allowed:
        raise SceneError("fidelity", fidelity, f"must be one of {list(allowed)}")
    sc = scene.expanded()
    have = [b.name for b in sc.bodies]
    chosen = set(have) if bodies is None else {bodies} if isinstance(bodies, str) else set(bodies)
    unknown = sorted(chosen - set(have), key=str)
    if unknown:
        raise SceneError("bodies", unknown[0], f"no body of that name; have {have}")

    def pick(items):
        return tuple(dataclasses.replace(b, fidelity=fidelity) if b.name in chosen else b for b in items)

    stages = []
    for st in scene.stages:
        planets = {b.name for b in sc.bodies[len(scene.bodies):] if b.stage == st.name and b.role == "planet"}
        if chosen & planets not in (set(), planets):  # some planets of a stage, not all
            return dataclasses.replace(sc, bodies=pick(sc.bodies))
        changes = {role: dataclasses.replace(getattr(st, role), fidelity=fidelity)
                   for role in ("sun", "ring", "carrier") if f"{st.name}.{role}" in chosen}
        if planets and planets <= chosen:
            changes["planets"] = dataclasses.replace(st.planets, fidelity=fidelity)
        stages.append(dataclasses.replace(st, **changes))
    return dataclasses.replace(scene, bodies=pick(scene.bodies), stages=tuple(stages))


#: The bearing stiffness fields, each once, in field order.
_STIFFNESSES = tuple(dict.fromkeys(Bearing.FIELDS))


def scale_bearings(scene: Scene, factor: float, directions=("k_radial", "k_axial", "k_tilt")) -> Scene:
    """Copy of ``scene`` with the named bearing stiffnesses times ``factor`` (finite, > 0):
    its own bearings and the bearing tables of its planetary stages (kept as stages)."""
    if isinstance(factor, bool) or not isinstance(factor, (int, float)) or not 0 < factor < math.inf:
        raise SceneError("factor", factor, "must be a finite number > 0")
    for d in directions:
        if d not in _STIFFNESSES:
            raise SceneError("directions", d, f"must be among {list(_STIFFNESSES)}")

    def scaled(b):
        return None if b is None else dataclasses.replace(b, **{d: getattr(b, d) * factor for d in directions})

    stages = tuple(dataclasses.replace(
        st, planets=dataclasses.replace(st.planets, bearing=scaled(st.planets.bearing)),
        **{role: dataclasses.replace(getattr(st, role), bearing=scaled(getattr(st, role).bearing))
           for role in ("sun", "ring", "carrier")}) for st in scene.stages)
    return dataclasses.replace(scene, bearings=tuple(scaled(b) for b in scene.bearings), stages=stages)
