"""Twist arrows of a torsional mode image: each body's rotation about its own axis,
referred to one reference body (the rotor) through the speed ratios.

Along a geared drivetrain the bodies' angles in a torsional mode differ by the gear ratios
(the NREL 5 MW generator turns 96 x the rotor's angle), so drawn to one scale the fast
bodies hide the rest. Divided by each body's speed ratio to the reference
(omega_body / omega_reference in the rigid-body mode, :func:`assembly.analysis.drivetrain.speed_ratios`)
every angle becomes the angle at the reference shaft: the classical equivalent system
"referred to the low-speed shaft". The arrows show these referred angles, so the rigid-body
mode draws equal arrows everywhere and a torsional mode shows where the chain twists.

Each arrow sits on the body's rim on the camera side, tangent to the rim (the direction
its rim point moves), its length proportional to the referred angle, the longest
:data:`ARROW_FRACTION` of the drawing's size. A model without exactly one rigid-body mode
(a rotor held in the housing) has no speed ratios: its arrows show the angles themselves.
"""
from __future__ import annotations

import logging

import numpy as np

log = logging.getLogger(__name__)

#: Longest twist arrow as a fraction of the framed size (bounding-box diagonal, m).
ARROW_FRACTION = 0.12
#: Arrows shorter than this fraction of the longest are left out (bodies at rest).
ARROW_FLOOR = 0.02
#: A body whose speed ratio is below this (a fixed ring) gets no arrow.
RATIO_FLOOR = 1e-6


def reference_body(scene) -> str:
    """The body angles are referred to: the body of role "rotor", else the first body."""
    return next((b.name for b in scene.bodies if b.role == "rotor"), scene.bodies[0].name)


def referred_angles(model, z_abs, reference: str | None = None) -> tuple:
    """(body -> angle in rad referred to the reference, reference name or None) of the mode
    shape ``z_abs`` (absolute coordinates): each body's rotation about its own axis over
    its speed ratio to the reference; without speed ratios (no single rigid-body mode)
    the angles themselves and None. Bodies that do not turn with the chain are left out."""
    from ...analysis.drivetrain import speed_ratios
    from ...errors import MechanismError
    from ...model.probes import axial_rotation
    ref = reference or reference_body(model.scene)
    try:
        ratios = speed_ratios(model, ref)
    except MechanismError as exc:
        log.info("twist arrows without speed ratios: %s", exc)
        ratios, ref = {b: 1.0 for b in model.bodies}, None
    z = np.asarray(z_abs, float)
    return ({b: float(axial_rotation(model, z, b)) / r for b, r in ratios.items() if abs(r) > RATIO_FLOOR},
            ref)


def twist_arrows(shapes: dict, angles: dict, view_direction, size: float) -> list:
    """(body, start point (m), arrow vector (m), sign) per body of ``angles``: on the rim
    point facing ``view_direction``, tangent to the rim in the sense of the angle, length
    ``ARROW_FRACTION * size`` for the largest |angle|; ``sign`` +1 in the reference's sense."""
    amax = max((abs(a) for a in angles.values()), default=0.0)
    if amax <= 0:
        return []
    v = np.asarray(view_direction, float)
    out = []
    for name, a in angles.items():
        if abs(a) < ARROW_FLOOR * amax or name not in shapes:
            continue
        sh = shapes[name]
        ax = sh.axes[:, 2]
        toward = v - (v @ ax) * ax
        n = np.linalg.norm(toward)
        toward = sh.axes[:, 0] if n < 1e-9 else toward / n
        rim = sh.position + ax * sh.axial_offset + toward * (sh.r_outer + 0.01 * size)
        out.append((name, rim, np.cross(ax, toward) * np.sign(a) * ARROW_FRACTION * size * abs(a) / amax,
                    float(np.sign(a))))
    return out
