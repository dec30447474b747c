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


def harmonic_power(theta: np.ndarray, values: np.ndarray, n_max: int = MAX_HARMONIC) -> np.ndarray:
    """Mean-square share of harmonics 0..n_max in ``values`` (n_points,) or (n_points, k)
    sampled at angles ``theta`` (rad): least-squares fit of a0 + sum a_n cos(n theta) +
    b_n sin(n theta), then a0^2 and (a_n^2 + b_n^2) / 2 summed over the k columns.
    ``n_max`` is lowered to what the points resolve (2 n_max + 1 < number of points)."""
    th = np.asarray(theta, float).ravel()
    V = np.asarray(values, float).reshape(len(th), -1)
    n_max = int(min(n_max, (len(th) - 2) // 2))
    if n_max < 0:
        raise ValueError(f"need at least 2 points on the ring, got {len(th)}")
    n = np.arange(1, n_max + 1)
    A = np.hstack([np.ones((len(th), 1)), np.cos(np.outer(th, n)), np.sin(np.outer(th, n))])
    c, *_ = np.linalg.lstsq(A, V, rcond=None)
    p = np.empty(n_max + 1)
    p[0] = float((c[0] ** 2).sum())
    p[1:] = 0.5 * ((c[1:n_max + 1] ** 2).sum(axis=1) + (c[n_max + 1:] ** 2).sum(axis=1))
    return p


def dominant_harmonic(theta: np.ndarray, values: np.ndarray, n_max: int = MAX_HARMONIC) -> int:
    """Harmonic number n (0..n_max) with the largest mean-square share of ``values``."""
    return int(np.argmax(harmonic_power(theta, values, n_max)))


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
    fe, _ = body.coupled()
    key = "_rim_nodes"
    if body.info.get(key) is None:
        body.info[key] = rim_nodes(np.asarray(fe.nodes, float))
    rim = body.info[key]
    z = np.asarray(zb, float).reshape(body.ndof, -1)
    Rl = body.rigid_local
    MR = body.M @ Rl
    ze = z - Rl @ np.linalg.solve(Rl.T @ MR, np.asarray(MR).T @ z)
    u = body.expand(ze).reshape(-1, 3, z.shape[1])[rim]  # local axes
    th, ucyl = cylindrical(np.asarray(fe.nodes, float)[rim], u)
    return dominant_harmonic(th, ucyl.reshape(len(rim), -1))
