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
    assert math.isfinite(d["del_m4"])
