"""The life tables of a run (``[simulation.life]``, assembly.dynamics.life_tables) against closed
forms.

Theory.
* ISO 281:2007: a bearing's basic rating life L10 = (C / P)^p million revolutions, P the dynamic
  equivalent load X F_r + Y F_a; under a load varying in steps P is the mean of the levels
  weighted by their revolutions with exponent p, (sum P_i^p n_i / sum n_i)^(1/p) (also Harris &
  Kotzalas, Rolling Bearing Analysis, 2006). At a constant speed n (rev/s) the life in hours is
  L10 1e6 / n / 3600.
* A rigid shaft on one bearing under constant forces at rest in its static equilibrium (the run
  starts there) keeps them: the bearing carries the forces exactly, whatever the spin.
* A gear pair in static balance (input torque T1 = r1 F, output T2 = r2 F) carries the mesh force
  F = T1 / r1 at every step; each tooth of gear i meets its mate once per revolution, so a run
  of T seconds at omega_i gives omega_i T / 2 pi load cycles; Palmgren-Miner's damage for the S-N
  curve N_f = N_ref (T_ref / T)^k is D = n (T / T_ref)^k / N_ref.
* A planetary stage: a tooth of the sun, of a planet or of the ring meets its mate once per
  revolution relative to the carrier (Willis), |omega_gear - omega_carrier| T / 2 pi cycles.
"""
from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from assembly.dynamics.life_tables import bearing_rows, check_life, gear_rows
from assembly.dynamics.simulate import simulate
from assembly.errors import SceneError
from assembly.model.assemble import assemble
from assembly.scene.schema import load_scene
from assembly.scene.time_domain import GearRating, LifeTables
from tests.app.test_simulate_cli import pair_file

SHAFT = """
name = "shaft on a bearing"
[[bodies]]
name = "shaft"
mass = 50.0
polar_inertia = 1.0
fidelity = "rigid"
role = "rotor"
[[bearings]]
name = "B"
body = "shaft"
k_radial = 1.0e8
k_axial = 1.0e8
k_tilt = 1.0e6
c_radial = 2.0e3
c_axial = 2.0e3
c_tilt = 20.0
{more}
[simulation]
speed = {speed}
loads = [{{ body = "shaft", kind = "force", direction = [1.0, 0.0, 0.0], value = 1000.0 }},
         {{ body = "shaft", kind = "force", direction = [0.0, 0.0, 1.0], value = 400.0 }}]
[simulation.life]
{life}
"""
RATED = 'bearings = [{ bearing = "B", rating = 5.0e4, exponent = 3.0, radial_factor = 0.4, axial_factor = 1.5 }]'


def shaft_scene(tmp_path, life: str = RATED, speed: float = 10.0, more: str = ""):
    p = tmp_path / "shaft.toml"
    p.write_text(SHAFT.format(life=life, speed=speed, more=more), encoding="utf-8")
    return load_scene(p)


def test_a_constant_load_gives_iso_281_l10(tmp_path):
    # P = X F_r + Y F_a = 0.4 x 1000 + 1.5 x 400 = 1000 N; L10 = (5e4 / 1e3)^3 = 1.25e5 million rev
    omega, t_end = 10.0, 0.2
    r = simulate(shaft_scene(tmp_path, speed=omega), t_end, 1e-3, [])
    (b,) = r.life.bearings
    # the static start to Newton's tolerance (1e-10 of the forces), the trapezoid exact on a
    # constant speed (the spin has no spring: it turns freely)
    assert b.equivalent_load_n == pytest.approx(1000.0, rel=1e-9)
    assert b.revolutions == pytest.approx(omega * t_end / (2 * math.pi), rel=1e-12)
    assert b.l10_mrev == pytest.approx((5.0e4 / 1.0e3) ** 3, rel=3e-9)
    assert b.l10_hours == pytest.approx(1.25e5 * 1e6 / (omega / (2 * math.pi)) / 3600, rel=3e-9)
    assert b.note == ""
    # the run's JSON carries the table (finite numbers only)
    doc = json.loads(json.dumps(r.as_json(), allow_nan=False))
    assert doc["life"]["bearings"][0]["l10_mrev"] == b.l10_mrev


def test_a_two_level_spectrum_gives_the_iso_281_mean_load(tmp_path):
    # the same model read through a chosen history: F_r at 1000 N for the first 300 intervals at
    # 10 rad/s and at 2000 N for the next 100 at 30 rad/s -> revolutions 300 and 300 x 1/... per
    # interval h: n1 = 300 x 10 h / 2pi, n2 = 100 x 30 h / 2pi (equal), P = ((1e3^p + 2e3^p) / 2)^(1/p)
    scene = shaft_scene(tmp_path, life='bearings = [{ bearing = "B", rating = 5.0e4 }]')     # p = 10/3
    model = assemble(scene)
    h = 1e-3
    t = np.arange(401) * h
    fx = np.where(np.arange(401) < 300, 1000.0, 2000.0)
    w = np.where(np.arange(401) < 300, 10.0, 30.0)
    w[300] = 10.0                                  # the interval 299-300 at 10 rad/s on both ends
    w[301:] = 30.0
    hist = {"force:B:x": fx, "force:B:y": np.zeros(401), "speed:shaft": w}
    # the interval 300-301 is held at level fx[300] = 2000 N and turns (10 + 30)/2 h / 2pi
    n1 = 300 * 10.0 * h / (2 * np.pi)
    n2 = (20.0 + 99 * 30.0) * h / (2 * np.pi)
    p = 10.0 / 3.0
    (b,) = bearing_rows(model, scene.simulation.life, t, hist.__getitem__)
    want = ((1e3 ** p * n1 + 2e3 ** p * n2) / (n1 + n2)) ** (1 / p)
    assert b.revolutions == pytest.approx(n1 + n2, rel=1e-12)
    assert b.equivalent_load_n == pytest.approx(want, rel=1e-12)
    assert b.l10_mrev == pytest.approx((5.0e4 / want) ** p, rel=1e-11)


def test_a_bearing_that_does_not_turn_has_no_l10(tmp_path):
    r = simulate(shaft_scene(tmp_path, speed=0.0), 0.05, 1e-3, [])
    (b,) = r.life.bearings
    assert b.l10_mrev is None and b.l10_hours is None and b.equivalent_load_n is None
    assert "does not turn" in b.note


# the torsional pair of tests/app/test_simulate_cli.py (rotor r_b 0.05 m, generator 0.15 m, a linear
# mesh), 100 N m on the rotor against 300 N m on the generator, at 10 rad/s
LOADS = 'loads = [{ body = "rotor", value = 100.0 }]\ngenerator = { torque = 300.0 }\n'
GEARS = ('[simulation.life]\ngears = [{ mesh = "m", torque_ref = 80.0, cycles_ref = 1.0e6, slope = 6.0 }, '
         '{ mesh = "m", gear = "generator", torque_ref = 200.0, cycles_ref = 1.0e7, slope = 8.0, torque_limit = 100.0 }]')


def pair(tmp_path, gears: str = GEARS):
    return load_scene(pair_file(tmp_path, sim=LOADS + gears))


def test_a_balanced_pair_gives_miner_damage_of_its_torque(tmp_path):
    t_end = 0.5
    r = simulate(pair(tmp_path), t_end, 1e-4, ["force:m"])
    pin, wheel = r.life.gears
    # F = 100 / 0.05 = 2000 N from the static start on (a linear mesh); T on each gear r_i F
    assert pin.peak_torque == pytest.approx(100.0, rel=1e-9) and wheel.peak_torque == pytest.approx(300.0, rel=1e-9)
    n_pin, n_wheel = 10.0 * t_end / (2 * math.pi), 10.0 / 3.0 * t_end / (2 * math.pi)
    assert pin.cycles == pytest.approx(n_pin, rel=1e-9) and wheel.cycles == pytest.approx(n_wheel, rel=1e-9)
    assert pin.torque_eq == pytest.approx(100.0, rel=1e-9)
    assert pin.damage == pytest.approx(n_pin * (100.0 / 80.0) ** 6 / 1e6, rel=1e-8)
    assert wheel.damage == pytest.approx(n_wheel * (300.0 / 200.0) ** 8 / 1e7, rel=1e-8)
    assert pin.life_hours == pytest.approx(t_end / pin.damage / 3600, rel=1e-12)
    # the DEL table of the output asked for: a constant force, cycles of its round-off alone (the
    # step's Newton tolerance, 1e-10 of the forces, against 2000 N)
    assert max(r.life.outputs["force:m"].dels.values()) <= 1e-9 * 2000.0


def test_below_the_endurance_limit_there_is_no_damage(tmp_path):
    wheel = simulate(pair(tmp_path, GEARS.replace("torque_limit = 100.0", "torque_limit = 300.001")), 0.05, 1e-4,
                     ["force:m"]).life.gears[1]
    # the wheel's 300 N m (to the run's round-off, 1e-9 of it) below a limit 3e-6 above it
    assert wheel.damage == 0.0 and wheel.life_hours is None and "no damage" in wheel.note
    assert wheel.cycles > 0


@pytest.fixture(scope="module")
def nrel5mw():
    return assemble(load_scene("nrel5mw"))


def test_planetary_teeth_count_their_revolutions_against_the_carrier(nrel5mw):
    # stage 1 of the 5 MW: ring fixed, carrier at the rotor's speed, sun faster; synthetic speeds
    life = LifeTables(gears=(GearRating("stage1.sun-planet0", 1e6, 1e7, 6.0, gear="stage1.sun"),
                             GearRating("stage1.sun-planet0", 1e6, 1e7, 6.0, gear="stage1.planet0"),
                             GearRating("stage1.planet0-ring", 1e6, 1e7, 6.0, gear="stage1.ring")))
    n = 101
    t = np.linspace(0.0, 2.0, n)
    w = {"stage1.carrier": 1.2, "stage1.sun": 7.0, "stage1.planet0": -2.5, "stage1.ring": 0.0}
    hist = {f"speed:{b}": np.full(n, v) for b, v in w.items()}
    hist.update({"force:stage1.sun-planet0": np.full(n, 1e5), "force:stage1.planet0-ring": np.full(n, 1e5)})
    sun, planet, ring = gear_rows(nrel5mw, life, t, hist.__getitem__)
    for row, gear in ((sun, "stage1.sun"), (planet, "stage1.planet0"), (ring, "stage1.ring")):
        assert row.cycles == pytest.approx(abs(w[gear] - w["stage1.carrier"]) * 2.0 / (2 * math.pi), rel=1e-12)
    # stage 1 is spur (beta_b = 0): the sun's torque is its base radius x F
    mesh = next(m for m in nrel5mw.scene.meshes if m.name == "stage1.sun-planet0")
    assert sun.peak_torque == pytest.approx(abs(mesh.base_radius1) * 1e5, rel=1e-12)


def test_the_helical_pinion_carries_the_generator_torque(nrel5mw):
    # rated torques in static balance through the gear ratio (Jonkman et al. 2009: 43 093.55 N m at
    # the generator; the rotor's 4.152243e6 N m = 43 093.55 x 96.354, the ratio of Nejad et al.'s
    # teeth to 5 digits: an imbalance below 5e-6 accelerates the chain, the pinion's share of it
    # far smaller): the torque about the pinion's axis of the stage 3 mesh force along its helical
    # line of action, |r_b| cos(beta_b) F, is the generator's torque
    from assembly.scene.time_domain import Generator, Simulation, TimeLoad
    sim = Simulation(speed=1.2671, generator=Generator(torque=43093.55), loads=(TimeLoad("rotor", value=4.152243e6),),
                     life=LifeTables(gears=(GearRating("stage3", 4e4, 1e7, 6.0, gear="pinion"),)))
    r = simulate(nrel5mw, 0.01, 1e-4, ["force:stage3"], simulation=sim)
    (pin,) = r.life.gears
    assert pin.peak_torque == pytest.approx(43093.55, rel=5e-6)
    mesh = next(m for m in nrel5mw.scene.meshes if m.name == "stage3")
    assert mesh.helix_angle != 0.0


def test_a_streamed_run_counts_what_a_kept_one_does(tmp_path):
    scene = shaft_scene(tmp_path, life=RATED + "\nwindow = [0.02, 0.1]")
    kept = simulate(scene, 0.1, 1e-3, ["force:B:x"])
    streamed = simulate(scene, 0.1, 1e-3, ["force:B:x"], history=tmp_path / "h.h5")
    assert streamed.life.window == kept.life.window == pytest.approx((0.02, 0.1), abs=1e-12)
    assert streamed.life.bearings == kept.life.bearings
    assert streamed.life.outputs["force:B:x"].dels == kept.life.outputs["force:B:x"].dels
    # a bearing named without a direction records one channel a direction: each is counted
    both = simulate(scene, 0.1, 1e-3, ["force:B"])
    assert {"force:B:x", "force:B:y", "force:B:z"} <= set(both.life.outputs)
    # a summary-only run keeps the histories its life tables count
    assert simulate(scene, 0.1, 1e-3, ["force:B:x"], arrays=False).life.bearings == kept.life.bearings


BAD = [
    ('bearings = [{ bearing = "Q", rating = 1e4 }]', "simulation.life.bearings[0].bearing"),
    ('bearings = [{ bearing = "R", rating = 1e4 }]', "simulation.life.bearings[0].bearing"),   # rigid radial
    ('bearings = [{ bearing = "B", rating = 1e4, axial_factor = 1.0 }, { bearing = "R", rating = 1e4 }]',
     "simulation.life.bearings[1].bearing"),
    ('bearings = [{ bearing = "B", rating = 0.0 }]', "simulation.life.bearings[0].rating"),
    ('bearings = [{ bearing = "B", rating = -5.0 }]', "simulation.life.bearings[0].rating"),
    ('bearings = [{ bearing = "B", rating = 1e4, exponent = 0.0 }]', "simulation.life.bearings[0].exponent"),
    ('bearings = [{ bearing = "B", rating = 1e4, axial_factor = -1.0 }]', "simulation.life.bearings[0].axial_factor"),
    ('bearings = [{ bearing = "B" }]', "simulation.life.bearings[0].rating"),
    ('gears = [{ mesh = "B", torque_ref = 1.0, cycles_ref = 1e6, slope = 6.0 }]', "simulation.life.gears[0].mesh"),
    ('exponents = [3.0, 0.0]', "simulation.life.exponents[1]"),
    ('bins = 0', "simulation.life.bins"),
    ('bins = 2.5', "simulation.life.bins"),
    ('cycles_ref = -1.0', "simulation.life.cycles_ref"),
    ('window = [0.05, 0.02]', "simulation.life.window"),
    ('window = [0.0, 9.0]', "simulation.life.window"),
    ('shaft = "nowhere"', "simulation.life.shaft"),
]
RIGID = """[[bearings]]
name = "R"
body = "shaft"
k_radial = inf
k_axial = 1.0e8
k_tilt = 1.0e6"""


@pytest.mark.parametrize("life,field", BAD)
def test_bad_life_tables_are_refused_naming_the_field(tmp_path, life, field):
    with pytest.raises(SceneError) as e:
        simulate(shaft_scene(tmp_path, life=life, more=RIGID), 0.1, 1e-3, [])
    assert e.value.path == field
    assert "\n" not in str(e.value)


def test_check_life_refuses_what_is_not_a_table(tmp_path):
    model = assemble(shaft_scene(tmp_path))
    with pytest.raises(SceneError, match="simulation.life"):
        check_life(model, {"bearings": []}, 1.0, None)
    # a rated gear that is not a gear of its mesh
    pm = assemble(pair(tmp_path))
    life = dataclasses.replace(pm.scene.simulation.life, gears=(GearRating("m", 1.0, 1e6, 6.0, gear="shaft"),))
    with pytest.raises(SceneError) as e:
        check_life(pm, life, 1.0, None)
    assert e.value.path == "simulation.life.gears[0].gear"
