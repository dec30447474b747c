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
field, or read, or refused by the part reader; never any other exception."""
from __future__ import annotations

import collections
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
from assembly.schema import SCENE_DIR, from_dict
from fe_components.fe_model import build_component
from fe_components.part_cad import step_length_unit
from fe_components.part_file import SIZE_RANGE, InterfaceRule, PartFile, PartFileError
from fe_components.part_geometry import part_geometry
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
    import gmsh

    own = not gmsh.isInitialized()
    if own:
        gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)

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
    finally:
        if own:
            gmsh.finalize()


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

    def part(self, d: Path) -> PartFile:
        kw = {"volumes": self.volumes} if self.volumes else {}
        return PartFile(str(d / self.file), rules(self.rules), units=self.units, **kw)


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


def write_scene(d: Path, case_id: str, file: str, units=None, volumes=None, rules=()) -> Path:
    """A scene of one flexible body read from ``file`` (relative to the scene's folder ``d``),
    held by a bearing at each of its first two interfaces."""
    lines = ['name = "part input check"', "band_hz = 3000.0", "", "[[bodies]]", 'name = "part"',
             'fidelity = "flexible"', "[bodies.component]", 'kind = "file"', f"file = {_toml(file)}"]
    if units:
        lines.append(f"units = {_toml(units)}")
    if volumes:
        lines.append(f"volumes = {_toml(volumes)}")
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
    scene = write_scene(bad, case.id, case.file, case.units, case.volumes, case.rules)
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
