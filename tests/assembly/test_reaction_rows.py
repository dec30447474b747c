"""The static report's rows say which bodies they are about, and its equilibrium check
measures an imbalance on the scale of the loads (assembly.reactions; conventions in its
module notes and docs/static.md)."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from assembly import Bearing, Body, LoadCase, Scene, Shaft
from assembly.reactions import equilibrium, static_report
from assembly.static import solve_static

from tests.assembly.test_static_forces import pair


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
