"""Mesh stiffness of a cylindrical gear pair from its teeth: ISO 6336-1:2006 / 2019, clause 9
(tooth stiffness parameters, method B). Plain functions on numbers.

Units: the standard's own in its formulas -- tooth-pair flexibility q' in mm um/N, stiffness
per unit face width in N/(mm um) -- and SI at the end: :func:`mesh_stiffness` returns N/m.
1 N/(mm um) = 1e9 N/m^2 (:data:`N_PER_MM_UM`), so k [N/m] = c_gamma_alpha * 1e9 * b [m].

* Virtual number of teeth of a helical gear: ``z_n = z / (cos^2(beta_b) cos(beta))``
  (beta reference helix angle, beta_b base helix angle).
* Minimum flexibility of a tooth pair (solid gears, standard basic rack, x within the
  usual range), in mm um/N::

      q' = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2 + C8 x1^2 + C9 x2^2

  with C1..C9 = 0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188,
  0.00529, 0.00182 (ISO 6336-1, clause 9.3.2, Table of constants; the same numbers as the
  ISO 6336 implementation of Reboucas, gfsReboucas/Drivetrain on GitHub, Gear_Set.m).
  Subscript 1 is the pinion (the external gear with fewer teeth, or the external gear of
  an internal pair), 2 the wheel. For an internal pair the standard takes z_n2 = infinity:
  the terms in 1/z_n2 vanish. The standard gives no replacement for x2 of the internal
  gear, so the internal gear's own profile shift coefficient enters C6 x2 + C9 x2^2 as
  given (ISO 21771 convention); with |x2| < 1 these two terms change q' by at most 0.0038,
  under 8 % of C1.
* Theoretical single stiffness ``c'_th = 1 / q'``; single stiffness (maximum stiffness of
  one tooth pair) ``c' = c'_th C_M C_R C_B cos(beta)`` with

  - C_M = 0.8, the correction between the theoretical and the measured stiffness of
    solid-disc gears;
  - C_R = 1 for a solid blank; a web gear (web thickness b_s, rim thickness s_R):
    ``C_R = 1 + ln(b_s / b) / (5 exp(s_R / (5 m_n)))`` (:func:`blank_factor`);
  - C_B = [1 + 0.5 (1.2 - h_fP / m_n)] [1 - 0.02 (20 deg - alpha_Pn)], the basic rack
    factor (dedendum h_fP of the basic rack, 1.25 m_n for the standard rack; alpha_Pn in
    degrees): 0.975 for the standard 20 deg rack.

* Mean mesh stiffness per unit face width ``c_gamma_alpha = c' (0.75 eps_alpha + 0.25)``
  (eps_alpha the transverse contact ratio, from the tip circles with the ISO 21771 tip
  alteration of :func:`fe_components.gear_pair.transverse_contact_ratio`). The standard
  states its values of c' and c_gamma for spur gears with eps_alpha >= 1.2 and says they
  can be up to about 10 % lower for spur gears with eps_alpha < 1.2: an estimate it allows
  ("can"), not a factor it prescribes, so it is not applied here (the 5 MW stage-1
  sun-planet pair of Nejad et al. (2016), eps_alpha 1.11, would be 10 % softer with it).
  The standard also reduces c' below a line load F_t K_A / b of 100 N/mm; not applied
  either (a linear, load-independent spring at the design load).

The standard's typical values for solid spur gears of the standard rack, without profile
shift (its method C) are c' = 14 and c_gamma_alpha = 20 N/(mm um).
"""
from __future__ import annotations

import math

from .gear_pair import base_helix_angle

#: Constants C1..C9 of q' (mm um/N), ISO 6336-1 clause 9.3.2.
Q_CONSTANTS = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
#: C_M: measured over theoretical stiffness of solid-disc gears (ISO 6336-1, clause 9.3.2).
C_M_SOLID = 0.8
#: Dedendum of the standard basic rack over the normal module (ISO 53), h_fP / m_n.
STANDARD_DEDENDUM = 1.25
#: N/m^2 in one N/(mm um).
N_PER_MM_UM = 1e9


def virtual_teeth(n_teeth: float, helix_angle: float, pressure_angle: float) -> float:
    """Virtual number of teeth z_n = z / (cos^2(beta_b) cos(beta)) (helix angle beta and
    normal pressure angle alpha_n in rad; z may be ``math.inf``)."""
    beta_b = base_helix_angle(pressure_angle, helix_angle)
    return n_teeth / (math.cos(beta_b) ** 2 * math.cos(helix_angle))


def tooth_pair_flexibility(zn1: float, zn2: float, x1: float, x2: float) -> float:
    """q' (mm um/N), the minimum flexibility of a tooth pair, from the virtual numbers of
    teeth of pinion and wheel (``zn2 = math.inf`` for an internal wheel) and their profile
    shift coefficients."""
    c1, c2, c3, c4, c5, c6, c7, c8, c9 = Q_CONSTANTS
    return (c1 + c2 / zn1 + c3 / zn2 + c4 * x1 + c5 * x1 / zn1 + c6 * x2 + c7 * x2 / zn2
            + c8 * x1 ** 2 + c9 * x2 ** 2)


def basic_rack_factor(pressure_angle: float, dedendum: float = STANDARD_DEDENDUM) -> float:
    """C_B = [1 + 0.5 (1.2 - h_fP/m_n)] [1 - 0.02 (20 - alpha_Pn[deg])] from the basic rack's
    normal pressure angle (rad) and dedendum over module h_fP/m_n (default 1.25)."""
    return (1.0 + 0.5 * (1.2 - dedendum)) * (1.0 - 0.02 * (20.0 - math.degrees(pressure_angle)))


def blank_factor(web_ratio: float | None = None, rim_ratio: float | None = None) -> float:
    """C_R: 1 for a solid blank (no arguments); for a web gear
    ``1 + ln(b_s/b) / (5 exp(s_R / (5 m_n)))`` from the web over face width b_s/b
    (``web_ratio``) and the rim thickness over the normal module s_R/m_n (``rim_ratio``)."""
    if web_ratio is None and rim_ratio is None:
        return 1.0
    if web_ratio is None or rim_ratio is None or not web_ratio > 0.0:
        raise ValueError(f"blank_factor: a web gear needs web_ratio > 0 and rim_ratio, got {web_ratio!r}, "
                         f"{rim_ratio!r}")
    return 1.0 + math.log(web_ratio) / (5.0 * math.exp(rim_ratio / 5.0))


def single_stiffness(z1: int, z2: int, x1: float, x2: float, helix_angle: float, pressure_angle: float,
                     internal: bool = False, c_m: float = C_M_SOLID, c_r: float = 1.0,
                     dedendum: float = STANDARD_DEDENDUM) -> float:
    """c' (N/(mm um)), the single stiffness of a tooth pair: gear 1 external (``z1`` teeth,
    shift ``x1``), gear 2 internal if ``internal`` (its ``z2`` positive). On an external pair
    the gear with fewer teeth is taken as the pinion (subscript 1 of the standard)."""
    if not internal and z2 < z1:
        z1, z2, x1, x2 = z2, z1, x2, x1
    zn1 = virtual_teeth(z1, helix_angle, pressure_angle)
    zn2 = math.inf if internal else virtual_teeth(z2, helix_angle, pressure_angle)
    q = tooth_pair_flexibility(zn1, zn2, x1, x2)
    if not q > 0.0:
        raise ValueError(f"tooth-pair flexibility q' = {q:.6g} mm um/N is not positive "
                         f"(profile shifts {x1:g}, {x2:g} far outside the standard's range)")
    return c_m * c_r * basic_rack_factor(pressure_angle, dedendum) * math.cos(helix_angle) / q


def mesh_stiffness_per_width(c_single: float, contact_ratio: float) -> float:
    """c_gamma_alpha = c' (0.75 eps_alpha + 0.25), mean mesh stiffness per unit face width
    (same unit as ``c_single``)."""
    return c_single * (0.75 * contact_ratio + 0.25)


def mesh_stiffness(z1: int, z2: int, x1: float, x2: float, helix_angle: float, pressure_angle: float,
                   contact_ratio: float, face_width: float, internal: bool = False) -> float:
    """Mean mesh stiffness along the line of action k = c_gamma_alpha b (N/m) of a solid
    pair of the standard basic rack (face width ``face_width`` in m, angles in rad;
    :func:`single_stiffness` for the gears)."""
    c = single_stiffness(z1, z2, x1, x2, helix_angle, pressure_angle, internal)
    return mesh_stiffness_per_width(c, contact_ratio) * N_PER_MM_UM * face_width
