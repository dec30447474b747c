"""A part's own frame in its file: the file's rotation axis and a point on it, mapped onto the
component's local z axis and origin (numpy only; m).

Every component turns about its local z. A part modelled about another axis of its file
names it (``axis``, a direction in the file's axes) and a point of that axis (``origin``, m
after the unit conversion, the file's axes); the part is then read in the frame whose z is
``axis`` and whose origin is ``origin``, with x and y by :func:`axis_frame` -- the convention
of a scene body's local axes, so a part drawn in an assembly's axes and a body given the same
``axis`` and ``position = origin`` sit where they were drawn. A file point ``x`` is at local
``R^T (x - origin)``; ``R = axis_frame(axis)``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def unit_vector(v, name: str = "vector") -> np.ndarray:
    """``v`` normalised (scaled by its largest entry first, so no finite vector overflows
    (1e200) or underflows (1e-200) in the norm); ValueError naming ``name`` on a zero or
    non-finite vector."""
    v = np.asarray(v, dtype=float)
    s = np.abs(v).max(initial=0.0)
    if not np.isfinite(s) or s == 0.0:
        raise ValueError(f"{name} must be a non-zero finite 3-vector, got {v.tolist()}")
    w = v / s
    return w / np.linalg.norm(w)


def axis_frame(axis) -> np.ndarray:
    """Right-handed orthonormal frame (columns x, y, z) whose z is ``axis``: x is the x axis
    (or y, when ``axis`` is within 26 deg of x) made normal to ``axis``, y = z cross x. The
    z axis gives the identity."""
    e3 = unit_vector(axis, "axis")
    ref = np.array([1.0, 0.0, 0.0]) if abs(e3[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = unit_vector(ref - ref.dot(e3) * e3)
    return np.column_stack([e1, np.cross(e3, e1), e3])


@dataclass(frozen=True)
class PartFrame:
    """The part's local frame in its file: ``R`` (columns: local x, y, z in the file's axes)
    and ``origin`` (m, the file's axes)."""

    R: np.ndarray
    origin: np.ndarray

    @classmethod
    def of(cls, axis=(0.0, 0.0, 1.0), origin=(0.0, 0.0, 0.0)) -> "PartFrame":
        return cls(axis_frame(axis), np.asarray(origin, float))

    @property
    def is_identity(self) -> bool:
        return bool(np.array_equal(self.R, np.eye(3)) and not self.origin.any())

    def points(self, x) -> np.ndarray:
        """Points (..., 3) of the file (m) in the local frame (exactly ``x`` for the identity)."""
        x = np.asarray(x, float)
        return x if self.is_identity else (x - self.origin) @ self.R

    def tensor(self, J) -> np.ndarray:
        """A second-order tensor (3, 3) of the file's axes in the local axes, ``R^T J R``."""
        J = np.asarray(J, float)
        return J if self.is_identity else self.R.T @ J @ self.R

    def affine(self, scale: float = 1.0) -> list:
        """gmsh's ``affineTransform`` (3 x 4, row by row) taking file points in model units
        (``scale`` m each) to local metres: ``R^T (scale x - origin)``."""
        A = scale * self.R.T
        t = -self.R.T @ self.origin if self.origin.any() else np.zeros(3)
        return np.hstack([A, t[:, None]]).ravel().tolist()
