"""One user's part checked alone, without a bearing or a scene around it: its FE mass
properties (against the CAD-exact ones for a STEP/BREP file), its free-free modes (six
rigid-body modes expected, then the first elastic ones), the interfaces its rules found, what
its file held and what was left out, and the element order. SI units, the part's local axes.

:func:`check_part` takes a :class:`fe_components.part.file.PartFile` (and how it is meshed,
:class:`assembly.scene.tables.FlexOptions`); :func:`check_body_part` the part of a scene's body, as
the scene builds it (its ``flex`` table, the same caches). ``flexgear part`` prints either.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..errors import SceneError, SolverError
from ..scene.tables import FlexOptions

log = logging.getLogger(__name__)

#: Rigid-body modes of a free solid: three translations, three rotations.
RIGID_MODES = 6


@dataclass(frozen=True)
class InterfaceCheck:
    """An interface found in the part: its rule (``select``), coupling, the faces and FE nodes
    it holds, their area (m^2) and its master point (m, local axes)."""

    name: str
    select: str
    coupling: str
    n_faces: int
    n_nodes: int
    area: float
    master: np.ndarray


@dataclass(frozen=True)
class PartCheck:
    """What :func:`check_part` found (SI units, the part's local axes).

    file : the part's file; source : "cad" or "mesh"; order : element order of the model
    (1 or 2); n_elements, n_nodes, n_dofs : FE model size; mesh_size : element size given
    to gmsh (CAD) or the file's median edge (mesh) [m]; read : a mesh file's
    :class:`~fe_components.part.cells.ReadSummary` (None for CAD); material : E, nu, rho;
    mass [kg], center_of_mass [m], inertia [kg m^2, about the centre of mass] of the FE model;
    cad : the same three from the CAD geometry (None for a mesh file) and cad_rel their
    relative differences (mass, centre against the part's size, inertia in the 2-norm);
    frequencies_hz : the lowest free-free frequencies (rigid-body ones first); n_rigid : how
    many of them are rigid-body modes (6 for one free solid); n_pieces : the mesh's pieces
    (elements joined through nodes); interfaces : :class:`InterfaceCheck` in rule order."""

    file: str
    source: str
    order: int
    n_elements: int
    n_nodes: int
    n_dofs: int
    mesh_size: float
    read: object
    material: object
    mass: float
    center_of_mass: np.ndarray
    inertia: np.ndarray
    cad: Optional[tuple]
    cad_rel: dict
    frequencies_hz: np.ndarray
    n_rigid: int
    n_pieces: int
    interfaces: tuple

    @property
    def elastic_hz(self) -> np.ndarray:
        """The free-free frequencies above the rigid-body ones (Hz)."""
        return self.frequencies_hz[self.n_rigid:]


def check_part(part, flex: FlexOptions = FlexOptions(), n_elastic: int = 6, caches=None) -> PartCheck:
    """Mesh (or read), assemble and check ``part`` (a PartFile) alone: meshed as ``flex``
    says (element size, order for a CAD part, material), cached in ``caches``
    (:class:`assembly.model.components.CacheDirs`, default the user's cache). Raises the part's own
    errors (PartFileError, MeshingError) and SolverError if the modes are not finite."""
    from cms.eigen import count_rigid_modes, free_free_shift, lowest_modes
    from fe_components.part.file import PartFile
    from fe_components.part.read import part_geometry

    from ..model.components import CacheDirs, build_fe, mesh_size

    if not isinstance(part, PartFile):
        raise SceneError("component", type(part).__name__, "must be a part read from a file (kind = 'file')")
    if not isinstance(flex, FlexOptions):
        raise SceneError("flex", type(flex).__name__, "must be FlexOptions (how the part is meshed)")
    if isinstance(n_elastic, bool) or not isinstance(n_elastic, int) or not 1 <= n_elastic <= 100:
        raise SceneError("n_elastic", n_elastic, "must be an integer in 1..100")
    caches = CacheDirs() if caches is None else caches
    geo = part_geometry(part)
    fe = build_fe(part, flex, caches)
    pieces = mesh_pieces(fe.mesh.t.T)
    k = min(RIGID_MODES * pieces + n_elastic, fe.n_dofs - 1)   # every piece's rigid-body modes, then elastic
    f = np.sort(lowest_modes(fe.K, fe.M, k, sigma=free_free_shift(fe.K, fe.M)).frequencies_hz)
    if not np.isfinite(f).all():
        raise SolverError("frequencies_hz", f.tolist(), f"{part.path.name}: the free-free modes are not finite")
    n_rigid = count_rigid_modes(f)
    if n_rigid != RIGID_MODES:
        log.warning("%s: %d rigid-body modes where a free solid has %d: %s", part.path.name, n_rigid, RIGID_MODES,
                    f"the part is {pieces} pieces that do not touch" if pieces > 1
                    else "check the mesh (elements joined at an edge or a node only?)")
    cad = None
    if geo.source == "cad":
        rho = flex.material.rho
        cad = (rho * geo.volume, np.asarray(geo.centroid), rho * np.asarray(geo.inertia_per_density))
    interfaces = tuple(InterfaceCheck(i.name, part.rule(i.name)[1].select, i.coupling, len(i.face_ids),
                                      len(fe.interfaces[i.name].nodes), i.area, np.asarray(i.master))
                       for i in geo.interfaces)
    return PartCheck(part.file, geo.source, fe.order, int(fe.mesh.t.shape[1]), int(fe.n_nodes), int(fe.n_dofs),
                     mesh_size(part, flex), geo.read, flex.material, fe.mass, fe.center_of_mass, fe.inertia, cad,
                     dict(fe.checks), f, n_rigid, pieces, interfaces)


def mesh_pieces(cells: np.ndarray) -> int:
    """Number of pieces of a mesh: sets of elements joined through shared nodes."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    n = int(cells.max()) + 1
    rows = np.repeat(cells[:, 0], cells.shape[1])
    graph = sp.coo_matrix((np.ones(rows.size), (rows, cells.ravel())), shape=(n, n))
    used = np.unique(cells)
    _, label = connected_components(graph, directed=False)
    return len(np.unique(label[used]))


def part_bodies(scene) -> dict:
    """Body name -> body of every body of ``scene`` (stages expanded) whose component is a
    part file."""
    from fe_components.part.file import PartFile
    return {b.name: b for b in scene.expanded().bodies if isinstance(b.component, PartFile)}


def check_body_part(scene, body: Optional[str] = None, n_elastic: int = 6, caches=None) -> PartCheck:
    """:func:`check_part` on the part of body ``body`` of ``scene`` (a stage carrier is
    ``<stage>.carrier``), meshed by its ``flex`` table (defaults if none); ``body`` may be
    left out when one body only has a part file."""
    parts = part_bodies(scene)
    if body is None:
        if len(parts) != 1:
            raise SceneError("body", None, f"name the body to check: bodies with a part file: {sorted(parts) or 'none'}")
        body = next(iter(parts))
    if body not in parts:
        names = {b.name for b in scene.expanded().bodies}
        what = "no such body in the scene" if body not in names else "its component is not a part file (kind = 'file')"
        raise SceneError("body", body, f"{what}; bodies with a part file: {sorted(parts) or 'none'}")
    b = parts[body]
    return check_part(b.component, b.flex if b.flex is not None else FlexOptions(), n_elastic, caches)
