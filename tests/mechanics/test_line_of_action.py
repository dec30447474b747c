"""The line of action of a parallel-axis mesh (assembly.mechanics.elements.line_of_action) is a property
of the pair, not of how the scene names it.

* Naming the gears the other way round describes the same contact: the same pitch point and
  the same line, the compression measured from the other side (n' = -n). The helix of the
  line of action flips with gear 1 (beta' = -beta: gear 1's flank normal lies at minus its
  base helix angle for an external gear, plus for an internal one, and the mate's hand is
  opposite, resp. equal -- ISO 21771; assembly.scene.gears.mesh_helix). The flank that
  closes when the new gear 1 turns positively: the same flank for an external pair (turning
  the driven gear against its driver closes the flank the driver loads), the other sense for
  an internal one (planet and ring turn the same way).
* The line of action lies in the transverse geometry: gears whose mid-planes are offset
  along the axis mesh along the same line, through the pitch point in gear 1's plane
  (the centre line is the transverse projection of c2 - c1).
Internal gears have a negative base radius (module notes of elements.py).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.mechanics.elements import line_of_action

ALPHA = math.radians(22.0)
PAIRS = [(0.05, 0.08), (0.03, -0.09), (-0.09, 0.03)]           # external; internal; ring as gear 1


@pytest.mark.parametrize("r1,r2", PAIRS, ids=["external", "internal", "ring-first"])
@pytest.mark.parametrize("beta", [0.0, 0.2, -0.2])
@pytest.mark.parametrize("drive", [1, -1])
def test_swapping_the_gears_gives_the_same_contact(r1, r2, beta, drive):
    axis = np.array([0.3, -0.2, 1.0]) / math.sqrt(1.13)
    ex = np.cross(axis, [1.0, 0.0, 0.0])
    ex /= np.linalg.norm(ex)
    c1 = np.array([0.1, 0.2, -0.3])
    c2 = c1 + (r1 + r2) / math.cos(ALPHA) * ex
    n, p = line_of_action(axis, c1, c2, r1, r2, ALPHA, beta, drive)
    swapped_drive = drive if r1 * r2 > 0 else -drive
    n2, p2 = line_of_action(axis, c2, c1, r2, r1, ALPHA, -beta, swapped_drive)
    np.testing.assert_allclose(n2, -n, atol=1e-14)
    np.testing.assert_allclose(p2, p, atol=1e-14)
    assert np.linalg.norm(n) == pytest.approx(1.0, abs=1e-15)
    # the pitch point on the centre line at r1 / cos(alpha) from gear 1 (signed radii: c2 - c1
    # is (r1 + r2) / cos(alpha) along ex)
    np.testing.assert_allclose(p, c1 + r1 / math.cos(ALPHA) * ex, atol=1e-15)
    # the normal's helix and pressure-angle parts: axial sin(beta), separating sin(alpha) cos(beta)
    assert abs(n @ axis) == pytest.approx(abs(math.sin(beta)), abs=1e-15)
    assert n @ ex == pytest.approx(math.sin(ALPHA) * math.cos(beta), abs=1e-15)


@pytest.mark.parametrize("r1,r2", PAIRS, ids=["external", "internal", "ring-first"])
def test_an_axial_offset_of_the_gears_changes_nothing(r1, r2):
    axis = np.array([0.0, 0.0, 1.0])
    c1 = np.zeros(3)
    c2 = np.array([(r1 + r2) / math.cos(ALPHA), 0.0, 0.0])
    for beta in (0.0, 0.25):
        n, p = line_of_action(axis, c1, c2, r1, r2, ALPHA, beta, 1)
        n_off, p_off = line_of_action(axis, c1, c2 + [0.0, 0.0, 0.04], r1, r2, ALPHA, beta, 1)
        np.testing.assert_allclose(n_off, n, atol=1e-15)
        np.testing.assert_allclose(p_off, p, atol=1e-15)
        assert p_off[2] == 0.0                               # in gear 1's transverse plane
