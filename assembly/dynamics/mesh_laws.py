"""The forces of nonlinear gear meshes as plain functions (module notes of
:mod:`assembly.dynamics.mesh_contact` and :mod:`assembly.dynamics.mesh_variation`): written
once, compiled by numba when it is installed (:mod:`assembly.dynamics.jit`) and called mesh
by mesh with numbers by the compiled step (:mod:`assembly.dynamics.step_kernel`) and by
:class:`assembly.dynamics.mesh_contact.Meshes`; without numba, the same functions take every
mesh at once as numpy arrays (their bodies are arithmetic that reads either way).

Parameters of a mesh (or (m,) arrays of them): ``k0`` mean stiffness (N/m), ``c`` contact
damper (N s/m), ``phase`` (rad), ``lin`` 1.0 without backlash (0.0 with), ``gap`` its backlash
(m; 0 without); its series ``f = 1 + sum_h a_h cos(h phi + p_h)`` by ``a`` (H,) and the
cosines and sines of its phases ``cp``, ``sp`` (H,) -- or, for every mesh at once, the
transposes (H, m) of those tables. The harmonics come from cos phi, sin phi by the angle-sum
recurrence (two trigonometric calls a mesh).
"""
from __future__ import annotations

import numpy as np

from .jit import njit


@njit
def mesh_law(delta, ddot, phi, k0, c, a, cp, sp, lin, gap):
    """(contact force along the line of action N, k N/m, contact slope s, flank compression e,
    f'(phi), f''(phi)) at compression ``delta`` (m), its rate ``ddot`` and angle ``phi``."""
    c1, s1 = np.cos(phi), np.sin(phi)
    ch, sh = c1, s1                                     # cos(h phi), sin(h phi) at h = 1
    f, df, d2f = 0.0 * phi, 0.0 * phi, 0.0 * phi
    for j in range(len(a)):
        h = j + 1.0
        cj = ch * cp[j] - sh * sp[j]                    # cos(h phi + p_h)
        sj = sh * cp[j] + ch * sp[j]                    # sin(h phi + p_h)
        f = f + a[j] * cj
        df = df - h * a[j] * sj
        d2f = d2f - h * h * a[j] * cj
        ch, sh = ch * c1 - sh * s1, sh * c1 + ch * s1
    f = 1.0 + f
    e = lin * delta + (1.0 - lin) * (np.maximum(delta, 0.0) + np.minimum(delta + gap, 0.0))
    s = np.maximum(lin, 1.0 * (delta >= 0.0) + 1.0 * (delta < -gap))
    k = k0 * f
    return k * e + c * s * ddot, k, s, e, df, d2f


@njit
def mesh_into(i, m, x, xd, k0, c, a, cp, sp, phase, lin, gap, con, gap_slope, nu, Kt, dc, scale, force, slope):
    """Mesh ``i`` (or the meshes of an index array ``i``) of m: its corrections nu along (g,
    r) to the linear model's mean spring and damper into ``nu[i]``, ``nu[m + i]``; their
    tangents d nu / d x into ``Kt`` (the 2 x 2 block of rows and columns i, m + i), d nu / d x'
    into ``dc`` (diagonal); the size of the terms nu[i] sums into ``scale``; the contact force
    and slope into ``force``, ``slope``. ``con`` 1.0 with the energy-consistent term, 0.0
    without; ``gap_slope``: the least contact slope a tangent uses."""
    delta, ddot = x[i], xd[i]
    frc, k, s, e, df, d2f = mesh_law(delta, ddot, x[m + i] - phase, k0, c, a, cp, sp, lin, gap)
    kdf = k0 * df
    nu[i] = frc - k0 * delta - c * ddot
    nu[m + i] = con * 0.5 * kdf * e * e
    scale[i] = np.abs(k * e) + np.abs(c * s * ddot) + np.abs(k0 * delta) + np.abs(c * ddot)
    scale[m + i] = np.abs(nu[m + i])
    dc[i] = c * (s - 1.0)
    dc[m + i] = 0.0
    Kt[i, i] = k * np.maximum(s, gap_slope) - k0
    Kt[i, m + i] = kdf * e                              # d nu_g / d angle
    Kt[m + i, i] = con * kdf * e * s                    # d nu_r / d delta (a potential's Hessian)
    Kt[m + i, m + i] = con * 0.5 * k0 * d2f * e * e
    force[i] = frc
    slope[i] = s


@njit
def mesh_forces(x, xd, k0, c, A, cP, sP, phase, lin, gap, con, gap_slope, nu, Kt, dc, scale, force, slope):
    """:func:`mesh_into` of every mesh, one at a time (``A``, ``cP``, ``sP``: (m, H)); the
    rest of the upper-left 2m x 2m block of ``Kt`` zero."""
    m = k0.shape[0]
    Kt[:2 * m, :2 * m] = 0.0
    for i in range(m):
        mesh_into(i, m, x, xd, k0[i], c[i], A[i], cP[i], sP[i], phase[i], lin[i], gap[i], con, gap_slope, nu, Kt,
                  dc, scale, force, slope)


def every_mesh(x, xd, k0, c, A, cP, sP, phase, lin, gap, con, gap_slope, nu, Kt, dc, scale, force, slope):
    """:func:`mesh_forces` with numpy arrays, every mesh at once (numba absent)."""
    m = k0.shape[0]
    Kt[:2 * m, :2 * m] = 0.0
    getattr(mesh_into, "py_func", mesh_into)(np.arange(m), m, x, xd, k0, c, A.T, cP.T, sP.T, phase, lin, gap, con,
                                             gap_slope, nu, Kt, dc, scale, force, slope)


@njit
def mesh_commit(contact, losses, slope):
    """An accepted step: a mesh in contact whose slope is now 0 lost it (a count in ``losses``)."""
    for i in range(contact.shape[0]):
        touching = slope[i] > 0.0
        if contact[i] and not touching:
            losses[i] += 1
        contact[i] = touching


def series_at(phi, A, P):
    """``f``, ``f'``, ``f''`` at angles ``phi`` (n,) of series of amplitudes and phases ``A``,
    ``P`` (n, H) (numpy arrays; :func:`mesh_law` at unit stiffness)."""
    phi = np.asarray(phi, float)
    _, f, _, _, df, d2f = getattr(mesh_law, "py_func", mesh_law)(
        0.0 * phi, 0.0 * phi, phi, 1.0, 0.0, np.asarray(A).T, np.cos(P).T, np.sin(P).T, 1.0, 0.0)
    return f, df, d2f


def flank(delta, lin, gap):
    """(e, s): the flank compression and contact slope of compressions ``delta`` (numpy arrays;
    :func:`mesh_law`'s dead zone)."""
    delta = np.asarray(delta, float)
    _, _, s, e, _, _ = getattr(mesh_law, "py_func", mesh_law)(delta, 0.0 * delta, 0.0 * delta, 0.0, 0.0,
                                                              np.zeros((0,) + delta.shape), None, None, lin, gap)
    return e, s
