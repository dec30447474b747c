"""Per-mode energy bookkeeping: kinetic share of each body, strain share of each spring
and of each flexible body, and kinetic energy split by motion type (in-plane, axial, tilt, spin) in each body's axes."""
from __future__ import annotations

import numpy as np

#: Motion categories of a body in its own axes (z = rotation axis); "elastic" is the
#: kinetic energy of a flexible body beyond its rigid-equivalent motion.
CATEGORIES = ("inplane", "axial", "tilt", "spin", "elastic")


def kinetic_by_body(result) -> np.ndarray:
    """(n_modes, n_bodies) kinetic-energy shares (rows sum to 1; zero rows for no motion)."""
    return _normalise(kinetic_energy_by_body(result))


def kinetic_energy_by_body(result) -> np.ndarray:
    """(n_modes, n_bodies) z_b' M_b z_b of each body (mass-normalised modes: shares of 1)."""
    m = result.model
    Z = result.abs_shapes
    cols = []
    for b in m.bodies:
        sl = m.body_slice(b)
        Mb = m.M_abs[sl, sl]
        cols.append(np.einsum("im,im->m", Z[sl], np.asarray(Mb @ Z[sl])))
    return np.column_stack(cols)


def strain_by_element(result) -> np.ndarray:
    """(n_modes, n_elements) strain-energy shares of the springs (rows sum to 1, or 0)."""
    m = result.model
    E = np.column_stack([_element_energy(m, el, result.abs_shapes) for el in m.elements]) \
        if m.elements else np.zeros((result.abs_shapes.shape[1], 0))
    return _normalise(E)


#: A flexible body whose share of a mode's total strain energy is below this carries no
#: stress worth drawing in that mode: its back-expanded stresses are round-off of the
#: reduction (relative size ~cond(K) x machine epsilon), not a stress field.
NEGLIGIBLE_STRAIN_SHARE = 1e-6


def strain_by_body(result) -> np.ndarray:
    """(n_modes, n_bodies) share of each body's elastic strain energy ``z_b' K_b z_b / 2`` in
    the mode's total strain energy ``z' K_abs z / 2`` (springs included); 0 for rigid bodies
    (their K_b is zero) and for modes without strain energy (rigid-body modes)."""
    m = result.model
    Z = result.abs_shapes
    E = np.zeros((Z.shape[1], len(m.bodies)))
    for j, (name, bm) in enumerate(m.bodies.items()):
        if bm.flexible:
            sl = m.body_slice(name)
            E[:, j] = np.einsum("im,im->m", Z[sl], np.asarray(bm.stiffness_matrix() @ Z[sl]))
    total = np.einsum("im,im->m", Z, np.asarray(m.K_abs @ Z))
    # a total below round-off of the largest mode's: no strain energy at all (rigid-body mode)
    has = total > 1e-12 * np.abs(total).max(initial=0.0)
    return np.where(has[:, None], np.clip(E, 0.0, None) / np.where(has, total, 1.0)[:, None], 0.0)


def _element_energy(model, el, Z) -> np.ndarray:
    e = el.B @ (model.attachment_operator(el) @ Z)
    return 0.5 * np.einsum("rm,r,rm->m", e, el.k, e)


def kinetic_by_category(result) -> np.ndarray:
    """(n_modes, n_bodies, 4) kinetic energy (unnormalised) per body and CATEGORIES entry."""
    m = result.model
    out = np.zeros((result.abs_shapes.shape[1], len(m.bodies), len(CATEGORIES)))
    total = kinetic_energy_by_body(result)
    for j, (name, bm) in enumerate(m.bodies.items()):
        z = bm.rigid_projection() @ result.abs_shapes[m.body_slice(name)]
        R = bm.axes
        u = R.T @ z[:3]
        th = R.T @ z[3:]
        Jl = R.T @ bm.inertia @ R
        rot = np.einsum("im,ij,jm->m", th, Jl, th)
        spin = Jl[2, 2] * th[2] ** 2
        out[:, j, 0] = bm.mass * (u[0] ** 2 + u[1] ** 2)
        out[:, j, 1] = bm.mass * u[2] ** 2
        out[:, j, 2] = rot - spin
        out[:, j, 3] = spin
        out[:, j, 4] = np.clip(total[:, j] - out[:, j, :4].sum(axis=1), 0.0, None)
    return out


def _normalise(E: np.ndarray) -> np.ndarray:
    tot = E.sum(axis=1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        S = np.where(tot > 0, E / np.where(tot > 0, tot, 1.0), 0.0)
    return S
