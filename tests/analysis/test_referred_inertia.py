"""Inertia referred to a shaft: twice the rigid-body mode's kinetic energy with that shaft at
1 rad/s; for two gears on fixed axes J_ref,1 = J1 + J2 (r1 / r2)^2 (the wheel turns at
r1 / r2 of the pinion's speed; e.g. Shigley's Mechanical Engineering Design, reflected
inertia of a gear train)."""
import math

import pytest

from assembly import Bearing, Body, GearMesh, Scene, load_scene
from assembly.analysis.modal import solve_modes
from assembly.analysis.referred import referred_inertia, referred_inertias
from assembly.app.report.tables import modes_json, modes_table
from assembly.errors import MechanismError, SceneError
from assembly.model.assemble import assemble

J1, J2, R1, R2, ALPHA = 3.0e-3, 4.0e-2, 0.05, 0.1, math.radians(20.0)


def pair(**bearing):
    return Scene(
        name="pair",
        bodies=(Body(name="g1", mass=2.0, polar_inertia=J1),
                Body(name="g2", mass=5.0, polar_inertia=J2, position=((R1 + R2) / math.cos(ALPHA), 0.0, 0.0))),
        bearings=tuple(Bearing(body=b, k_radial=3.5e8, k_axial=1.0e8, k_tilt=2.8e5, **bearing) for b in ("g1", "g2")),
        meshes=(GearMesh(gear1="g1", gear2="g2", stiffness=2.0e8, base_radius1=R1, base_radius2=R2,
                         pressure_angle=ALPHA),))


def test_two_gears_referred_to_either_shaft():
    model = assemble(pair())
    # the rigid-body mode is a null vector of K found numerically: its ratios hold to ~1e-12
    assert referred_inertia(model, "g1") == pytest.approx(J1 + J2 * (R1 / R2) ** 2, rel=1e-9)
    assert referred_inertia(model, "g2") == pytest.approx(J2 + J1 * (R2 / R1) ** 2, rel=1e-9)
    assert referred_inertias(model) == pytest.approx({"g1": J1 + J2 * (R1 / R2) ** 2,
                                                      "g2": J2 + J1 * (R2 / R1) ** 2}, rel=1e-9)


def test_no_rigid_body_mode_and_bad_names_are_refused():
    with pytest.raises(MechanismError):
        referred_inertia(assemble(pair(k_torsion=1e4)), "g1")   # the bearings hold the rotation
    with pytest.raises(SceneError):
        referred_inertia(assemble(pair()), "g3")


def test_modes_report_has_gear_and_referred_tables():
    res = solve_modes(assemble(pair()))
    text = modes_table(res)
    assert "gear meshes: geometry" in text and "inertia referred to each shaft" in text
    assert f"{J1 + J2 * (R1 / R2) ** 2:.6g}" in text
    js = modes_json(res)
    assert js["referred_inertia_kgm2"]["g2"] == pytest.approx(J2 + J1 * (R2 / R1) ** 2, rel=1e-9)
    assert js["gears"][0]["centre_distance_m"] == pytest.approx((R1 + R2) / math.cos(ALPHA), rel=1e-12)
    # a model without a rigid-body mode says why instead of a table
    held = modes_table(solve_modes(assemble(pair(k_torsion=1e4))))
    assert "no referred inertia:" in held


def test_planetary_referred_to_carrier_counts_orbiting_planets():
    # Lin & Parker N = 3, ring held in torsion: with the carrier at 1 rad/s the sun turns at
    # 1 + r_r / r_s, each planet at 1 - r_r / r_p (absolute) and orbits at the carrier
    # radius R_c = (r_s + r_p) / cos(alpha) (base radii, one pressure angle; Lin & Parker
    # 1999 kinematics): J_c + J_s (1 + r_r/r_s)^2 + N (J_p (1 - r_r/r_p)^2 + m_p R_c^2)
    sc = load_scene("lin_parker_n3")
    st = sc.stages[0]
    rs, rp, rr = st.sun.base_radius, st.planets.base_radius, abs(st.ring.base_radius)
    Rc = (rs + rp) / math.cos(st.pressure_angle_sun)
    n, p = st.planets.count, st.planets
    want = (st.carrier.polar_inertia + st.sun.polar_inertia * (1 + rr / rs) ** 2
            + n * (p.polar_inertia * (1 - rr / rp) ** 2 + p.mass * Rc ** 2))
    assert referred_inertia(assemble(sc), "stage.carrier") == pytest.approx(want, rel=1e-9)


def test_a_shape_that_is_no_rigid_body_mode_is_refused():
    """referred_inertias(model, shape): the rigid-body mode of the modal result gives the same
    numbers as the one found from the springs; an elastic mode (its springs strained), a
    shape of the wrong length or with a NaN is refused naming ``shape``."""
    import numpy as np

    from assembly import SceneError, assemble, load_scene, solve_modes
    from assembly.analysis.referred import referred_inertias

    m = assemble(load_scene("kahraman_beta20"))
    r = solve_modes(m)
    assert r.n_rigid == 1
    found = referred_inertias(m)
    given = referred_inertias(m, r.abs_shapes[:, 0])
    assert given.keys() == found.keys()
    for b in found:
        assert given[b] == pytest.approx(found[b], rel=1e-9)
    for bad in (r.abs_shapes[:, 1], r.abs_shapes[:-1, 0], np.full(m.n_abs, np.nan)):
        with pytest.raises(SceneError) as e:
            referred_inertias(m, bad)
        assert e.value.path == "shape"
