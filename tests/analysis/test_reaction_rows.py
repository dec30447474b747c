"""The static report's rows say which bodies they are about, and its equilibrium check
measures an imbalance on the scale of the loads (assembly.analysis.reactions; conventions in its
module notes and docs/static.md)."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from assembly import Bearing, Body, LoadCase, Scene, Shaft
from assembly.analysis.reactions import equilibrium, static_report
from assembly.analysis.static import solve_static
from tests.analysis.test_static_forces import pair


def test_bearing_and_shaft_rows_name_their_bodies():
    """A bearing to the housing, a bearing of one body in another's frame, a shaft: each row
    names the body it acts on and what it reacts against."""
    bodies = (Body(name="a", mass=2.0, polar_inertia=1e-2),
              Body(name="b", mass=1.0, polar_inertia=5e-3, position=(0.0, 0.0, 0.3)))
    scene = Scene(name="rows", bodies=bodies,
                  bearings=(Bearing(body="a", k_radial=1e8, k_axial=1e8, k_tilt=1e6),
                            Bearing(body="b", frame="a", k_radial=1e8, k_axial=1e8, k_tilt=1e6)),
                  shafts=(Shaft(name="s", body1="a", body2="b", k_torsion=1e5),),
                  load=LoadCase(input="b", output="a", torque=10.0))
    r = static_report(solve_static(scene, scene.load))
    assert [(row["body"], row["frame"]) for row in r.bearings] == [("a", "housing"), ("b", "a")]
    (shaft,) = r.shafts
    assert (shaft["body1"], shaft["body2"]) == ("a", "b")
    # the shaft carries the torque from b to the held a: body1 (a) lags, so its torque is -10 N m
    assert shaft["torque_Nm"] == pytest.approx(-10.0, rel=1e-12)


def test_axial_mesh_force_is_along_gear_1s_axis():
    """The mesh row's axial force is read along gear 1's axis (module notes); a bearing's
    reaction is in its own body's axes. A wheel modelled with its axis reversed (-z) changes
    neither the forces nor gear 1's reading: only the wheel bearing's local Fz changes sign."""
    sc = pair(beta=0.3)
    flipped = dataclasses.replace(sc, bodies=(sc.bodies[0], dataclasses.replace(sc.bodies[1], axis=(0, 0, -1))))
    a, b = (static_report(solve_static(s, s.load)) for s in (sc, flipped))
    assert b.meshes[0]["axial_N"] == pytest.approx(a.meshes[0]["axial_N"], rel=1e-12)
    assert abs(a.meshes[0]["axial_N"]) > 100.0
    assert b.bearings[0]["Fz_N"] == pytest.approx(a.bearings[0]["Fz_N"], rel=1e-12)
    assert b.bearings[1]["Fz_N"] == pytest.approx(-a.bearings[1]["Fz_N"], rel=1e-12)


def test_equilibrium_of_a_couple_is_fully_unbalanced():
    """Two opposite 1 N forces 1 m apart: no net force, a net couple of 1 N m. Its moment
    about the first force's point is the whole moment scale (sum |M_i| + |p_i - o| |F_i| =
    1 N m), so the relative error is exactly 1; about any point, the net moment is the same
    couple (a couple is free)."""
    w1, w2 = np.array([1.0, 0, 0, 0, 0, 0]), np.array([-1.0, 0, 0, 0, 0, 0])
    p1, p2 = np.array([0.0, 1.0, 0.0]), np.array([0.0, 2.0, 0.0])
    e = equilibrium([(w1, p1), (w2, p2)], p1)
    assert e["force_N"] == [0.0, 0.0, 0.0]
    np.testing.assert_allclose(e["moment_Nm"], [0.0, 0.0, 1.0], atol=1e-15)
    assert e["relative_error"] == pytest.approx(1.0, rel=1e-15)
    far = equilibrium([(w1, p1), (w2, p2)], np.array([3.0, -4.0, 0.0]))
    np.testing.assert_allclose(far["moment_Nm"], [0.0, 0.0, 1.0], atol=1e-14)
    # about (3, -4, 0) the arms are |p1 - o| = sqrt(34), |p2 - o| = sqrt(45): the scale they give
    assert far["relative_error"] == pytest.approx(1.0 / (math.sqrt(34.0) + math.sqrt(45.0)), rel=1e-14)


def test_shaft_section_load_is_in_body1s_axes():
    """The shaft's section load is read in body1's axes (docs/static.md): body2 modelled with
    its axis reversed changes nothing about a torque T into body1 held at body2 -- the
    shaft carries +T about body1's axis (body1 twisted ahead) either way."""
    def scene(axis2):
        bodies = (Body(name="a", mass=2.0, polar_inertia=1e-2),
                  Body(name="b", mass=1.0, polar_inertia=5e-3, position=(0.0, 0.0, 0.3), axis=axis2))
        return Scene(name="shaft axes", bodies=bodies,
                     bearings=(Bearing(body="a", k_radial=1e8, k_axial=1e8, k_tilt=1e6),
                               Bearing(body="b", k_radial=1e8, k_axial=1e8, k_tilt=1e6)),
                     shafts=(Shaft(name="s", body1="a", body2="b", k_torsion=1e5),),
                     load=LoadCase(input="a", output="b", torque=10.0))
    for axis2 in ((0, 0, 1), (0, 0, -1)):
        sc = scene(axis2)
        (shaft,) = static_report(solve_static(sc, sc.load)).shafts
        assert shaft["torque_Nm"] == pytest.approx(10.0, rel=1e-12), axis2


def test_mesh_rows_name_both_gears():
    r = static_report(solve_static(pair(), pair().load))
    (m,) = r.meshes
    assert (m["gear1"], m["gear2"]) == ("pinion", "wheel")


def test_torque_balance_counts_the_moment_of_the_other_loads():
    """A torque case with a point force beside the torque: about the input axis the input
    torque, the output reaction, the housing reactions and the force's own moment sum to
    zero; the force's moment is its arm times its tangential part (0.2 m x 50 N = 10 N m)."""
    from assembly.scene.tables import PointLoad
    lc = LoadCase(input="pinion", output="wheel", torque=100.0,
                  forces=(PointLoad(body="pinion", force=(0.0, 50.0, 0.0), point=(0.2, 0.0, 0.0)),))
    sc = dataclasses.replace(pair(), load=lc)
    r = static_report(solve_static(sc, lc))
    assert r.balance["loads_Nm"] == pytest.approx(10.0, rel=1e-12)
    assert r.balance["relative_error"] < 1e-10


def test_a_rigid_bearing_direction_reports_its_constraint_reaction_in_the_bearing_row():
    """A bearing rigid axially (k_axial = inf) holds the helical pair's thrust as a constraint:
    its row reports the same axial reaction as a stiff spring would (statics: the thrust is
    the mesh's, whatever holds it)."""
    sc = pair(beta=0.3)
    rigid = dataclasses.replace(sc, bearings=tuple(dataclasses.replace(b, k_axial=math.inf) for b in sc.bearings))
    a = static_report(solve_static(sc, sc.load))
    b = static_report(solve_static(rigid, rigid.load))
    for ra, rb in zip(a.bearings, b.bearings):
        assert abs(ra["Fz_N"]) > 100.0
        assert rb["Fz_N"] == pytest.approx(ra["Fz_N"], rel=1e-9)
