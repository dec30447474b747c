"""Where a time-domain run starts: the speed of every body and the static equilibrium.

Every body turns at its share of ``speed`` in the model's rigid-body mode phi, and q0 is
the static equilibrium under the loads at t = 0 with the rigid-body acceleration they give
taken out (inertia relief: ``K q + U nu = f - M phi alpha``, alpha = phi' f / phi' M phi,
phi' M q = 0), solved by Newton's method on the meshes' contact (:func:`static_start`).
"""
from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ..analysis.drivetrain import rigid_mode
from ..analysis.load_cases import single_rigid_mode
from ..errors import MechanismError, SceneError
from .transient import EPS, ROUNDOFF, tangent

#: Contact slope of an open gap in the static start's Newton tangent (a fraction of the
#: mesh stiffness): the exact tangent, 0, leaves a mechanism where a load pushes a gear across
#: its backlash. The first guess already rests each mesh on the flank the linear solution
#: loads (:meth:`assembly.dynamics.mesh_contact.Meshes.coast_preload`), so a gap is rarely
#: crossed; the residual stays exact, so the start is still the exact equilibrium.
GAP_SLOPE = 1e-3


def start_velocity(model, scene, sim, speed: float | None):
    """(v0 on q, phi: the rigid-body mode at a unit speed of the reference or the model's
    single rigid-body mode (None without one), the reference body or None): every body at
    its share of ``speed`` (rad/s of the reference; default ``sim.speed``)."""
    n = model.K.shape[0]
    speed = sim.speed if speed is None else speed
    reference = sim.reference
    if reference is None:
        have = [b for b in scene.expanded().bodies if b.role == "rotor"]
        reference = have[0].name if have else None
    if reference is None:               # no speed reference: the rigid-body mode still relieves the loads
        phi, why = single_rigid_mode(model)
        phi = None if phi is None else phi[:, 0]
    else:
        phi, why = rigid_mode_at(model, reference, "simulation.reference")
    if speed and (phi is None or reference is None):
        raise SceneError("simulation.speed", speed, "a starting speed needs a rotor (simulation.reference or a "
                                                    "body of role 'rotor') and one rigid-body mode" +
                         (f": {why}" if why else ""))
    return (speed * phi if speed else np.zeros(n)), phi, reference


def rigid_mode_at(model, reference: str, path: str):
    """(the rigid-body mode at a unit speed of ``reference``, "") or (None, why there is not
    one); SceneError at ``path`` when the reference stands still in it."""
    phi, why = single_rigid_mode(model)
    if phi is None:
        return None, why
    try:
        return rigid_mode(model, reference), ""
    except MechanismError:
        raise SceneError(path, reference, "this body stands still in the rigid-body mode: it cannot set the "
                                          "speed") from None


def static_start(M, K, U, nl, f0, phi, xd0, force_scale: float = 0.0, preload=None):
    """q0 of the module notes: Newton on ``K q + U nu(U'q, xd0) + M phi lam = f0``,
    ``phi' M q = 0`` (no rigid-body mode: phi None, plain ``K q + U nu = f0``). Converged when
    the step reaches round-off or the force residual is below 1e-12 x ``force_scale`` (N; the
    force that closes a mesh's backlash: a smaller load cannot say on which flank it rests)
    or below the round-off of the forces it sums.
    ``preload(x)``: forces along U that put the linear solution's meshes on the flank it
    loads (the first guess, so that Newton's method rarely has to cross a gap)."""
    n = K.shape[0]
    dense = not sp.issparse(K)
    if phi is not None:
        Mphi = M @ phi
        B = (np.block([[K, Mphi[:, None]], [Mphi[None, :], np.zeros((1, 1))]]) if dense else
             sp.bmat([[K, sp.csr_matrix(Mphi[:, None])], [sp.csr_matrix(Mphi[None, :]), None]]).tocsc())
        Ub = np.vstack([U, np.zeros((1, U.shape[1]))])
        rhs = np.concatenate([f0, [0.0]])
    else:
        B, Ub, rhs = K, U, f0
    lu = sla.lu_factor(B) if dense else sp.linalg.splu(sp.csc_matrix(B))
    solve = (lambda b: sla.lu_solve(lu, b)) if dense else lu.solve
    W = solve(Ub) if U.shape[1] else np.zeros((len(rhs), 0))
    S = Ub.T @ W
    z = solve(rhs)
    if preload is not None and U.shape[1]:
        p = preload(Ub.T @ z)
        if np.any(p):
            z = solve(rhs - Ub @ p)
    step = np.inf
    absB, absU = abs(B), np.abs(Ub)
    for _ in range(60):
        nu, dk, _ = nl.forces(0.0, Ub.T @ z, xd0)
        r = B @ z + Ub @ nu - rhs
        # or r at round-off: each row sums the forces |B| |z|, |U| (the terms of nu) and rhs,
        # rounded to about ROUNDOFF eps x their size (transient.ROUNDOFF)
        floor = ROUNDOFF * EPS * np.linalg.norm(absB @ np.abs(z) + absU @ nl.force_scale(nu) + np.abs(rhs))
        if not len(nu) or np.linalg.norm(r) <= max(1e-12 * max(np.linalg.norm(rhs), force_scale), floor):
            break
        # Newton step with the tangent B + Ub diag(dk) Ub' by Woodbury
        y = solve(r)
        Kt = tangent(dk)
        corr = np.linalg.solve(np.eye(len(nu)) + Kt @ S, Kt @ (Ub.T @ y))
        dz = y - W @ corr
        z = z - dz
        last, step = step, np.linalg.norm(dz)
        # converged: a step at round-off, or steps that stopped shrinking at a level the
        # conditioning of the bordered matrix allows (a piecewise-linear contact converges exactly)
        if step <= 1e-12 * max(np.linalg.norm(z), 1e-300) or (step <= 1e-8 * np.linalg.norm(z) and step >= 0.5 * last):
            break
    else:
        raise SceneError("simulation.static_start", True, "the static equilibrium at t = 0 did not converge "
                                                          "(meshes opening and closing); set static_start = false")
    return z[:n]
