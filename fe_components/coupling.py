"""Interface couplings: rigid spider (RBE2-like) and distributing coupling (RBE3-like).

Both tie an interface's slave nodes to a 6-DOF master node at position x_m
with DOFs q_m = [ux, uy, uz, rx, ry, rz] in GLOBAL axes (m, rad).  For a slave
node at x_i with r_i = x_i - x_m, the rigid-body kinematics is

    u_i = u_m + theta_m x r_i = G_i q_m,   G_i = [I, -[r_i]x]   (3 x 6).

RBE2 ("rbe2"): the slave DOFs are eliminated exactly, u_s = G q_m.  This adds
stiffness (the interface moves rigidly).

RBE3 ("rbe3"): the master is the weighted least-squares rigid fit of the slave
motion, q_m = A u_s with A = H^-1 G^T W, H = G^T W G (W = diag of the weights;
uniform weights, the Nastran RBE3 default).  A G = I, so a rigid motion of
the slaves gives exactly that motion at the master.  The master becomes a
coordinate by an invertible change of variables u_s = T_s [q_m; r] with
A T_s = [I, 0] (r spans the null space of A and joins the interior DOFs).

T_s = [G, N]: the master columns are the rigid motion of the slaves (A G = I)
and N is a sparse, well-conditioned basis of null(A) built on a binary
cluster tree of the slave nodes (a single pivot elimination would couple
every slave DOF to every other one: a dense (3 n_s)^2 block in K_c).
Leaf cluster c (3..6 nodes): six QR-pivoted DOFs p follow the others so that
the leaf's own fit stays zero, u_p = -A_cp^-1 A_co u_o (u_o kept).  Parent S
of children i, k (H_i = G_i^T W_i G_i, fit_S = sum_i H_S^-1 H_i fit_i): six
columns "rigid motion e of child i, compensated by the rigid motion
-(H_S^-1 H_k)^-1 (H_S^-1 H_i) e of child k" have zero fit on S.  Columns are
O(1), each node lies in ~log2(n_s) of them.

T is square and invertible for RBE3-only couplings, so K_c = T^T K T and
M_c = T^T M T have exactly the eigenvalues of the free body (RBE3 adds no
stiffness).  A master force f_m is carried by slave forces f_s = A^T f_m,
i.e. f_s = W G (G^T W G)^-1 f_m -- the classical RBE3 distribution.

Reduced coordinates q_c: first the interior coordinates (retained full-model
DOFs in ascending order, then the RBE3 cluster coordinates), then 6 DOFs per
master in interface order; ``u_full = T @ q_c``.

Entry points: :func:`couple` for the interfaces of an :class:`FEModel`, and
:func:`couple_nodes` for node sets of any solid given as arrays (K, M, node
positions); the first is a thin wrapper over the second.
"""
from __future__ import annotations

import functools
import logging
from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from .errors import CouplingError
from .fe_model import FEModel

log = logging.getLogger(__name__)

KINDS = ("rbe2", "rbe3")

#: Names of a master node's six coordinates, in their order in q_c.
MASTER_DOF_NAMES = ("ux", "uy", "uz", "rx", "ry", "rz")

#: name -> (node indices, master position (3,) [m], kind "rbe2" | "rbe3"): the array-level
#: description of interfaces taken by :func:`couple_nodes`.
NodeInterfaces = Mapping[str, tuple]


@dataclass
class CoupledModel:
    """A component with its interfaces coupled to 6-DOF master nodes.

    K_c, M_c : CSR matrices on q_c (SI), projected on first use (``projection``: back-expansion
        needs ``T`` only).  T : CSR (n_full, n_c), u_full = T @ q_c.
    boundary_dofs : int array into q_c, every master DOF (interface order).
    masters : list of (name, position (3,) [m], 6 indices into q_c ordered
        [ux, uy, uz, rx, ry, rz], global axes).
    kinds : coupling kind used per interface.
    retained : full-model DOF equal to each of the first len(retained) coordinates (DOFs of
        no interface); the RBE3 null-space coordinates follow them, then the masters.
    model : the FE model coupled by :func:`couple`; ``None`` from :func:`couple_nodes`.
    nodes : (n_full / 3, 3) node positions of the full model [m].
    """

    projection: Callable[[], tuple] = field(repr=False, compare=False)  # -> (K_c, M_c)
    T: sp.csr_matrix
    boundary_dofs: np.ndarray
    masters: list[tuple[str, np.ndarray, np.ndarray]]
    kinds: dict[str, str]
    retained: np.ndarray
    model: FEModel | None = None
    nodes: np.ndarray | None = None

    @functools.cached_property
    def _KM(self) -> tuple:
        return self.projection()

    @property
    def K_c(self) -> sp.csr_matrix:
        """Coupled stiffness T^T K T [N/m] (CSR)."""
        return self._KM[0]

    @property
    def M_c(self) -> sp.csr_matrix:
        """Coupled mass T^T M T [kg] (CSR)."""
        return self._KM[1]

    def master_index(self, name: str) -> np.ndarray:
        for n, _, idx in self.masters:
            if n == name:
                return idx
        raise KeyError(name)

    @property
    def boundary_names(self) -> list[str]:
        """Name of every master DOF, e.g. ``"bore:rz"``, in ``boundary_dofs`` order."""
        return [f"{name}:{d}" for name, _, _ in self.masters for d in MASTER_DOF_NAMES]

    def dof_layout(self, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(points (n_c, 3) [m], kinds (n_c,)) of every coupled coordinate: a retained DOF
        lies at its node (``nodes``, the full model's node positions) with kind 0, 1, 2
        (ux, uy, uz); a master DOF at its master with kind 0..5 (``MASTER_DOF_NAMES``).
        RBE3 null-space coordinates have no location: with any, raises CouplingError."""
        n_extra = self.T.shape[1] - len(self.retained) - len(self.boundary_dofs)
        if n_extra:
            name = next(n for n, k in self.kinds.items() if k == "rbe3")
            raise CouplingError(name, "rbe3", f"{n_extra} RBE3 null-space coordinates have no DOF location")
        nodes = np.asarray(nodes, dtype=float)
        points = np.vstack([nodes[self.retained // 3]] + [np.repeat(pos[None], 6, 0) for _, pos, _ in self.masters])
        kinds = np.concatenate([self.retained % 3] + [np.arange(6)] * len(self.masters))
        return points, kinds

    def rigid_body_basis(self, reference=(0.0, 0.0, 0.0)) -> np.ndarray:
        """(n_c, 6) rigid-body motions on q_c, columns [tx, ty, tz, rx, ry, rz] (m, rad) about
        ``reference`` (m): the basis a Craig-Bampton reductor needs for its mechanism and
        mass checks (``rigid_body_basis=``), for RBE2 and RBE3 couplings alike.

        Exact by construction: a retained DOF moves with its node, a master with its own
        point, and the RBE3 null-space coordinates are zero, since a rigid motion of the
        slaves is the master's rigid motion (A G = I). Checked: ``T R_c`` must reproduce
        the rigid motion of every full-model node."""
        if self.nodes is None:
            raise CouplingError("nodes", None, "this coupled model carries no node positions")
        ref = np.asarray(reference, dtype=float)
        full = rigid_kinematics(self.nodes, ref)                 # (n_full, 6), node-major rows
        R = np.zeros((self.T.shape[1], 6))
        R[:len(self.retained)] = full[self.retained]
        for _, pos, idx in self.masters:
            R[idx[:3]] = rigid_kinematics(pos[None], ref)             # the master point moves rigidly
            R[idx[3:]] = np.hstack([np.zeros((3, 3)), np.eye(3)])     # and turns with the body
        err = np.abs(self.T @ R - full).max() / max(np.abs(full).max(), 1e-300)
        if err > 1e-10:
            raise CouplingError("rigid_body_basis", float(err), "coupling does not reproduce rigid motion")
        return R


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
    interfaces = {name: (iface.nodes, iface.master, kinds.get(name, iface.coupling))
                  for name, iface in model.interfaces.items()}
    coupled = _couple(lambda: (model.K, model.M), model.n_dofs, model.nodes, interfaces)
    coupled.model = model
    return coupled


def couple_nodes(K: sp.spmatrix, M: sp.spmatrix, nodes: np.ndarray, interfaces: NodeInterfaces) -> CoupledModel:
    """Couple node sets of a solid to 6-DOF master nodes (RBE2 or RBE3, module doc).

    K, M : sparse (n, n) stiffness [N/m] and mass [kg], DOF ``3 * node + c`` (c = 0, 1, 2: x, y, z).
    nodes : (n / 3, 3) node positions [m].
    interfaces : name -> (node indices, master position (3,) [m], kind "rbe2" | "rbe3");
        the masters take this order in q_c.  Node sets must not share nodes.
    Returns a :class:`CoupledModel` with ``model=None``.
    """
    return _couple(lambda: (K, M), K.shape[0], nodes, interfaces)


def _couple(matrices: Callable[[], tuple], n_full: int, nodes, interfaces: NodeInterfaces) -> CoupledModel:
    """:func:`couple_nodes` with K, M from ``matrices()``, called when K_c or M_c is first
    needed (``n_full``: their size)."""
    nodes = np.asarray(nodes, dtype=float)
    if 3 * len(nodes) != n_full:
        raise CouplingError("nodes", nodes.shape, f"need K.shape[0] / 3 = {n_full / 3:g} node positions")
    ifaces = _checked_interfaces(len(nodes), interfaces)
    eliminated = np.zeros(n_full, dtype=bool)  # full DOFs replaced by master coordinates
    entries = ([], [], [])  # rows, column keys, values of T
    extra = _ExtraColumns()  # RBE3 cluster coordinates
    for k, (name, idx, master, kind) in enumerate(ifaces):
        # master columns are numbered after the interior ones: provisional negative keys
        mcols = -(6 * k + np.arange(6)) - 1
        _interface_entries(kind, nodes[idx], master, _node_dofs(idx), mcols, entries, eliminated, extra)
    T, retained, n_int = _transformation(n_full, entries, eliminated, extra.n, len(ifaces))
    masters = [(name, master.copy(), n_int + 6 * k + np.arange(6)) for k, (name, _, master, _) in enumerate(ifaces)]
    boundary = np.arange(n_int, T.shape[1])
    used = {name: kind for name, _, _, kind in ifaces}
    log.info("coupled %s: %d full DOFs -> %d (%d master DOFs)", ", ".join(f"{n}:{k}" for n, k in used.items()),
             n_full, T.shape[1], len(boundary))
    return CoupledModel(lambda: _projected(T, *matrices()), T, boundary, masters, used, retained, nodes=nodes)


def _checked_interfaces(n_nodes: int, interfaces: NodeInterfaces) -> list[tuple[str, np.ndarray, np.ndarray, str]]:
    """(name, node indices, master (3,), kind) per interface, after checking that node indices
    are in range, that no node belongs to two interfaces, and that every kind is known."""
    out = [(name, np.asarray(idx), np.asarray(master, dtype=float), kind)
           for name, (idx, master, kind) in interfaces.items()]
    owner = np.full(n_nodes, -1)
    for k, (name, idx, _, _) in enumerate(out):
        if idx.size and (idx.min() < 0 or idx.max() >= n_nodes):
            raise CouplingError(name, int(idx.min() if idx.min() < 0 else idx.max()),
                                f"node index outside 0..{n_nodes - 1}")
        clash = owner[idx] >= 0
        if np.any(clash):
            other = out[owner[idx[clash][0]]][0]
            raise CouplingError(name, int(clash.sum()), f"shares nodes with interface {other!r}")
        owner[idx] = k
    for name, _, _, kind in out:
        if kind not in KINDS:
            raise CouplingError(name, kind, f"coupling kind must be one of {KINDS}")
    return out


def _node_dofs(idx: np.ndarray) -> np.ndarray:
    """Full-model DOFs of nodes ``idx``, node-major (x, y, z per node): the rows of G."""
    return (3 * idx[:, None] + np.arange(3)[None, :]).ravel()


def _interface_entries(kind, pts, master, sdofs, mcols, entries, eliminated, extra) -> None:
    """Append one interface's entries of T: its master columns (the rigid motion of the slaves,
    u_s = G q_m) and, for RBE3, the null-space columns that keep the slave DOFs as coordinates."""
    rows, cols, vals = entries
    if kind == "rbe2":
        eliminated[sdofs] = True
    else:
        weights = np.ones(len(pts))
        tree = _rbe3_tree(pts, master, weights, np.arange(len(pts)))
        _rbe3_rec(tree, pts, master, weights, sdofs, rows, cols, vals, eliminated, extra)
    G = rigid_kinematics(pts, master)
    r, c = np.nonzero(G)
    rows.append(sdofs[r]); cols.append(mcols[c]); vals.append(G[r, c])


def _transformation(n_full, entries, eliminated, n_extra, n_masters):
    """T (CSR, n_full x n_c) from the collected entries plus the identity on the retained DOFs;
    column keys become q_c indices: retained DOFs, then RBE3 coordinates, then masters.
    Returns (T, retained full DOFs, number of interior coordinates)."""
    rows, cols, vals = entries
    retained = np.flatnonzero(~eliminated)
    n_ret = len(retained)
    col_of_full = np.full(n_full, -1)
    col_of_full[retained] = np.arange(n_ret)
    rows.append(retained); cols.append(retained); vals.append(np.ones(n_ret))
    R = np.concatenate(rows)
    C = np.concatenate(cols)
    V = np.concatenate(vals)
    n_int = n_ret + n_extra
    is_master = C < 0
    is_extra = C >= _EXTRA_BASE
    is_full = ~is_master & ~is_extra
    Cm = np.empty_like(C)
    Cm[is_full] = col_of_full[C[is_full]]
    Cm[is_extra] = n_ret + (C[is_extra] - _EXTRA_BASE)
    Cm[is_master] = n_int + (-C[is_master] - 1)
    if np.any(Cm < 0):  # pragma: no cover - internal consistency
        raise RuntimeError("coupling references an eliminated DOF")
    n_c = n_int + 6 * n_masters
    T = sp.csr_matrix((V, (R, Cm)), shape=(n_full, n_c))  # duplicates are summed
    T.eliminate_zeros()
    return T, retained, n_int


def _projected(T, K, M):
    """K_c = T^T K T and M_c = T^T M T (CSR), symmetrised to remove round-off asymmetry."""
    K_c = (T.T @ K @ T).tocsr()
    M_c = (T.T @ M @ T).tocsr()
    K_c = ((K_c + K_c.T) * 0.5).tocsr()
    M_c = ((M_c + M_c.T) * 0.5).tocsr()
    return K_c, M_c


# ---------------------------------------------------------------- RBE3 cluster tree
_EXTRA_BASE = 1 << 40  # provisional column keys of RBE3 cluster coordinates
LEAF_NODES = 6  # leaf clusters hold 3..6 nodes


class _ExtraColumns:
    def __init__(self) -> None:
        self.n = 0

    def new(self, k: int) -> np.ndarray:
        keys = _EXTRA_BASE + self.n + np.arange(k)
        self.n += k
        return keys


def _H(pts: np.ndarray, master: np.ndarray, w: np.ndarray) -> np.ndarray:
    G = rigid_kinematics(pts, master)
    return G.T @ (np.repeat(w, 3)[:, None] * G)


def _well_posed(pts, master, w) -> bool:
    return len(pts) >= 3 and np.linalg.cond(_H(pts, master, w)) < 1e10


def _rbe3_tree(pts, master, w, idx):
    """Binary tree of node-index arrays: split along the principal axis while both halves stay well posed."""
    if len(idx) > LEAF_NODES:
        x = pts[idx] - pts[idx].mean(axis=0)
        axis = np.linalg.svd(x, full_matrices=False)[2][0]
        order = idx[np.argsort(x @ axis, kind="stable")]
        half = len(order) // 2
        a, b = order[:half], order[half:]
        if _well_posed(pts[a], master, w[a]) and _well_posed(pts[b], master, w[b]):
            return (_rbe3_tree(pts, master, w, a), _rbe3_tree(pts, master, w, b))
    return idx


def _rbe3_rec(tree, pts, master, w, sdofs, rows, cols, vals, eliminated, extra):
    """Emit the interior (null-space) columns of a subtree; return (its node indices, H_subtree)."""
    if isinstance(tree, np.ndarray):  # leaf: DOFs with zero leaf fit, by pivot elimination in the leaf
        idx = tree
        dofs = (3 * idx[:, None] + np.arange(3)).ravel()  # local slave DOFs (node-major)
        A = rbe3_operator(pts[idx], master, w[idx])
        _, _, piv = sla.qr(A, mode="economic", pivoting=True)
        p, o = piv[:6], piv[6:]
        B = -np.linalg.solve(A[:, p], A[:, o])
        gp, go = sdofs[dofs[p]], sdofs[dofs[o]]
        eliminated[gp] = True
        eliminated[go] = True  # replaced by null-space coordinates (u_o is not their value)
        keys = extra.new(len(o))  # column j: 1 at DOF o_j, B[:, j] at the pivots
        rows.append(go); cols.append(keys); vals.append(np.ones(len(o)))
        rr, cc = np.meshgrid(np.arange(6), np.arange(len(o)), indexing="ij")
        rows.append(gp[rr.ravel()]); cols.append(keys[cc.ravel()]); vals.append(B.ravel())
        return idx, _H(pts[idx], master, w[idx])
    children = [_rbe3_rec(t, pts, master, w, sdofs, rows, cols, vals, eliminated, extra) for t in tree]
    H_S = sum(h for _, h in children)
    S = [np.linalg.solve(H_S, h) for _, h in children]  # fit of S = sum_i S_i (fit of child i)
    k = int(np.argmax([np.linalg.eigvalsh(h)[0] / np.linalg.eigvalsh(h)[-1] for _, h in children]))
    idx_k = children[k][0]
    G_k = rigid_kinematics(pts[idx_k], master)
    dofs_k = sdofs[(3 * idx_k[:, None] + np.arange(3)).ravel()]
    for i, (idx_i, _) in enumerate(children):
        if i == k:
            continue
        # rigid motion e of child i, compensated by child k so that the fit of S stays zero
        keys = extra.new(6)
        G_i = rigid_kinematics(pts[idx_i], master)
        dofs_i = sdofs[(3 * idx_i[:, None] + np.arange(3)).ravel()]
        Ck = -G_k @ np.linalg.solve(S[k], S[i])
        for Gm, d in ((G_i, dofs_i), (Ck, dofs_k)):
            r, c = np.nonzero(np.abs(Gm) > 0)
            rows.append(d[r]); cols.append(keys[c]); vals.append(Gm[r, c])
    return np.concatenate([c[0] for c in children]), H_S
