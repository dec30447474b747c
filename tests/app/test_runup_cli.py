"""flexgear runup end to end on a torsional pair: the run, its orders page and its life tables.

Checks from closed forms: the ramp's revolutions of the tracked shaft (the load revolution
distribution's total) equal its speed integrated over the ramp, (n0 + n1)/2 x T_ramp / 60 turns
(a linear ramp; the servo's lag leaves a(1 - ...) / w_b^2 rad, below 1e-3 turn here); the
load duration distribution's total is the ramp's length.
"""
from __future__ import annotations

import json
import math

import pytest

from assembly.app.cli import main
from assembly.app.report.links import folder_problems, read_page
from tests.app.test_simulate_cli import pair_file


def test_a_run_up_writes_its_orders_and_life_tables(tmp_path, capsys):
    scene = pair_file(tmp_path)
    out = tmp_path / "out"
    n0, n1, rate = 300.0, 600.0, 100.0                   # rpm, rpm/s: a 3 s ramp, 22.5 turns
    assert main(["runup", scene, "--speed-range", str(n0), str(n1), "--rate", str(rate), "--dt", "5e-4",
                 "--settle", "0.05", "--output", "force:m", "--out", str(out), "-q"]) == 0
    for f in ("index.html", "orders.html", "passages.csv", "life.csv", "life.json", "simulation.h5"):
        assert (out / f).is_file(), f
    life = json.loads((out / "life.json").read_text())
    ramp = (n1 - n0) / rate
    assert life["n_eq"] == pytest.approx(ramp, abs=1e-3)          # the ramp, to a step either end
    d = life["outputs"]["force:m"]
    assert sum(d["ldd"]["seconds"]) == pytest.approx(ramp, abs=1e-3)
    turns = (n0 + n1) / 2 * ramp / 60.0
    # the rotor of the pair (the driven body): its revolutions over the ramp
    assert sum(d["lrd"]["revolutions"]) == pytest.approx(turns, abs=1e-3 + 1e-3 * n1 / 60)
    assert "Loads to life" in (out / "index.html").read_text()
    assert folder_problems(out) == []      # both pages: the shared style, the navigation, links and anchors
    for page, other in (("index.html", "orders.html"), ("orders.html", "index.html")):
        assert other in read_page((out / page).read_text()).nav          # each page's navigation names the other
    assert math.isfinite(d["del_m4"])


def test_simulate_writes_the_rated_bearings_and_gears_tables(tmp_path, capsys):
    # the pair at 10 rad/s, 100 N m on the rotor against 300 N m on the generator: the rotor's teeth
    # carry r1 F = 100 N m, one cycle per revolution (tests/dynamics/test_life_tables.py derives it)
    import csv
    scene = pair_file(tmp_path, sim='loads = [{ body = "rotor", value = 100.0 }]\ngenerator = { torque = 300.0 }\n'
                      '[simulation.life]\ngears = [{ mesh = "m", torque_ref = 80.0, cycles_ref = 1.0e6, slope = 6.0 }]')
    out = tmp_path / "out"
    assert main(["simulate", scene, "--t-end", "0.2", "--dt", "1e-4", "--output", "force:m", "--out", str(out),
                 "-q"]) == 0
    (row,) = list(csv.DictReader(open(out / "life_gears.csv", encoding="utf-8")))
    cycles = 10.0 * 0.2 / (2 * math.pi)
    assert float(row["cycles"]) == pytest.approx(cycles, rel=1e-5)                 # 6 digits written
    assert float(row["damage"]) == pytest.approx(cycles * (100 / 80) ** 6 / 1e6, rel=1e-5)
    assert "Gears: equivalent torque and Miner damage" in (out / "index.html").read_text()
    assert json.loads((out / "life.json").read_text())["gears"][0]["gear"] == "rotor"
    # the speeds recorded for the table alone are in the history, not pictured
    assert (out / "trace_01.png").exists() and not (out / "trace_02.png").exists()


def test_a_bad_life_table_exits_2_naming_it_and_writes_nothing(tmp_path, capsys):
    scene = pair_file(tmp_path, sim='[simulation.life]\ngears = [{ mesh = "m", torque_ref = 80.0, cycles_ref = 1.0e6, '
                                    'slope = 6.0, gear = "nothing" }]')
    out = tmp_path / "out"
    assert main(["simulate", scene, "--t-end", "0.01", "--dt", "1e-4", "--out", str(out), "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "simulation.life.gears[0].gear" in err[0]
    assert not out.exists()


def test_the_step_warning_counts_a_run_ups_top_speed(tmp_path):
    # the pair's mesh varies at 20 teeth of the rotor: 20 x 10 rad/s / 2 pi = 31.8 Hz at the start,
    # 477 Hz at the run-up's 150 rad/s; dt = 1e-3 s gives 31 steps a period at the start and 2.1 at
    # the top, below the 10 the run asks for (assembly.dynamics.run_checks.STEPS_PER_PERIOD)
    from assembly.dynamics.simulate import simulate
    from assembly.scene.schema import load_scene
    scene = load_scene(pair_file(tmp_path, mesh="variation = { amplitudes = [0.1], teeth = 20 }",
                                 sim="drive = { end_speed = 150.0, t_end = 1.0 }"))
    r = simulate(scene, 0.01, 1e-3, ["force:m"])
    (w,) = [w for w in r.warnings if "mesh harmonic" in w]
    assert "2.0 steps per period of m's mesh harmonic 1 (477.5 Hz)" in w        # 2.09, rounded down


def test_a_step_just_short_of_ten_a_period_does_not_read_ten():
    # 9.96 steps a period is below the 10 asked: the warning says 9.9, not "10.0 ... below 10"
    from types import SimpleNamespace

    from assembly.dynamics.run_checks import step_warnings
    (w,) = step_warnings(1.0 / (9.96 * 1000.0), {}, SimpleNamespace(info=()), 1000.0)    # no meshes: the band
    assert "9.9 steps per period at the band's top" in w
