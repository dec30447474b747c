"""Filling in a mesh's stiffness variation from its gears' teeth (scene resolution).

A :class:`assembly.scene.time_domain.MeshVariation` given by ``step`` needs the profile contact
ratio eps_alpha and the overlap ratio eps_beta of its pair; left out, they come from the
teeth (ISO 21771 geometry, :func:`fe_components.gear_pair.transverse_contact_ratio`):
eps_beta = b sin|beta| / (pi m_n) with b the face width, beta the reference helix angle and
m_n the normal module. The counting gear's teeth fill ``teeth``. Stage meshes are phased by
their planet's angle here (``phase`` + z psi_n, Parker 2000). The series itself is
:mod:`assembly.dynamics.mesh_variation`'s business.
"""
from __future__ import annotations

import dataclasses
import math

from ..errors import SceneError
from .time_domain import MeshVariation


def overlap_ratio(face_width: float | None, helix_angle: float, normal_module: float) -> float:
    """eps_beta = b sin|beta| / (pi m_n) (0 without a face width or helix)."""
    if not face_width or helix_angle == 0.0:
        return 0.0
    return face_width * abs(math.sin(helix_angle)) / (math.pi * normal_module)


def filled(v: MeshVariation, path: str, teeth: int | None, contact_ratio: float | None,
           face_contact_ratio: float | None, phase_shift: float = 0.0) -> MeshVariation:
    """``v`` with ``teeth``, the contact ratios of a ``step`` wave and the planet phase
    filled in; SceneError at ``path`` when a needed number is neither given nor derivable."""
    if v.amplitudes is not None and v.step is not None:
        raise SceneError(f"{path}.step", v.step, "give either amplitudes (with phases) or step, not both")
    if v.amplitudes is None and v.step is None:
        raise SceneError(f"{path}.amplitudes", None, "missing: give amplitudes (a_h relative to the mean "
                                                     "stiffness) or step (dk/k0 of the rectangular wave)")
    if v.phases is not None and (v.amplitudes is None or len(v.phases) != len(v.amplitudes)):
        raise SceneError(f"{path}.phases", v.phases, "needs amplitudes of the same length")
    z = v.teeth if v.teeth is not None else teeth
    if z is None:
        raise SceneError(f"{path}.teeth", None, "missing: the counting gear has no teeth; give the number of "
                                                "teeth whose engagement the angle counts")
    changes = {"teeth": z, "phase": v.phase + phase_shift}
    if v.step is not None:
        c = v.contact_ratio if v.contact_ratio is not None else contact_ratio
        if c is None:
            raise SceneError(f"{path}.contact_ratio", None, "missing: the gears have no teeth to derive the "
                                                            "profile contact ratio from; give it (in (1, 2))")
        if not 1.0 < c < 2.0:
            raise SceneError(f"{path}.contact_ratio", round(c, 6), "the rectangular wave needs a profile contact "
                                                                   "ratio in (1, 2): give amplitudes instead")
        changes["contact_ratio"] = c
        changes["face_contact_ratio"] = (v.face_contact_ratio if v.face_contact_ratio is not None
                                         else face_contact_ratio or 0.0)
    return dataclasses.replace(v, **changes)


def stage_variations(st, path: str, psi: float) -> tuple:
    """(sun-planet, planet-ring) variations of the planet at angle ``psi`` (rad) of stage
    ``st`` (None where the stage gives none): counted on the sun's / ring's teeth."""
    from .gears import stage_contact_ratios  # gear_data reads this module's mesh_variation
    with_teeth = st.normal_module is not None
    ratios = stage_contact_ratios(st) if with_teeth and (st.variation_sun or st.variation_ring) else (None, None)
    eps_b = overlap_ratio(st.face_width, st.helix_angle, st.normal_module) if with_teeth else None
    out = []
    for which, z, eps in (("sun", st.sun.teeth, ratios[0]), ("ring", st.ring.teeth, ratios[1])):
        v = getattr(st, f"variation_{which}")
        if v is None:
            out.append(None)
            continue
        zc = v.teeth if v.teeth is not None else z
        out.append(filled(v, f"{path}.variation_{which}", z, eps, eps_b, (zc or 0) * psi))
    return tuple(out)


def mesh_variation(m, path: str, teeth: dict, geometry=None):
    """A ``[[meshes]]`` entry's variation with its numbers filled from the teeth
    (``teeth``: body name -> (path, GearTeeth) or missing; ``geometry``: the pair's
    :class:`fe_components.gear_pair.PairGeometry` when both gears have teeth)."""
    v = m.variation
    counting = m.gear1 if v.counting_gear == "gear1" else m.gear2
    t = teeth.get(counting)
    z = t[1].n_teeth if t is not None else None
    eps = eps_b = None
    if geometry is not None:
        t1 = teeth[m.gear1][1]
        eps = geometry.contact_ratio
        widths = [teeth[g][1].face_width for g in (m.gear1, m.gear2)]
        eps_b = overlap_ratio(min(widths), t1.helix_angle, t1.normal_module)
    return filled(v, f"{path}.variation", z, eps, eps_b)
