"""Small 3-D geometry helpers on plain arrays (SI: metres, radians)."""
from __future__ import annotations

import numpy as np


def unit(v, name: str = "vector") -> np.ndarray:
    """Return ``v`` normalised; raise on a zero or non-finite vector. Scaled by its largest
    entry first, so no finite vector overflows (1e200) or underflows (1e-200) in the norm."""
    v = np.asarray(v, dtype=float)
    s = np.abs(v).max(initial=0.0)
    if not np.isfinite(s) or s == 0.0:
        raise ValueError(f"{name} must be a non-zero finite 3-vector, got {v.tolist()}")
    w = v / s
    return w / np.linalg.norm(w)


def skew(a) -> np.ndarray:
    """Cross-product matrix: ``skew(a) @ b == np.cross(a, b)``."""
    ax, ay, az = a
    return np.array([[0.0, -az, ay], [az, 0.0, -ax], [-ay, ax, 0.0]])


def axis_frame(axis) -> np.ndarray:
    """Right-handed orthonormal frame whose third column is ``axis``.

    The first column is the global x (or y, if the axis is close to x) projected onto the
    plane normal to the axis, so a body on the global z axis gets the identity frame.
    """
    e3 = unit(axis, "axis")
    ref = np.array([1.0, 0.0, 0.0]) if abs(e3[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = unit(ref - ref.dot(e3) * e3)
    e2 = np.cross(e3, e1)
    return np.column_stack([e1, e2, e3])


def rigid_transfer(point, origin) -> np.ndarray:
    """6x6 map from a rigid motion [u, theta] at ``origin`` to the motion at ``point``.

    Small rotations: u(point) = u + theta x (point - origin), theta unchanged.
    """
    P = np.eye(6)
    P[:3, 3:] = -skew(np.asarray(point, float) - np.asarray(origin, float))
    return P


def block_rotation(R: np.ndarray) -> np.ndarray:
    """6x6 block-diagonal rotation acting on [u, theta]."""
    T = np.zeros((6, 6))
    T[:3, :3] = R
    T[3:, 3:] = R
    return T
