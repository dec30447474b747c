"""A user's part file that cannot be used is refused in one line naming the
file and the problem, exit code 2: open shells, non-manifold or multi-volume geometry (fuse
or refuse, and which), inverted or degenerate elements in a mesh file, units that make the
part absurdly large or small, a part that does not reach an interface's master, and the
rules' own mistakes (a rule selecting nothing, two rules on one face, a missing group, ...).

Every bad file is made here (gmsh OCC for STEP, in mm: gmsh writes STEP declaring mm;
meshio for mesh files, in m). Each class is checked on the Python side (the
:class:`PartFileError`'s field and message; ``build_component`` leaves nothing in the mesh
cache) and through the command line on a small scene (exit 2, one line on stderr naming
the file, nothing new in the cache folder). A fuzz test feeds random interface-rule tables
for the committed carrier_windows.step through the scene schema: each is refused naming a
field, or read, or refused by the part reader; never any other exception.

Mesh files as other tools write them: MED files in VTK's order, Nastran
decks breaking the format's rules (a GRID in another coordinate system, INCLUDE, a missing
GRID, a CTETRA of 7 nodes, an over-long free-field line, a GRID twice, a bad number), other
volume cells beside the tetrahedra, order = 1 on a quadratic file: refused as above. Fuzzed
through the API and (one case in four) ``flexgear part``: MED files with random node orders
(24), Nastran decks in random field formats and continuation styles (24), meshes with random
extra cells (30), random part axes and origins (24)."""
from __future__ import annotations

import collections
import itertools
import json
import math
import os
import random
import subprocess
import sys
import types
from dataclasses import dataclass, field
from pathlib import Path

import meshio
import numpy as np
import pytest

from assembly.errors import SceneError
from assembly.scene.schema import SCENE_DIR, from_dict
from fe_components.fe_model import build_component
from fe_components.gmsh_session import gmsh_model
from fe_components.part.cad import step_length_unit
from fe_components.part.file import SIZE_RANGE, InterfaceRule, PartFile, PartFileError
from fe_components.part.read import part_geometry
from tests.support.fuzz import examples

REPO = Path(__file__).resolve().parents[2]
CARRIER_STEP = SCENE_DIR / "parts" / "carrier_windows.step"
R_PIN = 0.09777438348018569  # m: the stage's carrier radius the carrier was drawn for

BOX_MM = (40.0, 30.0, 20.0)            # mm: the good CAD box, x, y, z from the origin
BOX_M = tuple(x * 1e-3 for x in BOX_MM)
BIG_MM = (200.0, 150.0, 100.0)         # mm: read as metres it is 269.3 m across (> 100 m)
TINY_MM = (0.2, 0.1, 0.15)             # mm: 0.2693 mm across (< 1 mm)
CUBE = 0.1                             # m: edge of the mesh files' cube
#: The cube split into 5 tetrahedra (corner indices of the cube's 8 corners below), all positive.
CUBE_CORNERS = CUBE * np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                                [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
CUBE_TETS = np.array([[0, 1, 3, 4], [1, 2, 3, 6], [1, 3, 4, 6], [1, 4, 5, 6], [3, 4, 6, 7]])
#: Edges of a tetrahedron in meshio's tetra10 order (midside nodes 4..9).
TET_EDGES = ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3))


def _tet_volumes(points, tets):
    p = points[tets[:, :4]]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6


def _tet10(shift: float):
    """The cube's 5 tetrahedra as tetra10, the midside node of edge (1, 4) (shared by 3 of
    them) moved by ``shift`` x CUBE along +y: the corners stay (every straight tetrahedron
    positive) while the curved element 2 folds. Measured with skfem's P2 mapping on element
    2, det J at the 4 stiffness quadrature points (order 2) and at 20000 random points:
    shift 1 -> +-8.9e-4 (both signs; negative at 49 % of the points), shift 2 -> all 4
    negative (-2.1e-4, -3.8e-3; negative at 84 % of the points: turned inside out)."""
    pts, cells, mids = list(CUBE_CORNERS), [], {}
    for t in CUBE_TETS:
        c = list(t)
        for a, b in TET_EDGES:
            key = tuple(sorted((int(t[a]), int(t[b]))))
            if key not in mids:
                mids[key] = len(pts)
                pts.append((CUBE_CORNERS[key[0]] + CUBE_CORNERS[key[1]]) / 2)
            c.append(mids[key])
        cells.append(c)
    pts = np.array(pts)
    pts[mids[(1, 4)]] += shift * CUBE * np.array([0.0, 1.0, 0.0])
    return pts, np.array(cells)


@pytest.fixture(scope="module")
def bad(tmp_path_factory) -> Path:
    """Folder holding every bad (and the few good) files of this module."""
    d = tmp_path_factory.mktemp("part-input")
    _cad_files(d)
    _mesh_files(d)
    (d / "part.stl").write_text("solid x\nendsolid x\n")
    for f in d.glob("*.step"):
        assert step_length_unit(f)[1] == 1e-3, f  # gmsh declares mm
    return d


def _cad_files(d: Path) -> None:
    with gmsh_model("cad-files") as gmsh:
        def write(name, build):
            gmsh.model.add(name)
            build(gmsh.model.occ)
            gmsh.model.occ.synchronize()
            gmsh.write(str(d / name))
            gmsh.model.remove()

        def open_shell(occ):  # the box's 6 faces, its volume removed
            v = occ.addBox(0, 0, 0, *BOX_MM)
            occ.synchronize()
            occ.remove([(3, v)])

        write("box.step", lambda occ: occ.addBox(0, 0, 0, *BOX_MM))
        write("open_shell.step", open_shell)
        write("two_faces.step", lambda occ: (occ.addRectangle(0, 0, 0, *BOX_MM[:2]),
                                             occ.addRectangle(0, 0, BOX_MM[2], *BOX_MM[:2])))
        write("two_boxes.step", lambda occ: (occ.addBox(0, 0, 0, *BOX_MM),
                                             occ.addBox(2.5 * BOX_MM[0], 0, 0, *BOX_MM)))  # 60 mm apart
        write("touching_boxes.step", lambda occ: (occ.addBox(0, 0, 0, *BOX_MM),
                                                  occ.addBox(BOX_MM[0], 0, 0, *BOX_MM)))  # share x = 40 mm
        write("box_and_face.step", lambda occ: (occ.addBox(0, 0, 0, *BOX_MM),
                                                occ.addRectangle(0, 0, 2.5 * BOX_MM[2], *BOX_MM[:2])))
        write("big_box.step", lambda occ: occ.addBox(0, 0, 0, *BIG_MM))
        write("tiny_box.step", lambda occ: occ.addBox(0, 0, 0, *TINY_MM))

        # a P1 mesh file with physical groups: the cube, faces x = 0 and x = CUBE
        gmsh.model.add("groups")
        occ = gmsh.model.occ
        v = occ.addBox(0, 0, 0, CUBE, CUBE, CUBE)
        occ.synchronize()
        for _, tag in gmsh.model.getEntities(2):
            x = occ.getCenterOfMass(2, tag)[0]
            for name, x0 in (("end_a", 0.0), ("end_b", CUBE)):
                if abs(x - x0) < 1e-12:
                    gmsh.model.addPhysicalGroup(2, [tag], name=name)
        gmsh.model.addPhysicalGroup(3, [v], name="solid")
        gmsh.option.setNumber("Mesh.MeshSizeMax", CUBE / 2)
        gmsh.option.setNumber("Mesh.ElementOrder", 1)
        gmsh.model.mesh.generate(3)
        gmsh.write(str(d / "groups.msh"))
        gmsh.model.remove()


def _mesh_files(d: Path) -> None:
    P, T = CUBE_CORNERS, CUBE_TETS
    assert (_tet_volumes(P, T) > 0).all() and _tet_volumes(P, T).sum() == pytest.approx(CUBE**3, rel=1e-12)
    meshio.write(d / "cube.vtu", meshio.Mesh(P, [("tetra", T)]))
    inverted = T.copy()
    inverted[2, [0, 1]] = inverted[2, [1, 0]]              # element 2: two nodes swapped
    meshio.write(d / "inverted.inp", meshio.Mesh(P, [("tetra", inverted)]))
    flat = np.vstack([P, [[CUBE / 2, CUBE / 2, 0.0]]])      # node 8 in the plane z = 0 ...
    meshio.write(d / "degenerate.vtu", meshio.Mesh(flat, [("tetra", np.vstack([T, [[0, 1, 2, 8]]]))]))  # ... flat tet
    meshio.write(d / "hexahedra.vtu", meshio.Mesh(P, [("hexahedron", np.arange(8)[None])]))
    surface = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                        [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])
    meshio.write(d / "surface.vtu", meshio.Mesh(P, [("triangle", surface)]))
    p10, t10 = _tet10(0.0)
    meshio.write(d / "mixed_order.vtu", meshio.Mesh(p10, [("tetra", T[:2]), ("tetra10", t10[2:])]))
    meshio.write(d / "cube_in_mm.vtu", meshio.Mesh(P * 1e3, [("tetra", T)]))
    (d / "not_a_mesh.msh").write_text("this is not a mesh\n")
    for shift, name in ((1.0, "folded_p2.vtu"), (2.0, "inside_out_p2.vtu")):
        p, t = _tet10(shift)
        assert (_tet_volumes(p, t) > 0).all()  # the straight elements are fine
        meshio.write(d / name, meshio.Mesh(p, [("tetra10", t)]))
    meshio.write(d / "cube_p2.vtu", meshio.Mesh(p10, [("tetra10", t10)]))
    # MED written in VTK's node order (as meshio writes any mesh it did not read from MED)
    meshio.write(d / "cube_vtk_order.med", meshio.Mesh(P, [("tetra", T)]), file_format="med")
    wedge = np.array([[0, 1, 3, 4, 5, 7]])
    meshio.write(d / "tets_and_wedge.vtu", meshio.Mesh(P, [("tetra", T), ("wedge", wedge)]))
    grids = [f"GRID,{i + 1},,{x!r},{y!r},{z!r}" for i, (x, y, z) in enumerate(P.tolist())]
    tetras = [f"CTETRA,{e + 1},1," + ",".join(str(n + 1) for n in t) for e, t in enumerate(T)]
    decks = {
        "grid_in_cp.bdf": grids[:3] + ["GRID,4,3,0.,0.1,0."] + grids[4:] + tetras,
        "include.bdf": ["INCLUDE 'more.bdf'"] + grids + tetras,
        "missing_grid.bdf": grids + tetras[:-1] + ["CTETRA,5,1,4,5,7,99"],
        "seven_nodes.bdf": grids + tetras[:-1] + ["CTETRA,5,1,4,5,7,8,1,2", ",3"],
        "long_free_line.bdf": grids + tetras[:-1] + ["CTETRA,5,1,4,5,7,8,,,,,,,,1"],
        "grid_twice.bdf": grids + grids[:1] + tetras,
        "not_a_number.bdf": grids[:-1] + ["GRID,8,,0.,0.1,1.0.1"] + tetras,
    }
    for name, lines in decks.items():
        (d / name).write_text("BEGIN BULK\n" + "\n".join(lines) + "\nENDDATA\n")


# ------------------------------------------------------------------ the classes of bad input
def plane(name, x, **kw) -> dict:
    return {"name": name, "select": "plane", "point": [x, 0.0, 0.0], "normal": [1.0, 0.0, 0.0], **kw}


BOX_ENDS = [plane("end_a", 0.0), plane("end_b", BOX_M[0])]
CUBE_ENDS = [plane("end_a", 0.0), plane("end_b", CUBE)]


@dataclass(frozen=True)
class Case:
    """A bad input: the file (in the ``bad`` folder), the PartFile's other fields, and the
    error: its field (``PartFileError.parameter``) and what the message must say."""

    id: str
    file: str
    parameter: str
    says: tuple
    units: str | None = None
    volumes: str | None = None
    rules: list = field(default_factory=lambda: BOX_ENDS)
    xfail: str | None = None  # a library bug the case finds (reported)
    order: int | None = None

    def part(self, d: Path) -> PartFile:
        kw = {"volumes": self.volumes} if self.volumes else {}
        return PartFile(str(d / self.file), rules(self.rules), units=self.units, order=self.order, **kw)


def rules(tables) -> tuple:
    """InterfaceRules of rule tables (arrays as tuples, as the scene reader makes them)."""
    return tuple(InterfaceRule(**{k: tuple(v) if isinstance(v, list) else v for k, v in t.items()}) for t in tables)


SIZE_TEXT = f"not a drivetrain part ({SIZE_RANGE[0]:g} to {SIZE_RANGE[1]:g} m)"
CASES = [
    # CAD geometry
    Case("open-shell", "open_shell.step", "file", ("an open shell", "6 faces and no closed volume")),
    Case("open-faces", "two_faces.step", "file", ("an open shell", "2 faces and no closed volume")),
    Case("two-volumes", "two_boxes.step", "volumes", ("2 separate volumes", "volumes = 'fuse'")),
    Case("two-volumes-fused-apart", "two_boxes.step", "volumes",
         ("fusing its 2 volumes leaves 2 separate parts", "do not all touch"), volumes="fuse"),
    Case("touching-volumes-refused", "touching_boxes.step", "volumes", ("2 separate volumes",)),
    Case("loose-face", "box_and_face.step", "file", ("non-manifold", "1 face(s) bound no volume")),
    # sqrt(200^2 + 150^2 + 100^2) = 269.26 "m"; sqrt(0.2^2 + 0.1^2 + 0.15^2) = 0.26926 mm
    Case("huge-units", "big_box.step", "units", ("269.3 m across", SIZE_TEXT, "did you mean units = 'mm'"),
         units="m", rules=[plane("end_a", 0.0), plane("end_b", 200.0)]),
    Case("tiny-part", "tiny_box.step", "units", ("0.0002693 m across", SIZE_TEXT)),
    # mesh files
    Case("inverted-tet", "inverted.inp", "file", ("1 of 5 tetrahedra are inverted (negative volume)", "element 2"),
         units="m", rules=CUBE_ENDS),
    Case("degenerate-tet", "degenerate.vtu", "file", ("1 of 6 tetrahedra are degenerate (zero volume)", "element 5"),
         units="m", rules=CUBE_ENDS),
    Case("hexahedra", "hexahedra.vtu", "file", ("['hexahedron']", "only tetrahedra"), units="m", rules=CUBE_ENDS),
    Case("surface-mesh", "surface.vtu", "file", ("no volume elements",), units="m", rules=CUBE_ENDS),
    Case("mixed-order", "mixed_order.vtu", "file", ("['tetra', 'tetra10']", "of one order"), units="m",
         rules=CUBE_ENDS),
    # meshio's gmsh reader calls sys.exit on it: read as gmsh only, SystemExit caught
    Case("not-a-mesh", "not_a_mesh.msh", "file", ("cannot read as a mesh",), units="m", rules=CUBE_ENDS),
    # sqrt(3) x 100 = 173.2 "m"
    Case("mesh-huge-units", "cube_in_mm.vtu", "units", ("173.2 m across", "did you mean units = 'mm'"), units="m",
         rules=CUBE_ENDS),
    Case("mesh-without-units", "cube.vtu", "units", ("carries no length unit",), rules=CUBE_ENDS),
    # the rules
    Case("rule-selects-nothing", "box.step", "interfaces[1]", ("interface 'mid' selects no face",),
         rules=[plane("end_a", 0.0), plane("mid", BOX_M[0] / 2)]),
    Case("rules-overlap", "box.step", "interfaces[1]",
         ("interface 'all' selects face", "already selected by interfaces[0] ('end_a')"),
         rules=[plane("end_a", 0.0), {"name": "all", "select": "box", "box_min": [-1.0, -1.0, -1.0],
                                      "box_max": [1.0, 1.0, 1.0]}]),
    # the face x = 0 spans z in [0, 0.02] m: a master at z = 1 m is 0.98 m from it (> a tenth of 0.054 m)
    Case("master-unreached", "box.step", "interfaces[0].master",
         ("does not reach the master of interface 'end_a'", "0.98 m from the interface's faces"),
         rules=[plane("end_a", 0.0, master=[0.0, BOX_M[1] / 2, 1.0]), plane("end_b", BOX_M[0])]),
    Case("missing-group", "groups.msh", "interfaces[1].group", ("no such group; the file has ['end_a', 'end_b']",),
         units="m", rules=[{"name": "end_a", "select": "group", "group": "end_a"},
                           {"name": "end_c", "select": "group", "group": "end_c"}]),
    Case("group-on-step", "box.step", "interfaces[0].select", ("a CAD file has no reliable face names",),
         rules=[{"name": "end_a", "select": "group", "group": "end_a"}, plane("end_b", BOX_M[0])]),
    Case("missing-file", "no_such_part.step", "file", ("cannot read", "No such file")),
    Case("unknown-suffix", "part.stl", "file", ("unknown file type '.stl'",)),
    # mesh files from other tools: a format's rules broken, volume cells that cannot be a part
    Case("med-in-vtk-order", "cube_vtk_order.med", "file",
         ("5 of 5 tetrahedra are inverted", "read in MED's node order", "written in another order"), units="m",
         rules=CUBE_ENDS),
    Case("tets-and-wedge", "tets_and_wedge.vtu", "file", ("['tetra', 'wedge']", "only tetrahedra"), units="m",
         rules=CUBE_ENDS),
    Case("nastran-grid-in-cp", "grid_in_cp.bdf", "file", ("line 5: GRID 4", "coordinate system CP = 3",
                                                          "export in it"), units="m", rules=CUBE_ENDS),
    Case("nastran-include", "include.bdf", "file", ("line 2: INCLUDE is not read",), units="m", rules=CUBE_ENDS),
    Case("nastran-missing-grid", "missing_grid.bdf", "file", ("CTETRA 5 names GRID 99",), units="m",
         rules=CUBE_ENDS),
    Case("nastran-seven-nodes", "seven_nodes.bdf", "file", ("CTETRA 5: 7 grid points", "4, or 10"), units="m",
         rules=CUBE_ENDS),
    Case("nastran-long-free-line", "long_free_line.bdf", "file", ("line 14: more than 10 comma-separated fields",),
         units="m", rules=CUBE_ENDS),
    Case("nastran-grid-twice", "grid_twice.bdf", "file", ("line 10: GRID 1 is defined twice",), units="m",
         rules=CUBE_ENDS),
    Case("nastran-not-a-number", "not_a_number.bdf", "file", ("line 9: '1.0.1' is not a number",), units="m",
         rules=CUBE_ENDS),
    Case("order-1-on-p2", "cube_p2.vtu", "order", ("holds quadratic tetrahedra (tetra10)", "leave order out"),
         units="m", rules=CUBE_ENDS, order=1),
]


def _read(case: Case, d: Path):
    return part_geometry(case.part(d))


CASE_PARAMS = [pytest.param(c, id=c.id, marks=[pytest.mark.xfail(strict=True, reason=c.xfail)] if c.xfail else [])
               for c in CASES]


def _files(folder: Path) -> set:
    """Every file under ``folder`` (relative paths), folders left out."""
    return {p.relative_to(folder) for p in folder.rglob("*") if not p.is_dir()} if folder.exists() else set()


@pytest.mark.parametrize("case", CASE_PARAMS)
def test_bad_part_is_refused_naming_the_file_and_the_problem(case, bad):
    with pytest.raises(PartFileError) as err:
        _read(case, bad)
    assert err.value.parameter == case.parameter
    message = str(err.value)
    assert Path(case.file).name in message
    for text in case.says:
        assert text in message, message
    assert "\n" not in message


@pytest.mark.parametrize("case", CASE_PARAMS)
def test_bad_part_leaves_nothing_in_the_mesh_cache(case, bad, tmp_path):
    """Meshing (or converting) a bad part: the same error, and no file in the cache (the
    mesh size given, so that the build gets as far as the mesh cache)."""
    cache = tmp_path / "cache"
    with pytest.raises(PartFileError) as err:
        build_component(case.part(bad), mesh_size=0.01, cache_dir=cache)  # m: any size, nothing is meshed
    assert err.value.parameter == case.parameter
    assert _files(cache) == set()


def test_touching_volumes_are_fused_on_request(bad):
    """The refused pair of touching boxes is one part with volumes = "fuse": the union of
    two 40 x 30 x 20 mm boxes, 2 x 24000 mm^3 (OpenCASCADE's volume: exact for boxes)."""
    geo = part_geometry(PartFile(str(bad / "touching_boxes.step"), volumes="fuse"))
    assert geo.volume == pytest.approx(2 * math.prod(BOX_M), rel=1e-9)
    assert np.allclose(geo.hi - geo.lo, (2 * BOX_M[0], BOX_M[1], BOX_M[2]), rtol=0, atol=1e-9)


def test_good_files_of_this_module_are_read(bad):
    """The references the bad files differ from are fine: the box, the cube mesh, the group file."""
    assert part_geometry(PartFile(str(bad / "box.step"), rules(BOX_ENDS))).volume \
        == pytest.approx(math.prod(BOX_M), rel=1e-9)
    assert part_geometry(PartFile(str(bad / "cube.vtu"), units="m")).volume == pytest.approx(CUBE**3, rel=1e-12)
    geo = part_geometry(PartFile(str(bad / "groups.msh"), (InterfaceRule("end_a", "group", group="end_a"),),
                                 units="m"))
    assert np.allclose(geo.interfaces[0].master, (0.0, CUBE / 2, CUBE / 2), atol=1e-12)  # the face's centre


@pytest.mark.parametrize("fields, parameter", [
    ({"units": "furlong"}, "units"),
    ({"interfaces": (InterfaceRule("a", "plane", point=(0.0, 0.0, 0.0), normal=(1.0, 0.0, 0.0)),
                     InterfaceRule("a", "plane", point=(0.04, 0.0, 0.0), normal=(1.0, 0.0, 0.0)))},
     "interfaces[1].name"),
    ({"units": None, "file_name": "cube.vtu"}, "units"),
    ({"file_name": "part.stl"}, "file"),
])
def test_every_part_file_error_names_the_file(fields, parameter, bad):
    fields = dict(fields)
    name = fields.pop("file_name", "box.step")
    with pytest.raises(PartFileError) as err:
        PartFile(str(bad / name), **fields)
    assert err.value.parameter == parameter
    assert name in str(err.value)


def test_rule_arrays_given_as_python_lists():
    """Arrays given as Python lists become tuples (a rule is hashable: the reader memoises on it)."""
    part = PartFile(str(CARRIER_STEP), (InterfaceRule("bearing_b", "cylinder", radius=0.045, span=[0.04, 0.08]),))
    assert part_geometry(part).interfaces[0].name == "bearing_b"


# --------------------------------------------------------------- folded second-order elements
def _folded_part(d: Path, name: str) -> PartFile:
    return PartFile(str(d / name), rules(CUBE_ENDS), units="m")


def test_folded_p2_element_is_refused_when_read(bad, tmp_path):
    """A tetra10 whose straight corners are fine but whose curved shape folds (det J of both
    signs) is refused on reading, before anything is written into the cache."""
    part = _folded_part(bad, "folded_p2.vtu")
    with pytest.raises(PartFileError) as err:
        build_component(part, cache_dir=tmp_path)
    assert err.value.parameter == "file"
    assert "folded_p2.vtu" in str(err.value) and "1 of 5 curved (P2) tetrahedra are folded" in str(err.value)
    assert list(tmp_path.iterdir()) == []


def test_p2_element_inside_out_is_refused(bad, tmp_path):
    """det J < 0 at all four quadrature points (no sign change there) is refused too."""
    with pytest.raises(PartFileError, match="inside_out_p2.vtu"):
        build_component(_folded_part(bad, "inside_out_p2.vtu"), cache_dir=tmp_path)


# ------------------------------------------------------------------------ the command line
def _toml(value) -> str:
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return repr(float(value))


def write_scene(d: Path, case_id: str, file: str, units=None, volumes=None, rules=(), order=None) -> Path:
    """A scene of one flexible body read from ``file`` (relative to the scene's folder ``d``),
    held by a bearing at each of its first two interfaces."""
    lines = ['name = "part input check"', "band_hz = 3000.0", "", "[[bodies]]", 'name = "part"',
             'fidelity = "flexible"', "[bodies.component]", 'kind = "file"', f"file = {_toml(file)}"]
    if units:
        lines.append(f"units = {_toml(units)}")
    if volumes:
        lines.append(f"volumes = {_toml(volumes)}")
    if order:
        lines.append(f"order = {order}")
    for r in rules:
        lines.append("[[bodies.component.interfaces]]")
        lines += [f"{k} = {_toml(v)}" for k, v in r.items()]
    for r in rules[:2]:
        lines += ["", "[[bearings]]", 'body = "part"', f"interface = {_toml(r['name'])}",
                  "k_radial = 1.0e8", "k_axial = 1.0e8", "k_tilt = 1.0e5"]
    path = d / f"scene-{case_id}.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def run_cli(scene: Path, cache: Path) -> types.SimpleNamespace:
    """``flexgear modes SCENE`` in a process of its own, the mesh cache in ``cache``; the
    files in the cache before and after."""
    cache.mkdir(parents=True, exist_ok=True)
    before = _files(cache)
    env = {**os.environ, "FLEXGEAR_CACHE_DIR": str(cache)}
    p = subprocess.run([sys.executable, "-m", "assembly.app.cli", "modes", str(scene)], capture_output=True,
                       text=True, env=env, cwd=REPO, timeout=300)
    return types.SimpleNamespace(returncode=p.returncode, stdout=p.stdout, stderr=p.stderr,
                                 new_files=_files(cache) - before)


def _one_error_line(run) -> str:
    assert run.returncode == 2, (run.stdout, run.stderr)
    lines = run.stderr.splitlines()
    assert len(lines) == 1, run.stderr
    assert lines[0].startswith("flexgear: error: ")
    return lines[0]


@pytest.mark.parametrize("case", CASE_PARAMS)
def test_cli_refuses_a_bad_part_in_one_line(case, bad, tmp_path):
    scene = write_scene(bad, case.id, case.file, case.units, case.volumes, case.rules, case.order)
    run = run_cli(scene, tmp_path / "cache")
    line = _one_error_line(run)
    assert line.startswith(f"flexgear: error: bodies[0].component.{case.parameter} = "), line
    assert Path(case.file).name in line
    for text in case.says:
        assert text in line, line
    assert run.stdout.strip() == ""  # no table (blank lines: see the test below)
    assert run.new_files == set()   # nothing meshed, nothing cached


def test_cli_reading_a_msh_part_prints_nothing_on_stdout(bad, tmp_path):
    case = next(c for c in CASES if c.id == "missing-group")
    run = run_cli(write_scene(bad, "stdout", case.file, case.units, case.volumes, case.rules), tmp_path / "cache")
    assert run.returncode == 2
    assert run.stdout == ""


@pytest.fixture(scope="module")
def folded_cli(bad, tmp_path_factory):
    """The command line on a scene whose mesh file has a folded P2 element."""
    scene = write_scene(bad, "folded-p2", "folded_p2.vtu", "m", None, CUBE_ENDS)
    return run_cli(scene, tmp_path_factory.mktemp("folded-cache"))


def test_cli_refuses_a_folded_p2_element_in_one_line(folded_cli):
    line = _one_error_line(folded_cli)
    assert "folded_p2.vtu" in line and "tetrahedra are folded or inverted" in line
    assert line.startswith("flexgear: error: bodies[0].component.file = ")


def test_cli_folded_p2_element_leaves_nothing_in_the_cache(folded_cli):
    assert folded_cli.new_files == set()


PIN_1 = "axis_point = [-0.048887191740092824, 0.08467509993320237, 0.0]"
PIN_1_MOVED = "axis_point = [-0.046887191740092824, 0.08467509993320237, 0.0]"  # 2 mm along x


@pytest.mark.parametrize("edit, says", [
    (f"{PIN_1}\nmaster = [-0.046887191740092824, 0.08467509993320237, 0.0]", "does not reach the planet"),
    # the bore (radius 15 mm) is 13..17 mm from the moved axis: a 2.5 mm tolerance finds it,
    # and the master, on the moved axis, is 2 mm from the planet
    (f"{PIN_1_MOVED}\ntolerance = 0.0025", "does not reach the planet"),
    (PIN_1_MOVED, "the cylinder rule of interface 'pin_1' selects no face of the part"),
], ids=["master-moved", "axis-moved-found", "axis-moved-lost"])
def test_cli_carrier_pin_off_its_planet(edit, says, tmp_path):
    """The shipped STEP carrier scene with pin_1 2 mm off planet 1's centre."""
    text = (SCENE_DIR / "planetary_step_carrier.toml").read_text()
    assert text.count(PIN_1) == 1 and text.count('file = "parts/carrier_windows.step"') == 1
    text = text.replace(PIN_1, edit).replace('file = "parts/carrier_windows.step"', f"file = {_toml(str(CARRIER_STEP))}")
    scene = tmp_path / "carrier.toml"
    scene.write_text(text)
    run = run_cli(scene, tmp_path / "cache")
    line = _one_error_line(run)
    assert line.startswith("flexgear: error: stages[0].carrier.component.interfaces[1] = 'pin_1': "), line
    assert "carrier_windows.step" in line and says in line
    if "planet" in says:
        assert "is 0.002 m from planet 1's centre" in line
    assert run.new_files == set()


# ------------------------------------------------------------------------------------ fuzz
PINS = [[R_PIN * math.cos(a), R_PIN * math.sin(a), 0.0] for a in (0.0, 2 * math.pi / 3, 4 * math.pi / 3)]
RADII = [0.015, 0.025, 0.04, 0.045, 0.02, 0.115, 0.135, 0.01, 1e-4]  # m: the carrier's bores and seats, others
ZS = [-0.07, -0.04, -0.025, 0.0, 0.025, 0.04, 0.08, 0.1]             # m: the carrier's faces, and between
BAD_NUMBERS = [math.nan, math.inf, -math.inf, -0.015, 0.0, 1e300, 1e-300, -1e7, True, "0.015", None, [0.01], {}]
REQUIRED = {"group": ("group",), "cylinder": ("radius",), "plane": ("point", "normal"), "box": ("box_min", "box_max")}
OPTIONAL = {"group": (), "cylinder": ("axis_point", "axis", "span", "outer_radius", "box_min", "box_max"),
            "plane": ("box_min", "box_max"), "box": ()}
KEYS = ("name", "select", "group", "axis_point", "axis", "radius", "outer_radius", "span", "point", "normal",
        "box_min", "box_max", "coupling", "master", "tolerance", "bogus")


def _plausible(rng, key):
    """A value of ``key`` that could select something on the carrier (m)."""
    if key in ("radius", "outer_radius"):
        return rng.choice(RADII)
    if key == "tolerance":
        return rng.choice([1e-6, 1e-5, 1e-3, 0.01, 0.5])
    if key in ("axis_point", "point"):
        return list(rng.choice(PINS + [[0.0, 0.0, z] for z in ZS]))
    if key in ("axis", "normal"):
        return rng.choice([[0.0, 0.0, 1.0], [0.0, 0.0, -2.0], [1.0, 0.0, 0.0], [0.0, 1.0, 1.0], [1e-90, 0.0, 1e-90]])
    if key == "span":
        return sorted(rng.sample(ZS, 2))
    if key == "box_min":
        return rng.choice([[-0.2, -0.2, -0.1], [0.0, -0.2, 0.03], [-0.01, -0.01, -0.01]])
    if key == "box_max":
        return rng.choice([[0.2, 0.2, 0.1], [0.2, 0.2, 0.09], [0.01, 0.01, 0.01]])
    if key == "master":
        return list(rng.choice(PINS + [[0.0, 0.0, 0.06], [5.0, 0.0, 0.0], [0.0, 0.0, 1e5]]))
    if key == "coupling":
        return rng.choice(["rbe2", "rbe3"])
    return "g"  # group


def _wrong(rng, key):
    """A value of ``key`` of the wrong type, not finite, negative, zero, huge or the wrong shape."""
    if key in ("radius", "outer_radius", "tolerance", "bogus"):
        return rng.choice(BAD_NUMBERS)
    if key in ("name", "select", "coupling", "group"):
        return rng.choice(["", " ", "sphere", "RBE2", 7, None, ["x"], "a/b"])
    base = list(_plausible(rng, key))
    k = rng.random()
    if k < 0.5:
        base[rng.randrange(len(base))] = rng.choice(BAD_NUMBERS)
        return base
    if k < 0.7:
        return [0.0] * len(base)  # a zero vector
    return rng.choice([base[:-1], base + [0.0], "x", 3.0, [], [base], {"x": 1}, [1e6] * len(base),
                       [-1e9] * len(base), base[::-1]])


def _random_rule_table(rng, i: int) -> dict:
    select = rng.choice(["cylinder", "cylinder", "plane", "box", "group"])
    t = {"name": f"itf{i}", "select": select}
    for k in REQUIRED[select]:
        if rng.random() < 0.95:
            t[k] = _plausible(rng, k)
    for k in OPTIONAL[select] + ("coupling", "master", "tolerance"):
        if rng.random() < 0.3:
            t[k] = _plausible(rng, k)
    if rng.random() < 0.1:  # a field the rule does not use
        k = rng.choice(KEYS[2:-1])
        t[k] = _plausible(rng, k)
    for _ in range(rng.choice([0, 0, 1, 1, 2])):
        k = rng.choice(KEYS)
        t[k] = _wrong(rng, k)
    return t


RULE_FIELDS = {"name", "select", "group", "axis_point", "axis", "radius", "outer_radius", "span", "point",
               "normal", "box_min", "box_max", "coupling", "master", "tolerance", "bogus"}


def test_fuzz_interface_rules_on_the_carrier():
    """Random interface-rule tables (seeded) for the committed carrier STEP, read as a scene
    reads a component table: a SceneError naming a field of the rule, or the part read, or a
    PartFileError of the rule naming the file; never another exception."""
    rng = random.Random(16)
    outcomes = collections.Counter()
    for i in range(examples(200)):
        table = _random_rule_table(rng, i)
        try:
            part = from_dict(PartFile, {"file": str(CARRIER_STEP), "interfaces": [table]}, "component")
        except SceneError as err:
            assert err.path.startswith("component.interfaces[0]"), (table, err)
            key = err.path.removeprefix("component.interfaces[0]").lstrip(".").split("[")[0]
            assert key in RULE_FIELDS or key == "", (table, err)
            outcomes["refused by the schema"] += 1
            continue
        except Exception as exc:  # noqa: BLE001 -- the point of the test
            pytest.fail(f"{table}: {type(exc).__name__}: {exc}")
        try:
            geo = part_geometry(part)
        except PartFileError as err:
            assert err.parameter.startswith("interfaces[0]"), (table, err)
            assert "carrier_windows.step" in str(err), (table, err)
            outcomes["refused by the reader"] += 1
            continue
        except Exception as exc:  # noqa: BLE001
            pytest.fail(f"{table}: {type(exc).__name__}: {exc}")
        (itf,) = geo.interfaces
        assert len(itf.face_ids) > 0 and np.isfinite(itf.master).all(), table
        outcomes["read"] += 1
    # the draw reaches every outcome (seeded: the same tables every run)
    assert set(outcomes) == {"refused by the schema", "refused by the reader", "read"}, outcomes


# ------------------------------------------------------- fuzz: mesh files from other tools
#: The cube's 5 tetrahedra, P1 and P2, as the fuzz's known mesh: volume CUBE^3, and the
#: straight elements' mass properties as the reference every variant must reproduce.
def _cube_mesh(order: int):
    if order == 1:
        return CUBE_CORNERS, CUBE_TETS
    return _tet10(0.0)


def _reference(order: int, d: Path):
    """The cube read from a plain .vtu: what every variant of the fuzz must give."""
    pts, tets = _cube_mesh(order)
    path = _write(d, f"ref{order}.vtu", pts, [("tetra" if order == 1 else "tetra10", tets)])
    return part_geometry(PartFile(path, units="m", order=1 if order == 1 else None))


@pytest.fixture(scope="module")
def fuzz_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz-files")


def _write(d: Path, name: str, pts, cells, **kw) -> str:
    path = d / name
    meshio.write(path, meshio.Mesh(pts, cells, **kw))
    return str(path)


def _same_geometry(geo, ref, what) -> None:
    """The part read is the reference cube: volume, centroid, inertia and box to 1e-12."""
    assert geo.volume == pytest.approx(ref.volume, rel=1e-12), what
    assert np.abs(geo.centroid - ref.centroid).max() < 1e-12 * CUBE, what
    assert np.abs(geo.inertia_per_density - ref.inertia_per_density).max() \
        < 1e-12 * np.abs(ref.inertia_per_density).max(), what


def _cli_json(argv, capsys) -> dict:
    """``flexgear part ... --json`` in this process: exit 0 and its JSON."""
    from assembly.app.cli import main
    code = main(["part", *map(str, argv), "--json", "--modes", "1"])
    out = capsys.readouterr()
    assert code == 0, out.err
    return json.loads(out.out)


def _cli_refused(argv, capsys) -> str:
    from assembly.app.cli import main
    assert main(["part", *map(str, argv)]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("flexgear: error: "), err
    return err


def test_fuzz_med_node_orders(fuzz_dir, capsys):
    """MED files of the cube whose tetrahedra are numbered from random corners (the edge
    nodes following): an even permutation of a MED element is the same element, read as the
    cube; an odd one is the mirror image, refused as inverted, counted. P1 and P2; through the
    Python API and (one in four) the command line."""
    from tests.support.mesh_writers import med_order, renumbered, write_med

    rng = random.Random(261)
    perms = list(itertools.permutations(range(4)))
    outcomes = collections.Counter()
    for case in range(examples(24)):
        order = rng.choice([1, 2])
        pts, tets = _cube_mesh(order)
        med = med_order(pts, tets)
        odd = np.array([rng.random() < 0.15 for _ in med])
        cells = np.array([renumbered(t, rng.choice([p for p in perms if _parity(p) == int(o)]))
                          for t, o in zip(med, odd)])
        path = fuzz_dir / f"med{case}.med"
        write_med(path, pts, cells)
        part = PartFile(str(path), units="m")
        cli = case % 4 == 0
        if odd.any():
            with pytest.raises(PartFileError) as err:
                part_geometry(part)
            assert f"{odd.sum()} of 5 tetrahedra are inverted" in str(err.value), (case, str(err.value))
            if cli:
                assert f"{odd.sum()} of 5 tetrahedra are inverted" in _cli_refused([path, "--units", "m"], capsys)
            outcomes["refused: mirrored elements"] += 1
            continue
        geo = part_geometry(part)
        _same_geometry(geo, _reference(order, fuzz_dir), case)
        assert geo.read.solid == ("tetra" if order == 1 else "tetra10") and geo.read.n_solid == 5
        if cli:
            j = _cli_json([path, "--units", "m", "--order", "2"], capsys)
            assert j["fe"]["mass_kg"] == pytest.approx(7850.0 * CUBE ** 3, rel=1e-12) and j["n_rigid"] == 6
        outcomes["read"] += 1
    assert set(outcomes) == {"read", "refused: mirrored elements"}, outcomes


def _parity(p) -> int:
    """0 for an even permutation, 1 for an odd one."""
    p, n = list(p), 0
    for i in range(len(p)):
        while p[i] != i:
            j = p[i]
            p[i], p[j] = p[j], p[i]
            n += 1
    return n % 2


def test_fuzz_nastran_field_formats_and_continuations(fuzz_dir, capsys):
    """Decks of the cube with every card in a random field format and continuation style
    (GRID free or large with implicit exponents; CTETRA free with + or blank continuations,
    small with markers or a blank first field after a stripped or padded line, large), comments
    and blank lines between cards, random tetrahedra left-handed, with or without BEGIN BULK:
    read as the cube, the left-handed ones counted as renumbered. API, and one in four through
    the command line."""
    from tests.support.mesh_writers import nastran_deck

    rng = random.Random(262)
    for case in range(examples(24)):
        order = rng.choice([1, 2])
        pts, tets = _cube_mesh(order)
        flipped = [rng.random() < 0.4 for _ in tets]
        path = fuzz_dir / f"deck{case}.{rng.choice(['bdf', 'nas'])}"
        path.write_text(nastran_deck(pts, tets, rng=rng, flipped=flipped, header=rng.random() < 0.7))
        geo = part_geometry(PartFile(str(path), units="m"))
        _same_geometry(geo, _reference(order, fuzz_dir), case)
        assert geo.read.renumbered == sum(flipped) and geo.read.n_solid == 5, case
        if case % 4 == 0:
            j = _cli_json([path, "--units", "m"], capsys)
            assert j["read"]["renumbered"] == sum(flipped) and j["order"] == order


#: Extra cells a file may hold, by what the reader must make of them: (meshio type, cells of
#: the cube's 8 corners (0..7) or of the 3 extra nodes (8..10), kind in the summary).
_EXTRA = [
    ("triangle", [[0, 3, 1]], "boundary face"),        # the z = 0 face of tetrahedron 0 (0, 1, 3, 4)
    ("triangle", [[8, 9, 10]], "surface"),              # a sheet of nodes of no tetrahedron
    ("triangle", [[0, 1, 6]], "surface"),               # through the cube: no face of the 5 tetrahedra
    ("quad", [[0, 1, 2, 3]], "surface"),                # the z = 0 square: no tetrahedron face is a quad
    ("line", [[0, 1]], "boundary edge"),
    ("line", [[0, 6]], "line"),                         # the cube's main diagonal: inside it
    ("vertex", [[7]], "boundary node"),
    ("vertex", [[9]], "point"),
]


def test_fuzz_extra_cells_are_counted(fuzz_dir, capsys):
    """The P1 cube with random extra cells (boundary faces, edges and nodes, sheets, quads,
    lines through it, points off it): the summary counts each kind exactly, warns if and only
    if something besides boundary tags is left out; a volume cell other than a tetrahedron
    added is refused. API, and one in four through the command line."""
    rng = random.Random(263)
    extra_pts = np.array([[0.5, 0.5, 2.0], [0.7, 0.5, 2.0], [0.5, 0.8, 2.0]]) * CUBE
    pts = np.vstack([CUBE_CORNERS, extra_pts])
    faces = collections.Counter(tuple(sorted(t[list(f)])) for t in CUBE_TETS
                                for f in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)))
    assert faces[(0, 1, 3)] == 1 and faces[(0, 1, 6)] == 0   # the table's claims: a boundary face, no face
    outcomes = collections.Counter()
    for case in range(examples(30)):
        picks = [rng.choice(_EXTRA) for _ in range(rng.randint(0, 5))]
        cells = [("tetra", CUBE_TETS)] + [(t, np.array(c)) for t, c, _ in picks]
        volume = rng.random() < 0.15
        if volume:
            cells.append(rng.choice([("hexahedron", np.arange(8)[None]), ("wedge", np.array([[0, 1, 3, 4, 5, 7]])),
                                     ("pyramid", np.array([[0, 1, 2, 3, 6]]))]))
        path = _write(fuzz_dir, f"extra{case}.vtu", pts, cells)
        if volume:
            with pytest.raises(PartFileError) as err:
                part_geometry(PartFile(path, units="m"))
            assert "only tetrahedra" in str(err.value) and cells[-1][0] in str(err.value)
            outcomes["refused"] += 1
            continue
        read = part_geometry(PartFile(path, units="m", order=1)).read
        want = collections.Counter()
        for t, c, kind in picks:
            want[(t, kind)] += 1
        got = {(c.name, c.kind): c.count for c in read.dropped}
        assert got == dict(want), (case, picks, read.text())
        assert bool(read.left_out) == any(not k.startswith("boundary") for _, _, k in picks)
        assert read.loose_nodes == 3
        if case % 4 == 0:
            j = _cli_json([path, "--units", "m"], capsys)
            assert {(d["name"], d["kind"]): d["count"] for d in j["read"]["dropped"]} == dict(want)
        outcomes["left out" if read.left_out else "tags only"] += 1
    assert set(outcomes) == {"refused", "left out", "tags only"}, outcomes


def test_fuzz_part_axes(fuzz_dir, capsys):
    """The P2 cube drawn about a random axis through a random origin of its file (random
    directions, the near-x branch of the frame convention, axes along the file's own), read
    with that axis and origin and plane rules written in the file's axes: the part of the z
    original, to 1e-12 (volume, centroid, inertia, interface masters), and the rules find
    the same faces. API, and one in four through the command line."""
    from tests.fe_components.test_part_frame import frame

    rng = random.Random(264)
    pts, tets = _cube_mesh(2)
    ref_rules = (InterfaceRule("end_a", "plane", point=(0.0, 0.0, 0.0), normal=(1.0, 0.0, 0.0)),
                 InterfaceRule("end_b", "plane", point=(CUBE, 0.0, 0.0), normal=(1.0, 0.0, 0.0)))
    ref = part_geometry(PartFile(_write(fuzz_dir, "axis_ref.vtu", pts, [("tetra10", tets)]), ref_rules, units="m"))
    for case in range(examples(24)):
        kind = rng.choice(["random", "near-x", "file axis"])
        if kind == "random":
            axis = tuple(rng.uniform(-1, 1) for _ in range(3))
        elif kind == "near-x":
            axis = (rng.choice([-1, 1]) * rng.uniform(0.95, 1.0), rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2))
        else:
            axis = tuple(rng.choice([-1.0, 1.0]) * e for e in rng.choice(np.eye(3).tolist()))
        origin = tuple(rng.uniform(-0.5, 0.5) for _ in range(3))
        R = frame(axis)
        o = np.array(origin)
        rules = tuple(InterfaceRule(r.name, "plane", point=tuple(o + R @ r.point), normal=tuple(R @ r.normal))
                      for r in ref_rules)
        path = _write(fuzz_dir, f"axis{case}.vtu", o + pts @ R.T, [("tetra10", tets)])
        geo = part_geometry(PartFile(path, rules, units="m", axis=axis, origin=origin))
        _same_geometry(geo, ref, (case, axis))
        for a, b in zip(geo.interfaces, ref.interfaces):
            assert np.array_equal(np.sort(a.face_ids), np.sort(b.face_ids)), (case, a.name)
            assert np.abs(a.master - b.master).max() < 1e-12 * CUBE, (case, a.name)
        if case % 4 == 0:
            j = _cli_json([path, "--units", "m", "--axis=" + ",".join(map(repr, axis)),   # '=': a leading minus
                           "--origin=" + ",".join(map(repr, origin))], capsys)
            assert np.abs(np.array(j["fe"]["center_of_mass_m"]) - ref.centroid).max() < 1e-12 * CUBE
