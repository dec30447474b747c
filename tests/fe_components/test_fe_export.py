"""VTU export (meshio) of a component with nodal fields."""
from __future__ import annotations

import meshio
import numpy as np

from cms.eigen import free_free_shift, lowest_modes
from fe_components.export import write_vtu
from fe_components.fe_model import build_component
from fe_components.reference import CASES, REF_DIR


def test_write_vtu_roundtrip(tmp_path):
    params, options = CASES["annulus"]
    m = build_component(params, options=options, cache_dir=REF_DIR)
    mode = lowest_modes(m.K, m.M, 7, sigma=free_free_shift(m.K, m.M)).vectors[:, 6]
    r = np.linalg.norm(m.nodes, axis=1)
    path = write_vtu(tmp_path / "annulus.vtu", m, {"mode_7": mode, "radius": r}, interfaces=True)
    assert path.exists() and not list(tmp_path.glob(".*tmp*"))
    back = meshio.read(path)
    assert back.cells[0].type == "tetra10"
    np.testing.assert_allclose(back.points, m.nodes)
    np.testing.assert_allclose(back.point_data["mode_7"], mode.reshape(-1, 3))
    np.testing.assert_allclose(back.point_data["radius"], r)
    assert back.point_data["interface_end_a"].sum() == len(m.interfaces["end_a"].nodes)
    # VTK tetra10 order: nodes 4..9 on edges (0,1),(1,2),(0,2),(0,3),(1,3),(2,3); on the straight
    # interior edges the mid node is the edge midpoint
    c = back.cells[0].data
    p = back.points
    edges = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    dev = np.stack([np.linalg.norm(p[c[:, 4 + k]] - 0.5 * (p[c[:, a]] + p[c[:, b]]), axis=1)
                    for k, (a, b) in enumerate(edges)])
    h = np.linalg.norm(p[c[:, 1]] - p[c[:, 0]], axis=1)
    assert np.median(dev / h) < 1e-12
    assert np.all(dev / h < 0.2)  # curved boundary edges bend a little, never far
