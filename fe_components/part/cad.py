"""A user's CAD part (STEP/BREP) read with gmsh's OpenCASCADE kernel: checked, converted to
metres, its interface faces found by the rules, meshed into the mesh cache.

gmsh is imported inside the functions only. Units: a STEP file's declared length unit is
converted to mm by OpenCASCADE, then to m here; ``units`` given overrides it
(the file's numbers are taken in that unit); a BREP file is in mm unless ``units`` says
otherwise. The checks, each a :class:`~fe_components.part.file.PartFileError` naming the
file: nothing readable, an open shell (faces but no closed volume), several volumes
(refused, or fused with ``volumes = "fuse"`` when they touch), loose faces bounding no
volume (non-manifold), a size that betrays wrong units.
"""
from __future__ import annotations

import logging
import os
import re

import numpy as np

from ..gmsh_session import gmsh_model
from ..volume_mesh import mesh_volume
from .file import UNITS, PartFile, PartFileError
from .frame import PartFrame
from .geometry import Faces, PartGeometry, check_size, in_frame, resolve_interfaces

log = logging.getLogger(__name__)

#: Parametric samples per direction of a face (kept where inside the trimmed face), and
#: samples per boundary curve.
FACE_SAMPLES = 9
CURVE_SAMPLES = 9

_SI_PREFIX = {"": 1.0, "MILLI": 1e-3, "CENTI": 1e-2, "DECI": 1e-1, "MICRO": 1e-6, "KILO": 1e3}
_CONVERTED = {"INCH": 0.0254, "FOOT": 0.3048}


def step_length_unit(path) -> tuple[str, float]:
    """(name, metres) of the length unit a STEP file declares (ISO 10303-41 ``LENGTH_UNIT``:
    ``SI_UNIT(.MILLI.,.METRE.)`` or a ``CONVERSION_BASED_UNIT('INCH', ...)``); mm if none is
    found (the STEP default of CAD tools)."""
    with open(path, "rb") as fh:
        text = fh.read().decode("latin-1")
    for m in re.finditer(r"LENGTH_UNIT\s*\(\s*\)[^;]*;", text):
        ent = m.group(0)
        si = re.search(r"SI_UNIT\s*\(\s*(?:\.(\w+)\.|\$)\s*,\s*\.METRE\.\s*\)", ent)
        if si:
            prefix = si.group(1) or ""
            if prefix in _SI_PREFIX:
                return (prefix.lower() + "metre"), _SI_PREFIX[prefix]
        conv = re.search(r"CONVERSION_BASED_UNIT\s*\(\s*'(\w+)'", ent)
        if conv and conv.group(1).upper() in _CONVERTED:
            return conv.group(1).lower(), _CONVERTED[conv.group(1).upper()]
    return "mm (none declared)", 1e-3


def load_solid(gmsh, part: PartFile) -> tuple[int, float, np.ndarray, np.ndarray]:
    """Import the part into the current gmsh model, checked to be one closed volume (fused
    if allowed): ``(volume tag, metres per model unit, extent lo, hi in m in the part's local
    frame)``. The CAD stays in its own numbers:
    OpenCASCADE's scaling (a general transformation) turns exact surfaces into B-spline
    approximations (0.6 % off in volume on the shipped carrier), so sizes, samples, mass
    properties and the mesh are scaled instead."""
    name = part.path.name
    occ = gmsh.model.occ
    is_step = part.path.suffix.lower() in (".step", ".stp")
    # mm, OpenCASCADE's own default: the target unit is process-wide state of its STEP
    # translator that also scales what gmsh writes later (a "M" left behind makes every STEP
    # written afterwards 1000 x too large), so it is left at mm and the conversion done here
    gmsh.option.setString("Geometry.OCCTargetUnit", "MM" if is_step else "")
    try:
        occ.importShapes(part.file, highestDimOnly=False)
        occ.synchronize()
    except Exception as exc:  # gmsh raises plain Exception
        raise PartFileError("file", part.file, f"{name}: OpenCASCADE cannot read it ({exc})") from None
    if is_step:  # OpenCASCADE converted from the declared unit to mm
        declared, metres = step_length_unit(part.path)
        factor = 1e-3 * (1.0 if part.units is None else UNITS[part.units] / metres)
        unit_text = declared if part.units is None else f"{part.units} (file declares {declared})"
    else:
        factor = part.scale
        unit_text = part.units or "mm (default for BREP)"
    vols = [t for _, t in gmsh.model.getEntities(3)]
    n_faces = len(gmsh.model.getEntities(2))
    if not vols:
        what = f"an open shell: {n_faces} faces and no closed volume (sew them into a solid in the CAD tool)" \
            if n_faces else "no solid, face or curve"
        raise PartFileError("file", part.file, f"{name}: {what}")
    if len(vols) > 1:
        if part.volumes != "fuse":
            raise PartFileError("volumes", part.volumes, f"{name}: {len(vols)} separate volumes; set volumes = "
                                                         "'fuse' to join them into one part, or export one solid")
        occ.fuse([(3, vols[0])], [(3, t) for t in vols[1:]])
        occ.synchronize()
        left = [t for _, t in gmsh.model.getEntities(3)]
        if len(left) != 1:
            raise PartFileError("volumes", "fuse", f"{name}: fusing its {len(vols)} volumes leaves {len(left)} "
                                                   "separate parts: they do not all touch")
        log.info("%s: fused %d volumes into one", name, len(vols))
        vols = left
    loose = [t for _, t in gmsh.model.getEntities(2) if len(gmsh.model.getAdjacencies(2, t)[0]) == 0]
    if loose:
        raise PartFileError("file", part.file, f"{name}: non-manifold: {len(loose)} face(s) bound no volume "
                                               "(loose or dangling faces); remove them in the CAD tool")
    pts = PartFrame.of(part.axis, part.origin).points(factor * _extent_points(gmsh))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    check_size(part, lo, hi, factor * (metres / 1e-3 if is_step else 1.0), unit_text)
    return vols[0], factor, lo, hi


def _extent_points(gmsh) -> np.ndarray:
    """Points (model units) along every curve of the model, whose box is the model's tight
    bounding box: OpenCASCADE's own boxes of curved solids are loose (control points)."""
    pts = []
    for _, c in gmsh.model.getEntities(1):
        lo, hi = gmsh.model.getParametrizationBounds(1, c)
        pts.append(np.asarray(gmsh.model.getValue(1, c, np.linspace(lo[0], hi[0], 4 * CURVE_SAMPLES).tolist())))
    return np.concatenate(pts).reshape(-1, 3)


def face_samples(gmsh, tag: int) -> np.ndarray:
    """Points (m) of CAD face ``tag``: a parametric grid kept where inside the trimmed face,
    and points along its boundary curves."""
    lo, hi = gmsh.model.getParametrizationBounds(2, tag)
    u = np.linspace(lo[0], hi[0], FACE_SAMPLES)
    v = np.linspace(lo[1], hi[1], FACE_SAMPLES)
    uv = np.stack(np.meshgrid(u, v, indexing="ij"), axis=-1).reshape(-1, 2)
    inside = [p for p in uv if gmsh.model.isInside(2, tag, list(p), parametric=True)]
    pts = [np.asarray(gmsh.model.getValue(2, tag, np.ravel(inside).tolist())).reshape(-1, 3)] if inside else []
    for _, c in gmsh.model.getBoundary([(2, tag)], combined=False, oriented=False):
        clo, chi = gmsh.model.getParametrizationBounds(1, abs(c))
        t = np.linspace(clo[0], chi[0], CURVE_SAMPLES)
        pts.append(np.asarray(gmsh.model.getValue(1, abs(c), t.tolist())).reshape(-1, 3))
    return np.concatenate(pts) if pts else np.zeros((0, 3))


def cad_faces(gmsh, f: float) -> Faces:
    """Every face of the current model with its samples, area and centroid, in metres
    (``f``: metres per model unit)."""
    occ = gmsh.model.occ
    tags = [t for _, t in gmsh.model.getEntities(2)]
    samples = [face_samples(gmsh, t) for t in tags]
    k = max(len(s) for s in samples)
    pts = np.stack([np.concatenate([s, np.repeat(s[-1:], k - len(s), axis=0)]) for s in samples])
    area = np.array([occ.getMass(2, t) for t in tags])
    centroid = np.array([occ.getCenterOfMass(2, t) for t in tags])
    return Faces(pts * f, area * f ** 2, centroid * f, np.asarray(tags))


def _geometry(gmsh, part: PartFile) -> tuple[PartGeometry, float]:
    """(the part in metres and its local frame, metres per model unit); the rules act on the
    file's axes."""
    occ = gmsh.model.occ
    vol, f, lo, hi = load_solid(gmsh, part)
    frame = PartFrame.of(part.axis, part.origin)
    faces = cad_faces(gmsh, f)
    interfaces = in_frame(resolve_interfaces(part, faces, {}, float(np.linalg.norm(hi - lo))), frame)
    return PartGeometry(lo, hi, occ.getMass(3, vol) * f ** 3, frame.points(np.asarray(occ.getCenterOfMass(3, vol)) * f),
                        frame.tensor(np.asarray(occ.getMatrixOfInertia(3, vol)).reshape(3, 3) * f ** 5),
                        interfaces, "cad"), f


def read_part_geometry(part: PartFile) -> PartGeometry:
    """The part's size, CAD-exact volume, centroid and inertia per unit density, and its
    interfaces (:class:`~fe_components.part.geometry.PartGeometry`), without meshing."""
    with gmsh_model("part") as gmsh:
        return _geometry(gmsh, part)[0]


def generate_part_mesh(part: PartFile, options, path) -> None:
    """Mesh the CAD part with ``options`` (:class:`~fe_components.meshing.MeshOptions`):
    one physical volume ``solid`` and one physical surface group per interface, in metres and
    the part's local frame; write ``path``."""
    with gmsh_model("part-mesh") as gmsh:
        geo, f = _geometry(gmsh, part)
        vol = [t for _, t in gmsh.model.getEntities(3)]
        gmsh.model.addPhysicalGroup(3, vol, name="solid")
        for itf in geo.interfaces:
            gmsh.model.addPhysicalGroup(2, [int(t) for t in itf.face_ids], name=itf.name)
        try:
            mesh_volume(gmsh, options, unit=f)
            # to metres, in the part's local frame
            gmsh.model.mesh.affineTransform(PartFrame.of(part.axis, part.origin).affine(f))
        except Exception as exc:  # gmsh raises plain Exception
            raise PartFileError("file", part.file, f"{part.path.name}: gmsh cannot mesh the part at size "
                                                   f"{options.size:g} m ({exc})") from None
        gmsh.write(os.fspath(path))
