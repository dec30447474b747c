"""Interface couplings: rigid spider (RBE2-like) and distributing coupling (RBE3-like).

Both tie an interface's slave nodes to a 6-DOF master node at position x_m
with DOFs q_m = [ux, uy, uz, rx, ry, rz] in GLOBAL axes (m, rad).  For a slave
node at x_i with r_i = x_i - x_m, the rigid-body kinematics is

    u_i = u_m + theta_m x r_i = G_i q_m,   G_i = [I, -[r_i]x]   (3 x 6).

RBE2 ("rbe2"): the slave DOFs are eliminated exactly, u_s = G q_m.  This adds
stiffness (the interface moves rigidly).

RBE3 ("rbe3"): the master is the weighted least-squares rigid fit of the slave
motion, q_m = A u_s with A = (G^T W G)^-1 G^T W (W = diag of the weights;
uniform weights, the Nastran RBE3 default).  A G = I, so a rigid motion of
the slaves gives exactly that motion at the master.  The master becomes a
coordinate by an invertible change of variables on the slave DOFs: six pivot
slave DOFs p (chosen by QR with column pivoting of A) are replaced by q_m,

    u_p = A_p^-1 (q_m - A_o u_o),   u_o kept (they join the interior DOFs).

T is square and invertible for RBE3-only couplings, so K_c = T^T K T and
M_c = T^T M T have exactly the eigenvalues of the free body (RBE3 adds no
stiffness).  A master force f_m is carried by slave forces f_s = A^T f_m,
i.e. f_s = W G (G^T W G)^-1 f_m -- the classical RBE3 distribution.

Reduced coordinates q_c: first the retained full-model DOFs in ascending
order, then 6 DOFs per master in interface order; ``u_full = T @ q_c``.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Mapping

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from .errors import CouplingError
from .fe_model import FEModel

log = logging.getLogger(__name__)

KINDS = ("rbe2", "rbe3")


@dataclass
class CoupledModel:
    """A component with its interfaces coupled to 6-DOF master nodes.

    K_c, M_c : CSR matrices on q_c (SI).  T : CSR (n_full, n_c), u_full = T @ q_c.
    boundary_dofs : int array into q_c, every master DOF (interface order).
    masters : list of (name, position (3,) [m], 6 indices into q_c ordered
        [ux, uy, uz, rx, ry, rz], global axes).
    kinds : coupling kind used per interface.
    retained : full-model DOF represented by each non-master coordinate q_c[:len(retained)].
    """

    K_c: sp.csr_matrix
    M_c: sp.csr_matrix
    T: sp.csr_matrix
    boundary_dofs: np.ndarray
    masters: list[tuple[str, np.ndarray, np.ndarray]]
    kinds: dict[str, str]
    model: FEModel
    retained: np.ndarray

    def master_index(self, name: str) -> np.ndarray:
        for n, _, idx in self.masters:
            if n == name:
                return idx
        raise KeyError(name)


def rigid_kinematics(points: np.ndarray, master: np.ndarray) -> np.ndarray:
    """G (3n x 6) with u = G q_m for the rigid motion q_m of a master at ``master``; rows node-major."""
    r = np.asarray(points, dtype=float) - np.asarray(master, dtype=float)[None, :]
    n = len(r)
    G = np.zeros((n, 3, 6))
    G[:, 0, 0] = G[:, 1, 1] = G[:, 2, 2] = 1.0
    # -[r]x theta = theta x r
    G[:, 0, 4], G[:, 0, 5] = r[:, 2], -r[:, 1]
    G[:, 1, 3], G[:, 1, 5] = -r[:, 2], r[:, 0]
    G[:, 2, 3], G[:, 2, 4] = r[:, 1], -r[:, 0]
    return G.reshape(3 * n, 6)


def rbe3_operator(points: np.ndarray, master: np.ndarray, weights: np.ndarray | None = None) -> np.ndarray:
    """A (6 x 3n): master motion = weighted least-squares rigid fit of the slave displacements."""
    G = rigid_kinematics(points, master)
    w = np.ones(len(points)) if weights is None else np.asarray(weights, dtype=float)
    Wd = np.repeat(w, 3)
    GtWG = G.T @ (Wd[:, None] * G)
    if np.linalg.cond(GtWG) > 1e12:
        raise CouplingError("rbe3", len(points), "slave nodes are (nearly) collinear: master rotation undefined")
    return np.linalg.solve(GtWG, (G * Wd[:, None]).T)


def couple(model: FEModel, kinds: Mapping[str, str] | None = None) -> CoupledModel:
    """Couple every interface of ``model`` to its master node.

    kinds : per-interface "rbe2" or "rbe3"; interfaces not named use their default
        (``Interface.coupling``: gear_mesh -> rbe3, bearing seats/bores/pins -> rbe2).
    """
    kinds = dict(kinds or {})
    unknown = set(kinds) - set(model.interfaces)
    if unknown:
        name = sorted(unknown)[0]
        raise CouplingError(name, kinds[name], f"no such interface (have {sorted(model.interfaces)})")
    n_full = model.n_dofs
    nodes = model.nodes
    owner = np.full(model.n_nodes, -1)
    names = list(model.interfaces)
    for k, name in enumerate(names):
        iface = model.interfaces[name]
        clash = owner[iface.nodes] >= 0
        if np.any(clash):
            other = names[owner[iface.nodes[clash][0]]]
            raise CouplingError(name, int(clash.sum()), f"shares nodes with interface {other!r}")
        owner[iface.nodes] = k

    eliminated = np.zeros(n_full, dtype=bool)  # full DOFs replaced by master coordinates
    rows, cols, vals = [], [], []  # entries of T: (full dof, "col key", value)
    # master columns are numbered after the retained DOFs; use provisional negative keys
    master_blocks = []
    used: dict[str, str] = {}
    for k, name in enumerate(names):
        iface = model.interfaces[name]
        kind = kinds.get(name, iface.coupling)
        if kind not in KINDS:
            raise CouplingError(name, kind, f"coupling kind must be one of {KINDS}")
        used[name] = kind
        pts = nodes[iface.nodes]
        sdofs = iface.dofs().ravel()  # node-major, matches G rows
        mcols = -(6 * k + np.arange(6)) - 1  # provisional keys for this master's 6 columns
        if kind == "rbe2":
            G = rigid_kinematics(pts, iface.master)
            eliminated[sdofs] = True
            r, c = np.nonzero(G)
            rows.append(sdofs[r]); cols.append(mcols[c]); vals.append(G[r, c])
        else:
            A = rbe3_operator(pts, iface.master)
            _, _, piv = sla.qr(A, mode="economic", pivoting=True)
            p, o = piv[:6], piv[6:]
            Ap_inv = np.linalg.inv(A[:, p])
            B = -Ap_inv @ A[:, o]  # (6, n_o): u_p contribution of the kept slave DOFs
            eliminated[sdofs[p]] = True
            # u_p = Ap_inv q_m + B u_o
            rr, cc = np.meshgrid(np.arange(6), np.arange(6), indexing="ij")
            rows.append(sdofs[p][rr.ravel()]); cols.append(mcols[cc.ravel()]); vals.append(Ap_inv.ravel())
            rr, cc = np.meshgrid(np.arange(6), np.arange(len(o)), indexing="ij")
            rows.append(sdofs[p][rr.ravel()]); cols.append(sdofs[o][cc.ravel()]); vals.append(B.ravel())
        master_blocks.append((name, iface.master.copy(), mcols))

    retained = np.flatnonzero(~eliminated)
    n_ret = len(retained)
    col_of_full = np.full(n_full, -1)
    col_of_full[retained] = np.arange(n_ret)
    # identity part for retained DOFs
    rows.append(retained); cols.append(retained); vals.append(np.ones(n_ret))
    R = np.concatenate(rows)
    C = np.concatenate(cols)
    V = np.concatenate(vals)
    is_master = C < 0
    Cm = np.empty_like(C)
    Cm[~is_master] = col_of_full[C[~is_master]]
    Cm[is_master] = n_ret + (-C[is_master] - 1)
    if np.any(Cm < 0):  # pragma: no cover - internal consistency
        raise RuntimeError("coupling references an eliminated DOF")
    n_c = n_ret + 6 * len(names)
    T = sp.csr_matrix((V, (R, Cm)), shape=(n_full, n_c))
    T.eliminate_zeros()
    K_c = (T.T @ model.K @ T).tocsr()
    M_c = (T.T @ model.M @ T).tocsr()
    K_c = ((K_c + K_c.T) * 0.5).tocsr()  # remove round-off asymmetry
    M_c = ((M_c + M_c.T) * 0.5).tocsr()
    masters = [(name, pos, n_ret + 6 * k + np.arange(6)) for k, (name, pos, _) in enumerate(master_blocks)]
    boundary = np.arange(n_ret, n_c)
    log.info("coupled %s: %d full DOFs -> %d (%d master DOFs)", ", ".join(f"{n}:{used[n]}" for n in names),
             n_full, n_c, len(boundary))
    return CoupledModel(K_c, M_c, T, boundary, masters, used, model, retained)
