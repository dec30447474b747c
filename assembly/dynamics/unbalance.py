"""An unbalance: a mass ``m`` at radius ``e`` and phase ``phi0`` on a rotating body, as a force
locked to the body's integrated rotation (Park et al.'s eccentricity; the unbalance response of
ROSS's time runs).

With the body's rotation ``theta`` (its row's coordinate, integrated by the time step, so the
force follows the body's own speed changes) the mass sits at ``e (cos psi, sin psi)``, ``psi =
theta + phi0``, in the body's plane (its two translation rows ``x``, ``y`` normal to the spin
axis); accelerating it takes ``m e (-theta'^2 (cos, sin) + theta'' (-sin, cos))``, and it pushes
the body the other way:

    F_x = m e (theta'^2 cos psi + theta'' sin psi),  F_y = m e (theta'^2 sin psi - theta'' cos psi).

The centripetal part is exact at every Newton iterate (its tangents in ``theta`` and
``theta'`` go to Newton's matrix); the tangential (Euler) part uses the last accepted step's
angular acceleration (explicit; zero at constant speed). The mass's own translation inertia is
the body's (include it in the body's mass), and its torque about the spin axis (``m e`` times
the body's translational acceleration across the arm) is left out: the spin is the
drivetrain's. In the balance ``M q'' + ... + U nu = f`` of :mod:`assembly.dynamics.transient`,
``nu = -(F_x, F_y, 0)`` along the columns ``(x, y, theta)``.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import SceneError
from .transient import Nonlinear


class Unbalance(Nonlinear):
    """The unbalance of the module notes on the rows ``x``, ``y`` (translations normal to the spin
    axis) and ``theta`` (the rotation) of an ``n``-coordinate model -- each a coordinate's index or
    a row (n,) on q -- ``mass`` (kg), ``radius`` (m), ``phase`` (rad); ``dt`` the run's step (for
    the tangential term's acceleration)."""

    def __init__(self, n: int, x, y, theta, mass: float, radius: float, phase: float, dt: float):
        for name, v in (("mass", mass), ("radius", radius)):
            if not (math.isfinite(v) and v >= 0.0):
                raise SceneError(f"unbalance.{name}", v, "must be a number >= 0")
        self.U = np.zeros((n, 3))
        for j, row in enumerate((x, y, theta)):
            if np.ndim(row) == 0:
                self.U[int(row), j] = 1.0
            else:
                self.U[:, j] = np.asarray(row, float).ravel()
        self.me, self.phase, self.dt = mass * radius, phase, dt
        self.alpha, self._w = 0.0, None

    def forces(self, t, x, xd):
        psi, w, a = x[2] + self.phase, xd[2], self.alpha
        c, s = math.cos(psi), math.sin(psi)
        me = self.me
        nu = -me * np.array([w * w * c + a * s, w * w * s - a * c, 0.0])
        dk = np.zeros((3, 3))
        dk[0, 2] = -me * (-w * w * s + a * c)                 # d nu / d theta
        dk[1, 2] = -me * (w * w * c + a * s)
        dc = np.zeros((3, 3))
        dc[0, 2], dc[1, 2] = -me * 2 * w * c, -me * 2 * w * s   # d nu / d theta'
        return nu, dk, dc

    def commit(self, t, x, xd):
        w = float(xd[2])
        if self._w is not None:
            self.alpha = (w - self._w) / self.dt
        self._w = w
