"""The rotor's quasi-steady aerodynamic torque as a nonlinear force of the time step: ``Q(Omega,
V(t), beta(t))`` from the performance surface (:mod:`assembly.dynamics.rotor_surface`) on the
rotor's rotation row, its speed tangent ``dQ/dOmega`` in Newton's matrix -- so the aerodynamic
damping ``-dQ/dOmega`` acts through the surface's own slope, never added by hand.

In the balance ``M q'' + C q' + K q + U nu = f`` of :mod:`assembly.dynamics.transient` a driving
torque enters as ``nu = -sense Q`` along the rotor's row ``u`` (``sense`` = +1 when the rotor
turns in the row's positive sense), with ``d nu / d q' = -dQ/dOmega`` (u' q' = sense Omega);
the thrust, when an axial row is given, as ``nu = -T`` along it (the quasi-steady thrust reads
the rotor's speed, not its axial motion: the rotor's axial velocity relative to the wind is
left out).
The Python step runs it (the compiled step knows the meshes and shaft torques only).
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from ..errors import SceneError
from .rotor_surface import RotorSurface, rotor_loads
from .transient import Nonlinear


class RotorAero(Nonlinear):
    """The aerodynamic torque on the row ``u`` (n,) of the rotor's rotation (module notes) and,
    given ``axial`` (n,), the thrust along that row (the rotor's axial translation, positive
    downwind): ``surface``, ``radius`` (m), ``density`` (kg/m^3), ``wind(t)`` (m/s) and
    ``pitch(t)`` (rad) the rotor-effective wind speed and the collective pitch; ``sense`` the
    rotor's turning sense on ``u``. :attr:`last` holds the last
    :class:`assembly.dynamics.rotor_surface.RotorLoads`; :attr:`state` the wind speed, pitch
    and loads of the last accepted step."""

    def __init__(self, u, surface: RotorSurface, radius: float, density: float, wind: Callable[[float], float],
                 pitch: Callable[[float], float], sense: float = 1.0, axial=None):
        cols = [np.asarray(u, float).ravel()] + ([] if axial is None else [np.asarray(axial, float).ravel()])
        self.U = np.column_stack(cols)
        self.surface, self.radius, self.density = surface, radius, density
        self.wind, self.pitch, self.sense = wind, pitch, float(sense)
        self.last = self.state = None

    def loads(self, t: float, xd: np.ndarray):
        wind, omega, pitch = float(self.wind(t)), self.sense * float(xd[0]), float(self.pitch(t))
        try:
            return rotor_loads(self.surface, self.radius, self.density, wind, omega, pitch)
        except SceneError as exc:                   # the state left the surface: name the table
            raise SceneError("turbine.surface", self.surface.source,
                             f"does not cover the rotor at t = {t:.6g} s (wind {wind:.4g} m/s, rotor speed "
                             f"{omega:.4g} rad/s, pitch {pitch:.4g} rad): {exc.path} {exc.value:.4g} {exc.reason}") \
                from None

    def commit(self, t, x, xd):
        self.state = (float(self.wind(t)), float(self.pitch(t)), self.loads(t, xd))

    def forces(self, t, x, xd):
        ld = self.loads(t, xd)
        self.last = ld
        if self.U.shape[1] == 1:
            return np.array([-self.sense * ld.torque]), np.zeros(1), np.array([-ld.dq_domega])
        # the thrust depends on the rotor's speed too: d nu_thrust / d x'_rotation = -sense dT/dOmega
        dc = np.array([[-ld.dq_domega, 0.0], [-self.sense * ld.dt_domega, 0.0]])
        return np.array([-self.sense * ld.torque, -ld.thrust]), np.zeros((2, 2)), dc

    def force_scale(self, nu):
        return np.abs(nu)
