"""The Craig-Bampton superelement (reduced model) and its versioned file format.

Reduced coordinates ``q = [q_b, q_m]``: the boundary (master) DOFs first, in the
order given to the reductor (physical units: m or rad), then the modal
coordinates of the fixed-interface normal modes (units: sqrt(kg) * m, since the
modes are mass-normalised, Phi^T M_ii Phi = I).

Full field: ``u[boundary_dofs] = q_b``, ``u[interior_dofs] = Psi q_b + Phi q_m``.

File format (version 1): one ``.npz`` with the arrays plus a JSON string
``metadata_json`` holding ``format``, ``version``, scalar fields and the
caller's metadata (mesh hash, material, interfaces, mode selection). Written to a
temporary file in the same directory and moved into place with ``os.replace``,
so a reader never sees a half-written file.
"""
from __future__ import annotations

import json
import logging
import os
import tempfile
from dataclasses import dataclass, field

import numpy as np

from .errors import CacheError, ReductionError

log = logging.getLogger(__name__)

FORMAT = "flexgear.cms.superelement"
VERSION = 1

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
        """Write atomically to ``path`` (``.npz``)."""
        path = os.fspath(path)
        meta = {"format": FORMAT, "version": VERSION,
                "boundary_names": list(self.boundary_names),
                "metadata": self.metadata}
        arrays = {k: np.asarray(getattr(self, k)) for k in _ARRAYS}
        directory = os.path.dirname(os.path.abspath(path))
        os.makedirs(directory, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=".npz", dir=directory)
        try:
            with os.fdopen(fd, "wb") as fh:
                np.savez(fh, metadata_json=np.array(json.dumps(meta, default=_json_default)),
                         **arrays)
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(tmp, path)
        except BaseException:
            if os.path.exists(tmp):
                os.unlink(tmp)
            raise
        log.debug("saved superelement (%d boundary, %d modes) to %s",
                  self.n_boundary, self.n_modes, path)

    @classmethod
    def load(cls, path: str | os.PathLike) -> "Superelement":
        path = os.fspath(path)
        try:
            with np.load(path, allow_pickle=False) as z:
                meta = json.loads(str(z["metadata_json"]))
                arrays = {k: z[k] for k in _ARRAYS}
        except (OSError, KeyError, ValueError) as exc:
            raise CacheError(f"cannot read superelement file: {exc}", "path", path) from exc
        if meta.get("format") != FORMAT or meta.get("version") != VERSION:
            raise CacheError("unknown superelement file format/version", "format/version",
                             (meta.get("format"), meta.get("version")))
        return cls(boundary_names=list(meta["boundary_names"]), metadata=meta["metadata"],
                   **arrays)


def _json_default(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o)}")
