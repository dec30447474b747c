"""How strongly an exciter takes part in a mode: the share of the mode's energy its element or
body holds, to rank the crossings of a Campbell diagram (:mod:`assembly.dynamics.campbell`).

For mass-normalised mode shapes phi_j (phi' M phi = 1) of eigenvalue w_j^2 the mode's strain
energy is w_j^2 / 2 and its kinetic energy (at unit modal velocity) 1/2:

* a gear mesh (rank-one spring k along its line of action, deflection row e = B A T on q) holds
  ``k (e phi_j)^2 / w_j^2`` of mode j's strain energy -- the same share sets the modal force a
  transmission error of that mesh puts into the mode (``k e phi_j`` per unit error): a mesh that
  carries no strain in a mode cannot excite it, whatever its phasing;
* a torque on a body about its own axis (a rotor order) enters mode j as ``s phi_j`` (s the
  body's spin row on q); the body's spin holds ``J (s phi_j)^2`` of the mode's kinetic energy, J
  its polar inertia: the share ranked for rotor orders;
* a body's own 1x (an unbalance, a runout) loads it: the body holds ``phi_b' M_b phi_b`` of the
  mode's kinetic energy (its block of the absolute shapes and mass).

Rigid-body modes (w = 0) get share 0. Shares of a planetary stage's order sum its meshes'.
"""
from __future__ import annotations

import numpy as np

from ..model.probes import spin_row, strain_rows
from .run_loads import polar_inertia


def mesh_strain_shares(model, res) -> dict:
    """{mesh element name: (n_modes,) share of each mode's strain energy} (module notes)."""
    lam = np.asarray(res.eigenvalues, float)
    elastic = lam > 0
    out = {}
    for el in model.elements:
        if el.kind != "mesh":
            continue
        e = strain_rows(model, el) @ res.shapes              # (1, n_modes)
        share = np.zeros(len(lam))
        share[elastic] = float(el.k[0]) * e[0, elastic] ** 2 / lam[elastic]
        out[el.name] = share
    return out


def spin_kinetic_shares(model, res, body: str) -> np.ndarray:
    """(n_modes,) share of each mode's kinetic energy the spin of ``body`` holds (module notes)."""
    s = spin_row(model, body) @ res.shapes
    share = polar_inertia(model, body) * np.asarray(s, float) ** 2
    share[np.asarray(res.eigenvalues, float) <= 0] = 0.0
    return share


def order_meshes(order, mesh_names) -> list:
    """The mesh elements an order of :mod:`assembly.dynamics.orders` comes from: every mesh of
    its planetary stage (names ``STAGE.``...), or its gear pair (named as the order's source, or
    unnamed: ``mesh[i]:GEAR1-GEAR2``)."""
    if order.stage is not None and order.n_planets is not None:
        return [m for m in mesh_names if m.startswith(f"{order.stage}.")]
    return [m for m in mesh_names if m == order.source or m.endswith(f":{order.source}")]


def body_kinetic_shares(model, res, body: str) -> np.ndarray:
    """(n_modes,) share of each mode's kinetic energy ``body`` holds, all its motions (module notes)."""
    sl = model.body_slice(body)
    phi = res.abs_shapes[sl]
    share = np.einsum("ij,ij->j", phi, model.M_abs[sl][:, sl] @ phi)
    share[np.asarray(res.eigenvalues, float) <= 0] = 0.0
    return share
