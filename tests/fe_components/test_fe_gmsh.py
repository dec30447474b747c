"""Tests that run gmsh on coarse meshes (marker ``gmsh``)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import fe_components.geometry as geometry
import fe_components.meshing as meshing
from cms.eigen import free_free_shift, lowest_modes
from fe_components.errors import MeshingError
from fe_components.fe_model import build_component
from fe_components.meshing import MeshOptions, ensure_mesh
from fe_components.params import CylinderParams, GearTeeth, PinionParams, ShaftSegment, WheelParams

pytestmark = pytest.mark.gmsh


def test_cache_reuses_file_without_gmsh(tmp_path, monkeypatch):
    params, opts = CylinderParams(0.2, 0.04), MeshOptions(size=0.02)
    path = ensure_mesh(params, opts, tmp_path)
    assert path.exists() and path.parent == tmp_path
    assert [p.name for p in tmp_path.iterdir()] == [path.name]  # no temporary left behind

    def fail(*a, **k):
        raise AssertionError("gmsh called for a cached mesh")

    monkeypatch.setattr(meshing, "generate_mesh", fail)
    assert ensure_mesh(params, opts, tmp_path) == path
    # any changed input is a different file
    assert meshing.mesh_path(params, MeshOptions(size=0.021), tmp_path) != path


def test_gmsh_failure_reports_parameter_set(tmp_path, monkeypatch):
    def broken_solid(occ, params, *a):
        return [(3, occ.addCylinder(0, 0, 0, 0, 0, params.length, 0.0))]  # zero radius: OCC refuses

    monkeypatch.setattr(geometry, "build_solid", broken_solid)  # meshing imports it when it meshes
    params = CylinderParams(0.2, 0.04)
    with pytest.raises(MeshingError) as e:
        ensure_mesh(params, MeshOptions(size=0.02), tmp_path)
    assert e.value.params["length"] == 0.2 and e.value.params["mesh.size"] == 0.02
    assert "length" in str(e.value)
    assert not list(tmp_path.iterdir())  # nothing half-written


def test_helical_involute_pinion_coarse(tmp_path):
    teeth = GearTeeth(18, 0.005, math.radians(20), 0.03, helix_angle=math.radians(12), fidelity="involute")
    shaft = (ShaftSegment(0.025, 0.03), ShaftSegment(0.05, 0.04), ShaftSegment(0.025, 0.03))
    p = PinionParams(teeth, shaft, gear_center=0.05)
    m = build_component(p, options=MeshOptions(size=0.012, flank_points=5, helix_sections=3), cache_dir=tmp_path)
    x = m.nodes[m.interfaces["gear_mesh"].nodes]
    r = np.hypot(x[:, 0], x[:, 1])
    assert r.max() == pytest.approx(teeth.tip_radius, rel=1e-3)
    # right-hand helix for beta > 0: the transverse profile turns by dphi/dz = tan(beta) / r_p;
    # every tip-land node lies within the tip half-angle of a tooth centre so turned
    from fe_components.involute import flank_half_angle

    tip = r > teeth.tip_radius - 1e-3 * teeth.normal_module
    z0 = p.gear_center - teeth.face_width / 2
    phi = np.arctan2(x[tip, 1], x[tip, 0]) - (x[tip, 2] - z0) * math.tan(teeth.helix_angle) / teeth.pitch_radius
    pitch = 2 * math.pi / teeth.n_teeth
    rel = (phi + pitch / 2) % pitch - pitch / 2
    assert tip.sum() > 20
    assert np.all(np.abs(rel) < flank_half_angle(teeth, teeth.tip_radius) + 0.01 * teeth.normal_module / teeth.tip_radius)
    f = lowest_modes(m.K, m.M, 7, sigma=free_free_shift(m.K, m.M)).frequencies_hz
    assert np.all(np.abs(f[:6]) < 1e-3 * f[6])


def test_long_slender_high_speed_pinion(tmp_path):
    # L / d = 20 shaft with a smooth 25-tooth gear: expressible and meshable
    teeth = GearTeeth(25, 0.003, math.radians(20), 0.05)
    shaft = (ShaftSegment(0.05, 0.04), ShaftSegment(0.35, 0.045), ShaftSegment(0.35, 0.045), ShaftSegment(0.05, 0.04))
    p = PinionParams(teeth, shaft, gear_center=0.4)
    m = build_component(p, options=MeshOptions(size=0.015), cache_dir=tmp_path)
    assert set(m.interfaces) == {"bearing_a", "bearing_b", "gear_mesh"}
    # mass = rho * (two seats + two shaft steps + gear annulus at the pitch radius 37.5 mm)
    m_ref = 7850 * math.pi * (0.02**2 * 0.1 + 0.0225**2 * 0.7 + (0.0375**2 - 0.0225**2) * 0.05)
    assert m.mass == pytest.approx(m_ref, rel=1e-3)
    m1 = build_component(p, options=MeshOptions(size=0.015, order=1), cache_dir=tmp_path)
    assert m1.order == 1 and m1.n_dofs < m.n_dofs
    assert m1.mass < m_ref  # P1 facets lie inside the convex cylinders
    f = lowest_modes(m1.K, m1.M, 7, sigma=free_free_shift(m1.K, m1.M)).frequencies_hz
    assert np.all(np.abs(f[:6]) < 1e-3 * f[6])


def test_helical_wheel_coarse(tmp_path):
    teeth = GearTeeth(40, 0.005, math.radians(20), 0.03, helix_angle=math.radians(-10), fidelity="involute")
    w = WheelParams(teeth, rim_inner_diameter=0.16, web_thickness=0.01, hub_outer_diameter=0.07,
                    hub_length=0.04, bore_diameter=0.04, n_holes=4, hole_diameter=0.03)
    m = build_component(w, options=MeshOptions(size=0.012, flank_points=4, helix_sections=3), cache_dir=tmp_path)
    assert set(m.interfaces) == {"bore", "gear_mesh"}
    np.testing.assert_allclose(m.center_of_mass[:2], 0, atol=1e-5)


def test_tooth_refinement(tmp_path):
    from scipy.spatial import cKDTree

    from fe_components.errors import GeometryError
    from fe_components.reference import PINION_SMOOTH

    def spacing(model):
        x = model.nodes[model.interfaces["gear_mesh"].nodes]
        d, _ = cKDTree(x).query(x, k=2)
        return np.median(d[:, 1])

    coarse = build_component(PINION_SMOOTH, options=MeshOptions(size=0.015), cache_dir=tmp_path)
    fine = build_component(PINION_SMOOTH, options=MeshOptions(size=0.015, tooth_size=0.004), cache_dir=tmp_path)
    # P2 surface nodes (vertices and edge midpoints) are about half an element edge apart
    assert 0.25 * 0.004 < spacing(fine) < 0.75 * 0.004
    assert spacing(coarse) > 2 * spacing(fine)
    # the shaft far from the teeth stays at the coarse size: seat node counts of the same order
    assert len(fine.interfaces["bearing_a"].nodes) < 3 * len(coarse.interfaces["bearing_a"].nodes)
    with pytest.raises(GeometryError) as e:
        ensure_mesh(CylinderParams(0.2, 0.04), MeshOptions(size=0.02, tooth_size=0.01), tmp_path)
    assert e.value.parameter == "tooth_size"
    with pytest.raises(GeometryError):
        MeshOptions(size=0.01, tooth_size=0.02)


@pytest.mark.slow
def test_coarse_curved_mesh_is_untangled(tmp_path):
    # 50 mm elements on a 20-tooth, m_n = 4 mm pinion: curving the P2 edges onto the teeth folds
    # some elements; the mesher repairs them (gmsh high-order optimisation) instead of failing
    from fe_components.reference import PINION_INVOLUTE

    m = build_component(PINION_INVOLUTE, options=MeshOptions(size=0.05), cache_dir=tmp_path)
    f = lowest_modes(m.K, m.M, 7, sigma=free_free_shift(m.K, m.M)).frequencies_hz
    assert np.all(np.abs(f[:6]) < 1e-3 * f[6])
