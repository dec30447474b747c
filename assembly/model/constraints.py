"""Constraints: fixed DOFs, rigid bearing directions and the torsional fidelity.

A constrained direction is removed from the independent coordinates (``z = T q`` in
:mod:`assembly.model.assemble`) instead of being modelled as a huge spring. Three sources:
``[[fixed]]`` DOFs, bearing directions of infinite stiffness (and near-rigid ones, see
:func:`rigidify`), and the five non-spin DOFs of every torsional body -- so a torsional
model is literally the rigid model with five DOFs per body held.
"""
from __future__ import annotations

import dataclasses
import logging
import math

import numpy as np

from ..scene.tables import DOF_NAMES, SPLIT_STIFFNESSES, Scene, derive
from ..scene.validate import can_constrain

log = logging.getLogger(__name__)

#: A bearing direction becomes an exact constraint only when that shifts no mode at or
#: below the scene's band by more than this relative frequency: a tenth of the solve's
#: documented accuracy (:data:`assembly.analysis.resolution.FREQ_RTOL`), so that a few constrained
#: directions acting on one mode still add up to less than it.
CONSTRAINT_RTOL = 1e-7


#: Fields of one radial or tilt direction: a bearing turned by ``radial_angle`` acts along
#: other axes than its body's DOFs, so one of them alone cannot become a body constraint.
_PER_DIRECTION = frozenset(f for parts in SPLIT_STIFFNESSES.values() for f in parts)


def candidates(scene: Scene) -> list:
    """(bearing index, field) of every finite, non-zero bearing stiffness that
    :func:`can_constrain` allows to become a constraint (stages expanded), except one
    direction of a bearing turned by ``radial_angle``."""
    by_name = {b.name: b for b in scene.bodies}
    out = []
    for i, br in enumerate(scene.bearings):
        if can_constrain(br, by_name[br.body]):
            out += [(i, f) for f in dict.fromkeys(br.diagonal_fields()) if 0 < getattr(br, f) < math.inf
                    and not (br.radial_angle != 0.0 and f in _PER_DIRECTION)]
    return out


def constraint_shift(k: float, coupling: float, mass: float, band_hz: float) -> float:
    """First-order bound on the relative frequency shift that holding a DOF rigidly, instead
    of by a grounded spring ``k``, causes in any mode at or below ``band_hz``.

    With the DOF x held by ``k`` (N/m or N m/rad) and the rest r, a mode phi at lambda
    moves by ``delta lambda = |(K_xr - lambda M_xr) phi|^2 / k`` to first order. Cauchy-Schwarz
    on the positive semi-definite coupling stiffness K' (everything but the candidate
    bearing springs) and on M gives ``|K_xr phi|^2 <= K'_xx lambda`` and ``|M_xr phi|^2 <=
    M_xx``, so the relative frequency shift is at most
    ``0.5 (sqrt(K'_xx / k) + omega_band sqrt(M_xx / k))^2``: small when the spring is stiff
    against both the springs it works with (``coupling``) and the inertia it carries
    (``mass``, kg or kg m^2) at the top of the band.
    """
    w = 2 * math.pi * band_hz
    root_k = math.sqrt(k)      # square roots first: no overflow for any k > 0
    # K'_xx is a diagonal entry of a positive semi-definite matrix: a negative one is the
    # round-off of a zero (T' K T on axes not along x, y, z: -5e-11)
    r = (math.sqrt(max(coupling, 0.0)) + w * math.sqrt(mass)) / root_k if root_k > 0 else math.inf
    return 0.5 * r * r if r < 1e150 else math.inf


def rigidify(scene: Scene, diagonal: dict, band_hz: float) -> tuple[Scene, list]:
    """Scene (stages expanded) with near-rigid bearing directions replaced by ``inf``
    (constraints), and the list of (bearing, field, stiffness) converted.

    ``diagonal`` maps each independent DOF name (``body.x``) to (K'_xx, M_xx) of the model
    assembled without the :func:`candidates` springs (K': the coupling stiffness they are
    judged against; :func:`assembly.model.assemble.assemble`). A candidate direction becomes a constraint
    when :func:`constraint_shift` is at most CONSTRAINT_RTOL on every independent DOF it
    acts on (a direction acting on no independent DOF, e.g. the radial bearing of a
    torsional body, is left as it is: it does nothing). A stiffer spring left elastic
    raises the highest frequency; :func:`assembly.analysis.modal.solve_modes` then checks that the
    low modes are still resolved and names the spring if they are not.
    """
    out, changed = list(scene.bearings), []
    for i, f in candidates(scene):
        br = out[i]
        k = getattr(br, f)
        dofs = [f"{br.body}.{d}" for d, g in zip(DOF_NAMES, br.diagonal_fields()) if g == f and f"{br.body}.{d}" in diagonal]
        shift = max((constraint_shift(k, *diagonal[d], band_hz) for d in dofs), default=math.inf)
        if shift <= CONSTRAINT_RTOL:
            out[i] = dataclasses.replace(br, **{f: math.inf})
            changed.append((br.name or br.body, f, k))
    if not changed:
        return scene, []
    log.info("near-rigid bearing directions modelled as constraints: %s", changed)
    return derive(scene, bearings=tuple(out)), changed


def constrained_dofs(scene: Scene) -> dict:
    """Local DOF names held at zero, per body (fixed DOFs, rigid bearings, torsional)."""
    out = {b.name: set() for b in scene.bodies}
    for f in scene.fixed:
        out[f.body].update(f.dofs)
    for br in scene.bearings:
        for name, ki in zip(DOF_NAMES, br.diagonal()):
            if np.isinf(ki):
                out[br.body].add(name)
    for b in scene.bodies:
        if b.fidelity == "torsional":
            out[b.name].update(d for d in DOF_NAMES if d != "rz")
    return out
