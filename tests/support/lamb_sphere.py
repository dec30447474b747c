"""Exact natural frequencies of a free, homogeneous, isotropic elastic sphere.

Reference solution for FE tests: H. Lamb, "On the vibrations of an elastic sphere",
Proc. London Math. Soc. 13 (1882) 189-212. The modes split into two classes, each
(2n+1)-fold degenerate in the azimuthal index m:

* torsional (toroidal, Lamb's "first class"): u = curl(r j_n(k r) Y_nm), divergence free;
* spheroidal (Lamb's "second class"): u = grad(j_n(h r) Y_nm) + curl curl(r j_n(k r) Y_nm),

with h = omega / c_L, k = omega / c_T, c_T = sqrt(mu / rho), c_L = sqrt((lambda + 2 mu) / rho).
Roots are returned as eta = omega a / c_T = k a (a = radius); xi = omega a / c_L = h a.

Frequency equations (traction-free surface r = a), in the form of Y. Sato and T. Usami,
"Basic study on the oscillation of a homogeneous elastic sphere, Part I: frequency of the
free oscillations", Geophys. Mag. 31 (1962) 15-24, eq. (2.2), which is written with
J_{n+1/2}; here with spherical Bessel functions j_n(x) = sqrt(pi / 2x) J_{n+1/2}(x) (a
positive factor per column, so the same roots). The same equations follow directly from the
potentials above (sigma_rr = sigma_r(theta,phi) = 0 at r = a); they were re-derived that way
for this module:

* torsional:   (n - 1) j_n(eta) - eta j_{n+1}(eta) = 0                     (= eta j_n' - j_n)
* spheroidal:  det [[A11, A12], [A21, A22]] = 0 with
      A11 = (2n(n-1) - eta^2) j_n(xi) + 4 xi j_{n+1}(xi)            (sigma_rr of the grad part)
      A12 = 2n(n+1) ((n-1) j_n(eta) - eta j_{n+1}(eta))             (sigma_rr of the curl curl part)
      A21 = 2 ((n-1) j_n(xi) - xi j_{n+1}(xi))                       (shear stress, grad part)
      A22 = (2(n^2-1) - eta^2) j_n(eta) + 2 eta j_{n+1}(eta)         (shear stress, curl curl part)
* n = 0 (breathing mode, no shear stress and no curl curl part): A11 = 0, i.e.
      4 xi j_1(xi) = eta^2 j_0(xi)  <=>  1 - xi cot(xi) = xi^2 c_L^2 / (4 c_T^2)  (Lamb 1882).

The equations contain only j_n and j_{n+1} (no quotients), so they have no poles; each
column is divided by hypot(j_n, j_{n+1}) of its argument (positive: consecutive spherical
Bessel functions have no common zero), which keeps the values O(1) without moving a root.
Roots: sign changes on a fine grid, refined with scipy.optimize.brentq.

Rigid-body modes: the torsional n = 1 equation is -eta j_2(eta) = 0, whose root eta = 0 is
the 3 rigid rotations; the spheroidal n = 1 equation vanishes at eta = 0 (the 3 rigid
translations). The scan starts at eta > 0, so both are excluded: every returned root is
positive and is an elastic mode (e.g. torsional n = 1 roots are the zeros of j_2, the first
being 5.7635).
"""
from __future__ import annotations

import logging
import math

import numpy as np
from scipy.optimize import brentq
from scipy.special import spherical_jn

log = logging.getLogger(__name__)

_STEP = 2e-3          # scan step in eta; smallest root spacing seen: 0.16 (n <= 20, eta <= 40)
_CHUNK = 10.0         # eta range scanned per pass when looking for `count` roots
_ETA_START = _STEP    # first grid point: excludes the rigid-body root eta = 0


def shear_to_longitudinal_speed_ratio(nu: float) -> float:
    """c_T / c_L = sqrt((1 - 2 nu) / (2 (1 - nu))) for Poisson ratio -1 < nu < 1/2."""
    if not -1.0 < nu < 0.5:
        raise ValueError(f"Poisson ratio must lie in (-1, 0.5), got {nu}")
    return math.sqrt((1.0 - 2.0 * nu) / (2.0 * (1.0 - nu)))


def _bessel_pair(n: int, x):
    """j_n(x), j_{n+1}(x) and their (positive) scale hypot(j_n, j_{n+1})."""
    jn, jn1 = spherical_jn(n, x), spherical_jn(n + 1, x)
    return jn, jn1, np.hypot(jn, jn1)


def torsional_equation(n: int, eta):
    """Scaled torsional frequency function ((n-1) j_n - eta j_{n+1}) / hypot(j_n, j_{n+1})."""
    jn, jn1, s = _bessel_pair(n, eta)
    return ((n - 1) * jn - eta * jn1) / s


def spheroidal_equation(n: int, nu: float, eta):
    """Scaled spheroidal frequency function of order n (see module docstring), no poles."""
    eta = np.asarray(eta, dtype=float)
    xi = eta * shear_to_longitudinal_speed_ratio(nu)
    jx, jx1, sx = _bessel_pair(n, xi)
    a11 = ((2 * n * (n - 1) - eta**2) * jx + 4 * xi * jx1) / sx
    if n == 0:
        return a11
    je, je1, se = _bessel_pair(n, eta)
    a12 = 2 * n * (n + 1) * ((n - 1) * je - eta * je1) / se
    a21 = 2 * ((n - 1) * jx - xi * jx1) / sx
    a22 = ((2 * (n * n - 1) - eta**2) * je + 2 * eta * je1) / se
    return a11 * a22 - a12 * a21


def _roots_in(f, lo: float, hi: float) -> list[float]:
    """Roots of f in (lo, hi]: sign changes on a grid of step _STEP, refined by brentq."""
    grid = np.arange(lo, hi + _STEP, _STEP)
    with np.errstate(invalid="ignore"):
        values = f(grid)
    # j_n underflows to 0 (0/0 in the scaling) only for eta << n, far below the lowest root
    # of order n (> 0.8 n): drop that leading stretch, refuse any other non-finite value
    finite = np.isfinite(values)
    first = int(np.argmax(finite)) if finite.any() else grid.size
    if not finite[first:].all():
        raise FloatingPointError(f"non-finite frequency function on [{lo}, {hi}]")
    grid, values = grid[first:], values[first:]
    roots = []
    for i in np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) <= 0):
        if values[i] == 0.0:
            roots.append(float(grid[i]))
        elif values[i + 1] != 0.0:
            roots.append(brentq(f, grid[i], grid[i + 1], xtol=1e-14, rtol=4 * np.finfo(float).eps))
    return roots


def _scan(f, count: int | None = None, eta_max: float | None = None) -> np.ndarray:
    """The first `count` positive roots of f, or all up to eta_max (whichever limit is given;
    both: the first `count` below eta_max)."""
    if count is None and eta_max is None:
        raise ValueError("give count or eta_max")
    roots: list[float] = []
    lo = _ETA_START
    while (count is None or len(roots) < count) and (eta_max is None or lo < eta_max):
        hi = lo + _CHUNK if eta_max is None else min(lo + _CHUNK, eta_max)
        for r in _roots_in(f, lo, hi):
            if (not roots or r > roots[-1] + _STEP / 2) and (eta_max is None or r <= eta_max):
                roots.append(r)
        lo = hi
    return np.array(roots[:count] if count is not None else roots)


def torsional_roots(n: int, count: int) -> np.ndarray:
    """First `count` roots eta = omega a / c_T of the torsional equation of order n >= 1
    ((n - 1) j_n(eta) = eta j_{n+1}(eta), Lamb 1882); the rigid rotation eta = 0 of n = 1
    is excluded. Independent of the Poisson ratio."""
    if n < 1:
        raise ValueError("torsional modes have order n >= 1")
    roots = _scan(lambda eta: torsional_equation(n, eta), count=count)
    log.debug("torsional n=%d roots %s", n, roots)
    return roots


def spheroidal_roots(n: int, nu: float, count: int) -> np.ndarray:
    """First `count` positive roots eta = omega a / c_T of the spheroidal equation of order
    n >= 0 (n = 0: breathing modes) for Poisson ratio nu; the rigid translation eta = 0 of
    n = 1 is excluded."""
    if n < 0:
        raise ValueError("spheroidal modes have order n >= 0")
    roots = _scan(lambda eta: spheroidal_equation(n, nu, eta), count=count)
    log.debug("spheroidal n=%d nu=%g roots %s", n, nu, roots)
    return roots


def _families_below(eta_max: float, nu: float) -> list[tuple[float, str, int]]:
    """(eta, class, n) of every mode family with eta <= eta_max.

    Orders are added until the lowest root of an order n >= 2 lies above eta_max: the
    fundamental root of each class grows with n from n = 2 on (it tends to the surface wave
    limit eta ~ (n + 1/2) c_R / c_T), so no higher order can contribute."""
    out: list[tuple[float, str, int]] = []
    for kind, first_n, equation in (
        ("torsional", 1, lambda n: (lambda eta: torsional_equation(n, eta))),
        ("spheroidal", 0, lambda n: (lambda eta: spheroidal_equation(n, nu, eta))),
    ):
        n = first_n
        while True:
            roots = _scan(equation(n), eta_max=eta_max)
            out += [(float(eta), kind, n) for eta in roots]
            if n >= 2 and roots.size == 0:
                break
            n += 1
    return out


def sphere_frequencies(radius: float, E: float, nu: float, rho: float,
                       f_max_hz: float | None = None,
                       count: int | None = None) -> list[tuple[float, str, int, int]]:
    """Elastic mode families of a free sphere, sorted by frequency:
    (frequency Hz, "torsional" | "spheroidal", order n, multiplicity 2n + 1).

    All families up to f_max_hz, or the lowest `count` families (both given: the lowest
    `count` up to f_max_hz). The 6 rigid-body modes (eta = 0) are excluded."""
    if f_max_hz is None and count is None:
        raise ValueError("give f_max_hz or count")
    c_t = math.sqrt(E / (2.0 * (1.0 + nu) * rho))
    to_hz = c_t / (2.0 * math.pi * radius)
    eta_max = f_max_hz / to_hz if f_max_hz is not None else 4.0
    while True:
        families = sorted(_families_below(eta_max, nu))
        if count is None or len(families) >= count or f_max_hz is not None:
            break
        eta_max *= 1.5
    families = families[:count] if count is not None else families
    log.debug("sphere a=%g m: %d families up to eta=%g", radius, len(families), eta_max)
    return [(eta * to_hz, kind, n, 2 * n + 1) for eta, kind, n in families]
