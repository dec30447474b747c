"""A speed-controlled drive (``[simulation.drive]``): a run-up or run-down of the drivetrain at a
prescribed rate, as a test bench's motor drives it.

The drive is a servo on the driven body's rotation ``theta = r' q`` (``r`` its spin row): a
spring and a damper to a reference that turns at ``omega_ref(t)`` -- the starting speed
``omega_0`` until ``t_start``, linear to ``end_speed`` at ``t_end``, held after -- with
``theta_ref(t) = integral of omega_ref``:

    T = k (theta_ref - theta) + c (omega_ref - omega),   k = J w_b^2,  c = 2 J w_b,

``w_b = 2 pi f_b`` the servo's bandwidth and J the drivetrain's inertia referred to the driven
body (``phi' M phi / (r' phi)^2``, phi its rigid-body motion): on the rigid drivetrain the servo
is a critically damped oscillator at f_b. In the balance ``M q'' + C q' + K q = f`` it is a
rank-one spring and damper, ``k r r'`` and ``c r r'``, and the load ``r (k theta_ref(t) + c
omega_ref(t))``: linear, so both time steps run it (compiled or not). Its tracking error obeys
``e'' + 2 w_b e' + w_b^2 e = -omega_ref'`` (e = theta - theta_ref): on a ramp of rate a the
speed error decays to 0 and the angle lags by ``a / w_b^2``; the static twist at the start
(the loads at t = 0 held by the servo's spring) stays as an offset.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..errors import SceneError
from ..model.probes import body_point, spin_row


@dataclass(frozen=True)
class DriveRamp:
    """``omega_ref(t)`` (:meth:`speed`) and ``theta_ref(t)`` (:meth:`angle`) of the module notes,
    of a float or an array of times; ``origin`` "" (no file to warn about)."""

    omega0: float
    end_speed: float
    t_start: float
    t_end: float
    origin: str = ""

    def speed(self, t):
        t = np.asarray(t, float)
        u = np.clip((t - self.t_start) / (self.t_end - self.t_start), 0.0, 1.0)
        return self.omega0 + (self.end_speed - self.omega0) * u

    def angle(self, t):
        t = np.asarray(t, float)
        a = (self.end_speed - self.omega0) / (self.t_end - self.t_start)
        t1 = np.clip(t, None, self.t_start)
        t2 = np.clip(t, self.t_start, self.t_end) - self.t_start
        t3 = np.clip(t - self.t_end, 0.0, None)
        return self.omega0 * (t1 + t2 + t3) + 0.5 * a * t2 * t2 + (self.end_speed - self.omega0) * t3


@dataclass(frozen=True)
class Drive:
    """The drive's parts on q: ``K`` and ``C`` (rank-one, dense or sparse as the model's),
    ``vector`` (n,) and ``history(t)`` (the load ``vector x history``), the ``ramp``, the
    driven ``body``, its row ``row``, ``stiffness`` k and ``damping`` c."""

    K: object
    C: object
    vector: np.ndarray
    history: object
    ramp: DriveRamp
    body: str
    row: np.ndarray
    stiffness: float
    damping: float


class DriveLoad:
    """``k theta_ref(t) + c omega_ref(t)`` of a float or an array of times."""

    origin = ""

    def __init__(self, ramp: DriveRamp, k: float, c: float):
        self.ramp, self.k, self.c = ramp, k, c

    def __call__(self, t):
        return self.k * self.ramp.angle(t) + self.c * self.ramp.speed(t)


def speed_drive(model, table, reference: str | None, v0: np.ndarray, phi, sparse: bool) -> Drive:
    """The :class:`Drive` of a ``[simulation.drive]`` ``table`` on ``model`` (``reference``: the
    run's reference body, the default driven body; ``v0`` the starting velocity; ``phi`` the
    rigid-body mode, None without one; ``sparse``: the run's matrices are sparse)."""
    path = "simulation.drive"
    if not table.t_end > table.t_start:
        raise SceneError(f"{path}.t_end", table.t_end, f"must be after t_start = {table.t_start:g} s")
    name = table.body if table.body is not None else reference
    if name is None:
        raise SceneError(f"{path}.body", None, "missing: name the driven body (or give the scene a body of role "
                                               "'rotor')")
    body, _ = body_point(model, name, f"{path}.body", name)
    r = spin_row(model, body)
    if phi is None or abs(r @ phi) <= 1e-12 * float(np.abs(phi).max(initial=1.0)):
        raise SceneError(f"{path}.body", name, "does not turn with the drivetrain (no rigid-body rotation): a speed "
                                               "drive turns a free drivetrain")
    J = float(phi @ (model.M @ phi)) / float(r @ phi) ** 2
    wb = 2.0 * np.pi * table.bandwidth
    k, c = J * wb * wb, 2.0 * J * wb
    ramp = DriveRamp(float(r @ v0), table.end_speed, table.t_start, table.t_end)
    if sparse:                                   # the row's few coordinates only
        nz = np.flatnonzero(r)
        R = sp.csr_matrix((np.outer(r[nz], r[nz]).ravel(), (np.repeat(nz, len(nz)), np.tile(nz, len(nz)))),
                          shape=(len(r), len(r)))
    else:
        R = np.outer(r, r)
    return Drive(k * R, c * R, r.copy(), DriveLoad(ramp, k, c), ramp, body, r, k, c)
