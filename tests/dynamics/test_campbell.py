"""Campbell diagram (assembly.dynamics): orders, Parker's phasing rule, gyroscopic whirl,
crossings.

Closed forms used below:

* A fixed-axis gear of z teeth turning at n rpm engages z n / 60 teeth per second: the mesh
  frequency (Hz); its mate (z2 teeth, n2 = n z / z2) gives the same z2 n2 / 60.
* Planetary stage, ring fixed (Willis): n_carrier = n_sun Z_s / (Z_s + Z_r); the mesh
  frequency is the sun's teeth times its speed relative to the carrier,
  Z_s |n_s - n_c| / 60 = Z_s n_s Z_r / (Z_s + Z_r) / 60 = Z_r |n_c| / 60.
* Parker (2000), J. Sound Vib. 236(4), 561-573: N equally spaced planets, sun teeth Z_s, mesh
  harmonic h: rotational modes only if h Z_s / N is an integer, translational only if
  (h Z_s +- 1) / N is, otherwise planet modes only.
* A disc (polar J_p, transverse J_t) spinning at Omega on isotropic tilt springs k:
  J_t th_x'' + J_p Omega th_y' + k th_x = 0, J_t th_y'' - J_p Omega th_x' + k th_y = 0; with
  th_x + i th_y = exp(i w t): J_t w^2 - J_p Omega w - k = 0, so the forward and backward
  whirl are w = +- a + sqrt(a^2 + k / J_t), a = Omega J_p / (2 J_t) (rad/s).
"""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from assembly import Bearing, Body, Scene, SceneError, assemble
from assembly.analysis.modal import solve_modes
from assembly.dynamics.campbell import NEGLIGIBLE, campbell, check_speed_range, line_crossings
from assembly.dynamics.gyroscopic import gyroscopic_matrix, whirl_frequencies
from assembly.dynamics.phasing import equally_spaced, excited_class
from assembly.scene.schema import load_scene
from tests.support.campbell_scene import campbell_scene

Z_PINION, Z_WHEEL, Z_SUN, Z_RING = 21, 83, 20, 80   # tests/support/campbell_scene.py


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    p = tmp_path_factory.mktemp("campbell") / "pair_planetary.toml"
    p.write_text(campbell_scene())
    return load_scene(str(p))


def _order(c, name):
    return next(o for o in c.orders if o.name == name)


@pytest.mark.parametrize("reference, z", [("pinion", Z_PINION), ("wheel", Z_WHEEL)])
def test_fixed_axis_mesh_frequency_is_teeth_times_speed(small, reference, z):
    # the reference gear's own teeth: f = h z n / 60 (its mate's teeth give the same)
    c = campbell(small, (0.0, 1000.0), reference=reference)
    for h in (1, 2, 3):
        assert _order(c, f"pinion-wheel mesh x{h}").hz_per_rpm == pytest.approx(h * z / 60.0, rel=1e-12)


def test_planetary_mesh_frequency_relative_to_carrier(small):
    # pinion at n: sun at n Z_PINION / Z_WHEEL (external pair; the sense drops out),
    # carrier at n_s Z_s / (Z_s + Z_r); Willis: Z_s |n_s - n_c| / 60 = Z_r |n_c| / 60
    c = campbell(small, (0.0, 1000.0))
    n_s = Z_PINION / Z_WHEEL
    n_c = n_s * Z_SUN / (Z_SUN + Z_RING)
    assert abs(c.ratios["planetary.sun"]) == pytest.approx(n_s, rel=1e-12)
    assert abs(c.ratios["planetary.carrier"]) == pytest.approx(n_c, rel=1e-12)
    for h in (1, 2, 3):
        f = _order(c, f"planetary mesh x{h}").hz_per_rpm
        assert f == pytest.approx(h * Z_SUN * (n_s - n_c) / 60.0, rel=1e-12)
        assert f == pytest.approx(h * Z_RING * n_c / 60.0, rel=1e-12)


# Parker (2000) rule applied by hand to Z_s = 19 (NREL 5 MW stage 1, Nejad et al. 2016,
# Table V), h Z_s = 19, 38, 57, 76, 95, 114 for h = 1..6:
#   N = 3: remainders 1, 2, 0, 1, 2, 0 -> (h Z_s -+ 1)/3 integer except h = 3, 6 (rotational)
#   N = 4: remainders 3, 2, 1, 0, 3, 2 -> 3 and 1 translational, 0 rotational, 2 planet
#   N = 5: remainders 4, 3, 2, 1, 0, 4 -> 4 and 1 translational, 0 rotational, 3 and 2 planet
R, T, P = "rotational", "translational", "planet"
PARKER_19 = {3: (T, T, R, T, T, R), 4: (T, P, T, R, T, P), 5: (T, P, P, T, R, T)}


@pytest.mark.parametrize("n_planets", sorted(PARKER_19))
def test_parker_phasing_rule_sun_19_teeth(n_planets):
    got = tuple(excited_class(h, 19, n_planets) for h in range(1, 7))
    assert got == PARKER_19[n_planets]


@pytest.mark.parametrize("bad", [0, -1, 1.0, True])
def test_parker_rule_refuses_non_positive_or_non_integer(bad):
    for args in ((bad, 19, 3), (1, bad, 3), (1, 19, bad)):
        with pytest.raises(ValueError, match="integer >= 1"):
            excited_class(*args)


def test_equally_spaced():
    third = 2 * math.pi / 3
    assert equally_spaced((0.0, third, 2 * third))
    assert equally_spaced((1.0, 1.0 + third, 1.0 + 2 * third))      # any starting angle
    assert not equally_spaced(tuple(math.radians(a) for a in (0.0, 86.4, 180.0, 266.4)))


def test_phasing_verdicts_of_the_small_stage(small):
    # Z_s = 20, N = 4: 20 h / 4 is an integer for every h -> only rotational modes of the
    # stage can be excited; its translational and planet modes cannot
    c = campbell(small, (0.0, 3000.0))
    rows = [x for x in c.crossings if x.order.startswith("planetary mesh") and x.scope in ("planetary", "global")]
    judged = {(x.mode_class, x.excitable) for x in rows if x.mode_class in (R, T, P)}
    assert (T, False) in judged and (P, False) in judged and (R, True) in judged
    assert all(ok == (cls == R) for cls, ok in judged)
    # parallel meshes and rotor orders excite every class their exciter takes part in: ruled
    # out exactly where it holds none of the mode's energy
    others = [x for x in c.crossings if not x.order.startswith("planetary")]
    assert others and all(x.excitable is (x.share >= NEGLIGIBLE) for x in others)


def test_unequal_planets_leave_the_rule_undecided(tmp_path):
    p = tmp_path / "unequal.toml"
    p.write_text(campbell_scene((0.0, 86.4, 180.0, 266.4)))
    c = campbell(load_scene(str(p)), (0.0, 3000.0))
    rows = [x for x in c.crossings if re.fullmatch(r"planetary mesh x\d+", x.order) and x.share >= NEGLIGIBLE]
    assert rows and all(x.excitable is None and "not equally spaced" in x.rule for x in rows)
    assert any("not equally spaced" in n for n in c.notes)


JP, JT, K_TILT = 2.0, 1.5, 1.0e4     # kg m^2, kg m^2, N m/rad


def _disc() -> Scene:
    inf = math.inf
    return Scene(name="spinning disc", bodies=(Body(name="disc", mass=10.0, polar_inertia=JP, transverse_inertia=JT,
                                                    role="rotor"),),
                 bearings=(Bearing(body="disc", k_radial=inf, k_axial=inf, k_tilt=K_TILT),))


def _whirl_hz(omega):
    a = omega * JP / (2 * JT)
    s = math.sqrt(a * a + K_TILT / JT)
    return np.array([s - a, s + a]) / (2 * math.pi)


@pytest.mark.parametrize("omega", [0.0, 30.0, 150.0, 1000.0])
def test_gyroscopic_disc_forward_and_backward_whirl(omega):
    model = assemble(_disc())
    res = solve_modes(model)
    assert res.n_rigid == 1          # the free spin
    f = whirl_frequencies(model.K, model.M, gyroscopic_matrix(model, {"disc": omega}), res.n_rigid)
    assert f == pytest.approx(_whirl_hz(omega), rel=1e-9)


def test_gyroscopic_campbell_of_the_disc():
    c = campbell(_disc(), (0.0, 6000.0), points=61, gyroscopic=True)
    for n, f in zip(c.speeds_rpm, c.frequencies_hz):
        assert f == pytest.approx(_whirl_hz(n * 2 * math.pi / 60.0), rel=1e-9)
    # the 1P line (w = Omega) meets the forward whirl where (J_t - J_p) w^2 = k: never for
    # J_p > J_t; the backward whirl where (J_t + J_p) w^2 = k. Between sampled speeds the
    # line is interpolated linearly: the crossing lies in the same 100 rpm step as the exact one
    x = [r for r in c.crossings if r.order == "1P"]
    assert len(x) == 1 and x[0].mode == 2
    exact = math.sqrt(K_TILT / (JT + JP)) * 60 / (2 * math.pi)
    assert math.floor(x[0].speed_rpm / 100.0) == math.floor(exact / 100.0)


def test_crossing_of_a_constant_line_is_exact():
    f0, a = 37.3, 0.123
    assert line_crossings([0.0, 100.0, 1000.0], [f0] * 3, a) == [(f0 / a, f0)]
    assert line_crossings([0.0, 100.0], [f0] * 2, a) == []                 # f0 / a = 303 rpm: outside
    # a line f0 + b n meets a n at n = f0 / (a - b); linear in n, so interpolation is exact to round-off
    b = 0.02
    n = np.linspace(0.0, 1000.0, 7)
    ((x, f),) = line_crossings(n, f0 + b * n, a)
    assert x == pytest.approx(f0 / (a - b), rel=1e-12) and f == pytest.approx(a * f0 / (a - b), rel=1e-12)


def test_nrel5mw_campbell_stage3_mesh_crosses_every_mode_in_band():
    # orders per rotor rpm, ring fixed in stages 1 and 2 (Nejad et al. 2016, Table V teeth):
    # stage 1 carrier = rotor: Z_r / 60 = 56/60; stage 2 carrier = stage-1 sun, 1 + 56/19;
    # stage 3 wheel = stage-2 sun, (1 + 56/19)(1 + 93/18), 95 teeth
    c = campbell(load_scene("nrel5mw"), (0.0, 15.0))
    s1, s2 = 1 + 56 / 19, (1 + 56 / 19) * (1 + 93 / 18)
    assert _order(c, "stage1 mesh x1").hz_per_rpm == pytest.approx(56 / 60, rel=1e-12)
    assert _order(c, "stage2 mesh x1").hz_per_rpm == pytest.approx(93 * s1 / 60, rel=1e-12)
    a = _order(c, "stage3 mesh x1").hz_per_rpm
    assert a == pytest.approx(95 * s2 / 60, rel=1e-12)
    # constant lines: every elastic mode below a x 15 rpm is crossed once, at f / a
    below = {m.index + 1: m.frequency_hz for m in c.modes if m.frequency_hz <= 15 * a}
    rows = {x.mode: x for x in c.crossings if x.order == "stage3 mesh x1"}
    assert set(rows) == set(below) and len(below) > 20
    for k, f in below.items():
        assert rows[k].speed_rpm == f / a and rows[k].frequency_hz == f
    # Parker on stage 1 (Z_s = 19, N = 3): h = 3 reaches rotational modes, h = 1 translational
    assert excited_class(3, 19, 3) == R and excited_class(1, 19, 3) == T
    assert all(x.excitable is not True or x.mode_class == T for x in c.crossings if x.order == "stage1 mesh x1")


@pytest.mark.parametrize("rng", [(5.0, 1.0), (3.0, 3.0), (-1.0, 5.0), (0.0, -2.0), (math.nan, 1.0), (0.0, math.inf)])
def test_bad_speed_range(rng):
    with pytest.raises(SceneError) as err:
        check_speed_range(rng)
    assert err.value.path.split("[")[0] == "speed_range"


@pytest.mark.parametrize("kw, path", [(dict(reference="nope"), "reference"), (dict(points=1), "points"),
                                      (dict(harmonics=0), "harmonics")])
def test_bad_arguments(small, kw, path):
    with pytest.raises(SceneError) as err:
        campbell(small, (0.0, 100.0), **kw)
    assert err.value.path == path


def test_scene_without_a_free_chain():
    # torsion held by the bearing: no rigid-body mode, nothing to spin
    held = Scene(name="held", bodies=(Body(name="disc", mass=1.0, polar_inertia=1.0, role="rotor"),),
                 bearings=(Bearing(body="disc", k_radial=1e8, k_axial=1e8, k_tilt=1e5, k_torsion=1e5),))
    with pytest.raises(SceneError) as err:
        campbell(held, (0.0, 100.0))
    assert err.value.path == "SCENE" and "no free chain" in str(err.value)


def test_crossings_rank_by_the_exciters_share_of_the_mode(small, tmp_path):
    # every crossing whose exciter holds none of the mode's energy comes below every one whose
    # exciter holds a positive share
    ranked = campbell(small, (0.0, 3000.0)).ranked()
    zero = [i for i, x in enumerate(ranked) if x.share < NEGLIGIBLE]
    positive = [i for i, x in enumerate(ranked) if x.share >= NEGLIGIBLE and x.excitable is not False]
    assert zero and positive and max(positive) < min(zero)
    # ruled out, by the phasing rule or for want of a modal force
    assert all(x.excitable is False for x in ranked if x.share < NEGLIGIBLE)
    assert any("no modal force" in x.rule for x in ranked)


def test_a_pairs_shares_are_the_closed_form(tmp_path):
    # a torsional pair (J1 = 2, J2 = 0.5 kg m^2, base radii 0.05 / 0.15 m) has one elastic mode and
    # one spring: the mesh holds all of its strain energy. The mode is mass-orthogonal to the
    # rigid turning (theta2 = -(r1/r2) theta1), so theta2 = J1 r2 theta1 / (J2 r1) and the rotor's
    # spin holds J2 r1^2 / (J2 r1^2 + J1 r2^2) = 0.027 of its kinetic energy
    from tests.app.test_simulate_cli import pair_file
    c = campbell(load_scene(pair_file(tmp_path, mesh="variation = { amplitudes = [0.1], teeth = 20 }")),
                 (0.0, 4000.0))
    mesh = [x for x in c.crossings if x.order.startswith("m mesh")]
    rotor = [x for x in c.crossings if x.order.endswith("P")]
    assert mesh and rotor
    assert all(x.share == pytest.approx(1.0, rel=1e-9) and x.excitable for x in mesh)
    j1, j2, r1, r2 = 2.0, 0.5, 0.05, 0.15
    assert all(x.share == pytest.approx(j2 * r1 ** 2 / (j2 * r1 ** 2 + j1 * r2 ** 2), rel=1e-9) for x in rotor)


def test_shaft_planet_pass_and_sideband_orders_follow_the_chain(small):
    # each turning body's 1x at |ratio| n / 60; the stage's planet pass N |n_c - n_ring| / 60; the
    # mesh's first sidebands f_mesh -+ |n_c - n_ring| / 60 (a planet's once-round against the
    # ring); rotor orders only when the reference is a rotor
    c = campbell(small, (0.0, 3000.0))
    by = {o.name: o for o in c.orders}
    r = c.ratios
    for o in (o for o in c.orders if o.kind == "shaft"):
        assert o.hz_per_rpm == pytest.approx(abs(r[o.source]) / 60.0, rel=1e-12)
    speeds = {round(abs(v), 9) for v in r.values() if v != 0}
    assert len([o for o in c.orders if o.kind == "shaft"]) == len(speeds)
    carrier = abs(r["planetary.carrier"] - r["planetary.ring"]) / 60.0
    assert by["planetary planet pass"].hz_per_rpm == pytest.approx(4 * carrier, rel=1e-12)
    mesh = by["planetary mesh x1"].hz_per_rpm
    assert by["planetary mesh x1 +1"].hz_per_rpm == pytest.approx(mesh + carrier, rel=1e-12)
    assert by["planetary mesh x1 -1"].hz_per_rpm == pytest.approx(mesh - carrier, rel=1e-12)
    rotor = any(b.role == "rotor" and b.name == c.reference for b in small.bodies)
    assert rotor == any(o.kind == "rotor" for o in c.orders)


def test_no_rotor_orders_without_a_rotor_as_reference():
    # the quill drive has no rotor: its pinion as the reference draws no 1P/3P/6P lines
    c = campbell(load_scene("two_stage_quill"), (0.0, 3000.0), reference="pinion")
    assert not any(o.kind == "rotor" for o in c.orders) and any(o.kind == "shaft" for o in c.orders)


def test_a_shaft_line_takes_the_share_of_every_body_turning_at_its_speed():
    """g2 and g3 turn at one speed (a shaft joins them): one 1x line. A mode held by g3 (a
    heavy disc on soft bearings, its kinetic energy ~all in g3) is driven by an unbalance of
    g3: its crossing with the line has g3's share, not g2's alone (which is ~0 there)."""
    from assembly import GearMesh, Shaft
    from assembly.dynamics.participation import body_kinetic_shares

    r1, r2, a = 0.05, 0.1, math.radians(20)
    x2 = (r1 + r2) / math.cos(a)
    sc = Scene(name="trio",
               bodies=(Body(name="g1", mass=2.0, polar_inertia=3e-3),
                       Body(name="g2", mass=5.0, polar_inertia=4e-2, position=(x2, 0, 0)),
                       Body(name="g3", mass=50.0, polar_inertia=1.0, position=(x2, 0, 0.5))),
               bearings=(Bearing(body="g1", k_radial=3.5e8, k_axial=1e8, k_tilt=2.8e5),
                         Bearing(body="g2", k_radial=3.5e8, k_axial=1e8, k_tilt=2.8e5),
                         Bearing(body="g3", k_radial=1e6, k_axial=1e8, k_tilt=1e4)),
               shafts=(Shaft(body1="g2", body2="g3", k_torsion=1e6, k_bending=1e3, k_axial=1e8, k_shear=1e5),),
               meshes=(GearMesh(gear1="g1", gear2="g2", stiffness=2e8, base_radius1=r1, base_radius2=r2,
                                pressure_angle=a),))
    m = assemble(sc)
    c = campbell(m, (0.0, 30000.0), reference="g1")
    line = next(o for o in c.orders if o.kind == "shaft" and "g3" in o.bodies)
    assert set(line.bodies) == {"g2", "g3"}
    res = solve_modes(m)
    both = body_kinetic_shares(m, res, "g2") + body_kinetic_shares(m, res, "g3")
    on = [x for x in c.crossings if x.order == line.name]
    assert on
    for x in on:
        assert x.share == pytest.approx(both[x.mode - 1], rel=1e-12)
    g3_modes = [x for x in on if body_kinetic_shares(m, res, "g3")[x.mode - 1] > 0.9]
    assert g3_modes and all(x.excitable is not False for x in g3_modes)
