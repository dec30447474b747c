"""Transverse involute tooth profile (pure numpy, no gmsh).

Standard basic rack (h_a* = 1, h_f* = 1.25), profile shift x, no tip relief;
below the base circle the flank continues radially to the root circle (the
trochoidal root fillet is not modelled).  Angles in rad, lengths in m.
Reference: ISO 21771:2007, sections 5.3 (involute, inv(a) = tan(a) - a)
and 5.4 (tooth thickness s_t = m_t (pi/2 + 2 x tan(alpha_n))).
"""
from __future__ import annotations

import math

import numpy as np

from .errors import GeometryError


def inv(alpha: float | np.ndarray) -> float | np.ndarray:
    """Involute function inv(alpha) = tan(alpha) - alpha."""
    return np.tan(alpha) - alpha


def flank_half_angle(teeth, r: float | np.ndarray) -> float | np.ndarray:
    """Half tooth angle theta(r) [rad] of the transverse profile at radius r >= base radius.

    theta(r) = s_t / (2 r_p) + inv(alpha_t) - inv(alpha_r), cos(alpha_r) = r_b / r.
    """
    r_p, r_b = teeth.pitch_radius, teeth.base_radius
    s_t = teeth.transverse_module * (math.pi / 2 + 2 * teeth.profile_shift * math.tan(teeth.pressure_angle))
    alpha_r = np.arccos(np.clip(r_b / np.asarray(r, dtype=float), -1.0, 1.0))
    return s_t / (2 * r_p) + inv(teeth.transverse_pressure_angle) - inv(alpha_r)


def check_tooth_shape(teeth) -> None:
    """Refuse pointed teeth and teeth that leave no gap on the root circle."""
    theta_tip = float(flank_half_angle(teeth, teeth.tip_radius))
    if theta_tip <= 0:
        raise GeometryError("profile_shift", teeth.profile_shift,
                            "teeth are pointed (zero tip thickness) for this tooth count and shift")
    r_start = max(teeth.base_radius, teeth.root_radius)
    theta_start = float(flank_half_angle(teeth, r_start))
    if 2 * math.pi / teeth.n_teeth - 2 * theta_start <= 0:
        raise GeometryError("profile_shift", teeth.profile_shift, "tooth spaces close at the root circle")


def flank_radii(teeth, n_points: int) -> np.ndarray:
    """Radii of ``n_points`` flank points from max(r_b, r_f) to r_a, uniform in roll angle."""
    r_b = teeth.base_radius
    r0 = max(r_b, teeth.root_radius)
    # roll length l = sqrt(r^2 - r_b^2) is uniform -> dense near the base circle where curvature is high
    l0, l1 = math.sqrt(max(r0**2 - r_b**2, 0.0)), math.sqrt(teeth.tip_radius**2 - r_b**2)
    lengths = np.linspace(l0, l1, n_points)
    r = np.sqrt(r_b**2 + lengths**2)
    r[0], r[-1] = r0, teeth.tip_radius
    return r
