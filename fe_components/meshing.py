"""gmsh meshing of the component solids, with a content-addressed, self-verifying mesh cache.

A mesh file is named ``<kind>-<hash>.msh`` where the hash covers every
geometry parameter, every mesh option, this module's ``MESHER_VERSION`` and
the gmsh version.  If the file exists and verifies it is reused and gmsh is not
imported.

Integrity rules (every mesh file this module writes or reads):

* The file ends with a ``$FlexgearContentHash`` section holding the SHA-256 of all
  bytes before it (gmsh and meshio skip unknown sections, so the file stays a valid
  .msh).  That hash is the mesh's *content hash* (:attr:`MeshEntry.sha256`,
  :attr:`RawMesh.content_hash`): downstream caches key on it, not on the file name.
* Every load checks it, from the same open file that is then parsed.  A missing
  section (truncated file, or written by an older version) or a mismatch is a
  :class:`~fe_components.errors.MeshCacheError`.
* In a cache folder, *any* failure to read, verify or parse an entry is a cache miss:
  the file is moved aside to ``<name>.corrupt-<UTC time>-<pid>`` in the same folder
  (delete those at will), a WARNING names it and the reason, and the mesh is
  generated again.  gmsh failures are :class:`~fe_components.errors.MeshingError`,
  never a cache error.
* The committed reference meshes (:data:`REFERENCE_DIR`, ``meshes/ref``) are never
  rewritten by a load: a corrupt one raises :class:`MeshCacheError` (restore it with
  ``git checkout -- meshes/ref``); a missing one is generated there.
* Writes go to a unique temporary file in the same folder (``tempfile.mkstemp``), are
  sealed and fsynced, then moved into place with :func:`os.replace`: a reader never
  sees a half-written entry, and concurrent writers of one entry each publish a
  complete, sealed file (gmsh output is deterministic, so they are identical).

gmsh is imported only when :func:`generate_mesh` meshes (through
:func:`fe_components.gmsh_session.gmsh_model`); the volume mesh itself is
:func:`fe_components.volume_mesh.mesh_volume`, shared with a user's CAD part.
"""
from __future__ import annotations

import contextlib
import dataclasses
import functools
import hashlib
import logging
import os
import tempfile
import time
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

import numpy as np

from .errors import GeometryError, MeshCacheError, MeshingError
from .params import PartFile, component_kind, params_as_flat_dict, params_digest

log = logging.getLogger(__name__)

#: Bump when the geometry or meshing code (this module, :mod:`fe_components.volume_mesh`) changes the produced mesh.
MESHER_VERSION = "2"  # 2: inverted curved P2 elements repaired by gmsh high-order optimisation

#: Environment variable naming the cache root (meshes in it, reductions in its ``cms`` subfolder).
CACHE_ENV = "FLEXGEAR_CACHE_DIR"
#: A folder that replaces :func:`default_cache_dir` in this process, or None.
DEFAULT_CACHE_DIR = None


@contextlib.contextmanager
def cache_root(folder):
    """Within the block, :func:`default_cache_dir` (and every cache default that reads it) is
    ``folder``: ``$FLEXGEAR_CACHE_DIR`` is set to it and restored (or removed) afterwards."""
    saved = os.environ.get(CACHE_ENV)
    os.environ[CACHE_ENV] = str(folder)
    try:
        yield Path(folder)
    finally:
        if saved is None:
            os.environ.pop(CACHE_ENV, None)
        else:
            os.environ[CACHE_ENV] = saved


def default_cache_dir() -> Path:
    """The cache root: ``$FLEXGEAR_CACHE_DIR`` if set (and not empty), else the user's cache
    folder ``$XDG_CACHE_HOME/flexgear``, else ``~/.cache/flexgear`` (XDG Base Directory
    Specification: a relative ``XDG_CACHE_HOME`` is ignored)."""
    if DEFAULT_CACHE_DIR is not None:
        return Path(DEFAULT_CACHE_DIR)
    env = os.environ.get(CACHE_ENV, "").strip()
    if env:
        return Path(env).expanduser()
    xdg = os.environ.get("XDG_CACHE_HOME", "").strip()
    base = Path(xdg) if xdg and Path(xdg).is_absolute() else Path.home() / ".cache"
    return base / "flexgear"


#: Committed reference meshes: verified on load like the cache, but never moved or rewritten.
REFERENCE_DIR = Path(__file__).resolve().parent.parent / "meshes" / "ref"


@dataclass(frozen=True)
class MeshOptions:
    """gmsh mesh controls.

    size : target (maximum) element edge length [m].
    order : 1 (linear tets) or 2 (quadratic, curved-boundary tets; default).
    min_size : minimum element size [m] (0 = none).
    curvature_elements : if > 0, gmsh ``Mesh.MeshSizeFromCurvature`` (elements per 2*pi).
    algorithm_3d : gmsh ``Mesh.Algorithm3D`` (10 = HXT, 1 = Delaunay).
    flank_points : interpolation points per involute flank (geometry).
    helix_sections : transverse sections lofted for a helical gear (geometry).
    tooth_size : optional element size [m] on the gear-mesh surfaces (teeth / rim), growing
        linearly to ``size`` at two whole depths (4.5 m_n) from them; None = uniform ``size``.
    """

    size: float
    order: int = 2
    min_size: float = 0.0
    curvature_elements: int = 0
    algorithm_3d: int = 10
    flank_points: int = 7
    helix_sections: int = 5
    tooth_size: float | None = None

    def __post_init__(self) -> None:
        if not (isinstance(self.size, (int, float)) and np.isfinite(self.size) and self.size > 0):
            raise GeometryError("mesh_size", self.size, "must be a finite number > 0 m")
        if self.order not in (1, 2):
            raise GeometryError("order", self.order, "must be 1 or 2")
        if not (0 <= self.min_size <= self.size):
            raise GeometryError("min_size", self.min_size, "must satisfy 0 <= min_size <= size")
        if self.helix_sections < 2:
            raise GeometryError("helix_sections", self.helix_sections, "must be >= 2")
        if self.flank_points < 3:
            raise GeometryError("flank_points", self.flank_points, "must be >= 3")
        if self.tooth_size is not None and not (np.isfinite(self.tooth_size) and 0 < self.tooth_size <= self.size):
            raise GeometryError("tooth_size", self.tooth_size, "must satisfy 0 < tooth_size <= size")

    def digest_fields(self) -> dict:
        """Fields entering the cache name; options left at None (features off) are omitted so
        that adding an optional feature keeps the names of existing meshes."""
        d = {"__type__": type(self).__name__}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if not (f.name in _OPTIONAL_FIELDS and v is None):
                d[f.name] = v
        return d


_OPTIONAL_FIELDS = ("tooth_size",)


@functools.lru_cache(maxsize=None)
def _gmsh_version() -> str:
    """Installed gmsh version (read once: importlib.metadata costs ~1 ms a call)."""
    try:
        return metadata.version("gmsh")
    except metadata.PackageNotFoundError:  # pragma: no cover
        return "unknown"


def mesh_path(params, options: MeshOptions, cache_dir: str | os.PathLike | None = None) -> Path:
    """Cache file of the mesh of ``params`` meshed with ``options``."""
    cache = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    digest = params_digest(params, options.digest_fields(), MESHER_VERSION, _gmsh_version())
    return cache / f"{component_kind(params)}-{digest}.msh"


@dataclass(frozen=True)
class MeshEntry:
    """A verified mesh file and its content hash (SHA-256 hex of the gmsh bytes)."""

    path: Path
    sha256: str


def ensure_mesh(params, options: MeshOptions, cache_dir: str | os.PathLike | None = None, *,
                heal: bool | None = None) -> Path:
    """Return the verified cached mesh file, generating it with gmsh if it is missing or unusable."""
    return cached_mesh(params, options, cache_dir, heal=heal).path


def cached_mesh(params, options: MeshOptions, cache_dir: str | os.PathLike | None = None, *,
                heal: bool | None = None) -> MeshEntry:
    """:func:`ensure_mesh` with the content hash: verifies the file's hash without parsing it.

    ``heal``: move an unusable file aside and mesh again (default: everywhere but
    :data:`REFERENCE_DIR`, where an unusable file raises :class:`MeshCacheError`)."""
    path = mesh_path(params, options, cache_dir)
    sha = _load_entry(path, mesh_content_hash, heal)
    if sha is None:
        with build_lock(path):  # another process may have meshed it while we waited
            sha = _load_entry(path, mesh_content_hash, heal)
            if sha is None:
                sha = generate_entry(params, options, path)
    return MeshEntry(path, sha)


def load_mesh(params, options: MeshOptions, cache_dir: str | os.PathLike | None = None, *,
              heal: bool | None = None) -> tuple[Path, RawMesh]:
    """(path, parsed mesh) of the cached mesh, generated if missing or unusable (see ``heal``
    in :func:`cached_mesh`); verified and parsed from one read of the file."""
    path = mesh_path(params, options, cache_dir)
    raw = _load_entry(path, read_mesh, heal)
    if raw is None:
        with build_lock(path):
            raw = _load_entry(path, read_mesh, heal)
            if raw is None:
                generate_entry(params, options, path)
    if raw is None:
        try:
            raw = read_mesh(path)
        except MeshCacheError as exc:
            raise MeshingError(component_kind(params), _report(params, options),
                               f"the mesh gmsh just wrote cannot be read back: {exc.reason}") from exc
    return path, raw


def _load_entry(path: Path, reader, heal: bool | None):
    """``reader(path)``, or None if the entry is absent or unusable (then moved aside)."""
    if not path.exists():
        return None
    try:
        out = reader(path)
    except Exception as exc:  # any failure to use an entry is a miss, whatever raised it
        reason = exc.reason if isinstance(exc, MeshCacheError) else f"{type(exc).__name__}: {exc}"
        if not (heal if heal is not None else path.parent.resolve() != REFERENCE_DIR.resolve()):
            raise MeshCacheError(path, reason, "restore the committed file (git checkout -- meshes/ref) or "
                                               "regenerate it (python -m fe_components.reference)") from exc
        move_aside(path, reason)
        return None
    log.info("mesh cache hit: %s", path)
    return out


@contextlib.contextmanager
def build_lock(path: Path):
    """Hold an exclusive lock (``fcntl.flock`` on ``.<name>.lock`` beside ``path``) while an
    entry is built, so that two processes never build the same entry at the same time: the
    second waits, then finds the first one's entry. A folder that cannot take the lock file
    (read-only) builds without it. The superelement cache (cms.cache) locks by the same rule,
    in its own copy: the two packages import nothing of each other."""
    import fcntl
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        lock = path.with_name(f".{path.name}.lock")
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError:
        yield
        return
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        # removed while held: whoever locks after this sees the published entry
        lock.unlink(missing_ok=True)
        os.close(fd)  # closing releases the lock


def move_aside(path: Path, reason: str, what: str = "mesh cache entry", then: str = "meshing again") -> None:
    """Rename an unusable cache file to ``<name>.corrupt-<UTC time>-<pid>`` and warn
    ("unusable <what> <path> (<reason>): moved to ...; <then>"). The superelement cache
    (cms.cache) moves bad files aside by the same rule, in its own copy: the two packages
    import nothing of each other; assembly.model.mass_cache uses this one."""
    dest = path.with_name(f"{path.name}.corrupt-{time.strftime('%Y%m%dT%H%M%SZ', time.gmtime())}-{os.getpid()}")
    try:
        os.replace(path, dest)
        where = f"moved to {dest.name}"
    except FileNotFoundError:  # another process moved or replaced it first
        where = "already gone"
    except OSError as err:
        where = f"could not be moved aside ({err})"
    log.warning("unusable %s %s (%s): %s; %s", what, path, reason, where, then)


def generate_entry(params, options: MeshOptions, path: Path) -> str:
    """Mesh ``params`` into a unique temporary file next to ``path``, seal it, move it into
    place; return its content hash (the cache's build step: callers hold :func:`build_lock`)."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".tmp.msh", dir=path.parent)
    except OSError as exc:
        raise MeshCacheError(path, f"cannot write to the mesh cache folder: {exc.strerror or exc}",
                             "set FLEXGEAR_CACHE_DIR to a writable folder") from None
    os.close(fd)
    try:
        t0 = time.perf_counter()
        generate_mesh(params, options, tmp)
        sha = seal_mesh_file(tmp)
        os.chmod(tmp, 0o644)  # mkstemp creates 0600
        os.replace(tmp, path)
        log.info("meshed %s in %.2f s -> %s", component_kind(params), time.perf_counter() - t0, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return sha


_SEAL_HEAD = b"$FlexgearContentHash\nsha256 "
_SEAL_TAIL = b"\n$EndFlexgearContentHash\n"
_SEAL_LEN = len(_SEAL_HEAD) + 64 + len(_SEAL_TAIL)


def seal_mesh_file(path: str | os.PathLike) -> str:
    """Append the ``$FlexgearContentHash`` section (SHA-256 of the file so far) to a gmsh
    file; return the hash."""
    with open(path, "rb+") as fh:
        sha = hashlib.sha256(fh.read()).hexdigest()
        fh.write(_SEAL_HEAD + sha.encode() + _SEAL_TAIL)
        fh.flush()
        os.fsync(fh.fileno())
    return sha


def _verified_hash(data: bytes, path) -> str:
    """The content hash stored at the end of ``data`` after checking it against the bytes."""
    seal = data[-_SEAL_LEN:]
    if len(data) <= _SEAL_LEN or not (seal.startswith(_SEAL_HEAD) and seal.endswith(_SEAL_TAIL)):
        raise MeshCacheError(path, "no content-hash section (truncated, or written by an older version)")
    stored = seal[len(_SEAL_HEAD):-len(_SEAL_TAIL)].decode("ascii", "replace")
    actual = hashlib.sha256(memoryview(data)[:-_SEAL_LEN]).hexdigest()
    if actual != stored:
        raise MeshCacheError(path, f"content hash mismatch (stored {stored[:16]}, file {actual[:16]})")
    return actual


def mesh_content_hash(path: str | os.PathLike) -> str:
    """Verified content hash of a sealed mesh file (raises :class:`MeshCacheError`)."""
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise MeshCacheError(path, f"cannot read: {exc}") from exc
    return _verified_hash(data, path)


def _report(params, options: MeshOptions) -> dict:
    return {**params_as_flat_dict(params), **{f"mesh.{k}": v for k, v in params_as_flat_dict(options).items()}}


def _surface_samples(gmsh, tag: int, n: int = 7) -> np.ndarray:
    lo, hi = gmsh.model.getParametrizationBounds(2, tag)
    u = np.linspace(lo[0], hi[0], n)
    v = np.linspace(lo[1], hi[1], n)
    uv = np.stack(np.meshgrid(u, v, indexing="ij"), axis=-1).reshape(-1)
    return np.asarray(gmsh.model.getValue(2, tag, uv.tolist())).reshape(-1, 3)


def generate_mesh(params, options: MeshOptions, path: str | os.PathLike) -> None:
    """Build the solid, tag interface surfaces as physical groups, mesh and write ``path`` (.msh)."""
    # the geometry, CAD and mesh-file readers and gmsh: loaded only to mesh (reading a cached
    # mesh, or a model without flexible bodies, needs none of them)
    from .geometry import build_solid, characteristic_length, interface_defs
    from .gmsh_session import gmsh_model
    from .part import cad as part_cad
    from .part import mesh as part_mesh
    from .volume_mesh import mesh_volume

    if isinstance(params, PartFile):  # the user's CAD or mesh file
        return (part_mesh if params.is_mesh else part_cad).generate_part_mesh(params, options, path)
    kind = component_kind(params)
    report = _report(params, options)
    with gmsh_model(kind) as gmsh:  # lazy: loading a cached mesh must not import gmsh
        try:
            gmsh.option.setNumber("Geometry.OCCUnionUnify", 0)  # keep shaft-segment faces distinct
            occ = gmsh.model.occ
            vols = build_solid(occ, params, options.flank_points, options.helix_sections)
            occ.synchronize()
            # free construction points (arc centres) are not part of the solid
            in_solid = {abs(t) for d, t in gmsh.model.getBoundary(vols, combined=False, oriented=False, recursive=True)
                        if d == 0}
            free_pts = [(0, t) for _, t in gmsh.model.getEntities(0) if t not in in_solid]
            if free_pts:
                gmsh.model.removeEntities(free_pts)
            vol_tags = [t for d, t in gmsh.model.getEntities(3)]
            if not vol_tags:
                raise RuntimeError("boolean operations produced no volume")
            tol = 1e-6 * characteristic_length(params)
            surfaces = {}
            for _, tag in gmsh.model.getEntities(2):
                pts = _surface_samples(gmsh, tag)
                surfaces[tag] = (pts, float(pts[:, 2].min()), float(pts[:, 2].max()))
            gmsh.model.addPhysicalGroup(3, vol_tags, name="solid")
            taken: dict[int, str] = {}
            tooth_tags: list[int] = []
            for idef in interface_defs(params):
                tags = [t for t, (pts, zlo, zhi) in surfaces.items()
                        if any(sel.matches(pts, zlo, zhi, tol) for sel in idef.selectors)]
                if not tags:
                    raise RuntimeError(f"no CAD surface found for interface {idef.name!r}")
                for t in tags:
                    if t in taken:
                        raise RuntimeError(f"surface {t} belongs to interfaces {taken[t]!r} and {idef.name!r}")
                    taken[t] = idef.name
                gmsh.model.addPhysicalGroup(2, tags, name=idef.name)
                if idef.name == "gear_mesh":
                    tooth_tags = tags
                log.debug("interface %s: surfaces %s", idef.name, tags)
            if options.tooth_size is not None:
                _tooth_refinement(gmsh, params, options, tooth_tags)
            mesh_volume(gmsh, options)
            gmsh.write(os.fspath(path))
        except GeometryError:
            raise
        except Exception as err:  # gmsh raises plain Exception
            raise MeshingError(kind, report, err) from err


def _tooth_refinement(gmsh, params, options: MeshOptions, tooth_tags: list[int]) -> None:
    """Background size field: ``tooth_size`` on the gear-mesh surfaces, ``size`` from 4.5 m_n away."""
    teeth = getattr(params, "teeth", None)
    if teeth is None or not tooth_tags:
        raise GeometryError("tooth_size", options.tooth_size, "the component has no gear teeth")
    fd = gmsh.model.mesh.field.add("Distance")
    gmsh.model.mesh.field.setNumbers(fd, "SurfacesList", tooth_tags)
    ft = gmsh.model.mesh.field.add("Threshold")
    gmsh.model.mesh.field.setNumber(ft, "InField", fd)
    gmsh.model.mesh.field.setNumber(ft, "SizeMin", options.tooth_size)
    gmsh.model.mesh.field.setNumber(ft, "SizeMax", options.size)
    gmsh.model.mesh.field.setNumber(ft, "DistMin", 0.0)
    gmsh.model.mesh.field.setNumber(ft, "DistMax", 4.5 * teeth.normal_module)
    gmsh.model.mesh.field.setAsBackgroundMesh(ft)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)


@dataclass(frozen=True)
class RawMesh:
    """Mesh read back from a cache file: points (n, 3) [m], volume cells, interface node sets,
    and the file's content hash (SHA-256 hex)."""

    points: np.ndarray
    cell_type: str  # "tetra" or "tetra10" (meshio names)
    cells: np.ndarray
    interface_nodes: dict[str, np.ndarray]  # indices into points
    content_hash: str = ""


def read_mesh(path: str | os.PathLike) -> RawMesh:
    """Read a sealed .msh: check its content hash, parse it with meshio from the same open
    file, drop orphan nodes, collect physical surface node sets.

    Any failure (unreadable, unsealed, hash mismatch, unparsable, no tetrahedra) raises
    :class:`MeshCacheError`."""
    try:
        with open(path, "rb") as fh:
            sha = _verified_hash(fh.read(), path)
            fh.seek(0)
            m = _parse_gmsh(fh)
    except MeshCacheError:
        raise
    except Exception as exc:
        raise MeshCacheError(path, f"cannot parse: {type(exc).__name__}: {exc}") from exc
    vol = [(c.type, c.data) for c in m.cells if c.type in ("tetra", "tetra10")]
    if not vol:
        raise MeshCacheError(path, "file holds no tetrahedra")
    cell_type = vol[0][0]
    cells = np.concatenate([d for t, d in vol if t == cell_type])
    used = np.unique(cells)
    remap = np.full(len(m.points), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    nodes: dict[str, np.ndarray] = {}
    for name, per_block in m.cell_sets.items():
        if name.startswith("gmsh:"):
            continue
        ids = []
        for block, idx in zip(m.cells, per_block):
            if block.type in ("triangle", "triangle6") and idx is not None and len(idx):
                ids.append(block.data[idx].ravel())
        if ids:
            nodes[name] = np.unique(remap[np.concatenate(ids)])
    return RawMesh(m.points[used].copy(), cell_type, remap[cells], nodes, sha)


def _parse_gmsh(fh):
    """meshio's gmsh reader on an open binary file (``meshio.read`` only takes a path;
    parsing the file object that was hashed leaves no window for a swap in between)."""
    from meshio.gmsh.main import read_buffer

    return read_buffer(fh)
