"""Circumferential harmonics of a displacement field: the nodal-diameter count of an
elastic mode of a body of revolution.

A mode of an axisymmetric (or cyclic) body varies around the axis as cos(n theta + phi);
n is its number of nodal diameters (Leissa, 1969, *Vibration of Plates*, NASA SP-160,
ch. 2: circular plates, modes with n nodal diameters and s nodal circles). Here n is the
harmonic holding the largest mean-square share of the displacement on a ring of points
around the axis, found by a least-squares Fourier fit (the points need not be evenly
spaced, as FE nodes never are).
"""
from __future__ import annotations

import numpy as np

#: Highest harmonic fitted (a ring of FE nodes resolves far more; higher counts are not
#: told apart from mesh noise in the few-mode band a drivetrain model keeps).
MAX_HARMONIC = 12
#: Points within this fraction of the largest radius form the outer ring.
RIM_FRACTION = 0.92


def fourier_fit(theta: np.ndarray, n_max: int = MAX_HARMONIC) -> np.ndarray:
    """Least-squares Fourier fit on the angles ``theta`` (rad) as an operator: the
    coefficients [a0, a_1..a_n, b_1..b_n] of a0 + sum a_n cos(n theta) + b_n sin(n theta)
    are ``fourier_fit(theta) @ values`` (the pseudo-inverse of the design matrix: one SVD
    per ring, reused for every field on it). ``n_max`` is lowered to what the points
    resolve (2 n_max + 1 < number of points)."""
    th = np.asarray(theta, float).ravel()
    n_max = int(min(n_max, (len(th) - 2) // 2))
    if n_max < 0:
        raise ValueError(f"need at least 2 points on the ring, got {len(th)}")
    n = np.arange(1, n_max + 1)
    A = np.hstack([np.ones((len(th), 1)), np.cos(np.outer(th, n)), np.sin(np.outer(th, n))])
    return np.linalg.pinv(A)


def harmonic_power(theta: np.ndarray, values: np.ndarray, n_max: int = MAX_HARMONIC,
                   fit: np.ndarray | None = None) -> np.ndarray:
    """Mean-square share of harmonics 0..n_max in ``values`` (n_points,) or (n_points, k)
    sampled at angles ``theta`` (rad): least-squares fit of a0 + sum a_n cos(n theta) +
    b_n sin(n theta), then a0^2 and (a_n^2 + b_n^2) / 2 summed over the k columns.
    ``n_max`` is lowered to what the points resolve (2 n_max + 1 < number of points).
    ``fit``: :func:`fourier_fit` of these ``theta`` and ``n_max``, when already formed."""
    th = np.asarray(theta, float).ravel()
    V = np.asarray(values, float).reshape(len(th), -1)
    P = fourier_fit(th, n_max) if fit is None else fit
    n_max = (P.shape[0] - 1) // 2
    c = P @ V
    p = np.empty(n_max + 1)
    p[0] = float((c[0] ** 2).sum())
    p[1:] = 0.5 * ((c[1:n_max + 1] ** 2).sum(axis=1) + (c[n_max + 1:] ** 2).sum(axis=1))
    return p


def dominant_harmonic(theta: np.ndarray, values: np.ndarray, n_max: int = MAX_HARMONIC,
                      fit: np.ndarray | None = None) -> int:
    """Harmonic number n (0..n_max) with the largest mean-square share of ``values``
    (``fit``: as in :func:`harmonic_power`)."""
    return int(np.argmax(harmonic_power(theta, values, n_max, fit)))


def cylindrical(points: np.ndarray, u: np.ndarray) -> tuple:
    """Angles (rad) of ``points`` (n, 3) about the z axis, and ``u`` (n, 3, ...) in
    (radial, tangential, axial) components."""
    th = np.arctan2(points[:, 1], points[:, 0])
    c, s = np.cos(th), np.sin(th)
    shape = (-1,) + (1,) * (u.ndim - 2)
    c, s = c.reshape(shape), s.reshape(shape)
    ur = c * u[:, 0] + s * u[:, 1]
    ut = -s * u[:, 0] + c * u[:, 1]
    return th, np.stack([ur, ut, u[:, 2]], axis=1)


def rim_nodes(points: np.ndarray, fraction: float = RIM_FRACTION) -> np.ndarray:
    """Indices of the points (n, 3; local axes, z = axis of revolution) within ``fraction``
    of the largest radius: the outer rim, where a body's elastic modes move most."""
    r = np.hypot(points[:, 0], points[:, 1])
    return np.flatnonzero(r >= fraction * r.max())


def body_nodal_diameters(body, zb: np.ndarray) -> int:
    """Nodal diameters of the elastic part of a flexible body's motion ``zb`` (body DOFs,
    (ndof,) or (ndof, k) for a group of repeated modes): the rigid-equivalent motion is
    removed, the rest back-expanded to the FE mesh, and the dominant harmonic of the
    (radial, tangential, axial) displacement on the outer rim returned."""
    rim, th, rot, fit = _rim_fit(body)
    z = np.asarray(zb, float).reshape(body.ndof, -1)
    Rl = body.rigid_local
    MR = body.M @ Rl
    ze = z - Rl @ np.linalg.solve(Rl.T @ MR, np.asarray(MR).T @ z)
    u = body.expand(ze, nodes=rim).reshape(-1, 3, z.shape[1])  # local axes
    c, s = rot
    ucyl = np.stack([c * u[:, 0] + s * u[:, 1], -s * u[:, 0] + c * u[:, 1], u[:, 2]], axis=1)
    return dominant_harmonic(th, ucyl.reshape(len(rim), -1), fit=fit)


def _rim_fit(body) -> tuple:
    """(rim node indices, their angles, (cos, sin) of them as columns, Fourier-fit
    operator) of a flexible body, formed once per body (kept in ``body.info``)."""
    key = "rim_fourier_fit"
    if body.info.get(key) is None:
        fe, _ = body.coupled()
        nodes = np.asarray(fe.nodes, float)
        rim = rim_nodes(nodes)
        th = np.arctan2(nodes[rim, 1], nodes[rim, 0])
        body.info[key] = (rim, th, (np.cos(th)[:, None], np.sin(th)[:, None]), fourier_fit(th))
    return body.info[key]
