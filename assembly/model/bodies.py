"""Body models: the DOFs a body brings to the assembly and how its points move.

A rigid body carries six absolute DOFs [ux, uy, uz, rx, ry, rz] (m, rad; global axes) at
its centre of mass. The torsional fidelity is *not* a separate model: it is this rigid
body with five DOFs constrained (see :mod:`assembly.model.constraints`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..mechanics.kinematics import axis_frame, rigid_transfer

ABS_DOF_NAMES = ("ux", "uy", "uz", "rx", "ry", "rz")


@dataclass(frozen=True)
class RigidBodyModel:
    """Rigid body: mass (kg), inertia about its centre of mass (kg m^2, global axes)."""

    name: str
    position: np.ndarray
    axes: np.ndarray
    mass: float
    inertia: np.ndarray
    axis_point: np.ndarray = None  # a point of the rotation axis (default: the COM)

    ndof = 6
    flexible = False

    def __post_init__(self):
        if self.axis_point is None:
            object.__setattr__(self, "axis_point", np.asarray(self.position, float))

    @classmethod
    def from_body(cls, body) -> "RigidBodyModel":
        R = axis_frame(body.axis)
        J = R @ body.inertia_local() @ R.T
        return cls(body.name, np.asarray(body.position, float), R, float(body.mass), J)

    def mass_matrix(self) -> np.ndarray:
        M = np.zeros((6, 6))
        M[:3, :3] = self.mass * np.eye(3)
        M[3:, 3:] = self.inertia
        return M

    def stiffness_matrix(self) -> np.ndarray:
        return np.zeros((6, 6))

    @classmethod
    def from_mass_properties(cls, name, position, axes, mass, inertia, axis_point=None) -> "RigidBodyModel":
        """A rigid body of given mass properties whose rotation axis passes through
        ``axis_point`` (e.g. a component's geometric axis; its mesh COM may sit a few
        micrometres off that axis)."""
        return cls(name, np.asarray(position, float), axes, float(mass), np.asarray(inertia, float),
                   None if axis_point is None else np.asarray(axis_point, float))

    def motion_at(self, point, interface=None) -> np.ndarray:
        """6 x 6 map from the body's DOFs to the motion [u, theta] at ``point``."""
        return rigid_transfer(point, self.position)

    def rigid_projection(self) -> np.ndarray:
        return np.eye(6)

    def rigid_motion(self, zb: np.ndarray) -> np.ndarray:
        return zb

    def dof_names(self) -> list[str]:
        return [f"{self.name}.{d}" for d in ABS_DOF_NAMES]
