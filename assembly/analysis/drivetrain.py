"""Kinematic chain and two-mass equivalent of a drivetrain (rotor -- gearbox -- generator).

Aero-elastic codes (OpenFAST ElastoDyn) model the drivetrain as two inertias joined by one
torsional spring: the rotor ``J_R`` on the low-speed shaft, the generator ``J_G`` on the
high-speed shaft, the gear ratio ``N`` between them and the spring ``k`` on the low-speed
side (Jonkman et al. (2009), NREL/TP-500-38060, section 5). Everything here is read off
the torsional model of the scene (:func:`assembly.scene.tables.with_fidelity` ``"torsional"``):

* the speed ratios of every body from the model's single rigid-body mode (gear geometry
  only, :func:`assembly.analysis.load_cases.single_rigid_mode`);
* ``k`` from the static condensation of ``K`` onto the rotor and generator rotations
  (:func:`assembly.mechanics.condensation.condense`): every mesh, shaft and bearing flexibility in
  between, in series and parallel as the scene joins them;
* ``J_R`` and ``J_G`` from the rigid-body mode's kinetic energy, split into the rotor body
  and the rest reflected to the generator shaft.

Units: kg m^2, N m/rad, rad/s ratios dimensionless, frequencies Hz.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from .. import arguments
from ..errors import MechanismError, SceneError, SolverError
from ..mechanics.condensation import condense
from ..model.probes import axial_rotation
from ..scene.paths import body_origins
from .load_cases import single_rigid_mode

log = logging.getLogger(__name__)

#: Body roles that mark the two ends of the drivetrain (``Body.role``).
ROLES = ("rotor", "generator")
#: Relative tolerance of the rank-one check of the condensed 2x2 stiffness and of the
#: agreement of its ratio with the rigid-body mode's (round-off of the condensation).
RANK_ONE_RTOL = 1e-6


@dataclass(frozen=True)
class TwoMass:
    """Two-mass equivalent of a drivetrain (ElastoDyn's GBRatio, GenIner, DTTorSpr).

    ``speed_ratio``: omega_generator / omega_rotor, signed (about each body's own axis);
    ``gear_ratio`` = its magnitude (GBRatio). ``rotor_inertia`` J_R (kg m^2): the rotor
    body alone. ``generator_inertia`` J_G (kg m^2, about the high-speed shaft; GenIner):
    everything else in the chain reflected to the generator's speed, i.e.
    ``generator_only_inertia`` (the generator body) plus ``gearbox_inertia`` (every other
    body -- gears, carriers, planets, brake discs, couplings -- times (omega_body /
    omega_generator)^2). ``stiffness`` k (N m/rad, low-speed side; DTTorSpr): the strain
    energy of the whole chain with the rotor and generator turned by th_R and th_G is
    0.5 k (th_R - th_G / speed_ratio)^2. ``damping`` (N m s/rad, low-speed side; DTTorDmp):
    None for a scene without damping (:mod:`assembly.analysis.two_mass`)."""

    rotor: str
    generator: str
    speed_ratio: float
    rotor_inertia: float
    generator_only_inertia: float
    gearbox_inertia: float
    stiffness: float
    damping: float | None = None

    @property
    def gear_ratio(self) -> float:
        """GBRatio: |omega_generator / omega_rotor|."""
        return abs(self.speed_ratio)

    @property
    def generator_inertia(self) -> float:
        """GenIner (kg m^2): generator plus the reflected rest of the chain."""
        return self.generator_only_inertia + self.gearbox_inertia

    def frequencies_hz(self) -> tuple[float, float]:
        """(free-free, generator locked) frequencies (Hz) of the two-mass model."""
        return two_mass_frequencies(self.rotor_inertia, self.generator_inertia, self.gear_ratio, self.stiffness)


def two_mass_frequencies(J_R: float, J_G: float, N: float, k: float) -> tuple[float, float]:
    """(free-free, generator locked) natural frequencies (Hz) of a rotor ``J_R`` (kg m^2)
    joined by a spring ``k`` (N m/rad, low-speed side) to a generator ``J_G`` (kg m^2,
    high-speed side) through a gear ratio ``N``: ``J_G`` seen from the low-speed side is
    N^2 J_G, so f_free = sqrt(k (1/J_R + 1/(N^2 J_G)))/(2 pi) and, with the generator
    held, f_locked = sqrt(k/J_R)/(2 pi)."""
    for name, v in (("J_R", J_R), ("J_G", J_G), ("N", N), ("k", k)):
        if not (isinstance(v, (int, float, np.floating)) and 0 < v < math.inf):
            raise ValueError(f"{name} = {v!r}: must be a finite number > 0")
    free = math.sqrt(k * (1.0 / J_R + 1.0 / (N * N * J_G))) / (2 * math.pi)
    locked = math.sqrt(k / J_R) / (2 * math.pi)
    return free, locked


def chain_ends(scene, rotor: str | None = None, generator: str | None = None) -> tuple[str, str]:
    """(rotor, generator) body names: as given, else the body of ``role = "rotor"`` /
    ``"generator"`` among the scene's ``[[bodies]]``. SceneError when a role is missing,
    given to two bodies, a given name is no body, or both ends are one body."""
    have = [b.name for b in scene.expanded().bodies]
    ends = []
    for role, name in zip(ROLES, (rotor, generator)):
        if name is not None:
            arguments.one_of(role, name, have)
            ends.append(name)
            continue
        marked = [(i, b.name) for i, b in enumerate(scene.bodies) if b.role == role]
        if not marked:
            raise SceneError("bodies.role", None, f"no body has role = {role!r}: set it on the {role}'s "
                                                  f"[[bodies]] table (or name the body: --{role} NAME)")
        if len(marked) > 1:
            (i0, n0), (i1, _) = marked[:2]
            raise SceneError(f"bodies[{i1}].role", role, f"bodies[{i0}] ({n0}) has role {role!r} too: "
                                                         "one body per end of the drivetrain")
        ends.append(marked[0][1])
    if ends[0] == ends[1]:                  # name the end the caller gave (the generator if both)
        raise SceneError("generator" if generator is not None else "rotor", ends[1],
                         "the rotor and the generator must be two different bodies")
    return ends[0], ends[1]


def rigid_mode(model, reference: str) -> np.ndarray:
    """The rigid-body mode on the independent coordinates q, scaled to a unit rotation of
    ``reference`` about its own axis. MechanismError when there is not exactly one
    rigid-body mode or the reference stands still in it."""
    phi, why = single_rigid_mode(model)
    if phi is None:
        raise MechanismError(f"speed ratios need exactly one rigid-body mode: {why}", phi)
    Z = model.T @ phi[:, 0]
    w_ref = axial_rotation(model, Z, reference)
    if abs(w_ref) <= 1e-12 * np.abs(Z).max():
        raise MechanismError(f"{reference} stands still in the rigid-body mode: no speed ratio to it", reference)
    return phi[:, 0] / w_ref


def _rigid_motion(model, reference: str) -> np.ndarray:
    """:func:`rigid_mode` on the absolute coordinates."""
    return model.T @ rigid_mode(model, reference)


def speed_ratios(model, reference: str) -> dict[str, float]:
    """Each body's rotation about its own axis over ``reference``'s (omega_body /
    omega_reference, signed) in the model's rigid-body mode (gear geometry only)."""
    Z = _rigid_motion(model, reference)
    return {b: float(axial_rotation(model, Z, b)) for b in model.bodies}


def own_rotation_column(model, body: str) -> int:
    """The column of ``q`` that is ``body``'s rotation about its own axis (one free
    coordinate of a body in the housing frame); SceneError naming the body's table else."""
    name = f"{body}.rz"
    col = model.dof_names.index(name) if name in model.dof_names else None
    unit = np.zeros(len(model.dof_names))
    if col is not None:
        unit[col] = 1.0
    ok = col is not None and np.allclose(axial_rotation(model, model.T @ np.eye(len(unit)), body), unit,
                                         rtol=0.0, atol=1e-12)
    if not ok:
        path = body_origins(model.source, model.scene).get(body, body)
        raise SceneError(path, body, "its rotation about its own axis is not one free coordinate of the torsional "
                                     "model (held by [[fixed]] or a rigid k_torsion, or measured in another body's "
                                     "frame): it cannot be an end of the two-mass model")
    return col


def two_mass_stiffness(model, rotor: str, generator: str) -> TwoMass:
    """Two-mass equivalent of the torsional ``model`` between ``rotor`` and ``generator``.

    Gear ratio from the rigid-body mode. Stiffness: ``K`` condensed onto the two rotations
    must be k [[1, -1/s], [-1/s, 1/s^2]] (rank one, null vector the rigid mode's
    (1, s), s = omega_G/omega_R); its (0, 0) entry is k on the low-speed side. Inertias:
    with the rotor turning at 1 rad/s, twice the rigid mode's kinetic energy 2T is split
    into the rotor body's share J_R and the rest, reflected to the generator shaft:
    GenIner = (2T - J_R)/s^2 -- everything downstream of the main shaft (gearbox parts,
    brake, coupling, generator) lumped on the generator, as a two-mass model must."""
    Z = _rigid_motion(model, rotor)
    s = float(axial_rotation(model, Z, generator))
    if abs(s) <= 1e-12:
        raise MechanismError(f"{generator} stands still when {rotor} turns: no gear ratio", generator)
    energy = {b: float(Z[model.body_slice(b)] @ (model.M_abs[model.body_slice(b)][:, model.body_slice(b)]
                                                 @ Z[model.body_slice(b)])) for b in model.bodies}
    rest = sum(e for b, e in energy.items() if b not in (rotor, generator))
    cols = [own_rotation_column(model, rotor), own_rotation_column(model, generator)]
    K_cc = condense(model.K, cols)
    k = float(K_cc[0, 0])
    if not k > 0:
        raise MechanismError(f"no stiffness between {rotor} and {generator} (condensed k = {k!r} N m/rad)", k)
    det = K_cc[0, 0] * K_cc[1, 1] - K_cc[0, 1] ** 2
    s_K = -K_cc[0, 0] / K_cc[0, 1] if K_cc[0, 1] != 0 else math.inf
    if abs(det) > RANK_ONE_RTOL * K_cc[0, 0] * K_cc[1, 1] or abs(s_K - s) > RANK_ONE_RTOL * abs(s):
        raise SolverError("condensed stiffness (N m/rad)", K_cc.tolist(),
                          f"not rank one k (th_R - th_G/s)^2 with the rigid-body mode's ratio s = {s:.9g}")
    log.info("two-mass %s -> %s: N = %.6g, k = %.6g N m/rad", rotor, generator, abs(s), k)
    return TwoMass(rotor, generator, s, energy[rotor], energy[generator] / s**2, rest / s**2, k)
