"""Number of rigid-body (0 Hz) modes of an assembled model, from its structure alone.

The stiffness is a sum of positive semi-definite parts: every spring row
``k_j b_j b_j'`` (k_j > 0) and each flexible body's own stiffness. The null space of such
a sum is the intersection of the parts' null spaces, so it does not depend on the
stiffness values at all -- a mesh of 1e20 N/m or a polar inertia of 1e-300 kg m^2 cannot
change it, while counting eigenvalues below a fraction of the largest one can.

A flexible body's own stiffness vanishes exactly on its six rigid motions (a connected FE
body; a superelement, deflated by :func:`assembly.flexible.deflate_rigid`), so every
zero-energy motion moves each flexible body rigidly. The count is therefore the nullity of
the spring rows restricted to ``W``: the free coordinates of the rigid bodies and the six
rigid motions of each flexible body. Each row is scaled to unit length (the stiffness
drops out) and each column to unit length (metres against radians, lever arms), and the
rank is read from the singular values with :data:`STRUCT_RTOL`.
"""
from __future__ import annotations

import numpy as np

#: Singular values of the row- and column-normalised spring matrix below this fraction of
#: the largest count as zero. Dependent rows give ~1e-16 (round-off of the unit rows); a
#: stiffness direction with a singular value s carries s^2 of a typical spring's
#: stiffness, so s = 1e-8 is an eigenvalue ratio of 1e-16, below double precision
#: anyway.
STRUCT_RTOL = 1e-8
#: Entries of a spring row below this fraction of the row's round-off scale
#: (|b| |A| |T| |W|, the sum of the magnitudes multiplied) are round-off of a product
#: that vanishes exactly (e.g. a planet bearing row seen from a torsional carrier).
DROP_RTOL = 1e-10


def zero_motion_basis(model) -> np.ndarray:
    """``W`` (n_q x n_w): columns spanning every motion that strains no body -- the free
    coordinates of each rigid body and the six rigid motions of each flexible body."""
    blocks = []
    for name, bm in model.bodies.items():
        sl = model.q_slices[name]
        n = sl.stop - sl.start
        if n == 0:
            continue
        local = np.asarray(bm.rigid_local) if bm.flexible else np.eye(n)
        W = np.zeros((model.K.shape[0], local.shape[1]))
        W[sl] = local
        blocks.append(W)
    return np.hstack(blocks) if blocks else np.zeros((model.K.shape[0], 0))


def spring_rows(model, W: np.ndarray) -> np.ndarray:
    """Every spring row ``b_j A_e T W`` (one per non-zero stiffness), round-off entries
    zeroed, zero rows dropped, each row scaled to unit length."""
    TW = model.T @ W
    absTW = abs(model.T) @ np.abs(W)
    rows = []
    for el in model.elements:
        A = model.attachment_operator(el)
        G = el.B[el.k > 0] @ (A @ TW)          # a damper row without a spring stores no energy
        scale = np.abs(el.B[el.k > 0]) @ (abs(A) @ absTW)
        G[np.abs(G) <= DROP_RTOL * scale.max(axis=1, keepdims=True)] = 0.0
        rows.append(G)
    G = np.vstack(rows) if rows else np.zeros((0, W.shape[1]))
    norms = np.linalg.norm(G, axis=1)
    keep = norms > 0
    return G[keep] / norms[keep, None]


def _null_space(model):
    """(``W``, ``V``): the zero-motion basis and the columns ``V`` (n_w x n_rigid) of its
    coefficients that no spring row strains (right singular vectors of the normalised rows
    below :data:`STRUCT_RTOL`; a coordinate no spring touches is one on its own)."""
    W = zero_motion_basis(model)
    if W.shape[1] == 0:
        return W, np.zeros((0, 0))
    G = spring_rows(model, W)
    if G.shape[0] == 0:
        return W, np.eye(W.shape[1])
    cn = np.linalg.norm(G, axis=0)
    on = cn > 0
    _, s, Vt = np.linalg.svd(G[:, on] / cn[on], full_matrices=True)
    rank = int(np.sum(s > STRUCT_RTOL * s[0])) if len(s) and s[0] > 0 else 0
    V = np.zeros((W.shape[1], int(on.sum()) - rank + int((~on).sum())))
    V[np.flatnonzero(on), :int(on.sum()) - rank] = Vt[rank:].T / cn[on][:, None]
    V[np.flatnonzero(~on), int(on.sum()) - rank:] = np.eye(int((~on).sum()))
    return W, V


def rigid_body_count(model) -> int:
    """Number of independent zero-energy motions (rigid-body modes) of ``model``."""
    return _null_space(model)[1].shape[1]


def rigid_body_modes(model) -> np.ndarray:
    """(n_q x n_rigid): a basis of the rigid-body modes of ``model`` on q, from its structure
    (not mass-normalised): every motion in it strains no spring and no flexible body."""
    W, V = _null_space(model)
    return W @ V
