"""Beam shafts drawn as cylinders of their diameter between their nodes (m).

A beam shaft (:attr:`assembly.scene.tables.Shaft.is_beam`) is a chain of Timoshenko elements
between consecutive nodes: body1's attachment point, its stations, body2's attachment point
(:func:`assembly.scene.shafts.beam_nodes`). Each element is drawn as a tube of the shaft's outer
radius along its centre line. In a mode shape the centre line follows the nodes' motions
[u, theta] with the cubic Hermite shape functions of a beam element (the element's own
bending interpolation): for xi = s / L in [0, 1],

    w(xi) = H1 u_a + H2 L (theta_a x e) + H3 u_b + H4 L (theta_b x e),
    H1 = 1 - 3 xi^2 + 2 xi^3,  H2 = xi - 2 xi^2 + xi^3,  H3 = 3 xi^2 - 2 xi^3,  H4 = xi^3 - xi^2,

with ``e`` the element's unit axis; the slope of the deformed centre line at a node is the
node's rotation crossed with the axis. Pure numpy except :func:`shaft_tube` (pyvista).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .plotter import load_pyvista

#: Points along each element's drawn centre line.
CENTRELINE_POINTS = 9


@dataclass(frozen=True)
class ShaftSegment:
    """One beam element drawn as a tube: from ``a`` (m, on body ``body_a``) to ``b`` (on
    ``body_b``), outer ``radius`` (m)."""

    name: str
    body_a: str
    body_b: str
    a: np.ndarray
    b: np.ndarray
    radius: float


def shaft_segments(model) -> list:
    """:class:`ShaftSegment` of every element of every beam shaft of an assembled model,
    in the order of ``model.elements`` (matched by the element's scene item)."""
    from ...scene.attach import component_masters
    from ...scene.shafts import beam_nodes
    sc = model.scene
    by_name = {b.name: b for b in sc.bodies}
    masters = None
    out = []
    for i, s in enumerate(sc.shafts):
        if not s.is_beam:
            continue
        masters = component_masters(sc) if masters is None else masters
        nodes = beam_nodes(s, i, by_name, masters)
        els = [el for el in model.elements if el.kind == "shaft" and el.item == ("shafts", i)]
        for el, na, nb in zip(els, nodes, nodes[1:]):
            out.append(ShaftSegment(el.name, na[0], nb[0], np.asarray(na[1], float), np.asarray(nb[1], float),
                                    0.5 * s.diameter))
    return out


def hermite_centreline(a, b, motion_a, motion_b, n: int = CENTRELINE_POINTS):
    """(points (n, 3), displacements (n, 3)) along the element from ``a`` to ``b`` (m) for
    node motions ``motion_a``/``motion_b`` = [u (m), theta (rad)] (global axes): the cubic
    Hermite interpolation of the module doc."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    L = float(np.linalg.norm(b - a))
    e = (b - a) / L
    ma, mb = np.asarray(motion_a, float), np.asarray(motion_b, float)
    xi = np.linspace(0.0, 1.0, n)[:, None]
    H1, H2 = 1 - 3 * xi**2 + 2 * xi**3, xi - 2 * xi**2 + xi**3
    H3, H4 = 3 * xi**2 - 2 * xi**3, xi**3 - xi**2
    w = (H1 * ma[:3] + H2 * L * np.cross(ma[3:6], e) + H3 * mb[:3] + H4 * L * np.cross(mb[3:6], e))
    return a + xi * (b - a), w


def shaft_tube(seg: ShaftSegment, motion, scale: float = 0.0, n_sides: int = 24):
    """Tube (pyvista PolyData) of ``seg``: its centre line moved by ``scale`` x the Hermite
    displacement of the node motions ``motion(body, point)`` -> [u, theta] (None: undeformed),
    with point array ``"displacement_m"`` (unscaled magnitude, m)."""
    pv = load_pyvista()
    zero = np.zeros(6)
    ma = zero if motion is None else motion(seg.body_a, seg.a)
    mb = zero if motion is None else motion(seg.body_b, seg.b)
    P, w = hermite_centreline(seg.a, seg.b, ma, mb)
    line = pv.lines_from_points(P + scale * w)
    line.point_data["displacement_m"] = np.linalg.norm(w, axis=1)
    return line.tube(radius=seg.radius, n_sides=n_sides, capping=True)
