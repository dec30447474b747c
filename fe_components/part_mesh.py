"""A user's volume mesh file (read by meshio: gmsh .msh, Abaqus .inp, Nastran .bdf, .vtu, ...)
as a component: checked, converted to metres, its interfaces found by name or rule, written
into the mesh cache in the package's own sealed gmsh format.

Tetrahedra only, linear (``tetra``, P1) or quadratic (``tetra10``, P2: the midside nodes are
kept where the file puts them, so curved boundaries stay curved). Named groups: gmsh physical
groups and any meshio cell set of surface triangles (an Abaqus ``*ELSET`` of faces), and
point sets (an Abaqus ``*NSET``): the boundary faces whose nodes all belong to the set.
Checks (:class:`~fe_components.part_file.PartFileError`, naming the file): unreadable, no
volume elements, other element types, inverted (negative volume) or degenerate (zero
volume) tetrahedra, a size that betrays wrong units.
"""
from __future__ import annotations

import contextlib
import functools
import io
import logging
import os

import numpy as np

from .gmsh_session import gmsh_model
from .part_file import UNITS, PartFile, PartFileError
from .part_geometry import Faces, PartGeometry, check_size, resolve_interfaces

log = logging.getLogger(__name__)

#: Corner triplets of a tetrahedron's faces, and the midside nodes of each (meshio / VTK
#: ``tetra10`` order: 4..9 on edges 01, 12, 02, 03, 13, 23), outward for a positive tetrahedron.
_FACES = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
_FACE_MIDS = np.array([[6, 5, 4], [4, 8, 7], [5, 9, 8], [7, 9, 6]])
_TET_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])
#: meshio's tetra10 node order -> gmsh's (the last two edges swapped).
_TO_GMSH_TET10 = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]
#: A tetrahedron smaller than this fraction of the median volume is degenerate.
DEGENERATE = 1e-6


@functools.lru_cache(maxsize=4)
def _read(part: PartFile):
    """(points m, cells, cell type, named face-node sets) of the file, checked."""
    import meshio
    name = part.path.name
    # a .msh is gmsh's (meshio would try ANSYS's first, print its failure and, on a corrupt
    # file, sys.exit): name the format where the suffix is ambiguous
    fmt = "gmsh" if part.path.suffix.lower() == ".msh" else None
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            m = meshio.read(part.file, file_format=fmt)   # its own failure messages are printed
    except (Exception, SystemExit) as exc:  # meshio raises many kinds on a bad file
        raise PartFileError("file", part.file, f"{name}: cannot read as a mesh ({type(exc).__name__}: {exc})") from None
    vol = {c.type for c in m.cells if c.type in ("tetra", "tetra10", "hexahedron", "hexahedron20", "hexahedron27",
                                                  "wedge", "wedge15", "pyramid", "pyramid13")}
    if not vol:
        raise PartFileError("file", part.file, f"{name}: holds no volume elements (a surface mesh?)")
    if vol - {"tetra", "tetra10"} or len(vol) > 1:
        raise PartFileError("file", part.file, f"{name}: holds {sorted(vol)} elements: only tetrahedra of one "
                                               "order (tetra or tetra10) are supported")
    ctype = vol.pop()
    cells = np.concatenate([c.data for c in m.cells if c.type == ctype]).astype(np.int64)
    used = np.unique(cells)
    remap = np.full(len(m.points), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    pts = np.asarray(m.points, float)[used, :3] * UNITS[part.units]
    cells = remap[cells]
    _check_elements(part, pts, cells)
    if ctype == "tetra10":
        _check_curved(part, pts, cells)
    named = {}
    for key, per_block in m.cell_sets.items():
        if key.startswith("gmsh:"):
            continue
        ids = [remap[b.data[i]] for b, i in zip(m.cells, per_block)
               if b.type in ("triangle", "triangle6") and i is not None and len(i)]
        if ids:
            named[key] = ("faces", [np.sort(x[:, :3], axis=1) for x in ids])
    for key, idx in m.point_sets.items():
        named[key] = ("nodes", remap[np.asarray(idx, dtype=np.int64)])
    return pts, cells, ctype, named


def _check_elements(part: PartFile, pts: np.ndarray, cells: np.ndarray) -> None:
    """Refuse inverted (negative volume) and degenerate (zero volume) tetrahedra."""
    vol = tet_volumes(pts, cells)
    med = float(np.median(np.abs(vol)))
    bad = {"inverted (negative volume)": np.flatnonzero(vol < -DEGENERATE * med),
           "degenerate (zero volume)": np.flatnonzero(np.abs(vol) <= DEGENERATE * med)}
    for what, idx in bad.items():
        if len(idx):
            c = pts[cells[idx[0], :4]].mean(axis=0)
            raise PartFileError("file", part.file, f"{part.path.name}: {len(idx)} of {len(cells)} tetrahedra are "
                                                   f"{what}; first: element {int(idx[0])} at "
                                                   f"{np.round(c, 6).tolist()} m")


#: Reference points where a curved (P2) element's Jacobian must be positive: the 4
#: vertices, the 6 edge midpoints, the centroid and the 4 face centroids.
_P2_CHECK_POINTS = np.array(
    [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [.5, 0, 0], [.5, .5, 0], [0, .5, 0], [0, 0, .5], [.5, 0, .5],
     [0, .5, .5], [.25, .25, .25], [1 / 3, 1 / 3, 0], [1 / 3, 0, 1 / 3], [0, 1 / 3, 1 / 3], [1 / 3, 1 / 3, 1 / 3]]).T


def _check_curved(part: PartFile, pts: np.ndarray, cells: np.ndarray) -> None:
    """Refuse a P2 element whose Jacobian is not positive everywhere: evaluated at its
    vertices, edge midpoints and face and body centroids (a midside node moved across the
    element folds it near a vertex while the quadrature points may still see it positive)."""
    import meshio
    from skfem.io.meshio import from_meshio
    mesh = from_meshio(meshio.Mesh(pts, [("tetra10", cells)]))
    mp = mesh._mapping()
    J = [[mp.J(i, j, _P2_CHECK_POINTS) for j in range(3)] for i in range(3)]
    d = (J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0])
         + J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]))   # det J per element and point
    bad = np.flatnonzero(d.min(axis=1) <= 0)
    if len(bad):
        c = pts[cells[bad[0], :4]].mean(axis=0)
        raise PartFileError("file", part.file, f"{part.path.name}: {len(bad)} of {len(cells)} curved (P2) "
                                               f"tetrahedra are folded or inverted (Jacobian not positive "
                                               f"everywhere); first: element {int(bad[0])} at "
                                               f"{np.round(c, 6).tolist()} m")


def tet_volumes(pts: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Signed volumes (m^3) of the straight tetrahedra on the corner nodes."""
    p = pts[cells[:, :4]]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6.0


def boundary_faces(cells: np.ndarray) -> np.ndarray:
    """Faces (corner nodes, then midside for P2) that belong to one tetrahedron only."""
    corners = cells[:, _FACES].reshape(-1, 3)
    key = np.sort(corners, axis=1)
    _, inv, count = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    once = count[inv.ravel()] == 1
    if cells.shape[1] == 10:
        return np.hstack([corners, cells[:, _FACE_MIDS].reshape(-1, 3)])[once]
    return corners[once]


def mass_moments(pts: np.ndarray, cells: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """(volume m^3, centroid m, inertia per unit density about it m^5) of the straight
    tetrahedra: the second moment of a tetrahedron is ``V/20 (sum x_i x_i' + s s')``, ``s``
    the sum of its corners."""
    p = pts[cells[:, :4]]
    v = tet_volumes(pts, cells)
    V = v.sum()
    c = (v @ p.mean(axis=1)) / V
    q = p - c
    s = q.sum(axis=1)
    S = np.einsum("e,eij->ij", v / 20.0, np.einsum("eki,ekj->eij", q, q) + np.einsum("ei,ej->eij", s, s))
    return float(V), c, np.trace(S) * np.eye(3) - S


def _faces(pts: np.ndarray, bf: np.ndarray) -> Faces:
    p = pts[bf[:, :3]]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    return Faces(pts[bf], area, p.mean(axis=1), np.arange(len(bf)))


def _named_faces(named: dict, bf: np.ndarray) -> dict:
    """Group name -> indices of the boundary faces it holds."""
    key = np.sort(bf[:, :3], axis=1)
    index = {tuple(k): i for i, k in enumerate(key)}
    out = {}
    for name, (kind, data) in named.items():
        if kind == "faces":
            out[name] = sorted({index[tuple(k)] for block in data for k in block if tuple(k) in index})
        else:
            member = np.zeros(int(bf.max()) + 1, bool)
            member[data[data < len(member)]] = True
            out[name] = np.flatnonzero(member[bf].all(axis=1)).tolist()
    return out


def _resolved(part: PartFile):
    pts, cells, ctype, named = _read(part)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    check_size(part, lo, hi, UNITS[part.units], part.units)
    bf = boundary_faces(cells)
    faces = _faces(pts, bf)
    size = float(np.linalg.norm(hi - lo))
    interfaces = resolve_interfaces(part, faces, _named_faces(named, bf), size)
    return pts, cells, ctype, bf, interfaces, (lo, hi)


def read_part_geometry(part: PartFile) -> PartGeometry:
    """The part's size, volume, centroid and inertia per unit density (of the straight
    elements), median edge and interfaces (:class:`~fe_components.part_geometry.PartGeometry`)."""
    pts, cells, _, _, interfaces, (lo, hi) = _resolved(part)
    V, c, J = mass_moments(pts, cells)
    edges = np.linalg.norm(pts[cells[:, _TET_EDGES[:, 0]]] - pts[cells[:, _TET_EDGES[:, 1]]], axis=-1)
    return PartGeometry(lo, hi, V, c, J, interfaces, "mesh", float(np.median(edges)))


def generate_part_mesh(part: PartFile, options, path) -> None:
    """Write the part's mesh to ``path`` in gmsh's format (the package's cache format): the
    elements as given, a physical volume ``solid`` and one physical surface group per
    interface holding its faces. ``options`` is not used: a mesh file is taken as it is."""
    pts, cells, ctype, bf, interfaces, _ = _resolved(part)
    with gmsh_model("part-file") as gmsh:
        v = gmsh.model.addDiscreteEntity(3)
        tags = np.arange(1, len(pts) + 1)
        gmsh.model.mesh.addNodes(3, v, tags.tolist(), pts.ravel().tolist())
        order = _TO_GMSH_TET10 if ctype == "tetra10" else [0, 1, 2, 3]
        gmsh.model.mesh.addElementsByType(v, 11 if ctype == "tetra10" else 4, [],
                                          (cells[:, order] + 1).ravel().tolist())
        gmsh.model.addPhysicalGroup(3, [v], name="solid")
        tri = 9 if ctype == "tetra10" else 2
        for itf in interfaces:
            s = gmsh.model.addDiscreteEntity(2)
            gmsh.model.mesh.addElementsByType(s, tri, [], (bf[itf.face_ids] + 1).ravel().tolist())
            gmsh.model.addPhysicalGroup(2, [s], name=itf.name)
        gmsh.option.setNumber("Mesh.Binary", 1)
        gmsh.write(os.fspath(path))
