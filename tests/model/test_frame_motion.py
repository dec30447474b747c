"""Gravity and the housing's motion as loads (assembly.model.frame_motion) on a rigid shaft on
two bearings.

Theory. A shaft of weight W = m g, its centre of mass at c along its axis z between bearings at
z_a and z_b: the bearings carry W (z_b - c)/(z_b - z_a) and W (c - z_a)/(z_b - z_a) (the lever
rule); with the shaft tilted by tau about x the weight's axial part W sin tau goes to the axial
springs, W cos tau to the radial ones. A housing acceleration a cos(w t) along x moves the shaft
(its two radial springs k each, no damper) by the base-excitation closed form: the absolute
motion over the housing's is the transmissibility k_x / (k_x - m w^2), k_x = 2 k (the centre of
mass midway between the bearings, so that the translation does not couple with the tilt).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.model.assemble import assemble
from assembly.model.frame_motion import frame_loads, gravity_load, housing_field
from assembly.scene.schema import scene_from_dict

M_S, ZC, ZA, ZB = 100.0, 0.4, 0.0, 1.0          # kg, m
KR, KA, KT = 1.0e8, 1.0e8, 1.0e6                 # N/m, N/m, N m/rad
G = 9.80665


def _shaft(zc=ZC, c_radial=0.0):
    return assemble(scene_from_dict({
        "name": "shaft on two bearings", "fidelity": "rigid",
        "bodies": [{"name": "shaft", "mass": M_S, "polar_inertia": 2.0, "position": [0.0, 0.0, zc]}],
        "bearings": [{"body": "shaft", "position": [0.0, 0.0, z], "k_radial": KR, "k_axial": KA, "k_tilt": 0.0,
                      "k_torsion": KT, "c_radial": c_radial} for z in (ZA, ZB)]}))


def _bearing_forces(model, q):
    """(y forces, z forces) of the two bearings on the shaft (spring force -k u at each)."""
    z = model.T @ q
    u, th = z[0:3], z[3:6]
    out = []
    for zp in (ZA, ZB):
        d = np.array([0.0, 0.0, zp - ZC])
        up = u + np.cross(th, d)
        out.append((-KR * up[1], -KA * up[2]))
    return np.array(out)


@pytest.mark.parametrize("tilt", [0.0, 5.0])
def test_gravity_is_carried_by_the_lever_rule(tilt):
    model = _shaft()
    f = gravity_load(model, tilt_deg=tilt)
    q = np.linalg.solve(model.K.toarray(), f)
    F = _bearing_forces(model, q)
    W, t = M_S * G, math.radians(tilt)
    lever = np.array([(ZB - ZC) / (ZB - ZA), (ZC - ZA) / (ZB - ZA)]) * W * math.cos(t)
    # K is well conditioned here (stiffnesses 1e6..1e8 on metre lever arms): round-off 1e-12 of W
    np.testing.assert_allclose(F[:, 0], lever, rtol=0, atol=1e-12 * W * 1e2)
    # gravity turned by +tau about x has the axial component -W sin tau: the axial springs push back
    assert F[:, 1].sum() == pytest.approx(W * math.sin(t), abs=1e-10 * W)


def test_a_housing_acceleration_gives_the_base_excitation_closed_form():
    # the centre of mass midway between the bearings: the x translation is decoupled from tilt
    model = _shaft((ZA + ZB) / 2)
    K, M = model.K.toarray(), model.M.toarray()
    L = frame_loads(model)
    w = 0.5 * math.sqrt(2 * KR / M_S)
    a = np.zeros(6)
    a[0] = 1.0                                      # unit acceleration amplitude along x
    rel = np.linalg.solve(K - w ** 2 * M, L @ a)    # the motion relative to the housing
    r = housing_field(model)
    # absolute x of the centre of mass: relative + the housing's own displacement -a / w^2
    x_abs = (model.T @ rel)[0] + (r @ a)[0] * (-1.0 / w ** 2)
    want = (2 * KR) / (2 * KR - M_S * w ** 2) * (-1.0 / w ** 2)
    assert x_abs == pytest.approx(want, rel=1e-12)


def test_a_flexible_bodys_field_is_its_rigid_motion():
    # hs_parallel_stage: the flexible pinion and wheel (Craig-Bampton superelements). Moved with
    # the housing, a body's master nodes follow the rigid transfer to their positions (in the
    # body's axes), and the body strains nothing: its reduced K times its field vanishes to
    # round-off (eps x |K| |r| x the number of terms summed: measured 6e-4 and 6e-3 of it)
    from assembly.mechanics.kinematics import block_rotation, rigid_transfer
    from assembly.scene.schema import load_scene
    model = assemble(load_scene("hs_parallel_stage"))
    origin = np.array([0.1, -0.2, 0.3])
    r = housing_field(model, origin)
    flex = [b for b in model.bodies.values() if getattr(b, "rigid_local", None) is not None]
    assert len(flex) == 2
    for body in flex:
        rb = r[model.body_slice(body.name)]
        for point, idx in body.masters.values():
            want = block_rotation(body.axes).T @ rigid_transfer(point, origin)
            np.testing.assert_allclose(rb[list(idx)], want, rtol=0, atol=1e-12 * np.abs(want).max())
        Kb = np.asarray(body.K.toarray() if hasattr(body.K, "toarray") else body.K)
        assert np.abs(Kb @ rb).max() <= len(Kb) * np.finfo(float).eps * np.abs(Kb).max() * np.abs(rb).max()


@pytest.mark.parametrize("ratio", [0.5, 1.0, 2.0])
def test_a_housing_acceleration_through_damped_bearings_gives_the_transmissibility(ratio):
    # base excitation of a damped single DOF: |X_abs / X_base| = |(k + i c w) / (k - m w^2 + i c w)|;
    # the housing's load -M r a on the motion relative to it, its dampers on the relative velocity
    from assembly.model.damping import damping_matrix
    c = 0.1 * 2 * math.sqrt(2 * KR * M_S)                 # 10 % of critical in x (two bearings)
    model = _shaft((ZA + ZB) / 2, c_radial=c / 2)
    K, M, C = model.K.toarray(), model.M.toarray(), damping_matrix(model).toarray()
    w = ratio * math.sqrt(2 * KR / M_S)
    a = np.zeros(6)
    a[0] = 1.0
    rel = np.linalg.solve(K + 1j * w * C - w ** 2 * M, frame_loads(model) @ a)
    base = (housing_field(model) @ a)[0] * (-1.0 / w ** 2)   # the housing's own x: -a / w^2
    x_abs = (model.T @ rel)[0] + base
    want = (2 * KR + 1j * w * c) / (2 * KR - M_S * w ** 2 + 1j * w * c)
    assert x_abs / base == pytest.approx(want, rel=1e-12)
