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

from .jit import pick
from .load_series import brake_torque, efficiency_factor
from .torque_laws import (
    CONSTANT,
    FRICTION,
    LAST_BRAKE,
    LAST_GEN,
    N_STATE,
    NONE,
    PI,
    TABLE,
    parameters,
    shaft_commit,
    shaft_forces,
)
from .transient import Nonlinear

LAWS = {"constant": CONSTANT, "table": TABLE, "pi": PI}


class ShaftTorques(Nonlinear):
    """Generator, brake and gearbox friction (module notes). ``generator``/``brake``: the
    scene tables or None; rows on q; ``sense``: the generator's starting sense (+1/-1);
    ``inertia``: the generator's polar inertia (kg m^2); ``dt`` (s) the run's step;
    ``history``: the torque T(t) of a generator of law "table" (a callable of t, N m).
    Parameters ``p`` and state ``s``: the arrays of :mod:`assembly.dynamics.torque_laws`."""

    compiled = "torques"                    # the compiled step knows these laws

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
            efficiency_factor(efficiency, 1.0)               # checked: in (0, 1]
            self.i_lss = len(cols)
            cols.extend(lss_rows)
        self.U = np.array(cols).T if cols else np.zeros((n, 0))
        g = generator
        law = NONE if g is None else LAWS[g.law]
        top = 0.0 if g is None else (g.max_torque if g.max_torque is not None else 1.1 * g.torque)
        self.p = parameters(law, sense, dt, (self.i_gen, self.i_brake, self.i_lss),
                            torque=0.0 if g is None else g.torque, kp=getattr(g, "kp", 0.0) or 0.0,
                            ki=getattr(g, "ki", 0.0) or 0.0, rated=getattr(g, "rated_speed", 0.0) or 0.0, top=top,
                            stick=brake.stick_speed if brake is not None else 1.0, eta=efficiency, inertia=inertia)
        self.s = np.zeros(N_STATE)

    def table(self, t):
        """T(t) of a generator of law "table" at ``t`` (s, a float or an array), else 0."""
        if self.history is None or self.gen is None or self.gen.law != "table":
            return 0.0 if np.ndim(t) == 0 else np.zeros(np.shape(t))
        return self.history(t)

    def brake_torque(self, t):
        """The brake's ramped torque at ``t`` (s, a float or an array), 0 without a brake."""
        b = self.brake
        if b is None:
            return 0.0 if np.ndim(t) == 0 else np.zeros(np.shape(t))
        return brake_torque(t, b.deploy_time, b.ramp_time, b.torque)

    def forces(self, t, x, xd):
        m = self.U.shape[1]
        nu, dc = np.zeros(m), np.zeros(m)
        pick(shaft_forces)(self.p, self.s, float(self.table(t)), float(self.brake_torque(t)), xd, nu, dc)
        return nu, np.zeros(m), dc

    def commit(self, t, x, xd):
        pick(shaft_commit)(self.p, self.s, float(self.table(t)), float(self.brake_torque(t)), x, xd)

    @property
    def friction(self) -> float:
        """The gearbox friction torque of the next step (N m)."""
        return float(self.s[FRICTION])

    @property
    def last(self) -> dict:
        """|generator|, |brake| torque (N m) of the last accepted step and the friction."""
        return {"generator": float(self.s[LAST_GEN]), "brake": float(self.s[LAST_BRAKE]), "friction": self.friction}
