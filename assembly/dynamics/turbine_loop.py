"""The controller in the loop: a controller (a DISCON library, :class:`assembly.dynamics.discon.Discon`,
or any object with its ``step``) called at its own sample time with the measured state, its
generator-torque demand held on the generator's row until the next call and its pitch demand
driving a pitch actuator whose angle the rotor's aerodynamics read
(:class:`assembly.dynamics.rotor_aero.RotorAero`).

It is the ``law`` of a :class:`assembly.dynamics.sampled.Sampled` load along the generator's row,
so the time step calls it between stretches, once a sample (:mod:`assembly.dynamics.sampled`).
Measured for the controller: generator speed ``g' q'`` and rotor speed ``r' q'`` (rows of the
model's velocities), the actuator's pitch, the last torque demand (as the measured torque), the
electrical power ``eta T_g omega_g``, the rotor-effective wind speed. The generator torque acts
on the model against the generator's turning (``f = -sense T_g g`` along its row ``g``).

Pitch actuator (:class:`PitchActuator`): first order, ``beta' = (beta_c - beta) / tau``, the
demand held over a sample, so between samples ``beta(t) = beta_c + (beta_j - beta_c)
exp(-(t - t_j) / tau)`` exactly; ``tau = 0``: the demand itself. Second order
(:class:`SecondOrderPitch`, OpenFAST's and ROSCO's usual actuator model): ``beta'' + 2 zeta w
beta' + w^2 beta = w^2 beta_c``; with ``x = beta - beta_c`` and the roots ``l1, l2 = w (-zeta +-
sqrt(zeta^2 - 1))`` of its characteristic equation, between samples exactly ``x(s) = ((l2 x_j -
x'_j) e^{l1 s} - (l1 x_j - x'_j) e^{l2 s}) / (l2 - l1)`` (complex roots when zeta < 1; ``zeta =
1``: ``x(s) = (x_j + (x'_j + w x_j) s) e^{-w s}``), ``s = t - t_j``, rate and angle continuous.
"""
from __future__ import annotations

import cmath
import math
from typing import Callable

import numpy as np

from ..errors import SceneError


class PitchActuator:
    """A first-order pitch actuator of time constant ``tau`` (s) from ``pitch0`` (rad)."""

    def __init__(self, tau: float, pitch0: float = 0.0):
        if not (math.isfinite(tau) and tau >= 0.0):
            raise SceneError("turbine.pitch_actuator.tau", tau, "must be a time constant >= 0 s")
        self.tau, self.t0, self.start, self.demand = tau, 0.0, pitch0, pitch0

    def pitch(self, t: float) -> float:
        """The blade pitch at ``t`` (rad), the demand held since the last sample."""
        if self.tau == 0.0:
            return self.demand
        return self.demand + (self.start - self.demand) * math.exp(-(t - self.t0) / self.tau)

    def command(self, t: float, demand: float) -> None:
        """A new demand from ``t`` on."""
        self.start, self.t0, self.demand = self.pitch(t), t, demand


class SecondOrderPitch:
    """A second-order pitch actuator of natural frequency ``omega`` (rad/s) and damping ratio
    ``zeta`` from ``pitch0`` (rad) at rest (module notes); :meth:`pitch` and :meth:`command` as
    :class:`PitchActuator`'s."""

    def __init__(self, omega: float, zeta: float, pitch0: float = 0.0):
        if not (math.isfinite(omega) and omega > 0.0):
            raise SceneError("turbine.controller.pitch_omega", omega, "must be a frequency > 0 rad/s")
        if not (math.isfinite(zeta) and zeta > 0.0):
            raise SceneError("turbine.controller.pitch_zeta", zeta, "must be a damping ratio > 0")
        self.w, self.zeta = omega, zeta
        root = cmath.sqrt(zeta * zeta - 1.0)
        self.l1, self.l2 = omega * (-zeta + root), omega * (-zeta - root)
        self.t0, self.x0, self.v0, self.demand = 0.0, 0.0, 0.0, pitch0

    def _state(self, t: float) -> tuple[float, float]:
        """(beta - demand, beta') at ``t``."""
        s, x0, v0 = t - self.t0, self.x0, self.v0
        if self.zeta == 1.0:
            e = math.exp(-self.w * s)
            return (x0 + (v0 + self.w * x0) * s) * e, (v0 - self.w * (v0 + self.w * x0) * s) * e
        l1, l2 = self.l1, self.l2
        a, b = (l2 * x0 - v0) / (l2 - l1), (l1 * x0 - v0) / (l2 - l1)
        e1, e2 = cmath.exp(l1 * s), cmath.exp(l2 * s)
        return (a * e1 - b * e2).real, (a * l1 * e1 - b * l2 * e2).real

    def pitch(self, t: float) -> float:
        return self.demand + self._state(t)[0]

    def command(self, t: float, demand: float) -> None:
        x, v = self._state(t)
        self.x0, self.v0, self.t0 = self.demand + x - demand, v, t
        self.demand = demand


class ControllerLoop:
    """The loop of the module notes: ``controller``, the rows ``generator_row`` and ``rotor_row``
    (n,), the sample ``period`` (s), ``wind(t)`` (m/s), the ``actuator``, the generator
    efficiency ``efficiency`` and its turning ``sense`` on its row. :meth:`law` is the sampled
    law; ``times``, ``torques``, ``pitches`` record every call."""

    def __init__(self, controller, generator_row, rotor_row, period: float, wind: Callable[[float], float],
                 actuator: PitchActuator, efficiency: float = 1.0, sense: float = 1.0, torque0: float = 0.0):
        self.controller = controller
        self.g, self.r = np.asarray(generator_row, float), np.asarray(rotor_row, float)
        self.period, self.wind, self.actuator = period, wind, actuator
        self.eta, self.sense, self.torque = efficiency, float(sense), torque0
        self.times, self.torques, self.pitches = [], [], []

    def law(self, t: float, q: np.ndarray, v: np.ndarray):
        wg, wr = self.sense * float(self.g @ v), self.sense * float(self.r @ v)
        beta = self.actuator.pitch(t)
        out = self.controller.step(t, self.period, wg, wr, beta, self.torque, float(self.wind(t)),
                                   power=self.eta * self.torque * wg)
        self.torque = out.generator_torque
        self.actuator.command(t, out.pitch)
        self.times.append(t)
        self.torques.append(self.torque)
        self.pitches.append(out.pitch)
        return [self.torque]

    def vector(self) -> np.ndarray:
        """The load vector of the generator torque (n, 1): against the generator's turning."""
        return (-self.sense * self.g).reshape(-1, 1)
