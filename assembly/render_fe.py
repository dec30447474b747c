"""Surfaces of flexible bodies for rendering (pyvista, imported lazily)."""
from __future__ import annotations

import numpy as np

_SURF: dict = {}


def fe_surface(body, shape, scale: float):
    """Outer surface of a flexible body's mesh (corner nodes, global axes), moved by
    ``scale`` x the back-expanded displacement of body DOFs ``shape`` (None: undeformed).
    Point arrays: ``displacement_m`` (unscaled magnitude, m) and, for a shape,
    ``von_mises_Pa`` when stresses were requested via ``body.info['render_stress']``."""
    import pyvista as pv
    fe, _ = body.coupled()
    key = id(fe)
    if key not in _SURF:
        nv = fe.mesh.p.shape[1]
        pts = body.origin + fe.mesh.p.T @ body.axes.T
        grid = pv.UnstructuredGrid({pv.CellType.TETRA: fe.mesh.t[:4].T.astype(np.int64)}, pts)
        surf = grid.extract_surface(pass_pointid=True)
        _SURF[key] = (surf, np.asarray(surf.point_data["vtkOriginalPointIds"]), nv)
    surf, ids, nv = _SURF[key]
    out = surf.copy()
    if shape is None:
        out.point_data["displacement_m"] = np.zeros(out.n_points)
        return out
    d = body.displacement_global(shape)[:nv][ids]
    out.points = np.asarray(surf.points) + scale * d
    out.point_data["displacement_m"] = np.linalg.norm(d, axis=1)
    return out
