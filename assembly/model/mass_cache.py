"""Cached mass properties of component meshes, so that a warm rigid load reads no mesh.

A component body that stays rigid needs only three things from its mesh: the mass (kg),
the centre of mass (m) and the inertia tensor about it (kg m^2), all in the component's
local axes. Integrating them means reading the .msh file and building a scikit-fem basis
(about 0.3-0.6 s per NREL 5 MW carrier or wheel), so they are kept beside the mesh cache
entry, in the mesh cache folder, as ``<mesh name>.mass-<digest>.json``: the mesh file's
name is the mesh's key (geometry, mesh options, mesher and gmsh versions), the digest
covers the density and this format's version.

Integrity rules, as for the mesh and superelement caches:

* The entry holds the SHA-256 of its own canonical JSON, and its text must be exactly what
  this version renders from the values it holds; every load checks both. *Any*
  failure to read, parse or verify an entry is a miss: the file is moved aside to
  ``<name>.corrupt-<UTC time>-<pid>`` with a WARNING naming it, and the properties are
  integrated from the mesh again and stored.
* The entry records the mesh file it came from (name, size in bytes, modification time in
  ns) and the mesh's content hash. A load compares the mesh file's size and modification
  time with one ``stat`` (no read): a mesh regenerated or replaced since is a quiet miss
  (the entry is stale, not corrupt) and the entry is rewritten.
* Writes are atomic (:func:`assembly.atomic_file.write_text_atomic`: unique temporary file,
  fsync, ``os.replace``), so concurrent writers each publish a whole file; a folder that
  cannot take the file costs only the reuse (a warning).

Floats are written with ``repr`` (JSON), which round-trips exactly: a hit returns the very
numbers the integration gave.
"""
from __future__ import annotations

import hashlib
import json
import logging
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..atomic_file import write_text_atomic

log = logging.getLogger(__name__)

#: Bump when the stored fields or the way the properties are integrated change.
FORMAT_VERSION = 1


@dataclass(frozen=True)
class MassProperties:
    """Mass properties of a component mesh in the component's local axes: ``mass`` (kg),
    ``center_of_mass`` (3,) (m), ``inertia`` (3, 3) about the centre of mass (kg m^2), and
    ``mesh_sha256``, the content hash of the mesh they were integrated from."""

    mass: float
    center_of_mass: np.ndarray
    inertia: np.ndarray
    mesh_sha256: str


def entry_path(mesh_file: Path, rho: float, folder: Path) -> Path:
    """The entry for the mesh ``mesh_file`` at density ``rho`` (kg/m^3), in ``folder``."""
    digest = hashlib.sha256(json.dumps({"rho": float(rho), "format": FORMAT_VERSION}).encode()).hexdigest()
    return Path(folder) / f"{Path(mesh_file).name}.mass-{digest[:16]}.json"


def _fingerprint(mesh_file: Path) -> dict:
    st = os.stat(mesh_file)
    return {"mesh": Path(mesh_file).name, "mesh_bytes": st.st_size, "mesh_mtime_ns": st.st_mtime_ns}


def _render(record: dict) -> str:
    """The entry's exact text: a load re-renders what it parsed and compares, so any changed
    byte (even white space the JSON parser would skip) is a damaged entry."""
    return json.dumps(record, indent=1) + "\n"


def seal(record: dict) -> str:
    """The SHA-256 of ``record`` (its canonical JSON, keys sorted): what an entry stores to
    show it was written whole by this code."""
    return hashlib.sha256(json.dumps(record, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def load(path: Path, mesh_file: Path, rho: float) -> MassProperties | None:
    """The stored properties of ``mesh_file`` at density ``rho``, or None on a miss: no entry,
    a stale one (the mesh file changed since), or an unusable one (moved aside, warning)."""
    from fe_components.meshing import move_aside
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        return None
    except (OSError, UnicodeDecodeError) as exc:
        move_aside(path, f"cannot read: {exc}", "mass-property cache entry", "integrating again")
        return None
    try:
        props, record = _parse(text, rho)
    except Exception as exc:  # any failure to use an entry is a miss, whatever raised it
        move_aside(path, f"{type(exc).__name__}: {exc}", "mass-property cache entry", "integrating again")
        return None
    try:
        now = _fingerprint(mesh_file)
    except OSError:
        return None
    if any(record[k] != v for k, v in now.items()):
        log.info("mass-property cache entry %s is stale (mesh %s changed since): integrating again", path,
                 mesh_file)
        return None
    log.info("mass-property cache hit: %s", path)
    return props


def _parse(text: str, rho: float) -> tuple[MassProperties, dict]:
    """Verified properties and record of an entry's text (raises ValueError, KeyError, ...)."""
    record = json.loads(text)
    if _render(record) != text:
        raise ValueError("not the text this version writes (changed bytes or white space)")
    stored = record.pop("sha256")
    if seal(record) != stored:
        raise ValueError("content hash mismatch")
    if record["format"] != FORMAT_VERSION:
        raise ValueError(f"format {record['format']!r}, expected {FORMAT_VERSION}")
    if record["rho"] != float(rho):
        raise ValueError(f"density {record['rho']!r} kg/m^3 under the key of {float(rho)!r}")
    mass = float(record["mass"])
    com = np.array(record["center_of_mass"], dtype=float)
    inertia = np.array(record["inertia"], dtype=float)
    if com.shape != (3,) or inertia.shape != (3, 3) or not (np.isfinite(mass) and mass > 0):
        raise ValueError("mass <= 0 or wrong shapes")
    return MassProperties(mass, com, inertia, str(record["mesh_sha256"])), record


def store(path: Path, props: MassProperties, mesh_file: Path, rho: float) -> Path | None:
    """Write the entry for ``props`` of ``mesh_file`` at density ``rho`` atomically; a folder
    that cannot take it (read-only, full) costs only the reuse: warn and return None. Call it
    right after verifying ``mesh_file``'s content hash: its size and modification time are
    read now."""
    record = {"format": FORMAT_VERSION, "rho": float(rho), "mass": float(props.mass),
              "center_of_mass": [float(x) for x in props.center_of_mass],
              "inertia": [[float(x) for x in row] for row in props.inertia],
              "mesh_sha256": props.mesh_sha256}
    try:
        record.update(_fingerprint(mesh_file))
        record["sha256"] = seal(record)
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        return write_text_atomic(path, _render(record))
    except OSError as exc:
        log.warning("cannot store mass properties in %s: %s; continuing without caching them",
                    Path(path).parent, exc.strerror or exc)
        return None
