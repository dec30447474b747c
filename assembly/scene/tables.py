"""Scene data types: bodies, bearings, gear meshes, shafts, fixed DOFs, planetary stages,
flexible-body options and the static load case. Data only: the rules a scene must obey
live in :mod:`assembly.scene.validate`, the stage builder in :mod:`assembly.scene.planetary`.

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
:mod:`assembly.scene.schema` checks both, the same way for a TOML table and for dataclasses
built in Python, before any other rule compares or combines them.
"""
from __future__ import annotations

import contextvars
import dataclasses
import functools
import math
from dataclasses import dataclass, field
from typing import Literal, Optional, get_args

import numpy as np

from fe_components.fields import quantity
from fe_components.gear_blank import GearBlank
from fe_components.material import STEEL, Material
from fe_components.params import MAX_PLANETS, ComponentParams, GearTeeth
from fe_components.sizes import FACE_WIDTH, GEAR_RADIUS, MODULE, SHAFT_DIAMETER

from .. import arguments
from ..errors import SceneError
from .time_domain import MeshVariation, Simulation
from .turbine import Turbine

HOUSING = "housing"
#: Band of interest (Hz) when a scene does not give ``band_hz``.
DEFAULT_BAND_HZ = 3000.0
#: Tables, plots, images and modal stresses show the modes up to this multiple of the band
#: (:attr:`Scene.display_limit_hz`); modes above it are flagged "outside the band". Matches
#: the default Craig-Bampton cutoff factor (assembly.scene.cutoffs.CB_CUTOFF_FACTOR), so with default
#: reductions every mode shown lies below every flexible body's cutoff.
DISPLAY_BAND_FACTOR = 1.5
DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")
Fidelity = Literal["torsional", "rigid", "flexible"]
Vec3 = tuple[float, float, float]
MemberSupport = Literal["bearing", "fixed", "floating"]
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


def damper(unit: str, default=0.0):
    """A viscous damping coefficient (N s/m or N m s/rad): finite, >= 0."""
    return quantity(unit, default, ge=0.0)


@dataclass(frozen=True)
class FlexOptions:
    """How a component body is meshed and reduced.

    ``mesh_size`` (m; default from the component's thinnest wall), ``order`` (2 = P2
    tetrahedra), ``n_modes`` or ``cutoff_hz`` (Hz) of fixed-interface modes (default:
    CB_CUTOFF_FACTOR x the scene's band), ``couplings`` {interface: 'rbe2'|'rbe3'},
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
    :mod:`assembly.scene.schema`, as is a plain dict given in Python), whose mesh then gives mass
    and inertia at every fidelity; ``position`` is then where the component's local origin
    sits (its local z along ``axis``); ``mass`` and inertias typed beside a component are the
    values its mesh replaces, reported beside the mesh's and never used
    (:mod:`assembly.model.body_table`). A carrier body needs its ``planet_angles`` and
    ``pin_pitch_radius``. ``fidelity = "flexible"`` needs a component; ``flex``
    says how it is meshed and reduced. ``fidelity`` left out: the scene's ``fidelity``
    (default "rigid").

    A gear body may carry its ``teeth`` (:class:`fe_components.params.GearTeeth`, ISO 21771:
    ``n_teeth``, ``normal_module``, ``pressure_angle``, ``face_width``, ``helix_angle``,
    ``profile_shift``, ...; angles may be given in degrees under ``<name>_deg``), or its
    component's ``teeth`` serve; giving both, they must be equal (one definition). A mesh
    between gears with teeth then derives base radii, working pressure angle and helix
    (:mod:`assembly.scene.gears`). ``internal = true``: the teeth are internal (a ring gear;
    ``teeth.n_teeth`` stays positive). ``position`` (m) left out: (0, 0, 0), or where a mesh
    with ``place`` puts the body (:mod:`assembly.scene.placement`).

    A body with ``teeth`` and without ``mass``, ``polar_inertia``, ``inertia_tensor`` and
    component takes its mass and inertias from its gear blank
    (:func:`fe_components.gear_blank.blank_mass_properties`: solid to the root circle, the
    tooth zone half metal, steel; a ring's rim 1.2 tooth depths thick), whose optional
    ``blank`` table (:class:`fe_components.gear_blank.GearBlank`) gives a bore, a ring's outer
    diameter or a length other than the face width (:func:`assembly.scene.gears.blank_body`).
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
    blank: Optional[GearBlank] = None

    def inertia_local(self) -> np.ndarray:
        """3x3 inertia tensor about the centre of mass in local axes (kg m^2)."""
        if self.inertia_tensor is not None:
            return np.asarray(self.inertia_tensor, float)
        jt = self.transverse_inertia if self.transverse_inertia is not None else self.polar_inertia / 2
        return np.diag([jt, jt, self.polar_inertia])


#: Every bearing stiffness field (:class:`Bearing`, :class:`BearingSpec`), in field order.
STIFFNESS_FIELDS = ("k_radial", "k_axial", "k_tilt", "k_torsion", "k_radial_x", "k_radial_y", "k_tilt_x", "k_tilt_y")
#: The stiffnesses that may be given per direction instead: {field: (its x field, its y field)}.
SPLIT_STIFFNESSES = {"k_radial": ("k_radial_x", "k_radial_y"), "k_tilt": ("k_tilt_x", "k_tilt_y")}
#: Every bearing damper field (:class:`Bearing`, :class:`BearingSpec`), in field order.
DAMPING_FIELDS = ("c_radial", "c_axial", "c_tilt", "c_torsion", "c_radial_x", "c_radial_y", "c_tilt_x", "c_tilt_y")
#: The dampers that may be given per direction instead, as the stiffnesses.
SPLIT_DAMPINGS = {"c_radial": ("c_radial_x", "c_radial_y"), "c_tilt": ("c_tilt_x", "c_tilt_y")}


class SixStiffnesses:
    """The diagonal 6x6 spring of a bearing table (:class:`Bearing`, :class:`BearingSpec`):
    ``k_radial`` along local x and y, or ``k_radial_x`` / ``k_radial_y`` (N/m); ``k_axial``
    along the axis (local z); ``k_tilt`` about local x and y, or ``k_tilt_x`` / ``k_tilt_y``
    (N m/rad); ``k_torsion`` about the axis. (Nejad et al. (2016), Wind Energy 19, Table VI
    give K_x axial, K_y, K_z radial and K_beta, K_gamma tilt: our k_axial, k_radial_x,
    k_radial_y, k_tilt_x, k_tilt_y.) Viscous dampers ``c_*`` (N s/m, N m s/rad; default 0)
    mirror the stiffnesses: ``c_radial`` or ``c_radial_x`` / ``c_radial_y``, ``c_axial``,
    ``c_tilt`` or ``c_tilt_x`` / ``c_tilt_y``, ``c_torsion``."""

    def diagonal_fields(self, prefix: str = "k") -> tuple[str, ...]:
        """The field behind each entry of :meth:`diagonal` (local x, y, z, rx, ry, rz):
        ``k_radial_x`` for x when given, else ``k_radial``; likewise y and the tilts.
        ``prefix="c"``: the same for the dampers (:meth:`damping_diagonal`)."""
        def pick(whole, part):
            return part if getattr(self, part) is not None else whole
        r, t = f"{prefix}_radial", f"{prefix}_tilt"
        return (pick(r, f"{r}_x"), pick(r, f"{r}_y"), f"{prefix}_axial",
                pick(t, f"{t}_x"), pick(t, f"{t}_y"), f"{prefix}_torsion")

    def damping_diagonal(self) -> np.ndarray:
        """diag(c_x, c_y, c_axial, c_rx, c_ry, c_torsion) (N s/m, N m s/rad): the viscous
        dampers beside the springs, same directions and split rule (a damper left out: 0)."""
        return np.array([getattr(self, f) or 0.0 for f in self.diagonal_fields("c")], float)

    def dampings(self) -> dict:
        """{field: value} of the damper fields given (not None, not 0)."""
        return {f: getattr(self, f) for f in DAMPING_FIELDS if getattr(self, f)}

    def diagonal(self) -> np.ndarray:
        """diag(k_x, k_y, k_axial, k_rx, k_ry, k_torsion) (N/m, N m/rad; ``inf`` = rigid)."""
        return np.array([getattr(self, f) for f in self.diagonal_fields()], float)

    def stiffnesses(self) -> dict:
        """{field: value} of the stiffness fields given (not None)."""
        return {f: getattr(self, f) for f in STIFFNESS_FIELDS if getattr(self, f) is not None}


@dataclass(frozen=True)
class Bearing(SixStiffnesses):
    """Diagonal 6x6 spring diag(k_radial_x, k_radial_y, k_axial, k_tilt_x, k_tilt_y, k_torsion)
    (:class:`SixStiffnesses`: ``k_radial`` / ``k_tilt`` stand for both directions).

    Acts on the motion of ``body`` relative to ``frame`` (default: the body's own reference
    frame) at ``position`` (default: the body's position, or the master node of
    ``interface`` for a body with a component), in the body's axes.
    Translational stiffness N/m, rotational N m/rad; ``inf`` constrains that direction.
    ``k_axial`` is required (:func:`assembly.scene.validate.check_bearing`), as are ``k_radial`` or
    both ``k_radial_x``/``k_radial_y``, and ``k_tilt`` or both ``k_tilt_x``/``k_tilt_y``.
    ``radial_angle`` (rad) turns the bearing's local x about the body's axis from the body's
    local x (:meth:`axes`): a planet's bearing takes its planet's angle on the carrier, so its
    x is radial and y tangential in every planet alike.
    """

    body: str
    k_radial: Optional[float] = stiffness("N/m", None)
    k_axial: Optional[float] = stiffness("N/m", None)
    k_tilt: Optional[float] = stiffness("N m/rad", None)
    k_torsion: float = stiffness("N m/rad", 0.0)
    frame: Optional[str] = None
    position: Optional[Vec3] = quantity("m", None)
    name: Optional[str] = name_field(None)
    interface: Optional[str] = None
    frame_interface: Optional[str] = None
    k_radial_x: Optional[float] = stiffness("N/m", None)
    k_radial_y: Optional[float] = stiffness("N/m", None)
    k_tilt_x: Optional[float] = stiffness("N m/rad", None)
    k_tilt_y: Optional[float] = stiffness("N m/rad", None)
    radial_angle: float = angle(0.0, abs_lt=4 * math.pi)
    c_radial: Optional[float] = damper("N s/m", None)
    c_axial: float = damper("N s/m")
    c_tilt: Optional[float] = damper("N m s/rad", None)
    c_torsion: float = damper("N m s/rad")
    c_radial_x: Optional[float] = damper("N s/m", None)
    c_radial_y: Optional[float] = damper("N s/m", None)
    c_tilt_x: Optional[float] = damper("N m s/rad", None)
    c_tilt_y: Optional[float] = damper("N m s/rad", None)

    def axes(self, body_axes: np.ndarray) -> np.ndarray:
        """The bearing's axes (columns local x, y, z): the body's turned by ``radial_angle``
        about its axis, so that ``k_radial_x`` / ``k_tilt_x`` act along / about the new x."""
        c, s = math.cos(self.radial_angle), math.sin(self.radial_angle)
        return np.asarray(body_axes, float) @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@dataclass(frozen=True)
class GearMesh:
    """Linear spring along the line of action between two parallel-axis gears.

    ``base_radius`` (m) is negative for an internal (ring) gear. ``pressure_angle`` is the
    transverse operating pressure angle (rad, > 0); ``helix_angle`` (rad) is the line of
    action's inclination to the transverse plane (the base helix angle), positive when gear 1
    is left-hand (from teeth: minus gear 1's signed base helix angle, see
    :func:`assembly.scene.gears.mesh_helix`). ``drive_sign`` (+1/-1) picks the loaded flank: the
    sense of rotation of gear 1 about its axis that closes the mesh with gear 2 held.
    The centre distance between the gear centres must equal (r1 + r2)/cos(pressure_angle).
    ``center1``/``center2`` default to the bodies' positions (the gear's mid-face centre).
    ``contact_point``: 'pitch' (default; one shared point, no strain under common rigid
    motion) or 'tangent' (each gear's base-circle tangent point, the convention of the
    published Kahraman/Peeters helical-pair table; see :func:`assembly.mechanics.elements.gear_mesh`).

    From teeth: when both gears carry teeth (``Body.teeth`` or their component's), leave
    out ``base_radius1/2``, ``pressure_angle`` and ``helix_angle``: they are derived (ISO
    21771, :mod:`assembly.scene.gears`): base radii ``z m_n cos(alpha_t) / (2 cos beta)``
    (negative for the gear whose body says ``internal``), the working transverse pressure
    angle from the profile shifts, and gear 1's helix angle. Numbers given as well must
    agree with the teeth (relative 1e-6), else the scene is refused naming both. A gear with
    teeth meshing a gear without: its base radius, if typed, must agree with its teeth.
    ``place`` ("gear1" or "gear2") puts that gear at the working centre distance from the
    other, along ``centre_line_angle`` (rad, in the other gear's axes from its local x;
    default 0) -- see :mod:`assembly.scene.placement`.

    ``stiffness`` (N/m) left out on a mesh between two gears with teeth: the ISO 6336-1
    (method B) mean mesh stiffness c_gamma_alpha b of solid gears, b the smaller face width
    (:mod:`fe_components.mesh_stiffness`); a typed number wins. Without teeth on both gears
    it must be given.

    ``damping`` (N s/m, default 0): a viscous damper beside the mesh spring, along the same
    line of action (:func:`assembly.mechanics.elements.gear_mesh`).

    Time-domain runs only (``flexgear simulate``; other analyses use the linear spring):
    ``backlash`` (m, normal backlash along the line of action): the teeth touch on the
    driving flank at compression delta > 0 and on the coast flank at delta < -backlash, and
    carry nothing in between (None: a linear spring in both senses); ``variation``: the
    stiffness as a function of the gear angle (:class:`assembly.scene.time_domain.MeshVariation`).
    """

    gear1: str
    gear2: str
    stiffness: Optional[float] = quantity("N/m", None, gt=0.0)
    base_radius1: Optional[float] = quantity("m", None, nonzero=True, hint="negative = internal gear",
                                             plausible=GEAR_RADIUS)
    base_radius2: Optional[float] = quantity("m", None, nonzero=True, hint="negative = internal gear",
                                             plausible=GEAR_RADIUS)
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
    damping: float = damper("N s/m")
    backlash: Optional[float] = quantity("m", None, ge=0.0)
    variation: Optional[MeshVariation] = None


@dataclass(frozen=True)
class Station:
    """A named point on a beam shaft, ``at`` metres from body1's attachment point along the
    shaft, strictly inside the shaft. It becomes the rigid body ``<shaft name>.<name>``
    (bearings, meshes and loads may name it like any body)."""

    name: str = name_field()
    at: float = quantity("m")


@dataclass(frozen=True)
class Shaft:
    """A shaft between two bodies: a diagonal spring typed by hand, or a Timoshenko beam
    of circular section.

    Spring (no ``diameter``): torsion (N m/rad), optional bending (N m/rad), axial and shear
    (N/m), acting on their relative motion at ``position`` (default: midway) in the axes of
    ``body1``.

    Beam (``diameter`` in m, optional ``bore_diameter`` in m and ``material``): the shaft
    runs from body1's attachment point (its position, ``position1`` (m, global) on a body
    without a component -- e.g. a gear's face where its shaft starts -- or ``interface1``'s
    master) to body2's (likewise ``position2``);
    its length is their distance and its axis their direction (parallel to body1's axis).
    The k_* fields and ``position`` are then derived and must be left out. ``stations``
    (:class:`Station`, e.g. the bearing seats) split it into Timoshenko elements
    (:mod:`assembly.mechanics.beam`) and become rigid bodies ``<name>.<station>`` of stage label
    ``stage`` (:mod:`assembly.scene.shafts`); the shaft's mass is lumped at its nodes.

    Damping: a spring shaft takes viscous dampers ``c_torsion``, ``c_bending`` (N m s/rad),
    ``c_axial`` and ``c_shear`` (N s/m) beside its springs (default 0); a beam shaft takes
    stiffness-proportional damping ``beta`` (s): each element's damping is
    ``C_e = beta K_e`` (a mode that strains only the shaft gets the ratio
    ``beta omega / 2``, omega in rad/s).
    """

    body1: str
    body2: str
    k_torsion: Optional[float] = quantity("N m/rad", None, gt=0.0)
    k_bending: float = quantity("N m/rad", 0.0, ge=0.0)
    k_axial: float = quantity("N/m", 0.0, ge=0.0)
    k_shear: float = quantity("N/m", 0.0, ge=0.0)
    position: Optional[Vec3] = quantity("m", None)
    name: Optional[str] = name_field(None)
    interface1: Optional[str] = None
    interface2: Optional[str] = None
    diameter: Optional[float] = quantity("m", None, gt=0.0, plausible=SHAFT_DIAMETER)
    bore_diameter: float = quantity("m", 0.0, ge=0.0, plausible=SHAFT_DIAMETER)
    material: Material = STEEL
    stations: tuple[Station, ...] = ()
    stage: Optional[str] = None
    position1: Optional[Vec3] = quantity("m", None)
    position2: Optional[Vec3] = quantity("m", None)
    c_torsion: float = damper("N m s/rad")
    c_bending: float = damper("N m s/rad")
    c_axial: float = damper("N s/m")
    c_shear: float = damper("N s/m")
    beta: float = quantity("s", 0.0, ge=0.0)

    #: The field behind each entry of :meth:`diagonal` (local x, y, z, rx, ry, rz).
    FIELDS = ("k_shear", "k_shear", "k_axial", "k_bending", "k_bending", "k_torsion")
    #: The damper behind each entry of :meth:`damping_diagonal`.
    DAMPING_FIELDS = ("c_shear", "c_shear", "c_axial", "c_bending", "c_bending", "c_torsion")

    @property
    def is_beam(self) -> bool:
        """A Timoshenko beam (``diameter`` given), not a hand-typed spring."""
        return self.diameter is not None

    def diagonal(self) -> np.ndarray:
        return np.array([getattr(self, f) for f in self.FIELDS], float)

    def damping_diagonal(self) -> np.ndarray:
        """The spring shaft's dampers (N s/m, N m s/rad), in :meth:`diagonal`'s order."""
        return np.array([getattr(self, f) for f in self.DAMPING_FIELDS], float)


@dataclass(frozen=True)
class Fixed:
    """DOFs of ``body`` (local names x, y, z, rx, ry, rz) held at zero relative to its frame."""

    body: str
    dofs: tuple[str, ...] = DOF_NAMES


@dataclass(frozen=True)
class BearingSpec(SixStiffnesses):
    """Stiffnesses of a member's bearing (N/m, N m/rad; ``inf`` = rigid direction), as
    :class:`Bearing`'s: ``k_radial`` or ``k_radial_x``/``k_radial_y``, ``k_tilt`` or
    ``k_tilt_x``/``k_tilt_y``, in the member's local axes."""

    k_radial: Optional[float] = stiffness("N/m", None)
    k_axial: Optional[float] = stiffness("N/m", None)
    k_tilt: Optional[float] = stiffness("N m/rad", None)
    k_torsion: float = stiffness("N m/rad", 0.0)
    k_radial_x: Optional[float] = stiffness("N/m", None)
    k_radial_y: Optional[float] = stiffness("N/m", None)
    k_tilt_x: Optional[float] = stiffness("N m/rad", None)
    k_tilt_y: Optional[float] = stiffness("N m/rad", None)
    c_radial: Optional[float] = damper("N s/m", None)
    c_axial: float = damper("N s/m")
    c_tilt: Optional[float] = damper("N m s/rad", None)
    c_torsion: float = damper("N m s/rad")
    c_radial_x: Optional[float] = damper("N s/m", None)
    c_radial_y: Optional[float] = damper("N s/m", None)
    c_tilt_x: Optional[float] = damper("N m s/rad", None)
    c_tilt_y: Optional[float] = damper("N m s/rad", None)


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
    ``normal_module`` (see :class:`PlanetaryStage`), and with them ``mass`` and
    ``polar_inertia`` may be left out (the gear blank, ``blank``). ``fidelity`` left out: the
    scene's."""

    mass: Optional[float] = quantity("kg", None, gt=0.0)
    polar_inertia: Optional[float] = quantity("kg m^2", None, gt=0.0)
    transverse_inertia: Optional[float] = quantity("kg m^2", None, gt=0.0)
    base_radius: Optional[float] = quantity("m", None, gt=0.0, hint="give the ring's as positive",
                                            plausible=GEAR_RADIUS)
    support: MemberSupport = "bearing"
    bearing: Optional[BearingSpec] = None
    fidelity: Optional[Fidelity] = None
    component: Optional[ComponentParams] = None
    flex: Optional[FlexOptions] = None
    bearing_interface: str = "bearing_b"
    teeth: Optional[int] = quantity("", None, integer=True, ge=3)
    profile_shift: float = quantity("", 0.0, gt=-1.0, lt=1.0)
    blank: Optional[GearBlank] = None


@dataclass(frozen=True)
class Planets:
    """N identical planets at ``angles`` (rad; default equally spaced from 0).
    ``outer_radius`` (m, default the pitch radius) is used for the overlap check.
    ``teeth`` and ``profile_shift`` (ISO 21771) replace ``base_radius`` when the stage gives
    ``normal_module``; ``mass`` and ``polar_inertia`` left out then come from the planets'
    gear blank (``blank``; see :class:`PlanetaryStage`). ``fidelity`` left out: the scene's.
    With teeth the planets must also mesh with sun and ring at their angles (assembly
    condition, :mod:`assembly.scene.planet_spacing`)."""

    count: int = quantity("", integer=True, ge=1, le=MAX_PLANETS)
    mass: Optional[float] = quantity("kg", None, gt=0.0)
    polar_inertia: Optional[float] = quantity("kg m^2", None, gt=0.0)
    bearing: BearingSpec = field(kw_only=True)
    base_radius: Optional[float] = quantity("m", None, gt=0.0, plausible=GEAR_RADIUS)
    transverse_inertia: Optional[float] = quantity("kg m^2", None, gt=0.0)
    angles: Optional[tuple[float, ...]] = angle(None)
    outer_radius: Optional[float] = quantity("m", None, gt=0.0, plausible=GEAR_RADIUS)
    fidelity: Optional[Fidelity] = None
    teeth: Optional[int] = quantity("", None, integer=True, ge=3)
    profile_shift: float = quantity("", 0.0, gt=-1.0, lt=1.0)
    blank: Optional[GearBlank] = None


@dataclass(frozen=True)
class PlanetaryStage:
    """A planetary stage. Mesh stiffness N/m; pressure angles transverse, rad.

    From teeth: ``normal_module`` (m), ``normal_pressure_angle`` (rad, or ``_deg``) and
    ``helix_angle`` (the sun's, rad) with ``teeth`` and ``profile_shift`` on ``sun``,
    ``planets`` and ``ring`` derive the base radii, both working pressure angles and the
    carrier radius (:func:`assembly.scene.gears.stage_from_teeth`, ISO 21771): the carrier
    radius is the sun-planet working centre distance; the planet-ring one must agree to
    :data:`assembly.scene.gears.RING_CENTRE_TOLERANCE` normal modules, and the ring mesh works
    at the carrier radius (``cos(alpha_ring) = (r_b,ring - r_b,planet) / R_c``). Typed base
    radii and pressure angles given as well must agree (relative 1e-6).

    ``helix_angle`` is therefore read two ways (:meth:`mesh_helix_angle`): without
    ``normal_module`` it is the sun-planet meshes' line-of-action helix, as
    ``[[meshes]].helix_angle``; with it, the sun teeth's reference helix angle (> 0 right
    hand, as ``GearTeeth.helix_angle``), and the meshes take the signed base helix angle.

    ``k_mesh_sun`` / ``k_mesh_ring`` (N/m) left out on a stage with ``normal_module``: the ISO
    6336-1 (method B) mean mesh stiffness c_gamma_alpha b of the sun-planet / planet-ring pair
    (solid gears, standard basic rack), b = ``face_width`` (m, then required); a typed number
    wins. Without ``normal_module`` both must be given.

    With ``normal_module``, sun, planets and ring may leave out ``mass`` and
    ``polar_inertia``: they come from their gear blanks (as a :class:`Body` with teeth; the
    ring's internal), of length ``face_width`` (m) unless their ``blank`` table says otherwise.

    ``c_mesh_sun`` / ``c_mesh_ring`` (N s/m, default 0): viscous dampers along the line of
    action of every sun-planet / planet-ring mesh (:attr:`GearMesh.damping`).

    Where: ``center`` (m, default the origin) and ``axis``; or ``coaxial_with``, the name of a
    body (one of the scene's bodies, or a member of a stage written before this one) whose
    axis the stage shares exactly: its centre is that body's position moved ``axial_offset``
    (m, default 0) along the body's axis, and its ``axis`` (parallel to the body's, either
    sense) becomes the body's (:func:`assembly.scene.placement.place_stages`). A stage joined to a
    body by a shaft must sit on that body's axis to the last bit: a typed centre a hair off
    it is a lever arm that the torsional model cannot turn.

    Time-domain runs: ``backlash`` (m) of every mesh of the stage, and ``variation_sun`` /
    ``variation_ring`` (:class:`assembly.scene.time_domain.MeshVariation`) of its sun-planet and
    planet-ring meshes, counted on the sun's and the ring's teeth relative to the carrier;
    each planet's meshes are phased by its angle psi_n (``phase`` + z psi_n), and with teeth
    the contact ratios default to the pairs' own.
    """

    name: str = name_field()
    sun: Member = field()
    ring: Member = field()
    carrier: Member = field()
    planets: Planets = field()
    k_mesh_sun: Optional[float] = quantity("N/m", None, gt=0.0)
    k_mesh_ring: Optional[float] = quantity("N/m", None, gt=0.0)
    pressure_angle_sun: Optional[float] = angle(None, gt=0.0, lt=_HALF_PI)
    pressure_angle_ring: Optional[float] = angle(None, gt=0.0, lt=_HALF_PI)
    helix_angle: float = angle(0.0, abs_lt=_HALF_PI)
    normal_module: Optional[float] = quantity("m", None, gt=0.0, plausible=MODULE)
    normal_pressure_angle: Optional[float] = angle(None, gt=0.0, lt=math.radians(45))
    face_width: Optional[float] = quantity("m", None, gt=0.0, plausible=FACE_WIDTH)
    drive_sign: int = 1
    center: Optional[Vec3] = quantity("m", None)
    axis: Vec3 = quantity("", (0.0, 0.0, 1.0))
    contact_point: Literal["pitch", "tangent"] = "pitch"
    c_mesh_sun: float = damper("N s/m")
    c_mesh_ring: float = damper("N s/m")
    backlash: Optional[float] = quantity("m", None, ge=0.0)
    variation_sun: Optional[MeshVariation] = None
    variation_ring: Optional[MeshVariation] = None
    coaxial_with: Optional[str] = None
    axial_offset: Optional[float] = quantity("m", None)

    def carrier_radius(self) -> float:
        """Planet-centre radius (m) from the sun-planet mesh geometry."""
        return (self.sun.base_radius + self.planets.base_radius) / math.cos(self.pressure_angle_sun)

    def mesh_helix_angle(self) -> float:
        """Line-of-action helix (rad) of the sun-planet meshes (the planet-ring meshes take
        its negative): ``helix_angle`` as typed, or from the sun's teeth minus their base
        helix angle (:func:`assembly.scene.gears.mesh_helix`)."""
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
class PointLoad:
    """A force (N) and a moment (N m) applied to ``body`` in a static load case.

    Where: at the master node of ``interface`` on a component body (required there), or at
    ``point`` (m, global) on a plain body -- default its position (its axis point). A force
    away from a rigid body's reference point acts on it through the rigid lever arm; on a
    flexible body the master node carries it. ``axes``: "global" (default) or "body" (the
    body's local axes, z = its axis) for both ``force`` and ``moment``."""

    body: str
    force: Vec3 = quantity("N", (0.0, 0.0, 0.0))
    moment: Vec3 = quantity("N m", (0.0, 0.0, 0.0))
    point: Optional[Vec3] = quantity("m", None)
    interface: Optional[str] = None
    axes: Literal["global", "body"] = "global"


@dataclass(frozen=True)
class Support:
    """DOFs of ``body`` held at zero relative to the housing for one load case only:
    ``dofs`` (subset of x, y, z, rx, ry, rz; default all six) in the body's local axes at
    the master node of ``interface`` (a component body: required) or at a plain body's
    position (its axis point)."""

    body: str
    interface: Optional[str] = None
    dofs: tuple[str, ...] = DOF_NAMES


@dataclass(frozen=True)
class LoadCase:
    """Static load case. A torque case: ``torque`` (N m) about ``input``'s axis, reacted by
    holding ``output`` against rotation about its own axis (relative to the housing);
    ``input_interface`` / ``output_interface`` name where the torque enters / where the
    output is held on a component body (e.g. its coupling seat): the interface's master
    node. Give all three of ``input``, ``output``, ``torque`` or none. Besides (or
    instead): ``forces``, point loads (:class:`PointLoad`), and ``supports``, DOFs held for
    this case only (:class:`Support`). A scene gives one ``[load]`` or a list ``[[loads]]``
    (not both; names unique); see docs/static.md."""

    input: Optional[str] = None
    output: Optional[str] = None
    torque: Optional[float] = quantity("N m", None, nonzero=True)
    input_interface: Optional[str] = None
    output_interface: Optional[str] = None
    name: str = name_field("rated torque")
    forces: tuple[PointLoad, ...] = ()
    supports: tuple[Support, ...] = ()

    def __post_init__(self):
        for f in ("forces", "supports"):
            if isinstance(getattr(self, f), list):  # Python callers may pass lists
                object.__setattr__(self, f, tuple(getattr(self, f)))

    @property
    def has_torque(self) -> bool:
        """Whether this is a torque case (input, output and torque given)."""
        return self.torque is not None


#: Mode classes a ``[damping] class_ratios`` key may name (:mod:`assembly.analysis.classify`).
MODE_CLASSES = ("rotational", "translational", "planet", "out-of-plane", "mixed", "elastic")


@dataclass(frozen=True)
class Damping:
    """Scene-level damping (``[damping]``), on top of the element dampers (``c_*``).

    ``modal_ratio``: one damping ratio zeta for every elastic mode; ``class_ratios``
    ({mode class: zeta}, classes of :mod:`assembly.analysis.classify`, e.g. ``rotational = 0.05``)
    overrides it for the modes of those classes. Ratios lie in [0, 1). Rigid-body (0 Hz)
    modes stay undamped. ``rayleigh_alpha`` (1/s) and ``rayleigh_beta`` (s): Rayleigh
    damping ``C = alpha M + beta K``, a mode of omega (rad/s) then having
    ``zeta = alpha / (2 omega) + beta omega / 2``; the ``alpha M`` part is taken with the
    rigid-body modes projected out (``alpha (M - M Phi_r Phi_r' M)``), so that it damps
    every elastic mode as the formula says and brakes no free rotation (see
    :mod:`assembly.dynamics.damping`)."""

    modal_ratio: Optional[float] = quantity("", None, ge=0.0, lt=1.0)
    class_ratios: Optional[dict] = None
    rayleigh_alpha: float = quantity("1/s", 0.0, ge=0.0)
    rayleigh_beta: float = quantity("s", 0.0, ge=0.0)

    @property
    def modal(self) -> bool:
        """Whether modal ratios are given (``modal_ratio`` or ``class_ratios``)."""
        return self.modal_ratio is not None or bool(self.class_ratios)

    @property
    def rayleigh(self) -> bool:
        """Whether Rayleigh damping is given (alpha or beta > 0)."""
        return self.rayleigh_alpha > 0 or self.rayleigh_beta > 0


#: True while :func:`derive` builds a scene from an already validated one.
_TRUSTED = contextvars.ContextVar("flexgear_trusted_scene", default=False)


@dataclass(frozen=True)
class Scene:
    """A drivetrain: bodies and the springs that join them (SI units throughout).

    ``stages`` holds planetary-stage descriptions; :meth:`expanded` turns each into bodies,
    bearings and meshes. ``band_hz``: the frequency band of interest (Hz), which sets the
    Craig-Bampton cutoff of flexible bodies. ``fidelity``: the default fidelity of every
    body, stage member and planets table that does not give its own (default "rigid").
    ``damping``: scene-level damping (:class:`Damping`); element dampers are the ``c_*``
    fields of bearings, meshes, shafts and stages. ``simulation``: the settings of time-domain
    runs (:class:`assembly.scene.time_domain.Simulation`); ``turbine``: the turbine around the
    drivetrain (:class:`assembly.scene.turbine.Turbine`).
    Construction first derives the gear numbers from teeth and places the bodies meshes
    place (:func:`assembly.scene.gears.resolve`), then validates everything (``SceneError``
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
    damping: Optional[Damping] = None
    simulation: Optional[Simulation] = None
    turbine: Optional[Turbine] = None

    def __post_init__(self):
        for f in ("bodies", "bearings", "meshes", "shafts", "fixed", "stages", "loads"):
            if isinstance(getattr(self, f), list):  # Python callers may pass lists
                object.__setattr__(self, f, tuple(getattr(self, f)))
        if not _TRUSTED.get():
            # these read the types defined here: import when used
            from .gears import resolve
            from .schema import checked_fields
            from .validate import references_exist, validate_scene
            # types and ranges before anything derives from them; a component given as a
            # table (dict) becomes its parameter object here, once
            for key, value in checked_fields(self).items():
                object.__setattr__(self, key, value)
            # every body a field names exists before deriving reads the bodies it names
            references_exist(self)
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
        """The same scene with every planetary stage expanded into plain elements and the
        stations of every beam shaft added as bodies (:attr:`expansion`; a scene already
        expanded is its own expansion)."""
        return self.expansion

    @functools.cached_property
    def expansion(self) -> "Scene":
        """:meth:`expanded`, computed once per scene (memoised on the instance)."""
        # the builders read these types
        from .planetary import expand_stages
        from .shafts import expand_shafts, shafts_expanded
        if not self.stages and shafts_expanded(self):
            return self
        out = derive(self, **expand_stages(self), stages=()) if self.stages else self
        if not shafts_expanded(out):
            out = derive(out, bodies=out.bodies + expand_shafts(out))
        return out

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
        """The value at a scene path such as ``"bearings[2].k_radial"`` (:func:`assembly.scene.edit.get_value`)."""
        from .edit import get_value
        return get_value(self, path)

    def with_value(self, path: str, value) -> "Scene":
        """New validated scene with the field at ``path`` (e.g. ``"shafts.quill.k_torsion"``,
        ``"meshes[0].helix_angle_deg"``) set to ``value`` (:func:`assembly.scene.edit.with_value`)."""
        from .edit import with_value
        return with_value(self, path, value)

    def with_values(self, changes: dict) -> "Scene":
        """New scene with every ``{path: value}`` set, validated once (:func:`assembly.scene.edit.with_values`)."""
        from .edit import with_values
        return with_values(self, changes)

    @property
    def display_limit_hz(self) -> float:
        """Highest frequency (Hz) shown by default: DISPLAY_BAND_FACTOR x the band."""
        return DISPLAY_BAND_FACTOR * self.band

    def body(self, name: str) -> Body:
        """The body called ``name`` (stages expanded); SceneError naming ``name`` if none is."""
        bodies = self.expanded().bodies
        for b in bodies:
            if b.name == name:
                return b
        raise arguments.unknown("name", name, [b.name for b in bodies])


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
    wrote; only a choice that splits the planets of one stage expands the scene. The bodies
    a beam shaft's stations make follow the scene's default fidelity (never flexible): all
    bodies chosen, that default becomes ``fidelity`` too."""
    allowed = get_args(Fidelity)
    scene_argument("scene", scene)
    if not isinstance(fidelity, str) or fidelity not in allowed:
        raise SceneError("fidelity", arguments.shown(fidelity), f"must be one of {list(allowed)}"
                         + arguments.nearest(fidelity, allowed))
    sc = scene.expanded()
    have = [b.name for b in sc.bodies]
    chosen = set(have) if bodies is None else set(arguments.names("bodies", bodies, empty=True))
    unknown = sorted(chosen - set(have), key=str)
    if unknown:
        raise arguments.unknown("bodies", unknown[0], have)

    def pick(items):
        return tuple(dataclasses.replace(b, fidelity=fidelity) if b.name in chosen else b for b in items)

    # a shaft's stations are made again by the new scene, at its default fidelity (never flexible)
    stations = {f"{s.name}.{st.name}" for s in scene.shafts for st in s.stations}
    default = {"fidelity": fidelity} if bodies is None and stations else {}
    stages = []
    # the tables as the user wrote them: numbers derived from teeth are derived again
    for st in scene.as_given("stages"):
        planets = {b.name for b in sc.bodies[len(scene.bodies):] if b.stage == st.name and b.role == "planet"}
        if chosen & planets not in (set(), planets):  # some planets of a stage, not all
            return dataclasses.replace(sc, bodies=pick(b for b in sc.bodies if b.name not in stations), **default)
        changes = {role: dataclasses.replace(getattr(st, role), fidelity=fidelity)
                   for role in ("sun", "ring", "carrier") if f"{st.name}.{role}" in chosen}
        if planets and planets <= chosen:
            changes["planets"] = dataclasses.replace(st.planets, fidelity=fidelity)
        stages.append(dataclasses.replace(st, **changes))
    return dataclasses.replace(scene, bodies=pick(scene.as_given("bodies")), meshes=scene.as_given("meshes"),
                               stages=tuple(stages), **default)


def with_simulation(scene: Scene, simulation) -> Scene:
    """Copy of ``scene`` with ``simulation`` (a :class:`Simulation` table, or None) as its
    ``[simulation]`` table, checked against the scene as a new scene is (the other tables as
    the user gave them)."""
    return with_tables(scene, simulation=simulation)


def with_tables(scene: Scene, **tables) -> Scene:
    """Copy of ``scene`` with the top-level ``tables`` given (e.g. ``turbine=...``), checked
    against the scene as a new scene is (the other tables as the user gave them)."""
    scene_argument("scene", scene)
    given = {key: scene.as_given(key) for key in scene.__dict__.get("_given", {}) if key not in tables}
    return dataclasses.replace(scene, **tables, **given)


def scale_bearings(scene: Scene, factor: float, directions=("k_radial", "k_axial", "k_tilt")) -> Scene:
    """Copy of ``scene`` with the named bearing stiffnesses times ``factor`` (finite, > 0):
    its own bearings and the bearing tables of its planetary stages (kept as stages).
    ``k_radial`` (``k_tilt``) scales ``k_radial_x``/``k_radial_y`` too where those are given."""
    scene_argument("scene", scene)
    factor = arguments.number("factor", factor, gt=0.0)
    directions = arguments.names("directions", directions)
    for d in directions:
        if d not in STIFFNESS_FIELDS:
            raise arguments.unknown("directions", d, STIFFNESS_FIELDS, "bearing stiffness")
    named = {f for d in directions for f in (d, *SPLIT_STIFFNESSES.get(d, ()))}

    def scaled(b):
        if b is None:
            return None
        return dataclasses.replace(b, **{f: k * factor for f, k in b.stiffnesses().items() if f in named})

    stages = tuple(dataclasses.replace(
        st, planets=dataclasses.replace(st.planets, bearing=scaled(st.planets.bearing)),
        **{role: dataclasses.replace(getattr(st, role), bearing=scaled(getattr(st, role).bearing))
           for role in ("sun", "ring", "carrier")}) for st in scene.as_given("stages"))
    return dataclasses.replace(scene, bearings=tuple(scaled(b) for b in scene.bearings), stages=stages,
                               bodies=scene.as_given("bodies"), meshes=scene.as_given("meshes"))


def scene_argument(name: str, value) -> Scene:
    """``value``, a :class:`Scene` (SceneError naming the argument ``name`` otherwise)."""
    return arguments.instance(name, value, Scene, "a Scene (load_scene(path) reads one from a file)")
