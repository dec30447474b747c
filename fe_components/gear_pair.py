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
convention (no tip shortening), used only for the contact ratio.
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
    without profile shift, |m_t (z1 + z2) / 2|."""

    transverse_pressure_angle: float
    working_pressure_angle: float
    base_radius1: float
    base_radius2: float
    centre_distance: float
    standard_centre_distance: float
    contact_ratio: float


def pair_geometry(t1, t2, internal: bool = False) -> PairGeometry:
    """Geometry of gear ``t1`` (external) meshing with ``t2`` (internal if ``internal``),
    both GearTeeth that mesh (:func:`pair_mismatch` is None; not checked here)."""
    s = -1 if internal else 1
    z1, z2, x1, x2 = t1.n_teeth, s * t2.n_teeth, t1.profile_shift, t2.profile_shift
    m_n, a_n, beta = t1.normal_module, t1.pressure_angle, t1.helix_angle
    alpha_t = transverse_pressure_angle(a_n, beta)
    alpha_wt = working_pressure_angle(z1, z2, x1, x2, a_n, beta)
    a_w = working_centre_distance(z1, z2, x1, x2, m_n, a_n, beta)
    r_b1, r_b2 = base_radius(z1, m_n, a_n, beta), base_radius(z2, m_n, a_n, beta)
    m_t = m_n / math.cos(beta)
    r_a1 = t1.tip_radius
    r_a2 = t2.pitch_radius - m_n * (1.0 + x2) if internal else t2.tip_radius
    g1 = math.sqrt(max(r_a1 ** 2 - r_b1 ** 2, 0.0))
    g2 = math.sqrt(max(r_a2 ** 2 - r_b2 ** 2, 0.0))
    eps = (g1 + s * g2 - s * a_w * math.sin(alpha_wt)) / (math.pi * m_t * math.cos(alpha_t))
    return PairGeometry(transverse_pressure_angle=alpha_t, working_pressure_angle=alpha_wt,
                        base_radius1=r_b1, base_radius2=r_b2, centre_distance=a_w,
                        standard_centre_distance=abs(m_t * (z1 + z2) / 2.0), contact_ratio=eps)
