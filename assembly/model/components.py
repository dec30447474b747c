"""Component bodies (a body's ``component``: fe_components parameters): placement,
interface master points, and the FE model (meshed with gmsh, assembled with scikit-fem).

Master points come from the component geometry alone (no meshing), so a scene is
validated before anything is meshed. FE models are memoised per process, keyed by the
content hash of the mesh they were assembled from, so the torsional, rigid and flexible
variants of one scene assemble each mesh once; meshes are cached on disk in
:class:`CacheDirs` (or read from the committed reference meshes).

Caches: the default root is the folder named by the environment variable
``FLEXGEAR_CACHE_DIR`` (``flexgear --cache-dir``), else the user's cache folder
``$XDG_CACHE_HOME/flexgear`` or ``~/.cache/flexgear`` (meshes and their mass properties,
assembly.model.mass_cache, in it; reductions in its ``cms`` subfolder). Every entry is verified on load and an unusable one is moved aside and rebuilt
with a warning (fe_components.meshing, cms.cache). A committed reference mesh that fails its
check is never touched: the scene uses a mesh generated in the cache instead, with a warning.
Component placement: a local point ``x`` sits at ``position + R x`` with
``R = axis_frame(axis)`` (local z = the body's axis). SI units.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path

from ..scene.attach import placement
from ..scene.tables import FlexOptions

log = logging.getLogger(__name__)

def default_cache_root() -> Path:
    """``$FLEXGEAR_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/flexgear`` or
    ``~/.cache/flexgear`` (:func:`fe_components.meshing.default_cache_dir`)."""
    from fe_components.meshing import default_cache_dir
    return default_cache_dir()


@dataclass(frozen=True)
class CacheDirs:
    """Folders of the on-disk caches: ``meshes`` (gmsh .msh files, keyed by geometry and
    mesh options) and ``superelements`` (Craig-Bampton reductions, keyed by the content hash
    of their mesh and what else they were built from). Defaults: :func:`default_cache_root`
    and its ``cms`` subfolder. Pass one to :func:`assembly.model.assemble.assemble` to keep a study's
    caches apart."""

    meshes: Path = field(default_factory=default_cache_root)
    superelements: Path = field(default_factory=lambda: default_cache_root() / "cms")


def mesh_size(params, options: FlexOptions) -> float:
    """The element size (m): the option, or the component's default (thinnest wall)."""
    from fe_components.fe_model import default_mesh_size
    return options.mesh_size if options.mesh_size is not None else default_mesh_size(params)


def mesh_entry(params, options: FlexOptions, caches: CacheDirs):
    """The component's verified mesh file and content hash (fe_components.meshing.MeshEntry),
    without assembling the FE model: the committed reference mesh if there is one for these
    parameters and it verifies, else the mesh cache (meshed again if missing or unusable). A
    corrupt reference mesh is left alone, with a warning."""
    from fe_components.errors import MeshCacheError
    from fe_components.meshing import cached_mesh, mesh_path
    from fe_components.reference import REF_DIR
    mopts = _mesh_options(params, options)
    if mesh_path(params, mopts, REF_DIR).exists():
        try:
            return cached_mesh(params, mopts, REF_DIR, heal=False)
        except MeshCacheError as exc:
            log.warning("committed reference mesh %s is unusable (%s): using a mesh generated in %s "
                        "instead; restore it with `git checkout -- meshes/ref`", exc.path,
                        exc.reason, caches.meshes)
    return cached_mesh(params, mopts, caches.meshes)


def _mesh_options(params, options: FlexOptions):
    from fe_components.meshing import MeshOptions
    return MeshOptions(size=mesh_size(params, options), order=options.order)


def mesh_file(params, options: FlexOptions, caches: CacheDirs) -> Path:
    """Where the component's mesh is, or will be, without reading or meshing anything: the
    committed reference mesh if there is one for these parameters, else the cache entry."""
    from fe_components.meshing import mesh_path
    from fe_components.reference import REF_DIR
    mopts = _mesh_options(params, options)
    ref = mesh_path(params, mopts, REF_DIR)
    return ref if ref.exists() else mesh_path(params, mopts, caches.meshes)


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


_FE_MEMO: dict = {}
_FE_MEMO_SIZE = 8


def forget_fe_models() -> None:
    """Drop the FE models memoised in this process (meshes stay cached on disk)."""
    _FE_MEMO.clear()


def build_fe(params, options: FlexOptions, caches: CacheDirs, mesh_sha256: str | None = None):
    """Mesh (cached on disk, verified) and assemble the component's FE model, memoised per
    process by the mesh's content hash. ``mesh_sha256``: prefer the memoised model of that
    exact mesh (e.g. the one a reduction was built from) over re-reading the disk; the
    caller checks ``fe.mesh_sha256``."""
    from fe_components.fe_model import build_component
    from fe_components.params import params_digest
    from fe_components.quality import check_quality
    m = options.material
    size = mesh_size(params, options)
    check_locking(options.order, m.nu)
    base = params_digest(params, size, options.order, m.E, m.nu, m.rho)
    if mesh_sha256 is not None and (base, mesh_sha256) in _FE_MEMO:
        return _FE_MEMO[(base, mesh_sha256)]
    entry = mesh_entry(params, options, caches)
    key = (base, entry.sha256)
    if key not in _FE_MEMO:
        fe = build_component(params, m, mesh_size=size, order=options.order, cache_dir=entry.path.parent)
        rep = check_quality(fe.mesh.p.T, fe.mesh.t.T)
        log.info("mesh quality: worst element %d, q = %.3g", rep.worst, rep.worst_quality)
        key = (base, fe.mesh_sha256)   # the file read, should it have changed since mesh_entry
        if len(_FE_MEMO) >= _FE_MEMO_SIZE:
            _FE_MEMO.pop(next(iter(_FE_MEMO)))
        _FE_MEMO[key] = fe
    return _FE_MEMO[key]


def local_mass_properties(params, options: FlexOptions, caches: CacheDirs):
    """Mass properties of the component's mesh in its local axes
    (:class:`assembly.model.mass_cache.MassProperties`): from the mass-property cache beside the
    mesh cache when the entry is there and the mesh file has not changed since (no mesh is
    read), else integrated over the FE model (meshing if needed) and stored."""
    from . import mass_cache
    rho = options.material.rho
    path = mass_cache.entry_path(mesh_file(params, options, caches), rho, caches.meshes)
    hit = mass_cache.load(path, mesh_file(params, options, caches), rho)
    if hit is not None:
        return hit
    fe = build_fe(params, options, caches)
    props = mass_cache.MassProperties(fe.mass, fe.center_of_mass, fe.inertia, fe.mesh_sha256)
    entry = mesh_entry(params, options, caches)     # the verified file now there (a miss may read)
    if entry.sha256 == fe.mesh_sha256:              # else the mesh changed under us: do not store
        mass_cache.store(mass_cache.entry_path(entry.path, rho, caches.meshes), props, entry.path, rho)
    return props


def mass_properties(body, options: FlexOptions, caches: CacheDirs):
    """(mass kg, centre of mass global m, inertia global about the centre of mass kg m^2) of
    a component body (:func:`local_mass_properties`, placed)."""
    p = local_mass_properties(body.component, options, caches)
    o, R = placement(body)
    return p.mass, o + R @ p.center_of_mass, R @ p.inertia @ R.T
