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
    energy = float(Z @ (m.M_abs @ Z))
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
