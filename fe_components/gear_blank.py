"""Mass and inertia of a gear blank from its teeth (SI: m, kg, kg m^2), for a gear given by
teeth, module, face width and profile shift only (e.g. Nejad et al. (2016), Wind Energy 19,
1089-1106, Table V).

The blank is coaxial annuli of length ``length`` (default the face width b), centred on the
mid-face, of density ``density`` (default steel, 7850 kg/m^3):

* the tooth zone between the root diameter d_f and the tip diameter d_a
  (:func:`fe_components.gear_pair.gear_diameters`, ISO 21771 / ISO 53 basic rack, with the
  pair's tip alteration k: d_a = d + 2 m_n (1 + x + k)) counted as half metal: tooth and gap
  are of equal width on the reference circle;
* an external gear: a solid annulus from the bore (``bore_diameter``, default 0) to d_f;
* an internal gear (ring): its teeth point inwards, d_a < d_f; a rim from d_f out to
  ``outer_diameter``, by default d_f + 2 s_R with the rim thickness s_R = 1.2 h_t, h_t =
  2.25 m_n the tooth depth: ISO 6336-3's rim thickness at and above which the rim factor
  Y_B = 1 (the rim no more weakens the tooth root), i.e. the thinnest rim a rating takes as
  solid.

An annulus of mass m between radii r_i and r_o, length L: ``m = rho L pi (r_o^2 - r_i^2)``,
polar ``J_p = m (r_o^2 + r_i^2) / 2``, transverse about its centre ``J_t = J_p / 2 + m L^2 / 12``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import GeometryError
from .fields import check_fields, quantity
from .gear_pair import ADDENDUM, DEDENDUM, gear_diameters
from .material import STEEL

#: ISO 6336-3: rim thickness s_R >= 1.2 h_t gives the rim factor Y_B = 1.
RIM_THICKNESS_PER_TOOTH_DEPTH = 1.2


@dataclass(frozen=True)
class GearBlank:
    """Optional blank dimensions of a gear whose mass comes from its teeth (m):
    ``bore_diameter`` (external gears; default 0, solid), ``outer_diameter`` (internal
    gears; default d_f + 2 x 1.2 x 2.25 m_n), ``length`` (default the face width)."""

    bore_diameter: float = quantity("m", 0.0, ge=0.0)
    outer_diameter: float | None = quantity("m", None, gt=0.0)
    length: float | None = quantity("m", None, gt=0.0)

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class MassProperties:
    """Mass (kg), polar and transverse inertia (kg m^2) about the centre of mass."""

    mass: float
    polar_inertia: float
    transverse_inertia: float


def annulus(density: float, length: float, r_inner: float, r_outer: float) -> MassProperties:
    """Mass properties of a coaxial annulus (density kg/m^3, lengths m) about its centre."""
    m = density * length * math.pi * (r_outer ** 2 - r_inner ** 2)
    jp = 0.5 * m * (r_outer ** 2 + r_inner ** 2)
    return MassProperties(m, jp, 0.5 * jp + m * length ** 2 / 12.0)


def blank_mass_properties(n_teeth: int, normal_module: float, helix_angle: float, profile_shift: float,
                          face_width: float, internal: bool = False, blank: GearBlank | None = None,
                          density: float = STEEL.rho, tip_alteration: float = 0.0) -> MassProperties:
    """Mass properties of the gear blank (module docstring) of a gear with ``n_teeth``,
    ``normal_module`` (m), ``helix_angle`` (rad), ``profile_shift`` x, ``face_width`` (m)
    and tip alteration coefficient ``tip_alteration`` k (<= 0,
    :func:`fe_components.gear_pair.tip_alteration`); ``internal``: a ring, x as ISO 21771
    gives it. Raises GeometryError naming the ``blank`` field that does not fit the teeth."""
    blank = blank or GearBlank()
    _, d_a, d_f = gear_diameters(n_teeth, normal_module, helix_angle, profile_shift, internal, tip_alteration)
    length = blank.length if blank.length is not None else face_width
    teeth = annulus(0.5 * density, length, min(d_a, d_f) / 2, max(d_a, d_f) / 2)
    if internal:
        if blank.bore_diameter != 0.0:
            raise GeometryError("bore_diameter", blank.bore_diameter, "an internal gear (ring) has no bore; "
                                                                      "give its outer_diameter")
        s_rim = RIM_THICKNESS_PER_TOOTH_DEPTH * (ADDENDUM + DEDENDUM) * normal_module
        d_out = blank.outer_diameter if blank.outer_diameter is not None else d_f + 2 * s_rim
        if d_out <= d_f:
            raise GeometryError("outer_diameter", d_out, f"must exceed the root diameter {d_f:.6g} m")
        body = annulus(density, length, d_f / 2, d_out / 2)
    else:
        if blank.outer_diameter is not None:
            raise GeometryError("outer_diameter", blank.outer_diameter,
                                "only an internal gear (ring) takes an outer diameter; an external "
                                "gear's is its tip diameter")
        if blank.bore_diameter >= d_f:
            raise GeometryError("bore_diameter", blank.bore_diameter,
                                f"must be smaller than the root diameter {d_f:.6g} m")
        body = annulus(density, length, blank.bore_diameter / 2, d_f / 2)
    return MassProperties(teeth.mass + body.mass, teeth.polar_inertia + body.polar_inertia,
                          teeth.transverse_inertia + body.transverse_inertia)
