"""Flexible bodies: component FE model (fe_components) -> Craig-Bampton superelement (cms).

A flexible body's DOFs are its superelement coordinates in the component's *local* axes:
the 6 DOFs [ux, uy, uz, rx, ry, rz] of every interface master node, then the modal
coordinates. Springs attach to master nodes (by interface name, or at a point that
coincides with a master, e.g. a planet on its carrier pin) through a rigid arm. A
mass-weighted rigid projection gives the body's rigid-equivalent motion at its centre of
mass, so torsional, rigid and flexible models of one scene share absolute coordinates for
MAC pairing and energy bookkeeping. Reductions are cached on disk (cms.cache), keyed by
the mesh's content hash, material, couplings, mode selection and the code that built them.
A reduction records the content hash of the mesh it was built from: a cached one whose
record does not match is rebuilt, and back-expansion (stresses, displacement fields) only
ever uses an FE model of that same mesh, never a mesh regenerated since (a mismatch raises
:class:`cms.errors.CacheError` rather than mix modes of one mesh with nodes of another).
"""
from __future__ import annotations

import dataclasses
import hashlib
import logging
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import numpy as np

from cms.errors import CacheError, ModeLimitError

from ..errors import SceneError, SolverError
from ..mechanics.kinematics import block_rotation, rigid_transfer
from ..scene.attach import placement
from ..scene.cutoffs import cutoff_for, cutoff_source
from ..scene.tables import MAX_MODES, FlexOptions
from .components import CacheDirs, build_fe, mesh_entry, mesh_size

log = logging.getLogger(__name__)

_DOFS6 = ("ux", "uy", "uz", "rx", "ry", "rz")


@dataclass
class FlexibleBodyModel:
    """A body whose DOFs are component coordinates in local axes (reduced or full FE).

    ``K``, ``M``: stiffness/mass on those DOFs (dense for a superelement, sparse CSR for an
    unreduced FE body). ``masters``: name -> (global position, 6 DOF indices).
    """

    flexible = True

    name: str
    position: np.ndarray          # global position of the centre of mass (m)
    axes: np.ndarray              # R: columns = local x, y, axis in global axes
    origin: np.ndarray            # global position of the component's local origin (m)
    mass: float                   # kg, from the mesh
    inertia: np.ndarray           # kg m^2 about the COM, global axes
    K: object
    M: object
    masters: dict
    rigid_local: np.ndarray       # (ndof, 6) local rigid motions about the local COM
    reduced: bool = True
    superelement: object = None
    info: dict = field(default_factory=dict)
    params: object = None
    options: FlexOptions = None
    caches: CacheDirs = field(default_factory=CacheDirs)
    _proj: np.ndarray = None
    _coupled: object = None
    _stress_projector: object = None
    _rows: tuple = None

    # ---- back-expansion to the FE mesh (lazy: needs only the cached mesh) ----------
    def coupled(self):
        """(FEModel, CoupledModel) of the component, rebuilt from the mesh cache on demand:
        of the very mesh the superelement was built from (checked by content hash)."""
        if self._coupled is None:
            built = self.superelement.metadata.get("mesh_sha256") if self.reduced else None
            fe, cm = _coupled_model(self.params, self.options, self.caches, mesh_sha256=built)
            if self.reduced and fe.mesh_sha256 != built:
                raise CacheError(f"{self.name}: the mesh {fe.mesh_file} is not the one this body's reduction was "
                                 f"built from (content {str(built)[:16]}); it changed during this run, so its "
                                 "stresses would not match the modes: run again to reduce the current mesh",
                                 "mesh_sha256", fe.mesh_sha256[:16])
            self._coupled = (fe, cm)
        return self._coupled

    def expand(self, zb: np.ndarray, nodes: np.ndarray | None = None) -> np.ndarray:
        """FE displacement field(s) (m, local axes, scikit-fem DOF order) of body DOFs ``zb``:
        Craig-Bampton back-expansion (constraint + fixed-interface modes), then the
        interface couplings (u = T q_c). ``nodes``: only the DOFs of these FE nodes (3 per
        node, in their order; the rows of T are kept for the next call with the same nodes)."""
        _, cm = self.coupled()
        qc = self.superelement.reconstruct(zb) if self.reduced else np.asarray(zb)
        if nodes is None:
            return cm.T @ qc
        key = np.asarray(nodes).tobytes()
        rows = self._rows
        if rows is None or rows[0] != key:
            dofs = (3 * np.asarray(nodes)[:, None] + np.arange(3)).ravel()
            rows = self._rows = (key, cm.T.tocsr()[dofs])
        return rows[1] @ qc

    def stress(self, zb: np.ndarray):
        """Nodal stresses (cms.stress.NodalStress, Pa) of body DOFs ``zb``: von Mises and
        principal stresses, L2-projected to the P2 nodes."""
        m = self.options.material
        return self.stress_projector()(self.expand(zb), m.E, m.nu)

    def stress_projector(self):
        """:class:`cms.stress.StressProjector` of the stiffness basis (projection at order
        2p, scalar mass matrix factorised), built once per body and reused for every load
        case and mode."""
        if self._stress_projector is None:
            from cms.stress import StressProjector
            fe, _ = self.coupled()
            self._stress_projector = StressProjector(fe.basis)
        return self._stress_projector

    def stress_rows(self, point) -> tuple[np.ndarray, np.ndarray, float]:
        """The projected stress (Pa; body axes, Voigt order xx, yy, zz, yz, xz, xy) at the FE
        stress node nearest to ``point`` (global, m) as rows on the body DOFs ``zb``: ``(rows
        (6, ndof), the node's global position (m), its distance from point (m))``. The same
        stress as :meth:`stress` gives at that node (:meth:`cms.stress.StressProjector.node_functional`)."""
        m = self.options.material
        proj = self.stress_projector()
        node, dist = proj.nearest_node(self.axes.T @ (np.asarray(point, float) - self.origin))
        _, cm = self.coupled()
        g = np.asarray((cm.T.T @ proj.node_functional(node, m.E, m.nu).T).T)   # rows on q_c
        if self.reduced:
            g = g @ self.superelement.reconstruct(np.eye(self.ndof))
        return g, self.origin + self.axes @ proj.sbasis.doflocs[:, node], dist

    def nodes_global(self) -> np.ndarray:
        fe, _ = self.coupled()
        return self.origin + fe.nodes @ self.axes.T

    def displacement_global(self, zb: np.ndarray) -> np.ndarray:
        """(n_nodes, 3) nodal displacement in global axes (m)."""
        return self.expand(zb).reshape(-1, 3) @ self.axes.T

    @property
    def ndof(self) -> int:
        return self.K.shape[0]

    def mass_matrix(self):
        return self.M

    def stiffness_matrix(self):
        return self.K

    def master_near(self, point, tol: float = 1e-6) -> str:
        d = {k: np.linalg.norm(p - np.asarray(point, float)) for k, (p, _) in self.masters.items()}
        k = min(d, key=d.get)
        if d[k] > tol:
            raise SceneError(f"{self.name}", np.round(np.asarray(point, float), 6).tolist(),
                             f"no interface master node at this attachment point (nearest: {k}, "
                             f"{d[k]:.3g} m away); name an interface of {sorted(self.masters)}")
        return k

    def motion_at(self, point, interface: Optional[str] = None):
        """Sparse (6 x ndof) map to the global motion [u, theta] at ``point``, carried from
        the interface master (named, or coinciding with ``point``) by a rigid arm."""
        name = interface or self.master_near(point)
        if name not in self.masters:
            raise SceneError(self.name, name, f"no such interface; have {sorted(self.masters)}")
        pos, idx = self.masters[name]
        G = rigid_transfer(point, pos) @ block_rotation(self.axes)
        import scipy.sparse as sp  # a flexible model only: a rigid one's path imports no SciPy
        S = sp.csr_matrix((np.ones(6), (np.arange(6), idx)), shape=(6, self.ndof))
        return sp.csr_matrix(G) @ S

    def rigid_projection(self) -> np.ndarray:
        """(6 x ndof): mass-weighted rigid-equivalent motion at the COM, global axes."""
        if self._proj is None:
            Rl = self.rigid_local
            MR = self.M @ Rl
            P = np.linalg.solve(Rl.T @ MR, np.asarray(MR).T)
            self._proj = block_rotation(self.axes) @ P
        return self._proj

    def rigid_motion(self, zb: np.ndarray) -> np.ndarray:
        return self.rigid_projection() @ zb

    def dof_names(self) -> list:
        names = [None] * self.ndof
        for k, (_, idx) in self.masters.items():
            for j, d in zip(idx, _DOFS6):
                names[j] = f"{self.name}.{k}.{d}"
        m = 0
        for j in range(self.ndof):
            if names[j] is None:
                names[j] = f"{self.name}.q{m}"
                m += 1
        return names


def _rigid_rows(points_local, kinds, com_local) -> np.ndarray:
    from cms.rigid import rigid_body_basis
    return rigid_body_basis(points_local, kinds, reference=com_local)


def flexible_body(body, options: FlexOptions, band_hz: float, reduce: bool = True,
                  caches: CacheDirs | None = None, path: str | None = None) -> FlexibleBodyModel:
    """The flexible model of ``body`` (its ``component`` parameters): Craig-Bampton
    superelement (cached) or full FE. ``path``: the body's table in the scene (``bodies[1]``,
    ``stages[0].carrier``) for error messages (default: its name)."""
    params = body.component
    caches = caches or CacheDirs()
    options = dataclasses.replace(options, mesh_size=mesh_size(params, options))
    t0 = time.perf_counter()
    if reduce:
        cutoff = cutoff_for(body, options, band_hz)
        try:
            parts = _reduced(body, params, options, cutoff, caches, path or body.name)
        except ModeLimitError as err:
            where, value = cutoff_source(path or body.name, options, band_hz)
            raise SceneError(where, value, f"body {body.name!r}: {err.max_modes + 1} fixed-interface modes lie "
                                           f"below the cutoff {cutoff:.6g} Hz (the last at {err.highest_hz:.6g} "
                                           f"Hz), more than MAX_MODES = {MAX_MODES}; lower the cutoff or give "
                                           "flex.n_modes") from None
        parts["info"]["reduce_time_s"] = time.perf_counter() - t0
    else:
        parts = _unreduced(body, params, options, caches)
        parts["info"]["build_time_s"] = time.perf_counter() - t0
    o, R = placement(body)
    com_l = parts.pop("com_local")
    fbm = FlexibleBodyModel(body.name, o + R @ com_l, R, o, parts["mass"], R @ parts["inertia"] @ R.T,
                            parts["K"], parts["M"], parts["masters"], parts["Rl"], reduce,
                            parts.get("superelement"), parts["info"], params, options, caches)
    if not reduce:
        fbm._coupled = parts["coupled"]
    return fbm


def _coupled_model(params, options: FlexOptions, caches: CacheDirs, mesh_sha256: str | None = None):
    """(FEModel, CoupledModel): the component's FE model with its interfaces coupled
    (``mesh_sha256``: see :func:`build_fe`)."""
    from fe_components.coupling import couple
    fe = build_fe(params, options, caches, mesh_sha256)
    return fe, couple(fe, dict(options.couplings or {}))


def _unreduced(body, params, options: FlexOptions, caches: CacheDirs) -> dict:
    """Every FE DOF of the coupled component (the reference model)."""
    fe, c = _coupled_model(params, options, caches)
    o, R = placement(body)
    return {"K": c.K_c, "M": c.M_c, "masters": {nm: (o + R @ p, idx) for nm, p, idx in c.masters},
            "Rl": c.rigid_body_basis(fe.center_of_mass), "com_local": fe.center_of_mass,
            "mass": fe.mass, "inertia": fe.inertia, "coupled": (fe, c),
            "info": {"n_full_dofs": int(fe.n_dofs)}}


def _reduce(params, options: FlexOptions, cutoff: float | None, caches: CacheDirs, mesh, path: str):
    """Craig-Bampton reduction of the coupled component (called on a cache miss), keeping at
    most MAX_MODES fixed-interface modes; ``mesh``: the verified mesh entry (its content hash
    is recorded as the one the reduction used); ``path``: the body's table in the scene."""
    from cms.craig_bampton import CraigBamptonReductor
    fe, c = _coupled_model(params, options, caches, mesh.sha256)
    n_interior = c.K_c.shape[0] - len(c.boundary_dofs)
    if options.n_modes is not None and options.n_modes > n_interior:
        raise SceneError(f"{path}.flex.n_modes", options.n_modes,
                         f"more than the {n_interior} interior DOFs of the body's mesh")
    red = CraigBamptonReductor(
        c.K_c, c.M_c, c.boundary_dofs, n_modes=options.n_modes, cutoff_hz=cutoff, max_modes=MAX_MODES,
        dof_names=[f"{nm}:{d}" for nm, _, _ in c.masters for d in _DOFS6],
        rigid_body_basis=c.rigid_body_basis(fe.center_of_mass), residual_vectors=options.residual_vectors,
        metadata={"mass": fe.mass, "center_of_mass": fe.center_of_mass.tolist(),
                  "inertia": fe.inertia.tolist(), "masters": {nm: p.tolist() for nm, p, _ in c.masters},
                  "n_full_dofs": int(fe.n_dofs), "n_coupled_dofs": int(c.K_c.shape[0]), "mesh_file": mesh.path.name,
                  "mesh_sha256": fe.mesh_sha256})
    return red.reduce()


#: Superelement metadata a flexible body reads (written by :func:`_reduce`).
_SE_METADATA = ("mesh_sha256", "masters", "center_of_mass", "mass", "inertia")


def _check_reduction(se, mesh_sha256: str) -> None:
    """Reject a superelement not built from the mesh with content hash ``mesh_sha256``
    (or lacking what a flexible body reads): the cache then reduces again."""
    md = se.metadata
    missing = [k for k in _SE_METADATA if k not in md]
    if missing:
        raise CacheError("superelement metadata incomplete", "missing", missing)
    if md["mesh_sha256"] != mesh_sha256:
        raise CacheError(f"superelement built from another mesh than {mesh_sha256[:16]} (the mesh changed "
                         "while it was reduced?)", "mesh_sha256", str(md["mesh_sha256"])[:16])


def _reduced(body, params, options: FlexOptions, cutoff: float | None, caches: CacheDirs, path: str) -> dict:
    """Superelement of the component (from the cache, or reduced and stored)."""
    from cms.cache import SuperelementCache
    mesh = mesh_entry(params, options, caches)
    m = options.material
    key_inputs = {"mesh_sha256": mesh.sha256, "material": [m.E, m.nu, m.rho],
                  "couplings": dict(options.couplings or {}), "n_modes": options.n_modes, "cutoff_hz": cutoff,
                  "residual_vectors": options.residual_vectors, "code": code_digest()}
    cache = SuperelementCache(caches.superelements)
    se = cache.get_or_reduce(key_inputs, lambda: _reduce(params, options, cutoff, caches, mesh, path),
                             check=lambda s: _check_reduction(s, mesh.sha256))
    md = se.metadata
    o, R = placement(body)
    names = list(md["masters"])
    masters = {nm: (o + R @ np.asarray(md["masters"][nm]), 6 * k + np.arange(6)) for k, nm in enumerate(names)}
    com_l = np.asarray(md["center_of_mass"])
    pts = np.repeat(np.array([md["masters"][nm] for nm in names]), 6, axis=0)
    Rl = np.zeros((se.K.shape[0], 6))
    Rl[:6 * len(names)] = _rigid_rows(pts, np.tile(np.arange(6), len(names)), com_l)
    n_rv = int(md.get("n_residual_vectors", 0))
    info = {"n_modes": se.n_modes - n_rv, "n_residual_vectors": n_rv, "n_full_dofs": md.get("n_full_dofs"),
            "cutoff_hz": cutoff, "cache_hits": cache.hits}
    return {"K": deflate_rigid(se.K, se.M, Rl, body.name), "M": se.M, "masters": masters, "Rl": Rl,
            "com_local": com_l, "mass": float(md["mass"]), "inertia": np.asarray(md["inertia"]),
            "superelement": se, "info": info}


#: Largest admissible |K_r R| / (|K_r| |R|) of a superelement before deflation: rigid
#: motions must be free of strain energy up to the round-off of the reduction (which grows
#: like cond(K_ii) * eps, ~1e-8 here); an inconsistent superelement gives ~1e-1.
RIGID_STRAIN_TOL = 1e-6


def deflate_rigid(K: np.ndarray, M: np.ndarray, R: np.ndarray, name: str) -> np.ndarray:
    """Remove round-off strain energy of rigid motions from a reduced stiffness.

    ``K <- P' K P`` with the M-orthogonal projector ``P = I - R (R'MR)^-1 R'M`` onto the
    motions with no rigid part: exact for an exactly singular ``K`` (K R = 0), and it makes
    free-free rigid modes come out at 0 Hz to round-off instead of at ~1e-6 x f_max.
    Raises if ``K R`` is not small: then the superelement is not free-free consistent.
    """
    KR = K @ R
    rel = np.linalg.norm(KR) / (np.linalg.norm(K) * np.linalg.norm(R))
    if rel > RIGID_STRAIN_TOL:
        raise SolverError(f"{name} superelement", f"|K R|/(|K||R|) = {rel:.2e}",
                          f"strains rigid motions (limit {RIGID_STRAIN_TOL:g}): not free-free consistent")
    MR = M @ R
    G = np.linalg.solve(R.T @ MR, MR.T)        # (R'MR)^-1 R'M
    P = np.eye(K.shape[0]) - R @ G
    Kd = P.T @ K @ P
    return 0.5 * (Kd + Kd.T)


def code_digest() -> str:
    """Digest of the source that turns a mesh into a superelement (FE model, couplings,
    Craig-Bampton): part of the reduction cache key, so a code change never reuses a
    reduction whose coordinates no longer match."""
    import cms.craig_bampton
    import fe_components.coupling
    import fe_components.fe_model
    import fe_components.mapping_memo
    h = hashlib.sha256()
    for mod in (fe_components.fe_model, fe_components.mapping_memo, fe_components.coupling, cms.craig_bampton):
        h.update(Path(mod.__file__).read_bytes())
    return h.hexdigest()[:16]
