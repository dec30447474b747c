"""Gyroscopic coupling of spinning bodies and the natural frequencies it splits.

A body spinning at Omega (rad/s) about its axis e (unit) with polar inertia J_p (kg m^2)
carries the angular momentum J_p Omega e; tilting the axis by small rotations theta turns
it, d/dt (J_p Omega (e + theta x e)) = J_p Omega (theta_dot x e), so the equations of
motion gain the skew-symmetric term G theta_dot with G = -Omega J_p skew(e) on the body's
three rotations (only the two tilts couple: skew(e) e = 0). In the body's own axes that is
Omega J_p [[0, 1], [-1, 0]] on (theta_x, theta_y) (e.g. Genta (2005), Dynamics of Rotating
Systems, ch. 4). The model becomes M q'' + G q' + K q = 0 with G = T' G_abs T, solved in
first-order form: A x = lambda B x, x = [q, q'], A = [[0, I], [-K, -G]], B = [[I, 0], [0, M]];
lambda = +- i omega.

Each body spins at its own speed from the kinematic chain. What is neglected: the carrier's
rotation as a moving frame (the Coriolis and centripetal terms of planets orbiting with it;
the model stays in fixed axes), and for a flexible body everything but its rigid-equivalent
spin: its elastic motion gets no gyroscopic or spin-softening terms (the rigid-equivalent
tilt of its reduced coordinates, :meth:`rigid_projection`, carries its whole J_p).
The inertia is taken as axisymmetric about the spin axis (J_p = e' J e).
"""
from __future__ import annotations

import math

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ..errors import SolverError
from ..mechanics.kinematics import skew


def body_gyroscopic(inertia: np.ndarray, axis, spin: float) -> np.ndarray:
    """3x3 gyroscopic matrix (N m s/rad) on a body's rotations (global axes) for spin
    ``spin`` (rad/s) about unit ``axis`` with inertia tensor ``inertia`` (kg m^2, global
    axes, about the centre of mass): -spin J_p skew(axis), J_p = axis' inertia axis."""
    e = np.asarray(axis, float)
    jp = float(e @ np.asarray(inertia, float) @ e)
    return -spin * jp * skew(e)


def gyroscopic_matrix(model, spins: dict) -> sp.csr_matrix:
    """G on the model's independent coordinates q (N m s/rad; ``T' G_abs T``) for body
    spins ``spins`` (body name -> rad/s about its own axis; bodies left out stand still)."""
    blocks = []
    for name, bm in model.bodies.items():
        w = spins.get(name, 0.0)
        if w == 0.0:
            blocks.append(sp.csr_matrix((bm.ndof, bm.ndof)))
            continue
        G6 = np.zeros((6, 6))
        G6[3:, 3:] = body_gyroscopic(bm.inertia, bm.axes[:, 2], w)
        P = np.asarray(bm.rigid_projection())
        blocks.append(sp.csr_matrix(P.T @ G6 @ P))
    G_abs = sp.block_diag(blocks, format="csr")
    return (model.T.T @ G_abs @ model.T).tocsr()


def whirl_frequencies(K, M, G, n_rigid: int) -> np.ndarray:
    """Ascending natural frequencies (Hz) of M q'' + G q' + K q = 0, the ``n_rigid`` zero
    (rigid-body) ones left out: the n - n_rigid largest omega = Im(lambda) / (2 pi) of the
    first-order problem. Solved on mass-diagonal scaled coordinates (q = D p, D = M_ii^-1/2)
    and scaled time (K_ii/M_ii up to 1), so a 4e7 kg m^2 rotor and a 534 kg m^2 generator
    share one scale. SolverError when the eigenvalues are not (numerically) imaginary pairs."""
    Kd, Md, Gd = (np.asarray(A.toarray() if hasattr(A, "toarray") else A, float) for A in (K, M, G))
    n = Kd.shape[0]
    d = 1.0 / np.sqrt(np.diag(Md))
    rho = float(np.max(np.diag(Kd) * d * d))
    s = 1.0 / math.sqrt(rho) if rho > 0 else 1.0   # time scale (s): omega' = omega s
    Ks = s * s * d[:, None] * Kd * d[None, :]
    Gs = s * d[:, None] * Gd * d[None, :]
    Ms = d[:, None] * Md * d[None, :]
    Z, I = np.zeros((n, n)), np.eye(n)
    A = np.block([[Z, I], [-Ks, -Gs]])
    B = np.block([[I, Z], [Z, Ms]])
    lam = sla.eig(A, B, right=False)
    if not np.all(np.isfinite(lam)):
        raise SolverError("gyroscopic eigenvalues", "non-finite", "the first-order problem is singular")
    scale = max(float(np.abs(lam).max()), 1.0)
    if np.abs(lam.real).max() > 1e-6 * scale:
        raise SolverError("gyroscopic eigenvalues", float(np.abs(lam.real).max()),
                          "real parts where an undamped gyroscopic system has none")
    w = np.sort(lam.imag)[n + n_rigid:]
    return w / s / (2 * math.pi)
