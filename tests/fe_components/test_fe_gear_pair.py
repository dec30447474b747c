"""Gear-pair geometry from teeth (ISO 21771:2007): working pressure angle and centre
distance against the published 5 MW reference gearbox, identities of unshifted pairs,
internal pairs, the inverse involute, and the contact ratio against the line of action."""
import math

import numpy as np
import pytest

from fe_components.gear_pair import (
    base_radius,
    gear_diameters,
    inv_inverse,
    pair_geometry,
    pair_mismatch,
    tip_alteration,
    working_centre_distance,
)
from fe_components.involute import inv
from fe_components.params import GearTeeth

DEG = math.radians


def teeth(z, m_n, x=0.0, beta=0.0, alpha=20.0):
    return GearTeeth(n_teeth=z, normal_module=m_n, pressure_angle=DEG(alpha), face_width=0.1,
                     helix_angle=DEG(beta), profile_shift=x)


# Nejad, Guo, Gao, Moan, "Development of a 5 MW reference gearbox for offshore wind
# turbines", Wind Energy 19 (2016) 1089-1106, Table V: normal pressure angle 20 deg;
# (sun, planet, ring teeth), m_n (m), helix (deg), shifts, centre distance (m).
# The table gives the centre distance to the whole millimetre, so a computed value is
# right within half a millimetre (0.5 mm): the rounding of the table, nothing else.
TABLE_V_PLANETARY = [
    ((19, 17, 56), 0.045, (0.617, 0.802, -0.501), 0.863),   # stage 1
    ((18, 36, 93), 0.021, (0.389, 0.504, 0.117), 0.584),    # stage 2
]
TABLE_ROUNDING = 0.5e-3  # m


@pytest.mark.parametrize("zs, m_n, xs, a_table", TABLE_V_PLANETARY)
def test_planetary_stages_give_the_published_centre_distance(zs, m_n, xs, a_table):
    sun, planet, ring = (teeth(z, m_n, x) for z, x in zip(zs, xs))
    a_sp = pair_geometry(sun, planet).centre_distance
    a_pr = pair_geometry(planet, ring, internal=True).centre_distance
    assert abs(a_sp - a_table) <= TABLE_ROUNDING
    assert abs(a_pr - a_table) <= TABLE_ROUNDING
    # the number form, ISO 21771's sign convention: z_ring < 0, x_ring as given
    assert working_centre_distance(zs[1], -zs[2], xs[1], xs[2], m_n, DEG(20), 0.0) == pytest.approx(a_pr, rel=1e-15)


def test_parallel_stage_gives_the_published_centre_distance():
    # Table V, stage 3: pinion 24 / wheel 95, m_n 14 mm, helix 10 deg, x 0.480 / 0.669, 861 mm
    g = pair_geometry(teeth(24, 0.014, 0.480, 10.0), teeth(95, 0.014, 0.669, -10.0))
    assert abs(g.centre_distance - 0.861) <= TABLE_ROUNDING
    # the shifts move the wheel out by (x1 + x2) m_n roughly: 845.9 mm unshifted
    assert g.standard_centre_distance == pytest.approx(0.014 * 119 / (2 * math.cos(DEG(10))), rel=1e-15)


@pytest.mark.parametrize("z1, z2, beta", [(17, 40, 0.0), (23, 71, 12.0), (31, 97, 25.0)])
def test_zero_shift_gives_the_standard_centre_distance(z1, z2, beta):
    # x1 + x2 = 0: inv(alpha_wt) = inv(alpha_t), a_w = m_n (z1 + z2) / (2 cos beta) (ISO 21771)
    m_n = 0.005
    g = pair_geometry(teeth(z1, m_n, 0.0, beta), teeth(z2, m_n, 0.0, -beta))
    assert g.centre_distance == pytest.approx(m_n * (z1 + z2) / (2 * math.cos(DEG(beta))), rel=1e-14)
    assert g.working_pressure_angle == g.transverse_pressure_angle
    # shifts of equal size and opposite sign keep it (V-zero pair)
    g0 = pair_geometry(teeth(z1, m_n, 0.3, beta), teeth(z2, m_n, -0.3, -beta))
    assert g0.centre_distance == pytest.approx(g.centre_distance, rel=1e-14)


def test_internal_pair_sign_and_radius():
    # planet 17 inside ring 56, no shift: a_w = m (56 - 17) / 2, and ISO's z2 < 0 gives the
    # same magnitude; the ring's base radius is negative (the scene's internal convention)
    m_n = 0.01
    g = pair_geometry(teeth(17, m_n), teeth(56, m_n), internal=True)
    assert g.centre_distance == pytest.approx(m_n * 39 / 2, rel=1e-14)
    assert g.base_radius2 < 0 < g.base_radius1
    assert g.centre_distance == pytest.approx(abs(g.base_radius1 + g.base_radius2) / math.cos(g.working_pressure_angle),
                                              rel=1e-14)
    # a positive shift sum on an internal pair brings the planet inwards (z1 + z2 < 0)
    assert pair_geometry(teeth(17, m_n, 0.3), teeth(56, m_n, 0.0), internal=True).centre_distance < g.centre_distance


@pytest.mark.parametrize("alpha_deg", [1.0, 14.5, 20.0, 28.1, 45.0, 70.0, 89.0])
def test_newton_inverse_of_inv(alpha_deg):
    a = DEG(alpha_deg)
    assert inv_inverse(float(inv(a))) == pytest.approx(a, rel=1e-12, abs=0)
    with pytest.raises(ValueError):
        inv_inverse(0.0)


def test_base_radius_matches_teeth():
    t = teeth(23, 0.004, 0.0, 12.0)
    assert base_radius(23, 0.004, DEG(20), DEG(12)) == t.base_radius
    assert base_radius(-56, 0.004, DEG(20), 0.0) == -teeth(56, 0.004).base_radius


def _path_of_contact(r_a1, r_b1, r_a2, r_b2, a, alpha, internal):
    """Length of the line of action inside both tip circles, found on a drawn line: gear 1
    at the origin, the line tangent to base circle 1 at T1 = r_b1 (cos a, sin a) and
    through the pitch point on the line of centres; gear 2 at (a, 0) (external: inside its
    tip circle, up to its tangent point T2) or the ring at (-a, 0) (internal: outside its
    tip circle, on the pitch point's side of T1)."""
    u = np.array([math.cos(alpha), math.sin(alpha)])
    d = np.array([-math.sin(alpha), math.cos(alpha)])
    T1 = r_b1 * u
    c2 = np.array([-a if internal else a, 0.0])
    s = np.linspace(-3 * a, 3 * a, 3_000_001)
    P = T1 + s[:, None] * d
    in1 = np.hypot(P[:, 0], P[:, 1]) <= r_a1
    r2 = np.hypot(P[:, 0] - c2[0], P[:, 1] - c2[1])
    if internal:
        on = in1 & (r2 >= r_a2) & (s <= 0.0)
    else:
        s_T2 = float((c2 - abs(r_b2) * u - T1) @ d)
        on = in1 & (r2 <= r_a2) & (s >= min(0.0, s_T2)) & (s <= max(0.0, s_T2))
    return s[on].max() - s[on].min(), s[1] - s[0]


@pytest.mark.parametrize("internal", [False, True])
def test_contact_ratio_is_path_of_contact_over_base_pitch(internal):
    # eps_a = g_a / p_bt, with g_a measured on a drawn line of action (ISO 21771 sec. 5.4)
    m_n = 0.01
    t1, t2 = teeth(19, m_n, 0.2), teeth(56 if internal else 41, m_n, 0.1)
    g = pair_geometry(t1, t2, internal)
    # ISO 21771 tip alteration: an external pair's tips are both shortened by
    # -k m_n = (x1 + x2) m_n - (a_w - a), a = m_n (z1 + z2) / 2 (spur); an internal pair none
    a = m_n * (t1.n_teeth + t2.n_teeth) / 2
    k_m = 0.0 if internal else g.centre_distance - a - (t1.profile_shift + t2.profile_shift) * m_n
    r_a2 = t2.pitch_radius - m_n * (1 + t2.profile_shift) if internal else t2.tip_radius + k_m
    g_a, ds = _path_of_contact(t1.tip_radius + k_m, t1.base_radius, r_a2, t2.base_radius, g.centre_distance,
                               g.working_pressure_angle, internal)
    p_bt = math.pi * m_n * math.cos(g.transverse_pressure_angle)
    assert g.contact_ratio == pytest.approx(g_a / p_bt, abs=2 * ds / p_bt)   # two sampling steps
    assert 1.0 < g.contact_ratio < 2.5


def test_pair_mismatch_names_the_field():
    assert pair_mismatch(teeth(20, 0.004), teeth(40, 0.005))[0] == "normal_module"
    assert pair_mismatch(teeth(20, 0.004), teeth(40, 0.004, alpha=25.0))[0] == "pressure_angle"
    assert pair_mismatch(teeth(20, 0.004, beta=10), teeth(40, 0.004, beta=10))[0] == "helix_angle"
    assert pair_mismatch(teeth(20, 0.004, beta=10), teeth(40, 0.004, beta=-10)) is None
    assert pair_mismatch(teeth(20, 0.004, beta=10), teeth(60, 0.004, beta=10), internal=True) is None


# Nejad et al. (2016), Wind Energy 19, Table V (as transcribed in gfsReboucas/Drivetrain on
# GitHub, NREL_5MW.m, with the tip alteration coefficients the authors took from KISSsoft):
# (z1, z2, x1, x2, m_n m, helix deg, tip diameters of gear 1 and 2 in m). Stage 1 and 2: sun,
# planet; stage 3: pinion, wheel. The table's own tips use slightly different k per gear
# (stage 1: -0.2410 sun, -0.2416 planet), so ours agree with it to its 0.1 mm rounding,
# i.e. within half of it, 0.05 mm, not to its third decimal.
TABLE_V_TIPS = [
    (19, 17, 0.617, 0.802, 0.045, 0.0, 0.978839, 0.905440),
    (18, 36, 0.389, 0.504, 0.021, 0.0, 0.432845, 0.815655),
    (24, 95, 0.480, 0.669, 0.014, 10.0, 0.380751, 1.395372),
]
TIP_ROUNDING = 0.05e-3   # m
# rings: (z, x, m_n, tip diameter m), no tip alteration
TABLE_V_RING_TIPS = [(56, -0.501, 0.045, 2.475087), (93, 0.117, 0.021, 1.906074)]


@pytest.mark.parametrize("z1, z2, x1, x2, m_n, beta, da1, da2", TABLE_V_TIPS)
def test_tip_alteration_gives_the_published_tip_diameters(z1, z2, x1, x2, m_n, beta, da1, da2):
    k = tip_alteration(z1, z2, x1, x2, m_n, DEG(20), DEG(beta))
    # k m_n = a_w - a - (x1 + x2) m_n: stage 1 a_w 863 mm, a = 45 * 36 / 2 = 810 mm,
    # (x1 + x2) m_n = 63.855 mm: k m_n = -10.86 mm, k = -0.241 (to a_w's 0.5 mm rounding: 0.011)
    if z1 == 19:
        assert k == pytest.approx((0.863 - 0.810 - 1.419 * 0.045) / 0.045, abs=0.5e-3 / 0.045)
    for z, x, d_a in ((z1, x1, da1), (z2, x2, da2)):
        assert abs(gear_diameters(z, m_n, DEG(beta), x, False, k)[1] - d_a) <= TIP_ROUNDING
        # without it the tips would be 2 |k| m_n (21.7, 3.5, 1.9 mm) too large
        assert gear_diameters(z, m_n, DEG(beta), x)[1] - d_a > 10 * TIP_ROUNDING


@pytest.mark.parametrize("z, x, m_n, d_a", TABLE_V_RING_TIPS)
def test_rings_take_no_tip_alteration(z, x, m_n, d_a):
    assert abs(gear_diameters(z, m_n, 0.0, x, internal=True)[1] - d_a) <= TIP_ROUNDING
    assert tip_alteration(17, -z, 0.802, x, m_n, DEG(20), 0.0) == 0.0


def test_unshifted_pair_has_no_tip_alteration():
    # x1 + x2 = 0: a_w = a, so k m_n = 0 (ISO 21771)
    assert tip_alteration(20, 40, 0.3, -0.3, 0.004, DEG(20), DEG(15)) == pytest.approx(0.0, abs=1e-12)
    assert tip_alteration(20, 40, 0.0, 0.0, 0.004, DEG(20), 0.0) == 0.0


def _eps_from_tips(da1, da2, z1, z2, m_n, a_w, internal=False):
    """eps_alpha of a spur pair from its tip diameters (ISO 21771, transverse contact ratio):
    (sqrt(r_a1^2 - r_b1^2) +- sqrt(r_a2^2 - r_b2^2) -+ a_w sin(alpha_w)) / (pi m_n cos(alpha)),
    r_b = z m_n cos(20 deg) / 2, cos(alpha_w) = (r_b2 +- r_b1) / a_w."""
    s = -1 if internal else 1
    rb1, rb2 = (z * m_n * math.cos(DEG(20)) / 2 for z in (z1, z2))
    alpha_w = math.acos((rb2 + s * rb1) / a_w)
    g = (math.sqrt((da1 / 2) ** 2 - rb1 ** 2) + s * math.sqrt((da2 / 2) ** 2 - rb2 ** 2)
         - s * a_w * math.sin(alpha_w))
    return g / (math.pi * m_n * math.cos(DEG(20)))


@pytest.mark.parametrize("zs, m_n, xs, a_table", TABLE_V_PLANETARY)
def test_contact_ratios_from_the_published_tips(zs, m_n, xs, a_table):
    # eps_alpha from Table V's tips (sun, planet, ring) at our working centre distance (the
    # table's is rounded to 1 mm); our tips differ from the table's by at most 0.05 mm, which
    # moves eps_alpha by at most sum r_a / sqrt(r_a^2 - r_b^2) dr_a / p_bt: under 1.5e-3 here.
    (z_s, z_p, z_r), (x_s, x_p, x_r) = zs, xs
    tips = {(19, 17): (0.978839, 0.905440, 2.475087), (18, 36): (0.432845, 0.815655, 1.906074)}[(z_s, z_p)]
    sun, planet, ring = (teeth(z, m_n, x) for z, x in zip(zs, xs))
    sp = pair_geometry(sun, planet)
    k = sp.tip_alteration
    pr = pair_geometry(planet, ring, internal=True, tip_alterations=(k, 0.0))
    assert sp.contact_ratio == pytest.approx(
        _eps_from_tips(tips[0], tips[1], z_s, z_p, m_n, sp.centre_distance), abs=1.5e-3)
    assert pr.contact_ratio == pytest.approx(
        _eps_from_tips(tips[1], tips[2], z_p, z_r, m_n, pr.centre_distance, internal=True), abs=1.5e-3)
    # the shortened tips lower both: stage 1 sun-planet from 1.39 to 1.11
    assert sp.contact_ratio < pair_geometry(sun, planet, tip_alterations=(0.0, 0.0)).contact_ratio
    assert pr.contact_ratio < pair_geometry(planet, ring, internal=True, tip_alterations=(0.0, 0.0)).contact_ratio
