"""Generator, brake and gearbox friction torques as plain functions on arrays (module notes of
:mod:`assembly.dynamics.drive_torques`): written once, called by
:class:`assembly.dynamics.drive_torques.ShaftTorques` (the Python step) and by the compiled
step (:mod:`assembly.dynamics.step_kernel`); compiled by numba when it is installed.

The parameters ``p`` and the state ``s`` are float arrays indexed by the constants below;
what depends on time alone -- a recorded generator torque ``T(t)`` (law "table") and the
brake's ramped torque ``T_b(t)`` -- comes in as numbers evaluated by the caller.
"""
from __future__ import annotations

import numpy as np

from .jit import njit

#: generator laws (``p[LAW]``)
NONE, CONSTANT, TABLE, PI = 0, 1, 2, 3
#: parameters: law, sense, torque, kp, ki, rated speed, top torque, dt, column of the generator,
#: of the brake, of the low-speed shaft's stiffness row (-1: none), stick speed, efficiency, inertia
LAW, SENSE, TORQUE, KP, KI, RATED, TOP, DT, I_GEN, I_BRAKE, I_LSS, STICK, ETA, INERTIA = range(14)
N_PARAMS = 14
#: state: PI integral, last error (and whether there is one), friction torque, last generator
#: speed (and whether there is one), its rate, low-speed-shaft torque, last |generator|, |brake|
INTEGRAL, ERROR, HAS_ERROR, FRICTION, OMEGA, HAS_OMEGA, ALPHA, LSS, LAST_GEN, LAST_BRAKE = range(10)
N_STATE = 10


@njit
def generator(p, s, table, xd):
    """(nu, d nu / d omega, speed error) of the generator; ``table``: T(t) of law "table"."""
    law = p[LAW]
    if law == NONE:
        return 0.0, 0.0, 0.0
    if law == CONSTANT:
        return p[SENSE] * p[TORQUE], 0.0, 0.0
    if law == TABLE:
        return p[SENSE] * table, 0.0, 0.0
    e = p[SENSE] * xd[int(p[I_GEN])] - p[RATED]
    e_prev = s[ERROR] if s[HAS_ERROR] else e
    T = p[TORQUE] + p[KP] * e + p[KI] * (s[INTEGRAL] + 0.5 * p[DT] * (e_prev + e))
    top = p[TOP]
    slope = p[KP] + 0.5 * p[DT] * p[KI] if 0.0 < T < top else 0.0
    return p[SENSE] * min(max(T, 0.0), top), slope, e


@njit
def brake(p, torque, xd):
    """(nu, d nu / d omega) of the brake of ramped torque ``torque`` (N m) at this instant."""
    if p[I_BRAKE] < 0:
        return 0.0, 0.0
    w = xd[int(p[I_BRAKE])]
    if abs(w) < p[STICK]:
        return torque * w / p[STICK], torque / p[STICK]
    return torque * (1.0 if w > 0 else (-1.0 if w < 0 else 0.0)), 0.0


@njit
def shaft_forces(p, s, table, torque, xd, nu, dc):
    """The torques along the columns (generator + friction, brake) into ``nu`` and their speed
    tangents into ``dc`` (the displacement tangent is 0); ``torque``: the brake's."""
    nu[:] = 0.0
    dc[:] = 0.0
    if p[I_GEN] >= 0:
        g, slope, _ = generator(p, s, table, xd)
        nu[int(p[I_GEN])] += g + s[FRICTION]
        dc[int(p[I_GEN])] += slope
    if p[I_BRAKE] >= 0:
        b, slope = brake(p, torque, xd)
        nu[int(p[I_BRAKE])] += b
        dc[int(p[I_BRAKE])] += slope


@njit
def shaft_commit(p, s, table, torque, x, xd):
    """An accepted step: the PI integral, the generator's acceleration, and the friction of
    the next step from this one's low-speed-shaft torque sign (explicit)."""
    g, _, e = generator(p, s, table, xd)
    if p[LAW] == PI:
        e_prev = s[ERROR] if s[HAS_ERROR] else e
        s[INTEGRAL] += 0.5 * p[DT] * (e_prev + e)
        s[ERROR], s[HAS_ERROR] = e, 1.0
    b, _ = brake(p, torque, xd)
    if p[I_GEN] >= 0:
        w = xd[int(p[I_GEN])]
        if s[HAS_OMEGA]:
            s[ALPHA] = (w - s[OMEGA]) / p[DT]
        s[OMEGA], s[HAS_OMEGA] = w, 1.0
    if p[I_LSS] >= 0:
        i = int(p[I_LSS])
        s[LSS] = x[i] + xd[i + 1]
        side = g + (b if p[I_BRAKE] >= 0 else 0.0) + p[INERTIA] * s[ALPHA]
        sign = 1.0 if s[LSS] >= 0 else -1.0
        s[FRICTION] = (1.0 / p[ETA] ** sign - 1.0) * side
    s[LAST_GEN], s[LAST_BRAKE] = abs(g), abs(b)


def parameters(law: int, sense: float, dt: float, columns: tuple, torque=0.0, kp=0.0, ki=0.0, rated=0.0, top=0.0,
               stick=1.0, eta=1.0, inertia=0.0) -> np.ndarray:
    """The parameter array ``p`` (``columns``: the generator's, brake's and low-speed shaft's,
    None for none)."""
    p = np.zeros(N_PARAMS)
    p[[LAW, SENSE, TORQUE, KP, KI, RATED, TOP, DT]] = law, sense, torque, kp, ki, rated, top, dt
    p[[I_GEN, I_BRAKE, I_LSS]] = [-1 if c is None else c for c in columns]
    p[[STICK, ETA, INERTIA]] = stick, eta, inertia
    return p
