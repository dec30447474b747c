"""``flexgear part`` and :func:`assembly.analysis.part_check.check_part`: one part checked alone, with no
bearing or scene around it -- its mass properties (FE, and CAD-exact for a STEP file with
their relative difference), its free-free modes (six rigid-body modes counted, the first
elastic ones), the interfaces its rules found, what its file held and the element order.

Every number is checked against a closed form: a box's mass and inertia, a face's area and
centre, six rigid-body modes of a free solid (twelve for two loose pieces), and the API's own
result for the command's."""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import meshio
import numpy as np
import pytest

from assembly.analysis.part_check import check_body_part, check_part
from assembly.app.cli import main
from assembly.errors import SceneError
from assembly.scene.schema import load_scene
from assembly.scene.tables import FlexOptions
from fe_components.gmsh_session import gmsh_model
from fe_components.part.file import PartFile, PartFileError
from tests.support.mesh_writers import kuhn_box

REPO = Path(__file__).resolve().parents[2]
BAR = (0.1, 0.02, 0.02)      # m: a steel bar, 5 cubes of 20 mm split into 30 tetrahedra
BOX_MM = (40.0, 30.0, 20.0)  # mm: the STEP box
RHO = 7850.0                 # kg/m^3: steel, the default material


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("part-cmd")
    pts, tets = kuhn_box(BAR, (5, 1, 1))
    meshio.write(d / "bar.vtu", meshio.Mesh(pts, [("tetra", tets)]))
    # a triangle on the x = 0 face across the diagonal the tetrahedra split it along (0-3): a
    # shell the tetrahedra do not have as a face (node = 4 i + 2 j + k)
    meshio.write(d / "bar_shell.vtu", meshio.Mesh(pts, [("tetra", tets), ("triangle", np.array([[0, 1, 2]]))]))
    # two bars side by side that do not touch: two loose pieces in one file
    pts2 = np.vstack([pts, pts + (0.0, 0.05, 0.0)])
    meshio.write(d / "two_bars.vtu", meshio.Mesh(pts2, [("tetra", np.vstack([tets, tets + len(pts)]))]))
    with gmsh_model("box") as gmsh:
        gmsh.model.occ.addBox(0, 0, 0, *BOX_MM)
        gmsh.model.occ.synchronize()
        gmsh.write(str(d / "box.step"))
    scene = d / "scene.toml"
    scene.write_text(f'''name = "one part"
[[bodies]]
name = "bar"
fidelity = "flexible"
flex = {{ material = {{ E = 2.1e11, nu = 0.3, rho = 7000.0 }} }}
[bodies.component]
kind = "file"
file = "bar.vtu"
units = "m"
order = 2
[[bodies.component.interfaces]]
name = "end_a"
select = "plane"
point = [0.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]
[[bodies.component.interfaces]]
name = "end_b"
select = "plane"
point = [{BAR[0]}, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]
coupling = "rbe3"
[[bearings]]
body = "bar"
interface = "end_a"
k_radial = 1.0e8
k_axial = 1.0e8
k_tilt = 1.0e5
[[bodies]]
name = "hub"
mass = 1.0
polar_inertia = 0.01
[[bearings]]
body = "hub"
k_radial = 1.0e8
k_axial = 1.0e8
k_tilt = 1.0e5
''')
    return d


def run(args, cache) -> tuple[int, str, str]:
    """The command in a process of its own (its log on stderr, as a user sees it)."""
    env = {**os.environ, "FLEXGEAR_CACHE_DIR": str(cache)}
    p = subprocess.run([sys.executable, "-m", "assembly.app.cli", "part", *map(str, args)], capture_output=True,
                       text=True, env=env, cwd=REPO, timeout=300)
    return p.returncode, p.stdout, p.stderr


def _box_inertia(m, a, b, c) -> np.ndarray:
    """About the centre of a solid box a x b x c: m (b^2 + c^2) / 12, ..."""
    return m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def test_a_step_file_against_its_cad(files, tmp_path):
    """A STEP box: FE and CAD-exact mass properties both the closed form (plane faces: the P2
    mesh is the box exactly), their difference printed; six rigid-body modes."""
    c = check_part(PartFile(str(files / "box.step")), FlexOptions(mesh_size=0.01), caches=_caches(tmp_path))
    a, b, h = (x * 1e-3 for x in BOX_MM)
    m = RHO * a * b * h
    assert c.source == "cad" and c.order == 2 and c.read is None
    assert c.mass == pytest.approx(m, rel=1e-12) and c.cad[0] == pytest.approx(m, rel=1e-9)
    assert np.allclose(c.center_of_mass, (a / 2, b / 2, h / 2), rtol=0, atol=1e-12)
    assert np.abs(c.inertia - _box_inertia(m, a, b, h)).max() < 1e-12 * c.inertia.max()
    assert max(c.cad_rel.values()) < 1e-9
    assert c.n_rigid == 6 and len(c.elastic_hz) == 6 and c.elastic_hz[0] > 1e3
    code, out, err = run([files / "box.step", "--mesh-size", "0.01", "--json"], tmp_path / "cache")
    assert code == 0, err
    j = json.loads(out)
    assert j["cad"]["mass_kg"] == pytest.approx(m, rel=1e-9) and j["fe"]["mass_kg"] == pytest.approx(c.mass, rel=1e-12)
    np.testing.assert_allclose(j["frequencies_hz"][6:], c.elastic_hz, rtol=1e-9)
    assert j["n_rigid"] == 6 and j["order"] == 2


def _caches(tmp_path):
    from assembly.model.components import CacheDirs
    return CacheDirs(tmp_path / "m", tmp_path / "s")


def test_a_mesh_file_report(files, tmp_path):
    """The linear bar lifted to P2 from the command line: what was read, the mass (the bar's
    exactly: straight tetrahedra), six rigid-body modes, the elastic frequencies the API gives."""
    api = check_part(PartFile(str(files / "bar.vtu"), units="m", order=2), caches=_caches(tmp_path))
    code, out, err = run([files / "bar.vtu", "--units", "m", "--order", "2"], tmp_path / "cache")
    assert code == 0, err
    assert "read: read 30 tetra; lifted to P2" in out and "P2 tetrahedra, 30 elements" in out
    assert f"{RHO * math.prod(BAR):.8g}" in out            # 3.14 kg
    assert "free-free modes: 6 rigid-body modes" in out and "<- a free solid has 6" not in out
    for f in api.elastic_hz:
        assert f"{f:12.6g} Hz" in out
    assert "interfaces: none (a free part)" in out
    assert "WARNING" not in err   # order = 2: no P1 warning


def test_a_linear_file_and_cells_left_out_are_said(files, tmp_path):
    code, out, err = run([files / "bar_shell.vtu", "--units", "m"], tmp_path / "cache")
    assert code == 0, err
    assert "read: read 30 tetra; dropped 1 triangle (surface)" in out
    assert "left out of the model: 1 triangle (surface)" in out
    assert "linear tetrahedra: too stiff in bending" in out
    (line,) = [x for x in err.splitlines() if x.startswith("WARNING")]
    assert "bar_shell.vtu" in line and "Left out of the model" in line and "order = 2" in line


def test_two_loose_pieces_show_twelve_rigid_body_modes(files, tmp_path):
    """Two bars that do not touch: each is free, so 12 rigid-body modes (printed and warned)."""
    c = check_part(PartFile(str(files / "two_bars.vtu"), units="m", order=2), caches=_caches(tmp_path))
    assert c.n_rigid == 12
    code, out, err = run([files / "two_bars.vtu", "--units", "m", "--order", "2"], tmp_path / "cache")
    assert code == 0 and "12 rigid-body modes  <- a free solid has 6" in out
    assert "12 rigid-body modes where a free solid has 6" in err


def test_a_scene_body(files, tmp_path, capsys):
    """The scene's part with its interfaces and flex material (rho = 7000): each end face
    found (area b c = 4e-4 m^2, master its centre), its faces (2 triangles) and nodes (a
    P2 square of 2 triangles: 9 nodes)."""
    scene = load_scene(files / "scene.toml")
    api = check_body_part(scene, "bar", caches=_caches(tmp_path))
    assert api.mass == pytest.approx(7000.0 * math.prod(BAR), rel=1e-12)
    by = {i.name: i for i in api.interfaces}
    for name, x in (("end_a", 0.0), ("end_b", BAR[0])):
        i = by[name]
        assert i.select == "plane" and i.n_faces == 2 and i.n_nodes == 9
        assert i.area == pytest.approx(BAR[1] * BAR[2], rel=1e-12)
        assert np.allclose(i.master, (x, BAR[1] / 2, BAR[2] / 2), rtol=0, atol=1e-15)
    assert by["end_b"].coupling == "rbe3"
    assert check_body_part(scene, caches=_caches(tmp_path)).mass == api.mass   # the only part body
    assert main(["part", str(files / "scene.toml"), "--body", "bar", "--json", "-q"]) == 0
    j = json.loads(capsys.readouterr().out)
    assert [i["name"] for i in j["interfaces"]] == ["end_a", "end_b"] and j["material"]["rho"] == 7000.0
    assert j["fe"]["mass_kg"] == pytest.approx(api.mass, rel=1e-12)


@pytest.mark.parametrize("args, says", [
    (["scene.toml", "--body", "hub"], "--body = 'hub': its component is not a part file"),
    (["scene.toml", "--body", "nope"], "--body = 'nope': no such body in the scene; bodies with a part file: ['bar']"),
    (["scene.toml", "--units", "mm"], "--units: applies to a part file"),
    (["bar.vtu", "--body", "bar"], "--body bar: names a body of a scene"),
    (["bar.vtu"], "--units = None: bar.vtu: a mesh file carries no length unit"),
    (["bar.vtu", "--units", "furlong"], "--units = 'furlong'"),
    (["bar.vtu", "--units", "m", "--axis", "0,0"], "--axis = '0,0': give three finite numbers"),
    (["bar.vtu", "--units", "m", "--axis", "0,0,0"], "--axis = '0,0,0': bar.vtu: must be a non-zero vector"),
    (["bar.vtu", "--units", "m", "--origin", "nan,0,0"], "--origin = 'nan,0,0': give three finite numbers"),
    (["bar.vtu", "--units", "mm"], "--units = 'mm': bar.vtu: read in mm, the part is 0.0001039 m across"),
    (["bar.vtu", "--units", "m", "--modes", "0"], "--modes = 0: must be >= 1"),
    (["box.step", "--mesh-size", "-1"], "--mesh-size = -1.0: must be"),
    (["bar.vtu", "--units", "m", "--mesh-size", "0.01"], "--mesh-size = 0.01: a mesh file brings its own elements"),
    (["box.step", "--order", "2"], "--order = 2: box.step: a CAD part is meshed at the body's flex order"),
    (["missing.vtu", "--units", "m"], "FILE = "),
])
def test_bad_arguments_are_one_line(args, says, files, capsys, monkeypatch):
    monkeypatch.chdir(files)
    assert main(["part", *args, "-q"]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("flexgear: error: "), err
    assert says in err, err


def test_api_errors_name_the_field(files):
    scene = load_scene(files / "scene.toml")
    with pytest.raises(SceneError) as err:
        check_body_part(scene, "hub")
    assert err.value.path == "body"
    with pytest.raises(SceneError) as err:
        check_part("bar.vtu")
    assert err.value.path == "component"
    with pytest.raises(SceneError) as err:
        check_part(PartFile(str(files / "bar.vtu"), units="m"), n_elastic=0)
    assert err.value.path == "n_elastic"
    with pytest.raises(SceneError) as err:
        check_part(PartFile(str(files / "bar.vtu"), units="m"), {"mesh_size": 0.01})
    assert err.value.path == "flex"
    with pytest.raises(PartFileError):
        check_part(PartFile(str(files / "bar.vtu"), units="mm"))


def test_scene_commands_say_what_was_left_out(files, tmp_path):
    """``flexgear modes`` on a scene whose part file holds a shell besides its tetrahedra:
    the table on stdout, one WARNING line on stderr naming the file and what was left out."""
    scene = files / "scene_shell.toml"
    scene.write_text((files / "scene.toml").read_text().replace('file = "bar.vtu"', 'file = "bar_shell.vtu"'))
    p = subprocess.run([sys.executable, "-m", "assembly.app.cli", "modes", str(scene)], capture_output=True, text=True,
                       env={**os.environ, "FLEXGEAR_CACHE_DIR": str(tmp_path)}, cwd=REPO, timeout=300)
    assert p.returncode == 0, p.stderr
    (line,) = p.stderr.splitlines()
    assert line.startswith("WARNING fe_components.part.read: bar_shell.vtu: read 30 tetra; dropped 1 triangle "
                           "(surface); lifted to P2"), line
    assert "Left out of the model (only tetrahedra are read): 1 triangle (surface)" in line
