"""Surfaces of flexible bodies for rendering (pyvista, imported lazily)."""
from __future__ import annotations

import numpy as np

_SURF: dict = {}


def fe_surface(body, shape, scale: float):
    """Outer surface of a flexible body's mesh (global axes), moved by ``scale`` x the
    back-expanded displacement of body DOFs ``shape`` (None: undeformed). Point array
    ``displacement_m`` (unscaled magnitude, m).

    The P2 (10-node) tetrahedra are drawn with their mid-side nodes: each quadratic surface
    triangle becomes four flat triangles through its six nodes (VTK nonlinear subdivision,
    level 1), so curved faces follow the FE geometry and the quadratic displacement field.
    Every drawn point is an FE node (matched once by position), so the displacement is
    the nodal one, not an interpolation."""
    import pyvista as pv
    from scipy.spatial import cKDTree
    fe, _ = body.coupled()
    key = id(fe)
    if key not in _SURF:
        m = fe.mesh
        pts = body.origin + np.asarray(m.p).T @ body.axes.T
        if m.t.shape[0] == 4 and hasattr(m, "t2e") and m.p.shape[1] > int(m.t.max()) + 1:
            # skfem's edge order per tetra (01, 12, 02, 03, 13, 23) is VTK's quadratic-tetra order.
            conn = np.vstack([m.t, int(m.t.max()) + 1 + m.t2e]).T.astype(np.int64)
            grid = pv.UnstructuredGrid({pv.CellType.QUADRATIC_TETRA: conn}, pts)
            surf = grid.extract_surface(pass_pointid=False, pass_cellid=False, nonlinear_subdivision=1,
                                        algorithm="dataset_surface")
        else:
            grid = pv.UnstructuredGrid({pv.CellType.TETRA: m.t[:4].T.astype(np.int64)}, pts)
            surf = grid.extract_surface(pass_pointid=False, pass_cellid=False, algorithm="dataset_surface")
        # Nodes in DOF order (what displacement_global returns), global axes.
        _, ids = cKDTree(body.origin + np.asarray(fe.nodes) @ body.axes.T).query(np.asarray(surf.points, float))
        _SURF[key] = (surf, ids, fe.nodes.shape[0])
    surf, ids, nv = _SURF[key]
    out = surf.copy()
    if shape is None:
        out.point_data["displacement_m"] = np.zeros(out.n_points)
        return out
    d = body.displacement_global(shape)[:nv][ids]
    out.points = np.asarray(surf.points) + scale * d
    out.point_data["displacement_m"] = np.linalg.norm(d, axis=1)
    return out


def render_stress_image(body, zb, path, title: str, window_size=(1200, 900)):
    """PNG of one flexible body coloured by von Mises stress (MPa) for body DOFs ``zb``,
    drawn on its undeformed surface; fixed camera from the body's bounding box."""
    from .render import _pyvista
    pv = _pyvista()
    st = body.stress(zb)
    fe, _ = body.coupled()
    nv = fe.mesh.p.shape[1]
    surf = fe_surface(body, None, 0.0)
    ids = _SURF[id(fe)][1]
    surf.point_data["von_mises_MPa"] = st.von_mises[:nv][ids] / 1e6
    pl = pv.Plotter(off_screen=True, window_size=list(window_size))
    try:
        pl.set_background("white")
        pl.add_mesh(surf, scalars="von_mises_MPa", cmap="turbo", show_edges=False,
                    scalar_bar_args=dict(title="von Mises [MPa]", color="black", vertical=False,
                                         position_x=0.55, position_y=0.04, width=0.4, height=0.07, fmt="%.3g"))
        k = int(np.argmax(st.von_mises))
        pmax = body.origin + body.axes @ st.points[k]
        pl.add_points(np.array([pmax]), color="black", point_size=14, render_points_as_spheres=True)
        pl.add_text(f"{title}\nmax over all nodes {st.von_mises[k] / 1e6:.4g} MPa at ({pmax[0]:.4f}, "
                    f"{pmax[1]:.4f}, {pmax[2]:.4f}) m (black dot); colours: outer surface",
                    position="upper_left", font_size=12, color="black")
        pl.camera_position = "iso"
        pl.reset_camera()
        pl.screenshot(str(path))
    finally:
        pl.close()
    return float(st.von_mises[k]), pmax
