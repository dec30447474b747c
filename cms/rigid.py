"""Rigid-body motion vectors and naming of free motions.

DOF layout convention (shared with scikit-fem's ``ElementVector``):
a DOF is described by the point it lives at and its *kind*:
0, 1, 2 = translation x, y, z (m); 3, 4, 5 = rotation about x, y, z (rad).
Plain solid nodes carry kinds 0, 1, 2 in the order ``3*node + xyz``; 6-DOF
master nodes (RBE2/RBE3 couplings) carry kinds 0..5.

The rigid-body basis ``R`` (n x 6) has columns
[translation x, translation y, translation z, rotation about x, y, z] about
``reference`` (default: the origin), for unit translation (1 m) / unit small
rotation (1 rad).
"""
from __future__ import annotations

import numpy as np

MOTION_NAMES = ("translation x", "translation y", "translation z",
                "rotation about x", "rotation about y", "rotation about z")


def solid_dof_layout(node_coords: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(dof_points, dof_kinds) for 3 translational DOFs per node, order 3*node + xyz."""
    X = np.asarray(node_coords, dtype=float).reshape(-1, 3)
    return np.repeat(X, 3, axis=0), np.tile(np.arange(3), len(X))


def master_dof_layout(master_coords: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(dof_points, dof_kinds) for 6-DOF master nodes [ux, uy, uz, rx, ry, rz]."""
    X = np.asarray(master_coords, dtype=float).reshape(-1, 3)
    return np.repeat(X, 6, axis=0), np.tile(np.arange(6), len(X))


def rigid_body_basis(dof_points: np.ndarray, dof_kinds: np.ndarray,
                     reference=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Rigid-body basis R (n x 6) for DOFs at ``dof_points`` with ``dof_kinds``.

    Column j < 3: unit translation along axis j. Column 3 + j: unit small
    rotation theta e_j about ``reference``, u = e_j x (p - reference).
    """
    P = np.asarray(dof_points, dtype=float) - np.asarray(reference, dtype=float)
    kinds = np.asarray(dof_kinds, dtype=int)
    n = len(kinds)
    R = np.zeros((n, 6))
    t = kinds < 3
    R[np.flatnonzero(t), kinds[t]] = 1.0
    r = ~t
    R[np.flatnonzero(r), kinds[r]] = 1.0  # rotational DOF follows rotation kind-3 -> column kind
    eye = np.eye(3)
    for j in range(3):
        u = np.cross(eye[j], P)              # (n, 3) displacement of each DOF's point
        R[np.flatnonzero(t), 3 + j] = u[np.flatnonzero(t), kinds[t]]
    return R


def describe_motion(c: np.ndarray, length_scale: float = 1.0) -> str:
    """Human-readable name of the rigid motion with coefficients ``c`` (6,).

    A motion with a rotation part omega is named as a rotation about the axis
    omega / |omega| through the point a = omega x t / |omega|^2 (plus a
    translation along the axis, if any).
    """
    c = np.asarray(c, dtype=float)
    t, w = c[:3], c[3:]
    wn = np.linalg.norm(w)
    if wn * length_scale < 1e-8 * max(np.linalg.norm(t), 1e-300):
        d = t / np.linalg.norm(t)
        return _single(d, "translation") or "translation along (%.3g, %.3g, %.3g)" % tuple(d)
    axis = w / wn
    if axis[np.argmax(np.abs(axis))] < 0:
        axis, w, t = -axis, -w, -t
    a = np.cross(w, t) / wn ** 2
    pitch = float(axis @ t) / wn     # translation along the axis per unit rotation (m/rad)
    name = _single(axis, "rotation") or "rotation about axis (%.3g, %.3g, %.3g)" % tuple(axis)
    name += " through point (%.4g, %.4g, %.4g) m" % tuple(a)
    if abs(pitch) > 1e-8 * length_scale:
        name += " with %.4g m/rad translation along the axis" % pitch
    return name


def _single(d, what):
    k = int(np.argmax(np.abs(d)))
    if abs(abs(d[k]) - 1.0) < 1e-8:
        return f"{what} {'about ' if what == 'rotation' else ''}{'xyz'[k]}"
    return None


def free_rigid_motions(R: np.ndarray, boundary_dofs: np.ndarray,
                       length_scale: float = 1.0, rtol: float = 1e-9) -> np.ndarray:
    """Rigid motions (6-vectors, columns) that leave every boundary DOF at rest.

    These make K_ii singular. ``length_scale`` (m) balances translation and
    rotation columns; ``rtol`` is the relative singular-value threshold.
    Returns an array (6, m), m = number of free motions (0 if fully held).
    """
    S = np.diag([1, 1, 1, length_scale, length_scale, length_scale]).astype(float)
    if len(boundary_dofs) == 0:
        return np.eye(6)
    Rb = R[np.asarray(boundary_dofs, dtype=int)] @ np.linalg.inv(S)
    _, s, Vt = np.linalg.svd(Rb, full_matrices=True)
    s_full = np.zeros(6)
    s_full[:len(s)] = s
    smax = max(s_full.max(), 1e-300)
    null = Vt[(s_full / smax) <= rtol].T
    return np.linalg.inv(S) @ null
