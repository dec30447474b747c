"""Rigid (RBE2-type) coupling of node sets to 6-DOF master nodes, by elimination.

Used by the cms tests and benchmark to build interfaces the way the assembly
uses them (``fe_components`` has its own coupling step; the reductor takes its
``K_c, M_c, boundary_dofs`` unchanged).

Every slave node s of set k follows its master rigidly (small rotations):
    u_s = t_k + theta_k x (p_s - p_k) = t_k - [p_s - p_k]~ theta_k.
Coupled coordinates: the non-slave DOFs of the solid in their original order,
then [ux, uy, uz, rx, ry, rz] of each master (m, rad). u_full = T @ q_c, and
K_c = T^T K T, M_c = T^T M T (masters carry no mass of their own).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from . import rigid
from .errors import ReductionError


@dataclass
class RigidCoupling:
    T: sp.csr_matrix               # (n_full, n_c)
    K: sp.csr_matrix               # coupled stiffness T^T K T
    M: sp.csr_matrix               # coupled mass T^T M T
    boundary_dofs: np.ndarray      # the 6 * n_masters master DOFs in coupled numbering
    master_points: np.ndarray      # (n_masters, 3), m
    dof_points: np.ndarray         # (n_c, 3) location of each coupled DOF, m
    dof_kinds: np.ndarray          # (n_c,) 0..5 = ux, uy, uz, rx, ry, rz
    boundary_names: list           # names of the master DOFs, e.g. "if0:rz"

    @property
    def dof_layout(self):
        return self.dof_points, self.dof_kinds

    @property
    def rigid_body_basis(self) -> np.ndarray:
        return rigid.rigid_body_basis(self.dof_points, self.dof_kinds)


def couple_rigid(K, M, node_coords, slave_node_sets, master_points=None,
                 names=None) -> RigidCoupling:
    """Tie each node set in ``slave_node_sets`` rigidly to a master node.

    ``node_coords``: (n/3, 3) node positions (DOF order 3*node + xyz);
    ``master_points``: (n_sets, 3), default the centroid of each set;
    ``names``: interface names (default ``"if0"``, ``"if1"``, ...).
    """
    X = np.asarray(node_coords, dtype=float)
    n = K.shape[0]
    if 3 * len(X) != n:
        raise ReductionError("node_coords must have n/3 rows", "node_coords.shape", X.shape)
    sets = [np.unique(np.asarray(s, dtype=np.int64)) for s in slave_node_sets]
    allslaves = np.concatenate(sets) if sets else np.zeros(0, dtype=np.int64)
    if len(np.unique(allslaves)) != len(allslaves):
        raise ReductionError("slave node sets overlap", "slave_node_sets",
                             int(len(allslaves) - len(np.unique(allslaves))))
    if master_points is None:
        master_points = np.array([X[s].mean(axis=0) for s in sets])
    master_points = np.asarray(master_points, dtype=float).reshape(-1, 3)
    names = names or [f"if{k}" for k in range(len(sets))]
    is_slave = np.zeros(n, dtype=bool)
    for s in sets:
        is_slave[(3 * s[:, None] + np.arange(3)).ravel()] = True
    keep = np.flatnonzero(~is_slave)
    nk = len(keep)
    nc = nk + 6 * len(sets)
    rows, cols, vals = [keep], [np.arange(nk)], [np.ones(nk)]
    for k, s in enumerate(sets):
        d = X[s] - master_points[k]                    # lever arms (ns, 3)
        base = nk + 6 * k
        for a in range(3):                             # displacement component a of slave
            r = 3 * s + a
            rows.append(r); cols.append(np.full(len(s), base + a)); vals.append(np.ones(len(s)))
            for j in range(3):                         # rotation theta_j contributes (e_j x d)_a
                coeff = np.cross(np.eye(3)[j], d)[:, a]
                nz = coeff != 0
                rows.append(r[nz]); cols.append(np.full(nz.sum(), base + 3 + j))
                vals.append(coeff[nz])
    T = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(n, nc))
    Kc = (T.T @ K @ T).tocsr()
    Mc = (T.T @ M @ T).tocsr()
    pts = np.vstack([np.repeat(X, 3, axis=0)[keep], np.repeat(master_points, 6, axis=0)])
    kinds = np.concatenate([np.tile(np.arange(3), len(X))[keep], np.tile(np.arange(6), len(sets))])
    bdofs = np.arange(nk, nc)
    dof_names = [f"{names[k]}:{c}" for k in range(len(sets))
                 for c in ("ux", "uy", "uz", "rx", "ry", "rz")]
    return RigidCoupling(T, Kc, Mc, bdofs, master_points, pts, kinds, dof_names)
