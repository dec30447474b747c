"""Gear-pair geometry from teeth (ISO 21771:2007): working pressure angle and centre
distance against the published 5 MW reference gearbox, identities of unshifted pairs,
internal pairs, the inverse involute, and the contact ratio against the line of action."""
import math

import numpy as np
import pytest

from fe_components.gear_pair import (base_radius, inv_inverse, pair_geometry, pair_mismatch,
                                     working_centre_distance)
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
    r_a2 = t2.pitch_radius - m_n * (1 + t2.profile_shift) if internal else t2.tip_radius
    g_a, ds = _path_of_contact(t1.tip_radius, t1.base_radius, r_a2, t2.base_radius, g.centre_distance,
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
