"""What a user's part is, read from its file before anything is meshed: size, volume, mass
properties and its interfaces (faces found by the rules, master positions). SI units.

The readers build it: a CAD file with gmsh's OpenCASCADE kernel (:mod:`fe_components.part.cad`),
a mesh file with meshio (:mod:`fe_components.part.mesh`); both hand their faces to
:func:`resolve_interfaces` and check the size with :func:`check_size`.
:func:`fe_components.part.read.part_geometry` picks the reader and reads a file once per
process. Every problem is a :class:`~fe_components.part.file.PartFileError` naming the field
and the file.
"""
from __future__ import annotations

import dataclasses
import logging
from dataclasses import dataclass
from typing import Optional

import numpy as np

from .cells import ReadSummary
from .file import SIZE_RANGE, UNITS, PartFile, PartFileError
from .frame import PartFrame
from .rules import computed_master, faces_match, unreached

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Faces:
    """Faces of a part with their sample points: ``points`` (n_faces, k, 3) [m] (CAD faces
    of fewer samples repeat their last), ``area`` (n_faces,) [m^2], ``centroid``
    (n_faces, 3) [m]; ``ids``: the faces' tags (CAD) or indices (mesh boundary)."""

    points: np.ndarray
    area: np.ndarray
    centroid: np.ndarray
    ids: np.ndarray


@dataclass(frozen=True)
class ResolvedInterface:
    """An interface found in the part: name, master (3,) [m], coupling, its faces' ids,
    their bounding box (m) and area (m^2)."""

    name: str
    master: np.ndarray
    coupling: str
    face_ids: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    area: float = 0.0


@dataclass(frozen=True)
class PartGeometry:
    """The part read from its file (m, m^3), in its local frame (the file's, or the one its
    ``axis`` and ``origin`` give): bounding box, volume, centroid, the inertia tensor per
    unit density about the centroid (m^5; CAD-exact for a CAD file, integrated over the
    elements for a mesh file), the interfaces in rule order and, for a mesh file, what was
    read (:class:`~fe_components.part.cells.ReadSummary`)."""

    lo: np.ndarray
    hi: np.ndarray
    volume: float
    centroid: np.ndarray
    inertia_per_density: np.ndarray
    interfaces: tuple[ResolvedInterface, ...]
    source: str  # "cad" or "mesh"
    edge_length: float = 0.0  # median element edge of a mesh file (m), 0 for CAD
    read: Optional[ReadSummary] = None  # what a mesh file held and what was left out (None for CAD)

    @property
    def size(self) -> float:
        """Bounding-box diagonal (m)."""
        return float(np.linalg.norm(self.hi - self.lo))


def check_size(part: PartFile, lo: np.ndarray, hi: np.ndarray, scale: float, unit_text: str) -> None:
    """Refuse a part whose size (bounding-box diagonal, m) is outside :data:`SIZE_RANGE`: its
    units are wrong. ``scale``: metres per file unit as read (``unit_text``, for the message)."""
    size = float(np.linalg.norm(np.asarray(hi) - np.asarray(lo)))
    if SIZE_RANGE[0] <= size <= SIZE_RANGE[1]:
        return
    raw = size / scale
    better = [u for u, f in UNITS.items() if 0.05 <= raw * f <= 20.0]
    hint = f"; did you mean units = {better[0]!r}?" if better else ""
    raise PartFileError("units", part.units, f"{part.path.name}: read in {unit_text}, the part is {size:.4g} m "
                                             f"across: not a drivetrain part ({SIZE_RANGE[0]:g} to "
                                             f"{SIZE_RANGE[1]:g} m){hint}")


def resolve_interfaces(part: PartFile, faces: Faces, named: dict, size: float) -> tuple[ResolvedInterface, ...]:
    """Apply the rules: each geometric rule selects the faces all of whose samples satisfy it,
    a group rule the faces of its named group (``named``: group name -> face indices into
    ``faces``). A rule that selects nothing, or a face selected by two rules, is an error
    naming the rule(s); so is a master the part does not reach."""
    owner: dict[int, int] = {}
    out = []
    tol_default = 1e-5 * size
    for i, rule in enumerate(part.interfaces):
        where = f"interfaces[{i}]"
        if rule.select == "group":
            if rule.group not in named:
                raise PartFileError(f"{where}.group", rule.group,
                                    f"{part.path.name}: no such group; the file has {sorted(named) or 'none'}")
            sel = np.asarray(named[rule.group], dtype=np.int64)
        else:
            tol = rule.tolerance if rule.tolerance is not None else tol_default
            sel = np.flatnonzero(faces_match(rule, faces.points, tol))
        if len(sel) == 0:
            raise PartFileError(where, rule.name, f"{part.path.name}: the {rule.select} rule of interface "
                                                  f"{rule.name!r} selects no face of the part")
        for f in sel:
            j = owner.setdefault(int(f), i)
            if j != i:
                other = part.interfaces[j]
                raise PartFileError(where, rule.name, f"{part.path.name}: interface {rule.name!r} selects face "
                                                      f"{int(faces.ids[f])}, already selected by interfaces[{j}] "
                                                      f"({other.name!r}): make the rules exclusive")
        area = faces.area[sel]
        centroid = (area @ faces.centroid[sel]) / area.sum()
        pts = faces.points[sel].reshape(-1, 3)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        master = computed_master(rule, centroid)
        gap = unreached(master, lo, hi, size)
        if gap is not None:
            raise PartFileError(f"{where}.master", np.round(master, 6).tolist(),
                                f"{part.path.name}: the part does not reach the master of interface "
                                f"{rule.name!r}: it lies {gap:.4g} m from the interface's faces (the part is "
                                f"{size:.4g} m across)")
        out.append(ResolvedInterface(rule.name, master, rule.coupling, faces.ids[sel], lo, hi, float(area.sum())))
        log.debug("interface %s: %d faces, master %s", rule.name, len(sel), master)
    return tuple(out)


def in_frame(interfaces, frame: PartFrame) -> tuple[ResolvedInterface, ...]:
    """Interfaces resolved in the file's axes, in the part's local frame: masters moved,
    face boxes the boxes of the moved corners."""
    if frame.is_identity:
        return tuple(interfaces)
    out = []
    for itf in interfaces:
        corners = np.array([[(itf.lo, itf.hi)[(k >> j) & 1][j] for j in range(3)] for k in range(8)])
        c = frame.points(corners)
        out.append(dataclasses.replace(itf, master=frame.points(itf.master), lo=c.min(axis=0), hi=c.max(axis=0)))
    return tuple(out)
