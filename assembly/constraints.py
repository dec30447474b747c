"""Constraints: fixed DOFs, rigid bearing directions and the torsional fidelity.

A constrained direction is removed from the independent coordinates (``z = T q`` in
:mod:`assembly.model`) instead of being modelled as a huge spring. Three sources:
``[[fixed]]`` DOFs, bearing directions of infinite stiffness (and near-rigid ones, see
:func:`rigidify`), and the five non-spin DOFs of every torsional body -- so a torsional
model is literally the rigid model with five DOFs per body held.
"""
from __future__ import annotations

import dataclasses
import logging
import math

import numpy as np

from .scene import DOF_NAMES, Bearing, Body, Scene, derive

log = logging.getLogger(__name__)

#: A bearing direction stiffer than RIGID_RATIO x the scene's reference stiffness (largest
#: gear-mesh or shaft stiffness, N/m; times the largest base radius squared for rotations)
#: is modelled as an exact constraint. Such a spring changes the physical frequencies by
#: about 1/RIGID_RATIO relative, but as a spring it puts eigenvalues RIGID_RATIO times
#: above the physics and costs the low modes their accuracy (eps * lambda_max).
RIGID_RATIO = 1e8


def can_constrain(bearing: Bearing, body: Body) -> bool:
    """Whether a direction of ``bearing`` may become an exact constraint: only on a plain
    rigid body (no component), at the body's own position, to its own reference frame,
    since the independent coordinates are the body's motion relative to that frame."""
    own_frame = bearing.frame is None or bearing.frame == body.frame
    at_body = bearing.position is None or np.allclose(bearing.position, body.position, rtol=0, atol=1e-12)
    return body.component is None and own_frame and at_body


def reference_stiffness(scene: Scene) -> tuple[float, float] | None:
    """(translational N/m, rotational N m/rad) scale of the scene's gear meshes and shafts,
    or None when it has neither."""
    ks = [m.stiffness for m in scene.meshes] + [max(s.k_axial, s.k_shear) for s in scene.shafts]
    if not ks or max(ks) <= 0:
        return None
    k_ref = max(ks)
    r = max([abs(m.base_radius1) for m in scene.meshes] + [abs(m.base_radius2) for m in scene.meshes] + [0.0])
    kr_ref = max([k_ref * r * r] + [max(s.k_torsion, s.k_bending) for s in scene.shafts])
    return k_ref, kr_ref


def rigidify(scene: Scene) -> tuple[Scene, list]:
    """Scene (stages expanded) with near-rigid bearing directions replaced by ``inf``
    (constraints), and the list of (bearing, direction, stiffness) converted. Only
    bearings that :func:`can_constrain` are converted."""
    ref = reference_stiffness(scene)
    if ref is None:
        return scene, []
    k_ref, kr_ref = ref
    by_name = {b.name: b for b in scene.bodies}
    out, changed = [], []
    for br in scene.bearings:
        new = {}
        if can_constrain(br, by_name[br.body]):
            for f, k in (("k_radial", k_ref), ("k_axial", k_ref), ("k_tilt", kr_ref), ("k_torsion", kr_ref)):
                v = getattr(br, f)
                if math.isfinite(v) and v > RIGID_RATIO * k:
                    new[f] = math.inf
                    changed.append((br.name or br.body, f, v))
        out.append(dataclasses.replace(br, **new) if new else br)
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
