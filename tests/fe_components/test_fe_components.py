"""Every reference component (committed mesh): free-free rigid modes, mass, interfaces, cache."""
from __future__ import annotations

import math
import sys

import numpy as np
import pytest

from cms.eigen import free_free_shift, lowest_modes
from fe_components.fe_model import build_component
from fe_components.material import STEEL
from fe_components.meshing import mesh_path
from fe_components.reference import CASES, REF_DIR

COMPONENTS = ["pinion_smooth", "pinion_involute", "wheel_smooth", "carrier"]

EXPECTED = {
    "pinion_smooth": ["bearing_a", "bearing_b", "gear_mesh"],
    "pinion_involute": ["bearing_a", "bearing_b", "gear_mesh"],
    "wheel_smooth": ["bore", "gear_mesh"],
    "carrier": ["pin_0", "pin_1", "pin_2", "bearing_a", "bearing_b", "output_bore"],
}


@pytest.fixture(scope="module")
def models():
    return {name: build_component(CASES[name][0], STEEL, options=CASES[name][1], cache_dir=REF_DIR)
            for name in COMPONENTS}


def test_reference_meshes_are_committed():
    for name, (params, options) in CASES.items():
        assert mesh_path(params, options, REF_DIR).exists(), f"run python -m fe_components.reference ({name})"


def test_cached_mesh_does_not_import_gmsh(monkeypatch):
    monkeypatch.setitem(sys.modules, "gmsh", None)  # any "import gmsh" now raises ImportError
    params, options = CASES["carrier"]
    model = build_component(params, STEEL, options=options, cache_dir=REF_DIR)
    assert model.n_dofs > 0


@pytest.mark.parametrize("name", COMPONENTS)
def test_six_rigid_body_modes(models, name):
    m = models[name]
    f = lowest_modes(m.K, m.M, 8, sigma=free_free_shift(m.K, m.M)).frequencies_hz
    assert np.all(np.abs(f[:6]) < 1e-3 * f[6]), f
    assert f[6] > 0


@pytest.mark.parametrize("name", COMPONENTS)
def test_interfaces(models, name):
    m = models[name]
    assert list(m.interfaces) == EXPECTED[name]
    for iface in m.interfaces.values():
        assert len(iface.nodes) >= 6
        assert iface.master.shape == (3,)
        assert iface.coupling in ("rbe2", "rbe3")
    # node sets are disjoint
    allnodes = np.concatenate([i.nodes for i in m.interfaces.values()])
    assert len(np.unique(allnodes)) == len(allnodes)


def test_pinion_interfaces_geometry(models):
    m = models["pinion_smooth"]
    p = CASES["pinion_smooth"][0]
    x = m.nodes
    seat = m.interfaces["bearing_a"]
    r = np.hypot(x[seat.nodes, 0], x[seat.nodes, 1])
    np.testing.assert_allclose(r, p.shaft[0].diameter / 2, rtol=1e-6)
    assert x[seat.nodes, 2].min() == pytest.approx(0.0, abs=1e-9)
    assert x[seat.nodes, 2].max() == pytest.approx(p.shaft[0].length, rel=1e-9)
    np.testing.assert_allclose(seat.master, [0, 0, p.shaft[0].length / 2])
    gm = m.interfaces["gear_mesh"]
    np.testing.assert_allclose(np.hypot(x[gm.nodes, 0], x[gm.nodes, 1]), p.teeth.pitch_radius, rtol=1e-6)
    np.testing.assert_allclose(gm.master, [0, 0, p.gear_center])
    assert gm.coupling == "rbe3"


def test_involute_gear_mesh_patch_spans_root_to_tip(models):
    m = models["pinion_involute"]
    t = CASES["pinion_involute"][0].teeth
    x = m.nodes[m.interfaces["gear_mesh"].nodes]
    r = np.hypot(x[:, 0], x[:, 1])
    assert r.max() == pytest.approx(t.tip_radius, rel=1e-6)
    assert r.min() == pytest.approx(t.root_radius, rel=1e-3)


def test_carrier_pins_in_both_cheeks(models):
    m = models["carrier"]
    p = CASES["carrier"][0]
    x = m.nodes
    for i, a in enumerate(p.planet_angles):
        iface = m.interfaces[f"pin_{i}"]
        c = p.pin_pitch_radius * np.array([math.cos(a), math.sin(a)])
        np.testing.assert_allclose(np.hypot(*(x[iface.nodes, :2] - c).T), p.pin_bore_diameter / 2, rtol=1e-6)
        z = x[iface.nodes, 2]
        s, t = p.cheek_spacing, p.cheek_thickness
        assert z.min() == pytest.approx(-s / 2 - t) and z.max() == pytest.approx(s / 2 + t)
        assert not np.any((z > -s / 2 + 1e-9) & (z < s / 2 - 1e-9))  # nothing between the cheeks
        np.testing.assert_allclose(iface.master, [c[0], c[1], 0.0], atol=1e-12)


def test_mass_properties_consistent(models):
    for name, m in models.items():
        e = np.zeros(m.n_dofs)
        e[0::3] = 1.0
        assert e @ (m.M @ e) == pytest.approx(m.mass, rel=1e-10)
        # inertia about the COM is symmetric positive definite and satisfies the triangle inequality
        w = np.linalg.eigvalsh(m.inertia)
        assert np.all(w > 0) and w[0] + w[1] >= w[2] * (1 - 1e-12)
        # axisymmetric parts (pinion, 3-fold carrier, 6-hole wheel): COM on the axis
        np.testing.assert_allclose(m.center_of_mass[:2], 0.0, atol=1e-6)


def test_dof_order_matches_skfem_vector_basis(models):
    m = models["wheel_smooth"]
    d = m.basis.doflocs
    np.testing.assert_array_equal(d[:, 0::3], d[:, 1::3])
    np.testing.assert_array_equal(d[:, 0::3], d[:, 2::3])
    assert m.K.shape == (m.n_dofs, m.n_dofs) and m.M.shape == m.K.shape


def test_involute_flank_nodes_lie_on_the_involute(models):
    # flank points at radius r sit at polar angle +-theta(r) from the tooth centre,
    # theta(r) = s_t / (2 r_p) + inv(alpha_t) - inv(alpha_r), cos(alpha_r) = r_b / r (ISO 21771)
    from fe_components.involute import flank_half_angle

    t = CASES["pinion_involute"][0].teeth
    x = models["pinion_involute"].nodes[models["pinion_involute"].interfaces["gear_mesh"].nodes]
    r = np.hypot(x[:, 0], x[:, 1])
    flank = (r > t.base_radius + 0.05 * t.normal_module) & (r < t.tip_radius - 0.05 * t.normal_module)
    pitch = 2 * np.pi / t.n_teeth
    phi = np.arctan2(x[flank, 1], x[flank, 0])
    rel = (phi + pitch / 2) % pitch - pitch / 2  # angle from the nearest tooth centre (tooth 0 at angle 0)
    err = np.abs(np.abs(rel) - flank_half_angle(t, r[flank])) * r[flank]  # arc length [m]
    assert flank.sum() > 100
    assert err.max() < 0.01 * t.normal_module  # spline through 7 exact points per flank


def test_package_import_does_not_load_gmsh_or_pyvista():
    import subprocess

    code = "import sys, fe_components; print('gmsh' in sys.modules or 'pyvista' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_inverted_curved_element_is_refused():
    import dataclasses

    from fe_components.errors import MeshingError
    from fe_components.fe_model import assemble
    from fe_components.meshing import read_mesh

    params, options = CASES["annulus"]
    raw = read_mesh(mesh_path(params, options, REF_DIR))
    pts = raw.points.copy()
    c = raw.cells[0]
    # push the mid-edge node of edge (0, 1) beyond vertex 1: the quadratic map folds over
    pts[c[4]] = pts[c[0]] + 1.5 * (pts[c[1]] - pts[c[0]])
    with pytest.raises(MeshingError) as e:
        assemble(params, dataclasses.replace(raw, points=pts))
    assert e.value.params["n_inverted"] >= 1
