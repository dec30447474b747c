"""A user's volume mesh file (gmsh .msh, Abaqus .inp, Salome/Code_Aster .med, .vtu, ...: read
by meshio; Nastran .bdf/.nas: :mod:`fe_components.part.nastran`) as a component: checked,
converted to metres and to the part's own frame, its interfaces found by name or rule,
written into the mesh cache in the package's own sealed gmsh format.

Tetrahedra only, linear (``tetra``, P1) or quadratic (``tetra10``, P2: the midside nodes are
kept where the file puts them, so curved boundaries stay curved); ``order = 2`` lifts a
linear mesh to P2 (:func:`fe_components.part.cells.lift_to_p2`). Node order: a format's own
(MED's is VTK's mirror image, :data:`~fe_components.part.cells.MIRROR`; Nastran numbers a
CTETRA either way and a left-handed one is renumbered, as Nastran does). Named groups: gmsh
physical groups, any meshio cell set of surface triangles (an Abaqus ``*ELSET`` of faces), a
MED group of faces, and point sets (an Abaqus ``*NSET``, a MED group of nodes): the boundary
faces whose nodes all belong to the set. What else the file holds is dropped and reported
(:class:`~fe_components.part.cells.ReadSummary`). Checks
(:class:`~fe_components.part.file.PartFileError`, naming the file): unreadable, no volume
elements, other element types, inverted (negative volume) or degenerate (zero volume)
tetrahedra, a size that betrays wrong units.
"""
from __future__ import annotations

import contextlib
import functools
import io
import logging
import os
from dataclasses import dataclass

import numpy as np

from ..gmsh_session import gmsh_model
from .cells import (
    MIRROR,
    OTHER_VOLUME_TYPES,
    SOLID_TYPES,
    TET_EDGES,
    CellCount,
    ReadSummary,
    boundary_faces,
    dropped_cells,
    lift_to_p2,
    med_groups,
    tet_volumes,
)
from .file import UNITS, PartFile, PartFileError
from .frame import PartFrame
from .geometry import Faces, PartGeometry, check_size, in_frame, resolve_interfaces
from .nastran import NastranError, read_bulk

log = logging.getLogger(__name__)

#: meshio's tetra10 node order -> gmsh's (the last two edges swapped).
_TO_GMSH_TET10 = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]
#: A tetrahedron smaller than this fraction of the median volume is degenerate.
DEGENERATE = 1e-6
NASTRAN_SUFFIXES = (".bdf", ".nas")


@dataclass(frozen=True)
class FileCells:
    """A mesh file as read, before any check: points (file units, the file's axes), cell
    blocks ``[(meshio type, cells)]``, named cell sets (per block) and point sets, and the
    element cards counted but not read (Nastran)."""

    points: np.ndarray
    blocks: list
    cell_sets: dict
    point_sets: dict
    cards: tuple = ()


def _file_cells(part: PartFile) -> FileCells:
    """Read the file with its format's reader; any failure names the file."""
    name = part.path.name
    suffix = part.path.suffix.lower()
    if suffix in NASTRAN_SUFFIXES:
        try:
            deck = read_bulk(part.file)
        except NastranError as exc:
            raise PartFileError("file", part.file, f"{name}: {exc}") from None
        except OSError as exc:
            raise PartFileError("file", part.file, f"{name}: cannot read: {exc.strerror or exc}") from None
        blocks = [({4: "tetra", 10: "tetra10"}[n], t) for n, t in deck.tets.items()]
        cards = tuple(CellCount(card, n, kind) for card, (kind, n) in deck.others.items())
        return FileCells(deck.points, blocks, {}, {}, cards)
    import meshio
    # a .msh is gmsh's (meshio would try ANSYS's first, print its failure and, on a corrupt
    # file, sys.exit): name the format where the suffix is ambiguous
    fmt = "gmsh" if suffix == ".msh" else None
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            m = meshio.read(part.file, file_format=fmt)   # its own failure messages are printed
    except (Exception, SystemExit) as exc:  # meshio raises many kinds on a bad file
        raise PartFileError("file", part.file, f"{name}: cannot read as a mesh ({type(exc).__name__}: {exc})") from None
    cell_sets, point_sets = med_groups(m) if suffix == ".med" else (m.cell_sets, m.point_sets)
    return FileCells(np.asarray(m.points, float), [(c.type, np.asarray(c.data)) for c in m.cells], cell_sets,
                     point_sets)


def _solid_type(part: PartFile, fc: FileCells) -> str:
    """The file's one tetrahedron type; anything else that fills a volume is refused."""
    vol = {t for t, c in fc.blocks if t in SOLID_TYPES + OTHER_VOLUME_TYPES and len(c)}
    vol |= {c.name for c in fc.cards if c.kind == "solid"}
    name = part.path.name
    if not vol:
        raise PartFileError("file", part.file, f"{name}: holds no volume elements (a surface mesh?)")
    if vol - set(SOLID_TYPES) or len(vol) > 1:
        raise PartFileError("file", part.file, f"{name}: holds {sorted(vol)} elements: only tetrahedra of one "
                                               "order (tetra or tetra10) are supported")
    return vol.pop()


def _oriented(part: PartFile, ctype: str, cells: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, int]:
    """(cells in VTK's node order, number renumbered) by the format's convention: MED's
    mirror image always; a Nastran CTETRA numbered left-handed renumbered (G2 <-> G3), as
    Nastran itself does; every other format as given."""
    suffix = part.path.suffix.lower()
    if suffix == ".med":
        return cells[:, MIRROR[ctype]], 0
    if suffix in NASTRAN_SUFFIXES:
        flip = tet_volumes(points, cells) < 0
        cells = cells.copy()
        cells[flip] = cells[flip][:, MIRROR[ctype]]
        return cells, int(flip.sum())
    return cells, 0


@dataclass(frozen=True)
class MeshPart:
    """A mesh file read and checked: points (m, the file's axes), tetrahedra (VTK order;
    ``tetra10`` once lifted), their type, named face/node sets, and what was read."""

    points: np.ndarray
    cells: np.ndarray
    cell_type: str
    named: dict
    summary: ReadSummary


@functools.lru_cache(maxsize=4)
def _read(part: PartFile) -> MeshPart:
    """The file's tetrahedra, checked, in metres; named face-node sets; the read summary."""
    fc = _file_cells(part)
    ctype = _solid_type(part, fc)
    name = part.path.name
    if part.order == 1 and ctype == "tetra10":
        raise PartFileError("order", 1, f"{name}: holds quadratic tetrahedra (tetra10): order = 1 would drop "
                                        "their midside nodes; leave order out")
    cells, renumbered = _oriented(part, ctype, np.concatenate([c for t, c in fc.blocks if t == ctype])
                                  .astype(np.int64), fc.points)
    used = np.unique(cells)
    remap = np.full(len(fc.points), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    pts = np.asarray(fc.points, float)[used, :3] * UNITS[part.units]
    cells = remap[cells]
    _check_elements(part, pts, cells)
    if ctype == "tetra10":
        _check_curved(part, pts, cells)
    named = {}
    for key, per_block in fc.cell_sets.items():
        if key.startswith("gmsh:"):
            continue
        ids = [remap[b[1][i]] for b, i in zip(fc.blocks, per_block)
               if b[0] in ("triangle", "triangle6") and i is not None and len(i)]
        if ids:
            named[key] = ("faces", [np.sort(x[:, :3], axis=1) for x in ids])
    for key, idx in fc.point_sets.items():
        named[key] = ("nodes", remap[np.asarray(idx, dtype=np.int64)])
    others = [(t, remap[np.asarray(c, np.int64)]) for t, c in fc.blocks if t != ctype and len(c)]
    summary = ReadSummary(name, ctype, len(cells), dropped_cells(others, boundary_faces(cells)[:, :3]) + fc.cards,
                          loose_nodes=len(fc.points) - len(used), renumbered=renumbered,
                          lifted=part.order == 2 and ctype == "tetra", linear_ok=part.order == 1)
    if summary.lifted:
        pts, cells = lift_to_p2(pts, cells)
    return MeshPart(pts, cells, "tetra10" if summary.lifted else ctype, named, summary)


def _check_elements(part: PartFile, pts: np.ndarray, cells: np.ndarray) -> None:
    """Refuse inverted (negative volume) and degenerate (zero volume) tetrahedra."""
    vol = tet_volumes(pts, cells)
    med = float(np.median(np.abs(vol)))
    bad = {"inverted (negative volume)": np.flatnonzero(vol < -DEGENERATE * med),
           "degenerate (zero volume)": np.flatnonzero(np.abs(vol) <= DEGENERATE * med)}
    for what, idx in bad.items():
        if len(idx):
            c = pts[cells[idx[0], :4]].mean(axis=0)
            hint = ""
            if len(idx) == len(cells) and part.path.suffix.lower() == ".med":
                hint = ("; read in MED's node order (Salome, Code_Aster): the file was written in another "
                        "order (e.g. VTK's, by meshio)")
            raise PartFileError("file", part.file, f"{part.path.name}: {len(idx)} of {len(cells)} tetrahedra are "
                                                   f"{what}; first: element {int(idx[0])} at "
                                                   f"{np.round(c, 6).tolist()} m{hint}")


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
    """Group name -> indices of the boundary faces it holds: a face set's faces, or the faces
    whose corner nodes all belong to a node set (so that a node set of a linear file still
    finds its faces once lifted to P2)."""
    key = np.sort(bf[:, :3], axis=1)
    index = {tuple(k): i for i, k in enumerate(key)}
    out = {}
    for name, (kind, data) in named.items():
        if kind == "faces":
            out[name] = sorted({index[tuple(k)] for block in data for k in block if tuple(k) in index})
        else:
            member = np.zeros(int(bf.max()) + 1, bool)
            member[data[(data >= 0) & (data < len(member))]] = True
            out[name] = np.flatnonzero(member[bf[:, :3]].all(axis=1)).tolist()
    return out


def _resolved(part: PartFile):
    """(the read file, its points in the part's local frame, boundary faces, interfaces in
    the local frame, local box): the rules act on the file's axes."""
    mp = _read(part)
    frame = PartFrame.of(part.axis, part.origin)
    local = frame.points(mp.points)
    lo, hi = local.min(axis=0), local.max(axis=0)
    check_size(part, lo, hi, UNITS[part.units], part.units)
    bf = boundary_faces(mp.cells)
    faces = _faces(mp.points, bf)
    size = float(np.linalg.norm(hi - lo))
    interfaces = in_frame(resolve_interfaces(part, faces, _named_faces(mp.named, bf), size), frame)
    return mp, local, bf, interfaces, (lo, hi)


def read_part_geometry(part: PartFile) -> PartGeometry:
    """The part's size, volume, centroid and inertia per unit density (of the straight
    elements), median edge, interfaces (:class:`~fe_components.part.geometry.PartGeometry`)
    and what was read, in its local frame."""
    mp, pts, _, interfaces, (lo, hi) = _resolved(part)
    V, c, J = mass_moments(pts, mp.cells)
    edges = np.linalg.norm(pts[mp.cells[:, TET_EDGES[:, 0]]] - pts[mp.cells[:, TET_EDGES[:, 1]]], axis=-1)
    return PartGeometry(lo, hi, V, c, J, interfaces, "mesh", float(np.median(edges)), mp.summary)


def generate_part_mesh(part: PartFile, options, path) -> None:
    """Write the part's mesh to ``path`` in gmsh's format (the package's cache format), in its
    local frame: the elements as given (or lifted to P2), a physical volume ``solid`` and one
    physical surface group per interface holding its faces. ``options`` is not used: a mesh
    file is taken as it is."""
    mp, pts, bf, interfaces, _ = _resolved(part)
    ctype, cells = mp.cell_type, mp.cells
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
