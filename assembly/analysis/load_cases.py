"""A load case on an assembled model: the applied loads as one load vector, the held
directions as constraint rows, and the motions the held model still allows.

Applied loads (:func:`applied_loads`): the torque case's couple ``torque`` (N m) about the
input body's axis -- on a flexible body at the named interface master -- and every point
load of ``forces``: a force (N) and a moment (N m) at a point of a rigid body (through its
rigid lever arm, :func:`assembly.mechanics.kinematics.rigid_transfer`) or at an interface master of
a flexible body. Each enters the load vector on the absolute coordinates ``z`` by virtual
work through the body's ``motion_at``: ``F += P' [f, m]``.

Held directions (:func:`held_directions`): the torque case's output, held against rotation
about its own axis relative to the housing (on a rigid body its independent rotation ``rz``
at its axis point, on a flexible body the rotation ``rz`` of the ``output_interface``
master), and each support's DOFs: the motion of the body at the support point, in the
body's local axes, relative to the housing. Each is one row ``c`` of constraints
``c' q = 0`` on the independent coordinates ``q`` (``z = T q``); on a rigid body in the
housing frame and on a flexible body's master it is one coordinate, which is then simply
dropped (as a ``[[fixed]]`` DOF is). A direction a constraint already holds (fixed DOF,
rigid bearing direction, torsional fidelity) gives a zero row and is left out.
Zero-energy motions come from the structure of the spring rows (:mod:`assembly.mechanics.nullity`),
never from small eigenvalues, so a held model that can still move is named before any
solve, and the unheld model's single rigid-body mode gives the kinematic speed ratio of
the chain (gear geometry only: base radii and centres).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..mechanics.dense import dense
from ..mechanics.kinematics import block_rotation
from ..mechanics.nullity import DROP_RTOL, STRUCT_RTOL, spring_rows, zero_motion_basis
from ..model.probes import axial_rotation, load_point
from ..scene.tables import DOF_NAMES


@dataclass(frozen=True)
class Applied:
    """One applied load: ``wrench`` [force N, moment N m] in global axes at ``point``
    (m, global) on ``body``, through ``interface`` on a flexible body."""

    body: str
    point: np.ndarray
    wrench: np.ndarray
    interface: str | None
    label: str


@dataclass(frozen=True)
class Held:
    """One held direction: ``dof`` (local axes) of ``body`` at ``point`` (m, global) held
    relative to the housing; ``support``: index into the case's ``supports`` (None: the
    torque case's output hold); ``row``: its constraint row on ``q``."""

    name: str
    body: str
    dof: str
    point: np.ndarray
    support: int | None
    row: np.ndarray


def applied_loads(model, load) -> list[Applied]:
    """Every load of ``load`` (torque couple and point loads) as an :class:`Applied`."""
    out = []
    if load.has_torque:
        bm = model.bodies[load.input]
        out.append(Applied(load.input, load_point(model, load.input, load.input_interface),
                           np.concatenate([np.zeros(3), load.torque * bm.axes[:, 2]]), load.input_interface,
                           f"torque into {load.input}"))
    for j, pl in enumerate(load.forces):
        R = model.bodies[pl.body].axes if pl.axes == "body" else np.eye(3)
        w = np.concatenate([R @ np.asarray(pl.force, float), R @ np.asarray(pl.moment, float)])
        out.append(Applied(pl.body, load_point(model, pl.body, pl.interface, pl.point), w, pl.interface,
                           f"forces[{j}] on {pl.body}" + (f".{pl.interface}" if pl.interface else "")))
    return out


def load_vector(model, load) -> np.ndarray:
    """Load vector on the absolute coordinates ``z`` (virtual work of every applied load:
    ``P' [f, m]`` with ``P`` the body's motion at the load point)."""
    F = np.zeros(model.n_abs)
    for a in applied_loads(model, load):
        sl = model.body_slice(a.body)
        F[sl] += np.asarray(model.bodies[a.body].motion_at(a.point, a.interface).T @ a.wrench).ravel()
    return F


def output_hold_name(model, load) -> str:
    """Name of the output hold: ``body.rz`` of a rigid body, ``body.interface.rz`` of a
    flexible one."""
    if model.bodies[load.output].flexible:
        return f"{load.output}.{load.output_interface}.rz"
    return f"{load.output}.rz"


def held_directions(model, load) -> list[Held]:
    """Every direction the case holds (output hold first, then the supports' DOFs), with
    its constraint row on ``q``; directions a constraint already holds are left out."""
    out = []
    if load.has_torque:
        iface = load.output_interface if model.bodies[load.output].flexible else None
        out += _rows(model, load.output, iface, ("rz",), None, output_hold_name(model, load))
    for j, su in enumerate(load.supports):
        where = f"{su.body}.{su.interface}" if su.interface else su.body
        out += _rows(model, su.body, su.interface, su.dofs, j, where)
    return out


def _rows(model, body: str, interface, dofs, support, where: str) -> list[Held]:
    """Constraint rows of ``dofs`` (local axes) of ``body`` at its load point, relative to
    the housing: ``e_d' R' P T`` (R the body axes, P its motion at the point); entries at
    round-off of the product's scale dropped, zero rows (already held) left out."""
    bm = model.bodies[body]
    p = load_point(model, body, interface)
    L = block_rotation(bm.axes).T @ dense(bm.motion_at(p, interface))
    Tb = model.T[model.body_slice(body)]
    out = []
    for d in dofs:
        e = L[DOF_NAMES.index(d)]
        row = np.asarray(Tb.T @ e).ravel()
        scale = np.asarray(abs(Tb).T @ np.abs(e)).ravel().max(initial=0.0)
        row[np.abs(row) <= DROP_RTOL * scale] = 0.0
        if np.any(row):
            out.append(Held(f"{where}.{d}", body, d, p, support, row))
    return out


def free_motions(model, rows: np.ndarray | None = None) -> np.ndarray:
    """(n_q x n_free) zero-energy motions of ``model`` with the constraint ``rows``
    (n_c x n_q, or None) held at zero: the null space of the unit spring rows (and the held
    rows) on the motions that strain no body (:func:`assembly.mechanics.nullity.zero_motion_basis`),
    read with :data:`assembly.mechanics.nullity.STRUCT_RTOL` like the rigid-body count."""
    W = zero_motion_basis(model)
    if W.shape[1] == 0:
        return np.zeros((model.K.shape[0], 0))
    G = spring_rows(model, W)
    if rows is not None and len(rows):
        H = np.asarray(rows) @ W
        n = np.linalg.norm(H, axis=1)
        G = np.vstack([G, H[n > 0] / n[n > 0, None]])
    cn = np.linalg.norm(G, axis=0)
    cn[cn == 0] = 1.0                       # a direction no spring touches: free
    Gs = G / cn
    if Gs.shape[0] == 0:
        return W
    _, s, Vt = np.linalg.svd(Gs, full_matrices=True)
    rank = int(np.sum(s > STRUCT_RTOL * s[0])) if len(s) and s[0] > 0 else 0
    C = Vt[rank:].T / cn[:, None]
    return W @ C


def single_rigid_mode(model) -> tuple[np.ndarray | None, str]:
    """The unheld model's one rigid-body mode (n_q x 1, :func:`free_motions`) and "", or
    None and why there is not exactly one: none (a bearing or shaft to the housing carries
    the torsion of a turning body) or several (a sub-chain turns freely of the rest)."""
    phi = free_motions(model)
    if phi.shape[1] == 1:
        return phi, ""
    if phi.shape[1] == 0:
        return None, "no rigid-body mode: bearings or shafts to the housing carry torsion of turning bodies"
    return None, (f"{phi.shape[1]} rigid-body modes: a sub-chain turns freely of the rest "
                  "(the chain is not one connected gear train)")


def speed_ratio(model, load) -> tuple[float | None, str]:
    """Kinematic speed ratio ``omega_input / omega_output`` (signed, about each body's own
    axis) from the unheld model's rigid-body mode, and a note. None when the assembly has
    no single rigid-body mode (then the ratio is not a property of the gearing alone)."""
    phi, why = single_rigid_mode(model)
    if phi is None:
        return None, why
    Z = model.T @ phi
    w_in, w_out = axial_rotation(model, Z, load.input)[0], axial_rotation(model, Z, load.output)[0]
    if abs(w_out) <= 1e-12 * abs(w_in):
        return None, "the output stands still in the rigid-body mode"
    return float(w_in / w_out), "from the rigid-body mode of the unheld assembly (gear geometry)"
