"""Flexible bodies: scene component -> FE model (fe_components) -> Craig-Bampton (cms).

A flexible body's DOFs are its superelement coordinates in the component's *local* axes:
the 6 DOFs [ux, uy, uz, rx, ry, rz] of every interface master node, then the modal
coordinates. Springs attach to master nodes (by interface name, or at a point that
coincides with a master, e.g. a planet on its carrier pin) through a rigid arm. A
mass-weighted rigid projection gives the body's rigid-equivalent motion at its centre of
mass, so torsional, rigid and flexible models of one scene share absolute coordinates for
MAC pairing and energy bookkeeping. Component placement: a local point ``x`` sits at
``position + R x`` with ``R = axis_frame(axis)`` (local z = the body's axis).
"""
from __future__ import annotations

import dataclasses
import logging
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal, Optional

import numpy as np

from .errors import SceneError
from .geometry import axis_frame, block_rotation, rigid_transfer

log = logging.getLogger(__name__)

#: Default Craig-Bampton cutoff as a multiple of the scene's band of interest, with
#: residual vectors on (FlexOptions.residual_vectors). The convergence study (`flexgear
#: bench flex`, README) against full FE, in-band coupled modes: HS stage 0.0002 % at 1.5x
#: (plain CB: 0.99 % at 1.5x and 2x, 0.19 % at 4x); planetary carrier < 1e-4 % (plain CB
#: 0.17 %); test pair (tests/data) < 1e-4 % (plain CB 0.67 % up to 6x). 1.5x rather than 1x
#: keeps the modes just above the band within 0.02 % too.
CUTOFF_FACTOR = 1.5
#: Band of interest (Hz) when a scene does not give ``band_hz``.
DEFAULT_BAND_HZ = 3000.0
#: Where reduced components are cached (keyed by mesh, material, couplings, modes).
CMS_CACHE_DIR = Path(__file__).resolve().parent.parent / "meshes" / "cache" / "cms"


@dataclass(frozen=True)
class MaterialSpec:
    """Isotropic linear-elastic material: E (Pa), nu (-), rho (kg/m^3). Default: steel."""

    E: float = 2.1e11
    nu: float = 0.3
    rho: float = 7850.0


@dataclass(frozen=True)
class FlexOptions:
    """How a component body is meshed and reduced.

    ``mesh_size`` (m; default from the component's thinnest wall), ``order`` (2 = P2
    tetrahedra), ``n_modes`` or ``cutoff_hz`` (Hz) of fixed-interface modes (default:
    CUTOFF_FACTOR x the scene's band), ``couplings`` {interface: 'rbe2'|'rbe3'},
    ``residual_vectors`` (default on): add the static response of the interior to the
    inertia of the interface motion (``cms.craig_bampton``), which carries the
    quasi-static part of every truncated mode for one more block solve.
    """

    mesh_size: Optional[float] = None
    order: Literal[1, 2] = 2
    n_modes: Optional[int] = None
    cutoff_hz: Optional[float] = None
    couplings: Optional[dict] = None
    material: MaterialSpec = MaterialSpec()
    residual_vectors: bool = True

    def check(self, path: str) -> None:
        if self.mesh_size is not None and not self.mesh_size > 0:
            raise SceneError(f"{path}.mesh_size", self.mesh_size, "must be > 0 m")
        if self.n_modes is not None and self.cutoff_hz is not None:
            raise SceneError(f"{path}.n_modes", self.n_modes, "give n_modes or cutoff_hz, not both")
        if self.n_modes is not None and self.n_modes < 0:
            raise SceneError(f"{path}.n_modes", self.n_modes, "must be >= 0 (0 = Guyan)")
        if self.cutoff_hz is not None and not self.cutoff_hz > 0:
            raise SceneError(f"{path}.cutoff_hz", self.cutoff_hz, "must be > 0 Hz")
        m = self.material
        if not m.E > 0:
            raise SceneError(f"{path}.material.E", m.E, "must be > 0 Pa")
        if not -1 < m.nu < 0.5:
            raise SceneError(f"{path}.material.nu", m.nu, "must lie in (-1, 0.5)")
        if not m.rho > 0:
            raise SceneError(f"{path}.material.rho", m.rho, "must be > 0 kg/m^3")
        for k, v in (self.couplings or {}).items():
            if v not in ("rbe2", "rbe3"):
                raise SceneError(f"{path}.couplings.{k}", v, "must be 'rbe2' or 'rbe3'")


def component_params(body, path: str):
    """fe_components parameters of a body's ``component`` table (errors name ``path``)."""
    from fe_components.params import component_from_dict
    return component_from_dict(dict(body.component), path)


def local_masters(params) -> dict:
    """Interface name -> master position in the component's local axes (m); no meshing."""
    from fe_components.geometry import interface_defs
    return {d.name: np.asarray(d.master, float) for d in interface_defs(params)}


def placement(body):
    """(origin (3,), R (3x3)) mapping local component points to global: x_g = o + R x."""
    return np.asarray(body.position, float), axis_frame(body.axis)


def global_masters(body, params) -> dict:
    o, R = placement(body)
    return {k: o + R @ v for k, v in local_masters(params).items()}


@dataclass
class FlexibleBodyModel:
    """A body whose DOFs are component coordinates in local axes (reduced or full FE).

    ``K``, ``M``: stiffness/mass on those DOFs (dense for a superelement, sparse CSR for an
    unreduced FE body). ``masters``: name -> (global position, 6 DOF indices).
    """

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
    _proj: np.ndarray = None
    _coupled: object = None

    # ---- back-expansion to the FE mesh (lazy: needs only the cached mesh) ----------
    def coupled(self):
        """(FEModel, CoupledModel) of the component, rebuilt from the mesh cache on demand."""
        if self._coupled is None:
            from fe_components.coupling import couple
            fe = build_fe(None, self.params, self.options)
            self._coupled = (fe, couple(fe, dict(self.options.couplings or {})))
        return self._coupled

    def expand(self, zb: np.ndarray) -> np.ndarray:
        """FE displacement field(s) (m, local axes, scikit-fem DOF order) of body DOFs ``zb``:
        Craig-Bampton back-expansion (constraint + fixed-interface modes), then the
        interface couplings (u = T q_c)."""
        _, cm = self.coupled()
        qc = self.superelement.reconstruct(zb) if self.reduced else np.asarray(zb)
        return cm.T @ qc

    def stress(self, zb: np.ndarray):
        """Nodal stresses (cms.stress.NodalStress, Pa) of body DOFs ``zb``: von Mises and
        principal stresses, L2-projected to the P2 nodes."""
        from cms.stress import recover_stress
        m = self.options.material
        return recover_stress(self.stress_basis(), self.expand(zb), m.E, m.nu)

    def stress_basis(self):
        """Vector basis for stress recovery, integrated at order 2p: the L2 projection
        needs an exact (non-singular) mass matrix; the stiffness basis uses order 2p-2."""
        if self.info.get("_stress_basis") is None:
            from skfem import Basis
            fe, _ = self.coupled()
            self.info["_stress_basis"] = Basis(fe.mesh, fe.basis.elem, intorder=2 * fe.order)
        return self.info["_stress_basis"]

    def nodes_global(self) -> np.ndarray:
        fe, _ = self.coupled()
        return self.origin + fe.nodes @ self.axes.T

    def displacement_global(self, zb: np.ndarray) -> np.ndarray:
        """(n_nodes, 3) nodal displacement in global axes (m)."""
        return self.expand(zb).reshape(-1, 3) @ self.axes.T

    # ---- rendering hooks (assembly.render draws flexible bodies through these) -------
    def render_reference(self):
        from .render_fe import fe_surface
        return fe_surface(self, None, 0.0)

    def render_mesh(self, shape, scale: float):
        from .render_fe import fe_surface
        return fe_surface(self, np.asarray(shape), scale)

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
        import scipy.sparse as sp
        name = interface or self.master_near(point)
        if name not in self.masters:
            raise SceneError(self.name, name, f"no such interface; have {sorted(self.masters)}")
        pos, idx = self.masters[name]
        G = rigid_transfer(point, pos) @ block_rotation(self.axes)
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
            for j, d in zip(idx, ("ux", "uy", "uz", "rx", "ry", "rz")):
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


def mesh_dir(params, mesh_size: float, order: int):
    """Committed reference mesh folder if it holds this exact mesh, else the default cache."""
    from fe_components.meshing import MeshOptions, mesh_path
    from fe_components.reference import REF_DIR
    return REF_DIR if mesh_path(params, MeshOptions(size=mesh_size, order=order), REF_DIR).exists() else None


_FE_MEMO: dict = {}

#: Bulk-to-shear modulus ratio K/G = 2(1 + nu) / (3(1 - 2 nu)) above which linear (P1)
#: tetrahedra lock volumetrically (nu > ~0.45): stiffness and frequencies come out too high.
LOCKING_RATIO = 10.0


def check_locking(order: int, nu: float) -> bool:
    """Warn (and return True) when P1 tetrahedra will lock at this Poisson ratio."""
    ratio = 2 * (1 + nu) / (3 * (1 - 2 * nu))
    if order == 1 and ratio > LOCKING_RATIO:
        log.warning("P1 tetrahedra lock volumetrically at nu = %.4g (bulk/shear modulus %.3g > %.0f): "
                    "results will be too stiff; use order = 2", nu, ratio, LOCKING_RATIO)
        return True
    return False


def build_fe(body, params, options: FlexOptions):  # noqa: ARG001 (body kept for symmetry)
    """Mesh (cached on disk) and assemble the component's FE model (memoised per process,
    so the torsional, rigid and flexible variants of a scene assemble each mesh once)."""
    from fe_components.fe_model import build_component, default_mesh_size
    from fe_components.material import Material
    from fe_components.params import params_digest
    m = options.material
    size = options.mesh_size if options.mesh_size is not None else default_mesh_size(params)
    check_locking(options.order, m.nu)
    key = params_digest(params, size, options.order, m.E, m.nu, m.rho)
    if key not in _FE_MEMO:
        if len(_FE_MEMO) >= 8:
            _FE_MEMO.pop(next(iter(_FE_MEMO)))
        from fe_components.quality import check_quality
        fe = build_component(params, Material(m.E, m.nu, m.rho), mesh_size=size, order=options.order,
                             cache_dir=mesh_dir(params, size, options.order))
        rep = check_quality(fe.mesh.p.T, fe.mesh.t.T)
        log.info("mesh quality: worst element %d, q = %.3g", rep.worst, rep.worst_quality)
        _FE_MEMO[key] = fe
    return _FE_MEMO[key]


def mass_properties(body, params, options: FlexOptions):
    """(mass kg, COM global, inertia global about COM) of a component body, from its mesh."""
    fe = build_fe(body, params, options)
    o, R = placement(body)
    return fe.mass, o + R @ fe.center_of_mass, R @ fe.inertia @ R.T, fe


def flexible_body(body, params, options: FlexOptions, band_hz: float, reduce: bool = True,
                  cache_dir=None) -> FlexibleBodyModel:
    """The flexible model of ``body``: Craig-Bampton superelement (cached) or full FE."""
    from cms.cache import SuperelementCache
    from cms.craig_bampton import CraigBamptonReductor
    from fe_components.coupling import couple
    from fe_components.meshing import MeshOptions, mesh_path
    from fe_components.fe_model import default_mesh_size

    o, R = placement(body)
    t0 = time.perf_counter()
    mesh_size = options.mesh_size if options.mesh_size is not None else default_mesh_size(params)
    mfile = mesh_path(params, MeshOptions(size=mesh_size, order=options.order))
    cutoff = options.cutoff_hz
    if options.n_modes is None and cutoff is None:
        cutoff = CUTOFF_FACTOR * band_hz
    if options.cutoff_hz is not None and options.cutoff_hz < band_hz:
        log.warning("%s: Craig-Bampton cutoff %.4g Hz lies below the scene's band %.4g Hz: coupled modes "
                    "in the band will be too stiff (the convergence study needs %g x band)",
                    body.name, options.cutoff_hz, band_hz, CUTOFF_FACTOR)
    couplings = dict(options.couplings or {})
    key_inputs = {"mesh": mfile.name, "material": [options.material.E, options.material.nu, options.material.rho],
                  "couplings": couplings, "n_modes": options.n_modes, "cutoff_hz": cutoff,
                  "residual_vectors": options.residual_vectors, "code": code_digest()}
    fe = cm = None

    def coupled():
        nonlocal fe, cm
        if cm is None:
            fe = build_fe(body, params, dataclasses.replace(options, mesh_size=mesh_size))
            cm = couple(fe, couplings)
        return cm

    if reduce:
        cache = SuperelementCache(cache_dir or CMS_CACHE_DIR)

        def do_reduce():
            c = coupled()
            n = c.K_c.shape[0]
            # rigid-body information for the reductor's mechanism check and self-checks
            Rl = _coupled_rigid_basis(c, fe.center_of_mass)
            red = CraigBamptonReductor(
                c.K_c, c.M_c, c.boundary_dofs, n_modes=options.n_modes, cutoff_hz=None if options.n_modes is not None else cutoff,
                dof_names=[f"{nm}:{d}" for nm, _, _ in c.masters for d in ("ux", "uy", "uz", "rx", "ry", "rz")],
                rigid_body_basis=Rl, residual_vectors=options.residual_vectors,
                metadata={"mass": fe.mass, "center_of_mass": fe.center_of_mass.tolist(),
                          "inertia": fe.inertia.tolist(), "masters": {nm: p.tolist() for nm, p, _ in c.masters},
                          "n_full_dofs": int(fe.n_dofs), "n_coupled_dofs": int(n), "mesh_file": mfile.name})
            return red.reduce()

        se = cache.get_or_reduce(key_inputs, do_reduce)
        md = se.metadata
        names = [nm for nm in md["masters"]]
        masters = {nm: (o + R @ np.asarray(md["masters"][nm]), 6 * k + np.arange(6)) for k, nm in enumerate(names)}
        com_l = np.asarray(md["center_of_mass"])
        pts = np.repeat(np.array([md["masters"][nm] for nm in names]), 6, axis=0)
        kinds = np.tile(np.arange(6), len(names))
        Rl = np.zeros((se.K.shape[0], 6))
        Rl[:6 * len(names)] = _rigid_rows(pts, kinds, com_l)
        K, M = deflate_rigid(se.K, se.M, Rl, body.name), se.M
        mass, inertia = float(md["mass"]), np.asarray(md["inertia"])
        n_rv = int(md.get("n_residual_vectors", 0))
        info = {"n_modes": se.n_modes - n_rv, "n_residual_vectors": n_rv, "n_full_dofs": md.get("n_full_dofs"), "cutoff_hz": cutoff,
                "reduce_time_s": time.perf_counter() - t0, "cache_hits": cache.hits}
    else:
        c = coupled()
        names = [nm for nm, _, _ in c.masters]
        masters = {nm: (o + R @ p, idx) for nm, p, idx in c.masters}
        com_l = fe.center_of_mass
        Rl = _coupled_rigid_basis(c, com_l)
        K, M = c.K_c, c.M_c
        mass, inertia = fe.mass, fe.inertia
        se = None
        info = {"n_full_dofs": int(fe.n_dofs), "build_time_s": time.perf_counter() - t0}
    fbm = FlexibleBodyModel(body.name, o + R @ com_l, R, o, mass, R @ inertia @ R.T, K, M, masters, Rl,
                            reduce, se, info, params, dataclasses.replace(options, mesh_size=mesh_size))
    if not reduce:
        fbm._coupled = (fe, cm)
    return fbm


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
        raise RuntimeError(f"{name}: superelement strains rigid motions (|K R|/|K||R| = {rel:.2e})")
    MR = M @ R
    G = np.linalg.solve(R.T @ MR, MR.T)        # (R'MR)^-1 R'M
    P = np.eye(K.shape[0]) - R @ G
    Kd = P.T @ K @ P
    return 0.5 * (Kd + Kd.T)


def code_digest() -> str:
    """Digest of the source that turns a mesh into a superelement (FE model, couplings,
    Craig-Bampton): part of the reduction cache key, so a code change never reuses a
    reduction whose coordinates no longer match."""
    import hashlib
    import cms.craig_bampton
    import fe_components.coupling
    import fe_components.fe_model
    h = hashlib.sha256()
    for mod in (fe_components.fe_model, fe_components.coupling, cms.craig_bampton):
        h.update(Path(mod.__file__).read_bytes())
    return h.hexdigest()[:16]


def _coupled_rigid_basis(c, com_local) -> np.ndarray:
    """Rigid motions about the local COM on coupled coordinates q_c, whatever their layout:
    the least-squares solution of T R_c = R_full (exact, T has full column rank and
    reproduces rigid motion), checked by its residual."""
    from cms.linsolve import factor
    fe = c.model
    Rfull = _rigid_rows(np.repeat(fe.nodes, 3, axis=0), np.tile(np.arange(3), fe.n_nodes), com_local)
    T = c.T.tocsc()
    Rc = factor((T.T @ T).tocsc()).solve(np.asarray(T.T @ Rfull))
    err = np.abs(T @ Rc - Rfull).max() / max(np.abs(Rfull).max(), 1e-300)
    if err > 1e-8:
        raise RuntimeError(f"rigid basis not reproduced by the coupling (error {err:.2e})")
    return np.asarray(Rc)
