"""Number of rigid-body (0 Hz) modes of an assembled model, from its structure alone.

The stiffness is a sum of positive semi-definite parts: every spring row
``k_j b_j b_j'`` (k_j > 0) and each flexible body's own stiffness. The null space of such
a sum is the intersection of the parts' null spaces, so it does not depend on the
stiffness values at all -- a mesh of 1e20 N/m or a polar inertia of 1e-300 kg m^2 cannot
change it, while counting eigenvalues below a fraction of the largest one can.

A flexible body's own stiffness vanishes exactly on its six rigid motions (a connected FE
body; a superelement, deflated by :func:`assembly.model.flexible.deflate_rigid`), so every
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
#: A lever arm (a translational spring's entry on a rotation) is a difference of
#: coordinates, known only to their rounding: its scale includes the magnitude of the
#: coordinates it comes from (:func:`coordinate_scale`), so an offset of 1 ulp -- a stage
#: centre typed as the repr of a derived number, a point computed on an axis not along x,
#: y or z -- counts as the zero it stands for, not as a lever arm that holds a free
#: rotation (its spring, k x (1 ulp)^2, lies far below any solve's round-off, which the
#: rigid-body check of :mod:`assembly.analysis.resolution` then confirms).
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


def coordinate_scale(model, el) -> float:
    """Largest coordinate magnitude (m) of the points a lever arm of element ``el`` is
    computed from: its point, and the position, axis point or component origin of each
    body it joins and of the frames those ride in."""
    frames = {b.name: b.frame for b in model.scene.bodies}
    pts = [np.asarray(el.point, float)]
    todo = [b for b in el.bodies if b is not None]
    while todo:
        bm = model.bodies[todo.pop()]
        pts += [np.asarray(getattr(bm, a), float) for a in ("position", "axis_point", "origin")
                if getattr(bm, a, None) is not None]
        if frames.get(bm.name) in model.bodies:
            todo.append(frames[bm.name])
    return float(max(np.abs(p).max() for p in pts))


def lever_weights(Bk: np.ndarray, ATW: np.ndarray) -> np.ndarray:
    """(rows x columns): how much each entry of the spring rows ``Bk @ ATW`` is a lever
    arm -- the row's weight on each body's translation times the column's rotation at that
    body's attachment -- per metre of lever arm."""
    out = np.zeros((Bk.shape[0], ATW.shape[1]))
    for j in range(Bk.shape[1] // 6):
        u = np.abs(Bk[:, 6 * j:6 * j + 3]).sum(axis=1)
        th = np.abs(np.asarray(ATW[6 * j + 3:6 * j + 6])).max(axis=0)
        out += np.outer(u, th)
    return out


def spring_rows(model, W: np.ndarray, operators: dict | None = None) -> np.ndarray:
    """Every spring row ``b_j A_e T W`` (one per non-zero stiffness), round-off entries
    zeroed, zero rows dropped, each row scaled to unit length. ``operators``: element index
    -> an attachment operator to use instead of the model's (e.g. with a hair offset
    removed, :mod:`assembly.analysis.lever_arms`)."""
    TW = model.T @ W
    absTW = abs(model.T) @ np.abs(W)
    rows = []
    for i, el in enumerate(model.elements):
        A = (operators or {}).get(i)
        if A is None:
            A = model.attachment_operator(el)
        Bk = el.B[el.k > 0]                    # a damper row without a spring stores no energy
        ATW = A @ TW
        G = Bk @ ATW
        scale = np.abs(Bk) @ (abs(A) @ absTW) + coordinate_scale(model, el) * lever_weights(Bk, ATW)
        G[np.abs(G) <= DROP_RTOL * scale.max(axis=1, keepdims=True)] = 0.0
        rows.append(G)
    G = np.vstack(rows) if rows else np.zeros((0, W.shape[1]))
    norms = np.linalg.norm(G, axis=1)
    keep = norms > 0
    return G[keep] / norms[keep, None]


def _null_space(model, operators: dict | None = None):
    """(``W``, ``V``): the zero-motion basis and the columns ``V`` (n_w x n_rigid) of its
    coefficients that no spring row strains (right singular vectors of the normalised rows
    below :data:`STRUCT_RTOL`; a coordinate no spring touches is one on its own).
    ``operators``: as :func:`spring_rows`."""
    W = zero_motion_basis(model)
    if W.shape[1] == 0:
        return W, np.zeros((0, 0))
    G = spring_rows(model, W, operators)
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


def rigid_body_count(model, operators: dict | None = None) -> int:
    """Number of independent zero-energy motions (rigid-body modes) of ``model``
    (``operators``: as :func:`spring_rows`)."""
    return _null_space(model, operators)[1].shape[1]


def rigid_body_modes(model) -> np.ndarray:
    """(n_q x n_rigid): a basis of the rigid-body modes of ``model`` on q, from its structure
    (not mass-normalised): every motion in it strains no spring and no flexible body."""
    W, V = _null_space(model)
    return W @ V
