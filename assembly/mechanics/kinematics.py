"""Small 3-D geometry helpers on plain arrays (SI: metres, radians)."""
from __future__ import annotations

import numpy as np

# re-exported: a body's local axes (x_global = position + axis_frame(axis) @ x_local) are the
# frame a user's part is read in from its file, one definition for both
from fe_components.part.frame import axis_frame  # noqa: F401
from fe_components.part.frame import unit_vector as unit


def skew(a) -> np.ndarray:
    """Cross-product matrix: ``skew(a) @ b == np.cross(a, b)``."""
    ax, ay, az = a
    return np.array([[0.0, -az, ay], [az, 0.0, -ax], [-ay, ax, 0.0]])


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
