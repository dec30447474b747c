"""Surfaces of flexible bodies for rendering (pyvista, imported lazily)."""
from __future__ import annotations

import time

import numpy as np

from .plotter import load_pyvista, save_png
from .views import WINDOW_SIZE

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
    from scipy.spatial import cKDTree
    pv = load_pyvista()
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


def stress_scale(body, st, title: str, unit: str = "MPa", factor: float = 1e-6) -> dict:
    """Colour range and title of a stress image, from one maximum so they cannot disagree:
    the maximum von Mises stress over *all* nodes of the body (P2 vertices, edge midpoints,
    interior) is both the top of the colour bar (``clim``) and the value in the title; the
    surface, coloured at its corner nodes, may stay below it. ``st``: NodalStress (Pa);
    ``factor``: Pa -> ``unit``. Returns dict(clim, vmax, point (global, m), text)."""
    k = int(np.argmax(st.von_mises))
    vmax = float(st.von_mises[k]) * factor
    pmax = body.origin + body.axes @ st.points[k]
    text = (f"{title}\nmax over all nodes {vmax:.4g} {unit} at ({pmax[0]:.4f}, {pmax[1]:.4f}, "
            f"{pmax[2]:.4f}) m (black dot) = top of the colour bar; colours: outer surface")
    return dict(clim=(0.0, vmax if vmax > 0 else 1.0), vmax=vmax, point=pmax, text=text)


class StressImages:
    """Writes von Mises images of flexible bodies with one off-screen plotter, reused
    for every image (a new plotter costs a new OpenGL context per image). Use as a
    context manager; :meth:`render` writes one PNG."""

    def __init__(self, window_size=WINDOW_SIZE):
        self.window_size = list(window_size)
        self._pl = None
        self.timings: list = []            # seconds per image

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self) -> None:
        if self._pl is not None:
            self._pl.close()
            self._pl = None

    def _plotter(self):
        if self._pl is None:
            pv = load_pyvista()
            self._pl = pv.Plotter(off_screen=True, window_size=self.window_size)
        pl = self._pl
        pl.clear()
        pl.set_background("white")
        return pl

    def render(self, body, st, path, title: str, unit: str = "MPa", factor: float = 1e-6) -> dict:
        """PNG of ``body`` coloured by von Mises stress ``st`` (NodalStress, Pa) x ``factor``
        in ``unit``, on its undeformed surface, fixed camera from the body's bounding box;
        colour range and title from :func:`stress_scale` (returned)."""
        t0 = time.perf_counter()
        fe, _ = body.coupled()
        nv = fe.mesh.p.shape[1]
        surf = fe_surface(body, None, 0.0)
        ids = _SURF[id(fe)][1]
        name = f"von_mises_{unit}"
        surf.point_data[name] = st.von_mises[:nv][ids] * factor
        sc = stress_scale(body, st, title, unit, factor)
        pl = self._plotter()
        pl.suppress_rendering = True     # one render per image, not one per added actor
        pl.add_mesh(surf, scalars=name, cmap="turbo", clim=sc["clim"], show_edges=False,
                    scalar_bar_args=dict(title=f"von Mises [{unit}]", color="black", vertical=False,
                                         position_x=0.55, position_y=0.04, width=0.4, height=0.07, fmt="%.3g"))
        pl.add_points(np.array([sc["point"]]), color="black", point_size=14, render_points_as_spheres=True)
        pl.add_text(sc["text"], position="upper_left", font_size=12, color="black")
        pl.camera_position = "iso"
        pl.reset_camera()
        pl.suppress_rendering = False
        pl.render()
        save_png(pl, path)
        self.timings.append(time.perf_counter() - t0)
        return sc
