"""A user's CAD part gives the physics of the same solid built in: mass properties against
OpenCASCADE's exact ones, a built-in wheel round-tripped through STEP, a free sphere against
Lamb's exact frequencies, and the cache keyed on the file's content."""
from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from cms.eigen import free_free_shift, lowest_modes
from fe_components.coupling import couple
from fe_components.fe_model import build_component
from fe_components.geometry import build_solid, interface_defs
from fe_components.gmsh_session import gmsh_model
from fe_components.material import STEEL
from fe_components.meshing import MeshOptions, mesh_path
from fe_components.part.file import InterfaceRule, PartFile
from fe_components.reference import WHEEL_SMOOTH
from tests.support.lamb_sphere import sphere_frequencies

PARTS = Path(__file__).resolve().parents[2] / "assembly" / "scenes" / "parts"
CARRIER_STEP = PARTS / "carrier_windows.step"
R_PIN = 0.09777438348018569  # m: the stage's carrier radius the part was drawn for


def carrier_part(path=CARRIER_STEP) -> PartFile:
    rules = [InterfaceRule(f"pin_{i}", "cylinder", axis_point=(R_PIN * math.cos(a), R_PIN * math.sin(a), 0.0),
                           radius=0.015, span=(-0.04, 0.04))
             for i, a in enumerate((0.0, 2 * math.pi / 3, 4 * math.pi / 3))]
    rules += [InterfaceRule("bearing_a", "cylinder", radius=0.04, span=(-0.07, -0.04)),
              InterfaceRule("bearing_b", "cylinder", radius=0.045, span=(0.04, 0.08)),
              InterfaceRule("output_bore", "cylinder", radius=0.025, span=(0.04, 0.08))]
    return PartFile(str(path), tuple(rules))


def _occ_exact(path: Path):
    """(volume m^3, centre m, inertia per unit density m^5) of a STEP file, straight from
    OpenCASCADE (BRepGProp), independently of flexgear's reader (read in mm, OCC's default
    target unit: another target would stay set for the STEP files written later)."""
    with gmsh_model("occ-exact") as gmsh:
        gmsh.option.setString("Geometry.OCCTargetUnit", "MM")
        (dim, tag), = [e for e in gmsh.model.occ.importShapes(str(path)) if e[0] == 3]
        gmsh.model.occ.synchronize()
        occ = gmsh.model.occ
        return (occ.getMass(3, tag) * 1e-9, np.array(occ.getCenterOfMass(3, tag)) * 1e-3,
                np.array(occ.getMatrixOfInertia(3, tag)).reshape(3, 3) * 1e-15)


def test_step_carrier_mass_properties_match_the_cad_to_1e_3(tmp_path):
    """Mass, centre of mass and inertia of the P2 FE model against
    OpenCASCADE's exact values (gmsh occ.getMass / getCenterOfMass / getMatrixOfInertia) to 1e-3."""
    V, c, J = _occ_exact(CARRIER_STEP)
    fe = build_component(carrier_part(), STEEL, mesh_size=0.012, cache_dir=tmp_path)
    assert fe.order == 2
    rho = STEEL.rho
    assert abs(fe.mass - rho * V) / (rho * V) < 1e-3
    size = 0.4  # m: the part's bounding-box diagonal is 0.38 m (270 mm across, 150 mm long)
    assert np.linalg.norm(fe.center_of_mass - c) / size < 1e-3
    assert np.linalg.norm(fe.inertia - rho * J, 2) / np.linalg.norm(rho * J, 2) < 1e-3
    # the model carries the same check (a warning above 1e-3)
    assert max(fe.checks.values()) < 1e-3 and set(fe.checks) == {"mass_rel", "center_of_mass_rel", "inertia_rel"}


def test_step_carrier_interfaces_sit_on_their_cylinders(tmp_path):
    """Every node of a pin interface lies on its bore (radius 15 mm about the pin axis, in a
    cheek), and the master is on the axis at the mid-plane (the cheeks are symmetric)."""
    fe = build_component(carrier_part(), STEEL, mesh_size=0.012, cache_dir=tmp_path)
    assert list(fe.interfaces) == ["pin_0", "pin_1", "pin_2", "bearing_a", "bearing_b", "output_bore"]
    for i, a in enumerate((0.0, 2 * math.pi / 3, 4 * math.pi / 3)):
        itf = fe.interfaces[f"pin_{i}"]
        p = fe.nodes[itf.nodes]
        r = np.hypot(p[:, 0] - R_PIN * math.cos(a), p[:, 1] - R_PIN * math.sin(a))
        assert np.allclose(r, 0.015, atol=1e-9)   # P2 nodes are placed on the CAD surface
        assert np.all(np.abs(p[:, 2]) >= 0.025 - 1e-9)  # in the cheeks (z in +-[25, 40] mm)
        assert np.allclose(itf.master, [R_PIN * math.cos(a), R_PIN * math.sin(a), 0.0], atol=1e-9)


def _export_step(params, path: Path) -> None:
    """The built-in solid of ``params`` written as STEP by OpenCASCADE (numbers in metres;
    the file declares mm, the OCC writer's default unit)."""
    with gmsh_model("export-step") as gmsh:
        gmsh.option.setNumber("Geometry.OCCUnionUnify", 0)
        build_solid(gmsh.model.occ, params)
        gmsh.model.occ.synchronize()
        gmsh.write(str(path))


def _wheel_rules() -> tuple[InterfaceRule, ...]:
    """The built-in wheel's interfaces as rules: the bore (RBE2) and the smooth rim at the
    pitch radius (RBE3), as geometry.interface_defs defines them."""
    w = WHEEL_SMOOTH
    h0, h1 = w.hub_offset - w.hub_length / 2, w.hub_offset + w.hub_length / 2
    b = w.teeth.face_width
    return (InterfaceRule("bore", "cylinder", radius=w.bore_diameter / 2, span=(h0, h1), master=(0, 0, w.hub_offset)),
            InterfaceRule("gear_mesh", "cylinder", radius=w.teeth.outer_radius, span=(-b / 2, b / 2),
                          coupling="rbe3"))


def _lowest(K, M, k: int) -> np.ndarray:
    res = lowest_modes(K, M, k, sigma=free_free_shift(K, M))
    return np.sort(res.frequencies_hz)


def test_builtin_wheel_through_step_gives_the_same_frequencies(tmp_path):
    """The built-in wheel exported to STEP and read back as a user part
    (units = "m": the OCC writer declares mm for numbers in metres) has the same free-free and
    coupled frequencies within 0.1 % at the same element size."""
    step = tmp_path / "wheel.step"
    _export_step(WHEEL_SMOOTH, step)
    part = PartFile(str(step), _wheel_rules(), units="m")
    opts = MeshOptions(size=0.015)
    builtin = build_component(WHEEL_SMOOTH, STEEL, options=opts, cache_dir=tmp_path)
    user = build_component(part, STEEL, options=opts, cache_dir=tmp_path)
    assert abs(user.mass - builtin.mass) / builtin.mass < 1e-3
    # the same interfaces at the same masters
    for d in interface_defs(WHEEL_SMOOTH):
        assert np.allclose(user.interfaces[d.name].master, d.master, atol=1e-9)
    k = 16  # 6 rigid + 10 elastic
    f_b, f_u = _lowest(builtin.K, builtin.M, k)[6:], _lowest(user.K, user.M, k)[6:]
    assert np.max(np.abs(f_u / f_b - 1)) < 1e-3, (f_b, f_u)
    cb, cu = couple(builtin), couple(user)
    g_b, g_u = _lowest(cb.K_c, cb.M_c, k)[6:], _lowest(cu.K_c, cu.M_c, k)[6:]
    assert np.max(np.abs(g_u / g_b - 1)) < 1e-3, (g_b, g_u)
    assert np.max(np.abs(g_b / f_b - 1)) > 1e-3  # the RBE2 bore does stiffen: the check can fail


def test_free_sphere_from_step_matches_lamb(tmp_path):
    """A free steel sphere (radius 50 mm) from a STEP file, no interfaces,
    reproduces the exact lowest frequencies of a free elastic sphere (Lamb 1882) to 0.5 %:
    the families torsional n = 2, spheroidal n = 2, spheroidal n = 1, with their 2n + 1
    multiplicities (5, 5, 3), after the 6 rigid-body modes."""
    step = tmp_path / "sphere.step"
    with gmsh_model("sphere") as gmsh:
        gmsh.model.occ.addSphere(0, 0, 0, 50.0)   # mm: the unit the STEP file declares
        gmsh.model.occ.synchronize()
        gmsh.write(str(step))
    part = PartFile(str(step))
    fe = build_component(part, STEEL, mesh_size=0.01, cache_dir=tmp_path)
    assert abs(fe.mass - STEEL.rho * 4 / 3 * math.pi * 0.05 ** 3) / fe.mass < 1e-3
    exact = sphere_frequencies(0.05, STEEL.E, STEEL.nu, STEEL.rho, count=3)
    want = np.concatenate([[f] * mult for f, _, _, mult in exact])   # 13 modes
    got = _lowest(fe.K, fe.M, 6 + len(want))
    assert np.all(got[:6] < 1e-3 * got[6])                          # 6 rigid-body modes
    assert np.max(np.abs(got[6:] / want - 1)) < 5e-3, (got[6:], want)


def test_cache_keys_on_the_file_content_not_its_name(tmp_path):
    """The mesh cache entry of a part follows its bytes: a copy under another name and folder
    hits the same entry; one changed byte (a STEP comment) makes another."""
    copy = tmp_path / "elsewhere" / "my_carrier.stp"
    copy.parent.mkdir()
    shutil.copy(CARRIER_STEP, copy)
    opts = MeshOptions(size=0.012)
    a, b = carrier_part(), carrier_part(copy)
    assert a.content_sha256 == b.content_sha256
    assert mesh_path(a, opts, tmp_path) == mesh_path(b, opts, tmp_path)
    changed = tmp_path / "changed.step"
    data = CARRIER_STEP.read_bytes()
    changed.write_bytes(data.replace(b"DATA;", b"DATA;\n/* revised */", 1))
    c = carrier_part(changed)
    assert c.content_sha256 != a.content_sha256
    assert mesh_path(c, opts, tmp_path) != mesh_path(a, opts, tmp_path)


@pytest.mark.parametrize("units, factor", [(None, 1.0), ("m", 1000.0)])
def test_step_units_are_the_files_unless_told(units, factor, tmp_path):
    """A STEP file's declared unit (mm here) is converted to metres; units = "m" takes its
    numbers as metres instead (a part 1000 x larger: the size check then refuses it)."""
    from fe_components.part.file import PartFileError
    from fe_components.part.read import part_geometry
    part = PartFile(str(CARRIER_STEP), carrier_part().interfaces, units=units)
    if factor == 1.0:
        geo = part_geometry(part)
        # mm drawing: 270 x 270 x 150 (the extent is sampled: 36 points on a 135 mm circle
        # miss its extremes by up to r (1 - cos 5 deg) = 0.5 mm)
        assert np.allclose(geo.hi - geo.lo, [0.27, 0.27, 0.15], atol=1e-3)
    else:
        with pytest.raises(PartFileError, match="carrier_windows.step.*did you mean units = 'mm'"):
            part_geometry(part)
