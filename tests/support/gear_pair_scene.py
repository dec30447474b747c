"""A spur gear pair at torsional fidelity (one rotation per gear, the mesh a spring along the
line of action), as a scene dict for :func:`assembly.scene.schema.scene_from_dict`: the smallest
scene with a nonlinear mesh for time-domain tests.

Gear 1 (``g1``) at the origin, gear 2 (``g2``) at the centre distance (r1 + r2) / cos(alpha)
on +x, both axes +z. With ``drive_sign = 1`` the compression along the line of action is
``delta = r1 theta1 + r2 theta2`` (a base-circle point moves r theta along the line of
action; the gears turn in opposite senses), so the rigid-body mode turns gear 2 at -r1/r2
times gear 1.
"""
from __future__ import annotations

import math

PRESSURE_ANGLE_DEG = 20.0


def gear_pair(J1: float, J2: float, r1: float, r2: float, k: float, *, teeth: int = 20,
              amplitudes=None, backlash: float | None = None, damping: float = 0.0,
              fix_gear1: bool = False, roles: tuple = (None, None), simulation: dict | None = None) -> dict:
    """Scene dict of the pair: polar inertias ``J1``, ``J2`` (kg m^2), base radii ``r1``,
    ``r2`` (m), mesh stiffness ``k`` (N/m) and damper ``damping`` (N s/m); ``amplitudes``:
    the relative stiffness harmonics a_h of k(phi) = k (1 + sum a_h cos(h phi)), phi =
    ``teeth`` x theta1 (None: constant stiffness); ``backlash`` (m, None: none);
    ``fix_gear1``: gear 1 held by a ``[[fixed]]`` table; ``roles``: the bodies' roles;
    ``simulation``: the ``[simulation]`` table."""
    bodies = [{"name": "g1", "mass": 1.0, "polar_inertia": J1},
              {"name": "g2", "mass": 1.0, "polar_inertia": J2,
               "position": [(r1 + r2) / math.cos(math.radians(PRESSURE_ANGLE_DEG)), 0.0, 0.0]}]
    for b, role in zip(bodies, roles):
        if role is not None:
            b["role"] = role
    mesh = {"name": "m", "gear1": "g1", "gear2": "g2", "stiffness": k, "base_radius1": r1, "base_radius2": r2,
            "pressure_angle_deg": PRESSURE_ANGLE_DEG, "damping": damping}
    if amplitudes is not None:
        mesh["variation"] = {"amplitudes": list(amplitudes), "teeth": teeth}
    if backlash is not None:
        mesh["backlash"] = backlash
    scene = {"name": "torsional gear pair", "fidelity": "torsional", "bodies": bodies, "meshes": [mesh]}
    if fix_gear1:
        scene["fixed"] = [{"body": "g1"}]
    if simulation is not None:
        scene["simulation"] = simulation
    return scene
