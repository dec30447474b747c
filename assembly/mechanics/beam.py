"""Two-node Timoshenko beam element of circular (hollow) section, as an :class:`Element`.

Its stiffness is written as six strain measures with a diagonal stiffness each (local
axes: ``ez`` along the beam from node a to node b, ``ex``, ``ey`` across), so that the
strain energy of every element -- and of every strain measure -- stays exact:

=========================  =====================================  ==================
strain measure             on the node motions [u, theta]          stiffness
=========================  =====================================  ==================
axial                      (u_b - u_a) . ez                        E A / L  (N/m)
twist                      (th_b - th_a) . ez                      G J_p / L (N m/rad)
bending about ex, ey       (th_b - th_a) . ex, . ey                E I / L  (N m/rad)
shear/chord in x-z plane   (u_b - u_a) . ex / L - (th_a + th_b) . ey / 2    12 E I / (L (1 + Phi))
shear/chord in y-z plane   (u_b - u_a) . ey / L + (th_a + th_b) . ex / 2    (N m/rad)
=========================  =====================================  ==================

with ``Phi = 12 E I / (kappa G A L^2)`` and the shear coefficient ``kappa`` of Cowper
(1966), J. Appl. Mech. 33, 335-340, for a hollow circular section. ``B' diag(k) B`` is the
textbook 12 x 12 Timoshenko stiffness matrix (Przemieniecki (1968), Theory of Matrix
Structural Analysis, eq. 5.116), checked entry by entry in tests/mechanics/test_beam_shaft.py.

Mass is lumped at the two nodes, half of the element to each: ``m_e / 2`` in each
translation, ``rho J_p L / 2`` about the axis and ``rho I L / 2`` (``I = J_p / 2``) about
each transverse axis. No ``m_e L^2 / 12`` term is added to the transverse inertia: the two
end masses already overstate the element's rotary inertia about its centre by
``m_e L^2 / 6 - m_e L^2 / 12 = m_e L^2 / 12`` (their ``m_e L^2 / 4`` against the rod's
``m_e L^2 / 12``), so such a term would double that error instead of correcting it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from .elements import Element
from .kinematics import axis_frame, rigid_transfer, unit


@dataclass(frozen=True)
class Section:
    """Circular (hollow) section: area A (m^2), second moment I (m^4) about a diameter,
    polar moment J_p = 2 I (m^4) and Cowper's shear coefficient kappa (-)."""

    A: float
    I: float
    J_p: float
    kappa: float


def cowper_kappa(nu: float, m: float) -> float:
    """Timoshenko shear coefficient of a hollow circular section, bore/outer diameter
    ratio ``m`` (0 = solid): Cowper (1966), Table 1,
    ``6 (1 + nu) (1 + m^2)^2 / ((7 + 6 nu) (1 + m^2)^2 + (20 + 12 nu) m^2)``."""
    q = (1.0 + m * m) ** 2
    return 6.0 * (1.0 + nu) * q / ((7.0 + 6.0 * nu) * q + (20.0 + 12.0 * nu) * m * m)


def section(diameter: float, bore_diameter: float, nu: float) -> Section:
    """Section properties of a round shaft, outer ``diameter`` and ``bore_diameter`` (m)."""
    d, di = diameter, bore_diameter
    A = math.pi * (d ** 2 - di ** 2) / 4.0
    I = math.pi * (d ** 4 - di ** 4) / 64.0
    return Section(A, I, 2.0 * I, cowper_kappa(nu, di / d))


def strain_measures(length: float, axes: np.ndarray) -> np.ndarray:
    """(6 x 12) rows of the strain measures above on [u_a, th_a, u_b, th_b] (global axes)
    for an element of ``length`` (m) whose local axes are the columns of ``axes``
    (third = beam axis). Rows: axial, twist, bending about ex, about ey, shear x-z, y-z."""
    ex, ey, ez = axes.T
    z3 = np.zeros(3)
    return np.array([
        np.concatenate([-ez, z3, ez, z3]),
        np.concatenate([z3, -ez, z3, ez]),
        np.concatenate([z3, -ex, z3, ex]),
        np.concatenate([z3, -ey, z3, ey]),
        np.concatenate([-ex / length, -ey / 2, ex / length, -ey / 2]),
        np.concatenate([-ey / length, ex / 2, ey / length, ex / 2]),
    ])


def stiffnesses(length: float, sec: Section, material) -> np.ndarray:
    """Diagonal stiffness of the six strain measures (N/m, then N m/rad)."""
    E, G = material.E, material.G
    phi = 12.0 * E * sec.I / (sec.kappa * G * sec.A * length ** 2)
    shear = 12.0 * E * sec.I / (length * (1.0 + phi))
    return np.array([E * sec.A / length, G * sec.J_p / length, E * sec.I / length, E * sec.I / length,
                     shear, shear])


def node_mass(length: float, sec: Section, rho: float, axes: np.ndarray) -> np.ndarray:
    """6 x 6 lumped mass (global axes, kg and kg m^2) one node takes from an element of
    ``length`` (m): half its mass and half its section rotary inertia (module notes)."""
    polar = rho * sec.J_p * length / 2.0
    M = np.zeros((6, 6))
    M[:3, :3] = rho * sec.A * length / 2.0 * np.eye(3)
    M[3:, 3:] = axes @ np.diag([polar / 2.0, polar / 2.0, polar]) @ axes.T
    return M


def timoshenko_element(name: str, body_a: Optional[str], body_b: Optional[str], p_a, p_b, sec: Section,
                       material, lumped=(True, True), interfaces=(None, None), item: tuple = ()) -> Element:
    """Timoshenko element from point ``p_a`` on ``body_a`` to ``p_b`` on ``body_b`` (m).

    Both bodies' motions are taken at the element's ``point`` ``p_a`` (as every element
    does), and body b's is carried to ``p_b`` by a rigid arm folded into ``B`` and the mass
    (as :func:`assembly.mechanics.elements.gear_mesh` does for its two contact points): exact for a
    rigid body and for a flexible body's interface master alike, since rigid transfers
    compose. ``lumped``: whether the element carries the half mass of node a / node b (a
    shaft's end bodies cannot hold it; its stations' bodies do)."""
    p_a, p_b = np.asarray(p_a, float), np.asarray(p_b, float)
    length = float(np.linalg.norm(p_b - p_a))
    axes = axis_frame(unit(p_b - p_a, f"{name} axis"))
    arm = np.eye(12)
    arm[6:, 6:] = rigid_transfer(p_b, p_a)
    B = strain_measures(length, axes) @ arm
    M = np.zeros((12, 12))
    for j, on in enumerate(lumped):
        if on:
            M[6 * j:6 * j + 6, 6 * j:6 * j + 6] = node_mass(length, sec, material.rho, axes)
    mass = arm.T @ M @ arm if M.any() else None
    return Element(name, "shaft", (body_a, body_b), p_a, B, stiffnesses(length, sec, material),
                   interfaces=tuple(interfaces), fields=("diameter",) * 6, item=item,
                   mass=None if mass is None else 0.5 * (mass + mass.T))
