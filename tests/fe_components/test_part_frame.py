"""A part modelled about another axis of its file than z: ``axis`` (the file's rotation axis)
and ``origin`` (a point of it, m in the file's axes) put it in its local frame, z along the
axis. The same part written about x, y, z and an oblique axis gives the z original's model:
the same free-free frequencies (1e-9), mass properties (1e-12) and interface masters, and in
a scene the same mass properties in the scene's axes; a STEP box drawn about an oblique axis
has its closed-form mass properties; the shipped carrier turned onto y keeps its pins.

The frame convention is written out here from docs/user_parts.md, independently of the
reader: local z = axis; local x = the file's x (its y when the axis is within 25.8 deg of x,
|a_x| >= 0.9) made normal to the axis; local y = z cross x; a file point x is at local
R^T (x - origin)."""
from __future__ import annotations

import math

import meshio
import numpy as np
import pytest
from scipy.spatial import cKDTree

from assembly.errors import SceneError
from assembly.model.components import CacheDirs, mass_properties
from assembly.scene.schema import SCENE_DIR, from_dict
from assembly.scene.tables import Body, FlexOptions
from cms.eigen import free_free_shift, lowest_modes
from fe_components.fe_model import build_component
from fe_components.gmsh_session import gmsh_model
from fe_components.material import STEEL
from fe_components.part.file import InterfaceRule, PartFile, PartFileError
from fe_components.part.read import part_geometry

OBLIQUE = (1.0, -2.0, 2.5)
AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0), "oblique": OBLIQUE,
        "near-x": (0.95, 0.1, -0.3)}   # |a_x| >= 0.9: the convention's other branch
ORIGIN = (0.02, -0.013, 0.05)   # m: where the part's local origin is in the rotated files


def frame(axis) -> np.ndarray:
    """The documented frame (columns: local x, y, z in the file's axes)."""
    e3 = np.asarray(axis, float) / np.linalg.norm(axis)
    ref = np.array([1.0, 0.0, 0.0]) if abs(e3[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = ref - ref.dot(e3) * e3
    e1 /= np.linalg.norm(e1)
    return np.column_stack([e1, np.cross(e3, e1), e3])


def _to_file(points, axis, origin=ORIGIN) -> np.ndarray:
    """Local points as the file drawn about ``axis`` through ``origin`` holds them."""
    return np.asarray(origin) + np.asarray(points) @ frame(axis).T


@pytest.fixture(scope="module")
def part_mesh(tmp_path_factory):
    """A part with no symmetry about its axis (a 80 x 50 x 30 mm block with a 12 mm hole off
    its centre, along z), meshed P2 by gmsh, and its end faces z = 0 and z = 30 mm."""
    with gmsh_model("block") as gmsh:
        occ = gmsh.model.occ
        block = occ.addBox(-0.03, -0.02, 0.0, 0.08, 0.05, 0.03)
        hole = occ.addCylinder(0.025, 0.01, 0.0, 0.0, 0.0, 0.03, 0.006)
        occ.cut([(3, block)], [(3, hole)])
        occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.02)   # m: coarse (about 400 tetra10)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.ElementOrder", 2)
        gmsh.model.mesh.generate(3)
        path = tmp_path_factory.mktemp("frame") / "block.msh"
        gmsh.write(str(path))
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 1)   # gmsh's defaults back, should the session go on
        gmsh.option.setNumber("Mesh.ElementOrder", 1)
    m = meshio.read(path)
    return m.points, np.concatenate([c.data for c in m.cells if c.type == "tetra10"])


def _rules(axis, origin) -> tuple:
    """The two end faces as plane rules, in the file's axes."""
    R, o = frame(axis), np.asarray(origin)
    return tuple(InterfaceRule(name, "plane", point=tuple(o + R @ (0.0, 0.0, z)), normal=tuple(R[:, 2]))
                 for name, z in (("end_a", 0.0), ("end_b", 0.03)))


@pytest.fixture(scope="module")
def models(part_mesh, tmp_path_factory):
    """axis name -> (FE model, free-free frequencies) of the part written about that axis
    and read with it; "original": the z file read without axis or origin."""
    pts, tets = part_mesh
    d = tmp_path_factory.mktemp("frames")
    out = {}
    for name, axis in {"original": None, **AXES}.items():
        path = d / f"block_{name}.vtu"
        if axis is None:
            meshio.write(path, meshio.Mesh(pts, [("tetra10", tets)]))
            part = PartFile(str(path), _rules((0, 0, 1), (0, 0, 0)), units="m")
        else:
            meshio.write(path, meshio.Mesh(_to_file(pts, axis), [("tetra10", tets)]))
            part = PartFile(str(path), _rules(axis, ORIGIN), units="m", axis=axis, origin=ORIGIN)
        fe = build_component(part, STEEL, cache_dir=d / "cache")
        f = lowest_modes(fe.K, fe.M, 12, sigma=free_free_shift(fe.K, fe.M)).frequencies_hz
        out[name] = (part, fe, np.sort(f))
    return out


@pytest.mark.parametrize("axis", list(AXES))
def test_same_model_about_every_axis(axis, models):
    _, ref, f_ref = models["original"]
    part, fe, f = models[axis]
    np.testing.assert_allclose(f[6:], f_ref[6:], rtol=1e-9)
    assert fe.mass == pytest.approx(ref.mass, rel=1e-12)
    size = 0.1   # m: the block's diagonal is 0.1 m
    assert np.abs(fe.center_of_mass - ref.center_of_mass).max() < 1e-12 * size
    assert np.abs(fe.inertia - ref.inertia).max() < 1e-12 * np.abs(ref.inertia).max()
    for name in ("end_a", "end_b"):
        assert np.array_equal(np.sort(fe.interfaces[name].nodes), np.sort(ref.interfaces[name].nodes))
        assert np.abs(fe.interfaces[name].master - ref.interfaces[name].master).max() < 1e-12 * size
    geo, geo_ref = part_geometry(part), part_geometry(models["original"][0])
    assert np.allclose(geo.lo, geo_ref.lo, rtol=0, atol=1e-12) and np.allclose(geo.hi, geo_ref.hi, rtol=0, atol=1e-12)


@pytest.mark.parametrize("axis", ["y", "oblique"])
def test_same_mass_properties_in_the_scene(axis, models, tmp_path):
    """A body placed at a position and along an axis in the scene: the rotated file with its
    axis and origin has the z original's mass, centre and inertia in the scene's axes (1e-12)."""
    caches = CacheDirs(tmp_path / "m", tmp_path / "s")
    place = {"position": (0.4, -0.2, 1.1), "axis": (0.3, 0.9, -0.1)}
    out = []
    for key in ("original", axis):
        body = Body(name="part", component=models[key][0], fidelity="rigid", **place)
        out.append(mass_properties(body, FlexOptions(), caches))
    (m0, c0, J0), (m1, c1, J1) = out
    assert m1 == pytest.approx(m0, rel=1e-12)
    assert np.abs(c1 - c0).max() < 1e-12 * np.linalg.norm(c0)
    assert np.abs(J1 - J0).max() < 1e-12 * np.abs(J0).max()


def test_a_part_drawn_in_the_assembly_sits_where_it_was_drawn(models):
    """The convention's point: a body given the part's axis and ``position = origin`` puts
    every file point back where the file has it (global = position + axis_frame(axis) local)."""
    from assembly.mechanics.kinematics import axis_frame

    part, fe, _ = models["oblique"]
    pts_file = _to_file(models["original"][1].nodes, OBLIQUE)   # what the file holds, node for node
    glob = np.asarray(ORIGIN) + fe.nodes @ axis_frame(OBLIQUE).T
    assert cKDTree(pts_file).query(glob)[0].max() < 1e-15 + 1e-12 * 0.1


# ----------------------------------------------------------------------------- a CAD part
BOX = (0.04, 0.03, 0.02)   # m: a 40 x 30 x 20 mm box, x, y, z from the local origin


def test_step_box_about_an_oblique_axis(tmp_path):
    """A STEP box drawn about an oblique axis (its local box turned and moved in the file)
    read with that axis and origin: OpenCASCADE's exact mass properties in the local frame are
    the box's closed forms, V = abc, centroid (a, b, c)/2, I = V (b^2 + c^2)/12 ... (1e-9),
    and its P2 mesh (plane faces: exact geometry) has the same mass and inertia (1e-9)."""
    R = frame(OBLIQUE)
    angle = math.acos((np.trace(R) - 1) / 2)
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / (2 * math.sin(angle))
    path = tmp_path / "box.step"
    with gmsh_model("box") as gmsh:
        occ = gmsh.model.occ
        v = occ.addBox(0, 0, 0, *(1e3 * np.array(BOX)))   # mm: gmsh's STEP declares mm
        occ.rotate([(3, v)], 0, 0, 0, *w, angle)
        occ.translate([(3, v)], *(1e3 * np.array(ORIGIN)))
        occ.synchronize()
        gmsh.write(str(path))
    part = PartFile(str(path), axis=OBLIQUE, origin=ORIGIN)
    geo = part_geometry(part)
    a, b, c = BOX
    V = a * b * c
    assert geo.volume == pytest.approx(V, rel=1e-9)
    assert np.abs(geo.centroid - np.array(BOX) / 2).max() < 1e-9 * a
    J = V / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    assert np.abs(geo.inertia_per_density - J).max() < 1e-9 * J.max()
    assert np.allclose(geo.lo, 0, atol=1e-9) and np.allclose(geo.hi, BOX, atol=1e-9)
    fe = build_component(part, STEEL, mesh_size=0.01, cache_dir=tmp_path / "cache")
    assert fe.mass == pytest.approx(STEEL.rho * V, rel=1e-9)
    assert np.abs(fe.inertia - STEEL.rho * J).max() < 1e-9 * STEEL.rho * J.max()
    assert fe.nodes.min(axis=0) == pytest.approx((0, 0, 0), abs=1e-9)


def test_carrier_turned_onto_y_keeps_its_pins(tmp_path):
    """The shipped STEP carrier turned so that its axis is the file's y (about x by -90 deg:
    z -> y), its pin rules turned with it, read with axis = y: the interface masters come out
    where the z carrier has them (the stage's pin check reads them), to 1e-9 of its size."""
    from tests.fe_components.test_part_physics import carrier_part

    src = SCENE_DIR / "parts" / "carrier_windows.step"
    path = tmp_path / "carrier_y.step"
    with gmsh_model("carrier-y") as gmsh:
        gmsh.option.setString("Geometry.OCCTargetUnit", "MM")
        ents = gmsh.model.occ.importShapes(str(src))
        gmsh.model.occ.rotate(ents, 0, 0, 0, 1, 0, 0, -math.pi / 2)
        gmsh.model.occ.synchronize()
        gmsh.write(str(path))
    ref = part_geometry(carrier_part())
    # z -> y is the documented frame's z -> y for axis y: x stays x, local y is -z of the file
    R = frame((0.0, 1.0, 0.0))
    assert np.allclose(R, [[1, 0, 0], [0, 0, 1], [0, -1, 0]])
    rules = []
    for r in carrier_part().interfaces:
        rules.append(InterfaceRule(r.name, r.select, axis_point=tuple(R @ r.axis_point), axis=tuple(R @ r.axis),
                                   radius=r.radius, span=r.span))
    turned = part_geometry(PartFile(str(path), tuple(rules), axis=(0.0, 1.0, 0.0)))
    assert [i.name for i in turned.interfaces] == [i.name for i in ref.interfaces]
    for a, b in zip(turned.interfaces, ref.interfaces):
        assert np.abs(a.master - b.master).max() < 1e-9 * ref.size, a.name
    assert turned.volume == pytest.approx(ref.volume, rel=1e-9)
    assert np.abs(turned.centroid - ref.centroid).max() < 1e-9 * ref.size


# ------------------------------------------------------------------------------ bad values
@pytest.mark.parametrize("fields, key", [
    ({"axis": [0.0, 0.0, 0.0]}, "axis"), ({"axis": [0.0, 1.0]}, "axis"), ({"axis": [math.nan, 0.0, 1.0]}, "axis"),
    ({"origin": [0.0, 0.0, math.inf]}, "origin"), ({"origin": "0,0,0"}, "origin"), ({"axis": 1.0}, "axis"),
])
def test_bad_axis_or_origin_is_refused_naming_the_field(fields, key):
    step = str(SCENE_DIR / "parts" / "carrier_windows.step")
    with pytest.raises(SceneError) as err:
        from_dict(PartFile, {"file": step, **fields}, "component")
    assert err.value.path.startswith(f"component.{key}")
    with pytest.raises(PartFileError) as err2:
        PartFile(step, **{k: tuple(v) if isinstance(v, list) else v for k, v in fields.items()})
    assert err2.value.parameter.startswith(key)
