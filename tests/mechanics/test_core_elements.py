"""Element-level properties of the gear-mesh and bearing springs (physics, no tables)."""
import dataclasses
import math

import numpy as np
import pytest

from assembly.mechanics.elements import gear_mesh, line_of_action
from assembly.mechanics.kinematics import rigid_transfer
from assembly.model.assemble import assemble
from assembly.scene.schema import load_scene
from assembly.scene.tables import Fixed

rng = np.random.default_rng(7)


def _mesh(beta_deg, r2=0.05, drive=1, contact="pitch"):
    alpha = math.radians(20)
    C = abs(0.03 + r2) / math.cos(alpha)
    c1 = np.array([0.01, -0.02, 0.3])
    d = np.array([math.cos(0.4), math.sin(0.4), 0.0])
    c2 = c1 + (C if r2 > 0 else -C) * d
    return gear_mesh("m", "a", "b", (0, 0, 1), c1, c2, 0.03, r2, alpha, math.radians(beta_deg),
                     drive, 2e8, contact), c1, c2


def _rigid_motion(e, c1, c2):
    """Attachment motions (at the element point) of both gears under one rigid motion."""
    u0, th = rng.normal(size=3), rng.normal(size=3)
    w = np.concatenate([u0 + np.cross(th, e.point), th])
    return np.concatenate([w, w])


@pytest.mark.parametrize("beta", [0.0, 15.0, -30.0])
@pytest.mark.parametrize("r2", [0.05, -0.12])  # external and internal gear 2
@pytest.mark.parametrize("drive", [1, -1])
def test_mesh_symmetric_rank_one_rigid_invariant(beta, r2, drive):
    e, c1, c2 = _mesh(beta, r2, drive)
    K = e.stiffness()
    assert K.shape == (12, 12)
    np.testing.assert_array_equal(K, K.T)
    s = np.linalg.svd(K, compute_uv=False)
    assert np.sum(s > 1e-12 * s[0]) == 1
    for _ in range(5):
        w = _rigid_motion(e, c1, c2)
        assert abs(w @ K @ w) <= 1e-12 * s[0] * (w @ w)


def test_tangent_contact_strains_a_common_tilt_when_helical():
    # The literature convention ('tangent') is invariant to common translations and spin
    # about the gear axis, but a helical mesh then resists a common rigid tilt: the reason
    # 'pitch' is the default.
    e, c1, c2 = _mesh(20.0, contact="tangent")
    K = e.stiffness()
    u0 = rng.normal(size=3)
    spin = np.array([0, 0, 1.0])
    for th in (np.zeros(3), spin):
        w = np.concatenate([u0 + np.cross(th, e.point), th])
        w = np.concatenate([w, w])
        assert abs(w @ K @ w) < 1e-12 * np.abs(K).max() * (w @ w)
    th = np.array([1.0, 0.3, 0.0])
    w = np.concatenate([np.cross(th, e.point), th])
    w = np.concatenate([w, w])
    assert w @ K @ w > 1e-6 * np.abs(K).max()


@pytest.mark.parametrize("drive", [1, -1])
def test_drive_sign_closes_mesh_and_mirrors_line(drive):
    n, p = line_of_action((0, 0, 1), (0, 0, 0), (0.1 / math.cos(0.35), 0, 0), 0.05, 0.05, 0.35, 0.0, drive)
    assert n[0] > 0  # gear 1 pushes gear 2 away along the centre line
    # turning gear 1 by +drive closes the mesh
    assert drive * np.cross(p, n)[2] > 0
    n_other, _ = line_of_action((0, 0, 1), (0, 0, 0), (0.1 / math.cos(0.35), 0, 0), 0.05, 0.05, 0.35, 0.0, -drive)
    np.testing.assert_allclose(n_other, [n[0], -n[1], -n[2]])  # mirror image about the centre line


@pytest.mark.parametrize("helix_deg", [0.0, 12.0])
def test_planet_mesh_forces_balance_under_torque(helix_deg):
    # Peeters, Vandepitte & Sas (2006), planetary rigid model: on a loaded planet the sun- and ring-mesh forces have equal
    # tangential and opposite radial components (net radial force 0), both meshes in
    # compression. For a helical stage the axial components cancel too.
    sc = load_scene("lin_parker_n3.toml")
    st = dataclasses.replace(sc.stages[0], helix_angle=math.radians(helix_deg))
    sc = dataclasses.replace(sc, stages=(st,), fixed=(Fixed("stage.carrier", ("rz",)),))
    m = assemble(sc)
    F = np.zeros(m.K.shape[0])
    F[m.dof_names.index("stage.sun.rz")] = 100.0  # N m on the sun, carrier held
    q = np.linalg.solve(m.K.toarray(), F)
    z = m.T @ q
    planet = "stage.planet1"
    sl = m.body_slice(planet)
    pos = m.bodies[planet].position
    radial = pos / np.linalg.norm(pos)
    forces = {}
    for el in m.elements:
        if el.kind == "mesh" and planet in el.bodies:
            K_abs = m.element_stiffness_abs(el)
            f = -(K_abs @ z)[sl][:3]  # force on the planet's centre
            e = el.B @ (m.attachment_operator(el) @ z)
            assert e[0] > 0, el.name  # compression
            forces["sun" if "sun" in el.name else "ring"] = f
    fs, fr = forces["sun"], forces["ring"]
    scale = np.linalg.norm(fs)
    assert abs((fs + fr) @ radial) < 1e-9 * scale
    assert fs @ radial > 0 > fr @ radial  # sun pushes out, ring pushes in
    tang = np.cross([0, 0, 1], radial)
    assert fs @ tang == pytest.approx(fr @ tang, rel=1e-9)
    assert abs(fs[2] + fr[2]) < 1e-9 * scale


def test_bearing_matches_diagonal_in_body_axes():
    sc = load_scene("kahraman_beta0.toml")
    m = assemble(sc)
    el = [e for e in m.elements if e.kind == "bearing"][0]
    K = el.stiffness()
    np.testing.assert_allclose(np.diag(K)[:6], [3.5e8, 3.5e8, 1e8, 277.5e3, 277.5e3, 0.0])
    # a bearing to the housing has no stiffness for the housing's (absent) motion
    np.testing.assert_array_equal(K[6:, :6], -K[:6, :6])


def test_rigid_transfer_moves_points_rigidly():
    th = np.array([0.0, 0.0, 1e-3])
    P = rigid_transfer([1.0, 0, 0], [0, 0, 0])
    np.testing.assert_allclose(P @ np.concatenate([np.zeros(3), th]), [0, 1e-3, 0, 0, 0, 1e-3])
