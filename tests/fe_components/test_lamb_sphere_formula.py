"""The exact free-sphere frequencies of tests/support/lamb_sphere.py (H. Lamb, Proc. London
Math. Soc. 13 (1882) 189-212) against published values and an independent closed form.

The spheroidal equation was also checked once against a P2 FE model of a free steel sphere
(gmsh + scikit-fem, a = 0.05 m, E = 210 GPa, nu = 0.3, rho = 7850 kg/m^3, mesh size 10 mm
and 7 mm): the ten lowest families agree to < 0.3 % (10 mm) and < 0.07 % (7 mm) with the
multiplicities 2n + 1, and the FE torsional clusters have no radial surface displacement.
That FE run (~1 min) is not repeated here; the ordering test below therefore uses the
formula's own numbers, which it established.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import spherical_jn

from tests.support.lamb_sphere import (
    shear_to_longitudinal_speed_ratio,
    sphere_frequencies,
    spheroidal_roots,
    torsional_roots,
)

STEEL_SPHERE = dict(radius=0.05, E=2.1e11, nu=0.3, rho=7850.0)


def _brentq_roots(f, x_max, count, step=1e-3):
    """First `count` sign-change roots of f on (0, x_max], refined by brentq."""
    x = np.arange(step, x_max, step)
    v = f(x)
    idx = np.flatnonzero(np.sign(v[:-1]) != np.sign(v[1:]))[:count]
    assert idx.size == count
    return np.array([brentq(f, x[i], x[i + 1], xtol=1e-15, rtol=1e-15) for i in idx])


def breathing_roots_closed_form(nu, count):
    """eta = omega a / c_T of the free sphere's radial modes, derived independently.

    u_r = A j_1(xi r / a), xi = omega a / c_L; sigma_rr = (lambda + 2 mu) u_r' + 2 lambda u_r / r
    = 0 at r = a gives (lambda + 2 mu) xi j_0(xi) = 4 mu j_1(xi), i.e.
        1 - xi cot(xi) = xi^2 c_L^2 / (4 c_T^2)           (Lamb 1882; note c_L over c_T),
    written pole-free as  sin xi - xi cos xi - q xi^2 sin xi = 0, q = c_L^2 / (4 c_T^2)."""
    r = shear_to_longitudinal_speed_ratio(nu)       # c_T / c_L
    q = 1.0 / (4.0 * r * r)
    xi = _brentq_roots(lambda x: np.sin(x) - x * np.cos(x) - q * x * x * np.sin(x), 12.0, count)
    return xi / r


@pytest.mark.parametrize("nu", [0.25, 0.3])
def test_breathing_modes_match_the_closed_form(nu):
    # both sides are brentq roots to ~1e-15: 1e-10 leaves room for the conditioning only
    np.testing.assert_allclose(spheroidal_roots(0, nu, 3), breathing_roots_closed_form(nu, 3),
                               rtol=1e-10)


def test_lowest_torsional_root_of_order_two():
    # Lamb (1882), first class, n = 2: omega a / c_T = 2.5011 (standard value for the free
    # sphere's lowest torsional mode); tolerance = half a unit of the 4th decimal
    assert torsional_roots(2, 1)[0] == pytest.approx(2.5011, abs=5e-5)


def test_torsional_frequencies_do_not_depend_on_poisson_ratio():
    # same shear modulus G = E / (2 (1 + nu)) and density, two Poisson ratios
    G, rho, a = 8.0e10, 7850.0, 0.05
    freqs = [[f for f, kind, *_ in sphere_frequencies(a, 2 * G * (1 + nu), nu, rho, f_max_hz=8e4)
              if kind == "torsional"] for nu in (0.2, 0.35)]
    np.testing.assert_allclose(freqs[0], freqs[1], rtol=1e-12)


def test_rigid_rotation_is_excluded_from_torsional_order_one():
    # n = 1: the equation is -eta j_2(eta) = 0; eta = 0 is the rigid rotation, the rest are the
    # zeros of j_2
    np.testing.assert_allclose(torsional_roots(1, 3),
                               _brentq_roots(lambda x: spherical_jn(2, x), 15.0, 3), rtol=1e-10)


def test_lowest_spheroidal_root_of_order_two_for_lambs_poisson_solid():
    # Lamb (1882), lambda = mu (nu = 1/4), second class, n = 2: omega a / c_T = 2.640
    # (given to 4 figures: tolerance half a unit of the 3rd decimal)
    assert spheroidal_roots(2, 0.25, 1)[0] == pytest.approx(2.640, abs=5e-4)


def test_rigid_translation_is_excluded_from_spheroidal_order_one():
    # the rigid translation is eta = 0; the first elastic n = 1 root lies above the n = 2 one
    for nu in (0.25, 0.3):
        assert spheroidal_roots(1, nu, 1)[0] > spheroidal_roots(2, nu, 1)[0]


def test_steel_sphere_families_order_and_multiplicities():
    # ordering of the 10 lowest families (from the formula; confirmed by the P2 FE run, see
    # module docstring): 51.01, 51.12 and 51.52 kHz are the close S0 / 2nd S2 / S4 triple
    expected = [("torsional", 2), ("spheroidal", 2), ("spheroidal", 1), ("torsional", 3),
                ("spheroidal", 3), ("spheroidal", 0), ("spheroidal", 2), ("spheroidal", 4),
                ("torsional", 4), ("torsional", 1)]
    fams = sphere_frequencies(**STEEL_SPHERE, count=11)
    assert [(kind, n) for _, kind, n, _ in fams[:10]] == expected
    assert all(m == 2 * n + 1 for _, _, n, m in fams)
    freqs = [f for f, *_ in fams]
    assert freqs == sorted(freqs) and freqs[0] > 1e4       # no rigid-body (0 Hz) family
    # the f_max form gives the same list: cut between the 10th and the 11th family
    assert sphere_frequencies(**STEEL_SPHERE, f_max_hz=0.5 * (freqs[9] + freqs[10])) == fams[:10]
