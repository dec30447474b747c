"""Mesh-quality check: catch sliver tetrahedra before they poison K.

Quality of a tetrahedron: q = 6 sqrt(2) V / l_rms^3 (V its volume, l_rms the root mean
square of its six edge lengths): 1 for the regular tetrahedron, -> 0 for a sliver (four
nearly coplanar vertices, which a length-based criterion does not see). Corner vertices
only; lengths in m.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import MeshingError

#: Elements below this quality make the stiffness matrix ill-conditioned; refuse them.
MIN_QUALITY = 1e-3


@dataclass(frozen=True)
class QualityReport:
    quality: np.ndarray      # (n_elements,) q in [0, 1]
    worst: int               # element index of the minimum
    worst_quality: float
    worst_center: np.ndarray  # (3,) m


def tet_quality(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """q = 6 sqrt(2) |V| / l_rms^3 of each tetrahedron (points (n, 3), tets (n_el, >=4))."""
    p = points[tets[:, :4]]
    a, b, c, d = p[:, 0], p[:, 1], p[:, 2], p[:, 3]
    vol = np.abs(np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))) / 6.0
    edges = [b - a, c - a, d - a, c - b, d - b, d - c]
    l2 = sum(np.einsum("ij,ij->i", e, e) for e in edges) / 6.0
    return 6.0 * np.sqrt(2.0) * vol / np.maximum(l2, 1e-300) ** 1.5


def check_quality(points: np.ndarray, tets: np.ndarray, min_quality: float = MIN_QUALITY) -> QualityReport:
    """Quality of every element; raises MeshingError naming the worst one below ``min_quality``."""
    q = tet_quality(np.asarray(points, float), np.asarray(tets))
    k = int(np.argmin(q))
    center = np.asarray(points, float)[np.asarray(tets)[k, :4]].mean(axis=0)
    rep = QualityReport(q, k, float(q[k]), center)
    if q[k] < min_quality:
        raise MeshingError("mesh", {"worst_element": k, "quality": float(q[k]),
                                    "center_m": [round(float(x), 6) for x in center],
                                    "n_below": int(np.sum(q < min_quality))},
                           f"sliver elements (quality < {min_quality:g}): refine or remesh")
    return rep
