"""Inertia referred to a shaft: what a speed controller on that shaft sees of the drivetrain.

J_ref = 2 T / omega_shaft^2, T the kinetic energy of the model's one rigid-body mode
(:func:`assembly.analysis.load_cases.single_rigid_mode`: gear geometry only): the sum of
every body's J (omega_body / omega_shaft)^2 plus the orbiting masses' m v^2 (planets on
their carrier). For two gears on fixed axes, referred to gear 1: J1 + J2 (r1 / r2)^2.
Units: kg m^2.
"""
from __future__ import annotations

import numpy as np

from .. import arguments
from ..errors import MechanismError
from ..model.assemble import model_of
from ..model.probes import axial_rotation
from .load_cases import single_rigid_mode

#: A rigid-body mode strains no spring: its Rayleigh frequency sqrt(z'Kz / z'Mz) is round-off,
#: at most sqrt(eps) ~ 1.5e-8 of the model's highest (eigenvalue round-off eps lambda_max),
#: bounded by sqrt(max K_ii / min M_ii); a shape above RIGID of that bound is refused.
RIGID = 1e-6


def referred_inertias(model, shape=None) -> dict[str, float]:
    """Body name -> the drivetrain's inertia referred to that body's shaft (kg m^2), for
    every body that turns in the rigid-body mode. ``model``: an :class:`AssembledModel`, or
    a Scene assembled as given; ``shape``: that mode on the absolute coordinates when the
    caller has it (a modal result's one rigid-body mode, any scaling), else it is found
    from the springs. MechanismError when the model has not exactly one rigid-body mode."""
    m = model_of("model", model)
    if shape is None:
        phi, why = single_rigid_mode(m)
        if phi is None:
            raise MechanismError(f"referred inertias need exactly one rigid-body mode: {why}", phi)
        shape = m.T @ phi[:, 0]
    Z = np.asarray(shape, float).ravel()
    if Z.size != m.n_abs or not np.all(np.isfinite(Z)):
        raise arguments.refuse("shape", f"<{Z.size} values>", f"must be {m.n_abs} finite values: the rigid-body "
                               "mode on the absolute coordinates")
    energy = float(Z @ (m.M_abs @ Z))
    kd, md = np.abs(m.K_abs.diagonal()), np.abs(m.M_abs.diagonal())   # sparse or dense alike
    top = np.sqrt(kd.max() / md[md > 0].min()) if np.any(md > 0) and kd.max() > 0 else 0.0   # rad/s scale
    w = np.sqrt(max(float(Z @ (m.K_abs @ Z)), 0.0) / energy) if energy > 0 else 0.0
    if w > RIGID * top:
        raise arguments.refuse("shape", "<array>", f"is not a rigid-body mode: its springs hold strain energy "
                               f"(Rayleigh frequency {w / (2 * np.pi):.3g} Hz)")
    w = {b: float(axial_rotation(m, Z, b)) for b in m.bodies}
    scale = max(abs(v) for v in w.values())
    if not scale > 0:
        raise MechanismError("no body turns in the rigid-body mode: no referred inertia", scale)
    return {b: energy / v**2 for b, v in w.items() if abs(v) > 1e-12 * scale}


def referred_inertia(model, shaft: str) -> float:
    """The drivetrain's inertia referred to ``shaft`` (a body name; kg m^2,
    :func:`referred_inertias`). MechanismError when ``shaft`` stands still in the
    rigid-body mode."""
    m = model_of("model", model)
    arguments.one_of("shaft", shaft, list(m.bodies))
    J = referred_inertias(m)
    if shaft not in J:
        raise MechanismError(f"{shaft} stands still in the rigid-body mode: no inertia referred to it", shaft)
    return J[shaft]
