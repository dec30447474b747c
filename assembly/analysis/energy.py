"""Per-mode energy bookkeeping: kinetic share of each body, strain share of each spring
and of each flexible body, and kinetic energy split by motion type (in-plane, axial, tilt, spin) in each body's axes."""
from __future__ import annotations

import numpy as np

#: Motion categories of a body in its own axes (z = rotation axis); "elastic" is the
#: kinetic energy of a flexible body beyond its rigid-equivalent motion.
CATEGORIES = ("inplane", "axial", "tilt", "spin", "elastic")


def kinetic_by_body(result) -> np.ndarray:
    """(n_modes, n_bodies) kinetic-energy shares of the bodies alone (rows sum to 1; zero
    rows for no motion). The half masses a beam shaft lumps at its end bodies belong to its
    elements (:func:`kinetic_by_element`), not to those bodies; its stations are bodies."""
    return _normalise(kinetic_energy_by_body(result))


def kinetic_by_element(result) -> np.ndarray:
    """(n_modes, n_elements) ``w' M_e w`` of each element's own mass ``M_e`` on its
    attachment motions ``w`` (zero for a massless spring), on the scale of
    :func:`kinetic_energy_by_body`: with it, the mode's total ``z' M_abs z``."""
    m = result.model
    Z = result.abs_shapes
    E = np.zeros((Z.shape[1], len(m.elements)))
    for j, el in enumerate(m.elements):
        if el.mass is not None:
            w = m.attachment_operator(el) @ Z
            E[:, j] = np.einsum("rm,rs,sm->m", w, el.mass, w)
    return E


def kinetic_energy_by_body(result) -> np.ndarray:
    """(n_modes, n_bodies) z_b' M_b z_b of each body with its own mass matrix M_b
    (mass-normalised modes: shares of 1 less what elements carrying mass hold)."""
    m = result.model
    Z = result.abs_shapes
    cols = []
    for b, bm in m.bodies.items():
        sl = m.body_slice(b)
        cols.append(np.einsum("im,im->m", Z[sl], np.asarray(bm.mass_matrix() @ Z[sl])))
    return np.column_stack(cols)


def strain_energy_by_element(result) -> np.ndarray:
    """(n_modes, n_elements) strain energy ``e' diag(k) e / 2`` of each spring (J for a
    mode of modal mass 1 kg, amplitude 1)."""
    m = result.model
    if not m.elements:
        return np.zeros((result.abs_shapes.shape[1], 0))
    return np.column_stack([element_strain_energy(m, el, result.abs_shapes) for el in m.elements])


def strain_energy_by_body(result) -> np.ndarray:
    """(n_modes, n_bodies) elastic strain energy ``z_b' K_b z_b / 2`` of each body (J; 0
    for rigid bodies, whose K_b is zero)."""
    m = result.model
    Z = result.abs_shapes
    E = np.zeros((Z.shape[1], len(m.bodies)))
    for j, (name, bm) in enumerate(m.bodies.items()):
        if bm.flexible:
            sl = m.body_slice(name)
            E[:, j] = 0.5 * np.einsum("im,im->m", Z[sl], np.asarray(bm.stiffness_matrix() @ Z[sl]))
    return E


def strain_by_element(result) -> np.ndarray:
    """(n_modes, n_elements) strain-energy shares of the springs (rows sum to 1, or 0)."""
    return _normalise(strain_energy_by_element(result))


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
    E = strain_energy_by_body(result)
    total = 0.5 * np.einsum("im,im->m", Z, np.asarray(m.K_abs @ Z))
    # a total below round-off of the largest mode's: no strain energy at all (rigid-body mode)
    has = total > 1e-12 * np.abs(total).max(initial=0.0)
    return np.where(has[:, None], np.clip(E, 0.0, None) / np.where(has, total, 1.0)[:, None], 0.0)


def element_strain_energy(model, el, Z) -> np.ndarray:
    """Strain energy 1/2 e' diag(k) e of element ``el`` of ``model`` in each column of ``Z``
    (absolute coordinates), e = B_e T_e z: one number per mode."""
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
