"""The cells of a user's mesh file: the tetrahedra the part is made of, what else the file
holds (dropped, and said so), the node order of the file's format, and a linear mesh lifted
to P2 (numpy only; node orders are meshio's / VTK's).

What a part drops is reported (:class:`ReadSummary`): a surface, line or point cell lying on
the solid's boundary (a face, an edge, a node of it) is the mesher's tag of that boundary
(gmsh physical groups, Salome groups) and named as such; anything else -- a shell, a beam, a
point mass, a spring -- is left out of the model, and the summary flags it.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SOLID_TYPES = ("tetra", "tetra10")
#: Volume cells that cannot be a part (only tetrahedra are).
OTHER_VOLUME_TYPES = ("hexahedron", "hexahedron20", "hexahedron24", "hexahedron27", "wedge", "wedge12", "wedge15",
                      "wedge18", "pyramid", "pyramid13", "pyramid14")
#: Corner triplets of a tetrahedron's faces (outward for a positive one) and their midside
#: nodes (``tetra10``: 4..9 on edges 01, 12, 02, 03, 13, 23).
TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
TET_FACE_MIDS = np.array([[6, 5, 4], [4, 8, 7], [5, 9, 8], [7, 9, 6]])
TET_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])
#: The same tetrahedron with its other handedness: corners 1 and 2 swapped, the edge nodes
#: following. It turns MED's order (Salome, Code_Aster: the face N1 N2 N3 numbered outward,
#: edge nodes N5..N10 on N1N2, N2N3, N3N1, N1N4, N2N4, N3N4) into VTK's (that face numbered
#: inward, towards N4; the same edges), and is Nastran's renumbering of a left-handed CTETRA
#: (G2 and G3 swapped, OptiStruct's CTETRA remarks). gmsh's MED reader (GModelIO_MED.cpp,
#: med2mshNodeIndex) maps the same way.
MIRROR = {"tetra": np.array([0, 2, 1, 3]), "tetra10": np.array([0, 2, 1, 3, 6, 5, 4, 7, 9, 8])}
#: A boundary tag's kind, by the dimension of the cell.
_TAG = {2: "boundary face", 1: "boundary edge", 0: "boundary node"}


def cell_dimension(cell_type: str) -> int:
    """0 (points), 1 (lines), 2 (surfaces) or 3 (volumes) of a meshio cell type."""
    if cell_type.startswith(("triangle", "quad", "polygon")):
        return 2
    if cell_type.startswith("line"):
        return 1
    if cell_type == "vertex":
        return 0
    return 3


def tet_volumes(pts: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Signed volumes (m^3) of the straight tetrahedra on the corner nodes."""
    p = pts[cells[:, :4]]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6.0


def boundary_faces(cells: np.ndarray) -> np.ndarray:
    """Faces (corner nodes, then midside for P2) that belong to one tetrahedron only."""
    corners = cells[:, TET_FACES].reshape(-1, 3)
    key = np.sort(corners, axis=1)
    _, inv, count = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    once = count[inv.ravel()] == 1
    if cells.shape[1] == 10:
        return np.hstack([corners, cells[:, TET_FACE_MIDS].reshape(-1, 3)])[once]
    return corners[once]


def on_boundary(cells: np.ndarray, boundary: np.ndarray, dim: int) -> np.ndarray:
    """Which ``cells`` (corner nodes first; -1 for a node of no tetrahedron) of dimension
    ``dim`` lie on the solid's boundary (``boundary``: its faces' corner nodes): a triangle
    that is a boundary face, a line along an edge of one, a point at a node of one."""
    if dim == 2 and cells.shape[1] not in (3, 6, 7):   # a quadrilateral is no face of a tetrahedron
        return np.zeros(len(cells), bool)
    k = {2: 3, 1: 2, 0: 1}[dim]
    if dim == 2:
        known = boundary
    elif dim == 1:
        known = boundary[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2)
    else:
        known = boundary.reshape(-1, 1)
    known = {tuple(r) for r in np.sort(known, axis=1)}
    corners = np.sort(cells[:, :k], axis=1)
    return np.array([bool((r >= 0).all()) and tuple(r) in known for r in corners], bool)


def lift_to_p2(points: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A linear mesh as P2: a node at the middle of every edge (shared by the tetrahedra on
    it, appended after the corners), ``tetra10`` cells. Straight edges: the same geometry."""
    key = np.sort(tets[:, TET_EDGES], axis=2).reshape(-1, 2)
    edges, inv = np.unique(key, axis=0, return_inverse=True)
    mids = 0.5 * (points[edges[:, 0]] + points[edges[:, 1]])
    return np.vstack([points, mids]), np.hstack([tets, len(points) + inv.reshape(-1, 6)])


def med_groups(mesh) -> tuple[dict, dict]:
    """(cell sets, point sets) of a MED file read by meshio, from its families: meshio keeps
    a cell's or node's family number (``cell_tags``, ``point_tags``) and each family's group
    names (``mesh.cell_tags``, ``mesh.point_tags``); a group is every family that names it."""
    cell_sets, point_sets = {}, {}
    tags = mesh.cell_data.get("cell_tags", [None] * len(mesh.cells))
    for fam, names in getattr(mesh, "cell_tags", {}).items():
        for name in names:
            per_block = cell_sets.setdefault(name, [np.zeros(0, np.int64) for _ in mesh.cells])
            for b, t in enumerate(tags):
                if t is not None:
                    per_block[b] = np.union1d(per_block[b], np.flatnonzero(np.asarray(t) == fam))
    ptags = mesh.point_data.get("point_tags")
    for fam, names in getattr(mesh, "point_tags", {}).items():
        for name in names:
            hit = np.flatnonzero(np.asarray(ptags) == fam) if ptags is not None else np.zeros(0, np.int64)
            point_sets[name] = np.union1d(point_sets.get(name, np.zeros(0, np.int64)), hit)
    return cell_sets, point_sets


@dataclass(frozen=True)
class CellCount:
    """Cells a part file holds and the part leaves out: ``name`` (meshio cell type, or the
    Nastran card), ``count``, ``kind`` (``boundary face``/``edge``/``node``: the mesher's tags
    of the solid's boundary; else ``surface``, ``line``, ``point``, ``shell``, ``beam``,
    ``spring``, ``mass``, ``rigid``: left out of the model)."""

    name: str
    count: int
    kind: str

    @property
    def is_tag(self) -> bool:
        return self.kind.startswith("boundary")


def counts_text(cells) -> str:
    """``56 triangle6 (surface), 3 CBAR (beam)`` of :class:`CellCount` s."""
    return ", ".join(f"{c.count} {c.name} ({c.kind})" for c in cells)


def dropped_cells(blocks, boundary: np.ndarray) -> tuple[CellCount, ...]:
    """What the part leaves out of the (type, cells in solid node numbers) ``blocks`` that
    are not tetrahedra: per type, the cells on the solid's boundary (tags) and the others."""
    out = []
    for ctype in dict.fromkeys(t for t, _ in blocks):
        cells = np.concatenate([c for t, c in blocks if t == ctype])
        dim = cell_dimension(ctype)
        tag = on_boundary(cells, boundary, dim) if dim < 3 else np.zeros(len(cells), bool)
        if tag.any():
            out.append(CellCount(ctype, int(tag.sum()), _TAG[dim]))
        if (~tag).any():
            out.append(CellCount(ctype, int((~tag).sum()), {2: "surface", 1: "line", 0: "point"}.get(dim, "other")))
    return tuple(out)


@dataclass(frozen=True)
class ReadSummary:
    """What was read from a mesh file and what was left out.

    file : the file's name; solid : ``tetra`` or ``tetra10`` as in the file; n_solid : their
    number; dropped : the other cells (:class:`CellCount`); loose_nodes : nodes of no
    tetrahedron; renumbered : left-handed tetrahedra renumbered (Nastran's rule);
    lifted : a linear mesh lifted to P2 (``order = 2``); linear_ok : linear kept on request
    (``order = 1``)."""

    file: str
    solid: str
    n_solid: int
    dropped: tuple[CellCount, ...] = ()
    loose_nodes: int = 0
    renumbered: int = 0
    lifted: bool = False
    linear_ok: bool = False

    @property
    def order(self) -> int:
        """Element order of the model: 2 for tetra10 or a lifted mesh, else 1."""
        return 2 if self.lifted or self.solid == "tetra10" else 1

    @property
    def left_out(self) -> tuple[CellCount, ...]:
        """Dropped cells that are not boundary tags: what the file meant as part of the model."""
        return tuple(c for c in self.dropped if not c.is_tag)

    def text(self) -> str:
        """One line: ``read 1234 tetra10; dropped 56 triangle6 (surface), 3 CBAR (beam)``."""
        parts = [f"read {self.n_solid} {self.solid}"]
        if self.dropped:
            parts.append("dropped " + counts_text(self.dropped))
        if self.loose_nodes:
            parts.append(f"{self.loose_nodes} nodes in no tetrahedron left out")
        if self.renumbered:
            parts.append(f"{self.renumbered} left-handed tetrahedra renumbered (G2 <-> G3)")
        if self.lifted:
            parts.append("lifted to P2 (order = 2: edge midpoints, straight edges)")
        return "; ".join(parts)
