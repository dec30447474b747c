"""A user's own part as a component: a CAD file (STEP/BREP) or a volume mesh file, and the
rules that find its interfaces (SI units: m).

``PartFile(file, units, interfaces, volumes)`` is a component like the parametric ones
(``kind = "file"`` in a scene): it is meshed (CAD) or converted (mesh file) into the mesh
cache, keyed on the file's *content* (SHA-256), the unit and the rules, never on its name.

Units: coordinates are converted to metres once, on reading. A STEP file declares its
length unit and OpenCASCADE converts from it (``units`` left out); a BREP file has none and
is read in mm unless ``units`` says otherwise; a mesh file has none either and needs
``units``. ``units`` given for a STEP file overrides what the file declares (a file whose
numbers are metres although it says mm).

Interfaces (:class:`InterfaceRule`), in the part's own axes after the unit conversion,
each coupled (RBE2 or RBE3) to a 6-DOF master node:

* ``select = "group"``: a named group of the mesh file (gmsh physical group, Abaqus
  node / element / surface set, any meshio point or cell set);
* ``select = "cylinder"``: faces on the cylinder of ``radius`` about the line through
  ``axis_point`` along ``axis``, within ``span`` (distances along the axis from
  ``axis_point``); with ``outer_radius``: every face lying between the two radii that is
  not a plane normal to the axis (gear teeth, a splined or knurled seat);
* ``select = "plane"``: faces in the plane through ``point`` with ``normal``;
* ``select = "box"``: faces inside the box ``box_min``..``box_max``;
  ``box_min``/``box_max`` also restrict a cylinder or plane rule.

A face belongs to a rule when every sample point of it does (tolerance ``tolerance``, m;
default 1e-5 of the part's size). The master is ``master`` if given, else the area centroid
of the selected faces (for a cylinder rule: projected onto the axis).

The part's own frame: every component turns about its local z. A part modelled about
another axis of its file gives ``axis`` (the file's rotation axis) and ``origin`` (a point
of it, m after the unit conversion, the file's axes); the part is read in the frame of
:mod:`fe_components.part.frame`. Rules, masters and ``origin`` are in the file's axes; the
part's geometry (mesh, mass properties, interface masters) comes out in its local frame.

``order`` (mesh files): left out, the file's elements as they are (linear tetrahedra with a
warning: too stiff in bending); 2 lifts a linear mesh to P2 (a midside node at the middle of
every edge: straight edges, the faceted geometry kept); 1 keeps a linear mesh linear (the
warning acknowledged).
"""
from __future__ import annotations

import hashlib
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal, Optional

from ..errors import GeometryError
from ..fields import check_fields, first_problem, quantity

#: Length units a file may be in, and their size in metres.
UNITS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "um": 1e-6, "in": 0.0254, "ft": 0.3048}
#: File suffixes read with gmsh's OpenCASCADE kernel.
CAD_SUFFIXES = (".step", ".stp", ".brep", ".brp")
#: File suffixes read with meshio (volume meshes).
MESH_SUFFIXES = (".msh", ".inp", ".bdf", ".nas", ".vtu", ".vtk", ".med", ".xdmf")
RULES = ("group", "cylinder", "plane", "box")
#: Bump when reading or meshing a part file changes the mesh it gives (part of the cache key).
#: 3: MED node order, own Nastran reader, order, axis and origin.
PART_READER_VERSION = 3
#: A part smaller or larger than this (bounding-box diagonal, m) has the wrong units.
SIZE_RANGE = (1e-3, 100.0)

_POINT = tuple[float, float, float]
_LEN = {"unit": "m", "abs_lt": 1e6}


class PartFileError(GeometryError):
    """A part file that cannot be used: ``parameter`` is the field (``file``, ``units``,
    ``interfaces[2]``), ``value`` the file or value, ``reason`` names the file."""


@dataclass(frozen=True)
class InterfaceRule:
    """How an interface's faces are found in the part, and how they are coupled (m)."""

    name: str
    select: Literal["group", "cylinder", "plane", "box"]
    group: Optional[str] = None
    axis_point: _POINT = quantity(**_LEN, default=(0.0, 0.0, 0.0))
    axis: _POINT = quantity("", default=(0.0, 0.0, 1.0), abs_lt=1e6)
    radius: Optional[float] = quantity("m", None, gt=0.0)
    outer_radius: Optional[float] = quantity("m", None, gt=0.0)
    span: Optional[tuple[float, float]] = quantity(**_LEN, default=None)
    point: Optional[_POINT] = quantity(**_LEN, default=None)
    normal: Optional[_POINT] = quantity("", None, abs_lt=1e6)
    box_min: Optional[_POINT] = quantity(**_LEN, default=None)
    box_max: Optional[_POINT] = quantity(**_LEN, default=None)
    coupling: Literal["rbe2", "rbe3"] = "rbe2"
    master: Optional[_POINT] = quantity(**_LEN, default=None)
    tolerance: Optional[float] = quantity("m", None, gt=0.0)

    def __post_init__(self) -> None:
        for f in ("axis_point", "axis", "span", "point", "normal", "box_min", "box_max", "master"):
            v = getattr(self, f)
            if isinstance(v, list):  # arrays as tuples: a rule is hashable (the reader memoises on it)
                object.__setattr__(self, f, tuple(v))
        check_fields(self)
        if not isinstance(self.name, str) or not self.name.strip():
            raise GeometryError("name", self.name, "must be a non-empty string")
        if self.select not in RULES:
            raise GeometryError("select", self.select, f"must be one of {list(RULES)}")
        if self.coupling not in ("rbe2", "rbe3"):
            raise GeometryError("coupling", self.coupling, "must be 'rbe2' or 'rbe3'")
        need = {"group": ("group",), "cylinder": ("radius",), "plane": ("point", "normal"),
                "box": ("box_min", "box_max")}[self.select]
        for f in need:
            if getattr(self, f) is None:
                raise GeometryError(f, None, f"missing: select = {self.select!r} needs {' and '.join(need)}")
        allowed = set(need) | ({"box_min", "box_max"} if self.select != "group" else set())
        allowed |= {"axis_point", "axis", "span", "outer_radius"} if self.select == "cylinder" else set()
        for f in ("group", "radius", "outer_radius", "span", "point", "normal", "box_min", "box_max"):
            if getattr(self, f) is not None and f not in allowed:
                raise GeometryError(f, getattr(self, f), f"not used by select = {self.select!r}")
        if (self.box_min is None) != (self.box_max is None):
            raise GeometryError("box_max" if self.box_max is None else "box_min", None,
                                "give both box_min and box_max")
        if self.box_min is not None and not all(a < b for a, b in zip(self.box_min, self.box_max)):
            raise GeometryError("box_max", self.box_max, f"must exceed box_min {self.box_min} in x, y and z")
        for f in ("axis", "normal"):
            v = getattr(self, f)
            if v is not None and math.hypot(*v) == 0:
                raise GeometryError(f, v, "must be a non-zero vector")
        if self.span is not None and not self.span[0] < self.span[1]:
            raise GeometryError("span", self.span, "must be [start, end] with start < end (m along the axis)")
        if self.outer_radius is not None and not self.outer_radius > self.radius:
            raise GeometryError("outer_radius", self.outer_radius, f"must exceed radius {self.radius} m")


def file_sha256(path: Path) -> str:
    """SHA-256 (hex) of the bytes of a file."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


@dataclass(frozen=True)
class PartFile:
    """A component read from the user's file (see the module docstring).

    file : the CAD (.step/.stp/.brep) or volume-mesh (.msh/.inp/.bdf/.vtu, ...) file; a
        relative path is relative to the current folder (a scene resolves it against the
        scene file's folder before it gets here).
    units : length unit of the file's coordinates (:data:`UNITS`); see the module docstring.
    interfaces : the interface rules, in master order (none: a free part, e.g. to check the FE
        model; a scene attaches springs to interfaces only).
    volumes : a file of several volumes is refused ("refuse", default) or fused into one
        part ("fuse": the volumes must touch).
    order : a mesh file's element order: None (as in the file), 2 (lift a linear mesh to
        P2) or 1 (keep a linear mesh linear); see the module docstring.
    axis : the part's rotation axis in the file's axes (default z).
    origin : the point of ``axis`` that becomes the local origin (m, the file's axes).
    content_sha256 : SHA-256 of the file's bytes, read on construction (the cache key).
    """

    file: str
    interfaces: tuple[InterfaceRule, ...] = ()
    units: Optional[str] = None
    volumes: Literal["refuse", "fuse"] = "refuse"
    order: Optional[Literal[1, 2]] = None
    axis: _POINT = quantity("", default=(0.0, 0.0, 1.0), abs_lt=1e6)
    origin: _POINT = quantity(**_LEN, default=(0.0, 0.0, 0.0))
    content_sha256: str = field(default="", init=False)

    def __post_init__(self) -> None:
        if not isinstance(self.file, (str, os.PathLike)) or not str(self.file).strip():
            raise PartFileError("file", self.file, "must be the path of a CAD or mesh file")
        path = Path(self.file).expanduser()
        if path.suffix.lower() not in CAD_SUFFIXES + MESH_SUFFIXES:
            raise PartFileError("file", str(self.file), f"{path.name}: unknown file type {path.suffix!r}; "
                                f"CAD {', '.join(CAD_SUFFIXES)} or mesh {', '.join(MESH_SUFFIXES)}")
        try:
            sha = file_sha256(path)
        except OSError as exc:
            raise PartFileError("file", str(self.file), f"cannot read: {exc.strerror or exc}") from None
        object.__setattr__(self, "file", str(path.absolute()))
        object.__setattr__(self, "content_sha256", sha)
        if self.units is not None and self.units not in UNITS:
            raise PartFileError("units", self.units, f"{path.name}: must be one of {list(UNITS)}")
        if self.units is None and self.is_mesh:
            raise PartFileError("units", None, f"{path.name}: a mesh file carries no length unit: "
                                               f"give units (one of {list(UNITS)})")
        if self.volumes not in ("refuse", "fuse"):
            raise PartFileError("volumes", self.volumes, "must be 'refuse' or 'fuse'")
        for f in ("axis", "origin"):
            if isinstance(getattr(self, f), list):
                object.__setattr__(self, f, tuple(getattr(self, f)))
        for f in ("axis", "origin"):
            v = getattr(self, f)
            if not isinstance(v, tuple) or len(v) != 3:
                raise PartFileError(f, v, f"{path.name}: must be 3 numbers (x, y, z)")
        problem = first_problem(self)
        if problem is not None:
            raise PartFileError(problem[0], problem[1], f"{path.name}: {problem[2]}")
        if math.hypot(*self.axis) == 0:
            raise PartFileError("axis", self.axis, f"{path.name}: must be a non-zero vector (the part's rotation "
                                                   "axis in the file's axes)")
        if self.order is not None and (isinstance(self.order, bool) or self.order not in (1, 2)):
            raise PartFileError("order", self.order, f"{path.name}: must be 1 or 2")
        if self.order is not None and not self.is_mesh:
            raise PartFileError("order", self.order, f"{path.name}: a CAD part is meshed at the body's flex order; "
                                                     "order applies to mesh files")
        if not isinstance(self.interfaces, tuple):
            object.__setattr__(self, "interfaces", tuple(self.interfaces))
        seen = {}
        for i, rule in enumerate(self.interfaces):
            if not isinstance(rule, InterfaceRule):
                raise PartFileError(f"interfaces[{i}]", rule, "must be an interface rule table")
            if rule.name in seen:
                raise PartFileError(f"interfaces[{i}].name", rule.name,
                                    f"{path.name}: already the name of interfaces[{seen[rule.name]}]")
            seen[rule.name] = i
            if rule.select == "group" and not self.is_mesh:
                raise PartFileError(f"interfaces[{i}].select", "group",
                                    f"{path.name}: a CAD file has no reliable face names: select by "
                                    "cylinder, plane or box")

    @property
    def path(self) -> Path:
        return Path(self.file)

    @property
    def is_mesh(self) -> bool:
        """True for a volume-mesh file, False for a CAD file."""
        return Path(self.file).suffix.lower() in MESH_SUFFIXES

    @property
    def scale(self) -> float | None:
        """Metres per file unit, or None (a STEP file's own declared unit)."""
        if self.units is not None:
            return UNITS[self.units]
        suffix = Path(self.file).suffix.lower()
        return None if suffix in (".step", ".stp") else UNITS["mm"]

    def cache_identity(self) -> dict:
        """What identifies the part's geometry for the caches (:func:`params_digest`): the
        file's content (not its name or folder), the unit and the rules."""
        return {"content_sha256": self.content_sha256, "units": self.units, "volumes": self.volumes,
                "interfaces": list(self.interfaces), "order": self.order, "axis": self.axis,
                "origin": self.origin, "reader": PART_READER_VERSION}

    def rule(self, name: str) -> tuple[int, InterfaceRule]:
        for i, r in enumerate(self.interfaces):
            if r.name == name:
                return i, r
        raise KeyError(name)

