"""ISO 6336-1 (method B) mesh stiffness: fe_components.mesh_stiffness."""
import math

import pytest

from fe_components.gear_pair import pair_geometry
from fe_components.mesh_stiffness import (
    C_M_SOLID,
    N_PER_MM_UM,
    Q_CONSTANTS,
    basic_rack_factor,
    blank_factor,
    mesh_stiffness,
    mesh_stiffness_per_width,
    single_stiffness,
    tooth_pair_flexibility,
    virtual_teeth,
)
from fe_components.params import GearTeeth

A20 = math.radians(20.0)


def _teeth(z, x=0.0, beta=0.0, m=0.004, b=0.04):
    return GearTeeth(n_teeth=z, normal_module=m, pressure_angle=A20, face_width=b, helix_angle=beta, profile_shift=x)


def test_rack_on_rack_without_shift_is_c1():
    # z_n1 = z_n2 = inf, x1 = x2 = 0: every term but C1 vanishes (ISO 6336-1, clause 9.3.2)
    assert tooth_pair_flexibility(math.inf, math.inf, 0.0, 0.0) == Q_CONSTANTS[0] == 0.04723


def test_standard_basic_rack_factor():
    # h_fP = 1.25 m_n, alpha_Pn = 20 deg: C_B = (1 + 0.5 (1.2 - 1.25)) (1 - 0) = 0.975
    assert basic_rack_factor(A20) == pytest.approx(0.975, rel=1e-15)
    # alpha_Pn = 25 deg, h_fP = 1.2 m_n: C_B = 1 x (1 - 0.02 (20 - 25)) = 1.1
    assert basic_rack_factor(math.radians(25.0), 1.2) == pytest.approx(1.1, rel=1e-14)


def test_blank_factor_solid_and_web():
    assert blank_factor() == 1.0
    # b_s = b: ln 1 = 0, a full-width web is a solid blank
    assert blank_factor(1.0, 3.0) == 1.0
    # b_s/b = 0.2, s_R = 5 m_n: 1 + ln 0.2 / (5 e) = 0.88158...
    assert blank_factor(0.2, 5.0) == pytest.approx(1.0 + math.log(0.2) / (5.0 * math.e), rel=1e-15)
    for bad in ((0.5, None), (None, 2.0), (0.0, 2.0), (-0.3, 2.0)):
        with pytest.raises(ValueError):
            blank_factor(*bad)


def test_virtual_teeth_spur_and_helical():
    assert virtual_teeth(24, 0.0, A20) == 24.0
    # beta = 30 deg: alpha_t = atan(tan 20 / cos 30), beta_b = atan(tan 30 cos alpha_t)
    beta = math.radians(30.0)
    beta_b = math.atan(math.tan(beta) * math.cos(math.atan(math.tan(A20) / math.cos(beta))))
    assert virtual_teeth(24, beta, A20) == pytest.approx(24 / (math.cos(beta_b) ** 2 * math.cos(beta)), rel=1e-15)
    # 0 < beta_b < beta: between z / cos(beta) and the common approximation z / cos^3(beta)
    assert 24 / math.cos(beta) < virtual_teeth(24, beta, A20) < 24 / math.cos(beta) ** 3


def test_standard_typical_values_lie_within_method_b_for_usual_spur_gears():
    """ISO 6336-1 (method C) takes c' = 14 and c_gamma_alpha = 20 N/(mm um) for solid spur
    gears of the standard basic rack without profile shift. Method B over the usual range of
    teeth (17 <= z1 <= z2 <= 150; 17 is the undercut limit of the 20 deg rack) must bracket
    both; its band is 10.9 ... 15.6 (c') from 17/17 to 150/150."""
    cs, cgs = [], []
    for z1 in (17, 20, 25, 30, 40, 60, 100, 150):
        for z2 in (17, 20, 25, 30, 40, 60, 100, 150):
            if z2 < z1:
                continue
            c = single_stiffness(z1, z2, 0.0, 0.0, 0.0, A20)
            eps = pair_geometry(_teeth(z1), _teeth(z2)).contact_ratio
            cs.append(c)
            cgs.append(mesh_stiffness_per_width(c, eps))
    assert min(cs) < 14.0 < max(cs)
    assert min(cgs) < 20.0 < max(cgs)
    # the upper bound of c' is the rack pair: 0.8 x 0.975 / C1 = 16.51 N/(mm um)
    assert max(cs) < C_M_SOLID * 0.975 / Q_CONSTANTS[0]


def test_more_teeth_stiffer_and_helix_softer_per_tooth_pair():
    zs = (17, 25, 40, 80, 200)
    pinion = [single_stiffness(z, 200, 0.0, 0.0, 0.0, A20) for z in zs]
    wheel = [single_stiffness(17, z, 0.0, 0.0, 0.0, A20) for z in zs]
    assert all(a < b for a, b in zip(pinion, pinion[1:]))
    assert all(a < b for a, b in zip(wheel, wheel[1:]))
    # the internal wheel (z_n2 = inf) is stiffer than any external one
    assert single_stiffness(17, 56, 0.0, 0.0, 0.0, A20, internal=True) > wheel[-1]
    # c' carries cos(beta): a helical pair's single stiffness falls with beta at fixed z_n
    assert single_stiffness(30, 60, 0.0, 0.0, math.radians(20), A20) < single_stiffness(30, 60, 0.0, 0.0, 0.0, A20)


def test_internal_wheel_is_the_limit_of_infinitely_many_teeth():
    # ISO 6336-1: z_n2 = inf for an internal gear; an external wheel of 1e15 teeth gives the
    # same q' up to its 1/z_n2 terms (0.26 x 1e-15)
    for z1, x1, x2 in ((17, 0.802, -0.501), (36, 0.504, 0.117), (24, 0.0, 0.0)):
        internal = single_stiffness(z1, 93, x1, x2, 0.0, A20, internal=True)
        assert internal == pytest.approx(single_stiffness(z1, 10 ** 15, x1, x2, 0.0, A20), rel=1e-12)


def test_pinion_is_the_gear_with_fewer_teeth():
    assert single_stiffness(60, 20, 0.3, -0.1, 0.0, A20) == single_stiffness(20, 60, -0.1, 0.3, 0.0, A20)


def test_mesh_stiffness_units():
    # k = c_gamma_alpha [N/(mm um)] x 1e9 [N/m^2 per N/(mm um)] x b [m]
    c = single_stiffness(20, 40, 0.0, 0.0, 0.0, A20)
    k = mesh_stiffness(20, 40, 0.0, 0.0, 0.0, A20, 1.6, 0.05)
    assert N_PER_MM_UM == 1e9
    assert k == pytest.approx(c * (0.75 * 1.6 + 0.25) * 1e9 * 0.05, rel=1e-15)


def test_profile_shifts_far_outside_the_range_are_refused():
    # q' <= 0 has no stiffness: z_n = 3 and x2 = 3 give C7 x2 / z_n2 = -0.24188, more than
    # C1 + (C2 + C3)/3 + C6 x2 + C9 x2^2 = 0.18835 makes up
    with pytest.raises(ValueError, match="not positive"):
        single_stiffness(3, 3, 0.0, 3.0, 0.0, A20)
