"""Parameter objects of the flexible components (SI units: m, rad).

Every dataclass validates itself in ``__post_init__`` and raises
:class:`~fe_components.errors.GeometryError` naming the parameter (dotted path
relative to the object) and the offending value, *before* any meshing: first every
number against the unit and range declared on its field (:mod:`fe_components.fields`:
a real number, finite, of physical magnitude, in range -- so no NaN or inf ever reaches
a comparison or gmsh), then the relations between fields (a gear face between the
bearing seats, a web inside the face width, non-overlapping bores).
Angle fields are declared with ``angle=True``, so a table reader (the scene schema)
may accept them in degrees under ``<name>_deg``.

Axis conventions (all components rotate about the global z axis through the
origin):

* pinion: shaft from z = 0 to z = sum(segment lengths); gear mid-face at
  ``gear_center``;
* wheel: gear mid-face at z = 0 (web and hub placed relative to it);
* carrier: mid-plane between the cheeks at z = 0, planet pins parallel to z.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from dataclasses import dataclass
from typing import Any

from .errors import GeometryError
from .fields import check_fields, quantity
from .gear_pair import base_radius, transverse_pressure_angle
from .involute import check_tooth_shape
from .part.file import PartFile
from .sizes import (
    FACE_PER_MODULE,
    FACE_WIDTH,
    GEAR_RADIUS,
    MODULE,
    SHAFT_DIAMETER,
    SHAFT_LENGTH,
    SLENDERNESS,
    unit_hint,
)

FIDELITIES = ("smooth", "involute")
#: Most planets a carrier may hold: more than any built stage (3 to 12) by far, and it
#: bounds the pairwise bore and post overlap checks (n^2) before anything is meshed.
MAX_PLANETS = 64

_LENGTH = {"unit": "m", "gt": 0.0}     # a length that must be > 0
_CLEARANCE = {"unit": "m", "ge": 0.0}  # a length that may be 0 (no bore, no hole)


# ---------------------------------------------------------------- teeth
def check_face_per_module(face_width: float, normal_module: float, face: str = "face_width",
                          module: str = "normal_module", error=GeometryError) -> None:
    """``face_width / normal_module`` within :data:`fe_components.sizes.FACE_PER_MODULE`:
    outside, one of them was typed in the wrong unit. ``error(face, value, reason)``
    names the face width (the message names the module too, ``module``: its path)."""
    r = face_width / normal_module
    lo, hi = FACE_PER_MODULE
    if lo <= r <= hi:
        return
    f = 1e-3 if r > hi else 1e3     # what brings the ratio back: the face width times f, or the module / f
    fixes = [f"{name} = {v:.6g} m" for name, v, rule in ((face, face_width * f, FACE_WIDTH),
                                                         (module, normal_module / f, MODULE))
             if rule.problem(v) is None and lo <= r * f <= hi]
    raise error(face, face_width,
                f"{r:.4g} x {module} = {normal_module:g} m: a gear's face is {lo:g} to {hi:g} modules wide "
                f"(ISO 6336-1 practice 6 to 60, watch wheels from 1, marine gears to 150): one of them is in "
                f"the wrong unit" + (f"; did you mean {' or '.join(fixes)}?" if fixes else ""))


@dataclass(frozen=True)
class GearTeeth:
    """Gear tooth data (ISO 21771 nomenclature, standard basic rack h_a* = 1, h_f* = 1.25).

    n_teeth : number of teeth z.
    normal_module : m_n [m].
    pressure_angle : normal pressure angle alpha_n [rad].
    face_width : b [m].
    helix_angle : beta [rad] (0 = spur; > 0 right-hand helix about +z, < 0 left-hand).
    fidelity : "smooth" (solid annulus of radius ``smooth_radius``) or "involute".
    smooth_radius : outer radius of the smooth annulus [m]; default pitch radius.
    profile_shift : profile shift coefficient x [-].
    """

    n_teeth: int = quantity(integer=True, ge=3)
    normal_module: float = quantity(**_LENGTH, plausible=MODULE)
    pressure_angle: float = quantity("rad", angle=True, gt=0.0, lt=math.radians(45))
    face_width: float = quantity(**_LENGTH, plausible=FACE_WIDTH)
    helix_angle: float = quantity("rad", 0.0, angle=True, abs_lt=math.radians(60))
    fidelity: str = "smooth"
    smooth_radius: float | None = quantity("m", None, gt=0.0, plausible=GEAR_RADIUS)
    profile_shift: float = quantity("", 0.0, gt=-1.0, lt=1.0)

    def __post_init__(self) -> None:
        check_fields(self)
        if self.fidelity not in FIDELITIES:
            raise GeometryError("fidelity", self.fidelity, f"must be one of {FIDELITIES}")
        check_face_per_module(self.face_width, self.normal_module)
        # Undercut limit of a gear cut by the standard rack (h_a* = 1), ISO 21771 / Niemann:
        # z_min = 2 (1 - x) cos(beta) / sin^2(alpha_t); the practical limit is its integer part
        # (17 teeth for alpha_n = 20 deg, beta = 0, x = 0).
        z_min = 2.0 * (1.0 - self.profile_shift) * math.cos(self.helix_angle) / math.sin(self.transverse_pressure_angle) ** 2
        if self.n_teeth < math.floor(z_min):
            raise GeometryError(
                "n_teeth", self.n_teeth,
                f"undercuts at pressure angle {math.degrees(self.pressure_angle):.3g} deg "
                f"(helix {math.degrees(self.helix_angle):.3g} deg, x = {self.profile_shift}): "
                f"needs at least {math.floor(z_min)} teeth or a larger profile shift")
        if self.root_radius <= 0:
            raise GeometryError("n_teeth", self.n_teeth, "root circle radius is not positive")
        if self.smooth_radius is not None:
            if self.smooth_radius > self.tip_radius * (1 + 1e-12):
                raise GeometryError("smooth_radius", self.smooth_radius,
                                    f"exceeds the tip radius {self.tip_radius:.6g} m")
        if self.fidelity == "involute":
            check_tooth_shape(self)

    # derived geometry (m, rad)
    @property
    def transverse_module(self) -> float:
        return self.normal_module / math.cos(self.helix_angle)

    @property
    def transverse_pressure_angle(self) -> float:
        return transverse_pressure_angle(self.pressure_angle, self.helix_angle)

    @property
    def pitch_radius(self) -> float:
        return 0.5 * self.n_teeth * self.transverse_module

    @property
    def base_radius(self) -> float:
        return base_radius(self.n_teeth, self.normal_module, self.pressure_angle, self.helix_angle)

    @property
    def tip_radius(self) -> float:
        return self.pitch_radius + self.normal_module * (1.0 + self.profile_shift)

    @property
    def root_radius(self) -> float:
        return self.pitch_radius - self.normal_module * (1.25 - self.profile_shift)

    @property
    def outer_radius(self) -> float:
        """Outer radius of the modelled gear body [m] (tip, or the smooth radius)."""
        if self.fidelity == "smooth":
            return self.smooth_radius if self.smooth_radius is not None else self.pitch_radius
        return self.tip_radius

    @property
    def inner_limit_radius(self) -> float:
        """Radius below which the gear body is solid (root circle, or smooth radius if smaller)."""
        return min(self.root_radius, self.outer_radius)



# ---------------------------------------------------------------- pinion
@dataclass(frozen=True)
class ShaftSegment:
    """One cylindrical shaft step: ``length`` and ``diameter`` [m]."""

    length: float = quantity(**_LENGTH, plausible=SHAFT_LENGTH)
    diameter: float = quantity(**_LENGTH, plausible=SHAFT_DIAMETER)

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class PinionParams:
    """Pinion integral with a stepped shaft along +z from z = 0.

    shaft : segments in order from z = 0; the first and last segments are the
        bearing seats "bearing_a" and "bearing_b".
    gear_center : z of the gear's mid-face [m].
    bore_diameter : optional central bore through the whole shaft [m] (0 = solid).
    """

    teeth: GearTeeth
    shaft: tuple[ShaftSegment, ...]
    gear_center: float = quantity("m")
    bore_diameter: float = quantity(**_CLEARANCE, default=0.0)

    def __post_init__(self) -> None:
        if not isinstance(self.teeth, GearTeeth):
            raise GeometryError("teeth", self.teeth, "must be a GearTeeth")
        if not isinstance(self.shaft, (list, tuple)) or not all(isinstance(s, ShaftSegment) for s in self.shaft):
            raise GeometryError("shaft", self.shaft, "must be an array of ShaftSegment")
        object.__setattr__(self, "shaft", tuple(self.shaft))
        if len(self.shaft) < 2:
            raise GeometryError("shaft", len(self.shaft), "needs at least two segments (two bearing seats)")
        check_fields(self)
        length = self.length
        b = self.teeth.face_width
        z0, z1 = self.gear_center - b / 2, self.gear_center + b / 2
        if z0 < self.shaft[0].length or z1 > length - self.shaft[-1].length:
            raise GeometryError("gear_center", self.gear_center,
                                f"gear face [{z0:.6g}, {z1:.6g}] m must lie between the bearing seats "
                                f"[{self.shaft[0].length:.6g}, {length - self.shaft[-1].length:.6g}] m")
        if self.bore_diameter / 2 >= self.teeth.inner_limit_radius:
            raise GeometryError("bore_diameter", self.bore_diameter,
                                f"bore radius at or beyond the root circle radius {self.teeth.inner_limit_radius:.6g} m")
        for i, seg in enumerate(self.shaft):
            if seg.length > SLENDERNESS * seg.diameter:
                raise GeometryError(f"shaft[{i}].length", seg.length,
                                    f"{seg.length / seg.diameter:.4g} diameters long: a shaft step is at most "
                                    f"{SLENDERNESS:g}; a length in the wrong unit"
                                    f"{unit_hint(seg.length, 0.0, SLENDERNESS * seg.diameter)}")
            if self.bore_diameter >= seg.diameter:
                raise GeometryError(f"shaft[{i}].diameter", seg.diameter,
                                    f"not larger than the bore diameter {self.bore_diameter} m")

    @property
    def length(self) -> float:
        return sum(s.length for s in self.shaft)



# ---------------------------------------------------------------- wheel
@dataclass(frozen=True)
class WheelParams:
    """Gear wheel: toothed rim + web (+ optional lightening holes) + hub with bore.

    The gear mid-face is at z = 0; the web mid-plane at ``web_offset`` and the
    hub centred at ``hub_offset`` (both axial, [m]).  Lightening holes are
    ``n_holes`` axial through-holes of ``hole_diameter`` on the circle of
    diameter ``hole_pitch_diameter`` (default: midway between hub and rim).
    """

    teeth: GearTeeth
    rim_inner_diameter: float = quantity(**_LENGTH)
    web_thickness: float = quantity(**_LENGTH)
    hub_outer_diameter: float = quantity(**_LENGTH)
    hub_length: float = quantity(**_LENGTH)
    bore_diameter: float = quantity(**_LENGTH)
    web_offset: float = quantity("m", 0.0)
    hub_offset: float = quantity("m", 0.0)
    n_holes: int = quantity("", 0, integer=True, ge=0)
    hole_diameter: float = quantity(**_CLEARANCE, default=0.0)
    hole_pitch_diameter: float | None = quantity("m", None, gt=0.0)

    def __post_init__(self) -> None:
        if not isinstance(self.teeth, GearTeeth):
            raise GeometryError("teeth", self.teeth, "must be a GearTeeth")
        check_fields(self)
        t = self.teeth
        if self.bore_diameter / 2 >= t.inner_limit_radius:
            raise GeometryError("bore_diameter", self.bore_diameter,
                                f"bore radius at or beyond the root circle radius {t.inner_limit_radius:.6g} m")
        if self.rim_inner_diameter / 2 >= t.inner_limit_radius:
            raise GeometryError("rim_inner_diameter", self.rim_inner_diameter,
                                f"rim inner radius at or beyond the root circle radius {t.inner_limit_radius:.6g} m")
        if self.hub_outer_diameter >= self.rim_inner_diameter:
            raise GeometryError("hub_outer_diameter", self.hub_outer_diameter,
                                f"must be smaller than rim_inner_diameter {self.rim_inner_diameter} m")
        if self.bore_diameter >= self.hub_outer_diameter:
            raise GeometryError("bore_diameter", self.bore_diameter,
                                f"must be smaller than hub_outer_diameter {self.hub_outer_diameter} m")
        self._check_web_and_hub()
        if self.n_holes:
            self._check_holes()

    def _check_web_and_hub(self) -> None:
        """The web lies inside the face width, the hub spans the web (offsets may be either
        sign: a web or hub shifted towards -z). Blames the thickness or length when it
        cannot fit at any offset, else the offset."""
        b = self.teeth.face_width
        if self.web_thickness > b * (1 + 1e-12):
            raise GeometryError("web_thickness", self.web_thickness, f"thicker than the face width {b} m")
        if abs(self.web_offset) + self.web_thickness / 2 > b / 2 * (1 + 1e-12):
            raise GeometryError("web_offset", self.web_offset,
                                f"a web of {self.web_thickness} m at this offset leaves the face width "
                                f"[{-b / 2:.6g}, {b / 2:.6g}] m")
        if self.hub_length < self.web_thickness * (1 - 1e-12):
            raise GeometryError("hub_length", self.hub_length,
                                f"hub must span the web thickness {self.web_thickness} m")
        if abs(self.hub_offset - self.web_offset) + self.web_thickness / 2 > self.hub_length / 2 * (1 + 1e-12):
            raise GeometryError("hub_offset", self.hub_offset,
                                f"a hub of {self.hub_length} m at this offset does not span the web "
                                f"(offset {self.web_offset} m, thickness {self.web_thickness} m)")

    def _check_holes(self) -> None:
        """Lightening holes fit between hub and rim and do not overlap."""
        if self.hole_diameter <= 0:
            raise GeometryError("hole_diameter", self.hole_diameter, "must be > 0 m when n_holes > 0")
        rh = self.hole_pitch_radius
        if rh - self.hole_diameter / 2 <= self.hub_outer_diameter / 2 or rh + self.hole_diameter / 2 >= self.rim_inner_diameter / 2:
            blame = "hole_pitch_diameter" if self.hole_pitch_diameter is not None and \
                self.hole_diameter < (self.rim_inner_diameter - self.hub_outer_diameter) / 2 else "hole_diameter"
            raise GeometryError(blame, getattr(self, blame),
                                f"holes of {self.hole_diameter} m on pitch radius {rh:.6g} m do not fit between "
                                f"hub and rim")
        if self.n_holes > 1 and 2 * rh * math.sin(math.pi / self.n_holes) <= self.hole_diameter:
            raise GeometryError("hole_diameter", self.hole_diameter,
                                f"{self.n_holes} holes on pitch radius {rh:.6g} m overlap")

    @property
    def hole_pitch_radius(self) -> float:
        if self.hole_pitch_diameter is not None:
            return self.hole_pitch_diameter / 2
        return (self.hub_outer_diameter + self.rim_inner_diameter) / 4



# ---------------------------------------------------------------- carrier
@dataclass(frozen=True)
class CarrierParams:
    """Planet carrier: two cheeks joined by posts, planet-pin bores, central hub.

    Cheek A occupies z in [-s/2 - t, -s/2], cheek B z in [s/2, s/2 + t]
    (s = ``cheek_spacing``, t = ``cheek_thickness``).  Hub A (bearing seat A,
    diameter ``seat_a_diameter``, length ``seat_a_length``) extends from
    cheek A towards -z; hub B (bearing seat B) from cheek B towards +z and
    holds the output bore (diameter ``output_bore_diameter``, depth = hub B
    length).  Posts (cylinders of ``post_diameter``) join the cheeks midway
    (in angle) between consecutive planets at radius ``post_radius``
    (default: pin pitch radius).  ``center_hole_diameter`` > 0 adds a central
    through-hole (e.g. for the sun shaft).  Angles in rad.

    ``planet_angles`` (rad) and ``pin_pitch_radius`` (m) place the planet pins; None means
    "set by the planetary stage" (the stage builder sets both with ``dataclasses.replace``).
    The checks that need them run when they are set; geometry, meshing and interfaces
    need them (:meth:`require_pins`).
    """

    pin_bore_diameter: float = quantity(**_LENGTH)
    cheek_diameter: float = quantity(**_LENGTH)
    cheek_thickness: float = quantity(**_LENGTH)
    cheek_spacing: float = quantity(**_LENGTH)
    post_diameter: float = quantity(**_LENGTH)
    seat_a_diameter: float = quantity(**_LENGTH)
    seat_a_length: float = quantity(**_LENGTH)
    seat_b_diameter: float = quantity(**_LENGTH)
    seat_b_length: float = quantity(**_LENGTH)
    output_bore_diameter: float = quantity(**_LENGTH)
    center_hole_diameter: float = quantity(**_CLEARANCE, default=0.0)
    post_radius: float | None = quantity("m", None, gt=0.0)
    planet_angles: tuple[float, ...] | None = quantity("rad", None, angle=True)
    pin_pitch_radius: float | None = quantity("m", None, gt=0.0)

    def __post_init__(self) -> None:
        check_fields(self)
        angles = None if self.planet_angles is None else tuple(float(a) for a in self.planet_angles)
        object.__setattr__(self, "planet_angles", angles)
        if angles is not None and not 2 <= len(angles) <= MAX_PLANETS:
            raise GeometryError("planet_angles", list(angles), f"needs 2 to {MAX_PLANETS} planets")
        r_p, d_p, R_c = self.pin_pitch_radius, self.pin_bore_diameter, self.cheek_diameter / 2
        if r_p is not None and r_p + d_p / 2 >= R_c:
            raise GeometryError("pin_bore_diameter", d_p,
                                f"pin bores on radius {r_p} m reach the cheek rim (radius {R_c} m)")
        if self.pins_set:
            self._check_pin_spacing()
        hub_r = max(self.seat_a_diameter, self.seat_b_diameter) / 2
        if hub_r >= R_c:
            raise GeometryError("seat_a_diameter" if self.seat_a_diameter >= self.seat_b_diameter else "seat_b_diameter",
                                2 * hub_r, f"hub larger than the cheek diameter {self.cheek_diameter} m")
        if r_p is not None and r_p - d_p / 2 <= hub_r:
            raise GeometryError("pin_pitch_radius", r_p,
                                f"pin bores (diameter {d_p} m) cut into the hub (radius {hub_r} m)")
        if self.output_bore_diameter >= self.seat_b_diameter:
            raise GeometryError("output_bore_diameter", self.output_bore_diameter,
                                f"must be smaller than seat_b_diameter {self.seat_b_diameter} m")
        if self.center_hole_diameter > 0:
            if self.center_hole_diameter >= min(self.seat_a_diameter, self.output_bore_diameter):
                raise GeometryError("center_hole_diameter", self.center_hole_diameter,
                                    "must be smaller than seat_a_diameter and output_bore_diameter")
        r_post = self.post_radius if self.post_radius is not None else r_p
        if r_post is not None:
            self._check_posts(r_post, R_c)

    @property
    def pins_set(self) -> bool:
        """Whether the planet pins are placed (``planet_angles`` and ``pin_pitch_radius``)."""
        return self.planet_angles is not None and self.pin_pitch_radius is not None

    def require_pins(self, names=("planet_angles", "pin_pitch_radius")) -> None:
        """GeometryError naming the first of the pin fields ``names`` not set (the geometry
        needs both)."""
        for name in names:
            if getattr(self, name) is None:
                raise GeometryError(name, None, "not set: the carrier's planet pins need planet_angles and "
                                                "pin_pitch_radius (a planetary stage sets them for its carrier)")

    def _check_pin_spacing(self) -> None:
        """Pin bores do not overlap one another."""
        r_p, d_p = self.pin_pitch_radius, self.pin_bore_diameter
        srt = sorted(a % (2 * math.pi) for a in self.planet_angles)
        for i in range(len(srt)):
            for j in range(i + 1, len(srt)):
                dist = 2 * r_p * abs(math.sin((srt[j] - srt[i]) / 2))
                if dist <= d_p:
                    raise GeometryError("pin_bore_diameter", d_p,
                                        f"pin bores at {math.degrees(srt[i]):.4g} and {math.degrees(srt[j]):.4g} deg "
                                        f"overlap (centre distance {dist:.6g} m)")

    def _check_posts(self, r_post: float, R_c: float) -> None:
        """Posts on radius ``r_post`` (m) inside the cheek rim (radius ``R_c``, m), clear of
        the central hole and, when the pins are placed, of the pin bores."""
        d_post, d_p = self.post_diameter, self.pin_bore_diameter
        if r_post + d_post / 2 >= R_c:
            raise GeometryError("post_diameter", d_post, f"posts reach the cheek rim (radius {R_c} m)")
        if r_post - d_post / 2 <= self.center_hole_diameter / 2:
            raise GeometryError("post_diameter", d_post, "posts cut into the central hole")
        if not self.pins_set:
            return
        r_p = self.pin_pitch_radius
        for a_post in self.post_angles:
            for a_pin in self.planet_angles:
                dx = r_post * math.cos(a_post) - r_p * math.cos(a_pin)
                dy = r_post * math.sin(a_post) - r_p * math.sin(a_pin)
                if math.hypot(dx, dy) <= (d_p + d_post) / 2:
                    raise GeometryError("post_diameter", d_post,
                                        f"post at {math.degrees(a_post):.4g} deg overlaps the pin bore at "
                                        f"{math.degrees(a_pin):.4g} deg")

    @property
    def n_planets(self) -> int:
        self.require_pins()
        return len(self.planet_angles)

    @property
    def post_radius_value(self) -> float:
        if self.post_radius is not None:
            return self.post_radius
        self.require_pins(("pin_pitch_radius",))
        return self.pin_pitch_radius

    @property
    def post_angles(self) -> tuple[float, ...]:
        """Post angles [rad]: midway between consecutive planets (sorted by angle)."""
        self.require_pins()
        srt = sorted(a % (2 * math.pi) for a in self.planet_angles)
        nxt = srt[1:] + [srt[0] + 2 * math.pi]
        return tuple((a + b) / 2 for a, b in zip(srt, nxt))



# ---------------------------------------------------------------- cylinder
@dataclass(frozen=True)
class CylinderParams:
    """Plain cylinder (or annulus if ``bore_diameter`` > 0) along z from 0 to ``length`` [m].

    Validation geometry with analytic mass, inertia and frequencies; interfaces
    "end_a" (face z = 0) and "end_b" (face z = length).
    """

    length: float = quantity(**_LENGTH, plausible=SHAFT_LENGTH)
    diameter: float = quantity(**_LENGTH, plausible=SHAFT_DIAMETER)
    bore_diameter: float = quantity(**_CLEARANCE, default=0.0)

    def __post_init__(self) -> None:
        check_fields(self)
        if self.bore_diameter >= self.diameter:
            raise GeometryError("bore_diameter", self.bore_diameter,
                                f"must be smaller than the diameter {self.diameter} m")



ComponentParams = PinionParams | WheelParams | CarrierParams | CylinderParams | PartFile

COMPONENT_KINDS = {"pinion": PinionParams, "wheel": WheelParams, "carrier": CarrierParams, "cylinder": CylinderParams,
                   "file": PartFile}


def component_kind(params: ComponentParams) -> str:
    for k, cls in COMPONENT_KINDS.items():
        if isinstance(params, cls):
            return k
    raise TypeError(f"not a component parameter object: {type(params).__name__}")


def params_digest(*objs: Any) -> str:
    """Stable SHA-256 (hex, 16 chars) over every field of the given dataclasses / values."""

    def enc(o: Any) -> Any:
        if dataclasses.is_dataclass(o) and hasattr(o, "cache_identity"):  # a user's part: its content
            return {"__type__": type(o).__name__, **enc(o.cache_identity())}
        if dataclasses.is_dataclass(o):
            return {"__type__": type(o).__name__, **{f.name: enc(getattr(o, f.name)) for f in dataclasses.fields(o)}}
        if isinstance(o, (list, tuple)):
            return [enc(v) for v in o]
        if isinstance(o, dict):
            return {str(k): enc(v) for k, v in sorted(o.items())}
        if isinstance(o, float):
            return repr(o)
        return o

    text = json.dumps([enc(o) for o in objs], sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def params_as_flat_dict(params: Any, prefix: str = "") -> dict[str, Any]:
    """Flatten a parameter dataclass into ``{"teeth.n_teeth": 20, ...}`` (for error reports)."""
    out: dict[str, Any] = {}
    for f in dataclasses.fields(params):
        v = getattr(params, f.name)
        key = f"{prefix}{f.name}"
        if dataclasses.is_dataclass(v):
            out.update(params_as_flat_dict(v, key + "."))
        elif isinstance(v, tuple) and v and dataclasses.is_dataclass(v[0]):
            for i, item in enumerate(v):
                out.update(params_as_flat_dict(item, f"{key}[{i}]."))
        else:
            out[key] = v
    return out
