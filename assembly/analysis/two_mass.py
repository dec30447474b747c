"""The two-mass equivalent of a drivetrain (rotor -- gearbox -- generator) with its damping:
:func:`two_mass` of a scene, the numbers an ElastoDyn model takes (GBRatio, GenIner,
DTTorSpr, DTTorDmp).

The stiffness part is :func:`assembly.analysis.drivetrain.two_mass_stiffness` of the scene's
torsional model; the damping part, DTTorDmp (N m s/rad, low-speed side), as follows.

Element dampers: the damping matrix on q condensed with the same static condensation as
the stiffness (:func:`assembly.mechanics.condensation.condense_along`: every interior coordinate
settles as the springs say) onto the rotor and generator rotations. For dampers between
the two ends only (shafts, meshes, bearings between bodies) it is ``c [[1, -1/s],
[-1/s, 1/s^2]]`` (s the speed ratio) and DTTorDmp = c, its (0, 0) entry. Exact for the
two-mass chain; with interior springs, each damper c_j counts with the square of the
share of the end-to-end twist its spring takes statically, ``c = sum c_j (k / k_j)^2``
(k_j on the low-speed side): the dampers of a chain whose interior inertias are small
against the ends. Dampers to the housing brake the rigid rotation and have no two-mass
counterpart: refused.

Modal ratios and Rayleigh damping: ``2 zeta omega_1 J_eq`` of the two-mass model's mode
(omega_1 its free-free angular frequency, ``J_eq = J_R N^2 J_G / (J_R + N^2 J_G)`` on the
low-speed side), zeta being the ratio the scene gives the lowest elastic mode of the
torsional model (its two-mass mode): ``class_ratios["rotational"]`` or ``modal_ratio``,
plus ``alpha / (2 omega_1) + beta omega_1 / 2``. Added to the element dampers' c.
"""
from __future__ import annotations

import dataclasses
import math

from ..errors import SolverError
from ..mechanics.condensation import condense_along
from ..model.assemble import assemble
from ..model.damping import damping_matrix, has_damping
from ..scene.tables import scene_argument, with_fidelity
from .drivetrain import RANK_ONE_RTOL, TwoMass, chain_ends, own_rotation_column, two_mass_stiffness


def two_mass_damping(model, tm) -> float:
    """DTTorDmp (N m s/rad) of the torsional ``model`` whose two-mass equivalent is ``tm``
    (:class:`assembly.analysis.drivetrain.TwoMass`); see the module notes."""
    cols = [own_rotation_column(model, tm.rotor), own_rotation_column(model, tm.generator)]
    C_cc = condense_along(model.K, damping_matrix(model), cols)
    c, s = float(C_cc[0, 0]), tm.speed_ratio
    J_R, JG_ls = tm.rotor_inertia, tm.generator_inertia * tm.gear_ratio ** 2
    J_eq = J_R * JG_ls / (J_R + JG_ls)
    # round-off floor: dampers without a torsional part (a bearing's radial and tilt dampers
    # seen by the torsional model) leave ~1e-13 N m s/rad; below 1e-12 of the two-mass mode's
    # critical damping 2 sqrt(k J_eq) the condensed damping is zero
    floor = 1e-12 * 2 * math.sqrt(tm.stiffness * J_eq)
    if abs(C_cc).max() * s * s <= floor:
        c, C_cc = 0.0, 0.0 * C_cc
    # a chain damper leaves the rigid rotation (1, s) free: C_cc (1, s) = 0
    drag = abs(C_cc[0, 0] + s * C_cc[0, 1]) + abs(C_cc[1, 0] + s * C_cc[1, 1]) / abs(s)
    if drag > RANK_ONE_RTOL * max(c, abs(C_cc[1, 1]) * s * s, 1e-300):
        raise SolverError("condensed damping (N m s/rad)", C_cc.tolist(),
                          "a damper brakes the rigid rotation of the drivetrain (a damper to the housing): "
                          "no two-mass torsional damper")
    d = model.scene.damping
    if d is None:
        return c
    w1 = 2 * math.pi * tm.frequencies_hz()[0]
    zeta = (d.class_ratios or {}).get("rotational", d.modal_ratio or 0.0)
    zeta += d.rayleigh_alpha / (2 * w1) + d.rayleigh_beta * w1 / 2
    return c + 2 * zeta * w1 * J_eq


def two_mass(scene, rotor: str | None = None, generator: str | None = None) -> TwoMass:
    """The two-mass equivalent of ``scene``'s torsional model between its rotor and generator
    (:func:`assembly.analysis.drivetrain.chain_ends`; default the bodies of role "rotor" and
    "generator"): :func:`assembly.analysis.drivetrain.two_mass_stiffness`, with its ``damping``
    (:func:`two_mass_damping`) when the scene has damping."""
    scene_argument("scene", scene)
    ends = chain_ends(scene, rotor, generator)
    model = assemble(with_fidelity(scene, "torsional"), source=scene)
    tm = two_mass_stiffness(model, *ends)
    return dataclasses.replace(tm, damping=two_mass_damping(model, tm)) if has_damping(scene) else tm
