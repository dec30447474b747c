"""Linear-elastic FE model of a component (scikit-fem): K, M, mass properties, interfaces.

DOF order is scikit-fem's ``ElementVector`` order: node positions are
``basis.doflocs[:, ::3]`` and DOF ``3 * node + c`` is displacement component
c (0 = x, 1 = y, 2 = z) of that node (the order Exudyn's FEMinterface takes).
Units: SI (m, kg, N, Pa); K in N/m, M in kg.
"""
from __future__ import annotations

import functools
import logging
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np
import scipy.sparse as sp

from .errors import MeshingError
from .geometry import AXIS, characteristic_length, interface_defs
from .mapping_memo import memoised_mapping
from .material import STEEL, Material
from .meshing import MeshOptions, RawMesh, load_mesh
from .params import CarrierParams, CylinderParams, PinionParams, WheelParams, component_kind, params_as_flat_dict
from .part.file import PartFile, PartFileError
from .part.read import part_geometry

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Interface:
    """A named set of surface nodes and the position of its 6-DOF master node.

    nodes : indices into ``FEModel.nodes`` (int array).
    master : master-node position (3,) [m], global axes.
    coupling : default coupling kind, "rbe2" (rigid spider) or "rbe3" (distributing).
    """

    name: str
    nodes: np.ndarray
    master: np.ndarray
    coupling: str

    def dofs(self) -> np.ndarray:
        """Full-model DOFs of the nodes, shape (n_nodes, 3) ordered x, y, z."""
        return 3 * self.nodes[:, None] + np.arange(3)[None, :]


@dataclass
class FEModel:
    """A meshed component: geometry, DOF map, K, M and interfaces together (SI units).

    ``K`` (stiffness, N/m) and ``M`` (consistent mass, kg) are assembled on first use
    (``matrices``): back-expansion and stress recovery of a cached reduction need the mesh,
    the basis and the interfaces only, and skip the assembly (most of a model's build time).
    """

    params: Any
    material: Material
    mesh: Any  # skfem.MeshTet1 / MeshTet2
    basis: Any  # skfem CellBasis with ElementVector (stiffness quadrature)
    interfaces: dict[str, Interface]
    mass: float  # [kg]
    center_of_mass: np.ndarray  # (3,) [m]
    inertia: np.ndarray  # (3, 3) [kg m^2] about the centre of mass, global axes
    axis: np.ndarray = field(default_factory=lambda: AXIS.copy())  # rotation axis (unit, through origin)
    order: int = 2
    mesh_file: Path | None = None
    mesh_sha256: str = ""  # content hash of the mesh file (fe_components.meshing), "" if not from a file
    timings: dict[str, float] = field(default_factory=dict)  # [s]: "mesh", "assembly", "matrices"
    checks: dict[str, float] = field(default_factory=dict)  # self-checks, e.g. FE vs CAD mass (relative)
    read: Any = None  # a mesh file's ReadSummary (fe_components.part.cells): what was read and dropped
    matrices: Callable[[], tuple] | None = field(default=None, repr=False, compare=False)  # -> (K, M)

    @functools.cached_property
    def _KM(self) -> tuple:
        t0 = time.perf_counter()
        KM = self.matrices()
        self.timings["matrices"] = time.perf_counter() - t0
        return KM

    @property
    def K(self) -> sp.csr_matrix:
        """Stiffness matrix [N/m] (CSR), assembled on first use."""
        return self._KM[0]

    @property
    def M(self) -> sp.csr_matrix:
        """Consistent mass matrix [kg] (CSR), assembled on first use."""
        return self._KM[1]

    @property
    def nodes(self) -> np.ndarray:
        """Node positions (n_nodes, 3) [m] in DOF order."""
        return self.basis.doflocs[:, ::3].T

    @property
    def n_nodes(self) -> int:
        return self.basis.N // 3

    @property
    def n_dofs(self) -> int:
        return self.basis.N


def default_mesh_size(params) -> float:
    """A mesh size [m] resolving the thinnest wall of the part with about two P2 elements."""
    if isinstance(params, CylinderParams):
        wall = (params.diameter - params.bore_diameter) / 2
        return min(wall / 2, params.length / 10)
    if isinstance(params, PinionParams):
        t = params.teeth
        feats = [s.diameter / 2 for s in params.shaft] + [t.face_width / 2]
        if t.fidelity == "involute":
            feats.append(1.0 * t.normal_module)
        return min(feats)
    if isinstance(params, WheelParams):
        t = params.teeth
        feats = [params.web_thickness, t.inner_limit_radius - params.rim_inner_diameter / 2,
                 (params.hub_outer_diameter - params.bore_diameter) / 2, t.face_width / 2]
        if params.n_holes:
            feats.append(params.hole_diameter / 2)
        if t.fidelity == "involute":
            feats.append(1.0 * t.normal_module)
        return min(feats)
    if isinstance(params, CarrierParams):
        p = params
        feats = [p.cheek_thickness, p.post_diameter / 2, p.pin_bore_diameter / 2,
                 (p.seat_b_diameter - p.output_bore_diameter) / 2, p.seat_a_diameter / 2]
        return min(feats)
    if isinstance(params, PartFile):
        geo = part_geometry(params)
        # a mesh file is used as it is (its median edge only names the cache entry); a CAD
        # part of unknown walls: a fortieth of its size (give the size in the scene)
        return geo.edge_length if params.is_mesh else geo.size / 40
    raise TypeError(type(params).__name__)


def build_component(params, material: Material = STEEL, mesh_size: float | None = None, order: int = 2,
                    cache_dir: str | os.PathLike | None = None, *, options: MeshOptions | None = None,
                    stiffness_intorder: int | None = None, mass_intorder: int | None = None) -> FEModel:
    """Mesh (or load the verified cached mesh of) a component and assemble its FE model.

    mesh_size : target element size [m] (default :func:`default_mesh_size`).
    order : 2 = quadratic tetrahedra with curved boundaries (default), 1 = linear.
    options : full :class:`MeshOptions` (overrides ``mesh_size`` and ``order``).
    stiffness_intorder : quadrature order for K (default 2p-2: exact on straight-sided tets).
    mass_intorder : quadrature order for M and mass properties (default 2p: exact on straight tets).
    """
    if options is None:
        options = MeshOptions(size=default_mesh_size(params) if mesh_size is None else mesh_size, order=order)
    t0 = time.perf_counter()
    path, raw = load_mesh(params, options, cache_dir)
    t_mesh = time.perf_counter() - t0
    model = assemble(params, raw, material, stiffness_intorder, mass_intorder)
    model.mesh_file = path
    model.mesh_sha256 = raw.content_hash
    model.timings["mesh"] = t_mesh
    if isinstance(params, PartFile):
        model.checks.update(cad_mass_check(model, params))
        model.read = part_geometry(params).read
    return model


#: Largest relative error of the FE mass, centre of mass and inertia against the CAD-exact
#: values accepted without a warning for a P2 mesh (curved elements integrate the volume
#: to about h^3 of the curvature; measured on the shipped carrier: below 1e-4).
CAD_MASS_TOL = 1e-3


def cad_mass_check(model: "FEModel", part: PartFile) -> dict:
    """Relative errors of the FE model's mass, centre of mass (against the part's size) and
    inertia tensor (matrix 2-norm) against the part's CAD-exact values; a WARNING above
    :data:`CAD_MASS_TOL` (P2). A mesh file has no exact geometry to check against: ``{}``."""
    geo = part_geometry(part)
    if geo.source != "cad":  # a mesh file has no exact geometry: its straight elements are no reference
        return {}
    rho = model.material.rho
    m_ref = rho * geo.volume
    J_ref = rho * geo.inertia_per_density
    out = {"mass_rel": abs(model.mass - m_ref) / m_ref,
           "center_of_mass_rel": float(np.linalg.norm(model.center_of_mass - geo.centroid)) / geo.size,
           "inertia_rel": float(np.linalg.norm(model.inertia - J_ref, 2) / np.linalg.norm(J_ref, 2))}
    worst = max(out, key=out.get)
    if model.order == 2 and out[worst] > CAD_MASS_TOL:
        log.warning("%s: FE %s differs from the CAD value by %.3g (> %g): refine the mesh", part.path.name,
                    worst.removesuffix("_rel"), out[worst], CAD_MASS_TOL)
    return out


def skfem_mesh(raw: RawMesh):
    """The scikit-fem mesh of a mesh read by :func:`~fe_components.meshing.read_mesh` (P1 or
    curved P2 tetrahedra, through meshio)."""
    import meshio
    import skfem.io.meshio  # noqa: F401  (registers from_meshio; not auto-imported)
    from skfem.io.meshio import from_meshio

    return from_meshio(meshio.Mesh(raw.points, [(raw.cell_type, raw.cells)]))


def assemble(params, raw: RawMesh, material: Material = STEEL, stiffness_intorder: int | None = None,
             mass_intorder: int | None = None) -> FEModel:
    """FE model of a mesh read by :func:`read_mesh`: basis, interfaces and mass properties now,
    K and M when first used (:class:`FEModel`)."""
    from skfem import Basis, BilinearForm, ElementTetP1, ElementTetP2, ElementVector, Functional, asm
    from skfem.helpers import dot
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    t0 = time.perf_counter()
    mesh = skfem_mesh(raw)
    p = 2 if raw.cell_type == "tetra10" else 1
    elem = ElementVector(ElementTetP2() if p == 2 else ElementTetP1())
    k_order = 2 * p - 2 if stiffness_intorder is None else stiffness_intorder
    m_order = 2 * p if mass_intorder is None else mass_intorder
    mapping = memoised_mapping(mesh)   # one inverse Jacobian per quadrature, shared by every basis
    kb = Basis(mesh, elem, mapping=mapping, intorder=max(k_order, 1))
    _check_jacobians(kb, raw, params)

    # mass properties integrated over the geometry with the mass quadrature
    sb = Basis(mesh, ElementTetP1(), mapping=mapping, intorder=m_order)
    def moment(f):
        return float(Functional(f).assemble(sb))

    rho = material.rho
    mass = rho * moment(lambda w: 1.0 + 0 * w.x[0])
    first = np.array([rho * moment(lambda w, i=i: w.x[i]) for i in range(3)])
    com = first / mass
    S = np.empty((3, 3))
    for i in range(3):
        for j in range(i, 3):
            S[i, j] = S[j, i] = rho * moment(lambda w, i=i, j=j: (w.x[i] - com[i]) * (w.x[j] - com[j]))
    inertia = np.trace(S) * np.eye(3) - S

    def matrices():
        """(K, M): linear elasticity and consistent mass, assembled by scikit-fem."""
        lam, mu = lame_parameters(material.E, material.nu)
        K = asm(linear_elasticity(lam, mu), kb).tocsr()

        @BilinearForm
        def _mass(u, v, w):
            return dot(u, v)

        mb = kb if m_order == k_order else Basis(mesh, elem, mapping=mapping, intorder=m_order)
        M = (material.rho * asm(_mass, mb)).tocsr()
        # cheap check: the consistent mass matrix carries the same mass (rigid translation)
        ex = np.zeros(M.shape[0])
        ex[0::3] = 1.0
        m_check = float(ex @ (M @ ex))
        if abs(m_check - mass) > 1e-8 * mass:
            log.warning("mass from M (%.9g kg) differs from integrated mass (%.9g kg)", m_check, mass)
        log.info("assembled K, M: %d DOFs (P%d)", kb.N, p)
        return K, M

    nodes = kb.doflocs[:, ::3].T
    interfaces = _interfaces(params, raw, nodes)
    t_asm = time.perf_counter() - t0
    log.info("FE model of %d DOFs (P%d) in %.2f s (K, M assembled when first used)", kb.N, p, t_asm)
    return FEModel(params=params, material=material, mesh=mesh, basis=kb, interfaces=interfaces,
                   mass=mass, center_of_mass=com, inertia=inertia, order=p, timings={"assembly": t_asm},
                   matrices=matrices)


def _check_jacobians(basis, raw: RawMesh, params) -> None:
    """Refuse curved elements whose Jacobian changes sign (inverted) at the quadrature points."""
    d = basis.mapping.detDF(basis.X)
    bad = np.flatnonzero(d.min(axis=1) * d.max(axis=1) <= 0)
    if len(bad) and isinstance(params, PartFile) and params.is_mesh:
        raise PartFileError("file", params.file, f"{params.path.name}: {len(bad)} of {d.shape[0]} curved "
                                                 f"elements are inverted (Jacobian changes sign); first: element "
                                                 f"{int(bad[0])}")
    if len(bad):
        report = {**params_as_flat_dict(params), "cell_type": raw.cell_type, "n_inverted": int(len(bad)),
                  "first_inverted_element": int(bad[0])}
        raise MeshingError(component_kind(params), report,
                           "inverted (negative-Jacobian) elements: use a smaller mesh size or order=1")


def _interfaces(params, raw: RawMesh, nodes: np.ndarray) -> dict[str, Interface]:
    from scipy.spatial import cKDTree

    tree = cKDTree(nodes)
    tol = 1e-9 * characteristic_length(params)
    out: dict[str, Interface] = {}
    for idef in interface_defs(params):
        if idef.name not in raw.interface_nodes:
            raise MeshingError("mesh", {"interface": idef.name}, "physical group missing from the mesh file")
        pts = raw.points[raw.interface_nodes[idef.name]]
        dist, idx = tree.query(pts)
        if np.any(dist > tol):
            raise MeshingError("mesh", {"interface": idef.name, "max_distance": float(dist.max())},
                               "interface nodes not found among the FE nodes")
        out[idef.name] = Interface(idef.name, np.unique(idx), np.asarray(idef.master, dtype=float), idef.coupling)
    return out
