"""The rotor's quasi-steady aerodynamics as plain functions on arrays (module notes of
:mod:`assembly.dynamics.rotor_surface` and :mod:`assembly.dynamics.rotor_aero`): written once,
called by :func:`assembly.dynamics.rotor_surface.rotor_loads`, by
:class:`assembly.dynamics.rotor_aero.RotorAero` (the Python step) and by the compiled step
(:mod:`assembly.dynamics.step_kernel`); compiled by numba when it is installed.

The surface comes in as its arrays (``tsr`` (n,), ``pitch`` (k,) rad, ``cq``, ``ct`` (n, k));
the rotor's parameters ``p`` and the state ``s`` of its accepted step are float arrays indexed
by the constants below. What depends on time alone -- the wind speed V(t) and the pitch
beta(t) -- comes in as numbers evaluated by the caller. A point the surface does not cover is
not an error here but a status (:data:`INSIDE` when it is covered), so that the compiled step
can stop on it and Python say why (:meth:`assembly.dynamics.rotor_aero.RotorAero.refuse`).
"""
from __future__ import annotations

import math

import numpy as np

from .jit import njit

#: the law's status: covered; radius, density or wind speed not a positive number; the tip-speed
#: ratio, the pitch outside the surface
INSIDE, NOT_POSITIVE, TSR_OUTSIDE, PITCH_OUTSIDE = 0, 1, 2, 3
#: the law's results (``out``): torque Q (N m), thrust T (N), tip-speed ratio, dQ/dOmega, dQ/dV,
#: dQ/dbeta, dT/dOmega, dT/dV
TORQUE, THRUST, TSR, DQ_DOMEGA, DQ_DWIND, DQ_DPITCH, DT_DOMEGA, DT_DWIND = range(8)
N_OUT = 8
#: parameters: radius (m), air density (kg/m^3), the rotor's turning sense on its row, 1.0 with
#: an axial (thrust) column
RADIUS, DENSITY, SENSE, AXIAL = range(4)
N_PARAMS = 4
#: state of the accepted step: wind speed, pitch, aerodynamic torque, thrust
WIND, PITCH, AERO_TORQUE, AERO_THRUST = range(4)
N_STATE = 4


@njit
def cell(grid, x):
    """(i, u): ``x`` lies in [grid[i], grid[i+1]] at fraction u (the last cell for the last
    point); i = -1 outside the grid (or x not a number)."""
    n = grid.shape[0]
    if not (grid[0] <= x <= grid[n - 1]):
        return -1, 0.0
    lo, hi = 0, n                                   # the first point above x: searchsorted "right"
    while lo < hi:
        mid = (lo + hi) // 2
        if grid[mid] <= x:
            lo = mid + 1
        else:
            hi = mid
    i = min(lo - 1, n - 2)
    return i, (x - grid[i]) / (grid[i + 1] - grid[i])


@njit
def bilinear(C, i, j, u, w, h, k):
    """(c, dc/dtsr, dc/dpitch): the bilinear interpolant of the table ``C`` in the cell (i, j) at
    fractions (u, w) of its sides h (tip-speed ratio) and k (pitch), and its slopes there."""
    c00, c01, c10, c11 = C[i, j], C[i, j + 1], C[i + 1, j], C[i + 1, j + 1]
    c = (1 - u) * (1 - w) * c00 + (1 - u) * w * c01 + u * (1 - w) * c10 + u * w * c11
    return c, ((1 - w) * (c10 - c00) + w * (c11 - c01)) / h, ((1 - u) * (c01 - c00) + u * (c11 - c10)) / k


@njit
def rotor_law(tsr, pitch, cq, ct, radius, density, wind, omega, beta, out):
    """The quasi-steady loads at wind speed ``wind`` (m/s), rotor speed ``omega`` (rad/s) and
    pitch ``beta`` (rad) into ``out`` (:data:`TORQUE` ...), from the Cq and Ct tables: Q = q R Cq,
    T = q Ct, q = rho pi R^2 V^2 / 2, lambda = Omega R / V (module notes of
    :mod:`assembly.dynamics.rotor_surface`). Returns the status (:data:`INSIDE` when covered;
    ``out`` is then written, else ``out[TSR]`` alone)."""
    if not (0.0 < radius < math.inf and 0.0 < density < math.inf and 0.0 < wind < math.inf):
        return NOT_POSITIVE
    lam = omega * radius / wind
    out[TSR] = lam
    i, u = cell(tsr, lam)
    if i < 0:
        return TSR_OUTSIDE
    j, w = cell(pitch, beta)
    if j < 0:
        return PITCH_OUTSIDE
    h, k = tsr[i + 1] - tsr[i], pitch[j + 1] - pitch[j]
    c_q, dcq_dtsr, dcq_dpitch = bilinear(cq, i, j, u, w, h, k)
    c_t, dct_dtsr, _ = bilinear(ct, i, j, u, w, h, k)
    qd = 0.5 * density * math.pi * (radius * radius) * (wind * wind)
    Q, T = qd * radius * c_q, qd * c_t
    dlam_domega, dlam_dwind = radius / wind, -lam / wind
    out[TORQUE], out[THRUST] = Q, T
    out[DQ_DOMEGA] = qd * radius * dcq_dtsr * dlam_domega
    out[DQ_DWIND] = 2 * Q / wind + qd * radius * dcq_dtsr * dlam_dwind      # d(q_dyn)/dV = 2 q_dyn / V
    out[DQ_DPITCH] = qd * radius * dcq_dpitch
    out[DT_DOMEGA] = qd * dct_dtsr * dlam_domega
    out[DT_DWIND] = 2 * T / wind + qd * dct_dtsr * dlam_dwind
    return INSIDE


@njit
def rotor_forces(p, tsr, pitch, cq, ct, wind, beta, xd, nu, dc, out):
    """(status, cross): the forces along the rotor's columns (module notes of
    :mod:`assembly.dynamics.rotor_aero`) into ``nu`` -- ``-sense Q`` on the rotation, ``-T`` on the
    axial column when ``p[AXIAL]`` -- and their speed tangents on the diagonal into ``dc``
    (``-dQ/dOmega``; the thrust's own is 0); ``cross`` = ``d nu_axial / d x'_rotation`` = ``-sense
    dT/dOmega`` (0 without an axial column). ``xd``: the columns' speeds; ``out``: the law's
    results. The status is the law's (nothing written unless :data:`INSIDE`)."""
    sense = p[SENSE]
    status = rotor_law(tsr, pitch, cq, ct, p[RADIUS], p[DENSITY], wind, sense * xd[0], beta, out)
    if status != INSIDE:
        return status, 0.0
    nu[0] = -sense * out[TORQUE]
    dc[0] = -out[DQ_DOMEGA]
    if p[AXIAL] == 0.0:
        return INSIDE, 0.0
    nu[1] = -out[THRUST]
    dc[1] = 0.0
    return INSIDE, -sense * out[DT_DOMEGA]


@njit
def rotor_commit(p, tsr, pitch, cq, ct, wind, beta, xd, s, out):
    """An accepted step: the wind speed, pitch and the loads at the step's speeds into the state
    ``s`` (the status of the law, covered at an accepted step)."""
    status = rotor_law(tsr, pitch, cq, ct, p[RADIUS], p[DENSITY], wind, p[SENSE] * xd[0], beta, out)
    s[WIND], s[PITCH], s[AERO_TORQUE], s[AERO_THRUST] = wind, beta, out[TORQUE], out[THRUST]
    return status


def parameters(radius: float, density: float, sense: float, axial: bool) -> np.ndarray:
    """The parameter array ``p``."""
    p = np.zeros(N_PARAMS)
    p[[RADIUS, DENSITY, SENSE, AXIAL]] = radius, density, sense, float(axial)
    return p
