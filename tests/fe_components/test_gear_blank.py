"""Gear blank mass properties from teeth (fe_components.gear_blank) and the tooth thickness on
the tip circle (fe_components.gear_pair.tip_thickness), against closed forms written out here.

Gear geometry: ISO 21771:2007 with the ISO 53 basic rack (h_aP = 1.0 m_n, h_fP = 1.25 m_n):
d = z m_n / cos(beta), external d_a = d + 2 m_n (1 + x), d_f = d - 2 m_n (1.25 - x).
A solid annulus (density rho, length b, diameters D_i < D_o) has
m = rho b pi/4 (D_o^2 - D_i^2), J_p = rho b pi/32 (D_o^4 - D_i^4), J_t = J_p/2 + m b^2/12.
"""
import math

import pytest

from fe_components.errors import GeometryError
from fe_components.gear_blank import GearBlank, blank_mass_properties
from fe_components.gear_pair import tip_thickness
from fe_components.involute import inv
from fe_components.material import STEEL

RHO = 7850.0          # kg/m^3, steel
DEG = math.radians


def closed_form(annuli, b):
    """(m, J_p, J_t) of coaxial annuli [(fill, D_i, D_o)] of length b: fill 1 solid, 1/2 the tooth zone."""
    m = sum(f * RHO * b * math.pi / 4 * (do ** 2 - di ** 2) for f, di, do in annuli)
    jp = sum(f * RHO * b * math.pi / 32 * (do ** 4 - di ** 4) for f, di, do in annuli)
    return m, jp, jp / 2 + m * b ** 2 / 12


def props(*args, **kw):
    p = blank_mass_properties(*args, **kw)
    return p.mass, p.polar_inertia, p.transverse_inertia


def test_steel_is_the_default_density():
    assert STEEL.rho == RHO


def test_solid_spur_blank():
    # z 40, m_n 4 mm, x 0, b 30 mm: d 160 mm, d_a 168 mm, d_f 150 mm;
    # m = rho b pi/4 (d_f^2 + (d_a^2 - d_f^2)/2) = 7850 * 0.03 * pi/4 * (0.0225 + 0.002862) = 4.691 kg
    want = closed_form([(1.0, 0.0, 0.150), (0.5, 0.150, 0.168)], 0.03)
    assert props(40, 0.004, 0.0, 0.0, 0.03) == pytest.approx(want, rel=1e-12)
    assert want[0] == pytest.approx(4.691, rel=1e-3)


def test_helical_shifted_blank_with_bore_and_own_length():
    # z 23, m_n 5 mm, beta 15 deg, x 0.3: d = 0.115 / cos 15 deg, d_a = d + 0.013, d_f = d - 0.0095;
    # bore 40 mm removed from the solid part; length 60 mm instead of the 50 mm face width
    d = 23 * 0.005 / math.cos(DEG(15))
    want = closed_form([(1.0, 0.040, d - 0.0095), (0.5, d - 0.0095, d + 0.013)], 0.06)
    got = props(23, 0.005, DEG(15), 0.3, 0.05, blank=GearBlank(bore_diameter=0.04, length=0.06))
    assert got == pytest.approx(want, rel=1e-12)


def test_ring_blank_default_rim_is_iso_6336_3_thickness():
    # internal z 99, m_n 4 mm, x 0.2 (ISO 21771 internal convention): d 396 mm,
    # d_a = d - 2 m_n (1 + x) = 386.4 mm inside, d_f = d + 2 m_n (1.25 - x) = 404.4 mm;
    # rim s_R = 1.2 h_t = 1.2 * 2.25 m_n = 10.8 mm -> outer diameter 426.0 mm
    want = closed_form([(0.5, 0.3864, 0.4044), (1.0, 0.4044, 0.4260)], 0.03)
    assert props(99, 0.004, 0.0, 0.2, 0.03, internal=True) == pytest.approx(want, rel=1e-12)
    wide = closed_form([(0.5, 0.3864, 0.4044), (1.0, 0.4044, 0.5)], 0.03)
    assert props(99, 0.004, 0.0, 0.2, 0.03, internal=True, blank=GearBlank(outer_diameter=0.5)) == \
        pytest.approx(wide, rel=1e-12)


def test_nrel_5mw_stage_1_sun():
    # Nejad et al. (2016), Wind Energy 19, Table V, stage 1 sun: z 19, m_n 45 mm, spur, x 0.617,
    # b 491 mm. d = 855 mm, d_a = 855 + 90 * 1.617 = 1000.53 mm, d_f = 855 - 90 * 0.633 = 798.03 mm;
    # m = 7850 * 0.491 * pi/4 * (0.798030^2 + (1.000530^2 - 0.798030^2)/2)
    #   = 3027.20 kg/m^2 * (0.636852 + 0.182104) m^2 = 2479.1 kg
    m, jp, jt = props(19, 0.045, 0.0, 0.617, 0.491)
    assert m == pytest.approx(2479.1, rel=5e-5)
    assert (m, jp, jt) == pytest.approx(closed_form([(1.0, 0.0, 0.79803), (0.5, 0.79803, 1.00053)], 0.491), rel=1e-12)


@pytest.mark.parametrize("internal, blank, field", [
    (False, GearBlank(bore_diameter=0.150), "bore_diameter"),      # bore reaches the root circle
    (False, GearBlank(bore_diameter=0.2), "bore_diameter"),
    (False, GearBlank(outer_diameter=0.3), "outer_diameter"),      # an external gear has no rim
    (True, GearBlank(bore_diameter=0.01), "bore_diameter"),        # a ring has no bore
    (True, GearBlank(outer_diameter=0.164), "outer_diameter"),     # rim inside the root circle
    (True, GearBlank(outer_diameter=0.1), "outer_diameter"),
])
def test_blanks_that_do_not_fit_the_teeth_are_refused(internal, blank, field):
    # z 40, m_n 4 mm, x 0: external d_f = 150 mm; internal d_f = 160 + 10 = 170 mm
    with pytest.raises(GeometryError) as err:
        blank_mass_properties(40, 0.004, 0.0, 0.0, 0.03, internal=internal, blank=blank)
    assert err.value.parameter == field


def test_blank_fields_have_ranges():
    for kw in ({"bore_diameter": -0.01}, {"outer_diameter": 0.0}, {"length": math.nan}):
        with pytest.raises(GeometryError):
            GearBlank(**kw)


# ---------------------------------------------------------------- tip thickness
def sa_external(z, m_n, alpha_n, x):
    """ISO 21771 spur tip thickness s_a = d_a (s_t/d + inv(alpha) - inv(alpha_a)),
    s_t = m_n (pi/2 + 2 x tan(alpha)), cos(alpha_a) = d cos(alpha) / d_a."""
    d, d_a = z * m_n, z * m_n + 2 * m_n * (1 + x)
    alpha_a = math.acos(d * math.cos(alpha_n) / d_a)
    s_t = m_n * (math.pi / 2 + 2 * x * math.tan(alpha_n))
    return d_a * (s_t / d + math.tan(alpha_n) - alpha_n - (math.tan(alpha_a) - alpha_a))


def test_tip_thickness_of_a_standard_20_tooth_gear():
    # z 20, m 1, alpha 20 deg, x 0: d 20, d_a 22, d_b = 20 cos 20 deg = 18.79385;
    # alpha_a = acos(18.79385 / 22) = acos(0.854266) = 31.3213 deg = 0.546659 rad,
    # inv(alpha_a) = 0.608518 - 0.546659 = 0.0618587; inv(20 deg) = 0.0149044; s_t/d = (pi/2)/20 = 0.0785398;
    # s_a = 22 (0.0785398 + 0.0149044 - 0.0618587) = 22 * 0.0315855 = 0.69488 (m_n)
    assert tip_thickness(20, 1.0, DEG(20), 0.0, 0.0) == pytest.approx(0.69488, rel=2e-5)
    assert tip_thickness(20, 1.0, DEG(20), 0.0, 0.0) == pytest.approx(sa_external(20, 1.0, DEG(20), 0.0), rel=1e-12)


def test_helical_tip_thickness_is_the_transverse_one():
    # a helical gear's transverse section is a spur gear of module m_t = m_n / cos(beta) and
    # pressure angle alpha_t = atan(tan(alpha_n) / cos(beta)); x m_n = x' m_t gives its shift
    beta, alpha_n = DEG(25), DEG(20)
    m_t, alpha_t = 1.0 / math.cos(beta), math.atan(math.tan(alpha_n) / math.cos(beta))
    x = 0.3
    d, d_a = 17 * m_t, 17 * m_t + 2 * (1 + x)
    s_t = m_t * (math.pi / 2 + 2 * x * math.tan(alpha_n))
    alpha_a = math.acos(d * math.cos(alpha_t) / d_a)
    spur = d_a * (s_t / d + inv(alpha_t) - inv(alpha_a))
    assert tip_thickness(17, 1.0, alpha_n, beta, x) == pytest.approx(spur, rel=1e-12)


def limit_shift(z, alpha_n):
    """Profile shift at which s_a = 0, by bisection on sa_external (decreasing in x)."""
    lo, hi = 0.0, 2.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if sa_external(z, 1.0, alpha_n, mid) > 0 else (lo, mid)
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("z", [8, 10, 12])
def test_tip_thickness_vanishes_at_the_bisected_limit_shift(z):
    x_lim = limit_shift(z, DEG(20))
    assert tip_thickness(z, 1.0, DEG(20), 0.0, x_lim) == pytest.approx(0.0, abs=1e-12)
    assert tip_thickness(z, 1.0, DEG(20), 0.0, x_lim - 1e-3) > 0 > tip_thickness(z, 1.0, DEG(20), 0.0, x_lim + 1e-3)


def test_internal_tip_thickness_is_the_gap_of_the_mating_rack_cut_external_gear():
    # An internal gear's tooth is the gap of the external gear of the same z cut with shift -x
    # (ISO 21771 sign convention): at radius r, s_int(r) = 2 pi r / z - s_ext(r), with
    # s_ext(r) = 2 r (s_t'/d + inv(alpha) - inv(alpha_r)), s_t' = m (pi/2 - 2 x tan(alpha)).
    z, x, alpha = 80, 0.25, DEG(20)
    d = z * 1.0
    r_a = d / 2 - (1 + x)                       # internal tip circle, inside
    alpha_r = math.acos(d / 2 * math.cos(alpha) / r_a)
    s_ext = 2 * r_a * ((math.pi / 2 - 2 * x * math.tan(alpha)) / d + inv(alpha) - inv(alpha_r))
    assert tip_thickness(z, 1.0, alpha, 0.0, x, internal=True) == pytest.approx(2 * math.pi * r_a / z - s_ext,
                                                                                rel=1e-12)
