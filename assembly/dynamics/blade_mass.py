"""A blade's mass moments from its distributed mass, summed the way ElastoDyn sums them, and
the rotor's inertia about the shaft axis.

ElastoDyn (OpenFAST's structural module, FAST's before it) takes the flexible blade, of length
``L = TipRad - HubRad`` from the root along the pitch axis, as elements j of width ``dr_j``
centred at ``r_j`` from the root; an element's mass is ``m_j = mu(r_j / L) dr_j`` with ``mu``
the blade table's BMassDen (times AdjBlMs) interpolated linearly in BlFract (held constant past
the table's ends). A tip-brake mass ``M_t`` sits at ``r = L``. About the blade root::

    mass = M_t + sum m_j,   first = M_t L + sum m_j r_j,   second = M_t L^2 + sum m_j r_j^2

A blade point at ``r`` from the root lies ``(HubRad + r) cos(precone)`` from the shaft axis, so
the rotor's inertia about that axis is (ElastoDyn's RotIner, which it writes to its summary)::

    J = HubIner + sum over blades cos^2(precone) (second + 2 HubRad first + HubRad^2 mass)

OpenFAST's ElastoDyn cuts the blade into ``BldNodes`` equal elements (:func:`uniform_elements`);
FAST v7 used AeroDyn's elements instead, so the same blade table gives a different sum there.
The midpoint sum is what the simulation code runs with, which is why it is kept here rather than
the exact integral of the interpolated table: for the NREL 5 MW deck the two differ by 0.45 %
(ElastoDyn's 17 equal elements give 38 677 041 kg m^2, the exact integral 38 501 328 kg m^2).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class BladeMass:
    """A blade's ``mass`` (kg), ``first`` (kg m) and ``second`` (kg m^2) mass moments about
    its root, along the pitch axis."""

    mass: float
    first: float
    second: float


def uniform_elements(count: int, length: float) -> tuple[np.ndarray, np.ndarray]:
    """(centres, widths) of ``count`` equal elements over a blade of ``length`` (ElastoDyn's
    ``RNodes``, ``DRNodes``), from the root."""
    width = length / count
    return (np.arange(count) + 0.5) * width, np.full(count, width)


def blade_mass(fraction, density, length: float, centres, widths, tip_mass: float = 0.0) -> BladeMass:
    """Mass moments about the root (module notes) of a blade of ``length`` whose mass per
    length (kg/m) is ``density`` at the stations ``fraction`` of the length, summed over the
    elements ``centres``, ``widths`` (m from the root), with a ``tip_mass`` at its tip."""
    centres = np.asarray(centres, float)
    m = np.interp(centres / length, np.asarray(fraction, float), np.asarray(density, float)) * np.asarray(widths, float)
    return BladeMass(mass=tip_mass + float(m.sum()),
                     first=tip_mass * length + float(m @ centres),
                     second=tip_mass * length ** 2 + float(m @ centres ** 2))


def rotor_inertia(hub_inertia: float, hub_radius: float, blades: Sequence[tuple[BladeMass, float]]) -> float:
    """The rotor's inertia about the shaft axis (kg m^2): the hub's plus each blade's, for
    ``blades`` as (:class:`BladeMass`, precone in rad), their roots ``hub_radius`` from the
    apex (module notes)."""
    return hub_inertia + sum(math.cos(cone) ** 2 * (b.second + 2 * hub_radius * b.first + hub_radius ** 2 * b.mass)
                             for b, cone in blades)
