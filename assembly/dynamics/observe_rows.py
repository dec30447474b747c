"""What a time-domain run records at each step, as rows on its state: ``Ok q + Oc v`` (a
nonlinear mesh's force, ``swap`` (row, mesh): its contact force plus ``Os v``), then ``Oa a``
and ``Sv v`` -- arrays that the Python step and the compiled step
(:mod:`assembly.dynamics.step_kernel`) read alike.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class Rows:
    """The recorded rows (module notes); ``meshes``: the run's
    :class:`assembly.dynamics.mesh_contact.Meshes` whose ``last_force`` the swaps read (None
    without swaps). Called as ``observe(q, v, a, nu)``."""

    Ok: np.ndarray
    Oc: np.ndarray
    Oa: np.ndarray
    Sv: np.ndarray
    Os: np.ndarray | None = None
    swap: tuple = ()
    meshes: object = None

    @property
    def size(self) -> int:
        return self.Ok.shape[0] + self.Oa.shape[0] + self.Sv.shape[0]

    def __call__(self, q, v, a, nu):
        y = self.Ok @ q + self.Oc @ v
        for i, j in self.swap:
            y[i] = self.meshes.last_force[j] + self.Os[i] @ v
        return np.concatenate([y, self.Oa @ a, self.Sv @ v])


def state_rows(n: int, q=True, v=False, a=False) -> Rows:
    """Rows recording the coordinates, velocities and accelerations asked for (in that order)
    of a model of ``n`` coordinates."""
    eye, none = np.eye(n), np.zeros((0, n))
    return Rows(eye if q else none, np.zeros((n, n)) if q else none, eye if a else none, eye if v else none)
