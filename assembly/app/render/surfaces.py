"""Surfaces (pyvista PolyData) of the bodies, undeformed and moved by a mode shape.

A rigid or torsional body is the triangulated solid of its drawn shape
(:mod:`assembly.app.render.shapes`) moved rigidly; a flexible body (``bm.flexible``) is its
own FE surface moved by the back-expanded displacement
(:func:`assembly.app.render.fe.fe_surface`). Each surface carries the point array
``"displacement_m"``: the unscaled displacement magnitude (m) the images are coloured by.
pyvista is imported lazily (:func:`assembly.app.render.plotter.load_pyvista`).
"""
from __future__ import annotations

import numpy as np

from .fe import fe_surface
from .plotter import load_pyvista
from .shapes import body_shapes, rigid_displacement, rigid_part, solid_surface


def body_actor(model, name: str, shape, scale: float = 1.0, shapes: dict | None = None,
               _cache: dict | None = None):
    """Warped surface (pyvista PolyData) of body ``name`` for mode shape ``shape`` (the body's
    slice of ``ModalResult.abs_shapes``), points moved by ``scale * displacement``, with point
    array ``"displacement_m"`` = unscaled displacement magnitude (m).

    A flexible body draws its own FE surface; rigid and torsional bodies are solids of their
    geometry moved rigidly.
    """
    pv = load_pyvista()
    bm = model.bodies[name]
    if bm.flexible:
        return fe_surface(bm, np.asarray(shape), scale)
    ref = reference_surface(model, name, shapes, _cache)
    d = rigid_displacement(rigid_part(bm, shape), bm.position, np.asarray(ref.points))
    out = pv.PolyData(np.asarray(ref.points) + scale * d, ref.faces)
    out.point_data["displacement_m"] = np.linalg.norm(d, axis=1)
    return out


def reference_surface(model, name: str, shapes: dict | None = None, _cache: dict | None = None):
    """Undeformed surface (pyvista PolyData) of body ``name``."""
    pv = load_pyvista()
    if _cache is not None and name in _cache:
        return _cache[name]
    bm = model.bodies[name]
    if bm.flexible:
        surf = fe_surface(bm, None, 0.0)
    else:
        shapes = shapes if shapes is not None else body_shapes(model)
        P, F = solid_surface(shapes[name])
        surf = pv.PolyData(P, np.hstack([np.full((len(F), 1), 3), F]).ravel())
    if _cache is not None:
        _cache[name] = surf
    return surf
