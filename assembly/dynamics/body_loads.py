"""Loads of a time-domain run that act on every body or follow a body's rotation: gravity (the
``[turbine]`` table's, turned by the shaft tilt), the housing's prescribed motion
(``[[simulation.nacelle]]``) -- both the housing's d'Alembert loads of
:mod:`assembly.model.frame_motion`, load vectors times histories -- and the unbalances
(``[[simulation.unbalance]]``, :class:`assembly.dynamics.unbalance.Unbalance` on the body's
lateral rows at its centre or interface and its rotation).

A nacelle acceleration is ``amplitude sin(2 pi frequency t + phase)`` or a series read as a
load's (m/s^2 or rad/s^2), which must cover the run.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..errors import SceneError
from ..model.frame_motion import frame_loads, scene_gravity
from ..model.probes import body_point, point_vector, spin_row
from .load_series import constant, file_history, require_cover
from .unbalance import Unbalance

#: The housing's six motions, in :func:`assembly.model.frame_motion.frame_loads`' column order.
DOFS = ("x", "y", "z", "rx", "ry", "rz")


class Harmonic:
    """``amplitude sin(2 pi frequency t + phase)`` of a float or an array of times (defined at
    every time: no ``origin`` file to warn about)."""

    origin = ""

    def __init__(self, amplitude: float, frequency: float, phase: float):
        self.a, self.w, self.p = amplitude, 2.0 * math.pi * frequency, phase

    def __call__(self, t):
        return self.a * np.sin(self.w * np.asarray(t, float) + self.p)


@dataclass(frozen=True)
class BodyLoads:
    """``vectors`` (n x k) times ``histories`` (k series of t): gravity and the nacelle's
    motion; ``nonlinear``: the unbalances."""

    vectors: np.ndarray
    histories: tuple
    nonlinear: list


def body_loads(model, scene, sim, dt: float, t_end: float, base_dir, phi=None, tilt=None) -> BodyLoads:
    """The :class:`BodyLoads` of ``scene`` (its ``[turbine]`` gravity, ``tilt`` (rad) in place of
    the table's when given) and ``sim`` (``[simulation]``) on ``model``; ``phi``: the model's
    rigid-body mode the drivetrain turns in (an unbalance needs a body that turns in it)."""
    n = model.K.shape[0]
    vecs, hist = [], []
    tb = scene.turbine
    if tb is not None and tb.gravity:
        vecs.append(scene_gravity(model, tb if tilt is None else dataclasses.replace(tb, tilt=tilt)))
        hist.append(constant(1.0, "turbine.gravity", ""))
    for i, nm in enumerate(sim.nacelle):
        path = f"simulation.nacelle[{i}]"
        vecs.append(frame_loads(model, nm.origin)[:, DOFS.index(nm.dof)])
        unit = "m/s^2" if nm.dof in ("x", "y", "z") else "rad/s^2"
        s = file_history(nm, path, base_dir, unit)
        if s is None:
            s = Harmonic(nm.amplitude, nm.frequency, nm.phase)
        else:
            require_cover(s, t_end, f"{path}.{'table' if nm.table else 'openfast'}")
        hist.append(s)
    return BodyLoads(np.array(vecs).T if vecs else np.zeros((n, 0)), tuple(hist),
                     [unbalance(model, u, i, dt, phi) for i, u in enumerate(sim.unbalance)])


def unbalance(model, u, i: int, dt: float, phi=None) -> Unbalance:
    """The :class:`Unbalance` of ``[[simulation.unbalance]]`` entry ``i``: on its body's lateral
    rows (local x, y at its centre, or at its interface) and its rotation."""
    path = f"simulation.unbalance[{i}]"
    where = u.body if u.interface is None else f"{u.body}:{u.interface}"
    body, iface = body_point(model, where, f"{path}.body", where)
    theta = spin_row(model, body)
    if not np.any(theta) or (phi is not None and abs(theta @ phi) <= 1e-12 * float(np.abs(phi).max())):
        raise SceneError(f"{path}.body", u.body, "does not turn with the drivetrain: an unbalance needs a "
                                                 "rotating body")
    axes = model.bodies[body].axes
    rows = []
    for j in (0, 1):
        w = np.zeros(6)
        w[:3] = axes[:, j]
        rows.append(point_vector(model, body, iface, w))
    if not (np.any(rows[0]) and np.any(rows[1])):
        raise SceneError(f"{path}.body", u.body, "turns about its axis only (torsional): it has no lateral "
                                                 "motion for an unbalance to act on")
    return Unbalance(model.K.shape[0], rows[0], rows[1], theta, u.mass, u.radius, u.phase, dt)
