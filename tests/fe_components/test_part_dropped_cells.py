"""What a mesh file holds besides its tetrahedra is said, not dropped silently: the read
summary (``PartGeometry.read``, ``FEModel.read``, one log line per file) counts every other
cell by type and kind. Cells on the solid's boundary (a face, an edge, a node of it) are the
mesher's tags of that boundary (gmsh physical groups, Salome groups): INFO. Anything else -- a
shell, a beam, a point mass, a rigid element -- is left out of the model: WARNING, naming
them. Other volume cells than tetrahedra stay refused (tests/fe_components/test_part_input.py).

The files are a structured box (tests/support/mesh_writers.kuhn_box) with cells added whose
kind is known by construction."""
from __future__ import annotations

import logging

import meshio
import numpy as np
import pytest

from fe_components.fe_model import build_component
from fe_components.material import STEEL
from fe_components.part.file import PartFile
from fe_components.part.read import part_geometry
from tests.support.mesh_writers import kuhn_box, nastran_deck

SIZE, CELLS = (0.1, 0.02, 0.02), (5, 1, 1)   # m, cubes: 30 tetrahedra, 24 nodes


def _box_boundary(pts, tets) -> np.ndarray:
    """The box's boundary triangles: the tetrahedron faces with all three corners on one of
    its six planes (a face is on the boundary if and only if it lies in a face of the box)."""
    faces = tets[:, [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]].reshape(-1, 3)
    out = set()
    for f in faces:
        p = pts[f]
        if any(np.ptp(p[:, k]) == 0 and p[0, k] in (0.0, SIZE[k]) for k in range(3)):
            out.add(tuple(sorted(f)))
    return np.array(sorted(out))


@pytest.fixture(scope="module")
def box():
    pts, tets = kuhn_box(SIZE, CELLS)
    tri = _box_boundary(pts, tets)
    assert len(tri) == 2 * (2 * 5 + 2 * 5 + 2)   # two triangles per square of the box's surface
    return pts, tets, tri


def _summary(tmp_path, caplog, name, points, cells, **mesh_kw):
    path = tmp_path / name
    meshio.write(path, meshio.Mesh(points, cells, **mesh_kw))
    with caplog.at_level(logging.INFO, logger="fe_components.part.read"):
        geo = part_geometry(PartFile(str(path), units="m", order=1))
    records = [r for r in caplog.records if r.name == "fe_components.part.read"]
    assert len(records) == 1
    return geo.read, records[0]


def test_boundary_tags_are_named_as_such_without_a_warning(box, tmp_path, caplog):
    """A file as gmsh writes it without physical groups: the boundary triangles, the box's
    12 edges cut into segments and its 8 corners besides the tetrahedra."""
    pts, tets, tri = box
    # two edges of the x = 0 face's triangles: a side of its square (nodes 0, 1) and the
    # diagonal the Kuhn split cuts it along (nodes 0, 3: the cube's diagonal is corner 0 to 6)
    edges = np.array([[0, 1], [0, 3]])
    assert all(np.ptp(pts[e][:, 0]) == 0 and pts[e[0], 0] == 0 for e in edges)
    read, rec = _summary(tmp_path, caplog, "tags.vtu", pts,
                         [("tetra", tets), ("triangle", tri), ("line", edges), ("vertex", np.array([[0], [5]]))])
    assert rec.levelno == logging.INFO
    assert read.text() == (f"read 30 tetra; dropped {len(tri)} triangle (boundary face), 2 line (boundary edge), "
                           "2 vertex (boundary node)")
    assert read.left_out == ()


def test_shells_beams_and_points_off_the_boundary_warn(box, tmp_path, caplog):
    """A shell sheet in the middle of the box (z = 10 mm is no face of the Kuhn cubes' single
    layer), a quadrilateral on the surface (no tetrahedron face is a quad), a beam across a
    cube's face diagonal it does not follow, and a point mass at a node of no tetrahedron."""
    pts, tets, tri = box
    extra = np.array([[0.05, 0.01, 0.01], [0.07, 0.01, 0.01], [0.05, 0.03, 0.01]])
    pts2 = np.vstack([pts, extra])
    n = len(pts)
    sheet = np.array([[n, n + 1, n + 2]])
    quad = np.array([[0, 1, 3, 2]])   # the x = 0 face's square (node = 4 i + 2 j + k)
    assert (pts[quad[0], 0] == 0).all()
    beam = np.array([[0, 23]])        # from one corner of the box to the far one: through it
    read, rec = _summary(tmp_path, caplog, "mixed.vtu", pts2,
                         [("tetra", tets), ("triangle", tri[:4]), ("triangle", sheet), ("quad", quad),
                          ("line", beam), ("vertex", np.array([[n]]))])
    assert rec.levelno == logging.WARNING
    text = rec.getMessage()
    assert text.startswith("mixed.vtu: read 30 tetra; dropped 4 triangle (boundary face), 1 triangle (surface), "
                           "1 quad (surface), 1 line (line), 1 vertex (point); 3 nodes in no tetrahedron left out")
    assert "Left out of the model (only tetrahedra are read): 1 triangle (surface), 1 quad (surface), 1 line (line), " \
           "1 vertex (point)" in text
    assert [c.count for c in read.left_out] == [1, 1, 1, 1] and read.loose_nodes == 3


def test_nastran_cards_left_out_are_named(box, tmp_path, caplog):
    """A deck with shells, a beam, a point mass and a rigid element besides its CTETRAs:
    each card counted by name and kind (Nastran's own element classes), a WARNING."""
    pts, tets, tri = box
    extra = ["CTRIA3,101,2,1,2,3", "CTRIA3,102,2,2,3,4", "CQUAD4,103,2,1,2,7,6", "CBAR,104,3,1,24,0.,0.,1.",
             "CONM2,105,12,,2.5", "RBE2,106,12,123456,1,2,3", "PSOLID,1,1", "MAT1,1,2.1+11,,0.3,7850."]
    path = tmp_path / "deck.bdf"
    path.write_text(nastran_deck(pts, tets, "free", "small-blank", extra=extra))
    with caplog.at_level(logging.INFO, logger="fe_components.part.read"):
        geo = part_geometry(PartFile(str(path), units="m", order=1))
    assert geo.read.text() == ("read 30 tetra; dropped 2 CTRIA3 (shell), 1 CQUAD4 (shell), 1 CBAR (beam), "
                               "1 CONM2 (mass), 1 RBE2 (rigid)")
    (rec,) = [r for r in caplog.records if r.name == "fe_components.part.read"]
    assert rec.levelno == logging.WARNING and "Left out of the model" in rec.getMessage()


def test_the_fe_model_carries_what_was_read(box, tmp_path):
    pts, tets, tri = box
    path = tmp_path / "model.vtu"
    meshio.write(path, meshio.Mesh(pts, [("tetra", tets), ("triangle", tri)]))
    fe = build_component(PartFile(str(path), units="m", order=2), STEEL, cache_dir=tmp_path / "cache")
    assert fe.read.text() == (f"read 30 tetra; dropped {len(tri)} triangle (boundary face); lifted to P2 "
                              "(order = 2: edge midpoints, straight edges)")
    assert fe.read.order == fe.order == 2
