"""Generator torque, shaft brake and gearbox friction of a time-domain run, as forces along
shaft rotations (:class:`assembly.dynamics.transient.Nonlinear`).

Directions (rows on q): the generator body's rotation ``r_g``, the brake body's ``r_b``
(their speeds omega = r q'), and the low-speed-shaft torque rows (stiffness and damper
parts, zero force: they only carry the shaft torque to the friction law). Forces ``nu``
enter the balance as ``M q'' + ... + U nu = f``, so a positive ``nu`` brakes a positive
rotation:

* generator, sense s (+1/-1, the generator's starting sense): ``nu = s T``, T constant,
  ``clip(T0 + kp e + ki I, 0, T_max)`` with e = s omega - omega_rated and I = int e dt
  (trapezoidal, so the step's tangent is kp + ki dt / 2), or a recorded history T(t) (law
  "table", e.g. OpenFAST's GenTq: positive brakes, negative drives);
* brake (ElastoDyn's HSS brake, Jonkman 2009): ``nu = T_b(t) clip(omega / omega_stick, -1,
  1)``: the full ramped torque against the motion, proportional to speed below the stick
  speed, so it stops the shaft and never drives it backwards;
* gearbox efficiency eta (ElastoDyn's GBoxEff): a friction torque on the generator of
  ``(1/eta^s - 1)`` times the generator-side torque (generator + brake + the generator's
  inertia torque J alpha) of the previous step, s the sign of the low-speed-shaft torque of
  the previous step (ElastoDyn takes the sign from the previous step too); explicit, so
  its tangent is 0.
"""
from __future__ import annotations

import numpy as np

from .load_series import brake_torque, efficiency_factor
from .transient import Nonlinear


class ShaftTorques(Nonlinear):
    """Generator, brake and gearbox friction (module notes). ``generator``/``brake``: the
    scene tables or None; rows on q; ``sense``: the generator's starting sense (+1/-1);
    ``inertia``: the generator's polar inertia (kg m^2); ``dt`` (s) the run's step;
    ``history``: the torque T(t) of a generator of law "table" (a callable of t, N m)."""

    def __init__(self, n: int, dt: float, generator=None, r_gen=None, sense: float = 1.0, brake=None, r_brake=None,
                 efficiency: float = 1.0, lss_rows=None, inertia: float = 0.0, history=None):
        cols, self.dt, self.history = [], dt, history
        self.gen, self.brake, self.eta, self.sense, self.J = generator, brake, efficiency, sense, inertia
        self.i_gen = self.i_brake = self.i_lss = None
        if generator is not None or efficiency < 1.0:
            self.i_gen = len(cols)
            cols.append(r_gen)
        if brake is not None:
            self.i_brake = len(cols)
            cols.append(r_brake)
        if efficiency < 1.0:
            self.i_lss = len(cols)
            cols.extend(lss_rows)
        self.U = np.array(cols).T if cols else np.zeros((n, 0))
        self.integral, self.error, self.friction, self.omega_prev, self.alpha = 0.0, None, 0.0, None, 0.0
        self.lss_torque = 0.0
        self.last = {"generator": 0.0, "brake": 0.0, "friction": 0.0}

    def _generator(self, t, xd):
        """(nu, d nu / d omega, error) of the generator at time ``t`` and the row speeds ``xd``."""
        g = self.gen
        if g is None:
            return 0.0, 0.0, 0.0
        if g.law == "constant":
            return self.sense * g.torque, 0.0, 0.0
        if g.law == "table":
            return self.sense * self.history(t), 0.0, 0.0
        e = self.sense * xd[self.i_gen] - g.rated_speed
        e_prev = e if self.error is None else self.error
        T = g.torque + g.kp * e + g.ki * (self.integral + 0.5 * self.dt * (e_prev + e))
        top = g.max_torque if g.max_torque is not None else 1.1 * g.torque
        slope = g.kp + 0.5 * self.dt * g.ki if 0.0 < T < top else 0.0
        return self.sense * float(np.clip(T, 0.0, top)), slope, e

    def _brake(self, t, xd):
        b = self.brake
        if b is None:
            return 0.0, 0.0
        Tb = float(brake_torque(t, b.deploy_time, b.ramp_time, b.torque))
        w = xd[self.i_brake]
        if abs(w) < b.stick_speed:
            return Tb * w / b.stick_speed, Tb / b.stick_speed
        return Tb * np.sign(w), 0.0

    def forces(self, t, x, xd):
        m = self.U.shape[1]
        nu, dc = np.zeros(m), np.zeros(m)
        if self.i_gen is not None:
            g, slope, _ = self._generator(t, xd)
            nu[self.i_gen] += g + self.friction
            dc[self.i_gen] += slope
        if self.i_brake is not None:
            b, slope = self._brake(t, xd)
            nu[self.i_brake] += b
            dc[self.i_brake] += slope
        return nu, np.zeros(m), dc

    def commit(self, t, x, xd):
        g, _, e = self._generator(t, xd)
        if self.gen is not None and self.gen.law == "pi":
            e_prev = e if self.error is None else self.error
            self.integral += 0.5 * self.dt * (e_prev + e)
            self.error = e
        b, _ = self._brake(t, xd)
        if self.i_gen is not None:
            w = xd[self.i_gen]
            if self.omega_prev is not None:
                self.alpha = (w - self.omega_prev) / self.dt
            self.omega_prev = w
        if self.i_lss is not None:
            self.lss_torque = x[self.i_lss] + xd[self.i_lss + 1]
            side = g + (b if self.i_brake is not None else 0.0) + self.J * self.alpha
            self.friction = efficiency_factor(self.eta, 1.0 if self.lss_torque >= 0 else -1.0) * side
        self.last = {"generator": abs(g), "brake": abs(b), "friction": self.friction}
