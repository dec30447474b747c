"""Bearings, shafts and gear meshes drawn as zig-zag springs between their attachment points.

:func:`spring_glyphs` places each element of an assembled model once, on the undeformed
drawing (:mod:`assembly.app.render.shapes`): a bearing to the housing ends on a fixed ground
point (out of the body's free face, or radially from a seat away from the body's centre); a
spring between a body and the plate that carries it runs axially to the plate; a mesh
spring lies along the line of action at the contact point, on the front face so it stays
visible. Beam shafts are not springs: they are drawn as tubes
(:mod:`assembly.app.render.shafts`). :func:`spring_points` moves both ends with their
bodies in a mode shape and returns the zig-zag's points. Pure numpy.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .shapes import assembly_size, rigid_displacement, rigid_part
from .views import View


def zigzag(a: np.ndarray, b: np.ndarray, lateral: np.ndarray, amplitude: float, coils: int = 6,
           lead: float = 0.15) -> np.ndarray:
    """Points of a zig-zag spring from ``a`` to ``b`` (straight leads at both ends)."""
    d = b - a
    ts = [0.0, lead]
    ts += list(lead + (1 - 2 * lead) * (np.arange(1, 2 * coils) / (2 * coils)))
    ts += [1 - lead, 1.0]
    offs = [0.0, 0.0] + [amplitude * (1 if k % 2 == 0 else -1) for k in range(2 * coils - 1)] + [0.0, 0.0]
    return np.array([a + t * d + o * lateral for t, o in zip(ts, offs)])


@dataclass
class SpringGlyph:
    """A spring of element ``name`` (its ``kind``, e.g. 'bearing', 'mesh', 'shaft') drawn
    from ``a`` (moves with body ``body_a``) to ``b`` (``body_b``; None = housing, fixed);
    ``ground``: ``b`` is a housing point (drawn as a small cube). Each end moves with its
    body's motion at that point (:func:`spring_points`)."""

    name: str
    kind: str
    a: np.ndarray
    b: np.ndarray
    body_a: str | None
    body_b: str | None
    ground: bool = False


def spring_glyphs(model, shapes: dict) -> list:
    """Where to draw each bearing, shaft and mesh of ``model`` (beam shafts are cylinders:
    :mod:`assembly.app.render.shafts`)."""
    size = assembly_size(shapes)
    out = []
    used_starts: list = []

    def free_start(p, axis, shape):
        # Spread springs that would start at the same point (coaxial sun/ring/carrier).
        e1 = shape.axes[:, 1]
        k = 0
        q = p.copy()
        while any(np.linalg.norm(q - u) < 1e-3 * size for u in used_starts):
            k += 1
            q = p - e1 * (0.35 * k * shape.r_outer)
        used_starts.append(q)
        return q

    beams = {i for i, sh in enumerate(model.scene.shafts) if sh.is_beam}
    for el in model.elements:
        if el.kind == "shaft" and el.item[:1] == ("shafts",) and el.item[1] in beams:
            continue   # drawn as a cylinder (render_shafts)
        if el.kind == "mesh":
            s1, s2 = shapes[el.bodies[0]], shapes[el.bodies[1]]
            ax = s1.axes[:, 2]
            # The element's own contact point and line of action (B = [n, 0, -n ...]).
            p, n = np.asarray(el.point, float), np.asarray(el.B[0, :3], float)
            half = 0.5 * min(abs(s1.r_outer) if s1.kind != "ring" else s1.r_inner,
                              abs(s2.r_outer) if s2.kind != "ring" else s2.r_inner)
            front = max(s1.axial_offset + s1.width / 2, s2.axial_offset + s2.width / 2)
            # Mesh spring in the front-face plane, along the line of action (in-plane part).
            nt = n - (n @ ax) * ax
            nt = nt / np.linalg.norm(nt)
            zc = (p - s1.position) @ ax
            p_front = p + ax * (front - zc + 0.02 * size)
            out.append(SpringGlyph(el.name, "mesh", p_front - half * nt, p_front + half * nt,
                                   el.bodies[0], el.bodies[1]))
        else:
            ba, bb = el.bodies
            sa = shapes[ba]
            ax = sa.axes[:, 2]
            L = 0.12 * size
            off_body = np.linalg.norm(np.asarray(el.point, float) - sa.position) > 1e-3 * size
            if bb is None and off_body:
                # Bearing seat away from the body's centre (e.g. on a shaft): radial spring
                # from the seat to the housing.
                start = np.asarray(el.point, float)
                out.append(SpringGlyph(el.name, el.kind, start, start - L * sa.axes[:, 1], ba, None, True))
            elif bb is None:
                # Bearing to the housing: axial spring out of the free face to a ground point.
                if sa.kind == "plate":
                    start = sa.face_center_back
                    direction = -ax
                else:
                    start = sa.face_center_front
                    direction = ax
                    if sa.kind == "ring":
                        start = start - sa.axes[:, 1] * 0.5 * (sa.r_inner + sa.r_outer)
                start = free_start(start, ax, sa)
                out.append(SpringGlyph(el.name, el.kind, start, start + L * direction, ba, None, True))
            else:
                sb = shapes[bb]
                if sb.kind == "plate" or sa.kind == "plate":
                    body, plate = (sa, sb) if sb.kind == "plate" else (sb, sa)
                    a = body.face_center_back
                    b = a + plate.axes[:, 2] * ((plate.face_center_front - a) @ plate.axes[:, 2])
                    if sa.kind == "plate":
                        a, b = b, a
                    out.append(SpringGlyph(el.name, el.kind, a, b, ba, bb))
                elif np.linalg.norm(sa.position - sb.position) > 1e-3 * size:
                    out.append(SpringGlyph(el.name, el.kind, sa.position.copy(), sb.position.copy(), ba, bb))
                else:
                    a = free_start(sa.face_center_front, ax, sa)
                    out.append(SpringGlyph(el.name, el.kind, a, a + 0.6 * L * ax, ba, bb))
    return out


def spring_points(model, g: SpringGlyph, res_shape_of, scale: float, view: View):
    """(zig-zag points (n, 3), unscaled displacement (m) of end ``a``, of end ``b``) of the
    spring ``g`` with each end moved by ``scale`` x its body's motion in the mode shape
    ``res_shape_of(body)`` (None: undeformed); a flexible body moves an interface point
    with ``motion_at``, any other point rigidly. The zig-zag lies across ``view``'s
    direction."""
    def moved(p, body):
        if body is None:
            return p, 0.0
        bm = model.bodies[body]
        z = res_shape_of(body)
        if z is None:
            return p, 0.0
        if bm.flexible:  # drawn with its own mesh
            try:
                d = (bm.motion_at(p) @ np.asarray(z, float))[:3]
            except (ValueError, KeyError):  # glyph end is not an interface point
                d = rigid_displacement(rigid_part(bm, z), bm.position, p[None, :])[0]
        else:
            d = rigid_displacement(rigid_part(bm, z), bm.position, p[None, :])[0]
        return p + scale * d, float(np.linalg.norm(d))

    a, da = moved(g.a, g.body_a)
    b, db = moved(g.b, g.body_b)
    L0 = float(np.linalg.norm(g.b - g.a))
    d = b - a
    lat = np.cross(d, view.direction)
    if np.linalg.norm(lat) < 1e-12 * max(L0, 1e-30):
        lat = view.up
    lat = lat / np.linalg.norm(lat)
    return zigzag(a, b, lat, 0.12 * L0 if g.kind != "mesh" else 0.09 * L0, coils=5), da, db
