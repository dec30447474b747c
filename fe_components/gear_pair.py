"""Geometry of a parallel-axis gear pair from its teeth (ISO 21771:2007, section 5).

Plain functions on numbers (SI: m, rad), with :func:`pair_geometry` for two
:class:`~fe_components.params.GearTeeth`:

* transverse pressure angle ``alpha_t = atan(tan(alpha_n) / cos(beta))``;
* base radius ``r_b = z m_n cos(alpha_t) / (2 cos(beta))``;
* working transverse pressure angle from
  ``inv(alpha_wt) = inv(alpha_t) + 2 tan(alpha_n) (x1 + x2) / (z1 + z2)``
  (inv(a) = tan(a) - a), solved by Newton's method (:func:`inv_inverse`);
* working centre distance ``a_w = m_n (z1 + z2) cos(alpha_t) / (2 cos(beta) cos(alpha_wt))``,
  which equals ``(r_b1 + r_b2) / cos(alpha_wt)``;
* transverse contact ratio ``eps_a = (sqrt(r_a1^2 - r_b1^2) +- sqrt(r_a2^2 - r_b2^2)
  -+ a_w sin(alpha_wt)) / p_bt``, ``p_bt = pi m_t cos(alpha_t)`` (lower signs: internal).

Internal gears: ISO 21771 writes the internal gear's tooth number negative (z2 < 0) and its
profile shift coefficient as given, which makes z1 + z2 and so a_w negative: the number
functions take z2 < 0 and return ``|a_w|``; :func:`pair_geometry` takes an ``internal`` flag
for the second gear instead (its ``GearTeeth.n_teeth`` stays positive). Only the base
radius an internal gear gets here is negative (the scene's convention). The tip circle of
an internal gear lies inside its pitch circle, ``r_a2 = r_2 - m_n (1 + x2)`` in the same sign
convention.

Tip alteration (ISO 21771, section 5.2.5; DIN 3960): a pair with profile shift works at a
centre distance a_w smaller than a + (x1 + x2) m_n, so teeth cut to ``d + 2 m_n (1 + x)``
would leave less than the standard bottom clearance 0.25 m_n. Both gears of an external pair
are shortened by ``k m_n = a_w - a - (x1 + x2) m_n`` (k <= 0, a = m_t (z1 + z2) / 2 the
reference centre distance): ``d_a = d + 2 m_n (1 + x + k)`` (:func:`tip_alteration`).
Nejad et al. (2016), Wind Energy 19, Table V: stage 1 (a_w 863 mm, a 810 mm) k = -0.241,
tip diameters 978.8 / 905.4 mm. Internal pairs get no tip alteration here (k = 0): the
formula in ISO 21771's signed quantities gives k >= 0 for them (a stage-1 ring of the same
table: +0.021), which would lengthen the teeth, and Table V's ring tips are d - 2 m_n (1 + x)
to its rounding. A gear meshing two partners (a planet: an external sun and an internal
ring) has one tip circle: it takes the k of its external pair.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .involute import inv

#: Newton's method on inv stops once a step is below this (relative, rad).
_NEWTON_TOL = 1e-15


def inv_inverse(value: float) -> float:
    """The angle alpha in (0, pi/2) (rad) with inv(alpha) = tan(alpha) - alpha = ``value``
    (> 0), by Newton's method (inv'(alpha) = tan^2(alpha)). inv is increasing and convex on
    (0, pi/2), so Newton started above the root descends to it monotonically: the start
    is the small-angle estimate (3 v)^(1/3) (inv(a) ~ a^3/3), moved towards pi/2 until inv
    exceeds the value."""
    if not (value > 0.0 and math.isfinite(value)):
        raise ValueError(f"inv_inverse: needs a finite value > 0, got {value!r}")
    a = min((3.0 * value) ** (1.0 / 3.0), 1.5)
    while float(inv(a)) < value:
        a = 0.5 * (a + math.pi / 2)
    for _ in range(200):
        t = math.tan(a)
        step = (t - a - value) / (t * t)
        a -= step
        if abs(step) <= _NEWTON_TOL * a:
            break
    return a


def transverse_pressure_angle(pressure_angle: float, helix_angle: float) -> float:
    """alpha_t = atan(tan(alpha_n) / cos(beta)) (rad) from the normal pressure angle and
    the helix angle (rad)."""
    return math.atan(math.tan(pressure_angle) / math.cos(helix_angle))


def base_helix_angle(pressure_angle: float, helix_angle: float) -> float:
    """beta_b = atan(tan(beta) cos(alpha_t)) (rad, signed as beta): the helix angle on the
    base cylinder (ISO 21771), the inclination of the flank normal -- the line of action --
    to the transverse plane."""
    return math.atan(math.tan(helix_angle) * math.cos(transverse_pressure_angle(pressure_angle, helix_angle)))


def base_radius(n_teeth: int, normal_module: float, pressure_angle: float, helix_angle: float) -> float:
    """r_b = z m_n cos(alpha_t) / (2 cos(beta)) (m); negative for z < 0 (internal gear)."""
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    return 0.5 * n_teeth * (normal_module / math.cos(helix_angle)) * math.cos(alpha_t)


#: ISO 53 basic rack: addendum h_aP = 1.0 m_n and dedendum h_fP = 1.25 m_n (in normal modules).
ADDENDUM = 1.0
DEDENDUM = 1.25


def tip_alteration(z1: int, z2: int, x1: float, x2: float, normal_module: float, pressure_angle: float,
                   helix_angle: float) -> float:
    """Tip alteration coefficient k (dimensionless, <= 0) of gear pair (z1, z2, shifts x1, x2),
    ISO 21771: ``k m_n = a_w - a - (x1 + x2) m_n``, a = m_t (z1 + z2) / 2, both gears of an
    external pair shortened by -k m_n. z2 < 0 (an internal gear 2): 0, no alteration (module
    docstring)."""
    if z2 < 0:
        return 0.0
    a_w = working_centre_distance(z1, z2, x1, x2, normal_module, pressure_angle, helix_angle)
    a = 0.5 * (z1 + z2) * normal_module / math.cos(helix_angle)
    return min((a_w - a) / normal_module - (x1 + x2), 0.0)


def gear_diameters(n_teeth: int, normal_module: float, helix_angle: float, profile_shift: float,
                   internal: bool = False, tip_alteration: float = 0.0) -> tuple[float, float, float]:
    """(d, d_a, d_f) (m, all positive): reference, tip and root diameters of a gear cut with
    the ISO 53 basic rack (ISO 21771), ``d = z m_n / cos(beta)``, tip shortened by the tip
    alteration coefficient k = ``tip_alteration`` (<= 0, :func:`tip_alteration`). External:
    ``d_a = d + 2 m_n (1 + x + k)``, ``d_f = d - 2 m_n (1.25 - x)``. Internal (``n_teeth`` > 0,
    ``x`` in ISO 21771's convention for internal gears, as :func:`pair_geometry` uses it): the
    tip circle lies inside, ``d_a = d - 2 m_n (1 + x + k)``, ``d_f = d + 2 m_n (1.25 - x)``."""
    d = n_teeth * normal_module / math.cos(helix_angle)
    s = -1.0 if internal else 1.0
    return (d, d + s * 2.0 * normal_module * (ADDENDUM + profile_shift + tip_alteration),
            d - s * 2.0 * normal_module * (DEDENDUM - profile_shift))


def tip_thickness(n_teeth: int, normal_module: float, pressure_angle: float, helix_angle: float,
                  profile_shift: float, internal: bool = False, tip_alteration: float = 0.0) -> float:
    """Transverse tooth thickness on the tip circle s_a (m; <= 0: pointed teeth), ISO 21771:
    ``s_a = d_a (s_t / d + inv(alpha_t) - inv(alpha_a))``, ``cos(alpha_a) = d_b / d_a``, from the
    thickness on the reference circle ``s_t = m_t (pi/2 + 2 x tan(alpha_n))``. An internal
    gear (ISO's signed diameters) narrows towards its tip inside: ``s_a = d_a (s_t / d -
    inv(alpha_t) + inv(alpha_a))``; a tip circle inside the base circle (no involute there)
    gives the thickness where the involute ends, on the base circle. The tip circle is
    :func:`gear_diameters`' with the tip alteration coefficient ``tip_alteration`` (<= 0)."""
    d, d_a, _ = gear_diameters(n_teeth, normal_module, helix_angle, profile_shift, internal, tip_alteration)
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    s_t = normal_module / math.cos(helix_angle) * (math.pi / 2 + 2 * profile_shift * math.tan(pressure_angle))
    alpha_a = math.acos(min(d * math.cos(alpha_t) / d_a, 1.0))
    sign = -1.0 if internal else 1.0
    return d_a * (s_t / d + sign * (float(inv(alpha_t)) - float(inv(alpha_a))))


def working_pressure_angle(z1: int, z2: int, x1: float, x2: float, pressure_angle: float,
                           helix_angle: float) -> float:
    """alpha_wt (rad) from inv(alpha_wt) = inv(alpha_t) + 2 tan(alpha_n) (x1 + x2)/(z1 + z2);
    z2 < 0 for an internal gear 2 (ISO 21771)."""
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    if x1 + x2 == 0.0:   # inv is one-to-one: no shift sum, no change of the angle
        return alpha_t
    v = float(inv(alpha_t)) + 2.0 * math.tan(pressure_angle) * (x1 + x2) / (z1 + z2)
    if not v > 0.0:
        raise ValueError(f"profile shifts x1 + x2 = {x1 + x2:.6g} leave no working pressure angle "
                         f"(inv(alpha_wt) = {v:.6g} <= 0)")
    return inv_inverse(v)


def working_centre_distance(z1: int, z2: int, x1: float, x2: float, normal_module: float,
                            pressure_angle: float, helix_angle: float) -> float:
    """|a_w| (m) = |m_n (z1 + z2) cos(alpha_t) / (2 cos(beta) cos(alpha_wt))|; z2 < 0 for
    an internal gear 2 (ISO 21771)."""
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    alpha_wt = working_pressure_angle(z1, z2, x1, x2, pressure_angle, helix_angle)
    return abs(normal_module * (z1 + z2) * math.cos(alpha_t) / (2.0 * math.cos(helix_angle) * math.cos(alpha_wt)))


def shift_sum_for_centre_distance(z1: int, z2: int, centre_distance: float, normal_module: float,
                                  pressure_angle: float, helix_angle: float) -> float | None:
    """x1 + x2 that puts the pair at the working centre distance ``centre_distance`` (m):
    :func:`working_centre_distance` inverted, ``cos(alpha_wt) = m_n |z1 + z2| cos(alpha_t) /
    (2 cos(beta) a_w)``, ``x1 + x2 = (z1 + z2) (inv(alpha_wt) - inv(alpha_t)) / (2 tan(alpha_n))``;
    z2 < 0 for an internal gear 2. None when no working pressure angle gives that distance."""
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    c = normal_module * abs(z1 + z2) * math.cos(alpha_t) / (2.0 * math.cos(helix_angle) * centre_distance)
    if not 0.0 < c < 1.0:
        return None
    return (z1 + z2) * (float(inv(math.acos(c))) - float(inv(alpha_t))) / (2.0 * math.tan(pressure_angle))


def transverse_contact_ratio(z1: int, z2: int, x1: float, x2: float, normal_module: float,
                             pressure_angle: float, helix_angle: float,
                             tip_alterations: tuple[float, float] | None = None) -> float:
    """eps_a = (sqrt(r_a1^2 - r_b1^2) +- sqrt(r_a2^2 - r_b2^2) -+ a_w sin(alpha_wt)) / p_bt of an
    external gear 1 with gear 2 (z2 < 0: internal, lower signs), tip radii
    r + m_n (1 + x + k) (external) and r - m_n (1 + x + k) (internal). ``tip_alterations``:
    (k1, k2) of the two gears; default the pair's own (:func:`tip_alteration`: k on both
    gears of an external pair, 0 on an internal pair) -- a planet's tips on its ring pair
    are those of its sun pair, so give (k_sun_planet, 0) there."""
    s = -1 if z2 < 0 else 1
    if tip_alterations is None:
        k = tip_alteration(z1, z2, x1, x2, normal_module, pressure_angle, helix_angle)
        tip_alterations = (k, k)
    m_t = normal_module / math.cos(helix_angle)
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    alpha_wt = working_pressure_angle(z1, z2, x1, x2, pressure_angle, helix_angle)
    a_w = working_centre_distance(z1, z2, x1, x2, normal_module, pressure_angle, helix_angle)
    g1, g2 = (math.sqrt(max((0.5 * z * m_t + sign * normal_module * (1.0 + x + k)) ** 2
                            - base_radius(z, normal_module, pressure_angle, helix_angle) ** 2, 0.0))
              for z, x, k, sign in ((z1, x1, tip_alterations[0], 1), (abs(z2), x2, tip_alterations[1], s)))
    return (g1 + s * g2 - s * a_w * math.sin(alpha_wt)) / (math.pi * m_t * math.cos(alpha_t))


def pair_mismatch(t1, t2, internal: bool = False):
    """(field, value on gear 1, value on gear 2, reason) of the first field on which teeth
    ``t1`` and ``t2`` (GearTeeth) cannot mesh, or None: equal normal modules and normal
    pressure angles (relative 1e-9), helix angles opposite on an external pair and equal on
    an internal one (1e-9 rad)."""
    for f in ("normal_module", "pressure_angle"):
        a, b = getattr(t1, f), getattr(t2, f)
        if abs(a - b) > 1e-9 * max(abs(a), abs(b)):
            return f, a, b, "must be equal on both gears"
    want = t1.helix_angle if internal else -t1.helix_angle
    if abs(t2.helix_angle - want) > 1e-9:
        return ("helix_angle", t1.helix_angle, t2.helix_angle,
                "must be equal on an internal pair" if internal
                else "must be opposite on an external pair (one left-hand, one right-hand)")
    return None


@dataclass(frozen=True)
class PairGeometry:
    """Derived geometry of a gear pair (m, rad). ``base_radius2`` is negative for an
    internal gear 2; ``centre_distance`` is |a_w|; ``standard_centre_distance`` is the one
    without profile shift, |m_t (z1 + z2) / 2|; ``tip_alteration`` the pair's k
    (:func:`tip_alteration`, 0 for an internal pair); ``contact_ratio`` eps_alpha with the
    tips of ``tip_alterations`` given to :func:`pair_geometry`."""

    transverse_pressure_angle: float
    working_pressure_angle: float
    base_radius1: float
    base_radius2: float
    centre_distance: float
    standard_centre_distance: float
    contact_ratio: float
    tip_alteration: float


def pair_geometry(t1, t2, internal: bool = False,
                  tip_alterations: tuple[float, float] | None = None) -> PairGeometry:
    """Geometry of gear ``t1`` (external) meshing with ``t2`` (internal if ``internal``),
    both GearTeeth that mesh (:func:`pair_mismatch` is None; not checked here);
    ``tip_alterations`` as :func:`transverse_contact_ratio` takes them."""
    s = -1 if internal else 1
    z1, z2, x1, x2 = t1.n_teeth, s * t2.n_teeth, t1.profile_shift, t2.profile_shift
    m_n, a_n, beta = t1.normal_module, t1.pressure_angle, t1.helix_angle
    alpha_t = transverse_pressure_angle(a_n, beta)
    alpha_wt = working_pressure_angle(z1, z2, x1, x2, a_n, beta)
    a_w = working_centre_distance(z1, z2, x1, x2, m_n, a_n, beta)
    r_b1, r_b2 = base_radius(z1, m_n, a_n, beta), base_radius(z2, m_n, a_n, beta)
    m_t = m_n / math.cos(beta)
    eps = transverse_contact_ratio(z1, z2, x1, x2, m_n, a_n, beta, tip_alterations)
    return PairGeometry(transverse_pressure_angle=alpha_t, working_pressure_angle=alpha_wt,
                        base_radius1=r_b1, base_radius2=r_b2, centre_distance=a_w,
                        standard_centre_distance=abs(m_t * (z1 + z2) / 2.0), contact_ratio=eps,
                        tip_alteration=tip_alteration(z1, z2, x1, x2, m_n, a_n, beta))
