"""The gear table of a scene: every mesh's derived numbers as the model uses them.

One row per scene mesh and per planetary stage pair (sun-planet, planet-ring; all planets
of a stage share one row): base radii, working transverse pressure angle alpha_wt, base
helix angle beta_b (the line of action's inclination, the model's ``helix_angle``),
working centre distance a_w = |r_b1 + r_b2| / cos(alpha_wt), mesh stiffness and where it
came from (typed, or ISO 6336-1 method B, :mod:`assembly.scene.gears`). Where the gears have
teeth (both gears of a mesh; a stage with ``normal_module``), also ISO 21771: reference
radii r = r_b / cos(alpha_t) = z m_n / (2 cos beta), the transverse reference pressure
angle alpha_t = atan(tan alpha_n / cos beta), the profile (transverse) contact ratio
eps_alpha with the tips the scene uses (:func:`assembly.scene.gears.body_tip_alterations`,
:func:`assembly.scene.gears.stage_contact_ratios`) and the overlap ratio
eps_beta = b |sin beta| / (pi m_n), b the smaller face width. SI units, angles in rad.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from fe_components.gear_pair import pair_geometry, transverse_pressure_angle

from ..scene.gears import ISO_SOURCE, body_teeth, body_tip_alterations, stage_contact_ratios
from ..scene.tables import scene_argument


@dataclass(frozen=True)
class GearRow:
    """One mesh (or a stage's planet meshes, ``count`` of them) as the model uses it. Radii
    are negative for an internal gear; the teeth numbers (``reference_radius1/2``,
    ``transverse_pressure_angle``, ``helix_angle``, ``contact_ratio``, ``overlap_ratio``,
    ``normal_module``, ``face_width``) are None without teeth."""

    name: str
    path: str
    gear1: str
    gear2: str
    count: int
    base_radius1: float
    base_radius2: float
    working_pressure_angle: float
    base_helix_angle: float
    centre_distance: float
    stiffness: float
    stiffness_source: str
    reference_radius1: float | None = None
    reference_radius2: float | None = None
    transverse_pressure_angle: float | None = None
    helix_angle: float | None = None
    normal_module: float | None = None
    face_width: float | None = None
    contact_ratio: float | None = None
    overlap_ratio: float | None = None

    def as_dict(self) -> dict:
        return {"mesh": self.name, "path": self.path, "gear1": self.gear1, "gear2": self.gear2,
                "count": self.count, "base_radius1_m": self.base_radius1, "base_radius2_m": self.base_radius2,
                "reference_radius1_m": self.reference_radius1, "reference_radius2_m": self.reference_radius2,
                "working_pressure_angle_rad": self.working_pressure_angle,
                "transverse_pressure_angle_rad": self.transverse_pressure_angle,
                "helix_angle_rad": self.helix_angle, "base_helix_angle_rad": self.base_helix_angle,
                "centre_distance_m": self.centre_distance, "normal_module_m": self.normal_module,
                "face_width_m": self.face_width, "contact_ratio": self.contact_ratio,
                "overlap_ratio": self.overlap_ratio, "stiffness_N_per_m": self.stiffness,
                "stiffness_source": self.stiffness_source}


def overlap_ratio(face_width: float, helix_angle: float, normal_module: float) -> float:
    """eps_beta = b |sin beta| / (pi m_n) (ISO 21771)."""
    return face_width * abs(math.sin(helix_angle)) / (math.pi * normal_module)


def _row(name, path, m, count, source, teeth=None) -> GearRow:
    """Row of expanded mesh ``m`` (its model numbers); ``teeth``: (alpha_n, beta, m_n, b,
    eps_alpha) of its gears, or None."""
    r1, r2, a = m.base_radius1, m.base_radius2, m.pressure_angle
    extra = {}
    if teeth is not None:
        a_n, beta, m_n, b, eps = teeth
        a_t = transverse_pressure_angle(a_n, beta)
        extra = dict(reference_radius1=r1 / math.cos(a_t), reference_radius2=r2 / math.cos(a_t),
                     transverse_pressure_angle=a_t, helix_angle=beta, normal_module=m_n, face_width=b,
                     contact_ratio=eps, overlap_ratio=None if b is None else overlap_ratio(b, beta, m_n))
    return GearRow(name, path, m.gear1, m.gear2, count, r1, r2, a, abs(m.helix_angle), abs(r1 + r2) / math.cos(a),
                   m.stiffness, source, **extra)


def _mesh_teeth(scene, m):
    """(alpha_n, beta of gear 1, m_n, b, eps_alpha) of scene mesh ``m`` between two gears
    with teeth, the contact ratio with the tips the scene derives; None otherwise."""
    bodies = {b.name: b for b in scene.bodies}
    teeth = {b.name: t for i, b in enumerate(scene.bodies) if (t := body_teeth(b, f"bodies[{i}]")) is not None}
    if m.gear1 not in teeth or m.gear2 not in teeth:
        return None
    tips = body_tip_alterations(scene.meshes, teeth, bodies)
    int1 = bodies[m.gear1].internal
    internal = int1 or bodies[m.gear2].internal
    (n1, t1), (n2, t2) = ((m.gear2, teeth[m.gear2][1]), (m.gear1, teeth[m.gear1][1])) if int1 else \
        ((m.gear1, teeth[m.gear1][1]), (m.gear2, teeth[m.gear2][1]))
    g = pair_geometry(t1, t2, internal, (tips.get(n1, 0.0), tips.get(n2, 0.0)))
    t = teeth[m.gear1][1]
    return (t.pressure_angle, t.helix_angle, t.normal_module, min(t1.face_width, t2.face_width), g.contact_ratio)


def _source(given, field: str) -> str:
    return ISO_SOURCE if getattr(given, field) is None else "typed"


def gear_table(scene) -> tuple[GearRow, ...]:
    """:class:`GearRow` of every scene mesh, then of each planetary stage's sun-planet and
    planet-ring meshes (one row each, ``count`` planets), in scene order."""
    scene_argument("scene", scene)
    expanded = {m.name: m for m in scene.expanded().meshes}
    out = []
    for i, (m, given) in enumerate(zip(scene.meshes, scene.as_given("meshes"))):
        out.append(_row(m.name, f"meshes[{i}]", expanded[m.name], 1, _source(given, "stiffness"),
                        _mesh_teeth(scene, m)))
    for i, (st, given) in enumerate(zip(scene.stages, scene.as_given("stages"))):
        n = st.planets.count
        eps = stage_contact_ratios(st) if st.normal_module is not None else (None, None)
        for k, (pair, field) in enumerate((("sun-planet", "k_mesh_sun"), ("planet-ring", "k_mesh_ring"))):
            first = expanded[f"{st.name}.sun-planet0" if k == 0 else f"{st.name}.planet0-ring"]
            # the planets' helix is the sun's, opposite (an external pair); the ring's the planets'
            beta = st.helix_angle if k == 0 else -st.helix_angle or 0.0
            teeth = None if st.normal_module is None else (st.normal_pressure_angle, beta, st.normal_module,
                                                           st.face_width, eps[k])
            out.append(_row(f"{st.name}.{pair}", f"stages[{i}].{field}", first, n, _source(given, field), teeth))
    return tuple(out)


def mesh_rows(scene) -> dict:
    """Expanded mesh name -> its :class:`GearRow` (every planet mesh of a stage -> the
    stage's row for that pair)."""
    rows = {r.name: r for r in gear_table(scene)}
    out = {}
    for m in scene.expanded().meshes:
        if m.name in rows:
            out[m.name] = rows[m.name]
            continue
        stage, _, pair = m.name.rpartition(".")
        key = f"{stage}.sun-planet" if pair.startswith("sun-planet") else f"{stage}.planet-ring"
        if key in rows:
            out[m.name] = rows[key]
    return out
