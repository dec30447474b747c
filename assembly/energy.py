"""Per-mode energy bookkeeping: kinetic share of each body, strain share of each spring,
and kinetic energy split by motion type (in-plane, axial, tilt, spin) in each body's axes."""
from __future__ import annotations

import numpy as np

#: Motion categories of a body in its own axes (z = rotation axis).
CATEGORIES = ("inplane", "axial", "tilt", "spin")


def kinetic_by_body(result) -> np.ndarray:
    """(n_modes, n_bodies) kinetic-energy shares (rows sum to 1; zero rows for no motion)."""
    m = result.model
    Z, M = result.abs_shapes, m.M_abs
    E = np.column_stack([np.einsum("im,ij,jm->m", Z[m.body_slice(b)], M[m.body_slice(b), m.body_slice(b)].toarray(),
                                   Z[m.body_slice(b)]) for b in m.bodies])
    return _normalise(E)


def strain_by_element(result) -> np.ndarray:
    """(n_modes, n_elements) strain-energy shares of the springs (rows sum to 1, or 0)."""
    m = result.model
    E = np.column_stack([_element_energy(m, el, result.abs_shapes) for el in m.elements]) \
        if m.elements else np.zeros((result.abs_shapes.shape[1], 0))
    return _normalise(E)


def _element_energy(model, el, Z) -> np.ndarray:
    e = el.B @ (model.attachment_operator(el) @ Z)
    return 0.5 * np.einsum("rm,r,rm->m", e, el.k, e)


def kinetic_by_category(result) -> np.ndarray:
    """(n_modes, n_bodies, 4) kinetic energy (unnormalised) per body and CATEGORIES entry."""
    m = result.model
    out = np.zeros((result.abs_shapes.shape[1], len(m.bodies), len(CATEGORIES)))
    for j, (name, bm) in enumerate(m.bodies.items()):
        z = result.abs_shapes[m.body_slice(name)]
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
    return out


def _normalise(E: np.ndarray) -> np.ndarray:
    tot = E.sum(axis=1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        S = np.where(tot > 0, E / np.where(tot > 0, tot, 1.0), 0.0)
    return S
