"""Spring elements acting on the 6-DOF motions [u (m), theta (rad)] of attachment points.

Each element is a set of strain measures ``e = B @ w`` (``w`` stacks the attachment
motions of its bodies in global axes, ground = no motion) with diagonal stiffness ``k``;
its stiffness on ``w`` is ``B.T @ diag(k) @ B`` and its strain energy ``0.5 * e @ (k * e)``.
Where an element attaches to a body is the body model's business (rigid transfer for a
rigid body, an interface master node for a flexible one), so the same element serves
every fidelity.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from .kinematics import block_rotation, rigid_transfer, unit


@dataclass(frozen=True)
class Element:
    """Springs ``k`` (one per row of ``B``) on the motions of bodies at ``point``.

    ``bodies`` has one or two names; ``None`` stands for the housing (no motion).
    ``B`` has 6 columns per entry of ``bodies`` (global axes). ``fields`` names the scene
    field behind each row's stiffness (e.g. ``k_radial``, ``stiffness``) and ``item`` the
    scene table entry that made the element (e.g. ``("bearings", 2)``, expanded scene), so
    that a spring can be named in an error message. ``mass`` (optional, kg and kg m^2):
    a mass matrix on the same stacked attachment motions, for an element that carries
    mass of its own (a beam shaft's half masses at its end bodies, :mod:`assembly.mechanics.beam`).
    ``c`` (optional; N s/m, N m s/rad): viscous dampers, one per row of ``B`` beside ``k``
    (a row may carry a damper without a spring, ``k = 0``); None: no damper.
    """

    name: str
    kind: str
    bodies: tuple[Optional[str], ...]
    point: np.ndarray
    B: np.ndarray
    k: np.ndarray
    interfaces: tuple = (None, None)
    fields: tuple = ()
    item: tuple = ()
    mass: Optional[np.ndarray] = None
    c: Optional[np.ndarray] = None

    def stiffness(self) -> np.ndarray:
        """Element stiffness on the stacked attachment motions (global axes), exactly
        symmetric: a sum of rank-one springs ``k_j * outer(b_j, b_j)``."""
        return _rank_one_sum(self.B, self.k)

    def damping(self) -> np.ndarray:
        """Element damping on the stacked attachment motions (global axes): a sum of
        rank-one dampers ``c_j * outer(b_j, b_j)`` (zero without dampers)."""
        c = np.zeros(len(self.k)) if self.c is None else self.c
        return _rank_one_sum(self.B, c)


def _rank_one_sum(B: np.ndarray, d: np.ndarray) -> np.ndarray:
    """``sum_j d_j outer(b_j, b_j)`` over the rows of ``B``, exactly symmetric."""
    if B.shape[0] == 1:
        return d[0] * np.outer(B[0], B[0])
    A = (B.T * d) @ B
    return 0.5 * (A + A.T)


def relative_spring(name: str, kind: str, body_a, body_b, point, axes: np.ndarray,
                    k_diag, fields: tuple = (), c_diag=None) -> Element:
    """Diagonal 6x6 spring on the motion of ``body_a`` relative to ``body_b`` at ``point``.

    ``axes`` (3x3, columns = local x, y, z) orient ``k_diag`` = (kx, ky, kz, krx, kry, krz);
    ``fields`` optionally names the scene field of each of the six entries; ``c_diag``
    (optional, N s/m and N m s/rad) the viscous dampers in the same six directions.
    Entries without spring and damper are dropped; infinite entries must have been turned
    into constraints.
    """
    k = np.asarray(k_diag, float)
    if np.any(np.isinf(k)):
        raise ValueError(f"{name}: infinite stiffness must be handled as a constraint")
    c = np.zeros(6) if c_diag is None else np.asarray(c_diag, float)
    Rt = block_rotation(axes).T
    keep = (k > 0) | (c > 0)
    B = np.hstack([Rt, -Rt])[keep]
    kept = tuple(f for f, on in zip(fields, keep) if on)
    return Element(name, kind, (body_a, body_b), np.asarray(point, float), B, k[keep], fields=kept,
                   c=c[keep] if np.any(c > 0) else None)


def line_of_action(axis, c1, c2, r1: float, r2: float, pressure_angle: float,
                   helix_angle: float, drive_sign: int):
    """Unit line-of-action vector ``n`` and pitch point ``p`` of a parallel-axis mesh.

    Transverse frame: ``ez`` = gear axis, ``ex`` along the centre line oriented so that
    ``c2 = c1 + C ex`` with ``C = (r1 + r2)/cos(alpha)`` signed (an internal gear has a
    negative base radius, so for it ``ex`` points from the ring centre out through gear 1).
    ``n = sin(alpha) cos(beta) ex + s (cos(alpha) cos(beta) ey + sin(beta) ez)``: its ``ex``
    part is always positive (gear 1 pushes gear 2 away), and ``s = +-1`` picks one of the
    two lines of action, mirror images about the centre line (the two tooth flanks): the
    one on which turning gear 1 by a positive angle about ``ez`` (``drive_sign`` = +1)
    closes the mesh. Same as Peeters et al. (2006) with ``s = -sign(phi_t)``. The pitch
    point divides the centre line in the ratio r1 : r2 and lies on the line of action.
    """
    ez = unit(axis, "gear axis")
    c1 = np.asarray(c1, float)
    d = np.asarray(c2, float) - c1
    d_t = d - (d @ ez) * ez
    ex = (1.0 if (r1 + r2) > 0 else -1.0) * unit(d_t, "centre line")
    ey = np.cross(ez, ex)
    ca, sa = math.cos(pressure_angle), math.sin(pressure_angle)
    cb, sb = math.cos(helix_angle), math.sin(helix_angle)
    p = c1 + (r1 / ca) * ex
    for s in (1.0, -1.0):
        n = sa * cb * ex + s * (ca * cb * ey + sb * ez)
        # d(compression)/d(theta1) = ez . ((p - c1) x n) must have the driving sign.
        if np.sign(ez @ np.cross(p - c1, n)) == drive_sign:
            return n, p
    raise AssertionError("unreachable: one flank always closes for each sense")


def gear_mesh(name: str, body1: str, body2: str, axis, c1, c2, r1, r2, pressure_angle,
              helix_angle, drive_sign, stiffness, contact_point: str = "pitch", damping: float = 0.0) -> Element:
    """Rank-one mesh spring ``k * outer(g, g)`` on the motions of both gears, and beside it
    the damper ``damping * outer(g, g)`` (N s/m, along the same line of action).

    ``contact_point="pitch"`` (default): compression ``delta = n . (u1(p) - u2(p))`` at the
    pitch point, shared by both gears, so a common rigid motion of the pair strains nothing.
    ``contact_point="tangent"``: each gear's motion is taken at its own base-circle tangent
    point, as in the formulation of Peeters et al. (2006) / Kahraman that produced the
    published helical-pair table; for a helix angle != 0 that variant puts strain into a
    common rigid tilt of both gears, so use it to reproduce literature, not by default.
    """
    n, p = line_of_action(axis, c1, c2, r1, r2, pressure_angle, helix_angle, drive_sign)
    if contact_point == "pitch":
        pts = (p, p)
    elif contact_point == "tangent":
        ez = unit(axis, "gear axis")
        t = n - (n @ ez) * ez
        t = t / np.linalg.norm(t)
        pts = tuple(p + ((np.asarray(c, float) - p) @ t) * t for c in (c1, c2))
    else:
        raise ValueError(f"contact_point must be 'pitch' or 'tangent', got {contact_point!r}")
    # Attachment motions are taken at pts[0] (gear 1) and pts[1] (gear 2); the element's
    # ``point`` is gear 1's, and gear 2's offset goes into B through a rigid arm.
    g1 = np.concatenate([n, np.zeros(3)])
    g2 = -np.concatenate([n, np.zeros(3)]) @ rigid_transfer(pts[1], pts[0])
    g = np.concatenate([g1, g2])
    return Element(name, "mesh", (body1, body2), pts[0], g[None, :], np.array([float(stiffness)]),
                   fields=("stiffness",), c=np.array([float(damping)]) if damping else None)
