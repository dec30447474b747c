"""The Craig-Bampton superelement (reduced model) and its versioned file format.

Reduced coordinates ``q = [q_b, q_m]``: the boundary (master) DOFs first, in the
order given to the reductor (physical units: m or rad), then the modal
coordinates of the fixed-interface normal modes (units: sqrt(kg) * m, since the
modes are mass-normalised, Phi^T M_ii Phi = I).

Full field: ``u[boundary_dofs] = q_b``, ``u[interior_dofs] = Psi q_b + Phi q_m``.

File format (version 2): one ``.npz`` with the arrays plus a JSON string
``metadata_json`` holding ``format``, ``version``, scalar fields and the
caller's metadata (mesh hash, material, interfaces, mode selection). The zip
archive comment, the last bytes of the file, is ``flexgear-sha256:<hex>``: the
SHA-256 of every byte before the hex digits, so any change to the file (truncation,
a flipped byte anywhere, garbage) fails :meth:`Superelement.load` with a
:class:`~cms.errors.CacheError`, as does any other failure to read it (version 1
files have no such comment). Written to a unique temporary file in the same
directory, fsynced and moved into place with ``os.replace``, so a reader never sees
a half-written file and concurrent writers never mix their bytes.
"""
from __future__ import annotations

import errno
import hashlib
import io
import json
import logging
import os
import tempfile
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import CacheError, ReductionError

log = logging.getLogger(__name__)

FORMAT = "flexgear.cms.superelement"
VERSION = 2  # 2: sealed with a SHA-256 in the zip comment

_ARRAYS = ("K", "M", "Phi", "Psi", "boundary_dofs", "interior_dofs", "eigenvalues",
           "boundary_points", "boundary_kinds")


@dataclass
class Superelement:
    """Reduced (Craig-Bampton) component.

    Attributes
    ----------
    K, M : (m, m) reduced stiffness (N/m, N/rad, ...) and mass, symmetric,
        m = n_boundary + n_modes, boundary coordinates first.
    Phi : (n_interior, n_modes) fixed-interface normal modes, mass-normalised; with
        residual vectors, the last ``metadata["n_residual_vectors"]`` columns are those
        (M-orthonormal Ritz vectors, see ``CraigBamptonReductor``).
    Psi : (n_interior, n_boundary) static constraint modes (interior response to a
        unit boundary displacement, others held).
    boundary_dofs, interior_dofs : indices into the full DOF vector.
    eigenvalues : (n_modes,) omega^2 of the fixed-interface modes (Ritz values for the
        residual vectors), (rad/s)^2.
    boundary_names : names of the boundary DOFs (e.g. ``"hub:ux"``).
    boundary_points : (n_boundary, 3) location of each boundary DOF (m), or empty.
    boundary_kinds : (n_boundary,) 0..5 = ux, uy, uz, rx, ry, rz, or -1 if unknown.
    metadata : JSON-serialisable description (mesh hash, material, interfaces,
        mode selection, solver, timings, self-checks).
    """

    K: np.ndarray
    M: np.ndarray
    Phi: np.ndarray
    Psi: np.ndarray
    boundary_dofs: np.ndarray
    interior_dofs: np.ndarray
    eigenvalues: np.ndarray
    boundary_names: list[str] = field(default_factory=list)
    boundary_points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    boundary_kinds: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    metadata: dict = field(default_factory=dict)

    # ---- sizes -------------------------------------------------------------
    @property
    def n_boundary(self) -> int:
        return len(self.boundary_dofs)

    @property
    def n_modes(self) -> int:
        return self.Phi.shape[1]

    @property
    def n_full(self) -> int:
        return len(self.boundary_dofs) + len(self.interior_dofs)

    @property
    def mode_frequencies_hz(self) -> np.ndarray:
        """Fixed-interface natural frequencies f = sqrt(omega^2) / (2 pi), Hz."""
        return np.sqrt(np.clip(self.eigenvalues, 0.0, None)) / (2.0 * np.pi)

    # ---- back-expansion ----------------------------------------------------
    def reconstruct(self, q: np.ndarray) -> np.ndarray:
        """Full DOF vector(s) from reduced coordinates ``q`` (shape (m,) or (m, nt))."""
        q = np.asarray(q, dtype=float)
        m = self.n_boundary + self.n_modes
        if q.shape[0] != m:
            raise ReductionError("reduced vector has wrong length", "q.shape", q.shape)
        qb, qm = q[:self.n_boundary], q[self.n_boundary:]
        u = np.zeros((self.n_full,) + q.shape[1:])
        u[self.boundary_dofs] = qb
        u[self.interior_dofs] = self.Psi @ qb + self.Phi @ qm
        return u

    # ---- persistence -------------------------------------------------------
    def save(self, path: str | os.PathLike) -> None:
        """Write atomically to ``path`` (``.npz``, sealed with its SHA-256)."""
        meta = {"format": FORMAT, "version": VERSION,
                "boundary_names": list(self.boundary_names),
                "metadata": self.metadata}
        arrays = {k: np.asarray(getattr(self, k)) for k in _ARRAYS}
        arrays["metadata_json"] = np.array(json.dumps(meta, default=json_default))
        write_sealed_npz(path, arrays)
        log.debug("saved superelement (%d boundary, %d modes) to %s",
                  self.n_boundary, self.n_modes, path)

    @classmethod
    def load(cls, path: str | os.PathLike) -> "Superelement":
        """Read a file written by :meth:`save`; any failure raises :class:`CacheError`."""
        path = os.fspath(path)
        try:
            z = read_sealed_npz(path)
            meta = json.loads(str(z["metadata_json"]))
            if meta.get("format") != FORMAT or meta.get("version") != VERSION:
                raise CacheError("unknown superelement file format/version", "format/version",
                                 (meta.get("format"), meta.get("version")))
            return cls(boundary_names=list(meta["boundary_names"]), metadata=meta["metadata"],
                       **{k: z[k] for k in _ARRAYS})
        except CacheError:
            raise
        except Exception as exc:  # any other failure to use the file is the same kind of error
            raise CacheError(f"cannot read superelement file: {type(exc).__name__}: {exc}",
                             "path", path) from exc


_SEAL = b"flexgear-sha256:"
_HEX = 64


def write_sealed_npz(path: str | os.PathLike, arrays: dict) -> None:
    """Write ``arrays`` as an ``.npz`` whose zip comment seals the file with its SHA-256:
    to a unique temporary file in the same directory, fsynced, then ``os.replace``d
    (:func:`atomic_write`; the directory is created if missing)."""
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    with zipfile.ZipFile(buf, "a") as zf:
        zf.comment = _SEAL + b"0" * _HEX       # placeholder of the final length
    body = buf.getvalue()[:-_HEX]
    data = body + hashlib.sha256(body).hexdigest().encode()
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    atomic_write(path, lambda fh: fh.write(data))


def atomic_write(path, write) -> Path:
    """Call ``write(binary file)`` on a temporary file in ``path``'s folder, fsync it and move it
    onto ``path`` (0o644). A missing or unwritable folder raises an OSError naming the folder;
    on any failure the temporary file is removed and ``path`` is untouched."""
    path = Path(path)
    folder = path.parent
    if not folder.is_dir():
        raise FileNotFoundError(errno.ENOENT, f"cannot write {path.name}: no such folder", str(folder))
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    except OSError as exc:
        raise type(exc)(exc.errno, f"cannot write {path.name} into this folder: {exc.strerror}",
                        str(folder)) from exc
    try:
        os.chmod(tmp, 0o644)                     # mkstemp makes it 0600
        with os.fdopen(fd, "wb") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def read_sealed_npz(path: str | os.PathLike) -> dict:
    """Arrays of a file written by :func:`write_sealed_npz`, after checking its seal
    (raises :class:`CacheError` if it is missing or does not match the bytes)."""
    with open(path, "rb") as fh:
        data = fh.read()
    if len(data) <= len(_SEAL) + _HEX or data[-_HEX - len(_SEAL):-_HEX] != _SEAL:
        raise CacheError("no content hash (truncated, or written by an older version)", "size_bytes",
                         len(data))
    actual = hashlib.sha256(memoryview(data)[:-_HEX]).hexdigest()
    if actual.encode() != data[-_HEX:]:
        stored = data[-_HEX:].decode("ascii", "replace")
        raise CacheError("content hash mismatch", "sha256", f"stored {stored[:16]}, file {actual[:16]}")
    with np.load(io.BytesIO(data), allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


def json_default(o):
    """``json.dumps`` default: NumPy scalars and arrays as plain numbers and lists."""
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o)}")
