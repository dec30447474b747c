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

The law is :mod:`assembly.dynamics.rotor_laws` (plain functions on arrays), which the Python
step calls through :meth:`RotorAero.forces` and the compiled step
(:mod:`assembly.dynamics.step_kernel`) calls itself, with the wind speed and pitch at the steps'
times that Python evaluates for its stretch (:meth:`RotorAero.inputs`); a state the surface does
not cover stops either step with the same refusal naming ``turbine.surface``
(:meth:`RotorAero.refuse`).
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from ..errors import SceneError
from .jit import pick
from .rotor_laws import (
    AERO_THRUST,
    AERO_TORQUE,
    N_OUT,
    N_STATE,
    PITCH,
    WIND,
    parameters,
    rotor_commit,
    rotor_forces,
)
from .rotor_surface import RotorSurface, rotor_loads, surface_arrays
from .transient import Nonlinear
from .wind import WindSeries


class RotorAero(Nonlinear):
    """The aerodynamic torque on the row ``u`` (n,) of the rotor's rotation (module notes) and,
    given ``axial`` (n,), the thrust along that row (the rotor's axial translation, positive
    downwind): ``surface``, ``radius`` (m), ``density`` (kg/m^3), ``wind(t)`` (m/s) and
    ``pitch(t)`` (rad) the rotor-effective wind speed and the collective pitch; ``sense`` the
    rotor's turning sense on ``u``. Parameters ``p``, the surface's ``tables`` and the state
    ``s`` (wind speed, pitch, aerodynamic torque and thrust of the last accepted step): the
    arrays of :mod:`assembly.dynamics.rotor_laws`."""

    compiled = "rotor"                      # the compiled step knows this law

    def __init__(self, u, surface: RotorSurface, radius: float, density: float, wind: Callable[[float], float],
                 pitch: Callable[[float], float], sense: float = 1.0, axial=None):
        cols = [np.asarray(u, float).ravel()] + ([] if axial is None else [np.asarray(axial, float).ravel()])
        self.U = np.column_stack(cols)
        self.surface, self.radius, self.density = surface, radius, density
        self.wind, self.pitch, self.sense = wind, pitch, float(sense)
        self.p = parameters(radius, density, self.sense, axial is not None)
        self.tables = surface_arrays(surface)
        self.s, self.out = np.zeros(N_STATE), np.zeros(N_OUT)

    def loads(self, t: float, xd: np.ndarray):
        """The :class:`assembly.dynamics.rotor_surface.RotorLoads` at ``t`` and the rotor row's
        speed ``xd[0]``; SceneError naming ``turbine.surface`` where the surface does not cover
        the rotor."""
        wind, omega, pitch = float(self.wind(t)), self.sense * float(xd[0]), float(self.pitch(t))
        try:
            return rotor_loads(self.surface, self.radius, self.density, wind, omega, pitch)
        except SceneError as exc:                   # the state left the surface: name the table
            raise SceneError("turbine.surface", self.surface.source,
                             f"does not cover the rotor at t = {t:.6g} s (wind {wind:.4g} m/s, rotor speed "
                             f"{omega:.4g} rad/s, pitch {pitch:.4g} rad): {exc.path} {exc.value:.4g} {exc.reason}") \
                from None

    def refuse(self, t: float, speed: float):
        """Raise the refusal of a step whose law had no answer at ``t`` with the rotor row's speed
        ``speed`` (the SceneError of :meth:`loads`, naming ``turbine.surface``)."""
        self.loads(t, np.array([speed]))
        raise SceneError("turbine.surface", self.surface.source, f"does not cover the rotor at t = {t:.6g} s "
                                                                 f"(rotor row's speed {speed:.4g})")

    def inputs(self, t: np.ndarray):
        """(wind speeds, pitches) at the times ``t`` (arrays): what the law reads at those steps,
        the numbers :meth:`forces` reads at each (a wind series on the array at once: the same
        interpolation element by element; the pitch time by time)."""
        wind = self.wind(t) if isinstance(self.wind, WindSeries) else [float(self.wind(x)) for x in t]
        return np.asarray(wind, float).reshape(len(t)), np.array([float(self.pitch(x)) for x in t])

    def commit(self, t, x, xd):
        pick(rotor_commit)(self.p, *self.tables, float(self.wind(t)), float(self.pitch(t)), xd, self.s, self.out)

    def forces(self, t, x, xd):
        m = self.U.shape[1]
        nu, dc = np.zeros(m), np.zeros(m)
        status, cross = pick(rotor_forces)(self.p, *self.tables, float(self.wind(t)), float(self.pitch(t)), xd, nu,
                                           dc, self.out)
        if status:
            self.refuse(t, float(xd[0]))
        if m == 1:
            return nu, np.zeros(1), dc
        # the thrust depends on the rotor's speed too: d nu_thrust / d x'_rotation = -sense dT/dOmega
        return nu, np.zeros((2, 2)), np.array([[dc[0], 0.0], [cross, dc[1]]])

    @property
    def state(self) -> dict:
        """The wind speed (m/s), pitch (rad), aerodynamic torque (N m) and thrust (N) of the last
        accepted step."""
        s = self.s
        return {"wind": float(s[WIND]), "pitch": float(s[PITCH]), "torque": float(s[AERO_TORQUE]),
                "thrust": float(s[AERO_THRUST])}

    def force_scale(self, nu):
        return np.abs(nu)
