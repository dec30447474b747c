"""A load case on an assembled model: the input torque as a load vector, the output hold as
one independent coordinate held at zero, and the motions the held model still allows.

The input torque (N m) is a couple about the input body's axis: on a rigid body its
rotation, on a flexible body the rotation of the named interface master about the body's
axis (local z). The output is held against rotation about its own axis relative to the
housing: on a rigid body its independent rotation ``rz`` (at its axis point), on a
flexible body the rotation ``rz`` of the master of ``output_interface`` -- the column of
``T`` (``z = T q``) for that coordinate is dropped, exactly as a ``[[fixed]]`` DOF of a rigid
body is. Zero-energy motions come from the structure of the spring rows
(:mod:`assembly.nullity`), never from small eigenvalues, so a held model that can still
move is named before any solve, and the unheld model's single rigid-body mode gives the
kinematic speed ratio of the chain (gear geometry only: base radii and centres).
"""
from __future__ import annotations

import numpy as np

from .nullity import STRUCT_RTOL, spring_rows, zero_motion_basis


def input_load(model, load) -> np.ndarray:
    """Load vector on the absolute coordinates ``z``: the couple ``load.torque`` (N m)
    about the input body's axis (at the interface master of a flexible body)."""
    bm = model.bodies[load.input]
    F = np.zeros(model.n_abs)
    sl = model.body_slice(load.input)
    if bm.flexible:
        idx = bm.masters[load.input_interface][1]   # local axes: z = the body's axis
        F[sl.start + idx[5]] = load.torque
    else:
        F[sl.start + 3:sl.start + 6] = load.torque * bm.axes[:, 2]
    return F


def held_name(model, load) -> str:
    """Name of the independent coordinate the output is held at: ``body.rz`` of a rigid
    body, ``body.interface.rz`` of a flexible one."""
    if model.bodies[load.output].flexible:
        return f"{load.output}.{load.output_interface}.rz"
    return f"{load.output}.rz"


def held_column(model, load) -> int | None:
    """Column of ``q`` that holds the output, or None when a constraint (a fixed DOF, a
    rigid bearing direction) already holds its rotation."""
    name = held_name(model, load)
    return model.dof_names.index(name) if name in model.dof_names else None


def free_motions(model, held: int | None = None) -> np.ndarray:
    """(n_q x n_free) zero-energy motions of ``model`` with coordinate ``held`` (a column
    of q, or None) held at zero: the null space of the unit spring rows (and the hold) on
    the motions that strain no body (:func:`assembly.nullity.zero_motion_basis`), read with
    :data:`assembly.nullity.STRUCT_RTOL` like the rigid-body count."""
    W = zero_motion_basis(model)
    if W.shape[1] == 0:
        return np.zeros((model.K.shape[0], 0))
    G = spring_rows(model, W)
    if held is not None and np.any(W[held]):
        G = np.vstack([G, W[held] / np.linalg.norm(W[held])])
    cn = np.linalg.norm(G, axis=0)
    cn[cn == 0] = 1.0                       # a direction no spring touches: free
    Gs = G / cn
    if Gs.shape[0] == 0:
        return W
    _, s, Vt = np.linalg.svd(Gs, full_matrices=True)
    rank = int(np.sum(s > STRUCT_RTOL * s[0])) if len(s) and s[0] > 0 else 0
    C = Vt[rank:].T / cn[:, None]
    return W @ C


def axial_rotation(model, Z: np.ndarray, body: str) -> np.ndarray:
    """Rotation (rad) of ``body`` about its own axis (rigid-equivalent) for columns of ``Z``
    (absolute coordinates)."""
    bm = model.bodies[body]
    return bm.axes[:, 2] @ bm.rigid_projection()[3:] @ Z[model.body_slice(body)]


def speed_ratio(model, load) -> tuple[float | None, str]:
    """Kinematic speed ratio ``omega_input / omega_output`` (signed, about each body's own
    axis) from the unheld model's rigid-body mode, and a note. None when the assembly has
    no single rigid-body mode (then the ratio is not a property of the gearing alone)."""
    phi = free_motions(model)
    if phi.shape[1] != 1:
        why = ("no rigid-body mode: bearings or shafts to the housing carry torsion of turning bodies"
               if phi.shape[1] == 0 else f"{phi.shape[1]} rigid-body modes: the output does not fix the chain")
        return None, why
    Z = model.T @ phi
    w_in, w_out = axial_rotation(model, Z, load.input)[0], axial_rotation(model, Z, load.output)[0]
    if abs(w_out) <= 1e-12 * abs(w_in):
        return None, "the output stands still in the rigid-body mode"
    return float(w_in / w_out), "from the rigid-body mode of the unheld assembly (gear geometry)"
